/* Accumulation at scale: 10^7 heavy-tailed samples into one set, on the host
 * and on the device through the shared accumulation code; the set mean must
 * be within 1e-6 relative of a long-double sum of the same floats. */
#include "cl/cl_device.h"
#include "estimator_core.h"
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

#define SAMPLES 10000000u
#define WORDS 7 /* accumulator_planes(1): one pixel, one set */

/* Three streams in the three channels: Pareto with tail index 1.1, Pareto
 * 1.5, and 1.0 with rare 1e6 spikes. */
static float *make_streams(void)
{
    float *rgb = malloc((size_t)SAMPLES * 3 * sizeof(float));
    TestRng rng = test_rng(2024);
    for (size_t i = 0; i < SAMPLES; ++i) {
        rgb[3 * i + 0] = (float)test_pareto(&rng, 1.1);
        rgb[3 * i + 1] = (float)test_pareto(&rng, 1.5);
        rgb[3 * i + 2] = (float)test_spiky(&rng, 1e6, 1e-5);
    }
    return rgb;
}

static const char *const stream_names[3] = {"Pareto 1.1", "Pareto 1.5", "1 + rare 1e6 spikes"};

static float *streams;
static long double exact_mean[3];

static int setup(void **state)
{
    (void)state;
    streams = make_streams();
    long double sum[3] = {0, 0, 0};
    for (size_t i = 0; i < SAMPLES; ++i)
        for (int c = 0; c < 3; ++c)
            sum[c] += streams[3 * i + (size_t)c];
    for (int c = 0; c < 3; ++c)
        exact_mean[c] = sum[c] / SAMPLES;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    free(streams);
    return 0;
}

static double relative_error(float mean, int channel)
{
    return (double)fabsl(((long double)mean - exact_mean[channel]) / exact_mean[channel]);
}

/* The set mean as the estimators see it: the sum rounded to float, / n. */
static float set_mean(const uint64_t *accumulators, int channel)
{
    FixedSum s = {accumulators[accumulator_index(0, (uint32_t)channel, 0, 0, 1)],
                  accumulators[accumulator_index(0, (uint32_t)channel, 1, 0, 1)]};
    return ldexpf(fixed_to_float(s), grid_exponent(accumulators[grid_index(0)])) / (float)SAMPLES;
}

static void accumulate_range(uint64_t *accumulators, size_t first, size_t count)
{
    for (size_t i = first; i < first + count; ++i)
        assert_int_equal(
            accumulate_sample(accumulators, 0, 1, 1, 0, streams[3 * i], streams[3 * i + 1], streams[3 * i + 2]),
            EST_ADD_EXACT);
}

static void test_plain_float_sum_fails_the_bar(void **state)
{
    (void)state;
    /* Why the accumulator exists: a plain float running sum misses 1e-6. */
    int failures = 0;
    for (int c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (size_t i = 0; i < SAMPLES; ++i)
            sum += streams[3 * i + (size_t)c];
        double error = relative_error(sum / (float)SAMPLES, c);
        printf("  plain float sum, %-20s relative error %.3e\n", stream_names[c], error);
        failures += error > 1e-6;
    }
    assert_true(failures > 0);
}

static void test_host_accumulation_is_accurate(void **state)
{
    (void)state;
    uint64_t accumulators[WORDS] = {0};
    accumulate_range(accumulators, 0, SAMPLES);
    for (int c = 0; c < 3; ++c) {
        double error = relative_error(set_mean(accumulators, c), c);
        printf("  host accumulation,   %-20s mean %.9Lg relative error %.3e\n", stream_names[c], exact_mean[c], error);
        assert_true(error <= 1e-6);
    }
}

static void test_split_accumulation_merges_exactly(void **state)
{
    (void)state;
    /* Exact sums are associative: two halves added equal the whole. */
    uint64_t whole[WORDS] = {0}, first[WORDS] = {0}, second[WORDS] = {0};
    accumulate_range(whole, 0, SAMPLES);
    accumulate_range(first, 0, 3333333);
    accumulate_range(second, 3333333, SAMPLES - 3333333);
    assert_int_equal(accumulators_merge_pixel(second, first, 0, 1, 1), 0);
    assert_memory_equal(second, whole, sizeof whole);
}

static void test_device_accumulation_is_accurate(void **state)
{
    (void)state;
    ClDevice device;
    if (!test_device_open(&device))
        skip();
    cl_program program = cl_program_build(&device, "estimator", "-DEST_SETS=1", NULL);
    assert_non_null(program);
    cl_int err = CL_SUCCESS;
    cl_kernel kernel = clCreateKernel(program, "accumulate_stream", &err);
    assert_int_equal(err, CL_SUCCESS);
    uint64_t accumulators[WORDS] = {0};
    uint32_t rejected[2] = {0, 0}; /* non-finite, rounded */
    cl_mem in = clCreateBuffer(device.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               (size_t)SAMPLES * 3 * sizeof(float), streams, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_mem acc = clCreateBuffer(device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof accumulators,
                                accumulators, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_mem rej =
        clCreateBuffer(device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof rejected, rejected, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_ulong length = SAMPLES, first = 0, pixels = 1;
    assert_int_equal(clSetKernelArg(kernel, 0, sizeof in, &in), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 1, sizeof length, &length), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 2, sizeof first, &first), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 3, sizeof acc, &acc), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 4, sizeof pixels, &pixels), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(kernel, 5, sizeof rej, &rej), CL_SUCCESS);
    size_t global = 1;
    assert_int_equal(clEnqueueNDRangeKernel(device.queue, kernel, 1, NULL, &global, NULL, 0, NULL, NULL), CL_SUCCESS);
    assert_int_equal(
        clEnqueueReadBuffer(device.queue, acc, CL_TRUE, 0, sizeof accumulators, accumulators, 0, NULL, NULL),
        CL_SUCCESS);
    assert_int_equal(clEnqueueReadBuffer(device.queue, rej, CL_TRUE, 0, sizeof rejected, rejected, 0, NULL, NULL),
                     CL_SUCCESS);
    assert_int_equal(rejected[0], 0);
    assert_int_equal(rejected[1], 0);

    uint64_t host[WORDS] = {0};
    accumulate_range(host, 0, SAMPLES);
    assert_memory_equal(accumulators, host, sizeof host);
    for (int c = 0; c < 3; ++c) {
        double error = relative_error(set_mean(accumulators, c), c);
        printf("  device accumulation, %-20s relative error %.3e\n", stream_names[c], error);
        assert_true(error <= 1e-6);
    }
    clReleaseMemObject(in);
    clReleaseMemObject(acc);
    clReleaseMemObject(rej);
    clReleaseKernel(kernel);
    clReleaseProgram(program);
    cl_device_close(&device);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain_float_sum_fails_the_bar),
        cmocka_unit_test(test_host_accumulation_is_accurate),
        cmocka_unit_test(test_split_accumulation_merges_exactly),
        cmocka_unit_test(test_device_accumulation_is_accurate),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
