#include "pbrt_film_reference.h"

#include <math.h>

void pbrt_reference_resample(const float *pairs, size_t count, double out[PBRT_REFERENCE_SAMPLES])
{
    size_t j = 0;
    for (int i = 0; i < PBRT_REFERENCE_SAMPLES; ++i) {
        double l = 360.0 + i;
        if (l <= pairs[0]) {
            out[i] = pairs[1];
            continue;
        }
        if (l >= pairs[2 * (count - 1)]) {
            out[i] = pairs[2 * count - 1];
            continue;
        }
        while (pairs[2 * (j + 1)] < l)
            j++;
        double l0 = pairs[2 * j], l1 = pairs[2 * j + 2], v0 = pairs[2 * j + 1], v1 = pairs[2 * j + 3];
        out[i] = v0 + (l - l0) / (l1 - l0) * (v1 - v0);
    }
}

static double sum_with(const float *cmf, const double s[PBRT_REFERENCE_SAMPLES])
{
    double sum = 0.0;
    for (int i = 0; i < PBRT_REFERENCE_SAMPLES; ++i)
        sum += (double)cmf[i] * s[i];
    return sum;
}

void pbrt_reference_normalise(const PbrtReferenceCmfs *cmfs, double s[PBRT_REFERENCE_SAMPLES])
{
    double k = PBRT_REFERENCE_CIE_Y_INTEGRAL / sum_with(cmfs->y, s);
    for (int i = 0; i < PBRT_REFERENCE_SAMPLES; ++i)
        s[i] *= k;
}

static double planck(double nm, double kelvin)
{
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    double l = nm * 1e-9;
    return 2.0 * h * c * c / (l * l * l * l * l * (exp(h * c / (l * kb * kelvin)) - 1.0));
}

void pbrt_reference_blackbody(double kelvin, double out[PBRT_REFERENCE_SAMPLES])
{
    double peak = planck(2.8977721e-3 / kelvin * 1e9, kelvin);
    for (int i = 0; i < PBRT_REFERENCE_SAMPLES; ++i)
        out[i] = planck(360.0 + i, kelvin) / peak;
}

double pbrt_reference_grey_sigmoid(double v)
{
    double c2 = (v - 0.5) / sqrt(v * (1.0 - v)); /* the polynomial's constant term */
    return 0.5 + c2 / (2.0 * sqrt(1.0 + c2 * c2));
}

/* 3x3 inverse by cofactors. */
static void inverse3(double m[3][3], double out[3][3])
{
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    out[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    out[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    out[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    out[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    out[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    out[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    out[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    out[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    out[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
}

void pbrt_reference_pixel(const PbrtReferenceCmfs *cmfs, const double white[PBRT_REFERENCE_SAMPLES],
                          const double emitted[PBRT_REFERENCE_SAMPLES],
                          const double photometric[PBRT_REFERENCE_SAMPLES], double scale, double rgb[3])
{
    /* RGBColorSpace: primaries (x, y) with Y = 1, scaled so that RGB
     * (1, 1, 1) is SpectrumToXYZ(illuminant) = sums / CIE_Y_integral. */
    static const double primaries[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    double p[3][3], p_inverse[3][3], w[3], c[3], xyz_from_rgb[3][3], rgb_from_xyz[3][3];
    const float *cmf[3] = {cmfs->x, cmfs->y, cmfs->z};
    for (int k = 0; k < 3; ++k) {
        p[0][k] = primaries[k][0] / primaries[k][1];
        p[1][k] = 1.0;
        p[2][k] = (1.0 - primaries[k][0] - primaries[k][1]) / primaries[k][1];
        w[k] = sum_with(cmf[k], white) / PBRT_REFERENCE_CIE_Y_INTEGRAL;
    }
    inverse3(p, p_inverse);
    for (int r = 0; r < 3; ++r)
        c[r] = p_inverse[r][0] * w[0] + p_inverse[r][1] * w[1] + p_inverse[r][2] * w[2];
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
            xyz_from_rgb[r][k] = p[r][k] * c[k];
    inverse3(xyz_from_rgb, rgb_from_xyz);
    /* The light's scale over SpectrumToPhotometric; the sensor's XYZ. */
    double k = scale / sum_with(cmfs->y, photometric), xyz[3];
    for (int r = 0; r < 3; ++r)
        xyz[r] = k * sum_with(cmf[r], emitted);
    for (int r = 0; r < 3; ++r)
        rgb[r] = rgb_from_xyz[r][0] * xyz[0] + rgb_from_xyz[r][1] * xyz[1] + rgb_from_xyz[r][2] * xyz[2];
}
