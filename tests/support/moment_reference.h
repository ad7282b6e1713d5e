/* An independent long-double implementation of the moment-based estimators
 * (docs/estimators.md, "Estimators that see each sample": abmm, gabmm, mean-or-mon), written from
 * the spec, not from kernels/film/sample_passes.h: two-pass central moments and
 * the paper's Gini of the set means. */
#ifndef TESTS_SUPPORT_MOMENT_REFERENCE_H
#define TESTS_SUPPORT_MOMENT_REFERENCE_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    long double mean, m2, m3; /* mean, central moments (means of (x - mean)^k) */
} ReferenceMoments;

ReferenceMoments reference_moments(const float *x, size_t n);

/* theta = mu - m3 / (3 m2 (n alpha + 2)); mu when m2 <= 0. */
long double reference_abmm(const float *x, size_t n, long double alpha);

/* G of m values: sorted ascending t_1..t_m, sum_i (2i - m - 1) t_i / (m sum t),
 * clamped to [0, 1] (0 when the sum is not positive). */
long double reference_gini(const long double *values, int m);

/* The set means of a stream of samples x (sample i is sample index
 * first_sample + i, in set index mod sets); non-empty sets only. Returns
 * their number. */
int reference_set_means(const float *x, size_t n, int sets, uint64_t first_sample, long double *means);

/* mean-or-mon on a grey stream (sample i in set (first_sample + i) mod
 * sets, every set holding >= 2 samples): the 95 % half-widths 1.96 s /
 * sqrt(n) of the mean and of the median set (even sets: the middle pair's
 * averaged), s the two-pass sample standard deviation (1/(n - 1)); the
 * mean where its half-width is no larger, else the median of the set
 * means. */
typedef struct {
    long double mean_width, mon_width;
    long double mean, mon;
    int chose_mean;
    long double value;
} ReferenceMeanOrMon;

ReferenceMeanOrMon reference_mean_or_mon(const float *x, size_t n, int sets, uint64_t first_sample);

#endif
