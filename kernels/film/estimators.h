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

/* What the family shares in a pixel (family_shared): the channels' mean
 * G (the paper's, before any Gini mode), the scales of the RGB points, and
 * gmedian's start and steps. */
typedef struct {
    est_float gbar;                /* mean of the channels' G */
    est_float epsilon;             /* 1e-11 in the units of the values (gmon-authors) */
    est_float down[EST_CHANNELS];  /* 2^-e_c, e_c a channel's scale exponent */
    est_float ratio[EST_CHANNELS]; /* 2^(e_c - e), e the largest e_c */
    est_float z[EST_CHANNELS];     /* gmedian's start (the channels' MoN on the scales down), then its result */
    int iterations;                /* gmedian's Weiszfeld steps */
} FamilyShared;

/* One side of a fixed-weight estimator (forms FIXED_WEIGHTS and GATED):
 * weights over the m sorted set means, or the median (MoN, exactly). */
typedef struct {
    est_float w[EST_CAPACITY];
    int median;
} FixedWeights;

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

/* The code below expands GMON_PASSES once per step, each row by its form:
 * FORM_STEP_(step, form, id, fn) becomes step##_FIXED(id, fn, sides),
 * step##_OF_SORTED(id, fn) or step##_WHOLE_PIXEL(id, fn) (each step defines
 * the three), so a row's fn is called only with its form's signature. */
#define FORM_STEP_(step, form, id, fn) FORM_STEP_##form(step, id, fn)
#define FORM_STEP_CORE(step, id, fn)
#define FORM_STEP_CORE_BY_RANK(step, id, fn)
#define FORM_STEP_SAMPLE(step, id, fn)
#define FORM_STEP_SAMPLE_NEIGHBOURHOOD(step, id, fn)
#define FORM_STEP_OF_SORTED(step, id, fn) step##_OF_SORTED(id, fn)
#define FORM_STEP_FIXED_WEIGHTS(step, id, fn) step##_FIXED(id, fn, 1)
#define FORM_STEP_GATED(step, id, fn) step##_FIXED(id, fn, 2)
#define FORM_STEP_WHOLE_PIXEL(step, id, fn) step##_WHOLE_PIXEL(id, fn)

/* The sides of every fixed-weight row: a gated one has two. */
#define FIXED_SIDES_(id, name, type, kind, form, fn)                                                                   \
    (FORM_HAS_(form, TRAIT_FIXED_WEIGHTS) ? (FORM_HAS_(form, TRAIT_WHOLE_PIXEL) ? 2 : 1) : 0) +
#define FIXED_SIDE_COUNT (GMON_PASSES(FIXED_SIDES_) 0)

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

/* estimate_family's steps. Per channel c, of its sorted values s and
 * median: */
#define FAMILY_CHANNEL_(id, name, type, kind, form, fn) FORM_STEP_(FAMILY_CHANNEL, form, id, fn)
#define FAMILY_CHANNEL_OF_SORTED(id, fn)                                                                               \
    if (passes & PASS_BIT(PASS_##id))                                                                                  \
        value[PASS_##id][c] = fn(s, m, params);
#define FAMILY_CHANNEL_FIXED(id, fn, sides)                                                                            \
    if (passes & PASS_BIT(PASS_##id)) {                                                                                \
        est_float x[2] = {EST_FLOATS(0.0f), EST_FLOATS(0.0f)};                                                         \
        float threshold = 0.0f;                                                                                        \
        EST_UNROLL                                                                                                     \
        for (int side = 0; side < (sides); ++side) {                                                                   \
            FixedWeights fixed;                                                                                        \
            fixed.median = 0;                                                                                          \
            threshold = fn(side, m, params, &fixed);                                                                   \
            x[side] = fixed.median ? median : weighted_sorted_average(s, m, fixed.w);                                  \
        }                                                                                                              \
        value[PASS_##id][c] = (sides) == 2 ? EST_SELECT(shared->gbar < threshold, x[0], x[1]) : x[0];                  \
    }
#define FAMILY_CHANNEL_WHOLE_PIXEL(id, fn)
/* Per pixel: */
#define FAMILY_PIXEL_(id, name, type, kind, form, fn) FORM_STEP_(FAMILY_PIXEL, form, id, fn)
#define FAMILY_PIXEL_OF_SORTED(id, fn)
#define FAMILY_PIXEL_FIXED(id, fn, sides)
#define FAMILY_PIXEL_WHOLE_PIXEL(id, fn)                                                                               \
    if (passes & PASS_BIT(PASS_##id))                                                                                  \
        fn(v, t, m, params, shared, value[PASS_##id]);

/* The family's estimates of one pixel from its sorted values v[c][0..m-1]
 * and its values by set t[c][0..m-1], into value[pass][c] for the passes of
 * `passes` beyond mean, MoN, G-MoN and the diagnostics, unclamped and in
 * the units of v (before the division by the set count), each by its
 * row's form (passes.h). */
EST_INLINE void estimate_family(const est_float (*v)[EST_CAPACITY], const est_float (*t)[EST_CAPACITY], int m,
                                uint32_t passes, const EstimatorParams *params, FamilyShared *shared,
                                est_float (*value)[EST_CHANNELS])
{
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        const est_float *s = v[c];
        const est_float median = median_of_sorted(s, m);
        GMON_PASSES(FAMILY_CHANNEL_)
    }
    GMON_PASSES(FAMILY_PIXEL_)
}

/* What the family shares on m sorted sets, from the channels' G:
 * gmedian's start is the channels' MoN, for `iterations` steps. */
EST_INLINE FamilyShared family_shared(const est_float (*v)[EST_CAPACITY], int m, est_float epsilon,
                                      const est_float *gini, int iterations)
{
    FamilyShared shared;
    shared.gbar = (gini[0] + gini[1] + gini[2]) / 3.0f;
    shared.epsilon = epsilon;
    shared.iterations = iterations;
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
        shared.z[c] = scaled(median_of_sorted(v[c], m), shared.down[c]);
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

/* standard_errors' steps for the fixed-weight rows, each side in its
 * slot: the leave-one-out estimates by rank of the sorted v (or the
 * median's), then at rank r of channel c the row's estimate. */
#define JACKKNIFE_WEIGHTS_(id, name, type, kind, form, fn) FORM_STEP_(JACKKNIFE_WEIGHTS, form, id, fn)
#define JACKKNIFE_WEIGHTS_OF_SORTED(id, fn)
#define JACKKNIFE_WEIGHTS_WHOLE_PIXEL(id, fn)
#define JACKKNIFE_WEIGHTS_FIXED(id, fn, sides)                                                                         \
    if (by_rank & PASS_BIT(PASS_##id)) {                                                                               \
        EST_UNROLL                                                                                                     \
        for (int side = 0; side < (sides); ++side) {                                                                   \
            FixedWeights fixed;                                                                                        \
            fixed.median = 0;                                                                                          \
            thresholds[slot + side] = fn(side, m - 1, params, &fixed);                                                 \
            medians[slot + side] = fixed.median;                                                                       \
            if (!fixed.median) {                                                                                       \
                EST_UNROLL                                                                                             \
                for (int c = 0; c < EST_CHANNELS; ++c)                                                                 \
                    leave_one_out_averages(v[c], m, fixed.w, averages[slot + side][c]);                                \
            }                                                                                                          \
        }                                                                                                              \
    }                                                                                                                  \
    slot += (sides);
#define JACKKNIFE_VALUE_(id, name, type, kind, form, fn) FORM_STEP_(JACKKNIFE_VALUE, form, id, fn)
#define JACKKNIFE_VALUE_OF_SORTED(id, fn)
#define JACKKNIFE_VALUE_WHOLE_PIXEL(id, fn)
#define JACKKNIFE_VALUE_FIXED(id, fn, sides)                                                                           \
    if (by_rank & PASS_BIT(PASS_##id)) {                                                                               \
        est_float x0 = medians[slot] ? median : averages[slot][c][r];                                                  \
        est_float x1 = (sides) == 2 && !medians[slot + (sides)-1] ? averages[slot + (sides)-1][c][r] : median;         \
        value[PASS_##id][c] = (sides) == 2 ? EST_SELECT(gbar_by_rank[c][r] < thresholds[slot], x0, x1) : x0;           \
    }                                                                                                                  \
    slot += (sides);

/* Standard errors (docs/estimators.md, "Standard errors") of the
 * estimates in `passes` of a pixel of m >= 2 sets, sorted v, by set t, into
 * out->error, in the units of v (before the division by the set count).
 * The mean's: from the set means and counts. The others: the jackknife
 * over sets, each set left out in turn (its place in each channel's order
 * found by counting, so every lane follows the same steps), scaled by the
 * channel's power of two (no overflow). gmedian restarts from the full
 * estimate (full->z, on the scales of `full`), with a quarter of the
 * iterations. */
EST_INLINE void standard_errors(const SetCounts *k, const est_float (*v)[EST_CAPACITY],
                                const est_float (*t)[EST_CAPACITY], int m, uint32_t passes, int gini_mode,
                                const EstimatorParams *params, est_float epsilon, const FamilyShared *full,
                                LaneEstimates *out)
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
        gmedian_step_sums(t, m, full->down, full->ratio, full->z, before, after);
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
        est_float gini[EST_CHANNELS];
        channel_ginis((const est_float(*)[EST_CAPACITY])rest_v, m - 1, gini);
        if (recomputed & PASS_BIT(PASS_GMON))
            gmon_of_sorted_sets((const est_float(*)[EST_CAPACITY])rest_v, m - 1, gini_mode, gini, value);
        /* gmedian's first step is taken below */
        FamilyShared shared =
            family_shared((const est_float(*)[EST_CAPACITY])rest_v, m - 1, epsilon, gini, iterations - 1);
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
            shared.z[c] = full->z[c];
        }
        if (recomputed & PASS_BIT(PASS_GMEDIAN))
            gmedian_first_step_without(before, after, left_out, shared.z);
        estimate_family((const est_float(*)[EST_CAPACITY])rest_v, (const est_float(*)[EST_CAPACITY])rest_t, m - 1,
                        recomputed, params, &shared, value);
        jackknife_add(recomputed, value, down, left_out == 0, sum, squares, origin);
    }
    if (by_rank) {
        /* each fixed-weight side's leave-one-out estimates, by rank, in
         * O(m), in slots by row */
        est_float averages[FIXED_SIDE_COUNT][EST_CHANNELS][EST_CAPACITY];
        float thresholds[FIXED_SIDE_COUNT];
        int medians[FIXED_SIDE_COUNT];
        int slot = 0;
        GMON_PASSES(JACKKNIFE_WEIGHTS_)
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
                slot = 0;
                GMON_PASSES(JACKKNIFE_VALUE_)
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
    FamilyShared shared =
        family_shared((const est_float(*)[EST_CAPACITY])sorted, m, epsilon, paper_gini, params->gmedian_iterations);
    estimate_family((const est_float(*)[EST_CAPACITY])sorted, (const est_float(*)[EST_CAPACITY])t, m, family, params,
                    &shared, out->value);
    if (with_stderr) {
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->value[PASS_GMON][c] = trimmed_average(
                sorted[c], m, trim_count(gini_mode == EST_GINI_PER_PIXEL ? shared.gbar : paper_gini[c], m), 1);
        }
        if (m >= 2) {
            standard_errors(&k, (const est_float(*)[EST_CAPACITY])sorted, (const est_float(*)[EST_CAPACITY])t, m,
                            passes & PASSES_ESTIMATES, gini_mode, params, epsilon, &shared, out);
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
