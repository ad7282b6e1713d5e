/* The stiff case, statistically (fixed seed): on heavy-tailed samples G-MoN
 * must beat the mean in MSE, and on light-tailed ones it must be unbiased.
 *
 * Each pixel gets n = 1024 samples with independent R, G, B streams, sample
 * s in set s mod M (M = 21), accumulated on the host with the renderer's
 * shared fixed-point code and estimated with estimator_from_accumulators.
 * Errors are taken against the distribution's true mean over all pixels and
 * channels. */
#include "estimator/estimator.h"
#include "estimator_core.h"
#include "sample_streams.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define PIXELS 10000
#define SAMPLES 1024
#define SETS 21
#define BATCH 1000 /* pixels accumulated at a time: 1 MB of accumulators */

typedef double (*Draw)(TestRng *rng);

static double draw_pareto(TestRng *rng)
{
    return test_pareto(rng, 1.5); /* x_min 1, mean 1.5 / 0.5 = 3 */
}

static double draw_uniform(TestRng *rng)
{
    return test_rng_uniform(rng); /* (0, 1]: mean 0.5 up to 2^-54 */
}

static double draw_gaussian(TestRng *rng)
{
    return 1.0 + 0.1 * test_rng_gaussian(rng);
}

/* The estimators scored: the three of the default mode, and G-MoN in the
 * two variant modes for information. */
enum { MEAN, MON, GMON, GMON_PER_PIXEL, GMON_LUMINANCE, ESTIMATORS };
static const char *const estimator_names[ESTIMATORS] = {"mean", "MoN", "G-MoN", "G-MoN (Gini per pixel)",
                                                        "G-MoN (by luminance)"};

typedef struct {
    double mse[ESTIMATORS];
    double relative_bias[ESTIMATORS];
} Scores;

static Scores run_distribution(Draw draw, double truth, uint64_t seed)
{
    const size_t words = accumulator_planes(SETS) * BATCH;
    uint64_t *accumulators = malloc(words * sizeof(uint64_t));
    float *image[ESTIMATORS];
    assert_non_null(accumulators);
    for (int e = 0; e < ESTIMATORS; ++e) {
        image[e] = malloc(3 * BATCH * sizeof(float));
        assert_non_null(image[e]);
    }
    double error_sum[ESTIMATORS] = {0}, squared_sum[ESTIMATORS] = {0};
    TestRng rng = test_rng(seed);
    for (size_t first = 0; first < PIXELS; first += BATCH) {
        memset(accumulators, 0, words * sizeof(uint64_t));
        for (size_t p = 0; p < BATCH; ++p)
            for (uint64_t s = 0; s < SAMPLES; ++s) {
                float r = (float)draw(&rng), g = (float)draw(&rng), b = (float)draw(&rng);
                uint32_t set = set_of_sample(s, SETS);
                /* Every stream spans far fewer binary orders than a sum holds. */
                assert_int_equal(accumulate_sample(accumulators, p, BATCH, SETS, set, r, g, b), EST_ADD_EXACT);
            }
        /* The default mode gives mean, MoN and G-MoN; the variants G-MoN. */
        const struct {
            GiniMode mode;
            int gmon_slot;
        } runs[3] = {{GINI_PER_CHANNEL, GMON}, {GINI_PER_PIXEL, GMON_PER_PIXEL}, {SORT_BY_LUMINANCE, GMON_LUMINANCE}};
        for (int r = 0; r < 3; ++r) {
            EstimatorSettings settings = {SETS, runs[r].mode, 0};
            int is_default = runs[r].mode == GINI_PER_CHANNEL;
            EstimatorImages images = {is_default ? image[MEAN] : NULL,
                                      is_default ? image[MON] : NULL,
                                      image[runs[r].gmon_slot],
                                      NULL,
                                      NULL,
                                      3 * BATCH};
            char message[256] = "";
            EstimatorStatus status = estimator_from_accumulators(&settings, accumulators, words, BATCH, SAMPLES,
                                                                 &images, message, sizeof message);
            if (status != ESTIMATOR_OK)
                print_error("%s\n", message);
            assert_int_equal(status, ESTIMATOR_OK);
        }
        for (int e = 0; e < ESTIMATORS; ++e)
            for (size_t i = 0; i < 3 * BATCH; ++i) {
                double error = (double)image[e][i] - truth;
                error_sum[e] += error;
                squared_sum[e] += error * error;
            }
    }
    Scores scores;
    const double estimates = 3.0 * PIXELS;
    for (int e = 0; e < ESTIMATORS; ++e) {
        scores.mse[e] = squared_sum[e] / estimates;
        scores.relative_bias[e] = error_sum[e] / estimates / truth;
    }
    for (int e = 0; e < ESTIMATORS; ++e)
        free(image[e]);
    free(accumulators);
    return scores;
}

static void print_scores(const char *distribution, const Scores *scores)
{
    for (int e = 0; e < ESTIMATORS; ++e)
        printf("| %-26s | %-22s | %12.6g | %+12.4e |\n", distribution, estimator_names[e], scores->mse[e],
               scores->relative_bias[e]);
    fflush(stdout);
}

static void print_header(void)
{
    printf("n = %d samples per pixel, M = %d, %d pixels x 3 independent channels\n", SAMPLES, SETS, PIXELS);
    printf("| %-26s | %-22s | %12s | %12s |\n", "distribution", "estimator", "MSE", "rel. bias");
    printf("|----------------------------|------------------------|--------------|--------------|\n");
}

static void test_heavy_tail_gmon_beats_mean(void **state)
{
    (void)state;
    print_header();
    Scores scores = run_distribution(draw_pareto, 3.0, 1001);
    print_scores("Pareto alpha 1.5 (mean 3)", &scores);
    assert_true(scores.mse[GMON] < scores.mse[MEAN]);
}

static void test_light_tails_gmon_unbiased(void **state)
{
    (void)state;
    print_header();
    Scores uniform = run_distribution(draw_uniform, 0.5, 1002);
    print_scores("uniform [0, 1] (mean 0.5)", &uniform);
    Scores gaussian = run_distribution(draw_gaussian, 1.0, 1003);
    print_scores("Gaussian 1, sd 0.1", &gaussian);
    assert_true(fabs(uniform.relative_bias[GMON]) < 1e-3);
    assert_true(fabs(gaussian.relative_bias[GMON]) < 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_heavy_tail_gmon_beats_mean),
        cmocka_unit_test(test_light_tails_gmon_unbiased),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
