/* The estimator core: per-set sample accumulation and the per-pixel
 * estimators (mean, MoN, G-MoN) of shared/ESTIMATORS.md.
 *
 * Valid C11 and OpenCL C 1.2. The host reference (host/estimator) and the
 * OpenCL kernels (kernels/estimator.cl, the path tracer) compile this one
 * file, so they agree bit for bit.
 *
 * In a kernel, EST_SETS (M) is a compile-time constant and sizes the private
 * arrays; the host compiles it with the maximum and passes M at run time.
 * The estimators work on lanes (lanes.h): one pixel on the host, and
 * EST_VECTOR_WIDTH pixels per work item in a vector kernel. */
#ifndef KERNELS_ESTIMATOR_CORE_H
#define KERNELS_ESTIMATOR_CORE_H

#include "compat.h"
#include "lanes.h"
#include "sorting_networks.h"

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
#define EST_GINI_PER_CHANNEL 0  /* default: one G and c per channel */
#define EST_GINI_PER_PIXEL 1    /* G = mean of the three channel G's */
#define EST_SORT_BY_LUMINANCE 2 /* order and trim whole RGB sets by luminance */

/* ------------------------------------------------------------------------
 * Set accumulation: exact sums on a per-pixel grid.
 *
 * Each set sum (one per set and channel) is a signed 128-bit integer, two
 * 64-bit words, counting units of 2^E, where E, the pixel's grid exponent, is
 * shared by every sum of the pixel. E is at most the exponent of the lowest
 * set bit of every nonzero sample value the pixel has received, so every
 * sample is added exactly and the sums are exact: they do not depend on
 * sample order, pass batching, devices or how sample ranges are split and
 * merged. When a finer sample arrives, the pixel's sums shift left (exact).
 * accumulators_normalize then puts a pixel in its one canonical form (E as
 * high as the sums allow exactly), so that equal sums have equal bits
 * whatever the order that built them: the renderer does it before its sums
 * leave it, merging at the end of every merge (estimates do not need it:
 * the same values give the same estimates on any grid). Scaling every
 * sample by 2^k moves E by k and leaves the integers as they are, so
 * estimates scale by exactly 2^k.
 *
 * Sums stay below 2^EST_SUM_BITS in magnitude. A pixel whose values span
 * more binary orders than that holds (about 100 minus log2 of the samples
 * per set, from its finest to its largest value) cannot be summed exactly:
 * its grid then stops moving down, or moves up so that the largest value
 * fits, and samples are rounded onto it (to nearest, ties away from zero).
 * accumulate_sample reports each sample it could not add exactly
 * (EST_ADD_ROUNDED) so that renders count and report them; a non-finite
 * sample is not added and reported as EST_ADD_NONFINITE.
 *
 * Buffer layout, planes of pixel_count words: the grid plane (0 while the
 * pixel has no nonzero sample, else E + EST_GRID_BIAS), then
 * [set][channel][word], so that neighbouring work items touch neighbouring
 * words.
 * ---------------------------------------------------------------------- */

#define EST_SUM_BITS 126
#define EST_GRID_MARGIN 24
#define EST_GRID_BIAS 1024
#define EST_ADD_EXACT 0
#define EST_ADD_NONFINITE 1
#define EST_ADD_ROUNDED 2

typedef struct {
    uint64_t lo;
    uint64_t hi; /* two's complement high word */
} FixedSum;

/* 64-bit words per pixel in an accumulation buffer. */
KERNEL_FN uint32_t accumulator_planes(uint32_t set_count)
{
    return 1 + set_count * EST_CHANNELS * 2;
}

/* Index of a pixel's grid word. */
KERNEL_FN uint64_t grid_index(uint64_t pixel)
{
    return pixel;
}

/* Index of the low word of sum s = set * EST_CHANNELS + channel (the high
 * word is one plane further). */
KERNEL_FN uint64_t sum_index(uint32_t s, uint64_t pixel, uint64_t pixel_count)
{
    return ((uint64_t)s * 2 + 1) * pixel_count + pixel;
}

/* Index of one 64-bit word of a set sum. */
KERNEL_FN uint64_t accumulator_index(uint32_t set, uint32_t channel, uint32_t word, uint64_t pixel,
                                     uint64_t pixel_count)
{
    return sum_index(set * EST_CHANNELS + channel, pixel, pixel_count) + word * pixel_count;
}

/* The grid exponent E of a grid word (0 for a pixel without samples, whose
 * sums are all 0). */
KERNEL_FN int grid_exponent(uint64_t grid)
{
    return grid == 0 ? 0 : (int)grid - EST_GRID_BIAS;
}

/* The exponent of the last bit of a finite float's significand. */
KERNEL_FN int ulp_exponent(uint32_t bits)
{
    int biased = (int)((bits >> 23) & 0xffu);
    return (biased != 0 ? biased : 1) - 150;
}

/* The significand of a finite float as an integer: the value is it times
 * 2^ulp_exponent. */
KERNEL_FN uint64_t float_significand(uint32_t bits)
{
    return (bits & 0x7fffffu) | ((bits & 0x7f800000u) != 0 ? 0x800000u : 0u);
}

/* The exponent of the lowest set bit of a nonzero finite float. */
KERNEL_FN int lowest_bit_exponent(uint32_t bits)
{
    return ulp_exponent(bits) + trailing_zeros64(float_significand(bits));
}

/* Whether |v| reaches 2^EST_SUM_BITS (bits 127 and 126 differ). */
KERNEL_FN int fixed_too_wide(FixedSum v)
{
    return (int)(((v.hi ^ (v.hi << 1)) >> 63) != 0);
}

/* Bits needed for the magnitude of v: v lies in [-2^b, 2^b). */
KERNEL_FN int fixed_bits(FixedSum v)
{
    uint64_t sign = (uint64_t)((int64_t)v.hi >> 63);
    uint64_t hi = v.hi ^ sign, lo = v.lo ^ sign;
    return hi != 0 ? 128 - leading_zeros64(hi) : (lo != 0 ? 64 - leading_zeros64(lo) : 0);
}

KERNEL_FN FixedSum fixed_add(FixedSum a, FixedSum b)
{
    FixedSum r;
    r.lo = a.lo + b.lo;
    r.hi = a.hi + b.hi + (r.lo < a.lo ? 1 : 0);
    return r;
}

/* v * 2^d, d in 0..127 (the caller checks that it fits). */
KERNEL_FN FixedSum fixed_shift_left(FixedSum v, int d)
{
    FixedSum r;
    if (d == 0) {
        r = v;
    } else if (d < 64) {
        r.hi = (v.hi << d) | (v.lo >> (64 - d));
        r.lo = v.lo << d;
    } else {
        r.hi = v.lo << (d - 64);
        r.lo = 0;
    }
    return r;
}

/* v / 2^d rounded to nearest, ties toward +infinity, d >= 1; *inexact is set
 * if bits were lost. |v| < 2^127 - 2^126, so adding the half cannot wrap. */
KERNEL_FN FixedSum fixed_shift_right_rounded(FixedSum v, int d, int *inexact)
{
    FixedSum r;
    if (d >= 127) {
        *inexact |= v.lo != 0 || v.hi != 0;
        r.lo = 0;
        r.hi = 0;
        return r;
    }
    FixedSum one, minus_one;
    one.lo = 1;
    one.hi = 0;
    minus_one.lo = ~(uint64_t)0;
    minus_one.hi = ~(uint64_t)0;
    FixedSum rounding = fixed_shift_left(one, d - 1); /* half a unit of the result */
    FixedSum lost_mask = fixed_add(fixed_shift_left(rounding, 1), minus_one);
    *inexact |= (v.lo & lost_mask.lo) != 0 || (v.hi & lost_mask.hi) != 0;
    v = fixed_add(v, rounding);
    if (d < 64) {
        r.lo = (v.lo >> d) | (v.hi << (64 - d));
        r.hi = (uint64_t)((int64_t)v.hi >> d);
    } else {
        r.lo = (uint64_t)((int64_t)v.hi >> (d - 64));
        r.hi = (uint64_t)((int64_t)v.hi >> 63);
    }
    return r;
}

/* A finite float on the grid 2^grid_exponent, rounded to nearest (ties away
 * from zero; *inexact is set if bits were lost). The caller keeps
 * |x| < 2^(grid_exponent + EST_SUM_BITS). */
KERNEL_FN FixedSum fixed_from_float(float x, int grid_exponent, int *inexact)
{
    uint32_t bits = float_bits(x);
    uint64_t mantissa = float_significand(bits);
    int shift = ulp_exponent(bits) - grid_exponent;
    FixedSum v;
    if (shift >= 0) {
        v.lo = mantissa;
        v.hi = 0;
        v = fixed_shift_left(v, shift);
    } else {
        int drop = -shift;
        v.hi = 0;
        v.lo = drop > 25 ? 0 : (mantissa + ((uint64_t)1 << (drop - 1))) >> drop;
        *inexact |= drop > 25 ? mantissa != 0 : (mantissa & (((uint64_t)1 << drop) - 1)) != 0;
    }
    if (bits >> 31) {
        v.lo = ~v.lo + 1;
        v.hi = ~v.hi + (v.lo == 0 ? 1 : 0);
    }
    return v;
}

/* The fixed-point value (lo, hi) of each lane, as an integer count of grid
 * units, as the nearest float (ties to even). Integer-to-float conversion is
 * correctly rounded in C and OpenCL alike, so every device rounds the same
 * way: a magnitude below 2^64 is converted whole; a larger one as the 64
 * bits from its leading one (or the bit below it), with a sticky bit for the
 * rest (far below the float's last bit, so it rounds exactly as the whole
 * would). The power of two that scales the result back carries the sign;
 * the product is exact (results lie below 2^128). Branch-free, for vectors. */
EST_INLINE est_float fixed_to_float_lanes(est_ulong lo, est_ulong hi)
{
    est_uint sign = EST_UINT_FROM_ULONG(hi >> 32) & 0x80000000u;
    est_lmask negative = EST_LONG_FROM_ULONG(hi) < 0;
    est_ulong negated_lo = ~lo + 1u;
    est_ulong negated_hi = ~hi + EST_SELECT(lo == 0u, EST_ULONGS(1u), EST_ULONGS(0u));
    lo = EST_SELECT(negative, negated_lo, lo);
    hi = EST_SELECT(negative, negated_hi, hi);
    /* The window starts z bits below the top of hi: z = 63 - floor(log2(hi))
     * from hi as a float, which rounds up at most to the next power of two,
     * so z is hi's leading zeros or one less (a 63-bit window then). A lane
     * with hi = 0 computes a z it does not use (kept in 0..63: shifts by 64
     * or more are undefined in C). (lo >> 1) >> (63 - z) is lo >> (64 - z)
     * without a 64-bit shift. */
    est_float hi_float = EST_FLOAT_FROM_ULONG(hi);
    est_int z = 63 - (EST_INT_FROM_UINT(EST_FLOAT_BITS(hi_float) >> 23) - 127);
    z = EST_SELECT(z < 0, EST_INTS(0), z) & 63;
    est_ulong shift = EST_ULONG_FROM_INT(z);
    est_ulong window = (hi << shift) | ((lo >> 1) >> (63u - shift));
    est_ulong sticky = EST_SELECT((lo << shift) != 0u, EST_ULONGS(1u), EST_ULONGS(0u));
    est_ulong word = EST_SELECT(hi == 0u, lo, window | sticky);
    est_int exponent = EST_SELECT(hi_float == 0.0f, EST_INTS(0), 64 - z);
    return EST_FLOAT_FROM_ULONG(word) * EST_FLOAT_FROM_BITS(sign | (EST_UINT_FROM_INT(exponent + 127) << 23));
}

#if EST_VECTOR_WIDTH == 1
/* The fixed-point value in grid units as the nearest float (ties to even). */
KERNEL_FN float fixed_to_float(FixedSum v)
{
    return fixed_to_float_lanes(v.lo, v.hi);
}
#endif

/* A sample is usable if every channel is finite. */
KERNEL_FN int sample_is_finite(float r, float g, float b)
{
    const uint32_t infinity_bits = 0x7f800000u;
    return (float_bits(r) & 0x7fffffffu) < infinity_bits && (float_bits(g) & 0x7fffffffu) < infinity_bits &&
           (float_bits(b) & 0x7fffffffu) < infinity_bits;
}

/* Sample index s goes to set s mod M (round robin). */
KERNEL_FN uint32_t set_of_sample(uint64_t sample_index, uint32_t set_count)
{
    return (uint32_t)(sample_index % set_count);
}

KERNEL_FN FixedSum load_sum(GLOBAL const uint64_t *accumulators, uint64_t lo_index, uint64_t pixel_count)
{
    FixedSum s;
    s.lo = accumulators[lo_index];
    s.hi = accumulators[lo_index + pixel_count];
    return s;
}

KERNEL_FN void store_sum(GLOBAL uint64_t *accumulators, uint64_t lo_index, uint64_t pixel_count, FixedSum s)
{
    accumulators[lo_index] = s.lo;
    accumulators[lo_index + pixel_count] = s.hi;
}

/* Moves a pixel's grid down by up to d bits (shifting its sums left, exact)
 * as far as its largest sum allows; returns the bits moved. */
KERNEL_COLD_FN int grid_refine(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                               int d)
{
    int widest = 0;
    KERNEL_NO_UNROLL
    for (uint32_t s = 0; s < set_count * EST_CHANNELS; ++s) {
        int bits = fixed_bits(load_sum(accumulators, sum_index(s, pixel, pixel_count), pixel_count));
        widest = bits > widest ? bits : widest;
    }
    int room = EST_SUM_BITS - widest;
    d = d < room ? d : room;
    if (d > 0)
        KERNEL_NO_UNROLL
    for (uint32_t s = 0; s < set_count * EST_CHANNELS; ++s) {
        uint64_t i = sum_index(s, pixel, pixel_count);
        store_sum(accumulators, i, pixel_count, fixed_shift_left(load_sum(accumulators, i, pixel_count), d));
    }
    return d > 0 ? d : 0;
}

/* Moves a pixel's grid up by d >= 1 bits (shifting its sums right,
 * rounded); returns 1 if that lost bits. */
KERNEL_COLD_FN int grid_coarsen(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                                int d)
{
    int inexact = 0;
    KERNEL_NO_UNROLL
    for (uint32_t s = 0; s < set_count * EST_CHANNELS; ++s) {
        uint64_t i = sum_index(s, pixel, pixel_count);
        store_sum(accumulators, i, pixel_count,
                  fixed_shift_right_rounded(load_sum(accumulators, i, pixel_count), d, &inexact));
    }
    return inexact;
}

/* accumulate_sample for a finite sample, any case. */
KERNEL_COLD_FN int accumulate_sample_in_general(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count,
                                                uint32_t set_count, uint32_t set, float r, float g, float b)
{
    float rgb[EST_CHANNELS];
    rgb[0] = r;
    rgb[1] = g;
    rgb[2] = b;
    /* The sample's finest bit and the bound of its magnitude: |x| < 2^top. */
    int finest = 0, top = 0, nonzero = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        uint32_t bits = float_bits(rgb[c]);
        if ((bits & 0x7fffffffu) == 0)
            continue;
        int lowest = lowest_bit_exponent(bits), bound = ulp_exponent(bits) + 24;
        finest = nonzero && finest < lowest ? finest : lowest;
        top = nonzero && top > bound ? top : bound;
        nonzero = 1;
    }
    if (!nonzero)
        return EST_ADD_EXACT;
    /* A new grid, or a finer one, goes EST_GRID_MARGIN bits further down
     * than this sample needs (where the sums leave room), so that the next
     * slightly finer samples need not shift every sum again: a pixel's
     * finest value keeps improving (on a new minimum, about ln n times in n
     * samples), and each shift touches all 3M sums. */
    uint64_t grid = accumulators[grid_index(pixel)];
    int target = finest - EST_GRID_MARGIN;
    int exponent = grid == 0 ? target : grid_exponent(grid);
    if (finest < exponent)
        exponent -= grid_refine(accumulators, pixel, pixel_count, set_count, exponent - target);
    /* Keep the sample below 2^(EST_SUM_BITS - 1) units, so that it and a
     * sum below 2^EST_SUM_BITS cannot wrap 128 bits. */
    int inexact = 0;
    if (top - exponent > EST_SUM_BITS - 1) {
        int d = top - exponent - (EST_SUM_BITS - 1);
        inexact |= grid_coarsen(accumulators, pixel, pixel_count, set_count, d);
        exponent += d;
    }
    int too_wide = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        if ((float_bits(rgb[c]) & 0x7fffffffu) == 0)
            continue;
        uint64_t i = accumulator_index(set, c, 0, pixel, pixel_count);
        FixedSum sum = fixed_add(load_sum(accumulators, i, pixel_count), fixed_from_float(rgb[c], exponent, &inexact));
        store_sum(accumulators, i, pixel_count, sum);
        too_wide |= fixed_too_wide(sum);
    }
    if (too_wide) {
        inexact |= grid_coarsen(accumulators, pixel, pixel_count, set_count, 1);
        exponent += 1;
    }
    if ((uint64_t)(exponent + EST_GRID_BIAS) != grid)
        accumulators[grid_index(pixel)] = (uint64_t)(exponent + EST_GRID_BIAS);
    return inexact ? EST_ADD_ROUNDED : EST_ADD_EXACT;
}

/* A value as a count of units 2^grid_exponent, if it is such a count and
 * below 2^(EST_SUM_BITS - 1) in magnitude (else *fits becomes 0), as nearly
 * every sample is once a pixel has its grid. */
KERNEL_FN FixedSum value_on_grid(float x, int grid_exponent, int *fits)
{
    /* The value is significand * 2^shift units, below 2^(shift + 24). */
    int shift = ulp_exponent(float_bits(x)) - grid_exponent;
    FixedSum v;
    v.lo = 0;
    v.hi = 0;
    if ((float_bits(x) & 0x7fffffffu) == 0) /* +-0 lies on every grid */
        return v;
    if (shift < -23 || shift + 24 > EST_SUM_BITS - 1) {
        *fits = 0;
        return v;
    }
    int inexact = 0;
    v = fixed_from_float(x, grid_exponent, &inexact);
    *fits &= !inexact;
    return v;
}

/* Adds one RGB sample to `set` of `pixel` (set_count sets). Returns
 * EST_ADD_EXACT, EST_ADD_ROUNDED (added, but not exactly: see above) or
 * EST_ADD_NONFINITE (not added; it still counts as a sample, as 0). The
 * common case, every value on the pixel's grid, is one 128-bit addend a
 * channel; the rest (a new pixel, a finer or much larger value) is
 * accumulate_sample_in_general, with the same result. */
KERNEL_FN int accumulate_sample(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                                uint32_t set, float r, float g, float b)
{
    if (!sample_is_finite(r, g, b))
        return EST_ADD_NONFINITE;
    uint64_t grid = accumulators[grid_index(pixel)];
    int exponent = grid_exponent(grid), fits = grid != 0;
    FixedSum values[EST_CHANNELS];
    values[0] = value_on_grid(r, exponent, &fits);
    values[1] = value_on_grid(g, exponent, &fits);
    values[2] = value_on_grid(b, exponent, &fits);
    if (!fits)
        return accumulate_sample_in_general(accumulators, pixel, pixel_count, set_count, set, r, g, b);
    int too_wide = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        uint64_t i = accumulator_index(set, c, 0, pixel, pixel_count);
        FixedSum sum = fixed_add(load_sum(accumulators, i, pixel_count), values[c]);
        store_sum(accumulators, i, pixel_count, sum);
        too_wide |= fixed_too_wide(sum);
    }
    if (!too_wide)
        return EST_ADD_EXACT;
    int inexact = grid_coarsen(accumulators, pixel, pixel_count, set_count, 1);
    accumulators[grid_index(pixel)] = grid + 1;
    return inexact ? EST_ADD_ROUNDED : EST_ADD_EXACT;
}

/* Puts a pixel's sums in their canonical form: its grid moved up by the
 * trailing zero bits all its sums share (exact), or no grid when they are
 * all 0. Equal sums then have equal bits. */
KERNEL_FN void accumulators_normalize(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count,
                                      uint32_t set_count)
{
    uint64_t grid = accumulators[grid_index(pixel)];
    if (grid == 0)
        return;
    int zeros = 128; /* trailing zeros shared by every sum */
    KERNEL_NO_UNROLL
    for (uint32_t s = 0; s < set_count * EST_CHANNELS; ++s) {
        FixedSum v = load_sum(accumulators, sum_index(s, pixel, pixel_count), pixel_count);
        int here = v.lo != 0 ? trailing_zeros64(v.lo) : (v.hi != 0 ? 64 + trailing_zeros64(v.hi) : 128);
        zeros = here < zeros ? here : zeros;
    }
    if (zeros == 128) {
        accumulators[grid_index(pixel)] = 0;
        return;
    }
    if (zeros == 0)
        return;
    grid_coarsen(accumulators, pixel, pixel_count, set_count, zeros); /* exact: only zero bits go */
    accumulators[grid_index(pixel)] = grid + (uint64_t)zeros;
}

/* Adds the sums of pixel `pixel` of `part` (same layout and set count) to
 * those of `total`, both modified: the grids are brought to the finer one
 * where the sums allow (exact), else to the coarser (rounded). Returns 1 if
 * the result is not exact. For merging renders of sample ranges. */
KERNEL_FN int accumulators_merge_pixel(GLOBAL uint64_t *total, GLOBAL uint64_t *part, uint64_t pixel,
                                       uint64_t pixel_count, uint32_t set_count)
{
    uint64_t part_grid = part[grid_index(pixel)], total_grid = total[grid_index(pixel)];
    if (part_grid == 0)
        return 0;
    int exponent = grid_exponent(part_grid);
    int inexact = 0;
    if (total_grid != 0) {
        int a = grid_exponent(total_grid), b = exponent;
        if (a > b)
            a -= grid_refine(total, pixel, pixel_count, set_count, a - b);
        else if (b > a)
            b -= grid_refine(part, pixel, pixel_count, set_count, b - a);
        if (a > b)
            inexact |= grid_coarsen(part, pixel, pixel_count, set_count, a - b);
        else if (b > a)
            inexact |= grid_coarsen(total, pixel, pixel_count, set_count, b - a);
        exponent = a > b ? a : b;
    }
    int too_wide = 0;
    KERNEL_NO_UNROLL
    for (uint32_t s = 0; s < set_count * EST_CHANNELS; ++s) {
        uint64_t i = sum_index(s, pixel, pixel_count);
        FixedSum sum = fixed_add(load_sum(total, i, pixel_count), load_sum(part, i, pixel_count));
        store_sum(total, i, pixel_count, sum);
        too_wide |= fixed_too_wide(sum);
    }
    if (too_wide) {
        inexact |= grid_coarsen(total, pixel, pixel_count, set_count, 1);
        exponent += 1;
    }
    total[grid_index(pixel)] = (uint64_t)(exponent + EST_GRID_BIAS);
    accumulators_normalize(total, pixel, pixel_count, set_count);
    return inexact;
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

/* The estimates of EST_VECTOR_WIDTH pixels, one per lane. */
typedef struct {
    est_float mean[EST_CHANNELS];
    est_float mon[EST_CHANNELS];
    est_float gmon[EST_CHANNELS];
    est_float gini[EST_CHANNELS]; /* G used for the trim, per channel */
    est_int trim[EST_CHANNELS];   /* c: sets dropped at each end */
} LaneEstimates;

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

/* Estimates computed on sums in grid units, scaled to the pixel's values. */
EST_INLINE void estimates_to_grid(LaneEstimates *out, est_int grid_exponent)
{
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        out->mean[c] = scale_by_grid(out->mean[c], grid_exponent);
        out->mon[c] = scale_by_grid(out->mon[c], grid_exponent);
        out->gmon[c] = scale_by_grid(out->gmon[c], grid_exponent);
    }
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

/* Gini coefficient of m ascending values t, clamped to [0, 1]. G is scale
 * invariant: values are scaled by `down` (from sorted_range_exponent(t, 0,
 * m - 1)) so the largest magnitude lies in [1, 2); lowest = t[0] * down and
 * differences = sum_of_differences(t, 0, m - 1, down, lowest, 1), which the
 * mean shares. Negative values shift everything by -t_1, which changes only
 * the denominator (sum_j (t_j - shift) = differences + m (t_1 - shift)),
 * since the numerator is built from differences. */
EST_INLINE est_float gini_sorted(const est_float *t, int m, est_float down, est_float lowest, est_float differences)
{
    if (m < 2)
        return EST_FLOATS(0.0f);
    est_float shift = EST_SELECT(lowest < 0.0f, lowest, EST_FLOATS(0.0f));
    est_float numerator = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 0; j < m / 2; ++j)
        numerator += (float)(m - 1 - 2 * j) * (scaled(t[m - 1 - j], down) - scaled(t[j], down));
    est_float total = differences + (float)m * (lowest - shift);
    est_float denominator = (float)m * total;
    est_float g = numerator / denominator;
    g = EST_SELECT(g < 0.0f, EST_FLOATS(0.0f), EST_SELECT(g > 1.0f, EST_FLOATS(1.0f), g));
    return EST_SELECT((denominator > 0.0f) & (denominator < INFINITY), g, EST_FLOATS(0.0f));
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

EST_INLINE est_float clamp_lanes(est_float x, est_float lo, est_float hi)
{
    return EST_SELECT(x < lo, lo, EST_SELECT(x > hi, hi, x));
}

/* A comparator: orders v[i] <= v[j]. */
EST_INLINE void compare_exchange(est_float *v, int i, int j)
{
    est_float a = v[i], b = v[j];
    est_mask swap = a > b;
    v[i] = EST_SELECT(swap, b, a);
    v[j] = EST_SELECT(swap, a, b);
}

/* A comparator on whole sets: by luminance, ties by r, g, b (so the order
 * does not depend on how the sets were numbered); the channels follow. */
EST_INLINE void compare_exchange_luminance(est_float *luma, est_float (*t)[EST_CAPACITY], int i, int j)
{
    est_mask swap = (luma[j] < luma[i]) |
                    ((luma[j] == luma[i]) &
                     ((t[0][j] < t[0][i]) |
                      ((t[0][j] == t[0][i]) & ((t[1][j] < t[1][i]) | ((t[1][j] == t[1][i]) & (t[2][j] < t[2][i]))))));
    est_float a = luma[i], b = luma[j];
    luma[i] = EST_SELECT(swap, b, a);
    luma[j] = EST_SELECT(swap, a, b);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        a = t[c][i];
        b = t[c][j];
        t[c][i] = EST_SELECT(swap, b, a);
        t[c][j] = EST_SELECT(swap, a, b);
    }
}

/* EST_SORTING_NETWORK(set_count, COMPARATOR) runs COMPARATOR(i, j) over the
 * sorting network for set_count values: the same comparators in the same
 * order everywhere. A kernel (set_count must be EST_SETS) expands them
 * inline with constant indices, or, past EST_UNROLL_MAX_SETS, loops over a
 * table of them as the host does (which looks its network up at run time). */
#define EST_NETWORK_PAIR(i, j) {i, j},
#if defined(EST_SETS) && EST_SETS <= EST_UNROLL_MAX_SETS
#define EST_SORTING_NETWORK(set_count, COMPARATOR) EST_PASTE(EST_NETWORK_, EST_SETS)(COMPARATOR)
#else
#ifdef EST_SETS
__constant uchar est_network_pairs[][2] = {EST_PASTE(EST_NETWORK_, EST_SETS)(EST_NETWORK_PAIR)};
#define EST_NETWORK_LENGTH (int)(sizeof est_network_pairs / sizeof est_network_pairs[0])
#define EST_NETWORK_PAIRS(set_count, length) (*(length) = EST_NETWORK_LENGTH, est_network_pairs)
#define EST_NETWORK_TABLE __constant uchar
#else
/* The comparators of the network for set_count values (1..64). */
EST_INLINE const uint8_t (*sorting_network(int set_count, int *length))[2]
{
    static const uint8_t pairs[][2] = {EST_ALL_NETWORKS(EST_NETWORK_PAIR)};
    static const int start[EST_MAX_SETS + 1] = {EST_NETWORK_START};
    *length = start[set_count] - start[set_count - 1];
    return pairs + start[set_count - 1];
}
#define EST_NETWORK_PAIRS(set_count, length) sorting_network(set_count, length)
#define EST_NETWORK_TABLE const uint8_t
#endif

#define EST_SORTING_NETWORK(set_count, COMPARATOR)                                                                     \
    {                                                                                                                  \
        int length_;                                                                                                   \
        EST_NETWORK_TABLE(*pairs_)[2] = EST_NETWORK_PAIRS(set_count, &length_);                                        \
        for (int k_ = 0; k_ < length_; ++k_)                                                                           \
            COMPARATOR(pairs_[k_][0], pairs_[k_][1])                                                                   \
    }
#endif

/* Clamps the channel's mean and MoN and computes its G-MoN (with the trim
 * already in out->trim[c]) from its set means v[0..m-1] (ascending: sorted),
 * then divides all three by divisor (see SetCounts). */
EST_INLINE void finish_channel(LaneEstimates *out, int c, const est_float *v, int m, int ascending, float divisor)
{
    /* Averages of values lie within them; the clamp removes the last ulp
     * that rounding could add. */
    est_float lo = v[0], hi = v[m - 1];
    if (!ascending) {
        hi = v[0];
        EST_UNROLL
        for (int j = 1; j < m; ++j) {
            lo = EST_SELECT(v[j] < lo, v[j], lo);
            hi = EST_SELECT(v[j] > hi, v[j], hi);
        }
    }
    out->mean[c] = clamp_lanes(out->mean[c], lo, hi) / divisor;
    out->mon[c] = clamp_lanes(out->mon[c], lo, hi) / divisor;
    out->gmon[c] = clamp_lanes(trimmed_average(v, m, out->trim[c], ascending), lo, hi) / divisor;
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
    if (!k->equal_counts) {
        /* The weighted mean, in set order, first: the means by set are then
         * not needed past the sort (but in luminance mode). */
        EST_UNROLL
        for (int j = 0; j < m; ++j)
            t[j] = t[j] / (j < k->with_extra ? k->more : k->fewer);
        est_float lo = t[0], hi = t[0];
        EST_UNROLL
        for (int j = 1; j < m; ++j) {
            lo = EST_SELECT(t[j] < lo, t[j], lo);
            hi = EST_SELECT(t[j] > hi, t[j], hi);
        }
        out->mean[c] = weighted_average(t, m, k->with_extra, k->more, k->fewer, (float)k->sample_count, lo, hi);
    }
    EST_UNROLL
    for (int j = 0; j < k->set_count; ++j)
        v[j] = t[j];
    EST_SORTING_NETWORK(k->set_count, EST_SORT_STEP)

    /* The mean (average_range(v, 0, m - 1, 1) with equal counts) and G share
     * the scaled differences. */
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float lowest = scaled(v[0], down);
    est_float differences = sum_of_differences(v, 0, m - 1, down, lowest, 1);
    if (k->equal_counts)
        out->mean[c] = scaled(lowest + differences / (float)m, power_of_two(e));
    out->mon[c] = average_range(v, k->most, m - 1 - k->most, 1);
    out->gini[c] = gini_sorted(v, m, down, lowest, differences);
    out->trim[c] = trim_count(out->gini[c], m);
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
    for (int c = 0; c < EST_CHANNELS; ++c) {
        out->mean[c] = EST_FLOATS(0.0f);
        out->mon[c] = EST_FLOATS(0.0f);
        out->gmon[c] = EST_FLOATS(0.0f);
        out->gini[c] = EST_FLOATS(0.0f);
        out->trim[c] = EST_INTS(0);
    }
}

/* Estimates EST_VECTOR_WIDTH pixels, one per lane.
 *   sums[c][j]   : sum of channel c over set j, j < set_count (any float)
 *   sample_count : samples of each pixel; set j holds ceil((n - j) / M)
 *   set_count    : M, 1..EST_CAPACITY (in a kernel: EST_SETS)
 *   m            : min(sample_count, M), the non-empty sets (a parameter so
 *                  that a kernel can make it a constant: estimate_pixel
 *                  computes it)
 *   gini_mode    : EST_GINI_PER_CHANNEL, EST_GINI_PER_PIXEL or
 *                  EST_SORT_BY_LUMINANCE
 *   finite       : see estimate_channel
 * In the default mode a channel needs only its own sums: a caller may run
 * estimate_channel_alone per channel instead (the same operations). */
EST_INLINE void estimate_lanes(est_float (*sums)[EST_CAPACITY], uint64_t sample_count, int set_count, int m,
                               int gini_mode, int finite, LaneEstimates *out)
{
    clear_estimates(out);
    if (m == 0)
        return;
    const SetCounts k = est_set_counts(sample_count, set_count, m);
    if (gini_mode == EST_GINI_PER_CHANNEL) {
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

    if (gini_mode == EST_GINI_PER_PIXEL) {
        est_float g = (out->gini[0] + out->gini[1] + out->gini[2]) / 3.0f;
        EST_UNROLL
        for (int c = 0; c < EST_CHANNELS; ++c) {
            out->gini[c] = g;
            out->trim[c] = trim_count(g, m);
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
            out->gini[c] = g;
            out->trim[c] = trim_count(g, m);
            out->mon[c] = average_range(sorted[c], k.most, m - 1 - k.most, 0);
            finish_channel(out, c, sorted[c], m, 0, k.divisor);
        }
    }
}

#if EST_VECTOR_WIDTH == 1
/* The estimates of one pixel. */
typedef LaneEstimates PixelEstimates;

/* Estimates one pixel (estimate_lanes with one lane):
 *   sums[c][j]   : sum of channel c over set j, j < set_count (any float)
 *   sample_count : samples of this pixel; set j holds ceil((n - j) / M)
 *   set_count    : M, 1..EST_CAPACITY
 *   gini_mode    : EST_GINI_PER_CHANNEL, EST_GINI_PER_PIXEL or
 *                  EST_SORT_BY_LUMINANCE */
EST_INLINE PixelEstimates estimate_pixel(float (*sums)[EST_CAPACITY], uint64_t sample_count, int set_count,
                                         int gini_mode)
{
    PixelEstimates out;
    int m = sample_count < (uint64_t)set_count ? (int)sample_count : set_count;
    estimate_lanes(sums, sample_count, set_count, m, gini_mode, 0, &out);
    return out;
}
#endif

#endif /* host, or a kernel with EST_SETS */

#endif /* KERNELS_ESTIMATOR_CORE_H */
