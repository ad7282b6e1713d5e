/* An independent long-double evaluation of the set-based estimator family of
 * docs/estimators.md ("The family's definitions") and of the per-pixel
 * standard error ("Standard errors"), for tests.
 *
 * Written from the spec's definitions, not from the shared float code: plain
 * sums, sorts and textbook formulas in long double. Every estimator is a
 * function of the non-empty sets' sums and counts, so the jackknife can run
 * it on m - 1 sets. The set counts, median, textbook Gini, G-MoN trim count
 * and trimmed mean come from long_double_reference.c. */
#ifndef TESTS_SUPPORT_FAMILY_REFERENCE_H
#define TESTS_SUPPORT_FAMILY_REFERENCE_H

#include <stdint.h>

#define REF_CHANNELS 3
#define REF_MAX_SETS 64

typedef struct {
    long double amon_alpha;                                                            /* default 0.5 */
    long double admon_alpha;                                                           /* default 0.5 */
    long double gmon_binary_threshold, gmon_partial_threshold, dmon_partial_threshold; /* default 0.25 each */
    long double gmon_partial_alpha, dmon_partial_alpha; /* the alpha above the threshold, default 0.5 each */
    int trimmed_c, winsorized_c;                        /* -1: default floor(m / 4) */
    /* gmedian: 0, Weiszfeld iterations until it converges; n > 0, exactly n
     * steps of Vardi and Zhang's modified Weiszfeld iteration from the
     * componentwise median, and for the jackknife max(1, n / 4) steps on
     * the m - 1 sets from the estimate of all m (what gmonrt computes, with
     * n = its gmedian.iterations; default 0). */
    int gmedian_iterations;
    long double huber_k; /* default 1 */
} RefFamilyParams;

void ref_family_params_default(RefFamilyParams *p);

/* Names as users select them: "mean", "mon", "gmon", "amon", "admon",
 * "ggmon", "gmon-binary", "gmon-partial", "dmon-partial", "gmon-authors",
 * "pakmon", "trimmed", "winsorized", "gmedian", "huber".
 *
 * The estimate of one pixel per channel. sums[c][j]: channel c's sum over set
 * j (j < set_count = M, 1..64); sample s went to set s mod M, so set j holds
 * n_j = ceil((n - j) / M) samples; only the m = min(n, M) non-empty sets take
 * part. A non-finite sum is read as 0 (as long_double_reference.c does).
 * The sums are only read; they are not const-qualified because C11 does not
 * convert float (*)[N] to const float (*)[N] (-Wpedantic rejects the call).
 * Returns 0, or -1 for an unknown name or a set_count outside 1..64.
 * sample_count == 0: out = 0. */
int ref_family_estimate(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                        uint64_t sample_count, int set_count, long double out[REF_CHANNELS]);

/* Its standard error per channel: for "mean" the closed form
 * sqrt(m / (m - 1) * sum_j (n_j (t_j - mu))^2) / n, for every other name the
 * jackknife over sets (ref_family_jackknife). m < 2: NaN. */
int ref_family_stderr(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                      uint64_t sample_count, int set_count, long double out[REF_CHANNELS]);

/* The jackknife over sets for any name, "mean" included: E_{-j} is the
 * estimator on the m - 1 non-empty sets without set j (each keeping its own
 * sum and count; m-dependent defaults recomputed for m - 1), Ebar their mean,
 * stderr = sqrt((m - 1) / m * sum_j (E_{-j} - Ebar)^2). m < 2: NaN. */
int ref_family_jackknife(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                         uint64_t sample_count, int set_count, long double out[REF_CHANNELS]);

#endif
