#!/usr/bin/env python3
"""What pbrt-v4 records for an emitter, step by step, against gmonrt's rule.

Follows pbrt-v4's rules (read in its source: lights.cpp DiffuseAreaLight::Create,
util/spectrum.cpp SpectrumToPhotometric and the named spectra, RGBIlluminantSpectrum,
film.h PixelSensor::ToSensorRGB, film.cpp PixelSensor::Create and RGBFilm,
util/colorspace.cpp RGBColorSpace) with the CIE tables gmonrt ships
(host/scene/spectrum_cie_data.c), and prints:
  1. the pixel pbrt-v4's default film records for `"rgb L" [1 1 1] "float scale" [20]`
     seen directly, computed exactly (1 nm sums), and the same for blackbody,
     stdillum-A and a flat spectrum, beside gmonrt's conversion rule;
  2. a Monte Carlo run of pbrt-v4's wavelength estimator (SampleVisible, 4 stratified
     wavelengths, nearest-nanometre table lookups): its mean and per-sample spread;
  3. candidate factors against the measured (21.23, 21.25, 20.91).
Standard library only. Run from the repository root:
    python3 scripts/pbrt_emitter_brightness.py
"""
import math
import os
import random
import re

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE = open(os.path.join(ROOT, "host", "scene", "spectrum_cie_data.c")).read()
LAMBDA = list(range(360, 831))  # pbrt-v4's Lambda_min..Lambda_max, 1 nm
CIE_Y_INTEGRAL = 106.856895  # pbrt-v4's constant
MEASURED = (21.23, 21.25, 20.91)  # ../shared/scenes/README.md, pbrt-v4 CPU


def table(name):
    body = re.search(r"%s\[[^\]]*\]\s*=\s*\{(.*?)\};" % re.escape(name), SOURCE, re.S).group(1)
    return [float(v) for v in re.findall(r"[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?", body)]


def resample(pairs):
    """Piecewise-linear (lambda, value) pairs on the 1 nm grid, ends held."""
    lam, val = pairs[0::2], pairs[1::2]
    out, j = [], 0
    for l in LAMBDA:
        if l <= lam[0]:
            out.append(val[0])
            continue
        if l >= lam[-1]:
            out.append(val[-1])
            continue
        while lam[j + 1] < l:
            j += 1
        t = (l - lam[j]) / (lam[j + 1] - lam[j])
        out.append(val[j] + t * (val[j + 1] - val[j]))
    return out


X, Y, Z = table("spectrum_cie_x"), table("spectrum_cie_y"), table("spectrum_cie_z")
D65 = resample(table("illuminant_D65"))
ILLUM_A = resample(table("illuminant_A"))


def inner(a, b):
    return sum(p * q for p, q in zip(a, b))


def luminance_normalised(s):
    """pbrt-v4's FromInterleaved(..., normalize=true): sum(ybar * s) = CIE_Y_integral."""
    k = CIE_Y_INTEGRAL / inner(Y, s)
    return [v * k for v in s]


def invert(m):
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    return [[(m[(c + 1) % 3][(r + 1) % 3] * m[(c + 2) % 3][(r + 2) % 3] -
              m[(c + 1) % 3][(r + 2) % 3] * m[(c + 2) % 3][(r + 1) % 3]) / det for c in range(3)] for r in range(3)]


def apply(m, v):
    return [sum(m[r][c] * v[c] for c in range(3)) for r in range(3)]


def rgb_from_xyz(white_spectrum):
    """pbrt-v4's RGBColorSpace: sRGB primaries, white = SpectrumToXYZ(illuminant)."""
    w = [inner(t, white_spectrum) / CIE_Y_INTEGRAL for t in (X, Y, Z)]
    prim = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)]
    p = [[x / y for x, y in prim], [1.0, 1.0, 1.0], [(1 - x - y) / y for x, y in prim]]
    c = apply(invert(p), w)
    return invert([[p[r][k] * c[k] for k in range(3)] for r in range(3)])


D65N = luminance_normalised(D65)  # "stdillum-D65", the sRGB colour space's illuminant
SRGB_FROM_XYZ = rgb_from_xyz(D65N)


def sigmoid_polynomial_grey(v):
    """RGBToSpectrumTable for r = g = b = v: coefficients (0, 0, (v - .5) / sqrt(v (1 - v)))."""
    c2 = (v - 0.5) / math.sqrt(v * (1 - v))
    return 0.5 + c2 / (2 * math.sqrt(1 + c2 * c2))  # the sigmoid, constant in lambda


def pbrt_pixel(emitted, photometric_of, scale, iso=100.0, exposure=1.0):
    """DiffuseAreaLight: scale /= SpectrumToPhotometric (sum ybar * s, 1 nm; for an
    RGBIlluminantSpectrum the illuminant alone); cie1931 PixelSensor: imagingRatio =
    exposure * ISO / 100 times (sum xbar L, sum ybar L, sum zbar L) (the Monte Carlo
    estimate's expectation); RGBFilm: RGBFromXYZ (no white balance for cie1931)."""
    k = scale / inner(Y, photometric_of)
    L = [k * v for v in emitted]
    xyz = [exposure * iso / 100.0 * inner(t, L) for t in (X, Y, Z)]
    return apply(SRGB_FROM_XYZ, xyz)


def gmonrt_rgb(s, scale):
    """gmonrt's SPECTRUM_ILLUMINANT: XYZ scaled to Y = 1, in linear sRGB, times scale."""
    xyz = [inner(t, s) for t in (X, Y, Z)]
    return [scale * v for v in apply(SRGB_FROM_XYZ, [c / xyz[1] for c in xyz])]


def planck(l_nm, kelvin):
    c, h, kb = 299792458.0, 6.62606957e-34, 1.3806488e-23
    l = l_nm * 1e-9
    return 2 * h * c * c / (l**5 * (math.exp(h * c / (l * kb * kelvin)) - 1))


def blackbody(kelvin):
    peak = planck(2.8977721e-3 / kelvin * 1e9, kelvin)
    return [planck(l, kelvin) / peak for l in LAMBDA]


def fmt(v):
    return "(" + ", ".join("%.6f" % x for x in v) + ")"


def main():
    print("1. Exact (1 nm sums), scale 20, default Film \"rgb\" (cie1931, iso 100, shutter 1):")
    rgb_scale, rsp = 2 * 1.0, sigmoid_polynomial_grey(0.5)  # RGBIlluminantSpectrum: 2 max(rgb), rgb / that
    white = [rgb_scale * rsp * d for d in D65N]
    print("   rgb L [1 1 1]: 2 * sigmoid(%.3f) * D65, normalised by D65 alone" % rsp)
    print("     pbrt-v4 pixel  %s   gmonrt (rgb as given) (20, 20, 20)" % fmt(pbrt_pixel(white, D65N, 20.0)))
    print("     pbrt-v4 factor on rgb L: %.9f" % (pbrt_pixel(white, D65N, 1.0)[1]))
    cases = [("blackbody L [6500]", blackbody(6500.0)), ("blackbody L [2700]", blackbody(2700.0)),
             ("spectrum L stdillum-A", luminance_normalised(ILLUM_A)),
             ("spectrum L [300 5 900 5]", [5.0] * len(LAMBDA))]
    for name, s in cases:
        print("   %-26s pbrt-v4 %s  gmonrt %s" % (name, fmt(pbrt_pixel(s, s, 20.0)), fmt(gmonrt_rgb(s, 20.0))))

    print("2. Monte Carlo of pbrt-v4's estimator for rgb L [1 1 1] scale 20 (SampleVisible, 4 wavelengths):")
    L = [20.0 / inner(Y, D65N) * v for v in white]

    def pdf(l):
        return 0.0039398042 / math.cosh(0.0072 * (l - 538)) ** 2 if 360 <= l <= 830 else 0.0

    def dense(t, l):
        i = int(math.floor(l + 0.5)) - 360  # DenselySampledSpectrum: lround
        return t[i] if 0 <= i < len(t) else 0.0

    rng = random.Random(1)
    n, sums, squares = 200000, [0.0] * 3, [0.0] * 3
    for _ in range(n):
        u = rng.random()
        e = [0.0] * 3
        for i in range(4):
            up = u + i / 4.0
            up = up - 1 if up > 1 else up
            l = 538 - 138.888889 * math.atanh(0.85691062 - 1.82750197 * up)
            w = dense(L, l) / pdf(l) / 4
            for c, t in enumerate((X, Y, Z)):
                e[c] += dense(t, l) * w
        rgb = apply(SRGB_FROM_XYZ, e)
        for c in range(3):
            sums[c] += rgb[c]
            squares[c] += rgb[c] * rgb[c]
    mean = [s / n for s in sums]
    spread = [math.sqrt(max(q / n - m * m, 0.0)) for q, m in zip(squares, mean)]
    print("   mean %s over %d samples; per-sample std %s" % (fmt(mean), n, fmt(spread)))
    spp = 16 * 16 * 16  # a 16x16 image at pbrt-v4's default 16 spp
    print("   std of a %d-sample image mean (independent samples): %s" % (spp, fmt([s / math.sqrt(spp) for s in spread])))

    print("3. Candidate factors against the measured %s (luminance %.4f):" %
          (fmt(MEASURED), sum(w * m for w, m in zip((0.2126, 0.7152, 0.0722), MEASURED))))
    g = math.exp(-1.5 * 1.5 / (2 * 0.25)) / math.sqrt(2 * math.pi * 0.25)
    gauss_1d = math.erf(1.5 / (0.5 * math.sqrt(2))) - 3.0 * g  # pbrt-v4's gaussian, radius 1.5, sigma 0.5
    for name, f in [("pbrt-v4's rules (this script, part 1)", 1.0),
                    ("CIE_Y_integral / 100", CIE_Y_INTEGRAL / 100.0),
                    ("1 / integral of the default gaussian filter", 1.0 / (gauss_1d * gauss_1d))]:
        print("   %-45s %.5f -> %s" % (name, f, fmt([20.0 * f] * 3)))
    print("4. To decide it, render this in pbrt-v4 twice, with and without the PixelFilter line:")
    print("   (20, 20, 20) with the box filter and 21.23 without means the gaussian's integral.")
    print(DECISIVE_SCENE)


DECISIVE_SCENE = """   LookAt 0 0 -1  0 0 0  0 1 0
   Camera "perspective" "float fov" [ 30 ]
   Film "rgb" "string filename" "quad.exr" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
   PixelFilter "box"
   Sampler "zsobol" "integer pixelsamples" [ 64 ]
   Integrator "path" "integer maxdepth" [ 1 ]
   WorldBegin
   AreaLightSource "diffuse" "rgb L" [ 1 1 1 ] "float scale" [ 20 ] "bool twosided" true
   Shape "trianglemesh" "integer indices" [ 0 1 2  2 3 0 ]
       "point3 P" [ -10 -10 1  10 -10 1  10 10 1  -10 10 1 ]"""


if __name__ == "__main__":
    main()
