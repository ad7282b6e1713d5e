#include "scene/spectrum.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void spectrum_from_pairs(const double *lambda, const double *value, size_t count, int hold_ends, Spectrum *out)
{
    size_t segment = 0;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
        double l = SPECTRUM_LAMBDA_MIN + i;
        if (count == 0 || l < lambda[0] || l > lambda[count - 1]) {
            out->value[i] = !hold_ends || count == 0 ? 0.0 : l < lambda[0] ? value[0] : value[count - 1];
            continue;
        }
        while (segment + 2 < count && lambda[segment + 1] < l)
            segment++;
        if (count == 1) {
            out->value[i] = value[0];
            continue;
        }
        double t = (l - lambda[segment]) / (lambda[segment + 1] - lambda[segment]);
        out->value[i] = value[segment] + t * (value[segment + 1] - value[segment]);
    }
}

/* Interleaved float pairs, as the data tables hold them. */
static void from_table(const NamedSpectrumTable *table, Spectrum *out)
{
    double lambda[1024], value[1024];
    size_t n = table->count < 1024 ? table->count : 1024;
    for (size_t i = 0; i < n; ++i) {
        lambda[i] = table->pairs[2 * i];
        value[i] = table->pairs[2 * i + 1];
    }
    spectrum_from_pairs(lambda, value, n, 1, out);
}

static double planck(double lambda_nm, double kelvin)
{
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23; /* pbrt-v4's constants */
    double l = lambda_nm * 1e-9;
    return 2.0 * h * c * c / (pow(l, 5) * (exp(h * c / (l * kb * kelvin)) - 1.0));
}

void spectrum_blackbody(double kelvin, Spectrum *out)
{
    double peak = planck(2.8977721e-3 / kelvin * 1e9, kelvin); /* Wien's displacement law */
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
        out->value[i] = planck(SPECTRUM_LAMBDA_MIN + i, kelvin) / peak;
}

static double y_sum(const Spectrum *s)
{
    double sum = 0.0;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
        sum += spectrum_cie_y[i] * s->value[i];
    return sum;
}

int spectrum_named(const char *name, Spectrum *out)
{
    for (size_t i = 0; i < spectrum_named_table_count; ++i)
        if (strcmp(name, spectrum_named_tables[i].name) == 0) {
            from_table(&spectrum_named_tables[i], out);
            return 0;
        }
    for (size_t i = 0; i < spectrum_cie_illuminant_count; ++i)
        if (strcmp(name, spectrum_cie_illuminants[i].name) == 0) {
            from_table(&spectrum_cie_illuminants[i], out);
            /* pbrt-v4 scales its illuminants to a luminance of 1. */
            double scale = SPECTRUM_CIE_Y_INTEGRAL / y_sum(out);
            for (int k = 0; k < SPECTRUM_SAMPLES; ++k)
                out->value[k] *= scale;
            return 0;
        }
    return -1;
}

void spectrum_daylight(double kelvin, Spectrum *out)
{
    double cct = kelvin * 1.4388 / 1.4380; /* the CIE's revised c2 (pbrt-v4's correction) */
    if (cct < 4000.0) {
        spectrum_blackbody(cct, out);
        return;
    }
    double x = cct <= 7000.0 ? -4.607e9 / pow(cct, 3) + 2.9678e6 / (cct * cct) + 0.09911e3 / cct + 0.244063
                             : -2.0064e9 / pow(cct, 3) + 1.9018e6 / (cct * cct) + 0.24748e3 / cct + 0.23704;
    double y = -3.0 * x * x + 2.870 * x - 0.275;
    double m = 0.0241 + 0.2562 * x - 0.7341 * y;
    double m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m, m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    double lambda[SPECTRUM_DAYLIGHT_SAMPLES], value[SPECTRUM_DAYLIGHT_SAMPLES];
    for (int i = 0; i < SPECTRUM_DAYLIGHT_SAMPLES; ++i) {
        lambda[i] = 300.0 + 5.0 * i;
        value[i] = (spectrum_daylight_s0[i] + m1 * spectrum_daylight_s1[i] + m2 * spectrum_daylight_s2[i]) * 0.01;
    }
    spectrum_from_pairs(lambda, value, SPECTRUM_DAYLIGHT_SAMPLES, 0, out);
}

int spectrum_parse_spd(const char *text, Spectrum *out, char *why, size_t why_size)
{
    size_t count = 0, capacity = 0;
    double *numbers = NULL;
    const char *s = text;
    int result = 0;
    for (;;) {
        while (*s && (isspace((unsigned char)*s) || *s == ','))
            s++;
        if (*s == '#') {
            while (*s && *s != '\n')
                s++;
            continue;
        }
        if (!*s)
            break;
        char *end;
        double x = strtod(s, &end);
        if (end == s || !isfinite(x)) {
            snprintf(why, why_size, "value %zu is not a number", count + 1);
            result = -1;
            break;
        }
        s = end;
        if (count == capacity) {
            capacity = capacity ? 2 * capacity : 256;
            double *grown = realloc(numbers, capacity * sizeof *numbers);
            if (!grown) {
                snprintf(why, why_size, "out of memory");
                result = -1;
                break;
            }
            numbers = grown;
        }
        numbers[count++] = x;
    }
    if (result == 0 && count == 0) {
        snprintf(why, why_size, "no (wavelength, value) pairs");
        result = -1;
    }
    if (result == 0 && count % 2 != 0) {
        snprintf(why, why_size, "an odd number of values (%zu): expected (wavelength, value) pairs", count);
        result = -1;
    }
    double *lambda = NULL, *value = NULL;
    if (result == 0) {
        lambda = malloc(count / 2 * sizeof *lambda);
        value = malloc(count / 2 * sizeof *value);
        if (!lambda || !value) {
            snprintf(why, why_size, "out of memory");
            result = -1;
        }
    }
    for (size_t i = 0; result == 0 && i < count / 2; ++i) {
        lambda[i] = numbers[2 * i];
        value[i] = numbers[2 * i + 1];
        if (i > 0 && !(lambda[i] > lambda[i - 1])) {
            snprintf(why, why_size, "wavelengths do not increase at pair %zu (%g after %g)", i + 1, lambda[i],
                     lambda[i - 1]);
            result = -1;
        }
    }
    if (result == 0)
        spectrum_from_pairs(lambda, value, count / 2, 0, out); /* pbrt-v4 reads files as 0 outside */
    free(lambda);
    free(value);
    free(numbers);
    return result;
}

void spectrum_to_xyz(const Spectrum *s, double xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
        xyz[0] += spectrum_cie_x[i] * s->value[i];
        xyz[1] += spectrum_cie_y[i] * s->value[i];
        xyz[2] += spectrum_cie_z[i] * s->value[i];
    }
    for (int k = 0; k < 3; ++k)
        xyz[k] /= SPECTRUM_CIE_Y_INTEGRAL;
}

static void multiply(double m[3][3], const double v[3], double out[3])
{
    for (int r = 0; r < 3; ++r)
        out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
}

static void invert(double m[3][3], double out[3][3])
{
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            out[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
        }
}

static void d65_white(double xyz[3])
{
    Spectrum d65;
    spectrum_named("stdillum-D65", &d65);
    spectrum_to_xyz(&d65, xyz);
}

void spectrum_xyz_from_srgb(double m[3][3])
{
    /* pbrt-v4's RGBColorSpace: the sRGB primaries, scaled so that RGB
     * (1, 1, 1) is the XYZ of its D65 illuminant. */
    static const double primaries[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    double p[3][3], inverse[3][3], white[3], scale[3];
    for (int c = 0; c < 3; ++c) {
        double x = primaries[c][0], y = primaries[c][1];
        p[0][c] = x / y;
        p[1][c] = 1.0;
        p[2][c] = (1.0 - x - y) / y;
    }
    d65_white(white);
    invert(p, inverse);
    multiply(inverse, white, scale);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            m[r][c] = p[r][c] * scale[c];
}

void spectrum_srgb_from_xyz(double m[3][3])
{
    double xyz_from_srgb[3][3];
    spectrum_xyz_from_srgb(xyz_from_srgb);
    invert(xyz_from_srgb, m);
}

void spectrum_to_rgb(const Spectrum *s, SpectrumKind kind, double rgb[3])
{
    double srgb_from_xyz[3][3], xyz[3] = {0, 0, 0};
    spectrum_srgb_from_xyz(srgb_from_xyz);
    if (kind == SPECTRUM_ALBEDO) {
        /* The reflected light of the colour space's illuminant, relative to
         * the illuminant itself: a constant 1 is (1, 1, 1). */
        Spectrum d65, lit;
        spectrum_named("stdillum-D65", &d65);
        for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
            lit.value[i] = s->value[i] * d65.value[i];
        spectrum_to_xyz(&lit, xyz);
    } else if (kind == SPECTRUM_ILLUMINANT) {
        /* pbrt-v4's lights divide by SpectrumToPhotometric: luminance 1. */
        double y = y_sum(s);
        if (y > 0.0) {
            spectrum_to_xyz(s, xyz);
            for (int k = 0; k < 3; ++k)
                xyz[k] *= SPECTRUM_CIE_Y_INTEGRAL / y;
        }
    } else {
        /* Each channel averages the values with the channel's positive
         * sensitivity to D65 light (the rows of sRGB-from-XYZ applied to
         * the matching functions), so a constant spectrum keeps its value. */
        Spectrum d65;
        spectrum_named("stdillum-D65", &d65);
        for (int c = 0; c < 3; ++c) {
            double sum = 0.0, weight_sum = 0.0;
            for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
                double w = (srgb_from_xyz[c][0] * spectrum_cie_x[i] + srgb_from_xyz[c][1] * spectrum_cie_y[i] +
                            srgb_from_xyz[c][2] * spectrum_cie_z[i]) *
                           d65.value[i];
                if (w > 0.0) {
                    sum += w * s->value[i];
                    weight_sum += w;
                }
            }
            rgb[c] = sum / weight_sum;
        }
        return;
    }
    multiply(srgb_from_xyz, xyz, rgb);
}

double spectrum_eta(const Spectrum *s)
{
    return y_sum(s) / SPECTRUM_CIE_Y_INTEGRAL;
}

void spectrum_white_balance(const Spectrum *illuminant, double m[3][3])
{
    /* Bradford's cone responses, as pbrt-v4's LMSFromXYZ. */
    double lms_from_xyz[3][3] = {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
    double xyz_from_lms[3][3], source[3], target[3], source_lms[3], target_lms[3];
    invert(lms_from_xyz, xyz_from_lms);
    spectrum_to_xyz(illuminant, source);
    d65_white(target);
    /* pbrt-v4 balances chromaticities: both whites at Y = 1. */
    double source_y = source[1], target_y = target[1];
    for (int k = 0; k < 3; ++k) {
        source[k] /= source_y;
        target[k] /= target_y;
    }
    multiply(lms_from_xyz, source, source_lms);
    multiply(lms_from_xyz, target, target_lms);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            double sum = 0.0;
            for (int k = 0; k < 3; ++k)
                sum += xyz_from_lms[r][k] * (target_lms[k] / source_lms[k]) * lms_from_xyz[k][c];
            m[r][c] = sum;
        }
}

void spectrum_film_from_radiance(double imaging_ratio, double white_balance_kelvin, float m[3][3])
{
    double balance[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, srgb_from_xyz[3][3], xyz_from_srgb[3][3];
    if (!(white_balance_kelvin > 0.0)) {
        /* No white balance: exactly the imaging ratio times the identity
         * (the product of the two matrices below would leave 1e-16s off
         * its diagonal, and the kernel would apply a matrix for nothing). */
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                m[r][c] = r == c ? (float)imaging_ratio : 0.0f;
        return;
    }
    {
        Spectrum daylight;
        spectrum_daylight(white_balance_kelvin, &daylight);
        spectrum_white_balance(&daylight, balance);
    }
    spectrum_srgb_from_xyz(srgb_from_xyz);
    spectrum_xyz_from_srgb(xyz_from_srgb);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            double sum = 0.0;
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k)
                    sum += srgb_from_xyz[r][j] * balance[j][k] * xyz_from_srgb[k][c];
            m[r][c] = (float)(imaging_ratio * sum);
        }
}
