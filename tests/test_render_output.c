/* The renderer end to end on the repository's scenes: the furnace scene's
 * analytic value; the EXR holds every layer and its estimators equal the
 * host reference applied to the set sums read back from the same file, bit
 * for bit; the image depends only on the seed and the samples, not on how
 * passes batch them; sample ranges add up exactly. Output files: written
 * through a temporary name (a failed write leaves the old file), the output
 * directory checked up front, `estimate` refusing sums without samples. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "cli/estimate.h"
#include "cli/options.h"
#include "cli/output_files.h"
#include "film/film.h"
#include "estimators.h"
#include "io/exr_image.h"
#include "render/render_exr.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "estimator_images.h"
#include "exact_sum.h"
#include "test_device.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

static void load(const char *name, unsigned size, RenderScene *scene)
{
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", GMON_SOURCE_DIR, name);
    SceneSummary summary;
    if (scene_convert_load(path, 0, size, size, 1, scene, &summary, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
}

static void render(const RenderScene *scene, RenderSettings *settings, RenderOutput *out)
{
    char error[1024];
    if (renderer_run(&test_device, 1, scene, settings, out, error, sizeof error))
        fail_msg("%s", error);
}

static void test_furnace_scene_matches_analytic_value(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    load("furnace.pbrt", 0, &scene);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 64;
    RenderOutput out;
    render(&scene, &settings, &out);
    /* Emission 1, albedo 0.5, maxdepth 5: 1 + 0.5 + ... + 0.5^5. */
    const double expected = 1.96875;
    size_t pixels = (size_t)out.width * out.height;
    double sum = 0.0, sum2 = 0.0;
    for (size_t i = 0; i < pixels * 3; ++i) {
        const float *mean = out.pass[PASS_MEAN];
        sum += mean[i];
        sum2 += (double)mean[i] * mean[i];
    }
    double mean = sum / (double)(pixels * 3);
    double standard_error = sqrt((sum2 / (double)(pixels * 3) - mean * mean) / (double)pixels);
    printf("  furnace.pbrt: mean %.5f, analytic %.5f, standard error %.5f (tolerance: 5 standard errors)\n", mean,
           expected, standard_error);
    assert_true(fabs(mean - expected) <= 5.0 * standard_error);
    render_output_free(&out);
    render_scene_destroy(&scene);
}

static void test_exr_estimates_equal_host_reference_on_its_sums(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    load("cornell-glass.pbrt", 24, &scene);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.estimator.set_count = 5;
    settings.estimator.passes = PASSES_ALL;
    settings.estimator.with_stderr = 1;
    settings.estimator.params.admon_alpha = 0.75f;
    settings.sample_count = 23;
    settings.seed = 3;
    RenderOutput out;
    render(&scene, &settings, &out);

    char path[256], error[1024];
    snprintf(path, sizeof path, "%s/test_render_output.exr", GMON_BINARY_DIR);
    static FilmFile file;
    render_output_file(&file, &out);
    assert_int_equal(exr_image_write(path, &file.image, error, sizeof error), IMAGE_IO_OK);

    ExrImage back;
    if (exr_image_read(path, &back, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("%s", error);
    EstimatorSettings recorded;
    assert_int_equal(film_file_settings(&back, &recorded, error, sizeof error), 0);
    assert_int_equal(recorded.passes, PASSES_ALL);
    assert_int_equal(recorded.with_stderr, 1);
    assert_memory_equal(&recorded.params, &settings.estimator.params, sizeof recorded.params);
    assert_non_null(back.nonfinite);
    assert_non_null(back.accumulators);
    assert_int_equal(back.metadata.set_count, 5);
    assert_int_equal(back.metadata.sample_count, 23);

    /* The file's sums, estimated again on the host with the settings it
     * records, give every layer it holds, bit for bit. */
    size_t pixels = (size_t)back.width * back.height, values = pixels * 3;
    EstimatorImages images = test_images_new(PASSES_ALL, 1, pixels);
    assert_int_equal(estimator_from_accumulators(&recorded, back.accumulators, accumulator_planes(5) * pixels, pixels,
                                                 back.metadata.sample_count, &images, error, sizeof error),
                     ESTIMATOR_OK);
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(PASSES_ALL & PASS_BIT(p)))
            continue;
        const void *layer = film_file_pass(&back, p, 0), *error_layer = film_file_pass(&back, p, 1);
        assert_non_null(layer);
        assert_memory_equal(images.pass[p], layer, values * 4);
        if (PASSES_ESTIMATES & PASS_BIT(p)) {
            assert_non_null(error_layer);
            assert_memory_equal(images.error[p], error_layer, values * 4);
        }
    }
    /* A render with light in it: the image is not black. */
    double total = 0.0;
    for (size_t i = 0; i < values; ++i)
        total += TEST_IMAGE(images, PASS_MEAN)[i];
    assert_true(total > 0.0);
    test_images_free(&images);
    exr_image_free(&back);
    remove(path);
    render_output_free(&out);
    render_scene_destroy(&scene);
}

static void test_image_independent_of_pass_batching_and_ranges(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    load("cornell-glass.pbrt", 16, &scene);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 24;
    settings.seed = 11;
    RenderOutput one_per_pass, big_passes, first_half, second_half;
    settings.seconds_per_pass = 1e-9; /* every pass one sample per pixel */
    render(&scene, &settings, &one_per_pass);
    settings.seconds_per_pass = 1e9; /* one sample, then everything left */
    render(&scene, &settings, &big_passes);
    size_t words =
        accumulator_planes((uint32_t)settings.estimator.set_count) * one_per_pass.width * one_per_pass.height;
    assert_memory_equal(one_per_pass.accumulators, big_passes.accumulators, words * 8);
    assert_memory_equal(one_per_pass.pass[PASS_GMON], big_passes.pass[PASS_GMON],
                        (size_t)one_per_pass.width * one_per_pass.height * 12);

    /* Samples [0, 10) and [10, 24) rendered apart add up to [0, 24). */
    settings.sample_count = 10;
    render(&scene, &settings, &first_half);
    settings.first_sample = 10;
    settings.sample_count = 14;
    render(&scene, &settings, &second_half);
    const size_t pixels = (size_t)one_per_pass.width * one_per_pass.height;
    for (size_t p = 0; p < pixels; ++p)
        assert_int_equal(accumulators_merge_pixel(first_half.accumulators, second_half.accumulators, p, pixels,
                                                  (uint32_t)settings.estimator.set_count),
                         0);
    assert_memory_equal(first_half.accumulators, one_per_pass.accumulators, words * 8);
    render_output_free(&one_per_pass);
    render_output_free(&big_passes);
    render_output_free(&first_half);
    render_output_free(&second_half);
    render_scene_destroy(&scene);
}

/* The image mean of one channel and its Monte Carlo standard error. Each
 * pixel's variance is estimated from the spread of its M set means (the
 * sets are independent), so image structure does not count as noise. */
static void image_mean(const RenderOutput *out, int channel, double *mean, double *standard_error)
{
    size_t pixels = (size_t)out->width * out->height;
    int m = out->set_count;
    double sum = 0.0, variance = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
        double set_means[EST_MAX_SETS], average = 0.0, spread = 0.0;
        for (int j = 0; j < m; ++j) {
            uint64_t n_j = (out->sample_count - (uint64_t)j + (uint64_t)m - 1) / (uint64_t)m;
            set_means[j] =
                (double)test_set_sum(out->accumulators, (uint32_t)j, (uint32_t)channel, p, pixels) / (double)n_j;
            average += set_means[j] / m;
        }
        for (int j = 0; j < m; ++j)
            spread += (set_means[j] - average) * (set_means[j] - average);
        sum += ((const float *)out->pass[PASS_MEAN])[3 * p + (size_t)channel];
        variance += spread / (m - 1) / m; /* variance of the pixel's mean */
    }
    *mean = sum / (double)pixels;
    *standard_error = sqrt(variance) / (double)pixels;
}

/* Next-event estimation with MIS and BSDF sampling alone estimate the same
 * image: their means agree within the combined standard error. The disk,
 * cylinder and curved two-sided bilinear patch lights (tessellated on the
 * host) check that light sampling picks and samples their triangles by
 * area; the ceiling light, that shadow rays at grazing angles reach it. */
static void test_nee_and_bsdf_sampling_agree(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const char *scenes[] = {"cornell-diffuse.pbrt",
                            "cornell-glass.pbrt",
                            "../tests/data/scenes/disk-light.pbrt",
                            "../tests/data/scenes/cylinder-light.pbrt",
                            "../tests/data/scenes/bilinear-light.pbrt",
                            "../tests/data/scenes/ceiling-light.pbrt"};
    for (int s = 0; s < (int)(sizeof scenes / sizeof scenes[0]); ++s) {
        RenderOutput outputs[2];
        for (int nee = 0; nee <= 1; ++nee) {
            RenderScene scene;
            load(scenes[s], 32, &scene);
            scene.constants.integrator.flags = nee ? RENDER_NEE : 0u;
            RenderSettings settings;
            render_settings_default(&settings);
            settings.sample_count = 126; /* a multiple of M: equal set counts */
            settings.seed = 5;
            render(&scene, &settings, &outputs[nee]);
            render_scene_destroy(&scene);
        }
        for (int c = 0; c < 3; ++c) {
            double m0, e0, m1, e1;
            image_mean(&outputs[0], c, &m0, &e0);
            image_mean(&outputs[1], c, &m1, &e1);
            double error = sqrt(e0 * e0 + e1 * e1);
            printf("  %s channel %d: BSDF only %.5f, NEE %.5f, difference %.2f standard errors\n", scenes[s], c, m0, m1,
                   fabs(m0 - m1) / error);
            assert_true(fabs(m0 - m1) <= 5.0 * error);
            assert_true(m1 > 0.01); /* lit */
        }
        render_output_free(&outputs[0]);
        render_output_free(&outputs[1]);
    }
}

/* cornell-glass.pbrt with its light scaled by 2^k, written beside the
 * build and loaded. */
static void load_scaled_cornell_glass(int k, unsigned size, RenderScene *scene)
{
    char source[1024], path[1024], error[1024];
    snprintf(source, sizeof source, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    snprintf(path, sizeof path, "%s/test_render_output_scaled.pbrt", GMON_BINARY_DIR);
    FILE *in = fopen(source, "r"), *out = fopen(path, "w");
    assert_true(in && out);
    char line[1024];
    int scaled = 0;
    while (fgets(line, sizeof line, in)) {
        char *include = strstr(line, "\"include/"); /* Include and Import */
        char *scale = strstr(line, "\"float scale\" [ 25 ]");
        if (include)
            fprintf(out, "%.*s\"%s/scenes/%s", (int)(include - line), line, GMON_SOURCE_DIR, include + 1);
        else if (scale) /* %.17g round-trips the double 25 * 2^k, a float */
            fprintf(out, "%.*s\"float scale\" [ %.17g ]%s", (int)(scale - line), line, ldexp(25.0, k),
                    scale + strlen("\"float scale\" [ 25 ]"));
        else
            fputs(line, out);
        scaled += scale != NULL;
    }
    fclose(in);
    assert_int_equal(fclose(out), 0);
    assert_int_equal(scaled, 1);
    SceneSummary summary;
    if (scene_convert_load(path, 0, size, size, 1, scene, &summary, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    remove(path);
}

/* Scaling every emitter by 2^k scales every sample by 2^k, so the exact
 * sums keep their integers and move their grid by k, and every estimate
 * scales by exactly 2^k: bright scenes (a light 2^30 times cornell-glass's,
 * whose fireflies reached 2^38 and were dropped before) and dim ones alike. */
static void test_emitter_scale_by_power_of_two_scales_every_estimate(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 40;
    settings.estimator.set_count = 5;
    settings.estimator.passes = PASSES_ALL;
    settings.estimator.with_stderr = 1;
    RenderScene scene;
    RenderOutput base;
    load_scaled_cornell_glass(0, 24, &scene);
    render(&scene, &settings, &base);
    render_scene_destroy(&scene);
    const size_t pixels = (size_t)base.width * base.height, values = pixels * 3;
    assert_int_equal(base.rejected_total + base.rounded_total, 0);
    float brightest = 0.0f;
    for (size_t i = 0; i < values; ++i)
        brightest = TEST_IMAGE(base, PASS_MEAN)[i] > brightest ? TEST_IMAGE(base, PASS_MEAN)[i] : brightest;
    const int ks[] = {-100, -61, 1, 30, 64, 100};
    for (size_t i = 0; i < sizeof ks / sizeof ks[0]; ++i) {
        const int k = ks[i];
        RenderOutput out;
        load_scaled_cornell_glass(k, 24, &scene);
        render(&scene, &settings, &out);
        render_scene_destroy(&scene);
        /* Every estimate and standard error but gmon-authors', whose 1e-11
         * on every mean is not scaled (the authors' choice). */
        int mismatches = 0, compared = 0;
        for (int e = 0; e < PASS_COUNT; ++e) {
            if (!(PASSES_ESTIMATES & PASS_BIT(e)) || e == PASS_GMON_AUTHORS)
                continue;
            for (int with_error = 0; with_error <= 1; ++with_error) {
                const float *a = with_error ? base.error[e] : base.pass[e];
                const float *b = with_error ? out.error[e] : out.pass[e];
                for (size_t v = 0; v < values; ++v) {
                    float want = ldexpf(a[v], k);
                    mismatches += memcmp(&want, &b[v], sizeof want) != 0;
                }
                compared += (int)values;
            }
        }
        assert_memory_equal(base.pass[PASS_GINI], out.pass[PASS_GINI], values * sizeof(float));
        assert_memory_equal(base.pass[PASS_TRIM], out.pass[PASS_TRIM], values * sizeof(int32_t));
        /* The sums' integers are the same; only the grids move, by k. */
        for (size_t p = 0; p < pixels; ++p)
            if (base.accumulators[grid_index(p)] != 0)
                assert_int_equal(out.accumulators[grid_index(p)], base.accumulators[grid_index(p)] + (uint64_t)k);
        assert_memory_equal(base.accumulators + pixels, out.accumulators + pixels,
                            (accumulator_planes(5) - 1) * pixels * sizeof(uint64_t));
        printf("  light x 2^%d: brightest mean %g, %d of %d estimates and errors differ from 2^%d x the unscaled "
               "ones, %llu non-finite, %llu rounded\n",
               k, (double)ldexpf(brightest, k), mismatches, compared, k, (unsigned long long)out.rejected_total,
               (unsigned long long)out.rounded_total);
        assert_int_equal(mismatches, 0);
        assert_int_equal(out.rejected_total + out.rounded_total, 0);
        render_output_free(&out);
    }
    render_output_free(&base);
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

static int file_has_text(const char *path, const char *text)
{
    char buffer[256] = "";
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(buffer, 1, sizeof buffer - 1, f);
    fclose(f);
    buffer[n] = '\0';
    return strcmp(buffer, text) == 0;
}

/* A writer that writes half a file, then fails (a full disk, say). */
static int write_half_then_fail(const char *path, const void *data, char *error, size_t error_size)
{
    (void)data;
    write_text(path, "trunc");
    snprintf(error, error_size, "%s: no space left on device", path);
    return -1;
}

static int write_new(const char *path, const void *data, char *error, size_t error_size)
{
    (void)error;
    (void)error_size;
    write_text(path, data);
    return 0;
}

static int partial_files_in(const char *directory)
{
    char command[1200];
    snprintf(command, sizeof command, "ls %s | grep -q partial", directory);
    return system(command) == 0;
}

static void test_failed_write_leaves_the_old_file(void **state)
{
    (void)state;
    char directory[] = "/tmp/gmon-test-output-XXXXXX", path[1024], error[1024] = "";
    assert_non_null(mkdtemp(directory));
    snprintf(path, sizeof path, "%s/image.exr", directory);
    write_text(path, "a good image");
    assert_int_equal(write_replacing(path, write_half_then_fail, NULL, error, sizeof error), -1);
    assert_non_null(strstr(error, "no space left"));
    assert_true(file_has_text(path, "a good image"));
    assert_false(partial_files_in(directory));
    assert_int_equal(write_replacing(path, write_new, "the new image", error, sizeof error), 0);
    assert_true(file_has_text(path, "the new image"));
    assert_false(partial_files_in(directory));
    remove(path);
    rmdir(directory);
}

static void test_output_path_checked_before_render(void **state)
{
    (void)state;
    char directory[] = "/tmp/gmon-test-output-XXXXXX", path[1024];
    assert_non_null(mkdtemp(directory));
    snprintf(path, sizeof path, "%s/out.exr", directory);
    assert_int_equal(check_output_path(path), 0);
    assert_int_equal(check_output_path("relative.exr"), 0);
    snprintf(path, sizeof path, "%s/missing/out.exr", directory);
    assert_int_equal(check_output_path(path), 1);
    snprintf(path, sizeof path, "%s/file", directory);
    write_text(path, "not a directory");
    snprintf(path, sizeof path, "%s/file/out.exr", directory);
    assert_int_equal(check_output_path(path), 1);
    snprintf(path, sizeof path, "%s/file", directory);
    remove(path);
    assert_int_equal(mkdir(path, 0777), 0);
    assert_int_equal(check_output_path(path), 1); /* a directory where the file would go */
    rmdir(path);
    rmdir(directory);
}

/* Set sums with no sample count estimate nothing: refused, nothing written. */
static void test_estimate_refuses_sums_without_samples(void **state)
{
    (void)state;
    char directory[] = "/tmp/gmon-test-output-XXXXXX", in[1024], out[1024], error[1024];
    assert_non_null(mkdtemp(directory));
    snprintf(in, sizeof in, "%s/no-samples.exr", directory);
    snprintf(out, sizeof out, "%s/estimate.exr", directory);
    uint64_t sums[(1 + 3 * 2) * 4] = {0}; /* M = 1 (the grid plane, then the sums), 2x2 pixels */
    float mean[3 * 4] = {0};
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = 2;
    image.height = 2;
    image.layers[image.layer_count++] = (ExrRgbLayer){"mean", 0, mean};
    image.accumulators = sums;
    image.metadata.set_count = 1;
    assert_int_equal(exr_image_write(in, &image, error, sizeof error), IMAGE_IO_OK);
    char *argv[] = {"gmonrt", "estimate", "--quiet", "--outfile", out, in};
    Options options;
    assert_int_equal(options_parse(6, argv, &options, error, sizeof error), 0);
    assert_int_equal(estimate_command(&options), 1);
    assert_int_equal(access(out, F_OK), -1);
    remove(in);
    rmdir(directory);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_furnace_scene_matches_analytic_value),
        cmocka_unit_test(test_exr_estimates_equal_host_reference_on_its_sums),
        cmocka_unit_test(test_image_independent_of_pass_batching_and_ranges),
        cmocka_unit_test(test_emitter_scale_by_power_of_two_scales_every_estimate),
        cmocka_unit_test(test_nee_and_bsdf_sampling_agree),
        cmocka_unit_test(test_failed_write_leaves_the_old_file),
        cmocka_unit_test(test_output_path_checked_before_render),
        cmocka_unit_test(test_estimate_refuses_sums_without_samples),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
