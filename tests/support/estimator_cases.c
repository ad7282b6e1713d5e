#include "estimator_cases.h"

#include "estimators.h"
#include "sample_streams.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

static const char *const case_names[CASE_COUNT] = {
    "random",
    "zeros",
    "all equal",
    "one outlier",
    "FLT_MAX",
    "denormals",
    "magnitudes 1e-30..1e30",
    "negative means",
    "mixed signs",
    "fewer samples than sets",
};

uint64_t estimator_case_set_samples(uint64_t n, int m, int j)
{
    return n > (uint64_t)j ? (n - (uint64_t)j + (uint64_t)m - 1) / (uint64_t)m : 0;
}

EstimatorCase estimator_case_make(EstimatorCaseKind kind, int m, uint64_t seed)
{
    EstimatorCase c = {kind, case_names[kind], m, 97, 0, NULL};
    TestRng rng = test_rng(seed * 131 + (uint64_t)kind * 7919 + (uint64_t)m);
    /* Unequal set counts where the case allows, to exercise weighting. */
    c.sample_count = (uint64_t)m * 16 + (uint64_t)(m > 1 ? m / 2 : 0);
    if (kind == CASE_ALL_EQUAL || kind == CASE_ONE_OUTLIER)
        c.sample_count = (uint64_t)m * 8;
    if (kind == CASE_FLT_MAX)
        c.sample_count = (uint64_t)m; /* one sample per set: means are the sums */
    if (kind == CASE_FEWER_SAMPLES_THAN_SETS)
        c.sample_count = (uint64_t)m / 2;
    c.sums = calloc((size_t)m * EST_CHANNELS * c.pixel_count, sizeof(float));
    for (size_t p = 0; p < c.pixel_count; ++p) {
        double base = 0.1 + 10.0 * test_rng_uniform(&rng);
        int outlier = (int)(test_rng_next(&rng) % (uint64_t)m);
        for (int j = 0; j < m; ++j) {
            double n_j = (double)estimator_case_set_samples(c.sample_count, m, j);
            for (int ch = 0; ch < EST_CHANNELS; ++ch) {
                double u = test_rng_uniform(&rng);
                double mean = 0.0;
                switch (kind) {
                case CASE_RANDOM:
                case CASE_FEWER_SAMPLES_THAN_SETS:
                    mean = 5.0 * u * u;
                    break;
                case CASE_ZEROS:
                    mean = 0.0;
                    break;
                case CASE_ALL_EQUAL:
                    mean = base * (ch + 1);
                    break;
                case CASE_ONE_OUTLIER:
                    mean = j == outlier ? base * 1000.0 : base;
                    break;
                case CASE_FLT_MAX:
                    mean = j == outlier ? FLT_MAX : (ch == 2 ? FLT_MAX * u : 1e30 * u);
                    break;
                case CASE_DENORMALS:
                    mean = FLT_MIN * u / n_j; /* sums are denormal */
                    break;
                case CASE_WIDE_MAGNITUDES:
                    mean = pow(10.0, -30.0 + 60.0 * u);
                    break;
                case CASE_NEGATIVE:
                    mean = -0.01 - 7.0 * u;
                    break;
                case CASE_MIXED_SIGNS:
                    mean = base * (2.0 * u - 0.5);
                    break;
                case CASE_COUNT:
                    break;
                }
                size_t i = (size_t)set_sum_index((uint32_t)j, (uint32_t)ch, p, c.pixel_count);
                /* All-equal means: n_j is equal, so S_j = n_j * mean exactly
                 * in float when mean is a float and n_j a power of two (8). */
                c.sums[i] = n_j > 0 ? (float)((double)(float)mean * n_j) : 0.0f;
            }
        }
    }
    return c;
}

void estimator_case_free(EstimatorCase *c)
{
    free(c->sums);
    c->sums = NULL;
}
