/* The integrators with light subpaths (kernels/tracing/bdpt.cl): the light
 * tracer ("lightpath") against the path tracer, which estimates the same
 * image by independent means (camera paths), and the splats' exactness:
 * the same sums bit for bit whatever the passes and slices. */
#include "cl/cl_device.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "test_device.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Renders scenes/<name> at width x height with the integrator `flags`. */
static void render_scene_file(const char *name, unsigned width, unsigned height, uint32_t flags,
                              const RenderSettings *settings, RenderOutput *out)
{
    char path[1024], error[2048];
    snprintf(path, sizeof path, "%s/scenes/%s", GMON_SOURCE_DIR, name);
    RenderScene scene;
    SceneSummary summary;
    assert_int_equal(scene_convert_load(path, 0, width, height, 1, &scene, &summary, error, sizeof error), 0);
    scene.constants.integrator.flags = flags;
    assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
    RenderStatus status = renderer_run(&test_device, 1, &scene, settings, out, error, sizeof error);
    if (status != RENDER_OK)
        fail_msg("%s: %s", name, error);
    render_scene_destroy(&scene);
}

/* Compares two renders' mean images over a grid of tiles x tiles regions
 * (each region's mean of the three channels): every region within
 * `tolerance` (relative) of the reference. */
static void assert_tiles_agree(const RenderOutput *test, const RenderOutput *reference, int tiles, double tolerance,
                               const char *what)
{
    const float *a = test->pass[PASS_MEAN], *b = reference->pass[PASS_MEAN];
    unsigned width = test->width, height = test->height;
    double worst = 0.0, total_a = 0.0, total_b = 0.0;
    for (int ty = 0; ty < tiles; ++ty)
        for (int tx = 0; tx < tiles; ++tx) {
            double sum_a = 0.0, sum_b = 0.0;
            for (unsigned y = ty * height / tiles; y < (ty + 1) * height / tiles; ++y)
                for (unsigned x = tx * width / tiles; x < (tx + 1) * width / tiles; ++x)
                    for (int c = 0; c < 3; ++c) {
                        sum_a += a[3 * ((size_t)y * width + x) + c];
                        sum_b += b[3 * ((size_t)y * width + x) + c];
                    }
            double error = fabs(sum_a - sum_b) / sum_b;
            worst = error > worst ? error : worst;
            total_a += sum_a;
            total_b += sum_b;
            if (error > tolerance)
                printf("  %s: tile (%d, %d): %.5f vs %.5f, %.2f%% off\n", what, tx, ty, sum_a, sum_b, 100.0 * error);
        }
    printf("  %s: image means %.5f vs %.5f (%.2f%%), worst of %dx%d tiles %.2f%% off\n", what,
           total_a / (3.0 * width * height), total_b / (3.0 * width * height), 100.0 * (total_a - total_b) / total_b,
           tiles, tiles, 100.0 * worst);
    assert_true(worst <= tolerance);
}

/* The light tracer and the path tracer estimate the same image: every
 * 4x4 region of the diffuse Cornell box within 2%. Covers the light's own
 * point seen by the camera, the connections of every bounce and the
 * gaussian filter's splats over neighbouring pixels. */
static void test_lightpath_matches_path_tracer(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.passes = PASS_BIT(PASS_MEAN);
    s.sample_count = 512;
    s.seed = 3;
    RenderOutput path, light;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE, &s, &path);
    s.seed = 4;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE | RENDER_LIGHTPATH, &s, &light);
    assert_string_equal(light.integrator, "lightpath");
    assert_int_equal(light.rejected_total, 0);
    assert_tiles_agree(&light, &path, 4, 0.02, "lightpath vs path");
    render_output_free(&path);
    render_output_free(&light);
}

/* Bidirectional path tracing (every strategy s, t by its MIS weight) and
 * the path tracer estimate the same image: every 4x4 region of the
 * diffuse Cornell box within 2%. */
static void test_bdpt_matches_path_tracer(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.passes = PASS_BIT(PASS_MEAN);
    s.sample_count = 256;
    s.seed = 5;
    RenderOutput path, bdpt;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE, &s, &path);
    s.seed = 6;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE | RENDER_BDPT, &s, &bdpt);
    assert_string_equal(bdpt.integrator, "bdpt");
    assert_int_equal(bdpt.rejected_total, 0);
    assert_tiles_agree(&bdpt, &path, 4, 0.02, "bdpt vs path");
    render_output_free(&path);
    render_output_free(&bdpt);
}

static void assert_same_sums(const RenderOutput *a, const RenderOutput *b)
{
    const size_t pixels = (size_t)a->width * a->height;
    assert_int_equal(a->set_count, b->set_count);
    assert_memory_equal(a->accumulators, b->accumulators,
                        accumulator_planes((uint32_t)a->set_count) * pixels * sizeof(uint64_t));
    assert_memory_equal(a->rejected, b->rejected, REJECTED_PLANES * pixels * sizeof(uint32_t));
    assert_memory_equal(a->pass[PASS_GMON], b->pass[PASS_GMON], pixels * 3 * sizeof(float));
}

/* Splats land in their sample's set of the pixel they reach, whatever
 * launched them: one pass of all samples, many short passes, and the
 * pixels cut into slices give the same set sums bit for bit, with the
 * light tracer and with bdpt. */
static void test_splat_sums_do_not_depend_on_passes_or_slices(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t integrators[] = {RENDER_LIGHTPATH, RENDER_BDPT};
    for (int i = 0; i < 2; ++i) {
        uint32_t flags = RENDER_NEE | integrators[i];
        RenderSettings s;
        render_settings_default(&s);
        s.estimator.set_count = 5;
        s.estimator.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_GMON);
        s.sample_count = 12;
        s.seed = 9;
        s.seconds_per_pass = 100.0; /* after the first pass of 1 sample, the other 11 in one */
        RenderOutput few, many, sliced;
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &few);
        s.seconds_per_pass = 1e-6; /* one sample a pass */
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &many);
        s.slice_bytes = 16 * 1024; /* 24x20 pixels' sums at M = 5 are 119 KiB */
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &sliced);
        assert_true(sliced.devices[0].slices > 1);
        assert_same_sums(&few, &many);
        assert_same_sums(&few, &sliced);
        printf("  %s: 1 + 11 samples, 12 passes of 1, %d slices: the same sums\n", few.integrator,
               sliced.devices[0].slices);
        render_output_free(&few);
        render_output_free(&many);
        render_output_free(&sliced);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lightpath_matches_path_tracer),
        cmocka_unit_test(test_bdpt_matches_path_tracer),
        cmocka_unit_test(test_splat_sums_do_not_depend_on_passes_or_slices),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
