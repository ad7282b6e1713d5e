/* An independent long-double implementation of zirr (Zirr, Hanika,
 * Dachsbacher, "Re-Weighting Firefly Samples for Improved Finite-Sample
 * Monte Carlo Estimates", CGF 2018), written from the paper's description
 * and docs/estimators.md's statement of it, not from kernels/film/sample_passes.h: the
 * split is derived from its two conditions (weights sum to 1, counts sum to
 * 1) rather than from the closed form, and cascades and reliabilities are
 * long double. */
#ifndef TESTS_SUPPORT_ZIRR_REFERENCE_H
#define TESTS_SUPPORT_ZIRR_REFERENCE_H

#include <stddef.h>

typedef struct {
    int cascades;      /* K */
    long double base;  /* b; the scales are b^k, k = 0..K-1 */
    long double kappa; /* threshold */
    long double emin;  /* the brightness always considered reliable */
} ZirrReferenceParams;

/* The zirr estimate of a width x height image whose pixel p (p = y * width
 * + x) has the n RGB samples samples[(p * n + i) * 3 + c] (each of filter
 * weight 1; all finite), into estimate[p * 3 + c]. */
void reference_zirr(const ZirrReferenceParams *params, const float *samples, size_t n, int width, int height,
                    long double *estimate);

#endif
