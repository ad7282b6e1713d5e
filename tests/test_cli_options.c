/* gmonrt's command line: defaults, every flag, and one-line errors with exit
 * code 2 for bad flags and values. */
#include "cli/options.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#define PARSE(options, error, ...)                                                                                     \
    options_parse((int)(sizeof((char *[]){"gmonrt", __VA_ARGS__}) / sizeof(char *)),                                   \
                  (char *[]){"gmonrt", __VA_ARGS__}, options, error, sizeof error)

static void test_defaults(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    char *argv[] = {"gmonrt"};
    assert_int_equal(options_parse(1, argv, &o, error, sizeof error), 0);
    assert_int_equal(o.command, COMMAND_RENDER);
    assert_null(o.input);
    assert_int_equal(o.estimator.set_count, 21);
    assert_int_equal(o.estimator.gini_mode, GINI_PER_CHANNEL);
    assert_int_equal(o.outputs, ESTIMATOR_OUTPUT_MEAN | ESTIMATOR_OUTPUT_MON | ESTIMATOR_OUTPUT_GMON);
    assert_string_equal(o.preview, "gmon");
    assert_int_equal(o.max_depth, -1);
    assert_int_equal(o.spp, 0);
}

static void test_every_flag(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "--spp", "128", "--seed=9", "--sets", "5", "--estimators", "mean,gmon",
                           "--gini-mode", "luminance", "--preview", "mean", "--exposure", "2.5", "--time", "30",
                           "--resolution", "320x200", "--maxdepth", "7", "--integrator", "bsdf", "--device", "cpu",
                           "--outfile", "x.exr", "--first-sample", "64", "--diagnostics", "--write-sets", "--quiet",
                           "--allow-unsupported", "--kernel-dir", "k", "scene.pbrt"),
                     0);
    assert_int_equal(o.spp, 128);
    assert_int_equal(o.seed, 9);
    assert_int_equal(o.estimator.set_count, 5);
    assert_int_equal(o.outputs, ESTIMATOR_OUTPUT_MEAN | ESTIMATOR_OUTPUT_GMON);
    assert_int_equal(o.estimator.gini_mode, SORT_BY_LUMINANCE);
    assert_string_equal(o.preview, "mean");
    assert_true(o.exposure == 2.5f);
    assert_true(o.time_budget == 30.0);
    assert_int_equal(o.width, 320);
    assert_int_equal(o.height, 200);
    assert_int_equal(o.max_depth, 7);
    assert_int_equal(o.bsdf_only, 1);
    assert_string_equal(o.devices, "cpu");
    assert_string_equal(o.outfile, "x.exr");
    assert_int_equal(o.first_sample, 64);
    assert_true(o.diagnostics && o.write_sets && o.quiet && o.allow_unsupported);
    assert_string_equal(o.kernel_dir, "k");
    assert_string_equal(o.input, "scene.pbrt");
}

static void test_subcommands(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "estimate", "--gini-mode", "pixel", "in.exr"), 0);
    assert_int_equal(o.command, COMMAND_ESTIMATE);
    assert_string_equal(o.input, "in.exr");
    assert_int_equal(PARSE(&o, error, "estimate"), 2);
    assert_int_equal(PARSE(&o, error, "--list-devices"), 0);
    assert_int_equal(o.command, COMMAND_LIST_DEVICES);
    assert_int_equal(PARSE(&o, error, "--help"), 0);
    assert_int_equal(o.command, COMMAND_HELP);
    assert_non_null(strstr(options_help(), "--spp"));
}

static void expect_error(const char *flag, const char *value, const char *fragment)
{
    Options o;
    char error[256] = "";
    char *argv[] = {"gmonrt", (char *)flag, (char *)value};
    int argc = value ? 3 : 2;
    assert_int_equal(options_parse(argc, argv, &o, error, sizeof error), 2);
    assert_non_null(strchr(error, ' '));
    assert_null(strchr(error, '\n'));
    if (!strstr(error, fragment))
        fail_msg("error for %s %s was '%s', expected it to mention '%s'", flag, value ? value : "", error, fragment);
}

static void test_bad_flags_and_values(void **state)
{
    (void)state;
    expect_error("--bogus", NULL, "--bogus");
    expect_error("--spp", NULL, "needs a value");
    expect_error("--spp", "0", "--spp");
    expect_error("--spp", "-4", "--spp");
    expect_error("--spp", "12x", "--spp");
    expect_error("--sets", "0", "1..64");
    expect_error("--sets", "65", "1..64");
    expect_error("--seed", "4294967296", "--seed");
    expect_error("--estimators", "mean,median", "--estimators");
    expect_error("--gini-mode", "global", "--gini-mode");
    expect_error("--resolution", "640", "WIDTHxHEIGHT");
    expect_error("--resolution", "0x480", "WIDTHxHEIGHT");
    expect_error("--time", "-1", "--time");
    expect_error("--time", "nan", "--time");
    expect_error("--integrator", "bdpt", "--integrator");
    expect_error("--preview", "median", "--preview");
    expect_error("--maxdepth", "many", "--maxdepth");
    expect_error("--quiet=yes", NULL, "takes no value");
    Options o;
    char error[256];
    assert_int_equal(PARSE(&o, error, "--estimators", "mean", "--preview", "gmon"), 2);
    assert_int_equal(PARSE(&o, error, "a.pbrt", "b.pbrt"), 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_every_flag),
        cmocka_unit_test(test_subcommands),
        cmocka_unit_test(test_bad_flags_and_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
