/* Several devices, one image: a render on every device present equals the
 * render on the first device alone, bit for bit (sums, counters and every
 * estimate), also when a device fails to build or fails mid-render; when
 * every device fails the samples saved before are still a valid render.
 * Also: checkpoints, the mean-only single sum, sample ranges not starting
 * at set 0, and the feature mask.
 *
 * CTest runs this under several POCL_DEVICES settings; GMON_EXPECT_DEVICES
 * says how many devices that must give, so that a setting PoCL ignored
 * cannot pass unnoticed. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "film/film.h"
#include "film/film_sample.h"
#include "estimators.h"
#include "feature_mask.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "exact_sum.h"
#include "test_device.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define MAX_DEVICES 8

static ClDevice devices[MAX_DEVICES];
static int device_count;
static RenderScene glass;

static int setup(void **state)
{
    (void)state;
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    SceneSummary summary;
    if (scene_convert_load(path, 0, 40, 30, 1, &glass, &summary, error, sizeof error) ||
        render_scene_finalize(&glass, error, sizeof error)) {
        fprintf(stderr, "%s\n", error);
        return -1;
    }
    ClDeviceInfo infos[MAX_DEVICES];
    ClDevice first;
    if (!test_device_open(&first))
        return test_running_in_ci() ? -1 : 0;
    cl_device_close(&first);
    int count = cl_devices_enumerate(infos, MAX_DEVICES);
    for (int i = 0; i < count; ++i)
        if (cl_device_open(&devices[device_count], &infos[i]) == 0)
            ++device_count;
    const char *expected = getenv("GMON_EXPECT_DEVICES");
    if (expected && atoi(expected) != device_count) {
        fprintf(stderr, "expected %s devices (POCL_DEVICES=%s), found %d\n", expected, getenv("POCL_DEVICES"),
                device_count);
        return -1;
    }
    printf("  %d device%s:", device_count, device_count == 1 ? "" : "s");
    for (int i = 0; i < device_count; ++i)
        printf(" '%s'", devices[i].info.name);
    printf("\n");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    for (int i = 0; i < device_count; ++i)
        cl_device_close(&devices[i]);
    render_scene_destroy(&glass);
    return 0;
}

#define REQUIRE_DEVICES(n)                                                                                             \
    do {                                                                                                               \
        if (device_count < (n))                                                                                        \
            skip();                                                                                                    \
    } while (0)

static RenderSettings small_settings(void)
{
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.set_count = 5;
    s.estimator.passes = PASSES_ALL | PASSES_SAMPLE; /* the per-sample state moves with the pixels too */
    s.estimator.with_stderr = 1;
    s.sample_count = 23;
    s.seed = 7;
    s.seconds_per_pass = 0.002; /* many short passes: many chances to rebalance */
    return s;
}

static RenderStatus render_on(int first_device, int count, const RenderSettings *s, RenderOutput *out)
{
    char error[2048];
    RenderStatus status = renderer_run(devices + first_device, count, &glass, s, out, error, sizeof error);
    if (status != RENDER_OK)
        printf("  renderer: %s\n", error);
    return status;
}

static void assert_same_render(const RenderOutput *a, const RenderOutput *b)
{
    const size_t pixels = (size_t)a->width * a->height;
    assert_int_equal(a->sample_count, b->sample_count);
    assert_int_equal(a->set_count, b->set_count);
    assert_memory_equal(a->accumulators, b->accumulators,
                        accumulator_planes((uint32_t)a->set_count) * pixels * sizeof(uint64_t));
    assert_memory_equal(a->rejected, b->rejected, REJECTED_PLANES * pixels * sizeof(uint32_t));
    assert_int_equal(a->rays, b->rays);
    for (int p = 0; p < PASS_COUNT; ++p) {
        assert_true((a->pass[p] == NULL) == (b->pass[p] == NULL));
        assert_true((a->error[p] == NULL) == (b->error[p] == NULL));
        const size_t images = (PASSES_SAMPLE & PASS_BIT(p)) ? (size_t)film_sample_pass_images(&a->estimator, p) : 1;
        if (a->pass[p])
            assert_memory_equal(a->pass[p], b->pass[p], images * pixels * 3 * sizeof(float));
        if (a->error[p])
            assert_memory_equal(a->error[p], b->error[p], pixels * 3 * sizeof(float));
    }
}

static void test_all_devices_equal_one_device(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    RenderOutput one, all;
    assert_int_equal(render_on(0, 1, &s, &one), RENDER_OK);
    assert_int_equal(render_on(0, device_count, &s, &all), RENDER_OK);
    assert_same_render(&one, &all);
    uint64_t total = 0;
    for (int i = 0; i < device_count; ++i) {
        printf("  device %d: %llu pixel samples, %.1f KiB\n", i, (unsigned long long)all.devices[i].samples,
               (double)all.devices[i].peak_bytes / 1024.0);
        assert_true(all.devices[i].samples > 0); /* every device does work */
        assert_false(all.devices[i].failed);
        total += all.devices[i].samples;
    }
    assert_int_equal(total, (uint64_t)s.sample_count * one.width * one.height);
    printf("  %d device(s), %d rebalances: identical to device 0 alone\n", device_count, all.rebalances);
    render_output_free(&one);
    render_output_free(&all);
}

/* A device whose largest allocation holds only part of its pixels renders
 * them in slices of their own buffers: the same render, bit for bit, as in
 * one buffer each; a pixel too large for any slice is refused. */
static void test_slices_equal_one_buffer_per_device(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    RenderOutput whole, sliced;
    assert_int_equal(render_on(0, device_count, &s, &whole), RENDER_OK);
    s.slice_bytes = 64 * 1024; /* the 40x30 pixels' accumulators alone are 290 KiB */
    assert_int_equal(render_on(0, device_count, &s, &sliced), RENDER_OK);
    assert_same_render(&whole, &sliced);
    for (int i = 0; i < device_count; ++i) {
        printf("  device %d: %d slice(s) of at most 64 KiB (%d without the limit)\n", i, sliced.devices[i].slices,
               whole.devices[i].slices);
        assert_int_equal(whole.devices[i].slices, 1);
    }
    assert_true(sliced.devices[0].slices > 1);
    render_output_free(&whole);
    render_output_free(&sliced);
    RenderOutput refused;
    s.slice_bytes = 8; /* under one pixel's set sums */
    assert_int_equal(render_on(0, 1, &s, &refused), RENDER_FAILED);
}

/* Renders on every device with `fault` injected: the render succeeds without
 * device `failed`, and equals the render on device 0 alone. The output stays
 * in *rest (caller frees). */
static void assert_fault_changes_nothing(const char *fault, int failed, RenderOutput *rest)
{
    RenderSettings s = small_settings();
    RenderOutput one;
    assert_int_equal(render_on(0, 1, &s, &one), RENDER_OK);
    s.fault = fault;
    RenderStatus status = render_on(0, device_count, &s, rest);
    s.fault = NULL;
    assert_int_equal(status, RENDER_OK);
    for (int i = 0; i < device_count; ++i)
        assert_int_equal(rest->devices[i].failed, i == failed);
    assert_non_null(strstr(rest->devices[failed].error, "injected"));
    assert_same_render(&one, rest);
    render_output_free(&one);
}

static void test_device_failing_mid_render_changes_nothing(void **state)
{
    (void)state;
    REQUIRE_DEVICES(2);
    RenderOutput rest;
    assert_fault_changes_nothing("1:pass:4", 1, &rest);
    render_output_free(&rest);
}

static void test_device_failing_to_build_is_left_out(void **state)
{
    (void)state;
    REQUIRE_DEVICES(2);
    RenderOutput rest;
    assert_fault_changes_nothing("0:build", 0, &rest);
    assert_int_equal(rest.devices[0].samples, 0);
    render_output_free(&rest);
}

/* Every device fails: the output is the render of the samples saved before
 * (those of a complete render of that many samples), and the status says
 * so. */
static void test_every_device_failing_keeps_saved_samples(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    s.seconds_per_pass = 0.0001; /* one sample a pass: pass 6 fails after 5 samples */
    char faults[256] = "";
    for (int i = 0; i < device_count; ++i)
        snprintf(faults + strlen(faults), sizeof faults - strlen(faults), "%s%d:pass:6", i ? "," : "", i);
    s.fault = faults;
    RenderOutput partial, expected;
    RenderStatus status = render_on(0, device_count, &s, &partial);
    s.fault = NULL;
    assert_int_equal(status, RENDER_INCOMPLETE);
    assert_true(partial.sample_count <= 5);
    printf("  every device failed at pass 6: %llu samples per pixel kept\n", (unsigned long long)partial.sample_count);
    if (partial.sample_count > 0) {
        s.sample_count = partial.sample_count;
        assert_int_equal(render_on(0, 1, &s, &expected), RENDER_OK);
        assert_same_render(&expected, &partial);
        render_output_free(&expected);
    }
    render_output_free(&partial);
}

typedef struct {
    int calls;
    uint64_t spp[16];
    float *mean_at_8;
} CheckpointLog;

static int log_checkpoint(void *user, const RenderOutput *out)
{
    CheckpointLog *log = user;
    if (log->calls < 16)
        log->spp[log->calls] = out->sample_count;
    ++log->calls;
    if (out->sample_count == 8) {
        size_t bytes = (size_t)out->width * out->height * 3 * sizeof(float);
        log->mean_at_8 = malloc(bytes);
        memcpy(log->mean_at_8, out->pass[PASS_MEAN], bytes);
    }
    return 0;
}

static void test_checkpoints_at_powers_of_two_equal_shorter_renders(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    CheckpointLog log = {0};
    s.checkpoint = log_checkpoint;
    s.checkpoint_user = &log;
    RenderOutput out, eight;
    assert_int_equal(render_on(0, device_count, &s, &out), RENDER_OK);
    const uint64_t expected[] = {1, 2, 4, 8, 16, 23};
    assert_int_equal(log.calls, 6);
    for (int i = 0; i < 6; ++i)
        assert_int_equal(log.spp[i], expected[i]);
    s.checkpoint = NULL;
    s.sample_count = 8;
    assert_int_equal(render_on(0, 1, &s, &eight), RENDER_OK);
    assert_non_null(log.mean_at_8);
    assert_memory_equal(log.mean_at_8, eight.pass[PASS_MEAN], (size_t)eight.width * eight.height * 3 * sizeof(float));
    free(log.mean_at_8);
    render_output_free(&out);
    render_output_free(&eight);
}

/* Only the mean asked for: one sum per pixel (M = 1), less memory, and the
 * same mean up to rounding. */
static void test_mean_only_keeps_one_sum_per_pixel(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    s.estimator.set_count = 21;
    s.estimator.passes = PASSES_DEFAULT;
    s.estimator.with_stderr = 0;
    RenderOutput all, mean_only;
    assert_int_equal(render_on(0, 1, &s, &all), RENDER_OK);
    s.estimator.passes = PASS_BIT(PASS_MEAN);
    assert_int_equal(render_on(0, 1, &s, &mean_only), RENDER_OK);
    assert_int_equal(all.set_count, 21);
    assert_int_equal(mean_only.set_count, 1);
    assert_null(mean_only.pass[PASS_GMON]);
    printf("  device memory: %zu bytes with M = 21, %zu with the mean only\n", all.devices[0].peak_bytes,
           mean_only.devices[0].peak_bytes);
    assert_true(mean_only.devices[0].peak_bytes * 8 < all.devices[0].peak_bytes);
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)all.width * all.height * 3; ++i) {
        double a = ((const float *)all.pass[PASS_MEAN])[i], b = ((const float *)mean_only.pass[PASS_MEAN])[i];
        double d = fabs(a - b) / fmax(fabs(a), 1e-6);
        worst = d > worst ? d : worst;
    }
    printf("  mean from 21 sets vs one sum: largest relative difference %.3g\n", worst);
    assert_true(worst < 1e-5);
    s.keep_sets = 1; /* --write-sets keeps M */
    RenderOutput kept;
    assert_int_equal(render_on(0, 1, &s, &kept), RENDER_OK);
    assert_int_equal(kept.set_count, 21);
    render_output_free(&kept);
    render_output_free(&all);
    render_output_free(&mean_only);
}

/* A range starting at sample 7 with M = 5 fills sets 2, 3, 4, 0, 1, ...:
 * the estimators must divide each set by its own count. The mean is then
 * the plain sum over all sets over n. */
static void test_sample_range_not_starting_at_set_zero(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    s.first_sample = 7;
    s.sample_count = 13;
    RenderOutput out;
    assert_int_equal(render_on(0, 1, &s, &out), RENDER_OK);
    const size_t pixels = (size_t)out.width * out.height;
    double worst = 0.0;
    for (size_t p = 0; p < pixels; ++p)
        for (uint32_t c = 0; c < 3; ++c) {
            long double sum = 0.0L;
            for (uint32_t j = 0; j < 5; ++j) {
                sum += test_set_sum(out.accumulators, j, c, p, pixels);
            }
            double mean = (double)(sum / 13.0L);
            double d = fabs(mean - ((const float *)out.pass[PASS_MEAN])[p * 3 + c]) / fmax(fabs(mean), 1e-3);
            worst = d > worst ? d : worst;
        }
    printf("  samples [7, 20), M = 5: mean vs sum / n, largest relative difference %.3g\n", worst);
    assert_true(worst < 1e-5);
    render_output_free(&out);
}

/* The splats of the light tracer and bdpt land on pixels of every
 * device: each device records those of its pixels' light subpaths and the
 * host hands each record to its pixel's device, so every split gives the
 * same sums. */
static void test_lightpath_splats_equal_one_device(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    const uint32_t integrators[] = {RENDER_LIGHTPATH, RENDER_BDPT};
    for (int i = 0; i < 2; ++i) {
        RenderScene light;
        char path[1024], error[1024];
        snprintf(path, sizeof path, "%s/scenes/cornell-diffuse.pbrt", GMON_SOURCE_DIR);
        SceneSummary summary;
        assert_int_equal(scene_convert_load(path, 0, 24, 20, 1, &light, &summary, error, sizeof error), 0);
        light.constants.integrator.flags = RENDER_NEE | integrators[i];
        assert_int_equal(render_scene_finalize(&light, error, sizeof error), 0);
        RenderSettings s = small_settings();
        /* The per-sample estimators that take splats (clamp, zirr) too. */
        s.estimator.passes = PASSES_ALL | PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_ZIRR);
        s.estimator.params.clamp_level_count = 2;
        s.estimator.params.clamp_levels[0] = INFINITY;
        s.estimator.params.clamp_levels[1] = 0.05f;
        RenderOutput one, all;
        assert_int_equal(renderer_run(devices, 1, &light, &s, &one, error, sizeof error), RENDER_OK);
        assert_int_equal(renderer_run(devices, device_count, &light, &s, &all, error, sizeof error), RENDER_OK);
        assert_same_render(&one, &all);
        printf("  %s on %d device(s), %d rebalances: identical to device 0 alone\n", one.integrator, device_count,
               all.rebalances);
        render_output_free(&one);
        render_output_free(&all);
        render_scene_destroy(&light);
    }
}

static void test_feature_mask_follows_scene_and_outputs(void **state)
{
    (void)state;
    uint64_t glass_features = render_scene_features(&glass);
    assert_true(glass_features & FEATURE_DIELECTRIC);
    assert_true(glass_features & FEATURE_TRIANGLES);
    assert_true(glass_features & FEATURE_AREA_LIGHTS);
    assert_true(glass_features & FEATURE_NEE);
    RenderScene diffuse;
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/cornell-diffuse.pbrt", GMON_SOURCE_DIR);
    SceneSummary summary;
    assert_int_equal(scene_convert_load(path, 0, 8, 8, 1, &diffuse, &summary, error, sizeof error), 0);
    diffuse.constants.integrator.flags = 0; /* BSDF sampling only */
    assert_int_equal(render_scene_finalize(&diffuse, error, sizeof error), 0);
    uint64_t features = render_scene_features(&diffuse);
    assert_int_equal(features & (FEATURE_DIELECTRIC | FEATURE_CONDUCTOR | FEATURE_COATED_DIFFUSE | FEATURE_ROUGH |
                                 FEATURE_SPHERES | FEATURE_ENVIRONMENT | FEATURE_NEE),
                     0);
    assert_true(features & FEATURE_DIFFUSE);
    render_scene_destroy(&diffuse);
}

/* The specialized kernels render the same image as the all-features ones
 * (up to the float reassociation the path tracer is allowed). */
static void test_specialized_kernels_match_all_features(void **state)
{
    (void)state;
    REQUIRE_DEVICES(1);
    RenderSettings s = small_settings();
    RenderOutput specialized, all;
    assert_int_equal(render_on(0, 1, &s, &specialized), RENDER_OK);
    s.all_features = 1;
    assert_int_equal(render_on(0, 1, &s, &all), RENDER_OK);
    assert_int_equal(all.features, FEATURES_ALL);
    assert_true(specialized.features != FEATURES_ALL);
    double sum_a = 0.0, sum_b = 0.0;
    size_t values = (size_t)all.width * all.height * 3;
    for (size_t i = 0; i < values; ++i) {
        sum_a += ((const float *)all.pass[PASS_MEAN])[i];
        sum_b += ((const float *)specialized.pass[PASS_MEAN])[i];
    }
    printf("  features 0x%" PRIx64 " vs all: image means %.6f and %.6f\n", specialized.features, sum_b / values,
           sum_a / values);
    assert_true(fabs(sum_a - sum_b) <= 1e-4 * fabs(sum_a));
    render_output_free(&specialized);
    render_output_free(&all);
}

int main(void)
{
    /* CTest runs only the device tests under the multi-device settings. */
    if (getenv("GMON_TEST_FILTER"))
        cmocka_set_test_filter(getenv("GMON_TEST_FILTER"));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_devices_equal_one_device),
        cmocka_unit_test(test_slices_equal_one_buffer_per_device),
        cmocka_unit_test(test_device_failing_mid_render_changes_nothing),
        cmocka_unit_test(test_device_failing_to_build_is_left_out),
        cmocka_unit_test(test_every_device_failing_keeps_saved_samples),
        cmocka_unit_test(test_checkpoints_at_powers_of_two_equal_shorter_renders),
        cmocka_unit_test(test_mean_only_keeps_one_sum_per_pixel),
        cmocka_unit_test(test_sample_range_not_starting_at_set_zero),
        cmocka_unit_test(test_lightpath_splats_equal_one_device),
        cmocka_unit_test(test_feature_mask_follows_scene_and_outputs),
        cmocka_unit_test(test_specialized_kernels_match_all_features),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
