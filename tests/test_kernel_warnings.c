/* The kernels build without a warning (clBuildProgram with -Werror), so
 * none reaches a user's terminal: the path tracer (and bdpt.cl) with every feature, with
 * each feature left out and with each alone (feature_mask.h: a feature
 * left out folds its tests to constants, where the compiler's warnings
 * about constant operands arise), and with each per-sample estimator; the
 * sample estimator with each; the estimator kernel over set counts, Gini
 * modes, standard errors, vector widths and the whole family. */
#include "cl/cl_device.h"
#include "feature_mask.h"
#include "film/estimator_program.h"
#include "film/film_sample.h"
#include "estimators.h"
#include "render/renderer.h"
#include "sampler.h"
#include "test_device.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

static int builds_without_warnings(const char *name, const char *options)
{
    char all[1200];
    snprintf(all, sizeof all, "-Werror %s", options);
    cl_program program = cl_program_build(&test_device, name, all, NULL);
    if (!program)
        return 0;
    clReleaseProgram(program);
    return 1;
}

static void test_path_tracer_variants(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings settings;
    render_settings_default(&settings);
    int failures = 0, builds = 0;
    /* Every feature; each left out; each alone (beside triangles, which
     * every scene but one of spheres alone has). */
    for (int variant = 0; variant < 129; ++variant) {
        int bit = (variant - 1) % 64;
        uint64_t features = FEATURES_ALL, feature = 1ull << bit;
        if (variant > 0 && !(FEATURES_ALL & feature))
            continue;
        if (variant > 0)
            features = variant <= 64 ? FEATURES_ALL & ~feature : FEATURE_TRIANGLES | feature;
        char options[1024];
        path_tracer_build_options(&settings.estimator, features, SAMPLER_SOBOL_SETS, settings.estimator.set_count, 128,
                                  options, sizeof options);
        ++builds;
        if (!builds_without_warnings("path_tracer", options)) {
            printf("  path tracer with features 0x%llx: warnings\n", (unsigned long long)features);
            ++failures;
        }
        /* bdpt.cl (lightpath, bdpt) with every feature and each alone. */
        if (variant == 0 || variant > 64) {
            ++builds;
            strncat(options, " -DBDPT_MAX_DEPTH=5", sizeof options - strlen(options) - 1);
            if (!builds_without_warnings("bdpt", options)) {
                printf("  bdpt with features 0x%llx: warnings\n", (unsigned long long)features);
                ++failures;
            }
        }
    }
    printf("  %d path tracer and bdpt builds, %d with warnings\n", builds, failures);
    assert_int_equal(failures, 0);
}

/* Each per-sample estimator: the path tracer that keeps its state and
 * the kernel that estimates it. */
static void test_sample_estimator_variants(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    int failures = 0;
    for (int pass = 0; pass < PASS_COUNT; ++pass) {
        if (!(PASSES_SAMPLE & PASS_BIT(pass)))
            continue;
        RenderSettings settings;
        render_settings_default(&settings);
        settings.estimator.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(pass);
        char options[1024];
        path_tracer_build_options(&settings.estimator, FEATURES_ALL, SAMPLER_SOBOL_SETS, settings.estimator.set_count,
                                  128, options, sizeof options);
        if (!builds_without_warnings("path_tracer", options)) {
            printf("  path tracer with %s: warnings\n", pass_name(pass));
            ++failures;
        }
        film_sample_estimator_options(&settings.estimator, options, sizeof options);
        if (!builds_without_warnings("sample_estimator", options)) {
            printf("  sample estimator with %s: warnings\n", pass_name(pass));
            ++failures;
        }
    }
    assert_int_equal(failures, 0);
}

static void test_estimator_variants(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    static const struct {
        int set_count;
        uint32_t passes;
        int with_stderr, gini_mode, vector_width;
    } variants[] = {
        {21, PASSES_ALL, 1, EST_GINI_PER_CHANNEL, 8},    {21, PASSES_ALL, 1, EST_GINI_PER_PIXEL, 1},
        {21, PASSES_ALL, 0, EST_SORT_BY_LUMINANCE, 8},   {2, PASSES_ALL, 1, EST_GINI_PER_CHANNEL, 16},
        {1, PASSES_DEFAULT, 0, EST_GINI_PER_CHANNEL, 8}, {64, PASSES_DEFAULT, 1, EST_GINI_PER_CHANNEL, 4},
    };
    int failures = 0;
    for (size_t i = 0; i < sizeof variants / sizeof variants[0]; ++i) {
        EstimatorSettings settings;
        estimator_settings_default(&settings);
        settings.set_count = variants[i].set_count;
        settings.passes = variants[i].passes;
        settings.with_stderr = variants[i].with_stderr;
        settings.gini_mode = variants[i].gini_mode;
        EstimatorLaunch launch = {variants[i].vector_width, 0, 1};
        char options[256];
        estimator_build_options(&settings, &launch, options, sizeof options);
        if (!builds_without_warnings("estimator", options)) {
            printf("  estimator with %s: warnings\n", options);
            ++failures;
        }
    }
    assert_int_equal(failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_path_tracer_variants),
        cmocka_unit_test(test_sample_estimator_variants),
        cmocka_unit_test(test_estimator_variants),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
