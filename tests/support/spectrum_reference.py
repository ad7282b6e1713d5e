#!/usr/bin/env python3
"""Reference RGB values for tests/test_spectrum.c, computed independently of
host/scene/spectrum.c: trapezoidal integration (numpy) of colour-science's
CIE 1931 tables, interpolated by numpy, and colour-science's own sRGB matrix
(the standard one, white x, y = 0.3127, 0.3290). Run:
    pip install colour-science==0.4.7 && python3 tests/support/spectrum_reference.py
and paste what it prints into the test."""
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


# The README's metal comparison: pbrt-v4 renders a metal under white (D65)
# light at normal incidence as the RGB of its spectral Fresnel reflectance
# R(lambda); gmonrt applies the Fresnel equations to the RGB eta and k.
def fresnel(n, k):
    return ((n - 1) ** 2 + k**2) / ((n + 1) ** 2 + k**2)


for metal in ("Au",):
    eta, k = pbrt_table(metal + ".eta"), pbrt_table(metal + ".k")
    spectral = M @ xyz(fresnel(eta, k) * d65) / xyz(d65)[1]
    rgb = fresnel(np.array(unbounded(eta)), np.array(unbounded(k)))
    print("%s normal-incidence reflectance: spectral %s, from RGB eta/k %s, difference %s%%"
          % (metal, spectral, rgb, 100 * (rgb / spectral - 1)))
