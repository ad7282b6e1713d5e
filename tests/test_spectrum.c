/* Spectra reduced to RGB (host/scene/spectrum.c) against values computed
 * independently by tests/support/spectrum_reference.py (trapezoidal
 * integration in numpy with colour-science's sRGB matrix), the .spd reader,
 * and the film matrix. */
#include "scene/spectrum.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

static void assert_close(double actual, double expected, double relative)
{
    if (!(fabs(actual - expected) <= relative * fabs(expected)))
        fail_msg("%.6g is not within %g%% of %.6g", actual, 100.0 * relative, expected);
}

static void assert_rgb(const double rgb[3], double r, double g, double b, double relative)
{
    assert_close(rgb[0], r, relative);
    assert_close(rgb[1], g, relative);
    assert_close(rgb[2], b, relative);
}

static void named_rgb(const char *name, SpectrumKind kind, double rgb[3])
{
    Spectrum s;
    assert_int_equal(spectrum_named(name, &s), 0);
    spectrum_to_rgb(&s, kind, rgb);
}

static void test_blackbody(void **state)
{
    (void)state;
    /* spectrum_reference.py: luminance-1 linear sRGB of Planck's law. */
    static const double expected[3][4] = {{2700, 1.93487226, 0.80375314, 0.19186044},
                                          {5500, 1.14427873, 0.97107067, 0.86233741},
                                          {6500, 1.04321978, 0.98367477, 1.03504627}};
    for (int i = 0; i < 3; ++i) {
        Spectrum s;
        double rgb[3], peak = 0.0;
        spectrum_blackbody(expected[i][0], &s);
        for (int k = 0; k < SPECTRUM_SAMPLES; ++k)
            peak = s.value[k] > peak ? s.value[k] : peak;
        /* pbrt-v4's normalisation: 1 at the peak (Wien: 527 nm at 5500 K,
         * 446 nm at 6500 K, on the grid; 1073 nm at 2700 K, beyond it). */
        if (expected[i][0] > 3000)
            assert_true(peak <= 1.0 && peak > 0.99999);
        else
            assert_true(peak < 0.9);
        spectrum_to_rgb(&s, SPECTRUM_ILLUMINANT, rgb);
        assert_rgb(rgb, expected[i][1], expected[i][2], expected[i][3], 2e-3);
    }
}

static void test_named_illuminants(void **state)
{
    (void)state;
    double rgb[3], xyz[3];
    named_rgb("stdillum-D65", SPECTRUM_ILLUMINANT, rgb);
    assert_rgb(rgb, 1.0, 1.0, 1.0, 1e-6); /* the colour space's own white */
    named_rgb("stdillum-A", SPECTRUM_ILLUMINANT, rgb);
    assert_rgb(rgb, 1.84512335, 0.82623954, 0.23338062, 2e-3);
    named_rgb("stdillum-F11", SPECTRUM_ILLUMINANT, rgb);
    assert_rgb(rgb, 1.41213252, 0.92485017, 0.5315018, 2e-3);
    /* pbrt-v4 scales its illuminants to luminance 1. */
    Spectrum a;
    assert_int_equal(spectrum_named("stdillum-A", &a), 0);
    spectrum_to_xyz(&a, xyz);
    assert_close(xyz[1], 1.0, 1e-9);
    assert_int_equal(spectrum_named("stdillum-D66", &a), -1);
    assert_int_equal(spectrum_named("metal-Xx-eta", &a), -1);
}

static void test_named_metal_and_glass(void **state)
{
    (void)state;
    double rgb[3];
    named_rgb("metal-Au-eta", SPECTRUM_UNBOUNDED, rgb);
    assert_rgb(rgb, 0.282615, 0.479352, 1.435338, 3e-3);
    named_rgb("metal-Au-k", SPECTRUM_UNBOUNDED, rgb);
    assert_rgb(rgb, 2.977891, 2.484696, 1.871997, 3e-3);
    Spectrum bk7;
    assert_int_equal(spectrum_named("glass-BK7", &bk7), 0);
    assert_close(spectrum_eta(&bk7), 1.51825190648, 1e-5);
    /* A constant spectrum keeps its value in every channel. */
    double one = 1.0, lambda = 500.0;
    Spectrum constant;
    spectrum_from_pairs(&lambda, &one, 1, 1, &constant);
    spectrum_to_rgb(&constant, SPECTRUM_UNBOUNDED, rgb);
    assert_rgb(rgb, 1.0, 1.0, 1.0, 1e-12);
    spectrum_to_rgb(&constant, SPECTRUM_ALBEDO, rgb);
    assert_rgb(rgb, 1.0, 1.0, 1.0, 1e-9);
}

static void test_albedo_step(void **state)
{
    (void)state;
    const double lambda[2] = {499, 501}, value[2] = {0.2, 0.8};
    Spectrum s;
    double rgb[3];
    spectrum_from_pairs(lambda, value, 2, 1, &s);
    assert_close(s.value[0], 0.2, 0);   /* held below the first wavelength */
    assert_close(s.value[470], 0.8, 0); /* and above the last */
    assert_close(s.value[140], 0.5, 1e-12);
    spectrum_to_rgb(&s, SPECTRUM_ALBEDO, rgb);
    assert_rgb(rgb, 0.83292015, 0.79247081, 0.14119011, 3e-3);
}

static void test_spd(void **state)
{
    (void)state;
    Spectrum s;
    char why[160];
    assert_int_equal(spectrum_parse_spd("# lambda value\n400 1 # a comment\n 600 3\n", &s, why, sizeof why), 0);
    assert_close(s.value[0], 0.0, 0); /* files are 0 outside their range (pbrt-v4's reader) */
    assert_close(s.value[40], 1.0, 1e-12);
    assert_close(s.value[140], 2.0, 1e-12);
    assert_close(s.value[240], 3.0, 1e-12);
    assert_close(s.value[241], 0.0, 0);
    assert_int_equal(spectrum_parse_spd("400 1 500", &s, why, sizeof why), -1);
    assert_non_null(strstr(why, "odd number of values (3)"));
    assert_int_equal(spectrum_parse_spd("400 1 400 2", &s, why, sizeof why), -1);
    assert_non_null(strstr(why, "do not increase at pair 2"));
    assert_int_equal(spectrum_parse_spd("400 one", &s, why, sizeof why), -1);
    assert_non_null(strstr(why, "value 2 is not a number"));
    assert_int_equal(spectrum_parse_spd("# nothing\n", &s, why, sizeof why), -1);
    assert_non_null(strstr(why, "no (wavelength, value) pairs"));
}

static void test_film_matrix(void **state)
{
    (void)state;
    float m[3][3];
    spectrum_film_from_radiance(1.0, 0.0, m);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            assert_true(fabs(m[r][c] - (r == c ? 1.0 : 0.0)) < 1e-6);
    spectrum_film_from_radiance(1.5, 0.0, m); /* iso 150 */
    assert_close(m[1][1], 1.5, 1e-6);
    /* White balance at T makes the daylight illuminant at T neutral. */
    Spectrum daylight;
    double rgb[3];
    spectrum_daylight(5000.0, &daylight);
    spectrum_to_rgb(&daylight, SPECTRUM_ILLUMINANT, rgb);
    assert_true(rgb[0] > 1.05 * rgb[2]); /* warm before */
    spectrum_film_from_radiance(1.0, 5000.0, m);
    double out[3];
    for (int r = 0; r < 3; ++r)
        out[r] = m[r][0] * rgb[0] + m[r][1] * rgb[1] + m[r][2] * rgb[2];
    assert_close(out[0], out[1], 1e-3);
    assert_close(out[2], out[1], 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blackbody),
        cmocka_unit_test(test_named_illuminants),
        cmocka_unit_test(test_named_metal_and_glass),
        cmocka_unit_test(test_albedo_step),
        cmocka_unit_test(test_spd),
        cmocka_unit_test(test_film_matrix),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
