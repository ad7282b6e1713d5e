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

static const NamedSpectrumTable *find_table(const NamedSpectrumTable *tables, size_t count, const char *name)
{
    for (size_t i = 0; i < count; ++i)
        if (strcmp(name, tables[i].name) == 0)
            return &tables[i];
    return NULL;
}

int spectrum_named(const char *name, Spectrum *out)
{
    const NamedSpectrumTable *table = find_table(spectrum_named_tables, spectrum_named_table_count, name);
    if (!table)
        table = find_table(spectrum_sensor_tables, spectrum_sensor_table_count, name);
    if (table) {
        from_table(table, out);
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

/* Each channel averages the values with the channel's positive
 * sensitivity to D65 light (the rows of sRGB-from-XYZ applied to the
 * matching functions), so a constant spectrum keeps its value. */
static void channel_averages(const Spectrum *s, double rgb[3])
{
    double srgb_from_xyz[3][3];
    Spectrum d65;
    spectrum_srgb_from_xyz(srgb_from_xyz);
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
        channel_averages(s, rgb);
        return;
    }
    multiply(srgb_from_xyz, xyz, rgb);
}

void spectrum_conductor_rgb(const Spectrum *eta, const Spectrum *k, double eta_rgb[3], double k_rgb[3])
{
    Spectrum reflectance;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
        double n = eta->value[i], kk = k->value[i];
        reflectance.value[i] = ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk);
    }
    /* The target is what pbrt-v4 renders under white light: the sRGB of the
     * spectral reflectance (an albedo), within [0, 0.999] (gold's red is
     * 1.022, outside the gamut; no k reaches 1). */
    double r[3];
    spectrum_to_rgb(&reflectance, SPECTRUM_ALBEDO, r);
    channel_averages(eta, eta_rgb);
    for (int c = 0; c < 3; ++c) {
        r[c] = r[c] < 0.0 ? 0.0 : r[c] > 0.999 ? 0.999 : r[c];
        /* ((n-1)^2 + k^2) / ((n+1)^2 + k^2) = R, solved for k^2 ... */
        double n = eta_rgb[c], k2 = (r[c] * (n + 1) * (n + 1) - (n - 1) * (n - 1)) / (1.0 - r[c]);
        if (k2 >= 0.0) {
            k_rgb[c] = sqrt(k2);
            continue;
        }
        /* ... or, below a dielectric's reflectance at n, k = 0 and n solved
         * from ((n-1) / (n+1))^2 = R on n's side of 1. */
        double root = sqrt(r[c]);
        k_rgb[c] = 0.0;
        eta_rgb[c] = n >= 1.0 ? (1.0 + root) / (1.0 - root) : (1.0 - root) / (1.0 + root);
    }
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

/* A camera's r, g, b responses (<sensor>_r/_g/_b). Returns 0, or -1 for none. */
static int sensor_responses(const char *sensor, Spectrum response[3])
{
    static const char *const suffix[3] = {"_r", "_g", "_b"};
    for (int c = 0; c < 3; ++c) {
        char name[64];
        const NamedSpectrumTable *table = NULL;
        if ((size_t)snprintf(name, sizeof name, "%s%s", sensor, suffix[c]) < sizeof name)
            table = find_table(spectrum_sensor_tables, spectrum_sensor_table_count, name);
        if (!table)
            return -1;
        from_table(table, &response[c]);
    }
    return 0;
}

int spectrum_sensor_known(const char *sensor)
{
    Spectrum response[3];
    return strcmp(sensor, "cie1931") == 0 || sensor_responses(sensor, response) == 0;
}

void spectrum_sensor_list(char *buf, size_t size)
{
    size_t used = (size_t)snprintf(buf, size, "cie1931");
    for (size_t i = 0; i < spectrum_sensor_table_count && used < size; ++i) {
        /* Each camera has _r, _g and _b tables: name it once, by its _r. */
        const char *name = spectrum_sensor_tables[i].name;
        size_t length = strlen(name);
        if (length > 2 && strcmp(name + length - 2, "_r") == 0)
            used += (size_t)snprintf(buf + used, size - used, ", %.*s", (int)(length - 2), name);
    }
}

static double inner_product(const Spectrum *a, const Spectrum *b)
{
    double sum = 0.0;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
        sum += a->value[i] * b->value[i];
    return sum;
}

/* pbrt-v4's ProjectReflectance: the three responses to a reflectance under
 * an illuminant, relative to the second response to the illuminant. */
static void project_reflectance(const Spectrum *reflectance, const Spectrum *illuminant, const Spectrum basis[3],
                                double out[3])
{
    Spectrum lit;
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
        lit.value[i] = reflectance->value[i] * illuminant->value[i];
    for (int c = 0; c < 3; ++c)
        out[c] = inner_product(&basis[c], &lit) / inner_product(&basis[1], illuminant);
}

static void cie_matching_functions(Spectrum xyz[3])
{
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
        xyz[0].value[i] = spectrum_cie_x[i];
        xyz[1].value[i] = spectrum_cie_y[i];
        xyz[2].value[i] = spectrum_cie_z[i];
    }
}

int spectrum_sensor_xyz_from_sensor_rgb(const char *sensor, double white_balance_kelvin, double m[3][3])
{
    Spectrum response[3], xyz_bar[3], daylight, d65;
    if (sensor_responses(sensor, response))
        return -1;
    cie_matching_functions(xyz_bar);
    spectrum_daylight(white_balance_kelvin, &daylight);
    spectrum_named("stdillum-D65", &d65);
    /* pbrt-v4 scales the XYZ so that the fit keeps the sensor's luminance
     * scale: a white under the daylight illuminant maps to Y = its luminance. */
    double scale = inner_product(&daylight, &xyz_bar[1]) / inner_product(&daylight, &response[1]);
    /* Normal equations of the least-squares fit XYZ_i ~ m * sensor_i. */
    double ata[3][3] = {{0}}, atb[3][3] = {{0}}, inverse[3][3];
    for (int s = 0; s < SPECTRUM_SWATCH_COUNT; ++s) {
        Spectrum swatch;
        double camera[3], xyz[3];
        from_table(&spectrum_swatch_tables[s], &swatch);
        project_reflectance(&swatch, &daylight, response, camera);
        project_reflectance(&swatch, &d65, xyz_bar, xyz);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                ata[r][c] += camera[r] * camera[c];
                atb[r][c] += camera[r] * xyz[c] * scale;
            }
    }
    invert(ata, inverse);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            m[r][c] = inverse[c][0] * atb[0][r] + inverse[c][1] * atb[1][r] + inverse[c][2] * atb[2][r];
    return 0;
}

int spectrum_sensor_from_srgb(const char *sensor, double m[3][3])
{
    Spectrum response[3], d65;
    if (sensor_responses(sensor, response))
        return -1;
    spectrum_named("stdillum-D65", &d65);
    for (int c = 0; c < 3; ++c) {
        Spectrum basis, lit;
        from_table(&spectrum_srgb_basis_tables[c], &basis);
        for (int i = 0; i < SPECTRUM_SAMPLES; ++i)
            lit.value[i] = d65.value[i] * basis.value[i] / SPECTRUM_CIE_Y_INTEGRAL; /* luminance-1 D65 */
        for (int r = 0; r < 3; ++r)
            m[r][c] = inner_product(&response[r], &lit);
    }
    return 0;
}

static void product(double a[3][3], double b[3][3], double out[3][3])
{
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            out[r][c] = a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c];
}

int spectrum_film_from_radiance(const char *sensor, double imaging_ratio, double white_balance_kelvin, float m[3][3])
{
    double xyz_from_sensor[3][3], sensor_from_srgb[3][3], srgb_from_xyz[3][3];
    if (strcmp(sensor, "cie1931") != 0) {
        double kelvin = white_balance_kelvin > 0.0 ? white_balance_kelvin : 6500.0; /* pbrt-v4's camera default */
        if (spectrum_sensor_xyz_from_sensor_rgb(sensor, kelvin, xyz_from_sensor) ||
            spectrum_sensor_from_srgb(sensor, sensor_from_srgb))
            return -1;
    } else if (white_balance_kelvin > 0.0) {
        Spectrum daylight;
        spectrum_daylight(white_balance_kelvin, &daylight);
        spectrum_white_balance(&daylight, xyz_from_sensor);
        spectrum_xyz_from_srgb(sensor_from_srgb);
    } else {
        /* No white balance: exactly the imaging ratio times the identity
         * (the product of sRGB-from-XYZ and XYZ-from-sRGB would leave
         * 1e-16s off its diagonal, and the kernel would apply a matrix for
         * nothing). */
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                m[r][c] = r == c ? (float)imaging_ratio : 0.0f;
        return 0;
    }
    double xyz_from_radiance[3][3], film[3][3];
    spectrum_srgb_from_xyz(srgb_from_xyz);
    product(xyz_from_sensor, sensor_from_srgb, xyz_from_radiance);
    product(srgb_from_xyz, xyz_from_radiance, film);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            m[r][c] = (float)(imaging_ratio * film[r][c]);
    return 0;
}

void spectrum_blackbody_srgb(double kelvin, double rgb[3])
{
    double xyz[3] = {0.0, 0.0, 0.0}, srgb_from_xyz[3][3];
    if (kelvin > 100.0) {
        Spectrum b;
        spectrum_blackbody(kelvin, &b);
        spectrum_to_xyz(&b, xyz);
    }
    spectrum_srgb_from_xyz(srgb_from_xyz);
    for (int k = 0; k < 3; ++k) {
        rgb[k] = 0.0;
        for (int j = 0; j < 3; ++j)
            rgb[k] += srgb_from_xyz[k][j] * xyz[j];
        rgb[k] = fmax(0.0, rgb[k]);
    }
}
