/* gmonrt's command line: defaults, every flag, and one-line errors with exit
 * code 2 for bad flags and values, and for flags a subcommand does not take. */
#include "cli/options.h"
#include "scene/scene.h"
#include "film/film.h"
#include "passes.h"
#include "sampler.h"
#include "scene_types.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
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
    assert_int_equal(o.estimator.passes, PASSES_DEFAULT);
    assert_int_equal(o.estimator.with_stderr, 0);
    assert_int_equal(o.preview, PASS_GMON);
    assert_int_equal(o.max_depth, -1);
    assert_int_equal(o.spp, 0);
}

/* --integrator: the path tracer (nee, bsdf), bdpt or the light tracer;
 * without it the scene's Integrator decides. */
static void test_integrators(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "scene.pbrt"), 0);
    assert_int_equal(o.light_subpaths, -1);
    assert_int_equal(PARSE(&o, error, "--integrator", "bdpt", "scene.pbrt"), 0);
    assert_int_equal(o.light_subpaths, SCENE_BDPT);
    assert_int_equal(o.bsdf_only, 0);
    assert_int_equal(PARSE(&o, error, "--integrator", "lightpath", "scene.pbrt"), 0);
    assert_int_equal(o.light_subpaths, SCENE_LIGHTPATH);
    assert_int_equal(PARSE(&o, error, "--integrator", "nee", "scene.pbrt"), 0);
    assert_int_equal(o.light_subpaths, 0);
    assert_int_equal(o.bsdf_only, 0);
}

static void test_every_flag(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "--spp", "128", "--seed=9", "--sets", "5", "--estimators", "mean,gmon",
                           "--gini-mode", "luminance", "--preview", "mean", "--exposure", "2.5", "--time", "30",
                           "--resolution", "320x200", "--maxdepth", "7", "--integrator", "bsdf", "--sampler",
                           "sobol-pixel", "--light-sampler", "power", "--device", "cpu", "--outfile", "x.exr",
                           "--first-sample", "64", "--diagnostics", "--write-sets", "--quiet", "--allow-unsupported",
                           "--kernel-dir", "k", "scene.pbrt"),
                     0);
    assert_int_equal(o.spp, 128);
    assert_int_equal(o.seed, 9);
    assert_int_equal(o.estimator.set_count, 5);
    assert_int_equal(o.estimator.passes, PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_GMON) | PASSES_DIAGNOSTICS);
    assert_int_equal(o.estimator.gini_mode, SORT_BY_LUMINANCE);
    assert_int_equal(o.preview, PASS_MEAN);
    assert_true(o.exposure == 2.5f);
    assert_true(o.time_budget == 30.0);
    assert_int_equal(o.width, 320);
    assert_int_equal(o.height, 200);
    assert_int_equal(o.max_depth, 7);
    assert_int_equal(o.bsdf_only, 1);
    assert_int_equal(o.light_subpaths, 0); /* the path tracer, whatever the scene asks */
    assert_int_equal(o.sampler, SAMPLER_SOBOL_PIXEL);
    assert_int_equal(o.light_sampler, LIGHT_SAMPLER_POWER);
    assert_int_equal(o.devices.kind, DEVICES_CPU);
    assert_string_equal(o.devices.spec, "cpu");
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
    assert_true(o.help);
    assert_int_equal(o.command, COMMAND_RENDER);
    assert_non_null(strstr(options_help(COMMAND_RENDER), "--spp N"));
    assert_non_null(strstr(options_help(COMMAND_RENDER), "143"));
}

/* --help lists every estimator and parameter of kernels/film/passes.h's tables
 * (a new row is listed without a line in options.c). */
#define PARAMETER_NAME_(type, field, name, value, lowest, highest) name,
static void test_help_lists_the_tables(void **state)
{
    (void)state;
    const char *help = options_help(COMMAND_ESTIMATE);
    for (int p = 0; p < PASS_COUNT; ++p)
        if ((PASSES_ESTIMATES | PASSES_SAMPLE) & PASS_BIT(p))
            assert_non_null(strstr(options_help(COMMAND_RENDER), pass_name(p)));
    static const char *const parameters[] = {GMON_ESTIMATOR_PARAMS(PARAMETER_NAME_) "clamp.levels"};
    for (size_t i = 0; i < sizeof parameters / sizeof parameters[0]; ++i)
        assert_non_null(strstr(help, parameters[i]));
}

/* Every parameter row names its estimator's row: "<estimator>.<name>". */
static void test_parameters_belong_to_estimators(void **state)
{
    (void)state;
    static const char *const parameters[] = {GMON_ESTIMATOR_PARAMS(PARAMETER_NAME_) "clamp.levels"};
    for (size_t i = 0; i < sizeof parameters / sizeof parameters[0]; ++i) {
        char estimator[64];
        snprintf(estimator, sizeof estimator, "%.*s", (int)strcspn(parameters[i], "."), parameters[i]);
        if (pass_from_name(estimator) < 0)
            fail_msg("parameter %s: no estimator '%s' in GMON_PASSES", parameters[i], estimator);
    }
}

/* Each subcommand takes only the flags it uses, and has its own --help. */
static void test_subcommand_flags_and_help(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    const char *render_only[] = {"--spp", "--sets", "--device", "--seed", "--time", "--checkpoints", "--kernel-dir"};
    for (size_t i = 0; i < sizeof render_only / sizeof render_only[0]; ++i) {
        assert_int_equal(PARSE(&o, error, "estimate", (char *)render_only[i], "4", "in.exr"), 2);
        assert_non_null(strstr(error, render_only[i]));
        assert_non_null(strstr(error, "gmonrt estimate --help"));
        assert_int_equal(PARSE(&o, error, "merge", (char *)render_only[i], "4", "a.exr", "b.exr"), 2);
        assert_non_null(strstr(error, "gmonrt merge --help"));
    }
    assert_int_equal(PARSE(&o, error, "merge", "--write-sets", "a.exr"), 2); /* merge always keeps the sums */
    assert_int_equal(PARSE(&o, error, "estimate", "--write-sets", "--diagnostics", "--outfile", "x.exr", "--quiet",
                           "--estimators", "mean", "--exposure", "2", "in.exr"),
                     0);
    assert_int_equal(PARSE(&o, error, "merge", "--diagnostics", "--gini-mode", "pixel", "a.exr", "b.exr"), 0);
    assert_int_equal(o.merge_count, 2);

    /* --help needs no input file, and lists only the subcommand's flags. */
    assert_int_equal(PARSE(&o, error, "estimate", "--help"), 0);
    assert_true(o.help);
    assert_int_equal(o.command, COMMAND_ESTIMATE);
    const char *estimate = options_help(COMMAND_ESTIMATE);
    assert_non_null(strstr(estimate, "usage: gmonrt estimate"));
    assert_non_null(strstr(estimate, "--gini-mode"));
    assert_non_null(strstr(estimate, "  --write-sets "));
    assert_non_null(strstr(estimate, "  --help "));
    assert_null(strstr(estimate, "--spp"));
    assert_null(strstr(estimate, "--device"));
    const char *merge = options_help(COMMAND_MERGE);
    assert_non_null(strstr(merge, "usage: gmonrt merge"));
    assert_non_null(strstr(merge, "merged.exr"));
    assert_null(strstr(merge, "  --write-sets "));
    assert_null(strstr(merge, "  --sets "));
}

/* The estimator family by name, its parameters and standard errors. */
static void test_estimator_family_flags(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "--estimators", "all", "--stderr", "--estimator-param", "admon.alpha=0.25",
                           "--estimator-param=trimmed.c=2", "--preview", "gmon-authors"),
                     0);
    assert_int_equal(o.estimator.passes, PASSES_ESTIMATES);
    assert_int_equal(o.estimator.with_stderr, 1);
    assert_true(o.estimator.params.admon_alpha == 0.25f);
    assert_int_equal(o.estimator.params.trimmed_c, 2);
    assert_true(o.estimator.params.amon_alpha == 0.5f); /* the others keep their defaults */
    assert_int_equal(o.preview, PASS_GMON_AUTHORS);
    /* Without gmon, the preview is the first estimator asked for. */
    assert_int_equal(PARSE(&o, error, "--estimators", "winsorized,pakmon"), 0);
    assert_int_equal(o.preview, PASS_PAKMON);
    assert_int_equal(PARSE(&o, error, "--estimators", "gmedian", "--preview", "mean"), 2);
    assert_non_null(strstr(error, "not among --estimators"));
    assert_int_equal(PARSE(&o, error, "--stderr", "--gini-mode", "luminance"), 2);
    assert_non_null(strstr(error, "--stderr"));
    assert_int_equal(PARSE(&o, error, "--estimator-param", "amon.alpha=3"), 2);
    assert_non_null(strstr(error, "amon.alpha"));
    assert_int_equal(PARSE(&o, error, "--estimator-param", "alpha=0.3"), 2);
    assert_non_null(strstr(error, "known parameter"));
    assert_int_equal(PARSE(&o, error, "--estimators", "gmon,trim"), 2);
    assert_non_null(strstr(error, "unknown estimator 'trim'"));
    /* estimate picks its preview once the file's estimators are known. */
    assert_int_equal(PARSE(&o, error, "estimate", "in.exr"), 0);
    assert_int_equal(o.preview, -1);
    assert_int_equal(PARSE(&o, error, "merge", "a.exr", "b.exr"), 0);
    assert_int_equal(o.preview, -1);
    assert_non_null(strstr(options_help(COMMAND_ESTIMATE), "--estimator-param"));
}

static void test_device_selection(void **state)
{
    (void)state;
    Options o;
    char error[256] = "";
    assert_int_equal(PARSE(&o, error, "scene.pbrt"), 0);
    assert_int_equal(o.devices.kind, DEVICES_ALL);
    assert_int_equal(PARSE(&o, error, "--device", "2,0"), 0);
    assert_int_equal(o.devices.kind, DEVICES_INDICES);
    assert_int_equal(o.devices.index_count, 2);
    assert_int_equal(o.devices.indices[0], 2);
    assert_int_equal(o.devices.indices[1], 0);
    assert_int_equal(PARSE(&o, error, "--device", "gpu"), 0);
    assert_int_equal(o.devices.kind, DEVICES_GPU);
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
    expect_error("--integrator", "mlt", "--integrator");
    expect_error("--preview", "median", "--preview");
    expect_error("--maxdepth", "many", "--maxdepth");
    expect_error("--sampler", "halton", "--sampler");
    expect_error("--light-sampler", "spatial", "--light-sampler");
    expect_error("--quiet=yes", NULL, "takes no value");
    /* 4294967304 is 2^32 + 8: read as 32 bits it would render 8x8. */
    expect_error("--resolution", "4294967304x8", "WIDTHxHEIGHT");
    expect_error("--resolution", "8x4294967304", "WIDTHxHEIGHT");
    expect_error("--resolution", "65537x8", "1..65536");
    expect_error("--resolution", "+8x8", "WIDTHxHEIGHT");
    expect_error("--resolution", "8x8x", "WIDTHxHEIGHT");
    expect_error("--device", "", "--device");
    expect_error("--device", "gpus", "--device");
    expect_error("--device", "-1", "--device");
    expect_error("--device", "0,", "--device");
    expect_error("--device", "0,,1", "--device");
    expect_error("--device", "1,x", "--device");
    expect_error("--device", "1,1", "named twice");
    /* These would write a hidden ./.exr. */
    expect_error("--outfile", "", "names no file");
    expect_error("--outfile", "out/", "names no file");
    expect_error("--outfile", ".exr", "names no file");
    Options o;
    char error[256];
    assert_int_equal(PARSE(&o, error, "--estimators", "mean", "--preview", "gmon"), 2);
    assert_int_equal(PARSE(&o, error, "a.pbrt", "b.pbrt"), 2);
    assert_int_equal(PARSE(&o, error, "--outfile", "out/.hidden.exr", "--resolution", "65536x1"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_every_flag),
        cmocka_unit_test(test_integrators),
        cmocka_unit_test(test_subcommands),
        cmocka_unit_test(test_subcommand_flags_and_help),
        cmocka_unit_test(test_help_lists_the_tables),
        cmocka_unit_test(test_parameters_belong_to_estimators),
        cmocka_unit_test(test_device_selection),
        cmocka_unit_test(test_bad_flags_and_values),
        cmocka_unit_test(test_estimator_family_flags),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
