/* gmon merge: EXRs of disjoint sample ranges merge into exactly the render
 * of their union (every set sum and estimate, bit for bit), in any order and
 * with ranges not aligned to M; mismatched scene, resolution, M or seed,
 * overlapping ranges and gaps are refused with a clear error. */
#define _POSIX_C_SOURCE 200809L
#include "cli/merge.h"
#include "cli/options.h"
#include "estimator_core.h"
#include "io/exr_image.h"
#include "render/render_exr.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "test_device.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

static RenderScene scene;
static SceneSummary summary;
static char directory[] = "/tmp/gmon-test-merge-XXXXXX";

static int setup(void **state)
{
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    if (scene_convert_load(path, 0, 20, 16, 1, &scene, &summary, error, sizeof error) ||
        render_scene_finalize(&scene, error, sizeof error) || !mkdtemp(directory)) {
        fprintf(stderr, "%s\n", error);
        return -1;
    }
    return test_device_setup(state);
}

static int teardown(void **state)
{
    render_scene_destroy(&scene);
    char command[256];
    snprintf(command, sizeof command, "rm -rf %s", directory);
    if (system(command) != 0)
        fprintf(stderr, "cannot remove %s\n", directory);
    return test_device_teardown(state);
}

/* Renders samples [first, first + count) with M sets and seed to NAME in the
 * test directory. */
static void render_part(const char *name, uint64_t first, uint64_t count, int sets, uint32_t seed)
{
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.set_count = sets;
    s.outputs = ESTIMATOR_OUTPUT_ALL;
    s.keep_sets = 1;
    s.first_sample = first;
    s.sample_count = count;
    s.seed = seed;
    RenderOutput out;
    char error[1024], path[1024];
    if (renderer_run(&test_device, 1, &scene, &s, &out, error, sizeof error) != RENDER_OK)
        fail_msg("%s", error);
    ExrImage image = render_output_exr(&out);
    image.metadata.scene_path = "cornell-glass.pbrt";
    image.metadata.scene_hash = summary.hash;
    snprintf(path, sizeof path, "%s/%s", directory, name);
    if (exr_image_write(path, &image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("%s", error);
    render_output_free(&out);
}

/* Runs `gmonrt merge --diagnostics --outfile <dir>/merged.exr <parts...>`;
 * returns its exit status. */
static int merge(const char *const *parts, int count)
{
    char out[1024];
    char paths[8][1024];
    char *argv[16] = {"gmonrt", "merge", "--quiet", "--diagnostics", "--outfile", out};
    int argc = 6;
    snprintf(out, sizeof out, "%s/merged.exr", directory);
    for (int i = 0; i < count; ++i) {
        snprintf(paths[i], sizeof paths[i], "%s/%s", directory, parts[i]);
        argv[argc++] = paths[i];
    }
    Options options;
    char error[512];
    assert_int_equal(options_parse(argc, argv, &options, error, sizeof error), 0);
    return merge_command(&options);
}

static void read_image(const char *name, ExrImage *image)
{
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/%s", directory, name);
    if (exr_image_read(path, image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("%s", error);
}

static void test_parts_merge_into_the_whole_bit_for_bit(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* M = 5; ranges of 7, 3 and 14 samples: none starts at a multiple of M. */
    render_part("whole.exr", 0, 24, 5, 3);
    render_part("a.exr", 0, 7, 5, 3);
    render_part("b.exr", 7, 3, 5, 3);
    render_part("c.exr", 10, 14, 5, 3);
    const char *parts[] = {"c.exr", "a.exr", "b.exr"}; /* any order */
    assert_int_equal(merge(parts, 3), 0);
    ExrImage whole, merged;
    read_image("whole.exr", &whole);
    read_image("merged.exr", &merged);
    size_t pixels = (size_t)whole.width * whole.height;
    assert_int_equal(merged.metadata.sample_count, 24);
    assert_int_equal(merged.metadata.first_sample, 0);
    assert_int_equal(merged.metadata.set_count, 5);
    assert_non_null(merged.accumulators);
    assert_memory_equal(merged.accumulators, whole.accumulators, accumulator_planes(5) * pixels * sizeof(uint64_t));
    assert_memory_equal(merged.mean, whole.mean, pixels * 3 * sizeof(float));
    assert_memory_equal(merged.mon, whole.mon, pixels * 3 * sizeof(float));
    assert_memory_equal(merged.gmon, whole.gmon, pixels * 3 * sizeof(float));
    assert_memory_equal(merged.gini, whole.gini, pixels * 3 * sizeof(float));
    assert_memory_equal(merged.trim, whole.trim, pixels * 3 * sizeof(int32_t));
    assert_memory_equal(merged.nonfinite, whole.nonfinite, pixels * sizeof(uint32_t));
    printf("  [0,7) + [7,10) + [10,24), M = 5: merged == whole render, bit for bit\n");
    exr_image_free(&whole);
    exr_image_free(&merged);

    /* A range not starting at 0 merges too: [7, 24) == b + c. */
    render_part("tail.exr", 7, 17, 5, 3);
    const char *tail_parts[] = {"b.exr", "c.exr"};
    assert_int_equal(merge(tail_parts, 2), 0);
    ExrImage tail;
    read_image("tail.exr", &tail);
    read_image("merged.exr", &merged);
    assert_int_equal(merged.metadata.first_sample, 7);
    assert_memory_equal(merged.accumulators, tail.accumulators, accumulator_planes(5) * pixels * sizeof(uint64_t));
    assert_memory_equal(merged.gmon, tail.gmon, pixels * 3 * sizeof(float));
    exr_image_free(&tail);
    exr_image_free(&merged);
}

static void test_mismatches_are_refused(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    render_part("m5.exr", 0, 4, 5, 3);
    render_part("m7.exr", 4, 4, 7, 3);
    render_part("seed9.exr", 4, 4, 5, 9);
    render_part("overlap.exr", 2, 4, 5, 3);
    render_part("gap.exr", 6, 4, 5, 3);
    const char *m[] = {"m5.exr", "m7.exr"}, *seed[] = {"m5.exr", "seed9.exr"}, *overlap[] = {"m5.exr", "overlap.exr"},
               *gap[] = {"m5.exr", "gap.exr"};
    assert_int_equal(merge(m, 2), 1);
    assert_int_equal(merge(seed, 2), 1);
    assert_int_equal(merge(overlap, 2), 1);
    assert_int_equal(merge(gap, 2), 1);

    /* Another scene (hash) and another resolution. */
    ExrImage image;
    read_image("m5.exr", &image);
    ExrImage other = image;
    other.metadata.scene_hash = "0123456789abcdef";
    other.metadata.first_sample = 4;
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/other-scene.exr", directory);
    assert_int_equal(exr_image_write(path, &other, error, sizeof error), IMAGE_IO_OK);
    const char *scene_mismatch[] = {"m5.exr", "other-scene.exr"};
    assert_int_equal(merge(scene_mismatch, 2), 1);
    exr_image_free(&image);

    RenderScene small;
    SceneSummary small_summary;
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    assert_int_equal(scene_convert_load(path, 0, 8, 8, 1, &small, &small_summary, error, sizeof error), 0);
    assert_int_equal(render_scene_finalize(&small, error, sizeof error), 0);
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.set_count = 5;
    s.keep_sets = 1;
    s.first_sample = 4;
    s.sample_count = 4;
    s.seed = 3;
    RenderOutput out;
    assert_int_equal(renderer_run(&test_device, 1, &small, &s, &out, error, sizeof error), RENDER_OK);
    ExrImage resized = render_output_exr(&out);
    resized.metadata.scene_hash = summary.hash;
    snprintf(path, sizeof path, "%s/8x8.exr", directory);
    assert_int_equal(exr_image_write(path, &resized, error, sizeof error), IMAGE_IO_OK);
    const char *size_mismatch[] = {"m5.exr", "8x8.exr"};
    assert_int_equal(merge(size_mismatch, 2), 1);
    render_output_free(&out);
    render_scene_destroy(&small);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parts_merge_into_the_whole_bit_for_bit),
        cmocka_unit_test(test_mismatches_are_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
