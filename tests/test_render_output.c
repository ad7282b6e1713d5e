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
#include "estimator/estimator.h"
#include "estimator_core.h"
#include "io/exr_image.h"
#include "render/render_exr.h"
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
        sum += out.mean[i];
        sum2 += (double)out.mean[i] * out.mean[i];
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
    settings.outputs = ESTIMATOR_OUTPUT_ALL;
    settings.sample_count = 23;
    settings.seed = 3;
    RenderOutput out;
    render(&scene, &settings, &out);

    char path[256], error[1024];
    snprintf(path, sizeof path, "%s/test_render_output.exr", GMON_BINARY_DIR);
    ExrImage image = render_output_exr(&out);
    assert_int_equal(exr_image_write(path, &image, error, sizeof error), IMAGE_IO_OK);

    ExrImage back;
    if (exr_image_read(path, &back, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("%s", error);
    assert_non_null(back.mean);
    assert_non_null(back.mon);
    assert_non_null(back.gmon);
    assert_non_null(back.gini);
    assert_non_null(back.trim);
    assert_non_null(back.nonfinite);
    assert_non_null(back.accumulators);
    assert_int_equal(back.metadata.set_count, 5);
    assert_int_equal(back.metadata.sample_count, 23);

    size_t pixels = (size_t)back.width * back.height, values = pixels * 3;
    float *mean = malloc(values * 4), *mon = malloc(values * 4), *gmon = malloc(values * 4), *gini = malloc(values * 4);
    int32_t *trim = malloc(values * 4);
    EstimatorImages images = {mean, mon, gmon, gini, trim, values};
    EstimatorSettings host = {back.metadata.set_count, GINI_PER_CHANNEL, 0};
    assert_int_equal(estimator_from_accumulators(&host, back.accumulators, (size_t)5 * 3 * 2 * pixels, pixels,
                                                 back.metadata.sample_count, &images, error, sizeof error),
                     ESTIMATOR_OK);
    assert_memory_equal(mean, back.mean, values * 4);
    assert_memory_equal(mon, back.mon, values * 4);
    assert_memory_equal(gmon, back.gmon, values * 4);
    assert_memory_equal(gini, back.gini, values * 4);
    assert_memory_equal(trim, back.trim, values * 4);
    /* A render with light in it: the image is not black. */
    double total = 0.0;
    for (size_t i = 0; i < values; ++i)
        total += mean[i];
    assert_true(total > 0.0);
    free(mean);
    free(mon);
    free(gmon);
    free(gini);
    free(trim);
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
    size_t words = (size_t)settings.estimator.set_count * 3 * 2 * one_per_pass.width * one_per_pass.height;
    assert_memory_equal(one_per_pass.accumulators, big_passes.accumulators, words * 8);
    assert_memory_equal(one_per_pass.gmon, big_passes.gmon, (size_t)one_per_pass.width * one_per_pass.height * 12);

    /* Samples [0, 10) and [10, 24) rendered apart add up to [0, 24). */
    settings.sample_count = 10;
    render(&scene, &settings, &first_half);
    settings.first_sample = 10;
    settings.sample_count = 14;
    render(&scene, &settings, &second_half);
    const size_t pixels = (size_t)one_per_pass.width * one_per_pass.height;
    for (size_t i = 0; i < words; ++i) {
        /* Planes [set][channel][word][pixel]: a low-word plane is followed
         * by its high-word plane. */
        if ((i / pixels) % 2)
            continue;
        FixedSum a = {first_half.accumulators[i], first_half.accumulators[i + pixels]};
        FixedSum b = {second_half.accumulators[i], second_half.accumulators[i + pixels]};
        FixedSum sum = fixed_add(a, b);
        assert_int_equal(sum.lo, one_per_pass.accumulators[i]);
        assert_int_equal(sum.hi, one_per_pass.accumulators[i + pixels]);
    }
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
            FixedSum s = {out->accumulators[accumulator_index((uint32_t)j, (uint32_t)channel, 0, p, pixels)],
                          out->accumulators[accumulator_index((uint32_t)j, (uint32_t)channel, 1, p, pixels)]};
            uint64_t n_j = (out->sample_count - (uint64_t)j + (uint64_t)m - 1) / (uint64_t)m;
            set_means[j] = fixed_to_float(s) / (double)n_j;
            average += set_means[j] / m;
        }
        for (int j = 0; j < m; ++j)
            spread += (set_means[j] - average) * (set_means[j] - average);
        sum += out->mean[3 * p + (size_t)channel];
        variance += spread / (m - 1) / m; /* variance of the pixel's mean */
    }
    *mean = sum / (double)pixels;
    *standard_error = sqrt(variance) / (double)pixels;
}

/* Next-event estimation with MIS and BSDF sampling alone estimate the same
 * image: their means agree within the combined standard error. */
static void test_nee_and_bsdf_sampling_agree(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const char *scenes[] = {"cornell-diffuse.pbrt", "cornell-glass.pbrt"};
    for (int s = 0; s < 2; ++s) {
        RenderOutput outputs[2];
        for (int nee = 0; nee <= 1; ++nee) {
            RenderScene scene;
            load(scenes[s], 32, &scene);
            scene.params.flags = nee ? RENDER_NEE : 0u;
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
        }
        render_output_free(&outputs[0]);
        render_output_free(&outputs[1]);
    }
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
    uint64_t sums[3 * 2 * 4] = {0}; /* M = 1, 2x2 pixels */
    float mean[3 * 4] = {0};
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = 2;
    image.height = 2;
    image.mean = mean;
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
        cmocka_unit_test(test_nee_and_bsdf_sampling_agree),
        cmocka_unit_test(test_failed_write_leaves_the_old_file),
        cmocka_unit_test(test_output_path_checked_before_render),
        cmocka_unit_test(test_estimate_refuses_sums_without_samples),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
