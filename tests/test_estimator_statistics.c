/* The stiff case, statistically (fixed seed), for the whole estimator
 * family: on heavy-tailed samples G-MoN must beat the mean in MSE, and on
 * light-tailed ones it must be unbiased; every estimator's MSE, bias and
 * the coverage of its standard error (the fraction of estimates within
 * 1.96 stderr of the truth) are printed.
 *
 * Each pixel gets n = 1024 samples with independent R, G, B streams, sample
 * s in set s mod M (M = 21), accumulated on the host with the renderer's
 * shared fixed-point code and estimated with estimator_from_accumulators.
 * Errors are taken against the distribution's true mean over all pixels and
 * channels. */
#include "film/film.h"
#include "estimators.h"
#include "estimator_images.h"
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

/* The estimators scored: every pass of the family in the default mode,
 * and G-MoN in the two variant modes for information. */
enum { GMON_PER_PIXEL = PASS_COUNT, GMON_LUMINANCE, ESTIMATORS };

static const char *estimator_name(int e)
{
    return e == GMON_PER_PIXEL ? "gmon (Gini per pixel)" : e == GMON_LUMINANCE ? "gmon (by luminance)" : pass_name(e);
}

static int is_scored(int e)
{
    return e >= PASS_COUNT || (PASSES_ESTIMATES & PASS_BIT(e));
}

typedef struct {
    double mse[ESTIMATORS];
    double relative_bias[ESTIMATORS];
    double coverage[ESTIMATORS]; /* fraction of estimates within 1.96 stderr of the truth; -1: none */
} Scores;

static Scores run_distribution(Draw draw, double truth, uint64_t seed)
{
    const size_t words = accumulator_planes(SETS) * BATCH;
    uint64_t *accumulators = malloc(words * sizeof(uint64_t));
    assert_non_null(accumulators);
    EstimatorImages family = test_images_new(PASSES_ESTIMATES, 1, BATCH);
    EstimatorImages variants[2] = {test_images_new(PASS_BIT(PASS_GMON), 0, BATCH),
                                   test_images_new(PASS_BIT(PASS_GMON), 0, BATCH)};
    double error_sum[ESTIMATORS] = {0}, squared_sum[ESTIMATORS] = {0}, covered[ESTIMATORS] = {0};
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
        const struct {
            GiniMode mode;
            EstimatorImages *images;
        } runs[3] = {{GINI_PER_CHANNEL, &family}, {GINI_PER_PIXEL, &variants[0]}, {SORT_BY_LUMINANCE, &variants[1]}};
        for (int r = 0; r < 3; ++r) {
            EstimatorSettings settings;
            estimator_settings_default(&settings);
            settings.set_count = SETS;
            settings.gini_mode = runs[r].mode;
            settings.passes = r == 0 ? PASSES_ESTIMATES : PASS_BIT(PASS_GMON);
            settings.with_stderr = r == 0;
            char message[256] = "";
            EstimatorStatus status = estimator_from_accumulators(&settings, accumulators, words, BATCH, SAMPLES,
                                                                 runs[r].images, message, sizeof message);
            if (status != ESTIMATOR_OK)
                print_error("%s\n", message);
            assert_int_equal(status, ESTIMATOR_OK);
        }
        for (int e = 0; e < ESTIMATORS; ++e) {
            if (!is_scored(e))
                continue;
            const float *image =
                e < PASS_COUNT ? TEST_IMAGE(family, e) : TEST_IMAGE(variants[e - PASS_COUNT], PASS_GMON);
            const float *error = e < PASS_COUNT ? family.error[e] : NULL;
            for (size_t i = 0; i < 3 * BATCH; ++i) {
                double difference = (double)image[i] - truth;
                error_sum[e] += difference;
                squared_sum[e] += difference * difference;
                if (error)
                    covered[e] += fabs(difference) <= 1.96 * (double)error[i];
            }
        }
    }
    Scores scores;
    const double estimates = 3.0 * PIXELS;
    for (int e = 0; e < ESTIMATORS; ++e) {
        scores.mse[e] = squared_sum[e] / estimates;
        scores.relative_bias[e] = error_sum[e] / estimates / truth;
        scores.coverage[e] = e < PASS_COUNT ? covered[e] / estimates : -1.0;
    }
    test_images_free(&family);
    test_images_free(&variants[0]);
    test_images_free(&variants[1]);
    free(accumulators);
    return scores;
}

static void print_scores(const char *distribution, const Scores *scores)
{
    for (int e = 0; e < ESTIMATORS; ++e) {
        if (!is_scored(e))
            continue;
        printf("| %-26s | %-22s | %12.6g | %+12.4e |", distribution, estimator_name(e), scores->mse[e],
               scores->relative_bias[e]);
        if (scores->coverage[e] >= 0.0)
            printf(" %8.3f |\n", scores->coverage[e]);
        else
            printf("          |\n");
    }
    fflush(stdout);
}

static void print_header(void)
{
    printf("n = %d samples per pixel, M = %d, %d pixels x 3 independent channels\n", SAMPLES, SETS, PIXELS);
    printf("| %-26s | %-22s | %12s | %12s | %8s |\n", "distribution", "estimator", "MSE", "rel. bias", "covered");
    printf("|----------------------------|------------------------|--------------|--------------|----------|\n");
}

static void test_heavy_tail_gmon_beats_mean(void **state)
{
    (void)state;
    print_header();
    Scores scores = run_distribution(draw_pareto, 3.0, 1001);
    print_scores("Pareto alpha 1.5 (mean 3)", &scores);
    assert_true(scores.mse[PASS_GMON] < scores.mse[PASS_MEAN]);
}

static void test_light_tails_gmon_unbiased(void **state)
{
    (void)state;
    print_header();
    Scores uniform = run_distribution(draw_uniform, 0.5, 1002);
    print_scores("uniform [0, 1] (mean 0.5)", &uniform);
    Scores gaussian = run_distribution(draw_gaussian, 1.0, 1003);
    print_scores("Gaussian 1, sd 0.1", &gaussian);
    assert_true(fabs(uniform.relative_bias[PASS_GMON]) < 1e-3);
    assert_true(fabs(gaussian.relative_bias[PASS_GMON]) < 1e-3);
    /* On light tails, where the central limit theorem holds for a set mean,
     * the mean's standard error is calibrated: from M = 21 set means,
     * error / stderr follows Student's t with 20 degrees of freedom, and
     * P(|t_20| <= 1.96) = 0.9358 (not 0.95: 1.96 is the normal quantile). */
    assert_true(fabs(uniform.coverage[PASS_MEAN] - 0.9358) < 0.005);
    assert_true(fabs(gaussian.coverage[PASS_MEAN] - 0.9358) < 0.005);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_heavy_tail_gmon_beats_mean),
        cmocka_unit_test(test_light_tails_gmon_unbiased),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
