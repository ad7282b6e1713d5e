/* The estimator core: per-set sample accumulation and the per-pixel
 * estimators (mean, MoN, G-MoN) of shared/ESTIMATORS.md.
 *
 * Valid C11 and OpenCL C 1.2. The host reference (host/estimator) and the
 * OpenCL kernels (kernels/estimator.cl, the path tracer) compile this one
 * file, so they agree bit for bit.
 *
 * In a kernel, EST_SETS (M) is a compile-time constant and sizes the private
 * arrays; the host compiles it with the maximum and passes M at run time. */
#ifndef KERNELS_ESTIMATOR_CORE_H
#define KERNELS_ESTIMATOR_CORE_H

#include "compat.h"

#define EST_MAX_SETS 64
#define EST_CHANNELS 3

#ifdef EST_SETS
#if EST_SETS < 1 || EST_SETS > EST_MAX_SETS
#error "EST_SETS (M) must be in 1..64"
#endif
#define EST_CAPACITY EST_SETS
#else
#define EST_CAPACITY EST_MAX_SETS
#endif

/* How G-MoN picks its trim count (ESTIMATORS.md, "Variants"). */
#define EST_GINI_PER_CHANNEL 0 /* default: one G and c per channel */
#define EST_GINI_PER_PIXEL 1   /* G = mean of the three channel G's */
#define EST_SORT_BY_LUMINANCE 2 /* order and trim whole RGB sets by luminance */

/* ------------------------------------------------------------------------
 * Set accumulation: exact fixed point.
 *
 * Each set sum (one per set and channel) is a signed 128-bit integer counting
 * units of 2^-56, held as two 64-bit words. A float sample is converted to
 * that grid (rounded to the nearest unit, ties away from zero) and added with
 * integer arithmetic, so sums are exact and associative: the result does not
 * depend on sample order, pass batching, devices or how sample ranges are
 * split and merged. Range: units of 1.4e-17, set sums below 2^71 (2.4e21).
 * Samples above EST_SAMPLE_LIMIT in magnitude (2^38, about 2.7e11; even 2^32
 * such samples cannot overflow a set) are treated like non-finite ones.
 * ---------------------------------------------------------------------- */

#define EST_FIXED_FRAC_BITS 56
#define EST_SAMPLE_LIMIT_EXPONENT 38 /* |sample| < 2^38 is accepted */

typedef struct {
    uint64_t lo;
    uint64_t hi; /* two's complement high word */
} FixedSum;

/* A float as a 128-bit fixed-point value. |x| must be below 2^71. */
KERNEL_FN FixedSum fixed_from_float(float x)
{
    uint32_t bits = float_bits(x);
    uint32_t biased_exponent = (bits >> 23) & 0xffu;
    uint64_t mantissa = bits & 0x7fffffu;
    if (biased_exponent != 0)
        mantissa |= 0x800000u;
    else
        biased_exponent = 1; /* denormal */
    /* x = mantissa * 2^(biased_exponent - 150); in units of 2^-56: */
    int shift = (int)biased_exponent - 150 + EST_FIXED_FRAC_BITS;
    FixedSum v;
    v.hi = 0;
    if (shift < 0) {
        int drop = -shift;
        v.lo = drop > 25 ? 0 : (mantissa + ((uint64_t)1 << (drop - 1))) >> drop;
    } else if (shift == 0) {
        v.lo = mantissa;
    } else if (shift < 64) {
        v.lo = mantissa << shift;
        v.hi = mantissa >> (64 - shift);
    } else {
        v.lo = 0;
        v.hi = mantissa << (shift - 64);
    }
    if (bits >> 31) {
        v.lo = ~v.lo + 1;
        v.hi = ~v.hi + (v.lo == 0 ? 1 : 0);
    }
    return v;
}

KERNEL_FN FixedSum fixed_add(FixedSum a, FixedSum b)
{
    FixedSum r;
    r.lo = a.lo + b.lo;
    r.hi = a.hi + b.hi + (r.lo < a.lo ? 1 : 0);
    return r;
}

/* True if any of the lowest `count` bits (0..127) of v are set. */
KERNEL_FN int fixed_low_bits_set(FixedSum v, int count)
{
    if (count <= 0)
        return 0;
    if (count < 64)
        return (v.lo & (((uint64_t)1 << count) - 1)) != 0;
    if (v.lo != 0)
        return 1;
    if (count == 64)
        return 0;
    return (v.hi & (((uint64_t)1 << (count - 64)) - 1)) != 0;
}

/* v >> count for count in 1..127, low word only (the caller needs 25 bits). */
KERNEL_FN uint64_t fixed_shift_right_low(FixedSum v, int count)
{
    if (count < 64)
        return (v.lo >> count) | (v.hi << (64 - count));
    return v.hi >> (count - 64);
}

/* The fixed-point value as the nearest float (ties to even). Done with
 * integer operations so every device rounds the same way. */
KERNEL_FN float fixed_to_float(FixedSum v)
{
    uint32_t sign = (uint32_t)(v.hi >> 63);
    if (sign) {
        v.lo = ~v.lo + 1;
        v.hi = ~v.hi + (v.lo == 0 ? 1 : 0);
    }
    if (v.hi == 0 && v.lo == 0)
        return 0.0f;
    int top = v.hi != 0 ? 127 - leading_zeros64(v.hi) : 63 - leading_zeros64(v.lo);
    uint32_t mantissa;
    if (top <= 23) {
        mantissa = (uint32_t)(v.lo << (23 - top));
    } else {
        int drop = top - 23;
        mantissa = (uint32_t)(fixed_shift_right_low(v, drop) & 0xffffffu);
        int round_bit = (int)((drop == 1 ? v.lo : fixed_shift_right_low(v, drop - 1)) & 1u);
        int sticky = fixed_low_bits_set(v, drop - 1);
        if (round_bit && (sticky || (mantissa & 1u))) {
            mantissa += 1;
            if (mantissa == 0x1000000u) {
                mantissa >>= 1;
                top += 1;
            }
        }
    }
    /* value = 1.m * 2^(top - 56); top <= 127 keeps it far from overflow. */
    uint32_t biased_exponent = (uint32_t)(top - EST_FIXED_FRAC_BITS + 127);
    return float_from_bits((sign << 31) | (biased_exponent << 23) | (mantissa & 0x7fffffu));
}

/* A sample is usable if every channel is finite and below the limit. */
KERNEL_FN int sample_is_usable(float r, float g, float b)
{
    const uint32_t limit_bits = (uint32_t)(127 + EST_SAMPLE_LIMIT_EXPONENT) << 23;
    return (float_bits(r) & 0x7fffffffu) < limit_bits && (float_bits(g) & 0x7fffffffu) < limit_bits &&
           (float_bits(b) & 0x7fffffffu) < limit_bits;
}

/* Sample index s goes to set s mod M (round robin). */
KERNEL_FN uint32_t set_of_sample(uint64_t sample_index, uint32_t set_count)
{
    return (uint32_t)(sample_index % set_count);
}

/* Index of one 64-bit word in an accumulation buffer laid out as planes
 * [set][channel][word][pixel], so neighbouring work items touch neighbouring
 * words. */
KERNEL_FN uint64_t accumulator_index(uint32_t set, uint32_t channel, uint32_t word, uint64_t pixel,
                                     uint64_t pixel_count)
{
    return ((uint64_t)(set * EST_CHANNELS + channel) * 2 + word) * pixel_count + pixel;
}

/* Adds one RGB sample to `set` of `pixel`. A non-finite or out-of-range
 * sample is added as 0 (it still counts as a sample) and reported by
 * returning 1, so the caller can count it. */
KERNEL_FN int accumulate_sample(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count,
                                uint32_t set, float r, float g, float b)
{
    int rejected = !sample_is_usable(r, g, b);
    if (rejected)
        return 1;
    float rgb[EST_CHANNELS];
    rgb[0] = r;
    rgb[1] = g;
    rgb[2] = b;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        uint64_t lo_index = accumulator_index(set, c, 0, pixel, pixel_count);
        uint64_t hi_index = accumulator_index(set, c, 1, pixel, pixel_count);
        FixedSum sum;
        sum.lo = accumulators[lo_index];
        sum.hi = accumulators[hi_index];
        sum = fixed_add(sum, fixed_from_float(rgb[c]));
        accumulators[lo_index] = sum.lo;
        accumulators[hi_index] = sum.hi;
    }
    return 0;
}

/* Index of one float in a set-sum buffer laid out as [set][channel][pixel]. */
KERNEL_FN uint64_t set_sum_index(uint32_t set, uint32_t channel, uint64_t pixel, uint64_t pixel_count)
{
    return (uint64_t)(set * EST_CHANNELS + channel) * pixel_count + pixel;
}

/* ------------------------------------------------------------------------
 * Per-pixel estimators.
 *
 * Numerically stable form (ESTIMATORS.md). Set means t_j = S_j / n_j are
 * kept as they are (a single scale for all sets would flush means 2^126
 * below the largest to zero, and 1e-30 and 1e30 can share a pixel). Each
 * sum instead scales the values it adds by the power of two that brings the
 * largest of them into [1, 2): exact, so nothing overflows even at FLT_MAX,
 * and results scale exactly with their inputs. Averages are computed as
 * base + mean(value - base) with a compensated sum, so equal means give that
 * value exactly; Gini's numerator pairs t_{m+1-j} - t_j, which never cancel.
 * ---------------------------------------------------------------------- */

typedef struct {
    float mean[EST_CHANNELS];
    float mon[EST_CHANNELS];
    float gmon[EST_CHANNELS];
    float gini[EST_CHANNELS]; /* G used for the trim, per channel */
    int32_t trim[EST_CHANNELS]; /* c: sets dropped at each end */
} PixelEstimates;

/* Neumaier's compensated sum. */
typedef struct {
    float sum;
    float compensation;
} CompensatedSum;

KERNEL_FN void compensated_add(CompensatedSum *s, float x)
{
    float t = s->sum + x;
    if (abs_float(s->sum) >= abs_float(x))
        s->compensation += (s->sum - t) + x;
    else
        s->compensation += (x - t) + s->sum;
    s->sum = t;
}

/* 2^k for k in -126..127, built from its bits (exact, no pow). */
KERNEL_FN float power_of_two(int k)
{
    return float_from_bits((uint32_t)(k + 127) << 23);
}

/* 2^k for k in -253..253 as two factors, each a float, whose product with x
 * (x * first * second) is exact when the result is normal. */
typedef struct {
    float first;
    float second;
} PowerOfTwo;

KERNEL_FN PowerOfTwo power_of_two_factors(int k)
{
    PowerOfTwo p;
    p.first = power_of_two(k > 127 ? 127 : (k < -126 ? -126 : k));
    p.second = power_of_two(k > 127 ? k - 127 : (k < -126 ? k + 126 : 0));
    return p;
}

KERNEL_FN float scaled(float x, PowerOfTwo p)
{
    return x * p.first * p.second;
}

/* floor(log2(a)) for finite a > 0, denormals included. */
KERNEL_FN int exponent_of(float a)
{
    uint32_t bits = float_bits(a) & 0x7fffffffu;
    int biased = (int)(bits >> 23);
    if (biased != 0)
        return biased - 127;
    /* denormal: mantissa * 2^-149 */
    return (63 - leading_zeros64((uint64_t)bits)) - 149;
}

/* floor(log2(max |v[j]|)) over first..last, or 0 if all are zero. */
KERNEL_FN int range_exponent(const float *v, int first, int last)
{
    float largest = 0.0f;
    for (int j = first; j <= last; ++j)
        largest = abs_float(v[j]) > largest ? abs_float(v[j]) : largest;
    return largest > 0.0f ? exponent_of(largest) : 0;
}

/* Mean of v[first..last] as v[first] + mean of the differences, on values
 * scaled so the largest lies in [1, 2). */
KERNEL_FN float average_range(const float *v, int first, int last)
{
    int e = range_exponent(v, first, last);
    PowerOfTwo down = power_of_two_factors(-e);
    float base = scaled(v[first], down);
    CompensatedSum s;
    s.sum = 0.0f;
    s.compensation = 0.0f;
    for (int j = first + 1; j <= last; ++j)
        compensated_add(&s, scaled(v[j], down) - base);
    return scaled(base + (s.sum + s.compensation) / (float)(last - first + 1), power_of_two_factors(e));
}

/* Sample-weighted mean of sorted set means, sum n_j t_j / n, scaled the same
 * way. */
KERNEL_FN float weighted_average(const float *v, const float *counts, int m, float total)
{
    int e = range_exponent(v, 0, m - 1);
    PowerOfTwo down = power_of_two_factors(-e);
    float base = scaled(v[0], down);
    CompensatedSum s;
    s.sum = 0.0f;
    s.compensation = 0.0f;
    for (int j = 1; j < m; ++j)
        compensated_add(&s, counts[j] * (scaled(v[j], down) - base));
    return scaled(base + (s.sum + s.compensation) / total, power_of_two_factors(e));
}

/* Gini coefficient of m ascending values, clamped to [0, 1]. G is scale
 * invariant: values are scaled so the largest magnitude lies in [1, 2).
 * Negative values shift everything by -t_1, which changes only the
 * denominator since the numerator is built from differences. */
KERNEL_FN float gini_sorted(const float *t, int m)
{
    if (m < 2)
        return 0.0f;
    PowerOfTwo down = power_of_two_factors(-range_exponent(t, 0, m - 1));
    float lowest = scaled(t[0], down);
    float shift = lowest < 0.0f ? lowest : 0.0f;
    float numerator = 0.0f;
    for (int j = 0; j < m / 2; ++j)
        numerator += (float)(m - 1 - 2 * j) * (scaled(t[m - 1 - j], down) - scaled(t[j], down));
    float total = 0.0f;
    for (int j = 0; j < m; ++j)
        total += scaled(t[j], down) - shift;
    float denominator = (float)m * total;
    if (!(denominator > 0.0f) || !(denominator < INFINITY))
        return 0.0f;
    float g = numerator / denominator;
    return g < 0.0f ? 0.0f : (g > 1.0f ? 1.0f : g);
}

/* c = floor(G * floor(m/2)), clamped so at least one set remains. */
KERNEL_FN int trim_count(float g, int m)
{
    int c = (int)(g * (float)(m / 2));
    int most = (m - 1) / 2;
    return c < 0 ? 0 : (c > most ? most : c);
}

/* Sorts values ascending, carrying a companion array along; ties are broken
 * by the companion so the result is independent of the input order. */
KERNEL_FN void sort_with_companion(float *v, float *companion, int m)
{
    for (int i = 1; i < m; ++i) {
        float key = v[i];
        float key2 = companion[i];
        int j = i - 1;
        while (j >= 0 && (v[j] > key || (v[j] == key && companion[j] > key2))) {
            v[j + 1] = v[j];
            companion[j + 1] = companion[j];
            --j;
        }
        v[j + 1] = key;
        companion[j + 1] = key2;
    }
}

/* Luminance order of sets: by luminance, ties by r, g, b, so the order does
 * not depend on how the sets were numbered. */
KERNEL_FN int luminance_before(float (*t)[EST_CAPACITY], const float *luma, int a, int b)
{
    if (luma[a] != luma[b])
        return luma[a] < luma[b];
    for (int c = 0; c < EST_CHANNELS; ++c)
        if (t[c][a] != t[c][b])
            return t[c][a] < t[c][b];
    return 0;
}

KERNEL_FN float clamp_float(float x, float lo, float hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* Estimates one pixel.
 *   sums[c][j]   : sum of channel c over set j, j < set_count (any float)
 *   sample_count : samples of this pixel; set j holds ceil((n - j) / M)
 *   set_count    : M, 1..EST_CAPACITY
 *   gini_mode    : EST_GINI_PER_CHANNEL, EST_GINI_PER_PIXEL or
 *                  EST_SORT_BY_LUMINANCE
 * Non-finite set sums (possible only in hand-made input) are read as 0. */
KERNEL_FN PixelEstimates estimate_pixel(float (*sums)[EST_CAPACITY], uint64_t sample_count, int set_count,
                                        int gini_mode)
{
    PixelEstimates out;
    for (int c = 0; c < EST_CHANNELS; ++c) {
        out.mean[c] = 0.0f;
        out.mon[c] = 0.0f;
        out.gmon[c] = 0.0f;
        out.gini[c] = 0.0f;
        out.trim[c] = 0;
    }
    /* Only the first m sets are non-empty; their counts are q or q + 1. */
    int few_samples = sample_count < (uint64_t)set_count;
    int m = few_samples ? (int)sample_count : set_count;
    if (m == 0)
        return out;
    uint64_t per_set = sample_count / (uint64_t)set_count;
    int with_extra = (int)(sample_count % (uint64_t)set_count);
    int equal_counts = few_samples || with_extra == 0;
    int most = (m - 1) / 2; /* largest trim */

    float t[EST_CHANNELS][EST_CAPACITY];      /* set means, by set */
    float sorted[EST_CHANNELS][EST_CAPACITY]; /* the same, ascending */
    float counts[EST_CAPACITY];               /* n_j, carried by the sort */

    for (int c = 0; c < EST_CHANNELS; ++c) {
        for (int j = 0; j < m; ++j) {
            float sum = (float_bits(sums[c][j]) & 0x7f800000u) == 0x7f800000u ? 0.0f : sums[c][j];
            counts[j] = few_samples ? 1.0f : (float)(per_set + (j < with_extra ? 1u : 0u));
            t[c][j] = sum / counts[j];
            sorted[c][j] = t[c][j];
        }
        sort_with_companion(sorted[c], counts, m);

        out.mean[c] = equal_counts ? average_range(sorted[c], 0, m - 1)
                                   : weighted_average(sorted[c], counts, m, (float)sample_count);
        out.mon[c] = average_range(sorted[c], most, m - 1 - most);
        out.gini[c] = gini_sorted(sorted[c], m);
        out.trim[c] = trim_count(out.gini[c], m);
    }

    if (gini_mode == EST_GINI_PER_PIXEL) {
        float g = (out.gini[0] + out.gini[1] + out.gini[2]) / 3.0f;
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out.gini[c] = g;
            out.trim[c] = trim_count(g, m);
        }
    } else if (gini_mode == EST_SORT_BY_LUMINANCE) {
        /* Luminance (Rec. 709) of each set, on one scale common to the
         * channels; sets are then ordered and trimmed whole. */
        int common = range_exponent(t[0], 0, m - 1);
        for (int c = 1; c < EST_CHANNELS; ++c) {
            int e = range_exponent(t[c], 0, m - 1);
            common = e > common ? e : common;
        }
        PowerOfTwo down = power_of_two_factors(-common);
        const float weight[EST_CHANNELS] = {0.2126f, 0.7152f, 0.0722f};
        float luma[EST_CAPACITY];
        int order[EST_CAPACITY];
        for (int j = 0; j < m; ++j) {
            luma[j] = 0.0f;
            for (int c = 0; c < EST_CHANNELS; ++c)
                luma[j] += weight[c] * scaled(t[c][j], down);
            order[j] = j;
        }
        for (int i = 1; i < m; ++i) {
            int key = order[i];
            int j = i - 1;
            while (j >= 0 && luminance_before(t, luma, key, order[j])) {
                order[j + 1] = order[j];
                --j;
            }
            order[j + 1] = key;
        }
        float luma_sorted[EST_CAPACITY];
        for (int j = 0; j < m; ++j)
            luma_sorted[j] = luma[order[j]];
        float g = gini_sorted(luma_sorted, m);
        /* Per channel the values now follow luminance order (not ascending);
         * the averages below accept any order. */
        for (int c = 0; c < EST_CHANNELS; ++c) {
            for (int j = 0; j < m; ++j)
                sorted[c][j] = t[c][order[j]];
            out.gini[c] = g;
            out.trim[c] = trim_count(g, m);
            out.mon[c] = average_range(sorted[c], most, m - 1 - most);
        }
    }

    for (int c = 0; c < EST_CHANNELS; ++c) {
        /* Averages of values lie within them; the clamp removes the last
         * ulp that rounding could add. */
        float lo = sorted[c][0], hi = sorted[c][0];
        for (int j = 1; j < m; ++j) {
            lo = sorted[c][j] < lo ? sorted[c][j] : lo;
            hi = sorted[c][j] > hi ? sorted[c][j] : hi;
        }
        out.mean[c] = clamp_float(out.mean[c], lo, hi);
        out.mon[c] = clamp_float(out.mon[c], lo, hi);
        out.gmon[c] = clamp_float(average_range(sorted[c], out.trim[c], m - 1 - out.trim[c]), lo, hi);
    }
    return out;
}

#endif /* KERNELS_ESTIMATOR_CORE_H */
