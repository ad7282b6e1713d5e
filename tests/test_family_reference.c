/* The long-double reference of the estimator family and its stderr
 * (tests/support/family_reference.c) on hand-computed cases and on the
 * properties docs/estimators.md lists, so that it can judge the float
 * implementation.
 *
 * In the comments t_1 <= ... <= t_m are a channel's set means, k = m / 2.
 * Unless a case says otherwise every channel holds the same set means times
 * 1, 2 and 0.5 (powers of two: the sums stay exact, every channel has the
 * same Gini, and an estimate of channel c is its channel-0 value times the
 * scale). The values that need a logarithm were computed with mpmath at 30
 * digits from the formulas written beside them. */
#include "family_reference.h"
#include "passes.h"
#include "sample_streams.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

/* Every set-based estimator, from the rows of kernels/film/passes.h (NULL for
 * the other rows), so that a new row is checked here too. */
#define ESTIMATE_NAME_(id, name, type, kind, form, fn) (kind) == PASS_ESTIMATE ? name : NULL,
static const char *const all_names[] = {GMON_PASSES(ESTIMATE_NAME_)};
#define NAME_COUNT (sizeof all_names / sizeof all_names[0])

static const double channel_scale[REF_CHANNELS] = {1.0, 2.0, 0.5};

/* Exact long-double arithmetic differs from the hand values only by rounding. */
#define HAND_TOLERANCE 1e-15L

/* Set j's count under round robin: ceil((n - j) / M), 0 when n <= j. */
static uint64_t set_samples(uint64_t n, int set_count, int j)
{
    return n <= (uint64_t)j ? 0 : (n - (uint64_t)j + (uint64_t)set_count - 1) / (uint64_t)set_count;
}

/* Sums from set means in set order, channel c scaled by channel_scale[c].
 * Empty sets get a huge sum that must be ignored. */
static void scaled_sums(float sums[REF_CHANNELS][REF_MAX_SETS], int set_count, uint64_t n, const double *means)
{
    for (int c = 0; c < REF_CHANNELS; ++c)
        for (int j = 0; j < REF_MAX_SETS; ++j) {
            uint64_t n_j = j < set_count ? set_samples(n, set_count, j) : 0;
            sums[c][j] = n_j > 0 ? (float)(means[j] * channel_scale[c] * (double)n_j) : 1e30f;
        }
}

static void assert_near(long double actual, long double expected, long double tolerance, const char *what, int c)
{
    if (!(fabsl(actual - expected) <= tolerance * fabsl(expected)))
        fail_msg("%s, channel %d: %.21Lg, expected %.21Lg", what, c, actual, expected);
}

typedef struct {
    const char *name;
    long double expected; /* channel 0; channel c is this times channel_scale[c] */
} Expectation;

static void check_scaled(const RefFamilyParams *p, int set_count, uint64_t n, const double *means,
                         const Expectation *expectations, size_t count)
{
    float sums[REF_CHANNELS][REF_MAX_SETS];
    scaled_sums(sums, set_count, n, means);
    for (size_t i = 0; i < count; ++i) {
        long double out[REF_CHANNELS];
        assert_int_equal(ref_family_estimate(expectations[i].name, p, sums, n, set_count, out), 0);
        for (int c = 0; c < REF_CHANNELS; ++c)
            assert_near(out[c], expectations[i].expected * (long double)channel_scale[c], HAND_TOLERANCE,
                        expectations[i].name, c);
    }
}

#define CHECK_SCALED(p, set_count, n, means, expectations)                                                             \
    check_scaled(p, set_count, n, means, expectations, sizeof expectations / sizeof expectations[0])

/* ------------------------------------------------------------------------
 * Hand-computed estimates.
 * ---------------------------------------------------------------------- */

/* m = 3, one sample per set, means 1, 2, 4 (in set order 4, 1, 2); k = 1.
 * G = (-2 * 1 + 0 * 2 + 2 * 4) / (3 * 7) = 2/7 in every channel: Gbar = 2/7. */
static const double means_124[] = {4, 1, 2};
static const Expectation expect_124[] = {
    {"mean", 7.0L / 3.0L},
    {"mon", 2.0L},
    {"gmon", 7.0L / 3.0L},       /* c = floor(2/7 * 1) = 0 */
    {"amon", 2.25L},             /* (0.5 * 1 + 2 + 0.5 * 4) / 2 */
    {"admon", 2.0L},             /* u = floor(1 * 0.5) = 0: the median */
    {"ggmon", 39.0L / 17.0L},    /* a = 5/7: (a * 1 + 2 + a * 4) / (1 + 2a) = (39/7) / (17/7) */
    {"gmon-binary", 2.0L},       /* Gbar = 0.29 >= 0.25: MoN */
    {"gmon-partial", 2.25L},     /* amon(0.5) */
    {"dmon-partial", 2.0L},      /* admon(0.5) */
    {"gmon-authors", 2.0L},      /* c = ceil(1 * 0.29) = 1 */
    {"pakmon", 2.0L},            /* m <= 3: H = 0, rho = 0: the median */
    {"trimmed", 7.0L / 3.0L},    /* c = floor(3 / 4) = 0 */
    {"winsorized", 7.0L / 3.0L}, /* c = 0 */
    {"gmedian", 2.0L},           /* collinear RGB means (t, 2t, t/2): the middle one */
    {"huber", 7.0L / 3.0L},      /* h = 1 (4 - 1) covers every distance: the mean */
};

static void test_three_sets(void **state)
{
    (void)state;
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 3, 3, means_124, expect_124);
}

/* The same pixel with M = 8 and n = 3: sets 3 .. 7 are empty (and hold 1e30). */
static void test_fewer_samples_than_sets(void **state)
{
    (void)state;
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 8, 3, means_124, expect_124);
}

/* m = 5, n = 10 (two samples per set), means 1, 1, 2, 2, 14 (set order 2, 14,
 * 1, 2, 1); k = 2. G = (-4 - 2 + 0 + 4 + 56) / (5 * 20) = 0.54 = Gbar. */
static void test_five_sets(void **state)
{
    (void)state;
    static const double means[] = {2, 14, 1, 2, 1};
    static const Expectation expect[] = {
        {"mean", 4.0L},
        {"mon", 2.0L},
        {"gmon", 5.0L / 3.0L},  /* c = floor(0.54 * 2) = 1: (1 + 2 + 2) / 3 */
        {"amon", 2.9L},         /* (0.25 * 1 + 0.5 * 1 + 2 + 0.5 * 2 + 0.25 * 14) / 2.5 = 7.25 / 2.5 */
        {"admon", 5.0L / 3.0L}, /* u = floor(2 * 0.5) = 1: (1 + 2 + 2) / 3 */
        /* a = 0.46: (a^2 (1 + 14) + a (1 + 2) + 2) / (1 + 2a + 2a^2) = 6.554 / 2.3432 */
        {"ggmon", 2.797029702970297029703L},
        {"gmon-binary", 2.0L},
        {"gmon-partial", 2.9L},
        {"dmon-partial", 5.0L / 3.0L},
        {"gmon-authors", 2.0L}, /* c = ceil(2 * 0.54) = 2 (gmon's floor gives 1) */
        /* sums 2, 2, 4, 4, 28, Sbar 8: squared deviations 36, 36, 16, 16, 400;
         * d_2 = 72/3 = 24, d_3 = 88/4 = 22, d_4 = 104/5 = 20.8; H = the entropy
         * of d^2 / sum d^2 over ln 3 = 0.99359660; rho = floor(2H) - floor(0.75)
         * = 1 (D = 2): (2 + H (1 + 2)) / (1 + 2H) */
        {"pakmon", 1.667381206232087676407L},
        {"trimmed", 5.0L / 3.0L}, /* c = floor(5 / 4) = 1 */
        {"winsorized", 1.6L},     /* 1, 1, 2, 2, 2 */
        {"gmedian", 2.0L},        /* collinear: the middle one */
        /* q = 1, h = 2 - 1 = 1: 14 weighs 1 / (14 - z); the steps from 2
         * (86/49, 4286/2449, ...) approach 7/4, where (6 + 14 w) / (4 + w) = z */
        {"huber", 1.75000000000000653333333333L},
    };
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 5, 10, means, expect);
}

/* m = 6 (even), one sample per set, means 1, 2, 3, 4, 6, 21 (set order 6, 1,
 * 21, 3, 2, 4); k = 3, middle pair 3, 4. G = (-5 - 6 - 3 + 4 + 18 + 105) /
 * (6 * 37) = 113/222 = 0.509 = Gbar. */
static void test_six_sets(void **state)
{
    (void)state;
    static const double means[] = {6, 1, 21, 3, 2, 4};
    static const Expectation expect[] = {
        {"mean", 37.0L / 6.0L},
        {"mon", 3.5L},
        {"gmon", 3.75L}, /* c = floor(0.509 * 3) = 1: (2 + 3 + 4 + 6) / 4 */
        {"amon", 5.2L},  /* (3.5 + 0.5 (2 + 6) + 0.25 (1 + 21)) / (1 + 1 + 0.5) = 13 / 2.5 */
        {"admon", 6.7L}, /* ((1 + 2 + 6 + 21) + 3.5) / 5 */
        /* a = 109/222: (3.5 + a (2 + 6) + a^2 (1 + 21)) / (1 + 2a + 2a^2) */
        {"ggmon", 5.166746265707086510433L},
        {"gmon-binary", 3.5L},
        {"gmon-partial", 5.2L},
        {"dmon-partial", 6.7L},         /* even m: alpha unused */
        {"gmon-authors", 37.0L / 6.0L}, /* even m: the mean of the set means */
        /* Sbar = 37/6; squared deviations (31^2, 25^2, 19^2, 13^2, 1, 89^2) / 36;
         * d_2 = 1586/108, d_3 = 1947/144, d_4 = 2116/180, d_5 = 2117/216;
         * H = entropy / ln 4 = 0.96953554; rho = floor(3H) - floor(0.9) = 2 = D:
         * (3.5 + H (2 + 6) + H^2 (1 + 21)) / (1 + 2H + 2H^2) */
        {"pakmon", 6.627060784932775556310L},
        {"trimmed", 3.75L},           /* c = floor(6 / 4) = 1 */
        {"winsorized", 23.0L / 6.0L}, /* 2, 2, 3, 4, 6, 6 */
        {"gmedian", 3.5L},            /* collinear, even: stays at the componentwise median */
        /* q = 1, h = 4 - 2 = 2; from 3.5, 1 and 21 weigh h / distance: the
         * steps approach 4 */
        {"huber", 3.99999999999191386934228975L},
    };
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 6, 6, means, expect);
}

/* m = 4, n = 9: counts 3, 2, 2, 2; means 1, 1, 2, 5, so sums 3, 2, 4, 10: the
 * sums are not in the order of the means (pakmon takes the means). */
static void test_unequal_counts(void **state)
{
    (void)state;
    static const double means[] = {1, 1, 2, 5};
    static const Expectation expect[] = {
        {"mean", 19.0L / 9.0L},
        {"mon", 1.5L},
        {"amon", 2.25L},   /* (1.5 + 0.5 (1 + 5)) / 2 */
        {"admon", 2.5L},   /* (1 + 5 + 1.5) / 3 */
        {"trimmed", 1.5L}, /* c = 1 */
        /* From the sorted means 1, 1, 2, 5 (mean 2.25), not the sums:
         * d_2 = (1.25^2 + 1.25^2) / 3, d_3 = (1.25^2 + 1.25^2 + 0.25^2) / 4;
         * H = entropy / ln 2 = 0.95003631; rho = floor(2H) - 0 = 1 = D:
         * (1.5 + H (1 + 5)) / (1 + 2H) */
        {"pakmon", 2.482771574459581740353L},
        /* of the means: q = 1, h = 2 - 1 = 1; from 1.5 the steps approach 5/3 */
        {"huber", 1.66666666592617876140735502L},
    };
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 4, 9, means, expect);
}

/* m = 7: floor(0.15 m) = 1 takes a distance off pakmon's rho. Means 1, 2, 3,
 * 4, 7, 8, 50; H = 0.98491907 (sums = means); rho = floor(3H) - 1 = 1:
 * (4 + H (3 + 7)) / (1 + 2H). */
static void test_pakmon_subtracts_fifteen_percent(void **state)
{
    (void)state;
    static const double means[] = {50, 1, 8, 2, 7, 3, 4};
    static const Expectation expect[] = {{"pakmon", 4.663281312563552259479L}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 7, 7, means, expect);
}

/* All sums equal: every deviation from Sbar is 0, so sum d^2 = 0, H = 0 and
 * rho = 0: pakmon is the median. */
static void test_pakmon_equal_sums_is_the_median(void **state)
{
    (void)state;
    static const double means[] = {3, 3, 3, 3, 3};
    static const Expectation expect[] = {{"pakmon", 3.0L}, {"mon", 3.0L}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 5, 5, means, expect);
}

/* m = 2, n = 3: counts 2, 1; channels differ: means R 1, 5; G 3, 1; B 0, 0.
 * The mean weighs by counts (R (2 + 5) / 3, G (6 + 1) / 3); every other
 * estimator is the mean of the two set means. */
static void test_two_sets(void **state)
{
    (void)state;
    float sums[REF_CHANNELS][REF_MAX_SETS] = {{2, 5}, {6, 1}, {0, 0}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (size_t i = 0; i < NAME_COUNT; ++i) {
        if (!all_names[i])
            continue;
        long double out[REF_CHANNELS];
        int mean = strcmp(all_names[i], "mean") == 0;
        long double expected[REF_CHANNELS] = {mean ? 7.0L / 3.0L : 3.0L, mean ? 7.0L / 3.0L : 2.0L, 0.0L};
        assert_int_equal(ref_family_estimate(all_names[i], &p, sums, 3, 2, out), 0);
        for (int c = 0; c < REF_CHANNELS; ++c)
            if (!(fabsl(out[c] - expected[c]) <= HAND_TOLERANCE))
                fail_msg("%s, channel %d: %.21Lg, expected %.21Lg", all_names[i], c, out[c], expected[c]);
    }
}

/* m = 1: every estimator is the one set's mean, exactly; also with M = 4
 * and n = 1 (sets 1..3 empty). n = 0: 0. */
static void test_one_set_and_none(void **state)
{
    (void)state;
    float one_set[REF_CHANNELS][REF_MAX_SETS] = {{10, 1e30f}, {0, 1e30f}, {-5, 1e30f}};
    float first_of_four[REF_CHANNELS][REF_MAX_SETS] = {{3, 7, 7, 7}, {-2, 7, 7, 7}, {0.5f, 7, 7, 7}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (size_t i = 0; i < NAME_COUNT; ++i) {
        if (!all_names[i])
            continue;
        long double out[REF_CHANNELS];
        assert_int_equal(ref_family_estimate(all_names[i], &p, one_set, 5, 1, out), 0);
        assert_true(out[0] == 2.0L && out[1] == 0.0L && out[2] == -1.0L);
        assert_int_equal(ref_family_estimate(all_names[i], &p, first_of_four, 1, 4, out), 0);
        assert_true(out[0] == 3.0L && out[1] == -2.0L && out[2] == 0.5L);
        assert_int_equal(ref_family_estimate(all_names[i], &p, first_of_four, 0, 4, out), 0);
        assert_true(out[0] == 0.0L && out[1] == 0.0L && out[2] == 0.0L);
    }
}

static void test_unknown_name_and_bad_set_count(void **state)
{
    (void)state;
    float sums[REF_CHANNELS][REF_MAX_SETS] = {{1, 2}, {1, 2}, {1, 2}};
    long double out[REF_CHANNELS];
    RefFamilyParams p;
    ref_family_params_default(&p);
    assert_int_equal(ref_family_estimate("median", &p, sums, 2, 2, out), -1);
    assert_int_equal(ref_family_stderr("median", &p, sums, 2, 2, out), -1);
    assert_int_equal(ref_family_jackknife("median", &p, sums, 2, 2, out), -1);
    assert_int_equal(ref_family_estimate("mon", &p, sums, 2, 0, out), -1);
    assert_int_equal(ref_family_estimate("mon", &p, sums, 2, REF_MAX_SETS + 1, out), -1);
}

/* Parameters are read: trimmed/winsorized c (clamped to floor((m - 1) / 2)),
 * amon/admon alpha, on means 1, 1, 2, 2, 14 (m = 5, k = 2). */
static void test_parameters(void **state)
{
    (void)state;
    static const double means[] = {2, 14, 1, 2, 1};
    RefFamilyParams p;
    ref_family_params_default(&p);
    p.trimmed_c = 9;      /* clamped to 2: the median */
    p.winsorized_c = 2;   /* 2, 2, 2, 2, 2 */
    p.amon_alpha = 1.0L;  /* the mean of the set means */
    p.admon_alpha = 1.0L; /* u = 2: every set */
    static const Expectation expect[] = {{"trimmed", 2.0L}, {"winsorized", 2.0L}, {"amon", 4.0L}, {"admon", 4.0L}};
    CHECK_SCALED(&p, 5, 5, means, expect);
}

/* ------------------------------------------------------------------------
 * The threshold switches, the authors' G-MoN.
 * ---------------------------------------------------------------------- */

/* Means 1, 3, 4 (m = 3): G = (-2 * 1 + 2 * 4) / (3 * 8) = 0.25 exactly in each
 * channel, so Gbar = 0.25: not below, the second branch. Lowering channel B's
 * top mean to 4 - 2^-20 gives G_B = (6 - 2e) / (24 - 3e) < 0.25, Gbar just
 * below (by 5e / 288 = 1.7e-8): the first branch. */
static void test_thresholds_switch_at_a_quarter(void **state)
{
    (void)state;
    float at[REF_CHANNELS][REF_MAX_SETS] = {{1, 3, 4}, {1, 3, 4}, {1, 3, 4}};
    float below[REF_CHANNELS][REF_MAX_SETS] = {{1, 3, 4}, {1, 3, 4}, {1, 3, 4.0f - 0x1p-20f}};
    static const struct {
        const char *name;
        long double at, below; /* channel R */
    } cases[] = {
        {"gmon-binary", 3.0L, 8.0L / 3.0L},   /* MoN | the mean of the set means */
        {"gmon-partial", 2.75L, 8.0L / 3.0L}, /* amon(0.5) = (0.5 + 3 + 2) / 2 | amon(1) */
        {"dmon-partial", 3.0L, 8.0L / 3.0L},  /* admon(0.5): u = 0 | admon(1): u = 1 */
    };
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        long double out[REF_CHANNELS];
        assert_int_equal(ref_family_estimate(cases[i].name, &p, at, 3, 3, out), 0);
        assert_near(out[0], cases[i].at, HAND_TOLERANCE, cases[i].name, 0);
        assert_int_equal(ref_family_estimate(cases[i].name, &p, below, 3, 3, out), 0);
        assert_near(out[0], cases[i].below, HAND_TOLERANCE, cases[i].name, 0);
    }
    /* A threshold of 0.2 puts "below" above it; 0.3 puts "at" below. */
    long double out[REF_CHANNELS];
    p.gmon_binary_threshold = 0.2L;
    assert_int_equal(ref_family_estimate("gmon-binary", &p, below, 3, 3, out), 0);
    assert_true(out[0] == 3.0L);
    p.gmon_binary_threshold = 0.3L;
    assert_int_equal(ref_family_estimate("gmon-binary", &p, at, 3, 3, out), 0);
    assert_near(out[0], 8.0L / 3.0L, HAND_TOLERANCE, "gmon-binary", 0);
    /* The alpha above the threshold is a parameter: amon(0) and admon(0) are MoN. */
    p.gmon_partial_alpha = 0.0L;
    p.dmon_partial_alpha = 0.0L;
    assert_int_equal(ref_family_estimate("gmon-partial", &p, at, 3, 3, out), 0);
    assert_true(out[0] == 3.0L);
    assert_int_equal(ref_family_estimate("dmon-partial", &p, at, 3, 3, out), 0);
    assert_true(out[0] == 3.0L);
}

/* Negative means -2, -1, 0, 2, 10 (m = 5): both Ginis shift by 2 to 0, 1, 2,
 * 4, 12: G = (-2 + 8 + 48) / (5 * 19) = 54/95 = 0.568. gmon trims
 * floor(2 * 0.568) = 1: (-1 + 0 + 2) / 3; gmon-authors ceil(1.14) = 2: 0. */
static void test_gmon_authors_negative_means(void **state)
{
    (void)state;
    static const double means[] = {0, -2, 10, -1, 2};
    static const Expectation expect[] = {{"gmon", 1.0L / 3.0L}, {"gmon-authors", 0.0L}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    CHECK_SCALED(&p, 5, 5, means, expect);
}

/* The 1e-11 on every mean matters for tiny means: 0, 1, 5, 6, 100 times
 * 1e-13 (m = 5, scaled by 1, 2, 0.5 per channel). Without it G' = 410 / 560
 * = 0.73 and c = ceil(1.46) = 2 (the median, 5e-13). With it, channel R:
 * 410 / (5 (112 + 500)) = 0.134, G: 820 / (5 (224 + 500)) = 0.227, B:
 * 205 / (5 (56 + 500)) = 0.074; G'bar = 0.145, c = ceil(0.29) = 1: the mean of
 * t_2 .. t_4 (of the float sums). */
static void test_gmon_authors_offset(void **state)
{
    (void)state;
    static const double means[] = {5e-13, 0, 100e-13, 1e-13, 6e-13};
    float sums[REF_CHANNELS][REF_MAX_SETS];
    scaled_sums(sums, 5, 5, means);
    RefFamilyParams p;
    ref_family_params_default(&p);
    long double out[REF_CHANNELS];
    assert_int_equal(ref_family_estimate("gmon-authors", &p, sums, 5, 5, out), 0);
    for (int c = 0; c < REF_CHANNELS; ++c) {
        long double expected = ((long double)sums[c][3] + sums[c][0] + sums[c][4]) / 3.0L;
        assert_near(out[c], expected, HAND_TOLERANCE, "gmon-authors", c);
    }
}

/* ------------------------------------------------------------------------
 * The geometric median.
 * ---------------------------------------------------------------------- */

static void check_gmedian(float sums[REF_CHANNELS][REF_MAX_SETS], int m, const long double expected[3],
                          long double tolerance)
{
    RefFamilyParams p;
    ref_family_params_default(&p);
    long double out[REF_CHANNELS];
    assert_int_equal(ref_family_estimate("gmedian", &p, sums, (uint64_t)m, m, out), 0);
    for (int c = 0; c < REF_CHANNELS; ++c)
        if (!(fabsl(out[c] - expected[c]) <= tolerance))
            fail_msg("gmedian channel %d: %.21Lg, expected %.21Lg", c, out[c], expected[c]);
}

static void test_gmedian(void **state)
{
    (void)state;
    /* Identical RGB means: that mean, exactly. */
    float identical[REF_CHANNELS][REF_MAX_SETS] = {
        {0.3f, 0.3f, 0.3f, 0.3f, 0.3f}, {1.7f, 1.7f, 1.7f, 1.7f, 1.7f}, {5, 5, 5, 5, 5}};
    check_gmedian(identical, 5, (long double[]){0.3f, 1.7f, 5}, 0.0L);
    /* Three collinear points (0, 5, 0) + s (1, -1, 2), s = 5, 0, 1: the middle one. */
    float collinear[REF_CHANNELS][REF_MAX_SETS] = {{5, 0, 1}, {0, 5, 4}, {10, 0, 2}};
    check_gmedian(collinear, 3, (long double[]){1, 4, 2}, 0.0L);
    /* An equilateral triangle (3, 0, 0), (0, 3, 0), (0, 0, 3): its Fermat point is
     * the centroid (1, 1, 1); the iterations start at the componentwise median 0. */
    float triangle[REF_CHANNELS][REF_MAX_SETS] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}};
    check_gmedian(triangle, 3, (long double[]){1, 1, 1}, 1e-15L);
    /* The triangle plus its centre: the centre, a set mean (the unit vectors to
     * the vertices cancel); the iterations start at (0.5, 0.5, 0.5). */
    float centred[REF_CHANNELS][REF_MAX_SETS] = {{3, 0, 0, 1}, {0, 3, 0, 1}, {0, 0, 3, 1}};
    check_gmedian(centred, 4, (long double[]){1, 1, 1}, 1e-15L);
    /* Three of five sets at (1, 1, 1): the minimiser is that set mean (the two unit
     * vectors from it to (10, 0, 0) and (0, 10, 0) sum to length 1.26 <= 3). A step
     * that ignores the sets at z would leave it for (5, 5, 0). */
    float majority[REF_CHANNELS][REF_MAX_SETS] = {{1, 10, 1, 0, 1}, {1, 0, 1, 10, 1}, {1, 0, 1, 0, 1}};
    check_gmedian(majority, 5, (long double[]){1, 1, 1}, 0.0L);
}

/* On random heavy-tailed pixels the result is the minimiser: the unit vectors
 * from z to the RGB set means sum to (almost) 0, the gradient of
 * sum_j |Z_j - z|. */
static void test_gmedian_gradient_vanishes(void **state)
{
    (void)state;
    TestRng rng = test_rng(13);
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (int trial = 0; trial < 20; ++trial) {
        const int m = 21;
        float sums[REF_CHANNELS][REF_MAX_SETS];
        for (int c = 0; c < REF_CHANNELS; ++c)
            for (int j = 0; j < m; ++j)
                sums[c][j] = (float)test_pareto(&rng, 1.5);
        long double z[REF_CHANNELS], gradient[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
        assert_int_equal(ref_family_estimate("gmedian", &p, sums, (uint64_t)m, m, z), 0);
        for (int j = 0; j < m; ++j) {
            long double d = sqrtl(powl(z[0] - sums[0][j], 2) + powl(z[1] - sums[1][j], 2) + powl(z[2] - sums[2][j], 2));
            for (int c = 0; c < REF_CHANNELS; ++c)
                gradient[c] += (z[c] - sums[c][j]) / d;
        }
        long double length = sqrtl(gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
        if (!(length < 1e-12L))
            fail_msg("trial %d: gradient length %Lg", trial, length);
    }
}

/* ------------------------------------------------------------------------
 * Properties on random pixels.
 * ---------------------------------------------------------------------- */

static void random_sums(TestRng *rng, float sums[REF_CHANNELS][REF_MAX_SETS])
{
    for (int c = 0; c < REF_CHANNELS; ++c)
        for (int j = 0; j < REF_MAX_SETS; ++j)
            sums[c][j] = (float)(10.0 * test_rng_uniform(rng));
}

static void estimate_or_fail(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                             uint64_t n, int set_count, long double out[REF_CHANNELS])
{
    assert_int_equal(ref_family_estimate(name, p, sums, n, set_count, out), 0);
}

/* amon(0) = admon(0) = MoN exactly (odd m; amon also for even m); amon(1) =
 * trimmed(0) = winsorized(0) = the mean of the set means (odd m), with
 * unequal counts. */
static void test_alpha_limits(void **state)
{
    (void)state;
    static const int set_counts[] = {1, 2, 3, 4, 5, 20, 21, 63, 64};
    TestRng rng = test_rng(7);
    RefFamilyParams zero, one;
    ref_family_params_default(&zero);
    zero.amon_alpha = zero.admon_alpha = 0.0L;
    ref_family_params_default(&one);
    one.amon_alpha = 1.0L;
    one.trimmed_c = one.winsorized_c = 0;
    for (size_t i = 0; i < sizeof set_counts / sizeof set_counts[0]; ++i)
        for (int trial = 0; trial < 20; ++trial) {
            int m = set_counts[i];
            uint64_t n = 3 * (uint64_t)m + (uint64_t)trial % (uint64_t)m;
            float sums[REF_CHANNELS][REF_MAX_SETS];
            random_sums(&rng, sums);
            long double mon[REF_CHANNELS], amon[REF_CHANNELS], admon[REF_CHANNELS];
            estimate_or_fail("mon", &zero, sums, n, m, mon);
            estimate_or_fail("amon", &zero, sums, n, m, amon);
            estimate_or_fail("admon", &zero, sums, n, m, admon);
            for (int c = 0; c < REF_CHANNELS; ++c) {
                assert_true(amon[c] == mon[c]);
                if (m % 2 == 1)
                    assert_true(admon[c] == mon[c]);
            }
            if (m % 2 == 0)
                continue;
            long double of_means[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
            for (int c = 0; c < REF_CHANNELS; ++c) {
                for (int j = 0; j < m; ++j)
                    of_means[c] += (long double)sums[c][j] / (long double)set_samples(n, m, j);
                of_means[c] /= (long double)m;
            }
            static const char *const equal_to_mean_of_means[] = {"amon", "trimmed", "winsorized"};
            for (size_t e = 0; e < 3; ++e) {
                long double out[REF_CHANNELS];
                estimate_or_fail(equal_to_mean_of_means[e], &one, sums, n, m, out);
                for (int c = 0; c < REF_CHANNELS; ++c)
                    assert_near(out[c], of_means[c], HAND_TOLERANCE, equal_to_mean_of_means[e], c);
            }
        }
}

/* ------------------------------------------------------------------------
 * Standard errors.
 * ---------------------------------------------------------------------- */

static void check_stderr(const char *name, int jackknife, float sums[REF_CHANNELS][REF_MAX_SETS], uint64_t n,
                         int set_count, const long double expected[REF_CHANNELS])
{
    RefFamilyParams p;
    ref_family_params_default(&p);
    long double out[REF_CHANNELS];
    int status = jackknife ? ref_family_jackknife(name, &p, sums, n, set_count, out)
                           : ref_family_stderr(name, &p, sums, n, set_count, out);
    assert_int_equal(status, 0);
    for (int c = 0; c < REF_CHANNELS; ++c)
        assert_near(out[c], expected[c], HAND_TOLERANCE, name, c);
}

/* n = 7, M = 3: counts 3, 2, 2; means 1, 4, 1 (sums 3, 8, 2); mu = 13/7.
 * Closed form: n_j (t_j - mu) = -18/7, 30/7, -12/7; sum of squares 1368/49;
 * sqrt(3/2 * 1368/49) / 7 = sqrt(2052) / 49.
 * Jackknife: E_{-j} = (8 + 2)/4 = 2.5, (3 + 2)/5 = 1, (3 + 8)/5 = 2.2; Ebar 1.9;
 * deviations 0.6, -0.9, 0.3: sqrt(2/3 * 1.26) = sqrt(0.84). */
static void test_mean_stderr_unequal_counts(void **state)
{
    (void)state;
    float sums[REF_CHANNELS][REF_MAX_SETS] = {{3, 8, 2}, {3, 8, 2}, {3, 8, 2}};
    long double closed = sqrtl(2052.0L) / 49.0L, jackknifed = sqrtl(0.84L);
    check_stderr("mean", 0, sums, 7, 3, (long double[]){closed, closed, closed});
    check_stderr("mean", 1, sums, 7, 3, (long double[]){jackknifed, jackknifed, jackknifed});
}

/* Means 1, 2, 4 (one sample each; channels scaled 1, 2, 0.5). MoN without
 * each set: median(2, 4) = 3, median(1, 4) = 2.5, median(1, 2) = 1.5; Ebar 7/3;
 * squared deviations 4/9 + 1/36 + 25/36 = 7/6; sqrt(2/3 * 7/6) = sqrt(7) / 3.
 * gmedian of the collinear RGB means without one set is the midpoint of the
 * other two: the same per channel. */
static void test_jackknife_of_the_median(void **state)
{
    (void)state;
    float sums[REF_CHANNELS][REF_MAX_SETS];
    scaled_sums(sums, 3, 3, means_124);
    long double s = sqrtl(7.0L) / 3.0L;
    long double expected[REF_CHANNELS] = {s, 2.0L * s, 0.5L * s};
    check_stderr("mon", 0, sums, 3, 3, expected);
    check_stderr("gmedian", 0, sums, 3, 3, expected);
}

/* trimmed's default c is recomputed for m - 1: means 1, 2, 3, 10 (m = 4,
 * c = 1); without a set m = 3 and c = 0: E_{-j} = 15/3, 14/3, 13/3, 6/3; Ebar 4;
 * squared deviations 1 + 4/9 + 1/9 + 4 = 50/9; sqrt(3/4 * 50/9) = 5 / sqrt(6). */
static void test_jackknife_recomputes_defaults(void **state)
{
    (void)state;
    static const double means[] = {3, 1, 10, 2};
    float sums[REF_CHANNELS][REF_MAX_SETS];
    scaled_sums(sums, 4, 4, means);
    long double s = 5.0L / sqrtl(6.0L);
    check_stderr("trimmed", 0, sums, 4, 4, (long double[]){s, 2.0L * s, 0.5L * s});
}

/* Equal counts: the jackknife of the mean is the closed form. */
static void test_jackknife_of_the_mean_is_the_closed_form(void **state)
{
    (void)state;
    static const int set_counts[] = {2, 3, 4, 21, 64};
    TestRng rng = test_rng(11);
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (size_t i = 0; i < sizeof set_counts / sizeof set_counts[0]; ++i)
        for (int trial = 0; trial < 10; ++trial) {
            int m = set_counts[i];
            float sums[REF_CHANNELS][REF_MAX_SETS];
            random_sums(&rng, sums);
            long double closed[REF_CHANNELS], jackknifed[REF_CHANNELS];
            assert_int_equal(ref_family_stderr("mean", &p, sums, 5 * (uint64_t)m, m, closed), 0);
            assert_int_equal(ref_family_jackknife("mean", &p, sums, 5 * (uint64_t)m, m, jackknifed), 0);
            for (int c = 0; c < REF_CHANNELS; ++c) {
                assert_true(closed[c] > 0.0L);
                assert_near(jackknifed[c], closed[c], 1e-13L, "mean", c);
            }
        }
}

/* Identical set means (with unequal counts: n = 7, M = 3, sums 1.5, 1, 1):
 * the mean's stderr is 0, and so is every jackknife. m < 2: NaN. */
static void test_stderr_of_identical_means_and_of_one_set(void **state)
{
    (void)state;
    float identical[REF_CHANNELS][REF_MAX_SETS] = {{1.5f, 1, 1}, {3, 2, 2}, {0, 0, 0}};
    RefFamilyParams p;
    ref_family_params_default(&p);
    for (size_t i = 0; i < NAME_COUNT; ++i) {
        if (!all_names[i])
            continue;
        long double out[REF_CHANNELS];
        assert_int_equal(ref_family_stderr(all_names[i], &p, identical, 7, 3, out), 0);
        for (int c = 0; c < REF_CHANNELS; ++c)
            if (out[c] != 0.0L)
                fail_msg("%s stderr, channel %d: %Lg", all_names[i], c, out[c]);
        assert_int_equal(ref_family_stderr(all_names[i], &p, identical, 1, 3, out), 0); /* m = 1 */
        assert_true(isnan(out[0]) && isnan(out[1]) && isnan(out[2]));
        assert_int_equal(ref_family_stderr(all_names[i], &p, identical, 0, 3, out), 0); /* m = 0 */
        assert_true(isnan(out[0]) && isnan(out[1]) && isnan(out[2]));
        assert_int_equal(ref_family_jackknife(all_names[i], &p, identical, 1, 3, out), 0);
        assert_true(isnan(out[0]) && isnan(out[1]) && isnan(out[2]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_three_sets),
        cmocka_unit_test(test_fewer_samples_than_sets),
        cmocka_unit_test(test_five_sets),
        cmocka_unit_test(test_six_sets),
        cmocka_unit_test(test_unequal_counts),
        cmocka_unit_test(test_pakmon_subtracts_fifteen_percent),
        cmocka_unit_test(test_pakmon_equal_sums_is_the_median),
        cmocka_unit_test(test_two_sets),
        cmocka_unit_test(test_one_set_and_none),
        cmocka_unit_test(test_unknown_name_and_bad_set_count),
        cmocka_unit_test(test_parameters),
        cmocka_unit_test(test_thresholds_switch_at_a_quarter),
        cmocka_unit_test(test_gmon_authors_negative_means),
        cmocka_unit_test(test_gmon_authors_offset),
        cmocka_unit_test(test_gmedian),
        cmocka_unit_test(test_gmedian_gradient_vanishes),
        cmocka_unit_test(test_alpha_limits),
        cmocka_unit_test(test_mean_stderr_unequal_counts),
        cmocka_unit_test(test_jackknife_of_the_median),
        cmocka_unit_test(test_jackknife_recomputes_defaults),
        cmocka_unit_test(test_jackknife_of_the_mean_is_the_closed_form),
        cmocka_unit_test(test_stderr_of_identical_means_and_of_one_set),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
