/* Exact accumulation of samples into per-set sums: the fixed-point sums on
 * a per-pixel grid, sample hygiene and the set a sample goes to. The path
 * tracer includes only this; the estimators read the sums through it.
 *
 * Valid C11 and OpenCL C 1.2: the host (host/film) and the kernels compile
 * this one file, so they agree bit for bit. */
#ifndef KERNELS_ACCUMULATE_H
#define KERNELS_ACCUMULATE_H

#include "../common/compat.h"
#include "lanes.h"

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

/* A finite float exactly: significand * 2^exponent, with its sign apart;
 * the significand lies below 2^EXACT_VALUE_WIDTH. */
#define EXACT_VALUE_WIDTH 24
typedef struct {
    uint64_t significand;
    int exponent;
    int negative;
} ExactValue;

KERNEL_FN ExactValue exact_of_float(float x)
{
    uint32_t bits = float_bits(x);
    ExactValue v;
    v.significand = float_significand(bits);
    v.exponent = ulp_exponent(bits);
    v.negative = (int)(bits >> 31);
    return v;
}

/* A value on the grid 2^grid_exponent, rounded to nearest (ties away from
 * zero; *inexact is set if bits were lost). The caller keeps |v| <
 * 2^(grid_exponent + EST_SUM_BITS). */
KERNEL_FN FixedSum fixed_from_exact(ExactValue x, int grid_exponent, int *inexact)
{
    uint64_t mantissa = x.significand;
    int shift = x.exponent - grid_exponent;
    FixedSum v;
    if (shift >= 0) {
        v.lo = mantissa;
        v.hi = 0;
        v = fixed_shift_left(v, shift);
    } else {
        int drop = -shift; /* mantissa < 2^48: the rounding half fits below 2^63 */
        v.hi = 0;
        v.lo = drop > 63 ? 0 : (mantissa + ((uint64_t)1 << (drop - 1))) >> drop;
        *inexact |= drop > 63 ? mantissa != 0 : (mantissa & (((uint64_t)1 << drop) - 1)) != 0;
    }
    if (x.negative) {
        v.lo = ~v.lo + 1;
        v.hi = ~v.hi + (v.lo == 0 ? 1 : 0);
    }
    return v;
}

/* A finite float on the grid 2^grid_exponent (fixed_from_exact). */
KERNEL_FN FixedSum fixed_from_float(float x, int grid_exponent, int *inexact)
{
    return fixed_from_exact(exact_of_float(x), grid_exponent, inexact);
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

/* Adds v to the sum at lo_index; returns whether that sum now reaches
 * 2^EST_SUM_BITS (fixed_too_wide). */
KERNEL_FN int add_to_sum(GLOBAL uint64_t *accumulators, uint64_t lo_index, uint64_t pixel_count, FixedSum v)
{
    FixedSum sum = fixed_add(load_sum(accumulators, lo_index, pixel_count), v);
    store_sum(accumulators, lo_index, pixel_count, sum);
    return fixed_too_wide(sum);
}

/* The end of additions on the pixel's grid word `grid`: if a sum grew too
 * wide, the grid moves up one bit (rounded). Returns EST_ADD_EXACT or
 * EST_ADD_ROUNDED. */
KERNEL_FN int end_additions_on_grid(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count,
                                    uint32_t set_count, uint64_t grid, int too_wide)
{
    if (!too_wide)
        return EST_ADD_EXACT;
    int inexact = grid_coarsen(accumulators, pixel, pixel_count, set_count, 1);
    accumulators[grid_index(pixel)] = grid + 1;
    return inexact ? EST_ADD_ROUNDED : EST_ADD_EXACT;
}

/* accumulate_exact for any finite values, any case. */
KERNEL_COLD_FN int accumulate_exact_in_general(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count,
                                               uint32_t set_count, uint32_t set, const ExactValue *values)
{
    /* The sample's finest bit and the bound of its magnitude: |x| < 2^top. */
    int finest = 0, top = 0, nonzero = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        if (values[c].significand == 0)
            continue;
        int lowest = values[c].exponent + trailing_zeros64(values[c].significand);
        int bound = values[c].exponent + EXACT_VALUE_WIDTH;
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
        if (values[c].significand == 0)
            continue;
        too_wide |= add_to_sum(accumulators, accumulator_index(set, c, 0, pixel, pixel_count), pixel_count,
                               fixed_from_exact(values[c], exponent, &inexact));
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
KERNEL_FN FixedSum value_on_grid(ExactValue x, int grid_exponent, int *fits)
{
    /* The value is significand * 2^shift units, below 2^(shift + EXACT_VALUE_WIDTH). */
    int shift = x.exponent - grid_exponent;
    FixedSum v;
    v.lo = 0;
    v.hi = 0;
    if (x.significand == 0) /* +-0 lies on every grid */
        return v;
    if (shift < -(EXACT_VALUE_WIDTH - 1) || shift + EXACT_VALUE_WIDTH > EST_SUM_BITS - 1) {
        *fits = 0;
        return v;
    }
    int inexact = 0;
    v = fixed_from_exact(x, grid_exponent, &inexact);
    *fits &= !inexact;
    return v;
}

/* Adds finite values (one a channel) to `set` of `pixel` (set_count sets);
 * see accumulate_sample. The common case, every value on the pixel's grid,
 * is one 128-bit addend a channel; the rest (a new pixel, a finer or much
 * larger value) is accumulate_exact_in_general, with the same result. */
KERNEL_FN int accumulate_exact(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                               uint32_t set, const ExactValue *x)
{
    uint64_t grid = accumulators[grid_index(pixel)];
    int exponent = grid_exponent(grid), fits = grid != 0;
    FixedSum values[EST_CHANNELS];
    values[0] = value_on_grid(x[0], exponent, &fits);
    values[1] = value_on_grid(x[1], exponent, &fits);
    values[2] = value_on_grid(x[2], exponent, &fits);
    if (!fits)
        return accumulate_exact_in_general(accumulators, pixel, pixel_count, set_count, set, x);
    int too_wide = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c)
        too_wide |= add_to_sum(accumulators, accumulator_index(set, c, 0, pixel, pixel_count), pixel_count, values[c]);
    return end_additions_on_grid(accumulators, pixel, pixel_count, set_count, grid, too_wide);
}

/* Adds one RGB sample to `set` of `pixel` (set_count sets). Returns
 * EST_ADD_EXACT, EST_ADD_ROUNDED (added, but not exactly: see above) or
 * EST_ADD_NONFINITE (not added; it still counts as a sample, as 0). */
KERNEL_FN int accumulate_sample(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                                uint32_t set, float r, float g, float b)
{
    if (!sample_is_finite(r, g, b))
        return EST_ADD_NONFINITE;
    ExactValue x[EST_CHANNELS];
    x[0] = exact_of_float(r);
    x[1] = exact_of_float(g);
    x[2] = exact_of_float(b);
    return accumulate_exact(accumulators, pixel, pixel_count, set_count, set, x);
}

/* Adds two finite RGB values at once: a to sum `first`, b to sum `second`
 * (the same sum or two) of `pixel`, with one grid check, as the two
 * accumulate_sample calls would add them exactly (a sample's deviation
 * from the sets, value - x; or x moved from one sum to another). Returns
 * EST_ADD_EXACT or EST_ADD_ROUNDED. */
KERNEL_FN int accumulate_two(GLOBAL uint64_t *accumulators, uint64_t pixel, uint64_t pixel_count, uint32_t set_count,
                             uint32_t first, const float *a, uint32_t second, const float *b)
{
    ExactValue x[2][EST_CHANNELS];
    for (int c = 0; c < EST_CHANNELS; ++c) {
        x[0][c] = exact_of_float(a[c]);
        x[1][c] = exact_of_float(b[c]);
    }
    const uint64_t grid = accumulators[grid_index(pixel)];
    const int exponent = grid_exponent(grid);
    int fits = grid != 0;
    FixedSum values[2][EST_CHANNELS];
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < EST_CHANNELS; ++c)
            values[k][c] = value_on_grid(x[k][c], exponent, &fits);
    if (!fits) {
        int added = accumulate_exact(accumulators, pixel, pixel_count, set_count, first, x[0]);
        int more = accumulate_exact(accumulators, pixel, pixel_count, set_count, second, x[1]);
        return added > more ? added : more;
    }
    int too_wide = 0;
    for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
        /* Each value lies below 2^(EST_SUM_BITS - 1): their sum, and a sum
         * below 2^EST_SUM_BITS plus either, cannot wrap 128 bits. */
        if (first == second)
            too_wide |= add_to_sum(accumulators, accumulator_index(first, c, 0, pixel, pixel_count), pixel_count,
                                   fixed_add(values[0][c], values[1][c]));
        else
            for (int k = 0; k < 2; ++k)
                too_wide |= add_to_sum(accumulators, accumulator_index(k ? second : first, c, 0, pixel, pixel_count),
                                       pixel_count, values[k][c]);
    }
    return end_additions_on_grid(accumulators, pixel, pixel_count, set_count, grid, too_wide);
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

#endif /* KERNELS_ACCUMULATE_H */
