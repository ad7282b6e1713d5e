/* The samplers (kernels/tracing/sampler.h), on the host: the Sobol points behind
 * them form a (0,2)-sequence; every 2D dimension of a stream is a
 * (0,k,2)-net at every power of two 2^k and every 1D dimension stratified,
 * for both Sobol samplers and any M; the scrambling gives each pixel,
 * dimension and seed its own uniformly distributed points; sobol-sets keeps
 * the sets' means independent (the variance of their mean is the variance
 * of one over M) where sobol makes them correlated; the independent
 * sampler draws exactly the random numbers the renderer always drew. */
#include "render/render_scene.h"
#include "sampler.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define MAX_LOG2 12

/* Whether the 2^k points (x[i], y[i]) (32-bit fractions) put exactly one
 * point in every elementary interval of area 2^-k: 2^a by 2^b cells,
 * a + b = k. */
static int is_02_net(const uint32_t *x, const uint32_t *y, int k)
{
    const uint32_t n = 1u << k;
    uint8_t *seen = malloc(n);
    assert_non_null(seen);
    int ok = 1;
    for (int a = 0; a <= k && ok; ++a) {
        const int b = k - a;
        memset(seen, 0, n);
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t cx = a ? x[i] >> (32 - a) : 0u, cy = b ? y[i] >> (32 - b) : 0u;
            uint32_t cell = (cx << b) | cy;
            if (seen[cell]++)
                ok = 0;
        }
    }
    free(seen);
    return ok;
}

/* Whether the 2^k fractions put one in each of 2^k equal intervals. */
static int is_stratified(const uint32_t *x, int k)
{
    uint8_t seen[1u << MAX_LOG2] = {0};
    for (uint32_t i = 0; i < (1u << k); ++i)
        if (seen[k ? x[i] >> (32 - k) : 0u]++)
            return 0;
    return 1;
}

static uint32_t bits_of(float u)
{
    /* Exact: unit_from_bits keeps 24 bits, which a float holds. */
    return (uint32_t)((double)u * 16777216.0) << 8;
}

/* Sobol's first two dimensions without scrambling, in aligned blocks of
 * 2^k points, are (0,k,2)-nets: the property all the rest builds on. */
static void test_sobol_points_form_a_02_sequence(void **state)
{
    (void)state;
    static uint32_t x[1u << MAX_LOG2], y[1u << MAX_LOG2];
    const uint32_t blocks[] = {0u, 1u, 5u, 77777u};
    for (int k = 0; k <= MAX_LOG2; ++k)
        for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; ++b) {
            for (uint32_t i = 0; i < (1u << k); ++i) {
                uint32_t index = (blocks[b] << k) + i;
                x[i] = reverse_bits32(index);
                y[i] = reverse_bits32(sobol_second_reversed(index));
            }
            assert_true(is_02_net(x, y, k));
        }
    /* The second dimension from its definition: the XOR of direction
     * numbers v_k for the index's bits k, v_0 = 1/2, v_{k+1} = v_k xor v_k / 2. */
    for (uint32_t index = 0; index < 100000u; index += 7u) {
        uint32_t expected = 0u, v = 0x80000000u;
        for (uint32_t bits = index; bits; bits >>= 1, v ^= v >> 1)
            if (bits & 1u)
                expected ^= v;
        assert_int_equal(reverse_bits32(sobol_second_reversed(index)), expected);
    }
}

/* The 2^k samples a stream's sequence holds first: samples 0..2^k - 1 for
 * sobol; for sobol-sets, set j's: j, j + M, j + 2M, ... */
static uint64_t sample_of_point(uint32_t mode, uint32_t set, uint32_t set_count, uint32_t point)
{
    return mode == SAMPLER_SOBOL_SETS ? (uint64_t)point * set_count + set : point;
}

static void test_streams_are_nets_at_every_power_of_two(void **state)
{
    (void)state;
    static uint32_t x[1u << MAX_LOG2], y[1u << MAX_LOG2], z[1u << MAX_LOG2];
    const uint32_t modes[] = {SAMPLER_SOBOL_PIXEL, SAMPLER_SOBOL_SETS};
    const uint32_t set_counts[] = {1u, 21u, 64u};
    const uint32_t dimensions[] = {0u, 3u, 9u, 2u + 40u * 7u, 0xfffffff0u};
    for (size_t m = 0; m < 2; ++m)
        for (size_t c = 0; c < 3; ++c)
            for (size_t d = 0; d < sizeof dimensions / sizeof dimensions[0]; ++d)
                for (uint32_t trial = 0; trial < 3; ++trial) {
                    const uint32_t seed = 17u * trial, set = trial % set_counts[c];
                    const uint64_t pixel = 1000003u * trial + d;
                    for (uint32_t i = 0; i < (1u << MAX_LOG2); ++i) {
                        uint64_t sample = sample_of_point(modes[m], set, set_counts[c], i);
                        SampleStream s = sample_stream(modes[m], seed, pixel, sample, set_counts[c]);
                        float u, v;
                        sample_2d(&s, dimensions[d], &u, &v);
                        x[i] = bits_of(u);
                        y[i] = bits_of(v);
                        z[i] = bits_of(sample_1d(&s, dimensions[d]));
                    }
                    /* 24 bits a float: nets finer than 2^-24 are not asked for. */
                    for (int k = 0; k <= MAX_LOG2; ++k) {
                        assert_true(is_02_net(x, y, k));
                        assert_true(is_stratified(z, k));
                    }
                }
}

/* A light subpath's numbers come from one sequence over the image: the
 * light streams of all 4096 pixels of a 64x64 image at one sample index
 * (of one set, with sobol-sets) form a (0,12,2)-net together, where the
 * pixels' own streams are independent of one another. */
static void test_light_streams_are_one_net_over_the_image(void **state)
{
    (void)state;
    static uint32_t x[1u << MAX_LOG2], y[1u << MAX_LOG2];
    const uint32_t modes[] = {SAMPLER_SOBOL_PIXEL, SAMPLER_SOBOL_SETS};
    const uint64_t pixels = 1u << MAX_LOG2;
    for (size_t m = 0; m < 2; ++m)
        for (uint64_t sample = 0; sample < 50u; sample += 7u) {
            for (uint64_t pixel = 0; pixel < pixels; ++pixel) {
                SampleStream s = light_sample_stream(modes[m], 3u, pixel, sample, 21u, pixels);
                float u, v;
                sample_2d(&s, 0x40000001u, &u, &v);
                x[pixel] = bits_of(u);
                y[pixel] = bits_of(v);
            }
            assert_true(is_02_net(x, y, MAX_LOG2));
        }
}

/* Every pixel, dimension and seed has its own scrambling: the first
 * sample's numbers differ among them and are uniform (chi-square over 32
 * bins of 32768 streams; 99.9th percentile of chi-square with 31 degrees of
 * freedom: 61.1). */
static void test_scrambling_is_uniform_and_distinct(void **state)
{
    (void)state;
    const uint32_t modes[] = {SAMPLER_SOBOL_PIXEL, SAMPLER_SOBOL_SETS};
    for (size_t m = 0; m < 2; ++m)
        for (int what = 0; what < 3; ++what) {
            unsigned counts[2][32] = {{0}};
            const unsigned n = 32768;
            for (unsigned i = 0; i < n; ++i) {
                uint64_t pixel = what == 0 ? i : 5u;
                uint32_t seed = what == 1 ? i : 3u, dimension = what == 2 ? 2u + 7u * i : 4u;
                SampleStream s = sample_stream(modes[m], seed, pixel, 0u, 21u);
                float u, v;
                sample_2d(&s, dimension, &u, &v);
                counts[0][(int)(u * 32.0f)]++;
                counts[1][(int)(v * 32.0f)]++;
            }
            for (int axis = 0; axis < 2; ++axis) {
                double chi2 = 0.0, expected = n / 32.0;
                for (int b = 0; b < 32; ++b)
                    chi2 += (counts[axis][b] - expected) * (counts[axis][b] - expected) / expected;
                assert_true(chi2 < 61.1);
            }
        }
}

/* An integrand with an edge and a smooth part, as images have. */
static double integrand(float u, float v)
{
    return (u + v < 1.1f ? 1.0 : 0.0) + (double)u * v;
}

/* The set-independence measure: over many pixels (independent
 * replicates), the variance of the mean of M set means against the
 * variance one set's mean has, over M. 1 when the sets are independent;
 * below 1 when they are negatively correlated. */
static double independence_ratio(uint32_t mode, uint32_t set_count, uint32_t per_set, double *correlation)
{
    enum { PIXELS = 4000 };
    double sum_mean = 0.0, sum_mean2 = 0.0, within = 0.0, sum_ab = 0.0, sum_a = 0.0, sum_b = 0.0, sum_a2 = 0.0,
           sum_b2 = 0.0;
    for (uint32_t p = 0; p < PIXELS; ++p) {
        double set_means[64] = {0.0};
        for (uint32_t s = 0; s < set_count * per_set; ++s) {
            SampleStream stream = sample_stream(mode, 9u, p, s, set_count);
            float u, v;
            sample_2d(&stream, 2u + 4u, &u, &v);
            set_means[s % set_count] += integrand(u, v) / per_set;
        }
        double mean = 0.0, square = 0.0;
        for (uint32_t j = 0; j < set_count; ++j)
            mean += set_means[j] / set_count;
        for (uint32_t j = 0; j < set_count; ++j)
            square += (set_means[j] - mean) * (set_means[j] - mean);
        within += square / (set_count - 1);
        sum_mean += mean;
        sum_mean2 += mean * mean;
        sum_a += set_means[0];
        sum_b += set_means[1];
        sum_a2 += set_means[0] * set_means[0];
        sum_b2 += set_means[1] * set_means[1];
        sum_ab += set_means[0] * set_means[1];
    }
    const double n = PIXELS;
    double var_mean = (sum_mean2 - sum_mean * sum_mean / n) / (n - 1);
    double cov = sum_ab / n - (sum_a / n) * (sum_b / n);
    *correlation = cov / sqrt((sum_a2 / n - (sum_a / n) * (sum_a / n)) * (sum_b2 / n - (sum_b / n) * (sum_b / n)));
    return var_mean / (within / n / set_count);
}

static void test_sets_stay_independent_with_sobol_sets(void **state)
{
    (void)state;
    double correlation;
    /* 4000 replicates: the ratio's standard error is about 0.03, the
     * correlation's 0.016. */
    double ratio = independence_ratio(SAMPLER_SOBOL_SETS, 8u, 8u, &correlation);
    assert_true(ratio > 0.85 && ratio < 1.15);
    assert_true(fabs(correlation) < 0.07);
    ratio = independence_ratio(SAMPLER_INDEPENDENT, 8u, 8u, &correlation);
    assert_true(ratio > 0.85 && ratio < 1.15);
    /* One sequence across the sets stratifies them against each other. */
    ratio = independence_ratio(SAMPLER_SOBOL_PIXEL, 8u, 8u, &correlation);
    assert_true(ratio < 0.5);
    assert_true(correlation < -0.07);
}

/* The independent sampler's numbers are rng_uniform's, dimension by
 * dimension: its images are the renderer's from before the samplers. */
static void test_independent_is_the_old_random_numbers(void **state)
{
    (void)state;
    for (uint64_t sample = 0; sample < 50; ++sample) {
        SampleStream s = sample_stream(SAMPLER_INDEPENDENT, 42u, 777u, sample, 21u);
        uint64_t key = rng_sample_key(42u, 777u, sample);
        for (uint32_t d = 0; d < 40; ++d) {
            float u, v;
            sample_2d(&s, d, &u, &v);
            assert_true(u == rng_uniform(key, d) && v == rng_uniform(key, d + 1u));
            assert_true(sample_1d(&s, d) == rng_uniform(key, d));
        }
    }
}

static void test_names_and_scene_samplers(void **state)
{
    (void)state;
    for (uint32_t i = 0; i < SAMPLER_COUNT; ++i)
        assert_int_equal(sampler_from_name(sampler_name(i)), (int)i);
    assert_int_equal(sampler_from_name("halton"), -1);
    assert_int_equal(sampler_for_scene("independent"), SAMPLER_INDEPENDENT);
    assert_int_equal(sampler_for_scene("zsobol"), SAMPLER_DEFAULT);
    assert_int_equal(sampler_for_scene(""), SAMPLER_DEFAULT);
    assert_int_equal(SAMPLER_DEFAULT, SAMPLER_SOBOL_SETS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sobol_points_form_a_02_sequence),
        cmocka_unit_test(test_streams_are_nets_at_every_power_of_two),
        cmocka_unit_test(test_scrambling_is_uniform_and_distinct),
        cmocka_unit_test(test_light_streams_are_one_net_over_the_image),
        cmocka_unit_test(test_sets_stay_independent_with_sobol_sets),
        cmocka_unit_test(test_independent_is_the_old_random_numbers),
        cmocka_unit_test(test_names_and_scene_samplers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
