/* Kernel == host, bit for bit: the estimator kernels on the OpenCL device
 * against the host reference (the same estimators.h compiled by the host
 * compiler), for M in {1, 2, 3, 4, 20, 21, 64}, every pass (the whole
 * estimator family, diagnostics and standard errors), every Gini mode and
 * every input case, plus sample streams with NaN and Inf accumulated on both. */
#include "cl/cl_device.h"
#include "film/film.h"
#include "film/estimator_program.h"
#include "estimator_cases.h"
#include "estimator_images.h"
#include "estimators.h"
#include "sample_streams.h"
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

static const int set_counts[] = {1, 2, 3, 4, 20, 21, 64};
#define SET_COUNTS (int)(sizeof set_counts / sizeof set_counts[0])

/* The kernels compared: every pass with and without standard errors, in
 * the Gini modes that have them, every pass in sort-by-luminance, and the
 * default passes (the kernels' fast path, channel by channel). */
typedef struct {
    GiniMode mode;
    uint32_t passes;
    int with_stderr;
} Variant;
static const Variant variants[] = {
    {GINI_PER_CHANNEL, PASSES_ALL, 1},
    {GINI_PER_CHANNEL, PASSES_ALL, 0},
    {GINI_PER_PIXEL, PASSES_ALL, 1},
    {SORT_BY_LUMINANCE, PASSES_ALL, 0},
    {GINI_PER_CHANNEL, PASSES_DEFAULT | PASSES_DIAGNOSTICS, 0},
};
#define VARIANTS (int)(sizeof variants / sizeof variants[0])

static EstimatorSettings variant_settings(int set_count, const Variant *v)
{
    EstimatorSettings settings;
    estimator_settings_default(&settings);
    settings.set_count = set_count;
    settings.gini_mode = v->mode;
    settings.passes = v->passes;
    settings.with_stderr = v->with_stderr;
    return settings;
}

static void test_kernel_equals_host_on_all_cases(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    int compared = 0;
    for (int mi = 0; mi < SET_COUNTS; ++mi) {
        for (int vi = 0; vi < VARIANTS; ++vi) {
            /* Every M with every pass and error; the other kernels (each
             * takes seconds to compile) at an even and an odd M. */
            if (vi > 0 && set_counts[mi] != 4 && set_counts[mi] != ESTIMATOR_DEFAULT_SETS)
                continue;
            EstimatorSettings settings = variant_settings(set_counts[mi], &variants[vi]);
            EstimatorProgram *program = estimator_program_new(&test_device, &settings, NULL, NULL);
            assert_non_null(program);
            for (int kind = 0; kind < CASE_COUNT; ++kind) {
                EstimatorCase c = estimator_case_make((EstimatorCaseKind)kind, set_counts[mi], 1);
                size_t values = (size_t)c.set_count * 3 * c.pixel_count;
                EstimatorImages host = test_images_new(settings.passes, settings.with_stderr, c.pixel_count);
                EstimatorImages kernel = test_images_new(settings.passes, settings.with_stderr, c.pixel_count);
                char message[256];
                assert_int_equal(estimator_from_sums(&settings, c.sums, values, c.pixel_count, c.sample_count, &host,
                                                     message, sizeof message),
                                 ESTIMATOR_OK);
                assert_int_equal(estimator_program_run(program, c.sums, 0, c.pixel_count, c.sample_count, &kernel), 0);
                char what[128];
                snprintf(what, sizeof what, "M=%d variant %d case '%s'", set_counts[mi], vi, c.name);
                assert_images_identical(&kernel, &host, c.pixel_count, what);
                ++compared;
                test_images_free(&host);
                test_images_free(&kernel);
                estimator_case_free(&c);
            }
            estimator_program_destroy(program);
        }
    }
    printf("compared %d (M, kernel, case) combinations bit for bit, %d passes each\n", compared, PASS_COUNT);
}

/* A stream of RGB samples with NaN, +Inf, -Inf, huge and denormal values
 * mixed into ordinary ones. */
static float *make_stream(size_t pixel_count, size_t length, uint64_t seed)
{
    float *samples = malloc(pixel_count * length * 3 * sizeof(float));
    TestRng rng = test_rng(seed);
    for (size_t i = 0; i < pixel_count * length * 3; ++i) {
        uint64_t pick = test_rng_next(&rng) % 100;
        double u = test_rng_uniform(&rng);
        float x = (float)(u * u * 4.0);
        if (pick == 0)
            x = NAN;
        else if (pick == 1)
            x = INFINITY;
        else if (pick == 2)
            x = -INFINITY;
        else if (pick == 3)
            x = 1e30f; /* with the denormals below, more than a set sum spans: rounded */
        else if (pick == 4)
            x = 1e-40f * (float)u;
        else if (pick < 10)
            x = (float)test_pareto(&rng, 1.2);
        samples[i] = x;
    }
    return samples;
}

/* Runs accumulate_stream over samples [first, first + length) of each
 * pixel's stream of `total` samples: one pass of a progressive render. */
static void device_accumulate(cl_kernel kernel, cl_mem accumulators, cl_mem rejected, const float *samples,
                              size_t pixel_count, size_t total, size_t first, size_t length)
{
    cl_int err = CL_SUCCESS;
    float *slice = malloc(pixel_count * length * 3 * sizeof(float));
    for (size_t p = 0; p < pixel_count; ++p)
        memcpy(slice + p * length * 3, samples + (p * total + first) * 3, length * 3 * sizeof(float));
    cl_mem in = clCreateBuffer(test_device.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               pixel_count * length * 3 * sizeof(float), slice, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_ulong stream_length = length, first_sample = first, pixels = pixel_count;
    assert_int_equal(clSetKernelArg(kernel, 0, sizeof in, &in), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 1, sizeof stream_length, &stream_length), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 2, sizeof first_sample, &first_sample), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 3, sizeof accumulators, &accumulators), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 4, sizeof pixels, &pixels), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 5, sizeof rejected, &rejected), CL_SUCCESS);
    size_t global = pixel_count;
    assert_int_equal(clEnqueueNDRangeKernel(test_device.queue, kernel, 1, NULL, &global, NULL, 0, NULL, NULL),
                     CL_SUCCESS);
    assert_int_equal(clFinish(test_device.queue), CL_SUCCESS);
    clReleaseMemObject(in);
    free(slice);
}

static void test_streams_with_nan_and_inf(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const size_t pixel_count = 61, length = 300;
    for (int mi = 0; mi < SET_COUNTS; ++mi) {
        const int m = set_counts[mi];
        float *samples = make_stream(pixel_count, length, (uint64_t)m);
        size_t words = accumulator_planes((uint32_t)m) * pixel_count;

        /* Host: the shared accumulation code, one sample at a time; two
         * counter planes, non-finite and rounded samples. */
        uint64_t *host_acc = calloc(words, sizeof(uint64_t));
        uint32_t *host_rejected = calloc(2 * pixel_count, sizeof(uint32_t));
        for (size_t p = 0; p < pixel_count; ++p)
            for (size_t i = 0; i < length; ++i) {
                const float *rgb = samples + (p * length + i) * 3;
                int added = accumulate_sample(host_acc, p, pixel_count, (uint32_t)m, set_of_sample(i, (uint32_t)m),
                                              rgb[0], rgb[1], rgb[2]);
                host_rejected[p] += added == EST_ADD_NONFINITE;
                host_rejected[pixel_count + p] += added == EST_ADD_ROUNDED;
            }
        for (size_t p = 0; p < pixel_count; ++p) /* as the kernel does at the end of a pass */
            accumulators_normalize(host_acc, p, pixel_count, (uint32_t)m);

        /* Device: the same stream in two passes of unequal length. */
        char options[64];
        snprintf(options, sizeof options, "-DEST_SETS=%d -DEST_PASSES=0", m);
        cl_program program = cl_program_build(&test_device, "estimator", options, NULL);
        assert_non_null(program);
        cl_int err = CL_SUCCESS;
        cl_kernel kernel = clCreateKernel(program, "accumulate_stream", &err);
        assert_int_equal(err, CL_SUCCESS);
        uint64_t *zero = calloc(words, sizeof(uint64_t));
        cl_mem acc = clCreateBuffer(test_device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                    words * sizeof(uint64_t), zero, &err);
        assert_int_equal(err, CL_SUCCESS);
        cl_mem rejected = clCreateBuffer(test_device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                         2 * pixel_count * sizeof(uint32_t), zero, &err);
        assert_int_equal(err, CL_SUCCESS);
        /* Two passes of unequal length, as a progressive render batches. */
        device_accumulate(kernel, acc, rejected, samples, pixel_count, length, 0, 113);
        device_accumulate(kernel, acc, rejected, samples, pixel_count, length, 113, length - 113);

        uint64_t *device_acc = malloc(words * sizeof(uint64_t));
        uint32_t *device_rejected = malloc(2 * pixel_count * sizeof(uint32_t));
        assert_int_equal(clEnqueueReadBuffer(test_device.queue, acc, CL_TRUE, 0, words * sizeof(uint64_t), device_acc,
                                             0, NULL, NULL),
                         CL_SUCCESS);
        assert_int_equal(clEnqueueReadBuffer(test_device.queue, rejected, CL_TRUE, 0,
                                             2 * pixel_count * sizeof(uint32_t), device_rejected, 0, NULL, NULL),
                         CL_SUCCESS);
        assert_memory_equal(device_acc, host_acc, words * sizeof(uint64_t));
        assert_memory_equal(device_rejected, host_rejected, 2 * pixel_count * sizeof(uint32_t));
        uint32_t nonfinite = 0, rounded = 0;
        for (size_t p = 0; p < pixel_count; ++p) {
            nonfinite += host_rejected[p];
            rounded += host_rejected[pixel_count + p];
        }
        assert_true(nonfinite > 0 && rounded > 0);

        /* And the estimates of those sums, from the accumulators. */
        /* Every variant at the paper's M; elsewhere the default passes and
         * all passes with errors (each kernel takes seconds to compile). */
        for (int vi = 0; vi < VARIANTS; ++vi) {
            if (m != ESTIMATOR_DEFAULT_SETS && vi != 0 && vi != VARIANTS - 1)
                continue;
            EstimatorSettings settings = variant_settings(m, &variants[vi]);
            EstimatorProgram *est = estimator_program_new(&test_device, &settings, NULL, NULL);
            assert_non_null(est);
            EstimatorImages host = test_images_new(settings.passes, settings.with_stderr, pixel_count);
            EstimatorImages kern = test_images_new(settings.passes, settings.with_stderr, pixel_count);
            assert_int_equal(
                estimator_from_accumulators(&settings, host_acc, words, pixel_count, length, &host, NULL, 0),
                ESTIMATOR_OK);
            assert_int_equal(estimator_program_run(est, device_acc, 1, pixel_count, length, &kern), 0);
            char what[96];
            snprintf(what, sizeof what, "stream M=%d variant %d", m, vi);
            assert_images_identical(&kern, &host, pixel_count, what);
            for (int p = 0; p < PASS_COUNT; ++p)
                for (size_t i = 0; (settings.passes & PASSES_ESTIMATES & PASS_BIT(p)) && i < pixel_count * 3; ++i)
                    assert_true(isfinite(TEST_IMAGE(host, p)[i]));
            test_images_free(&host);
            test_images_free(&kern);
            estimator_program_destroy(est);
        }

        free(device_acc);
        free(device_rejected);
        free(zero);
        free(host_acc);
        free(host_rejected);
        free(samples);
        clReleaseMemObject(acc);
        clReleaseMemObject(rejected);
        clReleaseKernel(kernel);
        clReleaseProgram(program);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kernel_equals_host_on_all_cases),
        cmocka_unit_test(test_streams_with_nan_and_inf),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
