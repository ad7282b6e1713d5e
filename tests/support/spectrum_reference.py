#!/usr/bin/env python3
"""Reference RGB values for tests/test_spectrum.c, computed independently of
host/scene/spectrum.c: trapezoidal integration (numpy) of colour-science's
CIE 1931 tables, interpolated by numpy, and colour-science's own sRGB matrix
(the standard one, white x, y = 0.3127, 0.3290). Run:
    pip install colour-science==0.4.7 && python3 tests/support/spectrum_reference.py
(from the repository root, with ../shared/scenes beside it) and paste what it
prints into the test."""
import re

import colour
import numpy as np

lam = np.arange(360.0, 831.0)
cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].values  # 360..830, 1 nm
M = colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB


def xyz(s):
    return np.array([np.trapezoid(cmfs[:, i] * s, lam) for i in range(3)])


def planck(l_nm, t):
    c, h, k = 299792458.0, 6.62607015e-34, 1.380649e-23
    l = l_nm * 1e-9
    return 2 * h * c * c / (l**5 * np.expm1(h * c / (l * k * t)))


def illuminant_rgb(s):  # luminance 1
    v = xyz(s)
    return M @ (v / v[1])


def pbrt_table(name):  # the data as pbrt-v4 ships it, ends held
    if name.startswith("stdillum-"):
        sd = colour.SDS_ILLUMINANTS[name[9:].replace("F", "FL") if name[9] == "F" else name[9:]]
        return np.interp(lam, sd.wavelengths, sd.values)
    pairs = np.loadtxt("../shared/scenes/killeroos/spds/%s.spd" % name)
    return np.interp(lam, pairs[:, 0], pairs[:, 1])


d65 = pbrt_table("stdillum-D65")
wt = [np.clip((M[c] @ cmfs.T) * d65, 0, None) for c in range(3)]


def unbounded(s):
    return [np.trapezoid(w * s, lam) / np.trapezoid(w, lam) for w in wt]


for t in (2700.0, 5500.0, 6500.0):
    print("blackbody %g K illuminant" % t, illuminant_rgb(planck(lam, t)))
print("stdillum-A illuminant", illuminant_rgb(pbrt_table("stdillum-A")))
print("stdillum-D65 illuminant", illuminant_rgb(d65))
print("stdillum-F11 illuminant", illuminant_rgb(pbrt_table("stdillum-F11")))
aces_d60 = colour.sd_CIE_illuminant_D_series(colour.temperature.CCT_to_xy_CIE_D(6000), M1_M2_rounding=True)
print("illum-acesD60 illuminant", illuminant_rgb(np.interp(lam, aces_d60.wavelengths, aces_d60.values)))
print("metal-Au-eta unbounded", unbounded(pbrt_table("Au.eta")))
print("metal-Au-k unbounded", unbounded(pbrt_table("Au.k")))
bk7 = np.array([300, 1.5527702635739, 322, 1.5458699289209, 344, 1.5404466868331, 366, 1.536090527917,
                388, 1.53252773217, 410, 1.529568767224, 432, 1.5270784291406, 454, 1.5249578457324,
                476, 1.5231331738499, 498, 1.5215482528369, 520, 1.5201596882463, 542, 1.5189334783109,
                564, 1.5178426478869, 586, 1.516865556749, 608, 1.5159846691816, 630, 1.5151856452759,
                652, 1.5144566604975, 674, 1.513787889767, 696, 1.5131711117948, 718, 1.5125994024544,
                740, 1.5120668948646, 762, 1.5115685899969, 784, 1.5111002059336, 806, 1.5106580569705,
                828, 1.5102389559626, 850, 1.5098401349174]).reshape(-1, 2)
s = np.interp(lam, bk7[:, 0], bk7[:, 1])
print("glass-BK7 eta", np.trapezoid(cmfs[:, 1] * s, lam) / np.trapezoid(cmfs[:, 1], lam))
# A reflectance: 0.2 below 500 nm, 0.8 above (inline pairs 499 0.2 501 0.8).
r = np.interp(lam, [499, 501], [0.2, 0.8])
print("step albedo", M @ xyz(r * d65) / xyz(d65)[1])


# docs/scenes.md's metal comparison ("Spectra"): pbrt-v4 renders a metal under white (D65)
# light at normal incidence as the RGB of its spectral Fresnel reflectance
# R(lambda); gmonrt applies the Fresnel equations to the RGB eta and k.
def fresnel(n, k):
    return ((n - 1) ** 2 + k**2) / ((n + 1) ** 2 + k**2)


def fresnel_complex(cos_i, n, k):  # unpolarised, pbrt-v4's FrComplex
    eta = n + 1j * k
    cos_t = np.sqrt(eta**2 - (1 - cos_i**2))
    r_s = (cos_i - cos_t) / (cos_i + cos_t)
    r_p = (eta**2 * cos_i - cos_t) / (eta**2 * cos_i + cos_t)
    return (np.abs(r_s) ** 2 + np.abs(r_p) ** 2) / 2


def conductor_fit(eta, k):  # per channel: eta averaged, k solved for the sRGB of R(0)
    n, r = np.array(unbounded(eta)), np.clip(albedo(fresnel(eta, k)), 0, 0.999)
    k2 = (r * (n + 1) ** 2 - (n - 1) ** 2) / (1 - r)
    return n, np.sqrt(np.clip(k2, 0, None))  # (none of the four metals needs k = 0)


def albedo(r):  # what pbrt-v4 renders for a reflectance lit by D65
    return M @ xyz(r * d65) / xyz(d65)[1]


def c_array(path, name):  # a (lambda, value) table of a host/scene data file
    body = re.search(r"static const float %s\[\] = \{([^}]*)\}" % name, open(path).read()).group(1)
    pairs = np.array([float(x) for x in body.split(",")]).reshape(-1, 2)
    return np.interp(lam, pairs[:, 0], pairs[:, 1])


def metal_table(metal, what):  # gold from the scenes' .spd files; the others as spectrum_data.c holds them
    if metal == "Au":
        return pbrt_table("Au." + what)
    return c_array("host/scene/spectrum_data.c", "%s_%s" % (metal, what))


print("conductors: fitted RGB eta, k; per-channel error (%) of the RGB Fresnel against the sRGB of the spectral "
      "one under D65, at 0 and 60 degrees: fitted [averaged eta and k, as before] {against the channel-weighted "
      "average of the spectral one instead}")
for metal in ("Au", "Ag", "Cu", "Al", "CuZn"):
    eta, k = metal_table(metal, "eta"), metal_table(metal, "k")
    n, kk = conductor_fit(eta, k)
    n0, k0 = np.array(unbounded(eta)), np.array(unbounded(k))
    row = []
    for degrees in (0, 60):
        c = np.cos(np.radians(degrees))
        spectral, weighted = albedo(fresnel_complex(c, eta, k)), np.array(unbounded(fresnel_complex(c, eta, k)))
        row.append("%d: %s [%s] {%s}" % (degrees, np.round(100 * (fresnel_complex(c, n, kk) / spectral - 1), 1),
                                         np.round(100 * (fresnel_complex(c, n0, k0) / spectral - 1), 1),
                                         np.round(100 * (fresnel_complex(c, n, kk) / weighted - 1), 1)))
    print("metal-%s eta %s k %s; %s" % (metal, n.round(6), kk.round(6), "; ".join(row)))


# Named camera sensors (docs/scenes.md, "The film's response"): pbrt-v4's PixelSensor
# fit, with plain sums over the 1 nm grid as pbrt-v4's ProjectReflectance,
# colour-science's D65, CIE D series and BabelColor swatches, and the sensor
# responses read from host/scene/spectrum_sensor_data.c.
def daylight(t):  # pbrt-v4's Spectra::D: a blackbody below 4000 K
    if t * 1.4388 / 1.4380 < 4000:
        return planck(lam, t * 1.4388 / 1.4380)
    xy = colour.temperature.CCT_to_xy_CIE_D(t * 1.4388 / 1.4380)
    sd = colour.sd_CIE_illuminant_D_series(xy, M1_M2_rounding=False)
    return np.interp(lam, sd.wavelengths, sd.values)


swatches = [np.interp(lam, sd.wavelengths, sd.values)
            for sd in colour.SDS_COLOURCHECKERS["BabelColor Average"].values()]
basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
basis = [np.interp(lam, basis.wavelengths, basis.values[:, c]) for c in range(3)]
sensors = ("canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d", "canon_eos_200d_mkii", "canon_eos_5d",
           "canon_eos_5d_mkii", "canon_eos_5d_mkiii", "canon_eos_5d_mkiv", "canon_eos_5ds", "canon_eos_m",
           "hasselblad_l1d_20c", "nikon_d810", "nikon_d850", "sony_ilce_6400", "sony_ilce_7m3", "sony_ilce_7rm3",
           "sony_ilce_9")
for sensor, wb in [("canon_eos_100d", 3200)] + [(s, 6500) for s in sensors]:
    bar = np.array([c_array("host/scene/spectrum_sensor_data.c", sensor + s) for s in ("_r", "_g", "_b")])
    D = daylight(wb)
    camera = np.array([bar @ (s * D) / (bar[1] @ D) for s in swatches])
    target = np.array([cmfs.T @ (s * d65) / (cmfs[:, 1] @ d65) for s in swatches]) * (
        (cmfs[:, 1] @ D) / (bar[1] @ D))
    xyz_from_sensor = np.linalg.lstsq(camera, target, rcond=None)[0].T
    sensor_from_srgb = np.array([bar @ (d65 * b) for b in basis]).T / (cmfs[:, 1] @ d65)
    film = M @ xyz_from_sensor @ sensor_from_srgb
    print("%s %g K XYZFromSensorRGB %s" % (sensor, wb, xyz_from_sensor.round(6).tolist()))
    print("  film matrix %s" % film.round(6).tolist())
    if wb == 6500:  # each swatch under D65: pbrt-v4's spectral sensor vs the film matrix on its sRGB
        spectral = np.array([M @ xyz_from_sensor @ bar @ (s * d65) / (cmfs[:, 1] @ d65) for s in swatches])
        rgb = np.clip([M @ xyz(s * d65) / xyz(d65)[1] for s in swatches], 0, 1)
        error = np.abs(rgb @ film.T - spectral)
        print("  24 swatches under D65, |film * sRGB - spectral| per channel: max %.4f (swatch %d), mean %.4f; "
              "relative to the swatch's largest channel: max %.1f%%, mean %.1f%%"
              % (error.max(), error.max(1).argmax() + 1, error.mean(),
                 100 * (error.max(1) / spectral.max(1)).max(), 100 * (error.max(1) / spectral.max(1)).mean()))
        white = M @ xyz_from_sensor @ bar @ d65 / (cmfs[:, 1] @ d65)  # a reflectance 1 under D65
        print("  white under D65: pbrt-v4's sensor %s, film matrix %s"
              % (white.round(4).tolist(), (film @ illuminant_rgb(d65)).round(4).tolist()))
