/* The per-sample estimators (passes.h, kind PASS_SAMPLE): the state the
 * path tracer updates with each sample beside the set sums, and the
 * estimates from it (docs/estimators.md, "Estimators that see each sample").
 *
 *   clamp      pbrt-v4's Film "maxcomponentvalue": a sample whose largest
 *              component exceeds V is scaled by V / max, at each of the
 *              levels V of clamp.levels; one sum per level
 *   clamp-sum  Cycles' sample clamping: if |r| + |g| + |b| > L the sample
 *              is scaled by L / that sum, with L = clamp-sum.direct for
 *              its direct light and clamp-sum.indirect for the rest (0: no
 *              clamping); one sum
 *   abmm, gabmm   from the pixel's moments (below)
 *   mean-or-mon   the mean where its 95 % confidence half-width is no
 *              larger than the median set's, else MoN: the sum of d^2
 *              (d = x - c, below) of each set beside the set sums
 * Both clamp the film's response to the radiance before the pixel filter's
 * weight multiplies it, as pbrt-v4 does.
 *   zirr       Zirr, Hanika and Dachsbacher's reweighting of framebuffer
 *              cascades: each sample split by its luminance between the
 *              two of K cascades (scales b^i) that bracket it; estimated
 *              over a 3x3 neighbourhood of the cascades (zirr_estimate),
 *              so after every sum of the image is gathered
 *
 * Every sum but the moments' (below) is an exact fixed-point sum as the set
 * sums are (accumulate.h):
 * a pass's sums form one block laid out as an accumulator of that many
 * "sets" (its own grid plane, then its sums), so the state depends only on
 * the samples, never on devices, pass batching or pixel moves. The blocks of
 * the requested passes follow each other in one buffer of uint64 planes.
 *
 * A sum that takes most samples as the sets do (clamp's levels, clamp-sum,
 * zirr's cascade 0) is kept as its deviation from the set sums: the sum of
 * value - x over the samples whose value differs from x, the sample as the
 * sets got it (film response times weight). Its estimate is the exact total
 * of the pixel's set sums plus that deviation (sets_plus_deviation), and a
 * sample that no level clamps costs a comparison, not an addition. So these
 * passes read the set sums at estimation, which every render keeps (one set
 * at least).
 *
 * Valid C11 and OpenCL C 1.2 (host/film/film_sample.c is the host side, the
 * reference the kernels are tested against). In the path tracer and in
 * kernels/film/sample_estimator.cl EST_SAMPLE_PASSES is the mask of requested
 * passes and EST_CLAMP_LEVEL_VALUES their levels (build options); the host
 * passes both at run time. */
#ifndef KERNELS_SAMPLE_PASSES_H
#define KERNELS_SAMPLE_PASSES_H

#include "accumulate.h"
#include "estimator_numerics.h"
#include "passes.h"
#include "../common/vec3.h"

/* SAMPLE_SUMS_DOUBLE: the moments' double sums (moment_sum_add), in the
 * path tracer and wherever SAMPLE_PASSES_DOUBLE (their estimation) is;
 * both need cl_khr_fp64 in a kernel. */
#if defined(SAMPLE_PASSES_DOUBLE) && !defined(SAMPLE_SUMS_DOUBLE)
#define SAMPLE_SUMS_DOUBLE
#endif

/* The state's blocks, in this order, each present only when a pass that
 * needs it is requested:
 *   clamp     an accumulator of L deviation sums (L = clamp's levels)
 *   clamp-sum an accumulator of 1 deviation sum
 *   moments   (abmm, gabmm, mean-or-mon) the pixel's shift c, three
 *             planes (one per channel: the float's bits | SHIFT_SET), then
 *             for abmm and gabmm the sum of d^3, d = x - c, three planes of
 *             doubles (moment_sum_add); the first moment comes from the
 *             set sums, the second from the squares after the blocks
 *   zirr      an accumulator of K sums, sum k the cascade of scale b^k
 *             (sum 0 as a deviation; last, so that the blocks before it do
 *             not depend on K) */
#define SAMPLE_BLOCK_CLAMP 0
#define SAMPLE_BLOCK_CLAMP_SUM 1
#define SAMPLE_BLOCK_MOMENTS 2
#define SAMPLE_BLOCK_ZIRR 3
#define SAMPLE_BLOCKS 4
#define SAMPLE_MOMENT_PASSES (PASS_BIT(PASS_ABMM) | PASS_BIT(PASS_GABMM))
#define SAMPLE_SHIFT_PASSES (SAMPLE_MOMENT_PASSES | PASS_BIT(PASS_MEAN_OR_MON))
#define SHIFT_SET 0x100000000ul
#if defined(EST_SAMPLE_PASSES) && !defined(SAMPLE_SUMS_DOUBLE)
/* A kernel with abmm, gabmm or mean-or-mon built without -DSAMPLE_SUMS_DOUBLE
 * would keep no moments: refused at compile time (a negative array size). */
typedef char sample_sums_need_double[((EST_SAMPLE_PASSES)&SAMPLE_SHIFT_PASSES) ? -1 : 1];
#endif

/* The sums of d^2 (d = x - c, squared exactly in double) follow the
 * blocks above, shared by abmm, gabmm and mean-or-mon: one double a
 * channel, or with mean-or-mon M (the render's sets, sample s in set s mod
 * M, as its set sums; set j's channel c in plane 3 j + c), so that their
 * planes depend on M, which the blocks above do not. */
KERNEL_FN uint32_t sample_square_count(uint32_t passes, uint32_t set_count)
{
    return (passes & PASS_BIT(PASS_MEAN_OR_MON)) ? set_count : 1u;
}

KERNEL_FN uint32_t sample_square_planes(uint32_t passes, uint32_t set_count)
{
    return (passes & SAMPLE_SHIFT_PASSES) ? sample_square_count(passes, set_count) * EST_CHANNELS : 0u;
}

/* Planes of a block; cascade_count (zirr's K) matters for zirr's only. */
KERNEL_FN uint32_t sample_block_planes(uint32_t passes, int level_count, int cascade_count, int block)
{
    if (block == SAMPLE_BLOCK_CLAMP)
        return (passes & PASS_BIT(PASS_CLAMP)) ? accumulator_planes((uint32_t)level_count) : 0u;
    if (block == SAMPLE_BLOCK_CLAMP_SUM)
        return (passes & PASS_BIT(PASS_CLAMP_SUM)) ? accumulator_planes(1) : 0u;
    if (block == SAMPLE_BLOCK_MOMENTS)
        return ((passes & SAMPLE_SHIFT_PASSES) ? EST_CHANNELS : 0u) +
               ((passes & SAMPLE_MOMENT_PASSES) ? EST_CHANNELS : 0u);
    return (passes & PASS_BIT(PASS_ZIRR)) ? accumulator_planes((uint32_t)cascade_count) : 0u;
}

/* The first plane of a block (zirr's block is last: no K needed). */
KERNEL_FN uint32_t sample_block_first_plane(uint32_t passes, int level_count, int block)
{
    uint32_t plane = 0;
    for (int b = 0; b < block && b < SAMPLE_BLOCK_ZIRR; ++b)
        plane += sample_block_planes(passes, level_count, 0, b);
    return plane;
}

/* Planes of the whole per-sample state. */
KERNEL_FN uint32_t sample_state_planes(uint32_t passes, int level_count, int cascade_count)
{
    return sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_ZIRR) +
           sample_block_planes(passes, level_count, cascade_count, SAMPLE_BLOCK_ZIRR);
}

/* The plane of set j's sum of d^2 in channel c, after the blocks. */
KERNEL_FN uint64_t sample_square_plane(uint32_t passes, int level_count, int cascade_count, uint32_t j, int c)
{
    return (uint64_t)sample_state_planes(passes, level_count, cascade_count) + j * EST_CHANNELS + (uint32_t)c;
}

/* RGB images a pass produces: one per clamp level, else one. */
KERNEL_FN int sample_pass_images(uint32_t passes, int level_count, int pass)
{
    if (!(passes & PASSES_SAMPLE & PASS_BIT(pass)))
        return 0;
    return pass == PASS_CLAMP ? level_count : 1;
}

/* The image slot of image `index` of a pass among all per-sample images. */
KERNEL_FN int sample_image_slot(uint32_t passes, int level_count, int pass, int index)
{
    int slot = index;
    for (int q = PASS_CLAMP; q < pass; ++q)
        slot += sample_pass_images(passes, level_count, q);
    return slot;
}

/* The per-sample passes estimated pixel by pixel (estimate_sample_passes):
 * every one but zirr, whose 3x3 neighbourhoods need the whole image
 * (estimate_zirr). Their images and slots: sample_pass_images and
 * sample_image_slot of this mask. */
#define SAMPLE_PIXEL_PASSES(passes) ((passes) & ~PASSES_NEIGHBOURHOOD)

/* pbrt-v4's rule: (r, g, b) scaled by V / max(r, g, b) when that exceeds V
 * (V = INFINITY changes nothing). */
KERNEL_FN void clamp_largest_component(float *rgb, float level)
{
    float largest = rgb[0] > rgb[1] ? rgb[0] : rgb[1];
    largest = rgb[2] > largest ? rgb[2] : largest;
    if (largest > level) {
        float scale = level / largest;
        for (int c = 0; c < EST_CHANNELS; ++c)
            rgb[c] *= scale;
    }
}

/* Cycles' rule: scaled by L / (|r| + |g| + |b|) when that exceeds L > 0;
 * returns whether it did. */
KERNEL_FN int clamp_component_sum(float *rgb, float limit)
{
    float sum = abs_float(rgb[0]) + abs_float(rgb[1]) + abs_float(rgb[2]);
    if (!(limit > 0.0f && sum > limit))
        return 0;
    float scale = limit / sum;
    for (int c = 0; c < EST_CHANNELS; ++c)
        rgb[c] *= scale;
    return 1;
}

/* ------------------------------------------------------------------------
 * zirr (Zirr, Hanika, Dachsbacher 2018): K cascades of scales
 * s_k = ZIRR_START b^k. The paper's rules as its authors' public code
 * (ic.js/rw: split.cpp, reweight.fs) applies them; docs/estimators.md, "zirr",
 * says what was chosen where the paper leaves it open.
 * ---------------------------------------------------------------------- */
#define ZIRR_START 1.0f

/* s_k, by repeated multiplication (the split and the estimate use these
 * same floats). */
KERNEL_FN float zirr_scale(int cascade, float base)
{
    float scale = ZIRR_START;
    for (int k = 0; k < cascade; ++k)
        scale *= base;
    return scale;
}

/* How a sample of luminance l (finite) is split: weight_lower of it into
 * cascade `lower`, weight_upper into lower + 1. Between s_k and s_{k+1}
 * the lower weight is linear in 1/l, (s_k / l - s_k / s_{k+1}) / (1 - s_k /
 * s_{k+1}), so that the weights add up to 1 and the sample's count
 * estimates w_lower l / s_k + w_upper l / s_{k+1} add up to 1 as well.
 * At or below s_0 all goes to cascade 0; above s_{K-1} the sample goes to
 * the last cascade scaled to luminance s_{K-1} (the authors' rule: no
 * cascade counts it). */
typedef struct {
    int lower;
    float weight_lower, weight_upper;
} ZirrSplit;

KERNEL_FN ZirrSplit zirr_split(float luminance, int cascade_count, float base)
{
    ZirrSplit split;
    float lower_scale = ZIRR_START, upper_scale = ZIRR_START * base;
    split.lower = 0;
    while (!(luminance < upper_scale) && split.lower < cascade_count - 2) {
        lower_scale = upper_scale;
        upper_scale *= base;
        ++split.lower;
    }
    if (luminance <= lower_scale) {
        split.weight_lower = 1.0f;
        split.weight_upper = 0.0f;
    } else if (luminance < upper_scale) {
        float ratio = lower_scale / upper_scale;
        float w = (lower_scale / luminance - ratio) / (1.0f - ratio);
        split.weight_lower = w > 0.0f ? w : 0.0f;
        split.weight_upper = 1.0f - split.weight_lower > 0.0f ? 1.0f - split.weight_lower : 0.0f;
    } else {
        split.weight_lower = 0.0f;
        split.weight_upper = upper_scale / luminance;
    }
    return split;
}

/* One sample: its film response `film` (clamp's input) and that of its
 * direct and indirect parts (clamp-sum's), each multiplied by the pixel
 * filter's `weight` after clamping; its set among the render's set_count
 * (set_of_sample: mean-or-mon's sums are per set). */
typedef struct {
    float film[EST_CHANNELS];
    float direct[EST_CHANNELS];
    float indirect[EST_CHANNELS];
    float weight;
    uint32_t set;
    uint32_t set_count;
} SampleParts;

/* A splat (kernels/film/splats.h) as the per-sample passes see it: a
 * sample of value its RGB (the filter's share is in it: weight 1) in the
 * set of the sample that made it, all of it indirect light. clamp clamps
 * it as pbrt-v4's RGBFilm::AddSplat does, zirr splits it by its own
 * luminance; the moment-based passes do not take splats (the host refuses
 * them). */
KERNEL_FN SampleParts splat_sample_parts(const float *rgb, uint32_t set, uint32_t set_count)
{
    SampleParts s;
    for (int c = 0; c < EST_CHANNELS; ++c) {
        s.film[c] = rgb[c];
        s.direct[c] = 0.0f;
        s.indirect[c] = rgb[c];
    }
    s.weight = 1.0f;
    s.set = set;
    s.set_count = set_count;
    return s;
}

/* The sample as the sets see it (film response times weight); returns
 * whether it is finite. */
KERNEL_FN int sample_film_weighted(const SampleParts *s, float *x)
{
    for (int c = 0; c < EST_CHANNELS; ++c)
        x[c] = s->film[c] * s->weight;
    return sample_is_finite(x[0], x[1], x[2]);
}

#ifdef SAMPLE_SUMS_DOUBLE
/* A double's bits, and back (a union reinterprets in C and OpenCL C). */
typedef union {
    double value;
    uint64_t bits;
} DoubleBits;

KERNEL_FN uint64_t double_bits(double x)
{
    DoubleBits v;
    v.value = x;
    return v.bits;
}

KERNEL_FN double double_from_bits(uint64_t bits)
{
    DoubleBits v;
    v.bits = bits;
    return v.value;
}

/* The moments' sums of d^2 and d^3 are plain double sums, no exact ones:
 * d, the difference of two floats, is kept to 2^-53 in double, its square
 * and cube to 2^-53 again, and the sums to about n 2^-53 of the sum of
 * their magnitudes (the sum of d^2 relative to itself: its terms are
 * positive). That is what the moments need, far within what the float
 * estimates keep, at one addition a sum instead of an exact one, and the
 * range ((2^128)^3 times 2^64 samples) never overflows. A pixel's samples
 * arrive in order on every device split and pass batching, so the sums
 * are deterministic (FP_CONTRACT off). No file or merge keeps them. */
KERNEL_FN void moment_sum_add(GLOBAL uint64_t *word, double x)
{
    *word = double_bits(double_from_bits(*word) + x);
}
#endif

/* Adds value - x to deviation sum `index` of the accumulator `block` (of
 * sum_count sums), x being the sample as the sets got it (x_finite: whether
 * they added it; a non-finite one counts as 0 there). Nothing when the two
 * agree bit for bit (or are both non-finite): the common case costs a
 * comparison. Both are added exactly; returns EST_ADD_* (EST_ADD_NONFINITE
 * for a non-finite value). */
KERNEL_FN int accumulate_deviation(GLOBAL uint64_t *block, uint64_t pixel, uint64_t pixel_count, uint32_t sum_count,
                                   uint32_t index, const float *value, const float *x, int x_finite)
{
    const int value_finite = sample_is_finite(value[0], value[1], value[2]);
    if (value_finite == x_finite &&
        (!x_finite || (float_bits(value[0]) == float_bits(x[0]) && float_bits(value[1]) == float_bits(x[1]) &&
                       float_bits(value[2]) == float_bits(x[2]))))
        return value_finite ? EST_ADD_EXACT : EST_ADD_NONFINITE;
    const float minus_x[EST_CHANNELS] = {-x[0], -x[1], -x[2]};
    if (value_finite && x_finite)
        return accumulate_two(block, pixel, pixel_count, sum_count, index, value, index, minus_x);
    if (x_finite) {
        int added = accumulate_sample(block, pixel, pixel_count, sum_count, index, minus_x[0], minus_x[1], minus_x[2]);
        return added > EST_ADD_NONFINITE ? added : EST_ADD_NONFINITE;
    }
    return accumulate_sample(block, pixel, pixel_count, sum_count, index, value[0], value[1], value[2]);
}

/* Adds one sample to the per-sample state of `pixel` (the caller adds it
 * to the set sums: accumulate_sample of sample_film_weighted). Returns
 * EST_ADD_* (the worst of its sums: non-finite samples are added to none). */
KERNEL_FN int sample_passes_add(GLOBAL uint64_t *state, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                int level_count, const float *levels, float direct_limit, float indirect_limit,
                                int cascade_count, float cascade_base, const SampleParts *s)
{
    int result = EST_ADD_EXACT;
    float x[EST_CHANNELS];
    const int x_finite = sample_film_weighted(s, x);
    if (passes & PASS_BIT(PASS_CLAMP)) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_CLAMP) * pixel_count;
        for (int level = 0; level < level_count; ++level) {
            float rgb[EST_CHANNELS];
            for (int c = 0; c < EST_CHANNELS; ++c)
                rgb[c] = s->film[c];
            clamp_largest_component(rgb, levels[level]);
            for (int c = 0; c < EST_CHANNELS; ++c)
                rgb[c] *= s->weight;
            int added = accumulate_deviation(block, pixel, pixel_count, (uint32_t)level_count, (uint32_t)level, rgb, x,
                                             x_finite);
            result = added > result ? added : result;
        }
    }
    if (passes & PASS_BIT(PASS_CLAMP_SUM)) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_CLAMP_SUM) * pixel_count;
        float direct[EST_CHANNELS], indirect[EST_CHANNELS], value[EST_CHANNELS];
        for (int c = 0; c < EST_CHANNELS; ++c) {
            direct[c] = s->direct[c];
            indirect[c] = s->indirect[c];
        }
        /* Neither part clamped: the sample itself (its parts add up to it
         * but for rounding). */
        const int clamped = clamp_component_sum(direct, direct_limit) | clamp_component_sum(indirect, indirect_limit);
        for (int c = 0; c < EST_CHANNELS; ++c)
            value[c] = clamped ? (direct[c] + indirect[c]) * s->weight : x[c];
        int added = accumulate_deviation(block, pixel, pixel_count, 1u, 0u, value, x, x_finite);
        result = added > result ? added : result;
    }
#ifdef SAMPLE_SUMS_DOUBLE
    if (passes & SAMPLE_SHIFT_PASSES) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_MOMENTS) * pixel_count;
        const uint32_t square_set = (passes & PASS_BIT(PASS_MEAN_OR_MON)) ? s->set : 0u;
        for (int c = 0; c < EST_CHANNELS; ++c) {
            /* The pixel's first sample is its shift: the moments about it do
             * not cancel as raw moments would (a pixel of 1e6 +- 1e3). A
             * non-finite sample is 0, as in the sets. */
            const float value = x_finite ? x[c] : 0.0f;
            uint64_t shift = block[(uint64_t)c * pixel_count + pixel];
            if (!(shift & SHIFT_SET)) {
                shift = SHIFT_SET | float_bits(value);
                block[(uint64_t)c * pixel_count + pixel] = shift;
            }
            const double d = (double)value - (double)float_from_bits((uint32_t)shift), square = d * d;
            moment_sum_add(
                state + sample_square_plane(passes, level_count, cascade_count, square_set, c) * pixel_count + pixel,
                square);
            if (passes & SAMPLE_MOMENT_PASSES)
                moment_sum_add(block + (uint64_t)(EST_CHANNELS + c) * pixel_count + pixel, square * d);
        }
    }
#endif
    if (passes & PASS_BIT(PASS_ZIRR)) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_ZIRR) * pixel_count;
        if (!x_finite)
            return EST_ADD_NONFINITE > result ? EST_ADD_NONFINITE : result;
        /* One luminance splits all three channels: colours are kept.
         * Cascade 0 is the sets' total plus its deviation: a sample it
         * keeps whole costs nothing, one split between cascades 0 and 1
         * moves its part v = x w_1 up (cascade 0 keeps x - v: the parts add
         * up to x exactly), and one above gives cascade 0 -x. */
        const ZirrSplit split = zirr_split(v_luminance(vec3(x[0], x[1], x[2])), cascade_count, cascade_base);
        float lower[EST_CHANNELS], upper[EST_CHANNELS];
        for (int c = 0; c < EST_CHANNELS; ++c) {
            lower[c] = x[c] * split.weight_lower;
            upper[c] = x[c] * split.weight_upper;
        }
        const float minus_upper[EST_CHANNELS] = {-upper[0], -upper[1], -upper[2]};
        const float minus_x[EST_CHANNELS] = {-x[0], -x[1], -x[2]};
        const uint32_t count = (uint32_t)cascade_count, next = (uint32_t)split.lower + 1;
        int added = EST_ADD_EXACT;
        if (split.lower == 0 && split.weight_lower > 0.0f) {
            if (split.weight_upper > 0.0f)
                added = accumulate_two(block, pixel, pixel_count, count, 0u, minus_upper, 1u, upper);
        } else if (split.weight_lower > 0.0f) {
            added = accumulate_two(block, pixel, pixel_count, count, 0u, minus_x, (uint32_t)split.lower, lower);
            if (split.weight_upper > 0.0f) {
                int more = accumulate_sample(block, pixel, pixel_count, count, next, upper[0], upper[1], upper[2]);
                added = more > added ? more : added;
            }
        } else {
            added = accumulate_two(block, pixel, pixel_count, count, 0u, minus_x, next, upper);
        }
        result = added > result ? added : result;
    }
    return result;
}

/* ------------------------------------------------------------------------
 * The exact total of a pixel's set sums plus a deviation sum: each on its
 * own grid, added as 256-bit integers on the finer grid (the set totals
 * stay below 2^132 units, a sum below 2^127), then rounded once. Grids more
 * than WIDE_GRID_SPAN bits apart (never met in practice: the deviations'
 * values are the samples' own, scaled) put the finer operands on the
 * coarser grid less WIDE_GRID_SPAN, rounded: still the same bits on every
 * device.
 * ---------------------------------------------------------------------- */
#define WIDE_GRID_SPAN 120

typedef struct {
    uint64_t word[4]; /* two's complement, word 0 lowest */
    int exponent;     /* the units: 2^exponent */
} WideSum;

/* Adds v (4 words, two's complement) times 2^shift, shift in
 * 0..WIDE_GRID_SPAN, to s. */
KERNEL_FN void wide_add_shifted(WideSum *s, const uint64_t *v, int shift)
{
    const int words = shift / 64, bits = shift % 64;
    uint64_t carry = 0;
    for (int i = 0; i < 4; ++i) {
        uint64_t here = i - words >= 0 ? v[i - words] : 0u;
        uint64_t below = i - words - 1 >= 0 ? v[i - words - 1] : 0u;
        uint64_t w = bits ? (here << bits) | (below >> (64 - bits)) : here;
        uint64_t sum = s->word[i] + w;
        uint64_t next = sum < w ? 1u : 0u;
        sum += carry;
        next += sum < carry ? 1u : 0u;
        s->word[i] = sum;
        carry = next;
    }
}

/* Adds v, a sum in units of 2^v_exponent, to s (rounded onto s's grid if
 * that is coarser). */
KERNEL_FN void wide_add(WideSum *s, FixedSum v, int v_exponent)
{
    int shift = v_exponent - s->exponent, inexact = 0;
    if (shift < 0) {
        v = fixed_shift_right_rounded(v, -shift, &inexact);
        shift = 0;
    }
    const uint64_t sign = (uint64_t)((int64_t)v.hi >> 63);
    const uint64_t words[4] = {v.lo, v.hi, sign, sign};
    wide_add_shifted(s, words, shift);
}

/* The magnitude of s as window 2^*exponent, window the 64 bits from its
 * leading one with a sticky bit for the rest (so that converting it rounds
 * as the whole would); returns whether s is negative. 0 gives window 0. */
KERNEL_FN int wide_window(WideSum s, uint64_t *window, int *exponent)
{
    const int negative = (int)(s.word[3] >> 63);
    if (negative) { /* magnitude: ~s + 1 */
        uint64_t carry = 1;
        for (int i = 0; i < 4; ++i) {
            s.word[i] = ~s.word[i] + carry;
            carry = carry && s.word[i] == 0 ? 1u : 0u;
        }
    }
    int top = 3;
    while (top > 0 && s.word[top] == 0)
        --top;
    const int zeros = s.word[top] != 0 ? leading_zeros64(s.word[top]) : 0;
    const uint64_t below = top > 0 ? s.word[top - 1] : 0u;
    uint64_t rest = zeros ? below << zeros : below;
    for (int i = 0; i < top - 1; ++i)
        rest |= s.word[i];
    *window = (zeros ? (s.word[top] << zeros) | (below >> (64 - zeros)) : s.word[top]) | (rest != 0 ? 1u : 0u);
    *exponent = s.exponent + 64 * top - zeros; /* the window's top bit is the leading one's */
    return negative;
}

/* The value of s as f 2^*exponent, f correctly rounded; a value that fits
 * 128 bits converts as fixed_to_float converts a sum, so that a set total
 * without deviation keeps its own bits. */
KERNEL_FN float wide_to_float(WideSum s, int *exponent)
{
    const uint64_t sign = (uint64_t)((int64_t)s.word[1] >> 63);
    if (s.word[2] == sign && s.word[3] == sign) {
        *exponent = s.exponent;
        return fixed_to_float_lanes(s.word[0], s.word[1]);
    }
    uint64_t window;
    const int negative = wide_window(s, &window, exponent);
    return negative ? -(float)window : (float)window;
}

/* A pixel's set sums as its estimates read them, once a pixel
 * (pixel_set_totals): the sets' grid word and, per channel, the exact
 * total of the set sums on that grid, four words (two's complement, word 0
 * lowest; below 2^132 units: the third word takes the carries). */
typedef struct {
    uint64_t grid;
    uint64_t total[EST_CHANNELS][4];
} PixelSetTotals;

KERNEL_FN void pixel_set_totals(GLOBAL const uint64_t *accumulators, uint32_t set_count, uint64_t pixel,
                                uint64_t pixel_count, PixelSetTotals *t)
{
    t->grid = accumulators[grid_index(pixel)];
    for (int c = 0; c < EST_CHANNELS; ++c) {
        uint64_t *total = t->total[c];
        total[0] = total[1] = total[2] = 0u;
        for (uint32_t j = 0; j < set_count; ++j) {
            FixedSum v = load_sum(accumulators, accumulator_index(j, (uint32_t)c, 0, pixel, pixel_count), pixel_count);
            uint64_t lo = total[0] + v.lo;
            uint64_t carry = lo < v.lo ? 1u : 0u;
            uint64_t hi = total[1] + v.hi;
            uint64_t next = hi < v.hi ? 1u : 0u;
            hi += carry;
            next += hi < carry ? 1u : 0u;
            total[0] = lo;
            total[1] = hi;
            total[2] += next + (uint64_t)((int64_t)v.hi >> 63);
        }
        total[3] = (uint64_t)((int64_t)total[2] >> 63);
    }
}

/* Channel c of `pixel`: the total of its set_count set sums (t, read from
 * `accumulators`) plus sum `index` of the deviation accumulator
 * `deviations` (NULL: none), exactly. */
KERNEL_FN WideSum sets_plus_deviation(const PixelSetTotals *t, GLOBAL const uint64_t *accumulators, uint32_t set_count,
                                      GLOBAL const uint64_t *deviations, uint32_t index, uint64_t pixel,
                                      uint64_t pixel_count, int c)
{
    WideSum s;
    for (int i = 0; i < 4; ++i)
        s.word[i] = 0;
    const uint64_t set_grid = t->grid;
    const uint64_t deviation_grid = deviations ? deviations[grid_index(pixel)] : 0u;
    const int e_sets = grid_exponent(set_grid), e_deviation = grid_exponent(deviation_grid);
    if (set_grid && deviation_grid) {
        const int finer = e_sets < e_deviation ? e_sets : e_deviation;
        const int coarser = e_sets < e_deviation ? e_deviation : e_sets;
        s.exponent = coarser - finer > WIDE_GRID_SPAN ? coarser - WIDE_GRID_SPAN : finer;
    } else {
        s.exponent = set_grid ? e_sets : e_deviation;
    }
    if (set_grid && e_sets >= s.exponent) /* the common case: the total placed once */
        wide_add_shifted(&s, t->total[c], e_sets - s.exponent);
    else if (set_grid)
        for (uint32_t j = 0; j < set_count; ++j)
            wide_add(&s, load_sum(accumulators, accumulator_index(j, (uint32_t)c, 0, pixel, pixel_count), pixel_count),
                     e_sets);
    if (deviation_grid)
        wide_add(&s, load_sum(deviations, accumulator_index(index, (uint32_t)c, 0, pixel, pixel_count), pixel_count),
                 e_deviation);
    return s;
}

/* The mean over n samples (0 for n = 0) of sets_plus_deviation, as the
 * mean of a render of one set computes it from its sum (so that clamp at
 * V = INFINITY, no deviation, equals that mean bit for bit). */
KERNEL_FN void sets_plus_deviation_mean(const PixelSetTotals *t, GLOBAL const uint64_t *accumulators,
                                        uint32_t set_count, GLOBAL const uint64_t *deviations, uint32_t index,
                                        uint64_t pixel, uint64_t pixel_count, uint64_t n, float *rgb)
{
    for (int c = 0; c < EST_CHANNELS; ++c) {
        int exponent;
        float sum = wide_to_float(
            sets_plus_deviation(t, accumulators, set_count, deviations, index, pixel, pixel_count, c), &exponent);
        rgb[c] = scale_by_grid(n > 0 ? sum / (float)n : 0.0f, exponent);
    }
}

/* Sum `index` of the accumulator `block` at `pixel` divided by n (0 for
 * n = 0), as sets_plus_deviation_mean without the sets. */
KERNEL_FN void accumulator_mean(GLOBAL const uint64_t *block, uint64_t pixel, uint64_t pixel_count, uint32_t index,
                                uint64_t n, float *rgb)
{
    int exponent = grid_exponent(block[grid_index(pixel)]);
    for (int c = 0; c < EST_CHANNELS; ++c) {
        uint64_t i = accumulator_index(index, (uint32_t)c, 0, pixel, pixel_count);
        float sum = fixed_to_float_lanes(block[i], block[i + pixel_count]);
        float mean = n > 0 ? sum / (float)n : 0.0f;
        rgb[c] = scale_by_grid(mean, exponent);
    }
}

/* Image `index` of clamp or clamp-sum at `pixel` after sample_count
 * samples, from its deviation and the render's set sums (t of
 * `accumulators`, set_count sets). */
KERNEL_FN void sample_sum_estimate(GLOBAL const uint64_t *state, const PixelSetTotals *t,
                                   GLOBAL const uint64_t *accumulators, uint32_t set_count, uint64_t pixel,
                                   uint64_t pixel_count, uint32_t passes, int level_count, uint64_t sample_count,
                                   int pass, int index, float *rgb)
{
    GLOBAL const uint64_t *block =
        state + (uint64_t)sample_block_first_plane(passes, level_count,
                                                   pass == PASS_CLAMP ? SAMPLE_BLOCK_CLAMP : SAMPLE_BLOCK_CLAMP_SUM) *
                    pixel_count;
    sets_plus_deviation_mean(t, accumulators, set_count, block, (uint32_t)index, pixel, pixel_count, sample_count, rgb);
}

/* The first step of zirr's estimate: the cascades' means B_k of `pixel`
 * (each sum / n; cascade 0's with the set sums), K RGB triples at
 * cascade_means + pixel K 3, so that the neighbourhoods read each pixel's
 * once. */
KERNEL_FN void zirr_pixel_means(GLOBAL const uint64_t *block, GLOBAL const uint64_t *accumulators, uint32_t set_count,
                                int cascade_count, uint64_t pixel, uint64_t pixel_count, uint64_t n,
                                GLOBAL float *cascade_means)
{
    PixelSetTotals totals;
    pixel_set_totals(accumulators, set_count, pixel, pixel_count, &totals);
    for (int k = 0; k < cascade_count; ++k) {
        float mean[EST_CHANNELS];
        if (k == 0)
            sets_plus_deviation_mean(&totals, accumulators, set_count, block, 0u, pixel, pixel_count, n, mean);
        else
            accumulator_mean(block, pixel, pixel_count, (uint32_t)k, n, mean);
        for (int c = 0; c < EST_CHANNELS; ++c)
            cascade_means[(pixel * (uint64_t)cascade_count + (uint64_t)k) * EST_CHANNELS + c] = mean[c];
    }
}

/* zirr's estimate at pixel (x, y) of a width x height image after n
 * samples a pixel, from the cascades' means B_k (sum / n) of the whole
 * image (zirr_pixel_means of every pixel). With
 * c_k = lum(B_k) n / s_k the estimated count of samples in cascade k (at
 * the pixel, or averaged over its 3x3 neighbourhood, clamped to the
 * image's edge), cascade i's reliability from counting is
 * (C - 1) / kappa, C = c_{i-1} + c_i + c_{i+1} at the pixel where that
 * sum over the neighbourhood is at least 1 sample, else the
 * neighbourhood's; from colour it is max(lum(P), emin) n / (kappa s_i) f,
 * P = sum_{k<i} r_k B_k (the estimate of the cascades below) and
 * f = (0.4 + 0.6 b) (1 - t) + t, t = min(1, 1 / kappa); r_i is their mean
 * clamped to [0, 1], and the estimate is P after the last cascade. */
KERNEL_FN void zirr_estimate(GLOBAL const float *cascade_means, uint32_t x, uint32_t y, uint32_t width, uint32_t height,
                             int cascade_count, float base, float kappa, float emin, uint64_t n, float *rgb)
{
    const float samples = (float)n;
    float means[EST_ZIRR_CASCADES_MAX][EST_CHANNELS], center[EST_ZIRR_CASCADES_MAX], hood[EST_ZIRR_CASCADES_MAX];
    for (int k = 0; k < cascade_count; ++k) {
        const float scale = zirr_scale(k, base);
        float around = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                int64_t qx = (int64_t)x + dx, qy = (int64_t)y + dy;
                qx = qx < 0 ? 0 : (qx >= (int64_t)width ? (int64_t)width - 1 : qx);
                qy = qy < 0 ? 0 : (qy >= (int64_t)height ? (int64_t)height - 1 : qy);
                GLOBAL const float *mean =
                    cascade_means +
                    (((uint64_t)qy * width + (uint64_t)qx) * (uint64_t)cascade_count + k) * EST_CHANNELS;
                around += v_luminance(vec3(mean[0], mean[1], mean[2]));
            }
        GLOBAL const float *mean =
            cascade_means + (((uint64_t)y * width + x) * (uint64_t)cascade_count + k) * EST_CHANNELS;
        for (int c = 0; c < EST_CHANNELS; ++c)
            means[k][c] = mean[c];
        center[k] = v_luminance(vec3(means[k][0], means[k][1], means[k][2])) * samples / scale;
        hood[k] = around / 9.0f * samples / scale;
    }
    const float t = 1.0f / kappa < 1.0f ? 1.0f / kappa : 1.0f;
    const float colour_factor = (0.4f + 0.6f * base) * (1.0f - t) + t;
    for (int c = 0; c < EST_CHANNELS; ++c)
        rgb[c] = 0.0f;
    for (int i = 0; i < cascade_count; ++i) {
        float at_pixel = center[i], around = hood[i];
        if (i > 0) {
            at_pixel += center[i - 1];
            around += hood[i - 1];
        }
        if (i + 1 < cascade_count) {
            at_pixel += center[i + 1];
            around += hood[i + 1];
        }
        const float count = around < 1.0f ? around : at_pixel;
        float brightness = v_luminance(vec3(rgb[0], rgb[1], rgb[2]));
        brightness = brightness > emin ? brightness : emin;
        const float by_count = (count - 1.0f) / kappa;
        const float by_colour = brightness * samples / (kappa * zirr_scale(i, base)) * colour_factor;
        float r = (by_count + by_colour) * 0.5f;
        r = r > 0.0f ? (r < 1.0f ? r : 1.0f) : 0.0f;
        for (int c = 0; c < EST_CHANNELS; ++c)
            rgb[c] += r * means[i][c];
    }
}

#ifdef SAMPLE_PASSES_DOUBLE
/* gabmm's and mean-or-mon's set-based parts; in a kernel it needs
 * -DEST_SETS (the sample estimator always has it: every pass reads the
 * set sums). */
#include "estimators.h"

/* ------------------------------------------------------------------------
 * abmm and gabmm: the moments in double (a kernel needs cl_khr_fp64), with
 * only + - * / so that host and kernels agree bit for bit.
 * ---------------------------------------------------------------------- */

/* 2^e as a double, e in -1022..1023, from its bits. */
KERNEL_FN double double_power_of_two(int e)
{
    return double_from_bits((uint64_t)(e + 1023) << 52);
}

/* Set `set`, channel c of an accumulator as a double count of its grid's
 * units (two roundings: deterministic). */
KERNEL_FN double accumulator_units(GLOBAL const uint64_t *block, uint32_t set, uint64_t pixel, uint64_t pixel_count,
                                   int c)
{
    uint64_t lo = block[accumulator_index(set, (uint32_t)c, 0, pixel, pixel_count)];
    uint64_t hi = block[accumulator_index(set, (uint32_t)c, 1, pixel, pixel_count)];
    return (double)(int64_t)hi * 18446744073709551616.0 + (double)lo;
}

/* The size of an accumulator's unit at `pixel`, 2^E. */
KERNEL_FN double accumulator_unit(GLOBAL const uint64_t *block, uint64_t pixel)
{
    return double_power_of_two(grid_exponent(block[grid_index(pixel)]));
}

typedef struct {
    double mean;   /* mu */
    double second; /* m2 = mean of (x - mu)^2 */
    double third;  /* m3 = mean of (x - mu)^3 */
} PixelMoments;

/* The exact total of channel c's set sums (t) as a double (one
 * rounding). */
KERNEL_FN double sets_total(const PixelSetTotals *t, int c)
{
    WideSum s;
    for (int i = 0; i < 4; ++i)
        s.word[i] = t->total[c][i];
    s.exponent = grid_exponent(t->grid);
    uint64_t window;
    int exponent;
    const int negative = wide_window(s, &window, &exponent);
    const double total = (double)window * double_power_of_two(exponent);
    return negative ? -total : total;
}

/* Set j's sum of d^2 in channel c (sample_square_plane). */
KERNEL_FN double sample_square_sum(GLOBAL const uint64_t *state, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                   int level_count, int cascade_count, uint32_t j, int c)
{
    return double_from_bits(state[sample_square_plane(passes, level_count, cascade_count, j, c) * pixel_count + pixel]);
}

/* Channel c's shift (the pixel's first sample). */
KERNEL_FN double sample_shift(GLOBAL const uint64_t *state, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                              int level_count, int c)
{
    GLOBAL const uint64_t *block =
        state + (uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_MOMENTS) * pixel_count;
    return (double)float_from_bits((uint32_t)block[(uint64_t)c * pixel_count + pixel]);
}

/* Channel c's mean and central moments after n samples: the mean mu from
 * the set sums (t, set_count sets), the others from the moments about the
 * shift: with a = mu - c, m2 = mean(d^2) - a^2, m3 = mean(d^3) - 3 a
 * mean(d^2) + 2 a^3; they cancel only as far as the shift is from the mean,
 * not as far as the mean is from 0. */
KERNEL_FN PixelMoments sample_moments(GLOBAL const uint64_t *state, const PixelSetTotals *t, uint32_t set_count,
                                      uint64_t pixel, uint64_t pixel_count, uint32_t passes, int level_count,
                                      int cascade_count, uint64_t n, int c)
{
    PixelMoments m;
    m.mean = m.second = m.third = 0.0;
    if (n == 0)
        return m;
    const double count = (double)n;
    GLOBAL const uint64_t *cubes =
        state +
        ((uint64_t)sample_block_first_plane(passes, level_count, SAMPLE_BLOCK_MOMENTS) + EST_CHANNELS) * pixel_count;
    double square_sum = 0.0;
    for (uint32_t j = 0; j < sample_square_count(passes, set_count); ++j)
        square_sum += sample_square_sum(state, pixel, pixel_count, passes, level_count, cascade_count, j, c);
    const double second = square_sum / count;
    const double third = double_from_bits(cubes[(uint64_t)c * pixel_count + pixel]) / count;
    m.mean = sets_total(t, c) / count;
    const double a = m.mean - sample_shift(state, pixel, pixel_count, passes, level_count, c);
    m.second = second - a * a;
    m.third = third - 3.0 * a * second + 2.0 * a * a * a;
    return m;
}

/* Orenstein's approximate Bayesian median of means: theta = mu - m3 / (3 m2
 * (n alpha + 2)) (mu where m2 is not positive). */
KERNEL_FN float abmm_of_moments(PixelMoments m, uint64_t n, double alpha)
{
    if (!(m.second > 0.0))
        return (float)m.mean;
    return (float)(m.mean - m.third / (3.0 * m.second * ((double)n * alpha + 2.0)));
}

/* A pixel's set means as gabmm and mean-or-mon read them, once a pixel
 * (pixel_set_means): each set's sample count (sample s of [first_sample,
 * first_sample + n) in set s mod M), per channel its float sum and mean
 * (the sum over the count, as MoN ranks them) and the non-empty sets in
 * ascending order of mean: with equal counts (SetCounts) of sum, which
 * orders the means too and is the order MoN sorts; ties by set index. */
typedef struct {
    uint32_t m; /* the non-empty sets: min(n, M) */
    uint64_t count[EST_CAPACITY];
    float sum[EST_CHANNELS][EST_CAPACITY];
    float mean[EST_CHANNELS][EST_CAPACITY];
    uint8_t order[EST_CHANNELS][EST_CAPACITY];
} PixelSetMeans;

/* A finite float as an unsigned key of the same order (-0 below +0, which
 * set sums never hold: a sum of 0 converts to +0). */
KERNEL_FN uint32_t float_order_key(float x)
{
    const uint32_t bits = float_bits(x);
    return (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
}

/* A comparator of the sorting network on the keys (value key << 32 | set
 * index): branch free, and the index breaks ties. */
KERNEL_FN void set_key_exchange(uint64_t *keys, int i, int j)
{
    const uint64_t a = keys[i], b = keys[j];
    keys[i] = a < b ? a : b;
    keys[j] = a < b ? b : a;
}
#define SET_KEY_STEP(i, j) set_key_exchange(keys, i, j);

KERNEL_FN void pixel_set_means(GLOBAL const uint64_t *accumulators, uint32_t set_count, uint64_t pixel,
                               uint64_t pixel_count, uint64_t first_sample, uint64_t n, PixelSetMeans *s)
{
    const uint32_t first_set = (uint32_t)(first_sample % set_count), extra = (uint32_t)(n % set_count);
    const uint64_t per_set = n / set_count;
    const int by_sum = n < set_count || extra == 0; /* SetCounts' equal_counts */
    s->m = 0;
    for (uint32_t j = 0; j < set_count; ++j) {
        s->count[j] = per_set + ((j + set_count - first_set) % set_count < extra ? 1u : 0u);
        s->m += s->count[j] != 0 ? 1u : 0u;
    }
    for (int c = 0; c < EST_CHANNELS; ++c) {
        uint64_t keys[EST_CAPACITY];
        for (uint32_t j = 0; j < set_count; ++j) {
            uint64_t i = accumulator_index(j, (uint32_t)c, 0, pixel, pixel_count);
            const float sum = fixed_to_float_lanes(accumulators[i], accumulators[i + pixel_count]);
            const float mean = s->count[j] != 0 ? sum / (float)s->count[j] : 0.0f;
            s->sum[c][j] = sum;
            s->mean[c][j] = mean;
            /* Empty sets last: no finite float's key reaches 0xffffffff. */
            const uint32_t key = s->count[j] == 0 ? 0xffffffffu : float_order_key(by_sum ? sum : mean);
            keys[j] = (uint64_t)key << 32 | j;
        }
        EST_SORTING_NETWORK(set_count, SET_KEY_STEP)
        for (uint32_t r = 0; r < set_count; ++r)
            s->order[c][r] = (uint8_t)keys[r];
    }
}

/* gabmm's Gbar: the mean of the channels' Gini coefficients of the set
 * means (estimators.h's G; 0 without samples). */
KERNEL_FN float sets_mean_gini(const PixelSetMeans *s)
{
    if (s->m == 0)
        return 0.0f;
    float total = 0.0f;
    for (int c = 0; c < EST_CHANNELS; ++c) {
        float t[EST_CAPACITY];
        for (uint32_t k = 0; k < s->m; ++k)
            t[k] = s->mean[c][s->order[c][k]];
        total += gini_of_sorted(t, (int)s->m);
    }
    return total / 3.0f;
}

/* abmm (alpha = 1) or gabmm (alpha = 1 - Gbar of `means`) of a pixel from
 * its channels' moments. */
KERNEL_FN void moment_estimate(const PixelMoments *moments, const PixelSetMeans *means, uint64_t n, int pass,
                               float *rgb)
{
    const double alpha = pass == PASS_GABMM ? 1.0 - (double)sets_mean_gini(means) : 1.0;
    for (int c = 0; c < EST_CHANNELS; ++c)
        rgb[c] = abmm_of_moments(moments[c], n, alpha);
}

/* ------------------------------------------------------------------------
 * mean-or-mon (the authors' MeanOrMON): per channel the 95 % confidence
 * half-widths 1.96 s / sqrt(n) of the mean (s from every sample of the
 * pixel) and of the median set's mean (s and n of that set; even m: the
 * middle pair's averaged), each averaged over the channels; the pixel is
 * the mean where the mean's is no larger, else MoN. s^2 is the sample
 * variance (1/(n - 1)) about the pixel's shift c (its first sample):
 * (Q - D^2 / n) / (n - 1) in double from D, the sum of d = x - c (the
 * exact set sums less n c), and Q, the sum of d^2, which loses to
 * cancellation only about log2((mean - c)^2 / s^2) of double's 53 bits.
 * ---------------------------------------------------------------------- */

/* sqrt(x) for double x >= 0 without library sqrt: x = 4^h f with f in
 * [1, 4), the float root of f refined by two Newton steps (each doubling
 * the correct bits, from float's 23 past double's 53); the same bits
 * everywhere. Values below 2^-1000 (never a variance of float samples'
 * sums, whose squares lie above 2^-300) give 0. */
KERNEL_FN double double_root(double x)
{
    if (!(x >= 0x1p-1000))
        return 0.0;
#ifdef __OPENCL_C_VERSION__
    int e = (int)((as_ulong(x) >> 52) & 0x7ffu) - 1023;
#else
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    int e = (int)((bits >> 52) & 0x7ffu) - 1023;
#endif
    int h = (e - (e < 0 ? 1 : 0)) / 2; /* floor(e / 2) */
    double f = x * double_power_of_two(-2 * h);
    double y = (double)root_of((float)f, 0);
    y = 0.5 * (y + f / y);
    y = 0.5 * (y + f / y);
    return y * double_power_of_two(h);
}

/* 1.96 s / sqrt(n) from a sum S and sum of squares Q of n >= 2 values
 * (0 where cancellation leaves Q - S^2 / n below 0). */
KERNEL_FN double confidence_half_width(double sum, double squares, uint64_t n)
{
    const double count = (double)n;
    double variance = (squares - sum * sum / count) / (count - 1.0);
    return 1.96 * double_root((variance > 0.0 ? variance : 0.0) / count);
}

/* The channel-averaged half-widths of the mean and of the median set of
 * `pixel` after n samples (its set means `means`); returns 0, leaving them
 * 0, while a set holds fewer than 2 samples (n < 2M: a set's s is
 * unknown). */
KERNEL_FN int mean_or_mon_half_widths(GLOBAL const uint64_t *state, GLOBAL const uint64_t *accumulators,
                                      const PixelSetMeans *means, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                      int level_count, int cascade_count, uint32_t set_count, uint64_t n,
                                      double *mean_width, double *mon_width)
{
    *mean_width = *mon_width = 0.0;
    if (n < 2u * set_count)
        return 0;
    const double unit = accumulator_unit(accumulators, pixel);
    const uint32_t low_rank = (set_count - 1) / 2, high_rank = set_count / 2;
    for (int c = 0; c < EST_CHANNELS; ++c) {
        /* Sums of d = x - c and d^2 by set: d's from the set sums. */
        const double shift = sample_shift(state, pixel, pixel_count, passes, level_count, c);
        double sums[EST_CAPACITY], squares_of_set[EST_CAPACITY], sum = 0.0, sum_squares = 0.0;
        for (uint32_t j = 0; j < set_count; ++j) {
            sums[j] =
                accumulator_units(accumulators, j, pixel, pixel_count, c) * unit - (double)means->count[j] * shift;
            sum += sums[j];
            squares_of_set[j] = sample_square_sum(state, pixel, pixel_count, passes, level_count, cascade_count, j, c);
            sum_squares += squares_of_set[j];
        }
        *mean_width += confidence_half_width(sum, sum_squares, n);
        double median_width = 0.0;
        for (uint32_t rank = low_rank; rank <= high_rank; ++rank) {
            const uint32_t j = means->order[c][rank];
            median_width += confidence_half_width(sums[j], squares_of_set[j], means->count[j]) /
                            (low_rank == high_rank ? 1.0 : 2.0);
        }
        *mon_width += median_width;
    }
    *mean_width /= 3.0;
    *mon_width /= 3.0;
    return 1;
}

/* mean-or-mon of a pixel: the set-based mean and MoN (estimators.h, per
 * channel, the same bits as the `mean` and `mon` passes), the mean where
 * its half-width is no larger than MoN's (so where both are 0, and while
 * they are unknown), else MoN. */
KERNEL_FN void mean_or_mon_estimate(GLOBAL const uint64_t *state, GLOBAL const uint64_t *accumulators,
                                    const PixelSetMeans *means, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                    int level_count, int cascade_count, uint32_t set_count, uint64_t first_sample,
                                    uint64_t n, float *rgb)
{
    const uint32_t first_set = (uint32_t)(first_sample % set_count), m = means->m;
    LaneEstimates e;
    clear_estimates(&e);
    if (m > 0) {
        /* estimate_channel and finish_channel's mean and MoN, on the sets
         * already in order. */
        const SetCounts k = est_set_counts(n, (int)set_count, (int)m);
        for (int c = 0; c < EST_CHANNELS; ++c) {
            float t[EST_CAPACITY], v[EST_CAPACITY];
            if (!k.equal_counts) {
                for (uint32_t j = 0; j < m; ++j) /* in the order the samples filled them */
                    t[j] = means->sum[c][(j + first_set) % set_count];
                unequal_sets_mean(&k, t, &e, c);
            }
            for (uint32_t r = 0; r < m; ++r)
                v[r] = k.equal_counts ? means->sum[c][means->order[c][r]] : means->mean[c][means->order[c][r]];
            sorted_channel(&k, v, &e, c);
            e.value[PASS_MEAN][c] = finish_value(e.value[PASS_MEAN][c], v[0], v[m - 1], k.divisor);
            e.value[PASS_MON][c] = finish_value(e.value[PASS_MON][c], v[0], v[m - 1], k.divisor);
        }
    }
    double mean_width, mon_width;
    mean_or_mon_half_widths(state, accumulators, means, pixel, pixel_count, passes, level_count, cascade_count,
                            set_count, n, &mean_width, &mon_width);
    const int pass = mean_width <= mon_width ? PASS_MEAN : PASS_MON;
    const int exponent = grid_exponent(accumulators[grid_index(pixel)]);
    for (int c = 0; c < EST_CHANNELS; ++c)
        rgb[c] = scale_by_grid(e.value[pass][c], exponent);
}

#endif /* SAMPLE_PASSES_DOUBLE */

/* The images of `pixel` of the passes estimated pixel by pixel
 * (SAMPLE_PIXEL_PASSES of passes), images[slot] as sample_image_slot
 * numbers them, after n samples [first_sample, first_sample + n) in the
 * render's set_count sets. What the passes share (the set totals, the
 * moments, the set means) is read once. */
#define SAMPLE_PIXEL_IMAGES_MAX (EST_CLAMP_LEVELS_MAX + PASS_COUNT)

KERNEL_FN void sample_pixel_estimates(GLOBAL const uint64_t *state, GLOBAL const uint64_t *accumulators, uint64_t pixel,
                                      uint64_t pixel_count, uint32_t passes, int level_count, int cascade_count,
                                      uint32_t set_count, uint64_t first_sample, uint64_t n,
                                      float (*images)[EST_CHANNELS])
{
    const uint32_t pixel_passes = SAMPLE_PIXEL_PASSES(passes);
    PixelSetTotals totals; /* read by clamp, clamp-sum and the moments only */
    if (pixel_passes & (PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_CLAMP_SUM) | SAMPLE_MOMENT_PASSES))
        pixel_set_totals(accumulators, set_count, pixel, pixel_count, &totals);
    for (int pass = PASS_CLAMP; pass <= PASS_CLAMP_SUM; ++pass)
        for (int i = 0; i < sample_pass_images(pixel_passes, level_count, pass); ++i)
            sample_sum_estimate(state, &totals, accumulators, set_count, pixel, pixel_count, passes, level_count, n,
                                pass, i, images[sample_image_slot(pixel_passes, level_count, pass, i)]);
#ifdef SAMPLE_PASSES_DOUBLE
    PixelMoments moments[EST_CHANNELS];
    if (pixel_passes & SAMPLE_MOMENT_PASSES)
        for (int c = 0; c < EST_CHANNELS; ++c)
            moments[c] =
                sample_moments(state, &totals, set_count, pixel, pixel_count, passes, level_count, cascade_count, n, c);
    PixelSetMeans means;
    means.m = 0; /* read by gabmm only, which fills it */
    if (pixel_passes & (PASS_BIT(PASS_GABMM) | PASS_BIT(PASS_MEAN_OR_MON)))
        pixel_set_means(accumulators, set_count, pixel, pixel_count, first_sample, n, &means);
    for (int pass = PASS_ABMM; pass <= PASS_GABMM; ++pass)
        if (pixel_passes & PASS_BIT(pass))
            moment_estimate(moments, &means, n, pass, images[sample_image_slot(pixel_passes, level_count, pass, 0)]);
    if (pixel_passes & PASS_BIT(PASS_MEAN_OR_MON))
        mean_or_mon_estimate(state, accumulators, &means, pixel, pixel_count, passes, level_count, cascade_count,
                             set_count, first_sample, n,
                             images[sample_image_slot(pixel_passes, level_count, PASS_MEAN_OR_MON, 0)]);
#else
    (void)first_sample;
    (void)cascade_count;
#endif
}

#endif /* KERNELS_SAMPLE_PASSES_H */
