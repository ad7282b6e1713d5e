/* The kernels build without a warning (clBuildProgram with -Werror), so
 * none reaches a user's terminal: the path tracer (and bdpt.cl) with every feature, with
 * each feature left out and with each alone (feature_mask.h: a feature
 * left out folds its tests to constants, where the compiler's warnings
 * about constant operands arise). */
#include "cl/cl_device.h"
#include "feature_mask.h"
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_path_tracer_variants),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
