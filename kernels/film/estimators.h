/* The per-pixel estimators of docs/estimators.md, from the set sums:
 * mean, MoN, G-MoN and the estimator family (passes.h lists them), with
 * their diagnostics and standard errors. This file is their shared core
 * (sorting, Gini, the weighted averages, estimate_family's dispatch, the
 * standard errors' driver); each estimator of the family is a file under
 * estimators/, included below, and its row in passes.h says how the core
 * treats it.
 *
 * Valid C11 and OpenCL C 1.2. The host reference (host/film) and the
 * estimator kernel (kernels/film/estimator.cl) compile these files, so they
 * agree bit for bit.
 *
 * In a kernel, EST_SETS (M) is a compile-time constant and sizes the private
 * arrays; the host compiles it with the maximum and passes M at run time.
 * The estimators work on lanes (lanes.h): one pixel on the host, and
 * EST_VECTOR_WIDTH pixels per work item in a vector kernel. */
#ifndef KERNELS_ESTIMATORS_H
#define KERNELS_ESTIMATORS_H

#include "accumulate.h"
#include "estimator_numerics.h"
#include "estimator_sort.h"
#include "passes.h"

/* How G-MoN picks its trim count (docs/estimators.md, "Mean, MoN and G-MoN"). */
#define EST_GINI_PER_CHANNEL 0  /* default: one G and c per channel */
#define EST_GINI_PER_PIXEL 1    /* G = mean of the three channel G's */
#define EST_SORT_BY_LUMINANCE 2 /* order and trim whole RGB sets by luminance */

/* ------------------------------------------------------------------------
 * Per-pixel estimators.
 *
 * Stable form (docs/estimators.md, "Stable Gini coefficient"). Set means t_j = S_j / n_j are
 * kept as they are (a single scale for all sets would flush means 2^126
 * below the largest to zero, and 1e-30 and 1e30 can share a pixel). Each
 * sum instead scales the values it adds by the power of two that brings the
 * largest of them into [1, 2): exact, so nothing overflows even at FLT_MAX,
 * and results scale exactly with their inputs. Averages are computed as
 * base + mean(value - base) with a compensated sum, so equal means give that
 * value exactly; Gini's numerator pairs t_{m+1-j} - t_j, which never cancel.
 * With equal set counts the sums themselves are sorted and averaged and only
 * the results are divided by the count (SetCounts).
 *
 * Written once for lanes (lanes.h): the host runs it on one pixel at a time,
 * a vector kernel on EST_VECTOR_WIDTH pixels at once, with the same
 * operations in the same order, so both give the same bits. It is branch
 * free per lane: sets are sorted by a fixed sorting network
 * (sorting_networks.h), and G-MoN's trimmed mean, whose range differs per
 * lane, visits every set and adds exact zeros for the trimmed ones. Branches
 * and loop bounds depend only on M, the sample count and the Gini mode,
 * which every lane shares; in a kernel M and the Gini mode are compile-time
 * constants, so the loops unroll and the arrays live in registers.
 * ---------------------------------------------------------------------- */

#if !defined(__OPENCL_C_VERSION__) || defined(EST_SETS)

/* The estimates of EST_VECTOR_WIDTH pixels, one per lane, by pass
 * (passes.h); only the requested ones are computed. */
typedef struct {
    est_float value[PASS_COUNT][EST_CHANNELS]; /* PASS_TRIM: the trim count c, exactly */
    est_float error[PASS_COUNT][EST_CHANNELS]; /* standard errors of the estimates */
} LaneEstimates;

/* Every NaN as one bit pattern, 0x7fc00000: arithmetic on a NaN keeps its
 * payload on x86 but gives 0x7fffffff on NVIDIA's GPUs, and host and devices
 * must agree bit for bit. */
EST_INLINE est_float canonical_nan(est_float x)
{
    return EST_SELECT(x != x, EST_FLOAT_FROM_BITS(EST_UINT_FROM_INT(EST_INTS(0x7fc00000))), x);
}

/* The last step before the estimates are stored, on the host and on the
 * devices alike: estimates computed on sums in grid units (from
 * accumulators) scaled to the pixel's values, and NaNs made canonical (the
 * trim count, an integer, aside). */
EST_INLINE void finish_estimates(LaneEstimates *out, uint32_t passes, int from_accumulators, est_int grid_exponent)
{
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p)
        if ((passes & PASS_BIT(p)) && p != PASS_TRIM) {
            const int scaled = from_accumulators && (PASSES_ESTIMATES & PASS_BIT(p));
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c) {
                est_float value = out->value[p][c], error = out->error[p][c];
                if (scaled) {
                    value = scale_by_grid(value, grid_exponent);
                    error = scale_by_grid(error, grid_exponent);
                }
                out->value[p][c] = canonical_nan(value);
                out->error[p][c] = canonical_nan(error);
            }
        }
}

/* Gini coefficient of m ascending values t, clamped to [0, 1]. G is scale
 * invariant: values are scaled by `down` (from sorted_range_exponent(t, 0,
 * m - 1)) so the largest magnitude lies in [1, 2); lowest = t[0] * down and
 * differences = sum_of_differences(t, 0, m - 1, down, lowest, 1), which the
 * mean shares. Negative values shift everything by -t_1, which changes only
 * the denominator (sum_j (t_j - shift) = differences + m (t_1 - shift)),
 * since the numerator is built from differences. offset: added to every
 * value, scaled (the authors' 1e-11; 0 for the paper's G). */
EST_INLINE est_float gini_sorted_offset(const est_float *t, int m, est_float down, est_float lowest,
                                        est_float differences, est_float offset)
{
    if (m < 2)
        return EST_FLOATS(0.0f);
    est_float shift = EST_SELECT(lowest < 0.0f, lowest, EST_FLOATS(0.0f));
    est_float numerator = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 0; j < m / 2; ++j)
        numerator += (float)(m - 1 - 2 * j) * (scaled(t[m - 1 - j], down) - scaled(t[j], down));
    est_float total = differences + (float)m * (lowest - shift + offset);
    est_float denominator = (float)m * total;
    est_float g = numerator / denominator;
    g = EST_SELECT(g < 0.0f, EST_FLOATS(0.0f), EST_SELECT(g > 1.0f, EST_FLOATS(1.0f), g));
    return EST_SELECT((denominator > 0.0f) & (denominator < INFINITY), g, EST_FLOATS(0.0f));
}

/* The paper's G: no offset. */
EST_INLINE est_float gini_sorted(const est_float *t, int m, est_float down, est_float lowest, est_float differences)
{
    return gini_sorted_offset(t, m, down, lowest, differences, EST_FLOATS(0.0f));
}

/* gini_sorted on its own. */
EST_INLINE est_float gini_of_sorted(const est_float *t, int m)
{
    est_float down = power_of_two(-sorted_range_exponent(t, 0, m - 1));
    est_float lowest = scaled(t[0], down);
    return gini_sorted(t, m, down, lowest, sum_of_differences(t, 0, m - 1, down, lowest, 1));
}

/* c = floor(G * floor(m/2)), clamped so at least one set remains. */
EST_INLINE est_int trim_count(est_float g, int m)
{
    est_int c = EST_INT_FROM_FLOAT(g * (float)(m / 2));
    int most = (m - 1) / 2;
    return EST_SELECT(c < 0, EST_INTS(0), EST_SELECT(c > most, EST_INTS(most), c));
}

/* Averages of values lie within them; the clamp removes the last ulp that
 * rounding could add. Then the division by the set count (SetCounts). */
EST_INLINE est_float finish_value(est_float x, est_float lo, est_float hi, float divisor)
{
    return clamp_lanes(x, lo, hi) / divisor;
}

/* Clamps the channel's mean and MoN and computes its G-MoN (with the trim
 * already in out) from its set means v[0..m-1] (ascending: sorted), then
 * divides all three by divisor (see SetCounts). */
EST_INLINE void finish_channel(LaneEstimates *out, int c, const est_float *v, int m, int ascending, float divisor)
{
    est_float lo = v[0], hi = v[m - 1];
    if (!ascending) {
        hi = v[0];
        EST_UNROLL
        for (int j = 1; j < m; ++j) {
            lo = EST_SELECT(v[j] < lo, v[j], lo);
            hi = EST_SELECT(v[j] > hi, v[j], hi);
        }
    }
    est_int trim = EST_INT_FROM_FLOAT(out->value[PASS_TRIM][c]);
    out->value[PASS_MEAN][c] = finish_value(out->value[PASS_MEAN][c], lo, hi, divisor);
    out->value[PASS_MON][c] = finish_value(out->value[PASS_MON][c], lo, hi, divisor);
    out->value[PASS_GMON][c] = finish_value(trimmed_average(v, m, trim, ascending), lo, hi, divisor);
}

#define EST_SORT_STEP(i, j) compare_exchange(v, i, j);
#define EST_LUMINANCE_STEP(i, j) compare_exchange_luminance(luma, sorted, i, j);

/* What every lane shares: the set counts. */
typedef struct {
    uint64_t sample_count;
    int set_count;    /* M */
    int m;            /* non-empty sets, min(sample_count, M) */
    int most;         /* largest trim, (m - 1) / 2 */
    int with_extra;   /* sets j < with_extra hold `more` samples, the others `fewer` */
    int equal_counts; /* every non-empty set holds `fewer` samples */
    float more;
    float fewer;
    /* With equal counts n_j = q the set means are the sums over q: the sums
     * are sorted and averaged as they are, and only the results are divided
     * by q (once, correctly rounded), which orders and weighs exactly as the
     * means would. With unequal counts every sum is divided by its count
     * (divisor 1). */
    float divisor;
} SetCounts;

/* m: min(sample_count, set_count) (a parameter so that a kernel can make it
 * a constant). */
EST_INLINE SetCounts est_set_counts(uint64_t sample_count, int set_count, int m)
{
    SetCounts k;
    k.sample_count = sample_count;
    k.set_count = set_count;
    k.m = m;
    k.most = (m - 1) / 2;
    const int few_samples = m < set_count; /* one sample in each non-empty set */
    const uint64_t per_set = sample_count / (uint64_t)set_count;
    k.with_extra = (int)(sample_count % (uint64_t)set_count);
    k.equal_counts = few_samples || k.with_extra == 0;
    k.more = few_samples ? 1.0f : (float)(per_set + 1u);
    k.fewer = few_samples ? 1.0f : (float)per_set;
    k.divisor = k.equal_counts ? k.fewer : 1.0f;
    return k;
}

/* MoN: the median of ascending v[0..m-1] (even m: the mean of the middle
 * pair). */
EST_INLINE est_float median_of_sorted(const est_float *v, int m)
{
    return average_range(v, (m - 1) / 2, m / 2, 1);
}

/* With unequal counts: the set means t[j] = sums over counts (in place,
 * in set order, j < m) and the channel's mean, weighted by the counts. */
EST_INLINE void unequal_sets_mean(const SetCounts *k, est_float *t, LaneEstimates *out, int c)
{
    const int m = k->m;
    EST_UNROLL
    for (int j = 0; j < m; ++j)
        t[j] = t[j] / (j < k->with_extra ? k->more : k->fewer);
    est_float lo = t[0], hi = t[0];
    EST_UNROLL
    for (int j = 1; j < m; ++j) {
        lo = EST_SELECT(t[j] < lo, t[j], lo);
        hi = EST_SELECT(t[j] > hi, t[j], hi);
    }
    out->value[PASS_MEAN][c] = weighted_average(t, m, k->with_extra, k->more, k->fewer, (float)k->sample_count, lo, hi);
}

/* The sorted part of one channel: from its ascending set means (or sums,
 * see SetCounts) v[0..m-1], its mean (with equal counts), MoN, G and trim
 * in out. */
EST_INLINE void sorted_channel(const SetCounts *k, const est_float *v, LaneEstimates *out, int c)
{
    const int m = k->m;
    /* The mean (average_range(v, 0, m - 1, 1) with equal counts) and G share
     * the scaled differences. */
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float lowest = scaled(v[0], down);
    est_float differences = sum_of_differences(v, 0, m - 1, down, lowest, 1);
    if (k->equal_counts)
        out->value[PASS_MEAN][c] = scaled(lowest + differences / (float)m, power_of_two(e));
    out->value[PASS_MON][c] = median_of_sorted(v, m);
    out->value[PASS_GINI][c] = gini_sorted(v, m, down, lowest, differences);
    out->value[PASS_TRIM][c] = EST_FLOAT_FROM_INT(trim_count(out->value[PASS_GINI][c], m));
}

/* The first part of one channel: from its sums (sums[j], j < M) the set
 * means by set, t (t[j] = +inf for the empty sets j >= m), the same sorted,
 * v, and the channel's mean, MoN, G and trim in out (mean and MoN before
 * finish_channel; with equal counts t and v hold sums, see SetCounts).
 * finite: 1 if the caller knows every sum is finite (converted accumulators
 * are), which skips a check that changes nothing then; non-finite sums
 * (possible only in hand-made input) are read as 0. */
EST_INLINE void estimate_channel(const SetCounts *k, const est_float *sums, int finite, est_float *t, est_float *v,
                                 LaneEstimates *out, int c)
{
    const int m = k->m;
    EST_UNROLL
    for (int j = 0; j < k->set_count; ++j) {
        est_float sum = sums[j];
        if (!finite)
            sum = EST_SELECT((EST_FLOAT_BITS(sum) & 0x7f800000u) == 0x7f800000u, EST_FLOATS(0.0f), sum);
        t[j] = j < m ? sum : EST_FLOATS(INFINITY);
    }
    /* The weighted mean, in set order, first: the means by set are then
     * not needed past the sort (but in luminance mode). */
    if (!k->equal_counts)
        unequal_sets_mean(k, t, out, c);
    EST_UNROLL
    for (int j = 0; j < k->set_count; ++j)
        v[j] = t[j];
    EST_SORTING_NETWORK(k->set_count, EST_SORT_STEP)
    sorted_channel(k, v, out, c);
}

/* One channel in the default mode (EST_GINI_PER_CHANNEL), start to end; m
 * >= 1. */
EST_INLINE void estimate_channel_alone(const SetCounts *k, const est_float *sums, int finite, LaneEstimates *out, int c)
{
    est_float t[EST_CAPACITY], v[EST_CAPACITY];
    estimate_channel(k, sums, finite, t, v, out, c);
    finish_channel(out, c, v, k->m, 1, k->divisor);
}

EST_INLINE void clear_estimates(LaneEstimates *out)
{
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->value[p][c] = EST_FLOATS(0.0f);
            out->error[p][c] = EST_FLOATS(0.0f);
        }
    }
}

/* ------------------------------------------------------------------------
 * The estimator family (docs/estimators.md, "The family's definitions").
 *
 * Most of them are weighted means of the sorted set means: each is a
 * choice of weights, and weighted_sorted_average computes them all the same
 * way, so equal weights give equal bits (amon(1), trimmed(0),
 * winsorized(0) and the mean of the set means agree exactly).
 * ---------------------------------------------------------------------- */

/* sum_j w[j] v[j] / sum_j w[j] over ascending v[0..m-1] (weights >= 0, one
 * at least > 0), as base + sum_j w[j] (v[j] - base) / sum_j w[j] with base
 * v[(m - 1) / 2], on values scaled so the largest lies in [1, 2): the
 * terms are added compensated, and equal values give that value exactly. */
EST_INLINE est_float weighted_sorted_average(const est_float *v, int m, const est_float *w)
{
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float base = scaled(v[(m - 1) / 2], down);
    est_float sum = EST_FLOATS(0.0f), compensation = EST_FLOATS(0.0f);
    est_float total = EST_FLOATS(0.0f), total_compensation = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 0; j < m; ++j) {
        compensated_add(&sum, &compensation, w[j] * (scaled(v[j], down) - base));
        compensated_add(&total, &total_compensation, w[j]);
    }
    return clamp_lanes(scaled(base + (sum + compensation) / (total + total_compensation), power_of_two(e)), v[0],
                       v[m - 1]);
}

/* 1 / sqrt(x) for x in [1, 4): the bit-level estimate (within 3.5e-2)
 * and three Newton steps, each taking the relative error e to 1.5 e^2
 * (1.8e-3, 5e-6, then float rounding); multiplications only: the same bits
 * everywhere. */
EST_INLINE est_float inverse_root_reduced(est_float x)
{
    est_float y = EST_FLOAT_FROM_BITS(0x5f3759dfu - (EST_FLOAT_BITS(x) >> 1));
    EST_UNROLL
    for (int i = 0; i < 3; ++i)
        y = y * (1.5f - 0.5f * x * y * y);
    return y;
}

/* sqrt(x) (inverse: 1 / sqrt(x)) for finite x >= 0 within about an ulp,
 * without library sqrt: x = 4^h f with f in [1, 4). 0 gives 0 (inverse:
 * 0, the Weiszfeld weight of a point at the current estimate). */
EST_INLINE est_float root_of(est_float x, int inverse)
{
    est_mask tiny = x < 1.17549435e-38f; /* denormal: scaled up by 2^64 first */
    est_float y = EST_SELECT(tiny, x * 18446744073709551616.0f, x);
    est_int e = EST_INT_FROM_UINT(EST_FLOAT_BITS(y) >> 23) - 127;
    est_int h = (e - EST_SELECT(e < 0, EST_INTS(1), EST_INTS(0))) / 2; /* floor(e / 2) */
    est_float f = y * power_of_two(-2 * h);
    est_float r = inverse_root_reduced(f);
    est_int shift = EST_SELECT(tiny, h - 32, h);
    est_float result = inverse ? r * power_of_two(-shift) : f * r * power_of_two(shift);
    return EST_SELECT(x > 0.0f, result, EST_FLOATS(0.0f));
}

/* x * 2^e for any e (clamped to +-378, past which every float result is 0
 * or infinite), in three exact steps. */
EST_INLINE est_float scale_by_power(est_float x, est_int e)
{
    e = EST_SELECT(e < -378, EST_INTS(-378), EST_SELECT(e > 378, EST_INTS(378), e));
    est_int first = EST_SELECT(e < -126, EST_INTS(-126), EST_SELECT(e > 126, EST_INTS(126), e));
    est_int rest = e - first;
    est_int second = EST_SELECT(rest < -126, EST_INTS(-126), EST_SELECT(rest > 126, EST_INTS(126), rest));
    return x * power_of_two(first) * power_of_two(second) * power_of_two(rest - second);
}

/* The estimators of the family, a file each (passes.h's rows say how
 * the code below treats each). */
#include "estimators/amon.h"
#include "estimators/admon.h"
#include "estimators/trimmed.h"
#include "estimators/winsorized.h"
#include "estimators/ggmon.h"
#include "estimators/gmon_binary.h"
#include "estimators/gmon_partial.h"
#include "estimators/dmon_partial.h"
#include "estimators/gmon_authors.h"
#include "estimators/pakmon.h"
#include "estimators/gmedian.h"
#include "estimators/huber.h"

/* The weighted means whose weights depend only on the set count and the
 * parameters, not on the values: their leave-one-out estimates take O(m)
 * in all (leave_one_out_averages). The Gini-gated estimators pick one of
 * two of them, or the median. */
enum {
    FIXED_AMON,
    FIXED_ADMON,
    FIXED_TRIMMED,
    FIXED_WINSORIZED,
    FIXED_MEAN,          /* of the set means: gmon-binary below its threshold */
    FIXED_AMON_ONE,      /* amon(1): gmon-partial below its threshold */
    FIXED_AMON_PARTIAL,  /* amon(gmon-partial.alpha): at or above it */
    FIXED_ADMON_ONE,     /* admon(1): dmon-partial below its threshold */
    FIXED_ADMON_PARTIAL, /* admon(dmon-partial.alpha): at or above it */
    FIXED_COUNT
};

/* The variants (bits 1 << FIXED_*) that `passes` need. */
EST_INLINE uint32_t fixed_variants(uint32_t passes)
{
    uint32_t v = 0u;
    if (passes & PASS_BIT(PASS_AMON))
        v |= 1u << FIXED_AMON;
    if (passes & PASS_BIT(PASS_ADMON))
        v |= 1u << FIXED_ADMON;
    if (passes & PASS_BIT(PASS_TRIMMED))
        v |= 1u << FIXED_TRIMMED;
    if (passes & PASS_BIT(PASS_WINSORIZED))
        v |= 1u << FIXED_WINSORIZED;
    if (passes & PASS_BIT(PASS_GMON_BINARY))
        v |= 1u << FIXED_MEAN;
    if (passes & PASS_BIT(PASS_GMON_PARTIAL))
        v |= (1u << FIXED_AMON_ONE) | (1u << FIXED_AMON_PARTIAL);
    if (passes & PASS_BIT(PASS_DMON_PARTIAL))
        v |= (1u << FIXED_ADMON_ONE) | (1u << FIXED_ADMON_PARTIAL);
    return v;
}

/* The weights of a variant over m sorted sets. */
EST_INLINE void fixed_weights(int variant, int m, const EstimatorParams *params, est_float *w)
{
    if (variant == FIXED_AMON)
        amon_weights(EST_FLOATS(params->amon_alpha), m, w);
    else if (variant == FIXED_ADMON)
        admon_weights(EST_FLOATS(params->admon_alpha), m, w);
    else if (variant == FIXED_TRIMMED)
        trim_weights(EST_INTS(sets_to_trim(params->trimmed_c, m)), m, w);
    else if (variant == FIXED_WINSORIZED)
        winsor_weights(sets_to_trim(params->winsorized_c, m), m, w);
    else if (variant == FIXED_MEAN)
        trim_weights(EST_INTS(0), m, w);
    else if (variant == FIXED_AMON_ONE)
        amon_weights(EST_FLOATS(1.0f), m, w);
    else if (variant == FIXED_AMON_PARTIAL)
        amon_weights(EST_FLOATS(params->gmon_partial_alpha), m, w);
    else if (variant == FIXED_ADMON_ONE)
        admon_weights(EST_FLOATS(1.0f), m, w);
    else
        admon_weights(EST_FLOATS(params->dmon_partial_alpha), m, w);
}

/* Channel c's estimates of the passes in PASSES_FIXED_WEIGHTS from the
 * values of their variants x[FIXED_*], the median and Gbar. */
EST_INLINE void fixed_weight_estimates(uint32_t passes, const est_float *x, est_float median, est_float gbar,
                                       const EstimatorParams *params, est_float (*value)[EST_CHANNELS], int c)
{
    if (passes & PASS_BIT(PASS_AMON))
        value[PASS_AMON][c] = x[FIXED_AMON];
    if (passes & PASS_BIT(PASS_ADMON))
        value[PASS_ADMON][c] = x[FIXED_ADMON];
    if (passes & PASS_BIT(PASS_TRIMMED))
        value[PASS_TRIMMED][c] = x[FIXED_TRIMMED];
    if (passes & PASS_BIT(PASS_WINSORIZED))
        value[PASS_WINSORIZED][c] = x[FIXED_WINSORIZED];
    if (passes & PASS_BIT(PASS_GMON_BINARY))
        value[PASS_GMON_BINARY][c] = gmon_binary_of(gbar, params, x[FIXED_MEAN], median);
    if (passes & PASS_BIT(PASS_GMON_PARTIAL))
        value[PASS_GMON_PARTIAL][c] = gmon_partial_of(gbar, params, x[FIXED_AMON_ONE], x[FIXED_AMON_PARTIAL]);
    if (passes & PASS_BIT(PASS_DMON_PARTIAL))
        value[PASS_DMON_PARTIAL][c] = dmon_partial_of(gbar, params, x[FIXED_ADMON_ONE], x[FIXED_ADMON_PARTIAL]);
}

/* The jackknife's leave-one-out estimates of a variant in O(m):
 * out[r] = weighted_sorted_average of the m - 1 ascending values left when
 * v[r] is removed, with the variant's weights w[0..m-2] for m - 1 sets.
 * The values below r keep their places and those above move down one, so
 * the weighted sum is a prefix, w[j] v[j] over j < r, plus a suffix,
 * w[j] v[j + 1] over j >= r: the suffixes are summed first (into out),
 * then each prefix is completed. Both compensated, on the scale and base of
 * all m values (weighted_sorted_average takes those of the m - 1): the
 * same to a few ulps of the values' range, not bit for bit. */
EST_INLINE void leave_one_out_averages(const est_float *v, int m, const est_float *w, est_float *out)
{
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e), up = power_of_two(e);
    est_float base = scaled(v[(m - 1) / 2], down);
    est_float total = EST_FLOATS(0.0f), total_compensation = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 0; j < m - 1; ++j)
        compensated_add(&total, &total_compensation, w[j]);
    total = total + total_compensation;
    est_float sum = EST_FLOATS(0.0f), compensation = EST_FLOATS(0.0f);
    out[m - 1] = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int r = m - 2; r >= 0; --r) {
        compensated_add(&sum, &compensation, w[r] * (scaled(v[r + 1], down) - base));
        out[r] = sum + compensation;
    }
    sum = EST_FLOATS(0.0f);
    compensation = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int r = 0; r < m; ++r) {
        est_float s = sum, sc = compensation;
        compensated_add(&s, &sc, out[r]);
        est_float lo = r == 0 ? v[1] : v[0], hi = r == m - 1 ? v[m - 2] : v[m - 1];
        out[r] = clamp_lanes(scaled(base + (s + sc) / total, up), lo, hi);
        if (r < m - 1)
            compensated_add(&sum, &compensation, w[r] * (scaled(v[r], down) - base));
    }
}

/* The of_sorted of the rows without one: never called. */
EST_INLINE est_float not_of_sorted(const est_float *v, int m, const EstimatorParams *params)
{
    (void)v;
    (void)m;
    (void)params;
    return EST_FLOATS(0.0f);
}

/* estimate_family's call of a TRAIT_OF_SORTED row's function on channel c
 * (s its sorted values), if requested (of_sorted_passes: PASSES_OF_SORTED
 * would expand GMON_PASSES within itself). */
#define ESTIMATE_OF_SORTED_(id, name, type, kind, traits, of_sorted)                                                   \
    if (of_sorted_passes & PASS_BIT(PASS_##id))                                                                        \
        value[PASS_##id][c] = of_sorted(s, m, params);

/* What the family shares in a pixel: the channels' G (the paper's, before
 * any Gini mode), the authors' G and the scales of the RGB points. */
typedef struct {
    est_float gbar;                /* mean of the channels' G */
    est_float authors_gbar;        /* the same with the authors' G */
    est_float down[EST_CHANNELS];  /* 2^-e_c, e_c a channel's scale exponent */
    est_float ratio[EST_CHANNELS]; /* 2^(e_c - e), e the largest e_c */
} FamilyShared;

/* The family's estimates of one pixel from its sorted values v[c][0..m-1]
 * and its values by set t[c][0..m-1], into value[pass][c] for the passes of
 * `passes` beyond mean, MoN, G-MoN and the diagnostics, unclamped and in
 * the units of v (before the division by the set count). gmedian starts
 * from z (its start on entry, each channel scaled by shared->down: the
 * channels' MoN)
 * and leaves its result there. */
EST_INLINE void estimate_family(const est_float (*v)[EST_CAPACITY], const est_float (*t)[EST_CAPACITY], int m,
                                uint32_t passes, const EstimatorParams *params, const FamilyShared *shared,
                                int iterations, est_float *z, est_float (*value)[EST_CHANNELS])
{
    const uint32_t of_sorted_passes = passes & PASSES_OF_SORTED;
    /* ggmon's and gmon-authors' weights follow Gbar, one per pixel: the
     * same for the three channels */
    est_float weights_ggmon[EST_CAPACITY], weights_authors[EST_CAPACITY];
    if (passes & PASS_BIT(PASS_GGMON))
        ggmon_weights(shared->gbar, m, weights_ggmon);
    if (passes & PASS_BIT(PASS_GMON_AUTHORS))
        gmon_authors_weights(shared->authors_gbar, m, weights_authors);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        const est_float *s = v[c];
        if (passes & PASS_BIT(PASS_GGMON))
            value[PASS_GGMON][c] = weighted_sorted_average(s, m, weights_ggmon);
        if (passes & PASSES_FIXED_WEIGHTS) {
            est_float x[FIXED_COUNT];
            EST_UNROLL
            for (int f = 0; f < FIXED_COUNT; ++f)
                if (fixed_variants(passes) & (1u << f)) {
                    est_float w[EST_CAPACITY];
                    fixed_weights(f, m, params, w);
                    x[f] = weighted_sorted_average(s, m, w);
                }
            fixed_weight_estimates(passes, x, median_of_sorted(s, m), shared->gbar, params, value, c);
        }
        if (passes & PASS_BIT(PASS_GMON_AUTHORS))
            value[PASS_GMON_AUTHORS][c] = weighted_sorted_average(s, m, weights_authors);
        GMON_PASSES(ESTIMATE_OF_SORTED_)
    }
    if (passes & PASS_BIT(PASS_GMEDIAN))
        gmedian_estimate(v, t, m, shared->down, shared->ratio, iterations, z, value[PASS_GMEDIAN]);
}

/* The G and MoN the family needs besides v and t, on m sets. */
EST_INLINE FamilyShared family_shared(const est_float (*v)[EST_CAPACITY], int m, uint32_t passes, est_float epsilon,
                                      est_float *gini, est_float *z)
{
    FamilyShared shared;
    shared.gbar = (gini[0] + gini[1] + gini[2]) / 3.0f;
    shared.authors_gbar = EST_FLOATS(0.0f);
    if (passes & PASS_BIT(PASS_GMON_AUTHORS))
        shared.authors_gbar =
            (gini_authors(v[0], m, epsilon) + gini_authors(v[1], m, epsilon) + gini_authors(v[2], m, epsilon)) / 3.0f;
    est_int e[EST_CHANNELS], largest = EST_INTS(-126);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        e[c] = sorted_range_exponent(v[c], 0, m - 1);
        largest = EST_SELECT(e[c] > largest, e[c], largest);
    }
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        shared.down[c] = power_of_two(-e[c]);
        shared.ratio[c] = scale_by_power(EST_FLOATS(1.0f), e[c] - largest); /* 0 far below the largest */
        z[c] = scaled(median_of_sorted(v[c], m), shared.down[c]);
    }
    return shared;
}

/* The paper's G of each channel of m sorted sets. */
EST_INLINE void channel_ginis(const est_float (*v)[EST_CAPACITY], int m, est_float *gini)
{
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        gini[c] = gini_of_sorted(v[c], m);
}

/* G-MoN (Gini per channel or per pixel) of m sorted sets, for the
 * jackknife. */
EST_INLINE void gmon_of_sorted_sets(const est_float (*v)[EST_CAPACITY], int m, int gini_mode, const est_float *gini,
                                    est_float (*value)[EST_CHANNELS])
{
    est_float gbar = (gini[0] + gini[1] + gini[2]) / 3.0f;
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        est_float g = gini_mode == EST_GINI_PER_PIXEL ? gbar : gini[c];
        value[PASS_GMON][c] = trimmed_average(v[c], m, trim_count(g, m), 1);
    }
}

/* Adds one leave-one-out estimate of each pass in `passes` (value, on the
 * scales `down`) to the jackknife's sums of differences to the first. */
EST_INLINE void jackknife_add(uint32_t passes, est_float (*value)[EST_CHANNELS], const est_float *down, int first,
                              est_float (*sum)[EST_CHANNELS], est_float (*squares)[EST_CHANNELS],
                              est_float (*origin)[EST_CHANNELS])
{
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p)
        if (passes & PASS_BIT(p)) {
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c) {
                est_float x = scaled(value[p][c], down[c]);
                if (first)
                    origin[p][c] = x;
                est_float d = x - origin[p][c];
                sum[p][c] += d;
                squares[p][c] += d * d;
            }
        }
}

/* Fewer than two sets: no error can be estimated (NaN). */
EST_INLINE void set_unknown_errors(LaneEstimates *out)
{
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c)
            out->error[p][c] = EST_FLOAT_FROM_BITS(EST_UINT_FROM_INT(EST_INTS(0x7fc00000)));
    }
}

/* Standard errors (docs/estimators.md, "Standard errors") of the
 * estimates in `passes` of a pixel of m >= 2 sets, sorted v, by set t, into
 * out->error, in the units of v (before the division by the set count).
 * The mean's: from the set means and counts. The others: the jackknife
 * over sets, each set left out in turn (its place in each channel's order
 * found by counting, so every lane follows the same steps), scaled by the
 * channel's power of two (no overflow). gmedian restarts from the full
 * estimate (gmedian_z, on the scales of `full`), with a quarter of the
 * iterations. */
EST_INLINE void standard_errors(const SetCounts *k, const est_float (*v)[EST_CAPACITY],
                                const est_float (*t)[EST_CAPACITY], int m, uint32_t passes, int gini_mode,
                                const EstimatorParams *params, est_float epsilon, const FamilyShared *full,
                                const est_float *gmedian_z, LaneEstimates *out)
{
    est_float down[EST_CHANNELS];
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        down[c] = power_of_two(-sorted_range_exponent(v[c], 0, m - 1));
    if (passes & PASS_BIT(PASS_MEAN)) {
        /* m / (m - 1) sum_j (n_j (t_j - mean))^2 / n^2, the set means by
         * set in t (with equal counts t holds sums, n_j = 1 and n = m in
         * its units) */
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            est_float mean = scaled(out->value[PASS_MEAN][c], down[c]);
            est_float squares = EST_FLOATS(0.0f);
            EST_UNROLL
            for (int j = 0; j < m; ++j) {
                float n_j = k->equal_counts ? 1.0f : (j < k->with_extra ? k->more : k->fewer);
                est_float deviation = n_j * (scaled(t[c][j], down[c]) - mean);
                squares += deviation * deviation;
            }
            float n = k->equal_counts ? (float)m : (float)k->sample_count;
            out->error[PASS_MEAN][c] = root_of(squares * ((float)m / (float)(m - 1)), 0) / n * (1.0f / down[c]);
        }
    }
    const uint32_t jackknifed = passes & PASSES_ESTIMATES & ~PASS_BIT(PASS_MEAN);
    if (!jackknifed)
        return;
    /* The spread of the leave-one-out estimates, accumulated as differences
     * to the first of them (which lies among them: the estimate from all
     * sets may not, e.g. admon's rule changes between even and odd m). */
    est_float sum[PASS_COUNT][EST_CHANNELS], squares[PASS_COUNT][EST_CHANNELS], origin[PASS_COUNT][EST_CHANNELS];
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            sum[p][c] = EST_FLOATS(0.0f);
            squares[p][c] = EST_FLOATS(0.0f);
            origin[p][c] = EST_FLOATS(0.0f);
        }
    }
    /* The passes by rank (MoN and the fixed-weight ones) depend on which
     * set is left out only through its rank in each channel, and on Gbar:
     * their leave-one-out estimates are taken by rank, after the loop over
     * the sets, which records each set's Gbar at its ranks. The others are
     * recomputed on each m - 1 sets. */
    const uint32_t by_rank = jackknifed & PASSES_BY_RANK, recomputed = jackknifed & ~PASSES_BY_RANK;
    const uint32_t gated = PASSES_GATED_BY_GBAR;
    est_float gbar_by_rank[EST_CHANNELS][EST_CAPACITY];
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        EST_UNROLL
        for (int j = 0; j < m; ++j)
            gbar_by_rank[c][j] = EST_FLOATS(0.0f);
    }
    const int iterations = params->gmedian_iterations / 4 > 1 ? params->gmedian_iterations / 4 : 1;
    /* gmedian's leave-one-out estimates start from the full estimate */
    WeiszfeldSums before[EST_CAPACITY + 1], after[EST_CAPACITY + 1];
    if (recomputed & PASS_BIT(PASS_GMEDIAN))
        gmedian_step_sums(t, m, full->down, full->ratio, gmedian_z, before, after);
    KERNEL_NO_UNROLL
    for (int left_out = 0; left_out < m && (recomputed || (jackknifed & gated)); ++left_out) {
        est_float rest_v[EST_CHANNELS][EST_CAPACITY], rest_t[EST_CHANNELS][EST_CAPACITY];
        est_int rank[EST_CHANNELS];
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            est_float x = t[c][0];
            EST_UNROLL
            for (int j = 1; j < m; ++j)
                x = EST_SELECT(j == left_out, t[c][j], x);
            /* its rank: the sets below it, and the equal ones before it */
            rank[c] = EST_INTS(0);
            EST_UNROLL
            for (int j = 0; j < m; ++j)
                rank[c] += EST_SELECT(j < left_out ? t[c][j] <= x : t[c][j] < x, EST_INTS(1), EST_INTS(0));
            EST_UNROLL
            for (int j = 0; j < m - 1; ++j) {
                rest_v[c][j] = EST_SELECT(j < rank[c], v[c][j], v[c][j + 1]);
                rest_t[c][j] = j < left_out ? t[c][j] : t[c][j + 1];
            }
        }
        est_float value[PASS_COUNT][EST_CHANNELS];
        est_float gini[EST_CHANNELS], z[EST_CHANNELS];
        channel_ginis((const est_float(*)[EST_CAPACITY])rest_v, m - 1, gini);
        if (recomputed & PASS_BIT(PASS_GMON))
            gmon_of_sorted_sets((const est_float(*)[EST_CAPACITY])rest_v, m - 1, gini_mode, gini, value);
        FamilyShared shared =
            family_shared((const est_float(*)[EST_CAPACITY])rest_v, m - 1, jackknifed, epsilon, gini, z);
        if (jackknifed & gated) {
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c) {
                EST_UNROLL
                for (int j = 0; j < m; ++j)
                    gbar_by_rank[c][j] = EST_SELECT(rank[c] == j, shared.gbar, gbar_by_rank[c][j]);
            }
        }
        /* gmedian on the full estimate's scales: its start need not lie
         * among the other sets, so it may not fit on theirs */
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            shared.down[c] = full->down[c];
            shared.ratio[c] = full->ratio[c];
            z[c] = gmedian_z[c];
        }
        if (recomputed & PASS_BIT(PASS_GMEDIAN))
            gmedian_first_step_without(before, after, left_out, z);
        estimate_family((const est_float(*)[EST_CAPACITY])rest_v, (const est_float(*)[EST_CAPACITY])rest_t, m - 1,
                        recomputed, params, &shared, iterations - 1, z, value);
        jackknife_add(recomputed, value, down, left_out == 0, sum, squares, origin);
    }
    if (by_rank) {
        /* each variant's leave-one-out estimates, by rank, in O(m) */
        const uint32_t variants = fixed_variants(by_rank);
        est_float averages[FIXED_COUNT][EST_CHANNELS][EST_CAPACITY];
        EST_UNROLL
        for (int f = 0; f < FIXED_COUNT; ++f)
            if (variants & (1u << f)) {
                est_float w[EST_CAPACITY];
                fixed_weights(f, m - 1, params, w);
                EST_UNROLL
                for (int c = 0; c < EST_CHANNELS; ++c)
                    leave_one_out_averages(v[c], m, w, averages[f][c]);
            }
        EST_UNROLL
        for (int r = 0; r < m; ++r) {
            est_float value[PASS_COUNT][EST_CHANNELS];
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c) {
                /* the median of the m - 1 left: the middle one or two, as
                 * median_of_sorted takes them */
                const int n = m - 1, low = (n - 1) / 2, high = n / 2;
                est_float middle[2] = {v[c][low + (low >= r)], v[c][high + (high >= r)]};
                est_float median = average_range(middle, 0, high - low, 1);
                value[PASS_MON][c] = median;
                est_float x[FIXED_COUNT];
                EST_UNROLL
                for (int f = 0; f < FIXED_COUNT; ++f)
                    x[f] = variants & (1u << f) ? averages[f][c][r] : EST_FLOATS(0.0f);
                fixed_weight_estimates(by_rank, x, median, gbar_by_rank[c][r], params, value, c);
            }
            jackknife_add(by_rank, value, down, r == 0, sum, squares, origin);
        }
    }
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p)
        if (jackknifed & PASS_BIT(p)) {
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c) {
                est_float spread = squares[p][c] - sum[p][c] * sum[p][c] / (float)m;
                spread = EST_SELECT(spread > 0.0f, spread, EST_FLOATS(0.0f));
                out->error[p][c] = root_of(spread * ((float)(m - 1) / (float)m), 0) * (1.0f / down[c]);
            }
        }
}

/* The passes of the family (beyond mean, MoN, G-MoN, diagnostics). */
EST_INLINE uint32_t family_passes(uint32_t passes)
{
    return passes & PASSES_FAMILY;
}

/* Whether an estimation needs a pixel's three channels at once: else each
 * channel is estimated alone (estimate_channel_alone). */
EST_INLINE int channels_together(uint32_t passes, int with_stderr, int gini_mode)
{
    return gini_mode != EST_GINI_PER_CHANNEL || family_passes(passes) != 0 || with_stderr;
}

/* Estimates EST_VECTOR_WIDTH pixels, one per lane.
 *   sums[c][j]    : sum of channel c over set j, j < set_count (any float)
 *   sample_count  : samples of each pixel; set j holds ceil((n - j) / M)
 *   set_count     : M, 1..EST_CAPACITY (in a kernel: EST_SETS)
 *   m             : min(sample_count, M), the non-empty sets (a parameter so
 *                   that a kernel can make it a constant: estimate_pixel
 *                   computes it)
 *   passes        : the passes to compute (passes.h)
 *   with_stderr   : also their standard errors (not with
 *                   EST_SORT_BY_LUMINANCE)
 *   gini_mode     : EST_GINI_PER_CHANNEL, EST_GINI_PER_PIXEL or
 *                   EST_SORT_BY_LUMINANCE (G-MoN and the diagnostics)
 *   params        : the family's parameters
 *   grid_exponent : the sums count units of 2^grid_exponent (0 for plain
 *                   float sums); only the authors' 1e-11 depends on it
 *   finite        : see estimate_channel
 * Results are in the units of the sums (finish_estimates scales them).
 * With only mean, MoN, G-MoN and diagnostics, in the default mode, a
 * channel needs only its own sums: a caller may run estimate_channel_alone
 * per channel instead (the same operations). */
EST_INLINE void estimate_lanes(est_float (*sums)[EST_CAPACITY], uint64_t sample_count, int set_count, int m,
                               uint32_t passes, int with_stderr, int gini_mode, const EstimatorParams *params,
                               est_int grid_exponent, int finite, LaneEstimates *out)
{
    clear_estimates(out);
    if (m == 0) {
        if (with_stderr)
            set_unknown_errors(out);
        return;
    }
    const SetCounts k = est_set_counts(sample_count, set_count, m);
    const uint32_t family = family_passes(passes);
    if (!channels_together(passes, with_stderr, gini_mode)) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c)
            estimate_channel_alone(&k, sums[c], finite, out, c);
        return;
    }

    est_float t[EST_CHANNELS][EST_CAPACITY];      /* set means by set */
    est_float sorted[EST_CHANNELS][EST_CAPACITY]; /* the same, ascending */
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        estimate_channel(&k, sums[c], finite, t[c], sorted[c], out, c);
    est_float paper_gini[EST_CHANNELS];
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        paper_gini[c] = out->value[PASS_GINI][c];
    /* The family and the errors work on the sorted sets, before G-MoN's
     * modes reorder them. 1e-11 in the units of the sums: */
    const est_float epsilon = scale_by_power(EST_FLOATS(1e-11f * k.divisor), -grid_exponent);
    est_float z[EST_CHANNELS];
    FamilyShared shared = family_shared((const est_float(*)[EST_CAPACITY])sorted, m, family, epsilon, paper_gini, z);
    estimate_family((const est_float(*)[EST_CAPACITY])sorted, (const est_float(*)[EST_CAPACITY])t, m, family, params,
                    &shared, params->gmedian_iterations, z, out->value);
    if (with_stderr) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->value[PASS_GMON][c] = trimmed_average(
                sorted[c], m, trim_count(gini_mode == EST_GINI_PER_PIXEL ? shared.gbar : paper_gini[c], m), 1);
        }
        if (m >= 2) {
            standard_errors(&k, (const est_float(*)[EST_CAPACITY])sorted, (const est_float(*)[EST_CAPACITY])t, m,
                            passes & PASSES_ESTIMATES, gini_mode, params, epsilon, &shared, z, out);
        } else {
            set_unknown_errors(out);
        }
        EST_UNROLL
        for (int p = 0; p < PASS_COUNT; ++p) {
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c)
                out->error[p][c] = out->error[p][c] / k.divisor;
        }
    }
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p)
        if (family & PASS_BIT(p)) {
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c)
                out->value[p][c] = finish_value(out->value[p][c], sorted[c][0], sorted[c][m - 1], k.divisor);
        }

    if (gini_mode == EST_GINI_PER_CHANNEL) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c)
            finish_channel(out, c, sorted[c], m, 1, k.divisor);
    } else if (gini_mode == EST_GINI_PER_PIXEL) {
        est_float g = shared.gbar;
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->value[PASS_GINI][c] = g;
            out->value[PASS_TRIM][c] = EST_FLOAT_FROM_INT(trim_count(g, m));
            finish_channel(out, c, sorted[c], m, 1, k.divisor);
        }
    } else if (gini_mode == EST_SORT_BY_LUMINANCE) {
        /* Luminance (Rec. 709) of each set, on one scale common to the
         * channels; sets are then ordered and trimmed whole. */
        est_int common = EST_INTS(0);
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            est_int e = sorted_range_exponent(sorted[c], 0, m - 1);
            common = c == 0 ? e : EST_SELECT(e > common, e, common);
        }
        est_float down = power_of_two(-common);
        est_float luma[EST_CAPACITY];
        EST_UNROLL
        for (int j = 0; j < set_count; ++j) {
            if (j < m) {
                luma[j] = EST_FLOATS(0.0f);
                luma[j] += 0.2126f * scaled(t[0][j], down);
                luma[j] += 0.7152f * scaled(t[1][j], down);
                luma[j] += 0.0722f * scaled(t[2][j], down);
            } else {
                luma[j] = EST_FLOATS(INFINITY);
            }
            EST_UNROLL
            for (int c = 0; c < EST_CHANNELS; ++c)
                sorted[c][j] = t[c][j];
        }
        EST_SORTING_NETWORK(set_count, EST_LUMINANCE_STEP)
        est_float g = gini_of_sorted(luma, m);
        /* Per channel the values now follow luminance order (not
         * ascending); the averages below accept any order. */
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->value[PASS_GINI][c] = g;
            out->value[PASS_TRIM][c] = EST_FLOAT_FROM_INT(trim_count(g, m));
            out->value[PASS_MON][c] = average_range(sorted[c], k.most, m - 1 - k.most, 0);
            finish_channel(out, c, sorted[c], m, 0, k.divisor);
        }
    }
}

#if EST_VECTOR_WIDTH == 1
/* The estimates of one pixel (estimate_lanes with one lane, the host's). */
typedef LaneEstimates PixelEstimates;
#endif

#endif /* host, or a kernel with EST_SETS */

#endif /* KERNELS_ESTIMATORS_H */
