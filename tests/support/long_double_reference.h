/* An independent long-double evaluation of the estimator formulas of
 * docs/estimators.md ("Mean, MoN and G-MoN"), for tests.
 *
 * It is written from the textbook definitions (set means S_j / n_j, sort,
 * median, the plain Gini formula, plain sums) and shares no code and no
 * numerical tricks with kernels/film/estimators.h: no power-of-two scaling, no
 * compensated sums, no cancellation-free Gini numerator. Long double's 64-bit
 * significand and wide exponent make the textbook form accurate far beyond
 * float for every test input, so the float implementation can be judged
 * against it. */
#ifndef TESTS_SUPPORT_LONG_DOUBLE_REFERENCE_H
#define TESTS_SUPPORT_LONG_DOUBLE_REFERENCE_H

#include "film/film.h" /* GiniMode */

#include <stddef.h>
#include <stdint.h>

#define LDREF_MAX_SETS 64
#define LDREF_CHANNELS 3

/* One channel under the default (per-channel) definitions. */
typedef struct {
    int m;                              /* non-empty sets */
    long double mean;                   /* sum S_j / sum n_j */
    long double sorted[LDREF_MAX_SETS]; /* set means, ascending, [0, m) */
    long double median;                 /* MoN */
    long double gini;                   /* G, clamped to [0, 1] */
    int trim;                           /* c */
    long double gmon;                   /* trimmed mean of sorted at c */
} LdChannel;

/* One pixel as the implementation should output it in a given Gini mode. */
typedef struct {
    int m;
    LdChannel channel[LDREF_CHANNELS]; /* per-channel quantities, any mode */
    /* Set means of each channel in the order the mode trims them: ascending
     * per channel, or by luminance for SORT_BY_LUMINANCE. */
    long double ordered[LDREF_CHANNELS][LDREF_MAX_SETS];
    long double mean[LDREF_CHANNELS];
    long double mon[LDREF_CHANNELS];
    long double gmon[LDREF_CHANNELS];
    long double gini[LDREF_CHANNELS]; /* G used for the trim */
    int trim[LDREF_CHANNELS];
    long double lowest[LDREF_CHANNELS]; /* t_1 and t_m of each channel */
    long double highest[LDREF_CHANNELS];
} LdPixel;

/* n_j = ceil((n - j) / M), 0 for j >= n. */
uint64_t ldref_set_samples(uint64_t sample_count, int set_count, int set);

/* Textbook Gini of m ascending values, with the negative-shift convention;
 * 0 if the denominator is 0; clamped to [0, 1]. */
long double ldref_gini(const long double *ascending, int m);

/* c = floor(G * floor(m / 2)), clamped to [0, floor((m - 1) / 2)]. */
int ldref_trim_count(long double gini, int m);

/* Mean of values[c .. m - 1 - c] (values in trimming order). */
long double ldref_trimmed_mean(const long double *values, int m, int c);

/* Median by position: the middle value, or the mean of the two middle ones. */
long double ldref_median(const long double *values, int m);

/* One channel from its M set sums (sums[j], j < set_count). Non-finite sums
 * are read as 0, as the implementation does. */
void ldref_channel(const float *sums, int set_count, uint64_t sample_count, LdChannel *out);

/* One pixel from set-sum planes [set][channel][pixel], in `mode`. */
void ldref_pixel(const float *set_sums, size_t pixel_count, size_t pixel, int set_count, uint64_t sample_count,
                 GiniMode mode, LdPixel *out);

#endif
