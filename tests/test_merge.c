/* gmon merge: EXRs of disjoint sample ranges merge into exactly the render
 * of their union (every set sum and estimate, bit for bit), in any order and
 * with ranges not aligned to M; mismatched scene, resolution, M or seed,
 * overlapping ranges and gaps are refused with a clear error. */
#define _POSIX_C_SOURCE 200809L
#include "cli/merge.h"
#include "cli/options.h"
#include "accumulate.h"
#include "film/film_file.h"
#include "film/film_merge.h"
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

/* The passes parts are rendered with. */
static uint32_t part_passes = PASSES_ALL;

/* Renders samples [first, first + count) with M sets and seed to NAME in the
 * test directory. */
static void render_part_of(const RenderScene *scene, const char *name, uint64_t first, uint64_t count, int sets,
                           uint32_t seed)
{
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.set_count = sets;
    s.estimator.passes = part_passes;
    s.keep_sets = 1;
    s.first_sample = first;
    s.sample_count = count;
    s.seed = seed;
    RenderOutput out;
    char error[1024], path[1024];
    if (renderer_run(&test_device, 1, scene, &s, &out, error, sizeof error) != RENDER_OK)
        fail_msg("%s", error);
    static FilmFile file;
    render_output_file(&file, &out);
    file.image.metadata.scene_path = "cornell-glass.pbrt";
    snprintf(path, sizeof path, "%s/%s", directory, name);
    if (exr_image_write(path, &file.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("%s", error);
    render_output_free(&out);
}

static void render_part(const char *name, uint64_t first, uint64_t count, int sets, uint32_t seed)
{
    render_part_of(&scene, name, first, count, sets, seed);
}

/* Writes a copy of part `name` as `copy` with other metadata. */
static void forge_part(const char *name, const char *copy, uint64_t first, uint64_t count, const char *hash)
{
    char path[1024], error[1024];
    ExrImage image;
    snprintf(path, sizeof path, "%s/%s", directory, name);
    assert_int_equal(exr_image_read(path, &image, error, sizeof error), IMAGE_IO_OK);
    ExrImage forged = image;
    forged.metadata.first_sample = first;
    forged.metadata.sample_count = count;
    if (hash)
        forged.metadata.scene_hash = hash;
    snprintf(path, sizeof path, "%s/%s", directory, copy);
    assert_int_equal(exr_image_write(path, &forged, error, sizeof error), IMAGE_IO_OK);
    exr_image_free(&image);
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

/* merge(), with what it printed on stderr in `message`; fails the test
 * unless it exits 1 and the message contains `expected`. */
static void merge_refused(const char *const *parts, int count, const char *expected)
{
    char path[1024], message[2048] = "";
    snprintf(path, sizeof path, "%s/stderr.txt", directory);
    fflush(stderr);
    int saved = dup(2);
    FILE *capture = fopen(path, "w");
    assert_true(saved >= 0 && capture);
    dup2(fileno(capture), 2);
    int status = merge(parts, count);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    fclose(capture);
    capture = fopen(path, "r");
    size_t length = fread(message, 1, sizeof message - 1, capture);
    message[length] = '\0';
    fclose(capture);
    if (status != 1 || !strstr(message, expected))
        fail_msg("merge exited %d with \"%s\"; expected exit 1 and \"%s\"", status, message, expected);
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
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(PASSES_ALL & PASS_BIT(p)))
            continue;
        assert_non_null(film_file_pass(&merged, p, 0));
        assert_memory_equal(film_file_pass(&merged, p, 0), film_file_pass(&whole, p, 0), pixels * 3 * sizeof(float));
    }
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
    assert_memory_equal(film_file_pass(&merged, PASS_GMON, 0), film_file_pass(&tail, PASS_GMON, 0),
                        pixels * 3 * sizeof(float));
    exr_image_free(&tail);
    exr_image_free(&merged);
}

/* bdpt's splats land in their sample's set wherever they are rendered:
 * parts of a bdpt render merge into the whole render bit for bit too. */
static void test_bdpt_parts_merge_into_the_whole_bit_for_bit(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene bdpt;
    char path[1024], error[1024];
    SceneSummary bdpt_summary;
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    assert_int_equal(scene_convert_load(path, 0, 20, 16, 1, &bdpt, &bdpt_summary, error, sizeof error), 0);
    bdpt.constants.integrator.flags = RENDER_NEE | RENDER_BDPT;
    assert_int_equal(render_scene_finalize(&bdpt, error, sizeof error), 0);
    render_part_of(&bdpt, "bdpt-whole.exr", 0, 12, 5, 3);
    render_part_of(&bdpt, "bdpt-a.exr", 0, 7, 5, 3);
    render_part_of(&bdpt, "bdpt-b.exr", 7, 5, 5, 3);
    const char *parts[] = {"bdpt-b.exr", "bdpt-a.exr"};
    assert_int_equal(merge(parts, 2), 0);
    ExrImage whole, merged;
    read_image("bdpt-whole.exr", &whole);
    read_image("merged.exr", &merged);
    size_t pixels = (size_t)whole.width * whole.height;
    assert_int_equal(merged.metadata.sample_count, 12);
    assert_string_equal(merged.metadata.integrator, "bdpt");
    assert_memory_equal(merged.accumulators, whole.accumulators, accumulator_planes(5) * pixels * sizeof(uint64_t));
    assert_memory_equal(film_file_pass(&merged, PASS_GMON, 0), film_file_pass(&whole, PASS_GMON, 0),
                        pixels * 3 * sizeof(float));
    printf("  bdpt: [0,7) + [7,12), M = 5: merged == whole render, bit for bit\n");
    exr_image_free(&whole);
    exr_image_free(&merged);
    render_scene_destroy(&bdpt);
}

/* Parts that hold other estimators than the default ones (no gmon, the
 * default preview): the merge computes theirs and previews the first. */
static void test_parts_keep_their_estimators(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    part_passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_GMEDIAN);
    render_part("g-whole.exr", 0, 9, 5, 3);
    render_part("g-a.exr", 0, 4, 5, 3);
    render_part("g-b.exr", 4, 5, 5, 3);
    part_passes = PASSES_ALL;
    const char *parts[] = {"g-a.exr", "g-b.exr"};
    assert_int_equal(merge(parts, 2), 0);
    ExrImage whole, merged;
    read_image("g-whole.exr", &whole);
    read_image("merged.exr", &merged);
    size_t pixels = (size_t)whole.width * whole.height;
    assert_null(film_file_pass(&merged, PASS_GMON, 0));
    assert_non_null(film_file_pass(&merged, PASS_GMEDIAN, 0));
    assert_memory_equal(film_file_pass(&merged, PASS_GMEDIAN, 0), film_file_pass(&whole, PASS_GMEDIAN, 0),
                        pixels * 3 * sizeof(float));
    exr_image_free(&whole);
    exr_image_free(&merged);
}

static void test_mismatches_are_refused(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    render_part("m5.exr", 0, 4, 5, 3);
    render_part("m7.exr", 4, 4, 5 + 2, 3);
    render_part("seed9.exr", 4, 4, 5, 9);
    render_part("overlap.exr", 2, 4, 5, 3);
    render_part("gap.exr", 6, 4, 5, 3);
    const char *m[] = {"m5.exr", "m7.exr"}, *seed[] = {"m5.exr", "seed9.exr"}, *overlap[] = {"m5.exr", "overlap.exr"},
               *gap[] = {"m5.exr", "gap.exr"};
    merge_refused(m, 2, "has M = 5 sets but");
    merge_refused(seed, 2, "has seed 3 but");
    merge_refused(overlap, 2, "the ranges overlap");
    merge_refused(gap, 2, "samples between them are missing");

    /* Options applied after the scene is read are named. */
    RenderScene shallow = scene;
    shallow.constants.integrator.max_depth = 1;
    render_part_of(&shallow, "depth1.exr", 4, 4, 5, 3);
    shallow.constants.integrator.max_depth = scene.constants.integrator.max_depth;
    shallow.constants.integrator.flags = 0; /* --integrator bsdf */
    render_part_of(&shallow, "bsdf.exr", 4, 4, 5, 3);
    shallow.constants.integrator.flags = scene.constants.integrator.flags;
    shallow.constants.integrator.sampler = SAMPLER_INDEPENDENT;
    render_part_of(&shallow, "independent.exr", 4, 4, 5, 3);
    const char *depth[] = {"m5.exr", "depth1.exr"}, *bsdf[] = {"m5.exr", "bsdf.exr"},
               *independent[] = {"m5.exr", "independent.exr"};
    char expected[64];
    snprintf(expected, sizeof expected, "differ in maxdepth (%u vs 1)", scene.constants.integrator.max_depth);
    merge_refused(depth, 2, expected);
    merge_refused(bsdf, 2, "differ in integrator (path vs bsdf)");
    merge_refused(independent, 2, "differ in sampler (sobol-sets vs independent)");

    /* Another scene (hash), ranges and counts that wrap 64 bits. */
    forge_part("m5.exr", "other-scene.exr", 4, 4, "0123456789abcdef");
    forge_part("m5.exr", "wraps.exr", UINT64_MAX - 1, 4, NULL);
    forge_part("m5.exr", "half.exr", 0, (uint64_t)1 << 63, NULL);
    forge_part("m5.exr", "other-half.exr", (uint64_t)1 << 63, ((uint64_t)1 << 63) - 1, NULL);
    forge_part("m5.exr", "one-more.exr", UINT64_MAX, 0, NULL);
    const char *scene_mismatch[] = {"m5.exr", "other-scene.exr"}, *wraps[] = {"wraps.exr"},
               *too_many[] = {"half.exr", "other-half.exr", "one-more.exr", "m5.exr"};
    merge_refused(scene_mismatch, 2, "render different scenes");
    merge_refused(wraps, 1, "passes 2^64");
    merge_refused(too_many, 4, "add up to 2^64 or more");

    RenderScene small;
    SceneSummary small_summary;
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    assert_int_equal(scene_convert_load(path, 0, 8, 8, 1, &small, &small_summary, error, sizeof error), 0);
    assert_int_equal(render_scene_finalize(&small, error, sizeof error), 0);
    render_part_of(&small, "8x8.exr", 4, 4, 5, 3);
    const char *size_mismatch[] = {"m5.exr", "8x8.exr"};
    merge_refused(size_mismatch, 2, "is 20x16 but");
    render_scene_destroy(&small);
}

/* film_merge on its own: a pixel's stream split into two sample ranges at
 * any point, each accumulated apart, merges into the sums of the whole
 * stream, bit for bit; values too far apart for one sum are rounded and
 * counted; M out of range is refused. */
static void test_film_merge_adds_ranges_exactly(void **state)
{
    (void)state;
    enum { PIXELS = 3, SETS = 4, SAMPLES = 37 };
    const size_t words = accumulator_planes(SETS) * PIXELS;
    uint64_t whole[accumulator_planes(SETS) * PIXELS], first[accumulator_planes(SETS) * PIXELS],
        second[accumulator_planes(SETS) * PIXELS];
    /* pixel 0: ordinary values; 1: 1e-12 beside 1e10; 2: no samples */
    float values[PIXELS][SAMPLES];
    for (int i = 0; i < SAMPLES; ++i) {
        values[0][i] = 0.25f * (float)(i % 5) + 0.001f * (float)i;
        values[1][i] = i % 3 ? 1e-12f * (float)(i + 1) : 1e10f;
        values[2][i] = 0.0f;
    }
    for (int split = 0; split <= SAMPLES; split += 6) {
        memset(whole, 0, sizeof whole);
        memset(first, 0, sizeof first);
        memset(second, 0, sizeof second);
        for (size_t p = 0; p < PIXELS; ++p) {
            for (int i = 0; i < SAMPLES; ++i) {
                float v = values[p][i];
                uint32_t set = set_of_sample((uint64_t)i, SETS);
                accumulate_sample(whole, p, PIXELS, SETS, set, v, 2.0f * v, -v);
                accumulate_sample(i < split ? first : second, p, PIXELS, SETS, set, v, 2.0f * v, -v);
            }
            accumulators_normalize(whole, p, PIXELS, SETS);
        }
        uint32_t rounded[PIXELS] = {0};
        assert_int_equal(film_merge(first, second, PIXELS, SETS, rounded), 0);
        assert_memory_equal(first, whole, words * sizeof(uint64_t));
        assert_int_equal(rounded[0] + rounded[1] + rounded[2], 0);
    }
    /* 2^-140 beside 2^100: beyond what a sum spans, rounded and counted. */
    memset(first, 0, sizeof first);
    memset(second, 0, sizeof second);
    accumulate_sample(first, 1, PIXELS, SETS, 0, 0x1p100f, 0.0f, 0.0f);
    accumulate_sample(second, 1, PIXELS, SETS, 0, 0x1p-140f, 0.0f, 0.0f);
    uint32_t rounded[PIXELS] = {0};
    assert_int_equal(film_merge(first, second, PIXELS, SETS, rounded), 1);
    assert_int_equal(rounded[1], 1);
    assert_int_equal(film_merge(first, second, PIXELS, 0, NULL), -1);
    assert_int_equal(film_merge(first, second, PIXELS, 65, NULL), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_film_merge_adds_ranges_exactly),
        cmocka_unit_test(test_parts_merge_into_the_whole_bit_for_bit),
        cmocka_unit_test(test_bdpt_parts_merge_into_the_whole_bit_for_bit),
        cmocka_unit_test(test_parts_keep_their_estimators),
        cmocka_unit_test(test_mismatches_are_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
