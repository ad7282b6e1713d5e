/* The host estimators against an independent long-double reference of the
 * formulas (tests/support/long_double_reference.c), and the properties that
 * docs/estimators.md ("Required properties") asks of every implementation;
 * plus the exact fixed-point accumulation and its conversion to float sums. */
#include "film/film.h"
#include "estimator_cases.h"
#include "estimators.h"
#include "long_double_reference.h"
#include "sample_streams.h"

#include <float.h>
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
#define SET_COUNT_CHOICES (sizeof set_counts / sizeof set_counts[0])

static const GiniMode modes[] = {GINI_PER_CHANNEL, GINI_PER_PIXEL, SORT_BY_LUMINANCE};
static const char *const mode_names[] = {"Gini per channel", "Gini per pixel", "sort by luminance"};
#define MODE_CHOICES 3

#define CASE_SEED 1

/* Only the first few failures print their details; the rest are counted. */
#define DETAILED_FAILURES 20

/* ------------------------------------------------------------------------
 * Running the host estimator.
 * ---------------------------------------------------------------------- */

typedef struct {
    float *mean;
    float *mon;
    float *gmon;
    float *gini;
    int32_t *trim;
    EstimatorImages images;
} Outputs;

static void outputs_init(Outputs *o, size_t pixel_count)
{
    size_t n = pixel_count * 3;
    o->mean = calloc(n, sizeof(float));
    o->mon = calloc(n, sizeof(float));
    o->gmon = calloc(n, sizeof(float));
    o->gini = calloc(n, sizeof(float));
    o->trim = calloc(n, sizeof(int32_t));
    assert_true(o->mean && o->mon && o->gmon && o->gini && o->trim);
    memset(&o->images, 0, sizeof o->images);
    o->images.pass[PASS_MEAN] = o->mean;
    o->images.pass[PASS_MON] = o->mon;
    o->images.pass[PASS_GMON] = o->gmon;
    o->images.pass[PASS_GINI] = o->gini;
    o->images.pass[PASS_TRIM] = o->trim;
    o->images.length = n;
}

static void outputs_free(Outputs *o)
{
    free(o->mean);
    free(o->mon);
    free(o->gmon);
    free(o->gini);
    free(o->trim);
}

/* Every output of two runs is bit-identical. */
static int outputs_identical(const Outputs *a, const Outputs *b, size_t pixel_count)
{
    size_t n = pixel_count * 3;
    return memcmp(a->mean, b->mean, n * sizeof(float)) == 0 && memcmp(a->mon, b->mon, n * sizeof(float)) == 0 &&
           memcmp(a->gmon, b->gmon, n * sizeof(float)) == 0 && memcmp(a->gini, b->gini, n * sizeof(float)) == 0 &&
           memcmp(a->trim, b->trim, n * sizeof(int32_t)) == 0;
}

/* Mean, MoN, G-MoN and the diagnostics, with M sets in a Gini mode. */
static EstimatorSettings default_passes(int set_count, GiniMode mode)
{
    EstimatorSettings settings;
    estimator_settings_default(&settings);
    settings.set_count = set_count;
    settings.gini_mode = mode;
    settings.passes = PASSES_DEFAULT | PASSES_DIAGNOSTICS;
    return settings;
}

static void estimate(int set_count, GiniMode mode, const float *sums, size_t pixel_count, uint64_t sample_count,
                     Outputs *o)
{
    EstimatorSettings settings = default_passes(set_count, mode);
    char message[256] = "";
    EstimatorStatus status = estimator_from_sums(&settings, sums, (size_t)set_count * 3 * pixel_count, pixel_count,
                                                 sample_count, &o->images, message, sizeof message);
    if (status != ESTIMATOR_OK)
        print_error("estimator_from_sums: %s\n", message);
    assert_int_equal(status, ESTIMATOR_OK);
}

static size_t plane_index(int set, int channel, size_t pixel, size_t pixel_count)
{
    return ((size_t)set * 3 + (size_t)channel) * pixel_count + pixel;
}

static int same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* The set sums of one channel of one pixel, for failure reports. */
static void print_channel_sums(const EstimatorCase *c, size_t pixel, int channel)
{
    print_error("    n = %llu, set sums:", (unsigned long long)c->sample_count);
    for (int j = 0; j < c->set_count; ++j)
        print_error(" %a", (double)c->sums[plane_index(j, channel, pixel, c->pixel_count)]);
    print_error("\n");
}

/* ------------------------------------------------------------------------
 * Against the long-double reference.
 * ---------------------------------------------------------------------- */

typedef struct {
    int failures;
    int boundary_cases; /* trim decisions where c differs at an integer G*k */
    int trim_decisions;
} ReferenceTally;

/* |got - want| <= 1e-6 * scale, where scale is |want| (plain relative
 * error) or, for mixed signs, the channel's largest |t_j|. One float spacing
 * below FLT_MIN (2^-149) is added because a denormal output cannot be closer
 * than that to the exact value. An exact 0 must be reproduced exactly where
 * the error is relative. */
static int close_enough(float got, long double want, long double scale, int relative)
{
    if (!isfinite(got))
        return 0;
    if (relative && want == 0.0L)
        return got == 0.0f;
    return fabsl((long double)got - want) <= 1e-6L * scale + (long double)FLT_TRUE_MIN;
}

static void report(ReferenceTally *tally, const EstimatorCase *c, int mode_index, size_t pixel, int channel,
                   const char *quantity, double got, long double want)
{
    if (tally->failures++ < DETAILED_FAILURES) {
        print_error("M = %d, case \"%s\", %s, pixel %zu, channel %d: %s = %.9g, reference %.12Lg\n", c->set_count,
                    c->name, mode_names[mode_index], pixel, channel, quantity, got, want);
        print_channel_sums(c, pixel, channel);
    }
}

static void check_pixel_against_reference(ReferenceTally *tally, const EstimatorCase *c, int mode_index,
                                          const Outputs *o, size_t p)
{
    LdPixel ref;
    ldref_pixel(c->sums, c->pixel_count, p, c->set_count, c->sample_count, modes[mode_index], &ref);
    const int m = ref.m;
    for (int ch = 0; ch < 3; ++ch) {
        size_t i = p * 3 + (size_t)ch;
        /* Mixed signs: the averages cancel, so a plain relative error means
         * nothing; measure the error against the largest |t_j| instead. */
        int relative = c->kind != CASE_MIXED_SIGNS;
        long double spread = fmaxl(fabsl(ref.lowest[ch]), fabsl(ref.highest[ch]));

        if (!close_enough(o->mean[i], ref.mean[ch], relative ? fabsl(ref.mean[ch]) : spread, relative))
            report(tally, c, mode_index, p, ch, "mean", o->mean[i], ref.mean[ch]);
        if (!close_enough(o->mon[i], ref.mon[ch], relative ? fabsl(ref.mon[ch]) : spread, relative))
            report(tally, c, mode_index, p, ch, "MoN", o->mon[i], ref.mon[ch]);
        if (!(fabsl((long double)o->gini[i] - ref.gini[ch]) <= 1e-5L))
            report(tally, c, mode_index, p, ch, "G", o->gini[i], ref.gini[ch]);

        /* c = floor(G * k) jumps where G * k is an integer: there a last-bit
         * difference in G may legitimately change c by one. Then G-MoN is
         * compared with the reference trimmed at the implementation's c. */
        int trim = o->trim[i];
        int counts_decision = modes[mode_index] == GINI_PER_CHANNEL || ch == 0;
        tally->trim_decisions += counts_decision;
        if (trim != ref.trim[ch]) {
            long double gk = ref.gini[ch] * (long double)(m / 2);
            int at_boundary = fabsl(gk - nearbyintl(gk)) <= 1e-4L && abs(trim - ref.trim[ch]) == 1 && trim >= 0 &&
                              trim <= (m - 1) / 2;
            if (!at_boundary) {
                report(tally, c, mode_index, p, ch, "trim c", trim, ref.trim[ch]);
                continue;
            }
            tally->boundary_cases += counts_decision;
        }
        long double want = trim == ref.trim[ch] ? ref.gmon[ch] : ldref_trimmed_mean(ref.ordered[ch], m, trim);
        if (!close_enough(o->gmon[i], want, relative ? fabsl(want) : spread, relative))
            report(tally, c, mode_index, p, ch, "G-MoN", o->gmon[i], want);
    }
}

static void test_matches_long_double_reference(void **state)
{
    (void)state;
    ReferenceTally tally = {0, 0, 0};
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s)
        for (int kind = 0; kind < CASE_COUNT; ++kind) {
            EstimatorCase c = estimator_case_make((EstimatorCaseKind)kind, set_counts[s], CASE_SEED);
            Outputs o;
            outputs_init(&o, c.pixel_count);
            for (int mode = 0; mode < MODE_CHOICES; ++mode) {
                estimate(c.set_count, modes[mode], c.sums, c.pixel_count, c.sample_count, &o);
                for (size_t p = 0; p < c.pixel_count; ++p)
                    check_pixel_against_reference(&tally, &c, mode, &o, p);
            }
            outputs_free(&o);
            estimator_case_free(&c);
        }
    printf("[ reference ] trim boundary cases (c off by one at an integer G*k): %d of %d trim decisions\n",
           tally.boundary_cases, tally.trim_decisions);
    if (tally.failures > 0)
        print_error("%d values differ from the long-double reference\n", tally.failures);
    assert_int_equal(tally.failures, 0);
}

/* ------------------------------------------------------------------------
 * Properties.
 * ---------------------------------------------------------------------- */

/* The float interval [t_1, t_m] rounded outward: a float output cannot do
 * better when t_1 or t_m is not a float. */
static float float_at_or_below(long double x)
{
    float f = (float)x;
    return (long double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float float_at_or_above(long double x)
{
    float f = (float)x;
    return (long double)f < x ? nextafterf(f, INFINITY) : f;
}

static void test_outputs_finite_and_within_set_means(void **state)
{
    (void)state;
    int failures = 0;
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s)
        for (int kind = 0; kind < CASE_COUNT; ++kind) {
            EstimatorCase c = estimator_case_make((EstimatorCaseKind)kind, set_counts[s], CASE_SEED);
            Outputs o;
            outputs_init(&o, c.pixel_count);
            for (int mode = 0; mode < MODE_CHOICES; ++mode) {
                estimate(c.set_count, modes[mode], c.sums, c.pixel_count, c.sample_count, &o);
                for (size_t p = 0; p < c.pixel_count; ++p) {
                    LdPixel ref;
                    ldref_pixel(c.sums, c.pixel_count, p, c.set_count, c.sample_count, modes[mode], &ref);
                    for (int ch = 0; ch < 3; ++ch) {
                        size_t i = p * 3 + (size_t)ch;
                        float lo = float_at_or_below(ref.lowest[ch]), hi = float_at_or_above(ref.highest[ch]);
                        const float values[3] = {o.mean[i], o.mon[i], o.gmon[i]};
                        static const char *const names[3] = {"mean", "MoN", "G-MoN"};
                        for (int v = 0; v < 3; ++v) {
                            if (isfinite(values[v]) && values[v] >= lo && values[v] <= hi)
                                continue;
                            if (failures++ < DETAILED_FAILURES) {
                                print_error("M = %d, case \"%s\", %s, pixel %zu, channel %d: %s = %a outside "
                                            "[t_1, t_m] = [%a, %a]\n",
                                            c.set_count, c.name, mode_names[mode], p, ch, names[v], (double)values[v],
                                            (double)lo, (double)hi);
                                print_channel_sums(&c, p, ch);
                            }
                        }
                    }
                }
            }
            outputs_free(&o);
            estimator_case_free(&c);
        }
    assert_int_equal(failures, 0);
}

/* All set means equal to `value` in every channel: G = 0 exactly and every
 * estimate is that value, bit for bit. */
static int check_all_equal(int set_count, GiniMode mode, const float *sums, size_t pixel_count, uint64_t sample_count,
                           const float *value, const char *what)
{
    Outputs o;
    outputs_init(&o, pixel_count);
    estimate(set_count, mode, sums, pixel_count, sample_count, &o);
    int failures = 0;
    for (size_t i = 0; i < pixel_count * 3; ++i) {
        if (same_bits(o.mean[i], value[i]) && same_bits(o.mon[i], value[i]) && same_bits(o.gmon[i], value[i]) &&
            o.gini[i] == 0.0f && o.trim[i] == 0)
            continue;
        if (failures++ < DETAILED_FAILURES)
            print_error("M = %d, %s, %s, pixel %zu, channel %zu: value %a, mean %a, MoN %a, G-MoN %a, G %a, "
                        "c %d\n",
                        set_count, what, mode_names[mode], i / 3, i % 3, (double)value[i], (double)o.mean[i],
                        (double)o.mon[i], (double)o.gmon[i], (double)o.gini[i], (int)o.trim[i]);
    }
    outputs_free(&o);
    return failures;
}

/* Sums S_j = n_j * value for every set; the values must make that exact. */
static float *equal_means_sums(int set_count, size_t pixel_count, uint64_t sample_count, const float *value)
{
    float *sums = malloc((size_t)set_count * 3 * pixel_count * sizeof(float));
    assert_non_null(sums);
    for (int j = 0; j < set_count; ++j)
        for (int ch = 0; ch < 3; ++ch)
            for (size_t p = 0; p < pixel_count; ++p) {
                long double s = (long double)value[p * 3 + (size_t)ch] *
                                (long double)estimator_case_set_samples(sample_count, set_count, j);
                sums[plane_index(j, ch, p, pixel_count)] = (float)s;
                assert_true((long double)(float)s == s);
            }
    return sums;
}

static void test_all_equal_means_give_that_value_exactly(void **state)
{
    (void)state;
    /* One sample per set, so a set mean is its sum: any float works. */
    static const float any_value[] = {FLT_MAX, -FLT_MAX, 0.1f,    -3.75f, 1e-30f, 5 * FLT_TRUE_MIN,
                                      FLT_MIN, 3e38f,    -7e-42f, 0.0f,   1.0f};
    /* Unequal counts (n = 3M + 1): dyadic values keep n_j * value exact. */
    static const float dyadic_value[] = {0.375f, -1.5f, 1024.0f, 0x1p-130f, -0x1p-100f, 0x1.8p100f, 0.0f};
    const size_t any_count = sizeof any_value / sizeof any_value[0];
    const size_t dyadic_count = sizeof dyadic_value / sizeof dyadic_value[0];
    int failures = 0;
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s) {
        const int m = set_counts[s];
        for (int mode = 0; mode < MODE_CHOICES; ++mode) {
            /* The shared cases: equal means (and equal counts), and zeros. */
            const EstimatorCaseKind kinds[2] = {CASE_ALL_EQUAL, CASE_ZEROS};
            for (int k = 0; k < 2; ++k) {
                EstimatorCase c = estimator_case_make(kinds[k], m, CASE_SEED);
                float *value = malloc(c.pixel_count * 3 * sizeof(float));
                assert_non_null(value);
                float n_0 = (float)estimator_case_set_samples(c.sample_count, m, 0);
                for (size_t p = 0; p < c.pixel_count; ++p)
                    for (int ch = 0; ch < 3; ++ch)
                        value[p * 3 + (size_t)ch] = c.sums[plane_index(0, ch, p, c.pixel_count)] / n_0;
                failures += check_all_equal(m, modes[mode], c.sums, c.pixel_count, c.sample_count, value, c.name);
                free(value);
                estimator_case_free(&c);
            }
            /* Hand-picked values, one per pixel, rotated across channels. */
            const struct {
                const float *values;
                size_t count;
                uint64_t sample_count;
                const char *what;
            } groups[2] = {{any_value, any_count, (uint64_t)m, "equal extreme means"},
                           {dyadic_value, dyadic_count, (uint64_t)m * 3 + 1, "equal means, unequal counts"}};
            for (int g = 0; g < 2; ++g) {
                float value[32 * 3];
                for (size_t p = 0; p < groups[g].count; ++p)
                    for (size_t ch = 0; ch < 3; ++ch)
                        value[p * 3 + ch] = groups[g].values[(p + ch) % groups[g].count];
                float *sums = equal_means_sums(m, groups[g].count, groups[g].sample_count, value);
                failures += check_all_equal(m, modes[mode], sums, groups[g].count, groups[g].sample_count, value,
                                            groups[g].what);
                free(sums);
            }
        }
    }
    assert_int_equal(failures, 0);
}

/* Reorders whole set planes: set j moves to permutation[j]. */
static void permute_sets(const float *sums, float *out, const int *permutation, int set_count, size_t pixel_count)
{
    size_t plane = 3 * pixel_count;
    for (int j = 0; j < set_count; ++j)
        memcpy(out + (size_t)permutation[j] * plane, sums + (size_t)j * plane, plane * sizeof(float));
}

static void test_invariant_under_set_permutation(void **state)
{
    (void)state;
    TestRng rng = test_rng(77);
    int failures = 0;
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s)
        for (int kind = 0; kind < CASE_COUNT; ++kind) {
            EstimatorCase c = estimator_case_make((EstimatorCaseKind)kind, set_counts[s], CASE_SEED);
            const int m = c.set_count;
            /* A multiple of M: every set has the same count, so any set may
             * take any other's place. */
            const uint64_t n = (uint64_t)m * 16;
            float *permuted = malloc((size_t)m * 3 * c.pixel_count * sizeof(float));
            assert_non_null(permuted);
            Outputs original, moved;
            outputs_init(&original, c.pixel_count);
            outputs_init(&moved, c.pixel_count);
            for (int mode = 0; mode < MODE_CHOICES; ++mode) {
                estimate(m, modes[mode], c.sums, c.pixel_count, n, &original);
                for (int trial = 0; trial < 3; ++trial) {
                    int permutation[EST_MAX_SETS];
                    for (int j = 0; j < m; ++j)
                        permutation[j] = trial == 0 ? m - 1 - j : j; /* first: reversed */
                    for (int j = m - 1; trial > 0 && j > 0; --j) {   /* then Fisher-Yates */
                        int r = (int)(test_rng_next(&rng) % (uint64_t)(j + 1));
                        int t = permutation[j];
                        permutation[j] = permutation[r];
                        permutation[r] = t;
                    }
                    permute_sets(c.sums, permuted, permutation, m, c.pixel_count);
                    estimate(m, modes[mode], permuted, c.pixel_count, n, &moved);
                    if (!outputs_identical(&original, &moved, c.pixel_count) && failures++ < DETAILED_FAILURES)
                        print_error("M = %d, case \"%s\", %s: outputs change when sets are permuted\n", m, c.name,
                                    mode_names[mode]);
                }
            }
            outputs_free(&original);
            outputs_free(&moved);
            free(permuted);
            estimator_case_free(&c);
        }
    assert_int_equal(failures, 0);
}

/* Zero or normal: scaling such a float by 2^k is exact if the result is. */
static int zero_or_normal(float x)
{
    return x == 0.0f || (isfinite(x) && fabsf(x) >= FLT_MIN);
}

static void test_power_of_two_scaling_is_exact(void **state)
{
    (void)state;
    /* The cases whose values stay in the normal range at every scale. */
    static const EstimatorCaseKind kinds[] = {CASE_RANDOM,
                                              CASE_ZEROS,
                                              CASE_ALL_EQUAL,
                                              CASE_ONE_OUTLIER,
                                              CASE_NEGATIVE,
                                              CASE_MIXED_SIGNS,
                                              CASE_FEWER_SAMPLES_THAN_SETS};
    static const int exponents[] = {-20, -3, 5, 40};
    int failures = 0;
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s)
        for (size_t kk = 0; kk < sizeof kinds / sizeof kinds[0]; ++kk) {
            EstimatorCase c = estimator_case_make(kinds[kk], set_counts[s], CASE_SEED);
            const size_t values = (size_t)c.set_count * 3 * c.pixel_count;
            float *scaled = malloc(values * sizeof(float));
            assert_non_null(scaled);
            Outputs base, out;
            outputs_init(&base, c.pixel_count);
            outputs_init(&out, c.pixel_count);
            for (int mode = 0; mode < MODE_CHOICES; ++mode) {
                estimate(c.set_count, modes[mode], c.sums, c.pixel_count, c.sample_count, &base);
                for (size_t e = 0; e < sizeof exponents / sizeof exponents[0]; ++e) {
                    const int k = exponents[e];
                    for (size_t i = 0; i < values; ++i) {
                        scaled[i] = ldexpf(c.sums[i], k);
                        assert_true(zero_or_normal(c.sums[i]) && zero_or_normal(scaled[i]));
                    }
                    estimate(c.set_count, modes[mode], scaled, c.pixel_count, c.sample_count, &out);
                    for (size_t i = 0; i < c.pixel_count * 3; ++i) {
                        const float before[3] = {base.mean[i], base.mon[i], base.gmon[i]};
                        const float after[3] = {out.mean[i], out.mon[i], out.gmon[i]};
                        int ok = same_bits(base.gini[i], out.gini[i]) && base.trim[i] == out.trim[i];
                        for (int v = 0; v < 3; ++v) {
                            assert_true(zero_or_normal(ldexpf(before[v], k))); /* else not exact */
                            ok = ok && same_bits(after[v], ldexpf(before[v], k));
                        }
                        if (!ok && failures++ < DETAILED_FAILURES)
                            print_error("M = %d, case \"%s\", %s, k = %d, pixel %zu, channel %zu: mean %a -> %a, "
                                        "MoN %a -> %a, G-MoN %a -> %a, G %a -> %a\n",
                                        c.set_count, c.name, mode_names[mode], k, i / 3, i % 3, (double)before[0],
                                        (double)after[0], (double)before[1], (double)after[1], (double)before[2],
                                        (double)after[2], (double)base.gini[i], (double)out.gini[i]);
                    }
                }
            }
            outputs_free(&base);
            outputs_free(&out);
            free(scaled);
            estimator_case_free(&c);
        }
    assert_int_equal(failures, 0);
}

/* One outlier among equal means: G-MoN lies between the median and the
 * mean. Mirrored (all sums negated) the outlier is low and the order flips. */
static void test_one_outlier_between_median_and_mean(void **state)
{
    (void)state;
    int failures = 0;
    for (size_t s = 0; s < SET_COUNT_CHOICES; ++s) {
        EstimatorCase c = estimator_case_make(CASE_ONE_OUTLIER, set_counts[s], CASE_SEED);
        const size_t values = (size_t)c.set_count * 3 * c.pixel_count;
        float *negated = malloc(values * sizeof(float));
        assert_non_null(negated);
        for (size_t i = 0; i < values; ++i)
            negated[i] = -c.sums[i];
        Outputs o;
        outputs_init(&o, c.pixel_count);
        for (int mirrored = 0; mirrored < 2; ++mirrored)
            for (int mode = 0; mode < MODE_CHOICES; ++mode) {
                estimate(c.set_count, modes[mode], mirrored ? negated : c.sums, c.pixel_count, c.sample_count, &o);
                for (size_t i = 0; i < c.pixel_count * 3; ++i) {
                    int ok = mirrored ? o.mean[i] <= o.gmon[i] && o.gmon[i] <= o.mon[i]
                                      : o.mon[i] <= o.gmon[i] && o.gmon[i] <= o.mean[i];
                    if (!ok && failures++ < DETAILED_FAILURES)
                        print_error("M = %d, %s, %s outlier, pixel %zu, channel %zu: MoN %a, G-MoN %a, mean %a\n",
                                    c.set_count, mode_names[mode], mirrored ? "low" : "high", i / 3, i % 3,
                                    (double)o.mon[i], (double)o.gmon[i], (double)o.mean[i]);
                }
            }
        outputs_free(&o);
        free(negated);
        estimator_case_free(&c);
    }
    assert_int_equal(failures, 0);
}

/* ------------------------------------------------------------------------
 * Accumulation: exact fixed-point sums, rounded once to float.
 * ---------------------------------------------------------------------- */

/* A random float k * 2^(e - 24) with a 24-bit k and e in [lowest, highest],
 * either sign: dyadic, so long double sums of a few hundred are exact as
 * long as highest - lowest + 24 + log2(count) <= 64. */
static float dyadic_sample(TestRng *rng, int lowest, int highest)
{
    uint64_t r = test_rng_next(rng);
    float k = (float)(r >> 40);
    int e = lowest + (int)((r >> 8) % (uint64_t)(highest - lowest + 1));
    return (r & 1) ? -ldexpf(k, e - 24) : ldexpf(k, e - 24);
}

/* Accumulates random dyadic samples (and some non-finite ones, which must be
 * rejected and add nothing) with the shared code; the float set sums must
 * be the correctly rounded exact sums, and estimating from accumulators must
 * equal estimating from those sums. */
static void check_accumulation(int set_count, size_t pixel_count, uint64_t sample_count, int lowest, int highest,
                               uint64_t seed)
{
    const size_t values = (size_t)set_count * 3 * pixel_count;
    const size_t words = accumulator_planes((uint32_t)set_count) * pixel_count;
    uint64_t *accumulators = calloc(words, sizeof(uint64_t));
    long double *exact = calloc(values, sizeof(long double));
    float *sums = malloc(values * sizeof(float));
    assert_true(accumulators && exact && sums);
    static const float unusable[] = {NAN, INFINITY, -INFINITY};
    TestRng rng = test_rng(seed);
    for (size_t p = 0; p < pixel_count; ++p)
        for (uint64_t s = 0; s < sample_count; ++s) {
            const int set = (int)(s % (uint64_t)set_count);
            float rgb[3];
            for (int ch = 0; ch < 3; ++ch)
                rgb[ch] = dyadic_sample(&rng, lowest, highest);
            if (test_rng_next(&rng) % 32 == 0) {
                /* One bad channel rejects the whole sample. */
                rgb[test_rng_next(&rng) % 3] = unusable[test_rng_next(&rng) % 3];
                assert_int_equal(accumulate_sample(accumulators, p, pixel_count, (uint32_t)set_count, (uint32_t)set,
                                                   rgb[0], rgb[1], rgb[2]),
                                 EST_ADD_NONFINITE);
                continue;
            }
            assert_int_equal(accumulate_sample(accumulators, p, pixel_count, (uint32_t)set_count, (uint32_t)set, rgb[0],
                                               rgb[1], rgb[2]),
                             EST_ADD_EXACT);
            for (int ch = 0; ch < 3; ++ch)
                exact[plane_index(set, ch, p, pixel_count)] += rgb[ch];
        }

    char message[256] = "";
    assert_int_equal(estimator_sums_from_accumulators(set_count, accumulators, words, pixel_count, sums, values,
                                                      message, sizeof message),
                     ESTIMATOR_OK);
    int failures = 0;
    for (size_t i = 0; i < values; ++i) {
        /* The long double sum is exact, so one conversion rounds it once. */
        float want = (float)exact[i];
        if (!same_bits(sums[i], want) && failures++ < DETAILED_FAILURES)
            print_error("M = %d, exponents %d..%d, value %zu: float sum %a, exact %La rounds to %a\n", set_count,
                        lowest, highest, i, (double)sums[i], exact[i], (double)want);
    }
    assert_int_equal(failures, 0);

    Outputs from_sums, from_accumulators;
    outputs_init(&from_sums, pixel_count);
    outputs_init(&from_accumulators, pixel_count);
    for (int mode = 0; mode < MODE_CHOICES; ++mode) {
        EstimatorSettings settings = default_passes(set_count, modes[mode]);
        estimate(set_count, modes[mode], sums, pixel_count, sample_count, &from_sums);
        assert_int_equal(estimator_from_accumulators(&settings, accumulators, words, pixel_count, sample_count,
                                                     &from_accumulators.images, message, sizeof message),
                         ESTIMATOR_OK);
        assert_true(outputs_identical(&from_sums, &from_accumulators, pixel_count));
    }
    outputs_free(&from_sums);
    outputs_free(&from_accumulators);
    free(accumulators);
    free(exact);
    free(sums);
}

static void test_accumulated_sums_are_correctly_rounded(void **state)
{
    (void)state;
    check_accumulation(7, 5, 1000, -16, 8, 11);    /* ordinary magnitudes */
    check_accumulation(21, 3, 2000, 20, 60, 12);   /* far above the old 2^38 limit */
    check_accumulation(21, 3, 2000, 100, 110, 16); /* near FLT_MAX (sums stay finite) */
    check_accumulation(3, 4, 600, -140, -110, 13); /* far below the old 2^-56 grid, into denormals */
    check_accumulation(5, 3, 1000, -20, 30, 17);   /* 50 binary orders in one pixel */
    check_accumulation(1, 2, 300, -10, 10, 14);    /* M = 1 */
    check_accumulation(64, 2, 3000, -5, 5, 15);    /* M = 64 */
}

/* Exact sums that fall on or near a rounding tie of the float result. */
static void test_accumulated_sums_round_ties_to_even(void **state)
{
    (void)state;
    static const struct {
        float samples[3];
        float expected;
    } cases[] = {
        {{1.0f, 0x1p-24f, 0.0f}, 1.0f},                       /* tie, even below */
        {{1.0f, 0x1p-23f, 0x1p-24f}, 1.0f + 0x1p-22f},        /* tie, even above */
        {{1.0f, 0x1p-24f, 0x1p-56f}, 1.0f + 0x1p-23f},        /* just above a tie */
        {{1.0f, 0x1p-24f, -0x1p-56f}, 1.0f},                  /* just below a tie */
        {{-1.0f, -0x1p-24f, 0.0f}, -1.0f},                    /* negative tie */
        {{-1.0f, -0x1p-23f, -0x1p-24f}, -1.0f - 0x1p-22f},    /* negative tie, up */
        {{0x1.fffffep37f, 0x1.fffffep37f, 0x1p14f}, 0x1p39f}, /* tie, carry into the exponent */
        {{0x1p-56f, -0x1p-56f, 0.0f}, 0.0f},                  /* cancels exactly */
    };
    const size_t count = sizeof cases / sizeof cases[0];
    /* One pixel per case, M = 1, the case's samples in channel 0. */
    const size_t words = accumulator_planes(1) * count;
    uint64_t *accumulators = calloc(words, sizeof(uint64_t));
    float *sums = malloc(3 * count * sizeof(float));
    assert_true(accumulators && sums);
    for (size_t p = 0; p < count; ++p)
        for (int s = 0; s < 3; ++s)
            assert_int_equal(accumulate_sample(accumulators, p, count, 1, 0, cases[p].samples[s], 0.0f, 0.0f),
                             EST_ADD_EXACT);
    assert_int_equal(estimator_sums_from_accumulators(1, accumulators, words, count, sums, 3 * count, NULL, 0),
                     ESTIMATOR_OK);
    for (size_t p = 0; p < count; ++p) {
        if (!same_bits(sums[p], cases[p].expected))
            print_error("case %zu: sum %a, expected %a\n", p, (double)sums[p], (double)cases[p].expected);
        assert_true(same_bits(sums[p], cases[p].expected));
    }
    free(accumulators);
    free(sums);
}

/* The fixed-point value on the grid 2^-56 as a long double: exact, since
 * it comes from one float (24 significant bits). */
#define GRID (-56)
static long double fixed_value(FixedSum v)
{
    int negative = (int)(v.hi >> 63);
    if (negative) {
        v.lo = ~v.lo + 1;
        v.hi = ~v.hi + (v.lo == 0 ? 1 : 0);
    }
    long double units = ldexpl((long double)v.hi, 64) + (long double)v.lo;
    return ldexpl(negative ? -units : units, GRID);
}

/* A random float with |x| in [2^lowest, 2^(highest + 1)), either sign. */
static float random_float(TestRng *rng, int lowest, int highest)
{
    uint64_t r = test_rng_next(rng);
    float significand = 1.0f + ldexpf((float)(r & 0x7fffff), -23);
    int e = lowest + (int)((r >> 23) % (uint64_t)(highest - lowest + 1));
    float x = ldexpf(significand, e);
    return (r >> 63) ? -x : x;
}

static void test_fixed_point_round_trip_is_exact_on_the_grid(void **state)
{
    (void)state;
    /* 2^-30 <= |x| < 2^38: x's lowest bit is at least 2^-53, on the 2^-56
     * grid, so the conversion both ways must be exact. */
    TestRng rng = test_rng(2718);
    int failures = 0;
    for (int i = 0; i < 1000000; ++i) {
        float x = random_float(&rng, -30, 37);
        if (i < 4) /* the ends of the range */
            x = (float[]){0x1p-30f, -0x1p-30f, 0x1.fffffep37f, -0x1.fffffep37f}[i];
        int inexact = 0;
        FixedSum v = fixed_from_float(x, GRID, &inexact);
        float back = ldexpf(fixed_to_float(v), GRID);
        if ((!same_bits(back, x) || fixed_value(v) != (long double)x || inexact) && failures++ < DETAILED_FAILURES)
            print_error("x = %a: fixed %La, back %a\n", (double)x, fixed_value(v), (double)back);
    }
    assert_int_equal(failures, 0);
    int inexact = 0;
    assert_true(same_bits(fixed_to_float(fixed_from_float(0.0f, GRID, &inexact)), 0.0f));
    assert_false(inexact);
}

/* Below the grid a value rounds to the nearest multiple of 2^-56, ties away
 * from zero; that multiple then converts back exactly. */
static void test_fixed_point_rounds_values_below_the_grid(void **state)
{
    (void)state;
    static const struct {
        float x;
        float expected;
    } cases[] = {
        {0x1p-57f, 0x1p-56f}, /* half a unit: away from zero */
        {-0x1p-57f, -0x1p-56f},
        {0x1p-58f, 0.0f},            /* a quarter: down */
        {0x1.8p-57f, 0x1p-56f},      /* 0.75 units */
        {0x1.8p-56f, 0x1p-55f},      /* 1.5 units: tie, away */
        {0x1.4p-56f, 0x1p-56f},      /* 1.25 units */
        {0x1.000002p-40f, 0x1p-40f}, /* bits below 2^-56 dropped */
        {FLT_TRUE_MIN, 0.0f},        /* denormals vanish */
        {-FLT_MIN, 0.0f},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        int inexact = 0;
        float got = ldexpf(fixed_to_float(fixed_from_float(cases[i].x, GRID, &inexact)), GRID);
        assert_true(inexact); /* every case loses bits */
        if (got != cases[i].expected)
            print_error("x = %a: got %a, expected %a\n", (double)cases[i].x, (double)got, (double)cases[i].expected);
        assert_true(got == cases[i].expected);
    }
    /* Random values from the denormals up to the grid, against roundl
     * (which rounds halfway cases away from zero too). */
    TestRng rng = test_rng(3141);
    int failures = 0;
    for (int i = 0; i < 1000000; ++i) {
        float x = random_float(&rng, -149, -30);
        long double want = ldexpl(roundl(ldexpl((long double)x, -GRID)), GRID);
        int inexact = 0;
        FixedSum v = fixed_from_float(x, GRID, &inexact);
        if ((fixed_value(v) != want || ldexpf(fixed_to_float(v), GRID) != (float)want ||
             inexact != (want != (long double)x)) &&
            failures++ < DETAILED_FAILURES)
            print_error("x = %a: fixed %La, expected %La\n", (double)x, fixed_value(v), want);
    }
    assert_int_equal(failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_long_double_reference),
        cmocka_unit_test(test_outputs_finite_and_within_set_means),
        cmocka_unit_test(test_all_equal_means_give_that_value_exactly),
        cmocka_unit_test(test_invariant_under_set_permutation),
        cmocka_unit_test(test_power_of_two_scaling_is_exact),
        cmocka_unit_test(test_one_outlier_between_median_and_mean),
        cmocka_unit_test(test_accumulated_sums_are_correctly_rounded),
        cmocka_unit_test(test_accumulated_sums_round_ties_to_even),
        cmocka_unit_test(test_fixed_point_round_trip_is_exact_on_the_grid),
        cmocka_unit_test(test_fixed_point_rounds_values_below_the_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
