/* Numerics of the estimators: compensated sums, exact power-of-two
 * scaling, and averages of ranges that neither overflow nor cancel
 * (docs/estimators.md, "Stable Gini coefficient"), on lanes (lanes.h). Only
 * operations that round the same in C and OpenCL C: + - * / (correctly
 * rounded on both sides) and bit manipulation; no library exp, log, pow or
 * sqrt, whose results differ between implementations. */
#ifndef KERNELS_ESTIMATOR_NUMERICS_H
#define KERNELS_ESTIMATOR_NUMERICS_H

#include "../common/compat.h"
#include "lanes.h"

/* Neumaier's compensated sum: adds x to *sum and the rounding error of that
 * addition to *compensation. The error is found with Knuth's TwoSum, exact
 * without Neumaier's branch on |sum| >= |x|, so it is the same value. Adding
 * +0 changes neither (neither ever holds -0). */
EST_INLINE void compensated_add(est_float *sum, est_float *compensation, est_float x)
{
    est_float t = *sum + x;
    est_float z = t - *sum;
    *compensation += (*sum - (t - z)) + (x - z);
    *sum = t;
}

/* The same when |*sum| >= |x| or the addition is exact (Dekker's Fast2Sum
 * then gives the exact error in two operations): so for terms >= 0 added
 * largest first. */
EST_INLINE void compensated_add_smaller(est_float *sum, est_float *compensation, est_float x)
{
    est_float t = *sum + x;
    *compensation += (*sum - t) + x;
    *sum = t;
}

/* 2^k for k in -127..127, built from its bits (exact, no pow; 2^-127 is a
 * denormal). */
EST_INLINE est_float power_of_two(est_int k)
{
    return EST_FLOAT_FROM_BITS(
        EST_SELECT(k > -127, EST_UINT_FROM_INT(k + 127) << 23, EST_UINT_FROM_INT(EST_INTS(0x00400000))));
}

/* x * 2^e for the grid exponents (e in -252..253), in two exact steps
 * (only the last can round, when the result is denormal). */
EST_INLINE est_float scale_by_grid(est_float x, est_int e)
{
    est_int first = EST_SELECT(e < -126, EST_INTS(-126), EST_SELECT(e > 127, EST_INTS(127), e));
    est_int second = e - first;
    return x * power_of_two(first) * power_of_two(second);
}

/* The scale of a sum: it multiplies the values it adds by 2^-s, where
 * s = floor(log2(largest)) for the largest magnitude among them, clamped to
 * [-126, 127]. The largest scaled value then lies in [1, 2), or, when every
 * value is denormal or zero (largest < 2^-126), every scaled value is zero
 * or at least 2^-23, normal. 2^-s and 2^s are floats, so scaling is one
 * multiplication, exact wherever its result is normal. */
EST_INLINE est_int scale_exponent(est_float largest)
{
    est_int e = EST_INT_FROM_UINT(EST_FLOAT_BITS(largest) >> 23) - 127; /* largest >= 0 */
    return EST_SELECT(e < -126, EST_INTS(-126), e);
}

EST_INLINE est_float scaled(est_float x, est_float factor)
{
    return x * factor;
}

/* max(largest, |x|): one step of the largest magnitude of a range. */
EST_INLINE est_float larger_magnitude(est_float largest, est_float x)
{
    est_float a = EST_FLOAT_FROM_BITS(EST_FLOAT_BITS(x) & 0x7fffffffu); /* |x| */
    return EST_SELECT(a > largest, a, largest);
}

/* The scale exponent of an ascending range v[first..last]: its largest
 * magnitude is at one end. */
EST_INLINE est_int sorted_range_exponent(const est_float *v, int first, int last)
{
    return scale_exponent(larger_magnitude(larger_magnitude(EST_FLOATS(0.0f), v[first]), v[last]));
}

/* sum_{j = first+1..last} (v[j] * down - base), compensated. ascending: v
 * is sorted and base = v[first] * down, so the terms are >= 0 and grow with
 * j: they are added largest first. */
EST_INLINE est_float sum_of_differences(const est_float *v, int first, int last, est_float down, est_float base,
                                        int ascending)
{
    est_float sum = EST_FLOATS(0.0f), compensation = EST_FLOATS(0.0f);
    if (ascending) {
        EST_UNROLL
        for (int j = last; j > first; --j)
            compensated_add_smaller(&sum, &compensation, scaled(v[j], down) - base);
    } else {
        EST_UNROLL
        for (int j = first + 1; j <= last; ++j)
            compensated_add(&sum, &compensation, scaled(v[j], down) - base);
    }
    return sum + compensation;
}

/* Mean of v[first..last] as v[first] + mean of the differences, on values
 * scaled so the largest lies in [1, 2). ascending: v is sorted. */
EST_INLINE est_float average_range(const est_float *v, int first, int last, int ascending)
{
    /* One value: what the general form gives, exactly (the scalings are
     * exact for the largest value of a range, and base + 0 turns -0 into
     * +0). */
    if (first == last)
        return v[first] + 0.0f;
    est_float largest = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = first; j <= last; ++j)
        if (!ascending || j == first || j == last)
            largest = larger_magnitude(largest, v[j]);
    est_int e = scale_exponent(largest);
    est_float down = power_of_two(-e);
    est_float base = scaled(v[first], down);
    return scaled(base + sum_of_differences(v, first, last, down, base, ascending) / (float)(last - first + 1),
                  power_of_two(e));
}

/* Mean of v[c..m-1-c] in each lane, c being that lane's trim (0..(m-1)/2),
 * computed as average_range does: every set is visited, in the same order,
 * and those outside a lane's range add exact zeros. */
EST_INLINE est_float trimmed_average(const est_float *v, int m, est_int c, int ascending)
{
    const int most = (m - 1) / 2;
    est_float first = v[0], last = v[m - 1]; /* v[c], v[m-1-c] */
    EST_UNROLL
    for (int k = 1; k <= most; ++k) {
        est_mask here = c == k;
        first = EST_SELECT(here, v[k], first);
        last = EST_SELECT(here, v[m - 1 - k], last);
    }
    est_float largest = EST_FLOATS(0.0f);
    if (ascending) {
        largest = larger_magnitude(larger_magnitude(largest, first), last);
    } else {
        EST_UNROLL
        for (int j = 0; j < m; ++j) /* j in [c, m-1-c] */
            largest = EST_SELECT(c <= (j < m - 1 - j ? j : m - 1 - j), larger_magnitude(largest, v[j]), largest);
    }
    est_int e = scale_exponent(largest);
    est_float down = power_of_two(-e);
    est_float base = scaled(first, down);
    est_float sum = EST_FLOATS(0.0f), compensation = EST_FLOATS(0.0f);
    if (ascending) {
        EST_UNROLL
        for (int j = m - 1; j > 0; --j) /* j in [c + 1, m-1-c] */
            compensated_add_smaller(
                &sum, &compensation,
                EST_SELECT(c < (j < m - j ? j : m - j), scaled(v[j], down) - base, EST_FLOATS(0.0f)));
    } else {
        EST_UNROLL
        for (int j = 1; j < m; ++j) /* j in [c + 1, m-1-c] */
            compensated_add(&sum, &compensation,
                            EST_SELECT(c < (j < m - j ? j : m - j), scaled(v[j], down) - base, EST_FLOATS(0.0f)));
    }
    return scaled(base + (sum + compensation) / EST_FLOAT_FROM_INT(m - 2 * c), power_of_two(e));
}

/* Sample-weighted mean sum_j n_j t_j / n of the set means t_0..t_{m-1}
 * (sets j < with_extra hold `more` samples, the others `fewer`), as
 * lowest + sum_j n_j (t_j - lowest) / n, on values scaled the same way;
 * lowest and highest: the smallest and largest t_j. The terms are added in
 * set order (the counts belong to the sets), all >= 0, so none cancel. */
EST_INLINE est_float weighted_average(const est_float *t, int m, int with_extra, float more, float fewer, float total,
                                      est_float lowest, est_float highest)
{
    est_int e = scale_exponent(larger_magnitude(larger_magnitude(EST_FLOATS(0.0f), lowest), highest));
    est_float down = power_of_two(-e);
    est_float base = scaled(lowest, down);
    est_float sum = EST_FLOATS(0.0f), compensation = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 0; j < m; ++j)
        compensated_add(&sum, &compensation, (j < with_extra ? more : fewer) * (scaled(t[j], down) - base));
    return scaled(base + (sum + compensation) / total, power_of_two(e));
}

EST_INLINE est_float clamp_lanes(est_float x, est_float lo, est_float hi)
{
    return EST_SELECT(x < lo, lo, EST_SELECT(x > hi, hi, x));
}

#endif /* KERNELS_ESTIMATOR_NUMERICS_H */
