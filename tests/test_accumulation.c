/* Accumulation at scale: 10^7 heavy-tailed samples into one set, on the host
 * and on the device through the shared accumulation code; the set mean must
 * be within 1e-6 relative of a long-double sum of the same floats. */
#include "cl/cl_device.h"
#include "film/film.h"
#include "accumulate.h"
#include "exact_sum.h"
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
    accumulators_normalize(accumulators, 0, 1, 1); /* as a kernel pass ends */
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

/* ---- The per-pixel grid: range, exactness, order, merging ---- */

/* A random float k * 2^e, k of up to 24 bits, e in [lowest, highest],
 * either sign when `signs`. */
static float wide_sample(TestRng *rng, int lowest, int highest, int signs)
{
    uint64_t r = test_rng_next(rng);
    float k = (float)((r >> 40) | 1);
    int e = lowest + (int)((r >> 8) % (uint64_t)(highest - lowest + 1));
    return signs && (r & 1) ? -ldexpf(k, e) : ldexpf(k, e);
}

#define GRID_SETS 3
#define GRID_WORDS (1 + GRID_SETS * 6)

/* Adds samples[0..count) (RGB) to one pixel of GRID_SETS sets; returns the
 * rounded samples. */
static int add_stream(uint64_t *accumulators, const float *samples, size_t count, size_t first)
{
    int rounded = 0;
    for (size_t i = 0; i < count; ++i) {
        const float *rgb = samples + 3 * i;
        int added = accumulate_sample(accumulators, 0, 1, GRID_SETS, set_of_sample(first + i, GRID_SETS), rgb[0],
                                      rgb[1], rgb[2]);
        assert_int_not_equal(added, EST_ADD_NONFINITE);
        rounded += added == EST_ADD_ROUNDED;
    }
    accumulators_normalize(accumulators, 0, 1, GRID_SETS);
    return rounded;
}

/* Each set sum, rounded to float, against the independent long accumulator
 * (tests/support/exact_sum.c). */
static void assert_sums_exact(const uint64_t *accumulators, const float *samples, size_t count)
{
    ExactSum exact[GRID_SETS][3];
    memset(exact, 0, sizeof exact);
    for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c)
            exact_sum_add(&exact[i % GRID_SETS][c], samples[3 * i + (size_t)c]);
    float sums[GRID_SETS * 3];
    assert_int_equal(
        estimator_sums_from_accumulators(GRID_SETS, accumulators, GRID_WORDS, 1, sums, GRID_SETS * 3, NULL, 0),
        ESTIMATOR_OK);
    for (int j = 0; j < GRID_SETS; ++j)
        for (int c = 0; c < 3; ++c) {
            float want = exact_sum_to_float(&exact[j][c]), got = sums[set_sum_index((uint32_t)j, (uint32_t)c, 0, 1)];
            if (memcmp(&want, &got, sizeof want) != 0)
                fail_msg("set %d channel %d: sum %a, exact %a", j, c, (double)got, (double)want);
        }
}

/* Samples spanning 90 binary orders in one pixel (k * 2^e, 24-bit k, at
 * most 2^(e_max + 24) over 2^e_min), from the smallest denormal 2^-149 up to
 * 2^127, either sign, are summed exactly: 1000 samples a set, so the sums
 * need e_max - e_min + 24 + 10 bits of the 126 they hold. */
static void test_wide_range_sums_are_exact(void **state)
{
    (void)state;
    const struct {
        int lowest, highest, signs;
    } ranges[] = {{-149, -62, 1}, {-40, 50, 0}, {-30, 55, 1}, {30, 103, 0}, {-10, 10, 1}};
    enum { COUNT = 3000 };
    float *samples = malloc(COUNT * 3 * sizeof(float));
    assert_non_null(samples);
    for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; ++r) {
        TestRng rng = test_rng(500 + r);
        for (size_t i = 0; i < COUNT * 3; ++i)
            samples[i] = wide_sample(&rng, ranges[r].lowest, ranges[r].highest, ranges[r].signs);
        uint64_t accumulators[GRID_WORDS] = {0};
        int rounded = add_stream(accumulators, samples, COUNT, 0);
        if (rounded)
            fail_msg("exponents %d..%d: %d samples rounded", ranges[r].lowest, ranges[r].highest, rounded);
        assert_sums_exact(accumulators, samples, COUNT);
    }
    free(samples);
}

/* Exact sums do not depend on the order of the samples, even when the grid
 * moves down late (a tiny value after large sums) or the big values come
 * last. */
static void test_order_does_not_matter(void **state)
{
    (void)state;
    enum { COUNT = 999 };
    float forward[COUNT * 3], backward[COUNT * 3];
    TestRng rng = test_rng(77);
    for (size_t i = 0; i < COUNT * 3; ++i)
        forward[i] = wide_sample(&rng, -20, 40, 1);
    forward[3 * (COUNT - 1)] = ldexpf(1.0f, -45); /* the finest, last */
    for (size_t i = 0; i < COUNT; ++i)            /* reversed order, same sets */
        memcpy(&backward[3 * i], &forward[3 * (COUNT - 1 - i)], 3 * sizeof(float));
    uint64_t a[GRID_WORDS] = {0}, b[GRID_WORDS] = {0};
    assert_int_equal(add_stream(a, forward, COUNT, 0), 0);
    /* backward[i] is sample COUNT - 1 - i: give it that sample's set. */
    for (size_t i = 0; i < COUNT; ++i) {
        const float *rgb = &backward[3 * i];
        assert_int_equal(
            accumulate_sample(b, 0, 1, GRID_SETS, set_of_sample(COUNT - 1 - i, GRID_SETS), rgb[0], rgb[1], rgb[2]),
            EST_ADD_EXACT);
    }
    accumulators_normalize(b, 0, 1, GRID_SETS);
    assert_memory_equal(a, b, sizeof a);
}

/* Ranges merged in any order, with different grids, equal the whole. */
static void test_merging_ranges_with_different_grids(void **state)
{
    (void)state;
    enum { COUNT = 1200, CUT = 500 };
    float samples[COUNT * 3];
    TestRng rng = test_rng(99);
    for (size_t i = 0; i < COUNT * 3; ++i)
        samples[i] = wide_sample(&rng, i < CUT * 3 ? 20 : -30, i < CUT * 3 ? 50 : 0, 0);
    uint64_t whole[GRID_WORDS] = {0}, first[GRID_WORDS] = {0}, second[GRID_WORDS] = {0}, empty[GRID_WORDS] = {0};
    add_stream(whole, samples, COUNT, 0);
    add_stream(first, samples, CUT, 0);
    add_stream(second, samples + 3 * CUT, COUNT - CUT, CUT);
    assert_true(first[grid_index(0)] > second[grid_index(0)]); /* different grids */
    uint64_t a[GRID_WORDS], b[GRID_WORDS];
    memcpy(a, first, sizeof a);
    memcpy(b, second, sizeof b);
    assert_int_equal(accumulators_merge_pixel(a, b, 0, 1, GRID_SETS), 0);
    assert_memory_equal(a, whole, sizeof a);
    memcpy(a, first, sizeof a);
    memcpy(b, second, sizeof b);
    assert_int_equal(accumulators_merge_pixel(b, a, 0, 1, GRID_SETS), 0);
    assert_memory_equal(b, whole, sizeof b);
    assert_int_equal(accumulators_merge_pixel(empty, whole, 0, 1, GRID_SETS), 0); /* into an empty pixel */
    assert_memory_equal(empty, whole, sizeof empty);
}

/* Values too far apart for one set sum (2^120 beside 2^-100) are rounded,
 * reported as such, never dropped: the sum stays within its last units of
 * the exact value, and scaling by 2^k still scales it exactly. */
static void test_range_beyond_a_sum_is_rounded_and_reported(void **state)
{
    (void)state;
    enum { COUNT = 300 };
    float samples[COUNT * 3];
    TestRng rng = test_rng(5);
    for (size_t i = 0; i < COUNT * 3; ++i)
        samples[i] = i % 2 ? wide_sample(&rng, 80, 100, 0) : wide_sample(&rng, -120, -100, 0);
    uint64_t accumulators[GRID_WORDS] = {0};
    int rounded = add_stream(accumulators, samples, COUNT, 0);
    printf("  2^-120..2^100 in one pixel: %d of %d samples rounded\n", rounded, COUNT);
    assert_true(rounded > 0);
    ExactSum exact[GRID_SETS][3];
    memset(exact, 0, sizeof exact);
    for (size_t i = 0; i < COUNT; ++i)
        for (int c = 0; c < 3; ++c)
            exact_sum_add(&exact[i % GRID_SETS][c], samples[3 * i + (size_t)c]);
    for (int j = 0; j < GRID_SETS; ++j)
        for (int c = 0; c < 3; ++c) {
            long double want = exact_sum_to_long_double(&exact[j][c]);
            long double got = test_set_sum(accumulators, (uint32_t)j, (uint32_t)c, 0, 1);
            if (fabsl(got - want) > ldexpl(fabsl(want), -60))
                fail_msg("set %d channel %d: %La, exact %La", j, c, got, want);
        }
    /* The same stream scaled by 2^-20: the same integers, the grid 20 lower. */
    float scaled[COUNT * 3];
    for (size_t i = 0; i < COUNT * 3; ++i)
        scaled[i] = ldexpf(samples[i], -20);
    uint64_t lower[GRID_WORDS] = {0};
    assert_int_equal(add_stream(lower, scaled, COUNT, 0), rounded);
    assert_int_equal(lower[grid_index(0)] + 20, accumulators[grid_index(0)]);
    assert_memory_equal(lower + 1, accumulators + 1, (GRID_WORDS - 1) * sizeof(uint64_t));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain_float_sum_fails_the_bar),
        cmocka_unit_test(test_host_accumulation_is_accurate),
        cmocka_unit_test(test_split_accumulation_merges_exactly),
        cmocka_unit_test(test_device_accumulation_is_accurate),
        cmocka_unit_test(test_wide_range_sums_are_exact),
        cmocka_unit_test(test_order_does_not_matter),
        cmocka_unit_test(test_merging_ranges_with_different_grids),
        cmocka_unit_test(test_range_beyond_a_sum_is_rounded_and_reported),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
