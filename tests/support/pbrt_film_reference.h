/* pbrt-v4's pixel for an emitter seen directly, written from pbrt-v4's rules
 * and independent of host/scene/spectrum.c (docs/scenes.md "Spectra", scripts/
 * pbrt_emitter_brightness.py): DiffuseAreaLight divides "scale" by
 * SpectrumToPhotometric (the sum of ybar times the spectrum over 360..830 nm,
 * for an rgb L its illuminant alone), the default cie1931 PixelSensor records
 * imaging ratio times the sums of xbar, ybar, zbar times the radiance (the
 * expectation of its wavelength estimator), RGBFilm maps XYZ to its colour
 * space: the sRGB primaries with the white of the colour space's illuminant.
 * Spectra are 471 values at 360..830 nm. Host only, for tests. */
#ifndef TESTS_SUPPORT_PBRT_FILM_REFERENCE_H
#define TESTS_SUPPORT_PBRT_FILM_REFERENCE_H

#include <stddef.h>

#define PBRT_REFERENCE_SAMPLES 471
#define PBRT_REFERENCE_CIE_Y_INTEGRAL 106.856895

typedef struct {
    const float *x, *y, *z; /* the CIE 1931 matching functions at 360..830 nm */
} PbrtReferenceCmfs;

/* Interleaved (lambda, value) pairs, interpolated linearly at each
 * nanometre, the end values held (pbrt-v4's PiecewiseLinearSpectrum of a
 * named spectrum). */
void pbrt_reference_resample(const float *pairs, size_t count, double out[PBRT_REFERENCE_SAMPLES]);

/* Scales s so that sum(ybar s) = CIE_Y_integral (FromInterleaved's normalize). */
void pbrt_reference_normalise(const PbrtReferenceCmfs *cmfs, double s[PBRT_REFERENCE_SAMPLES]);

/* BlackbodySpectrum: Planck's law over its value at Wien's peak. */
void pbrt_reference_blackbody(double kelvin, double out[PBRT_REFERENCE_SAMPLES]);

/* RGBToSpectrumTable for r = g = b = v in (0, 1): a constant sigmoid. */
double pbrt_reference_grey_sigmoid(double v);

/* The film's RGB for radiance scale * emitted / sum(ybar photometric), with
 * imaging ratio 1 and the colour space's illuminant `white`. */
void pbrt_reference_pixel(const PbrtReferenceCmfs *cmfs, const double white[PBRT_REFERENCE_SAMPLES],
                          const double emitted[PBRT_REFERENCE_SAMPLES],
                          const double photometric[PBRT_REFERENCE_SAMPLES], double scale, double rgb[3]);

#endif
