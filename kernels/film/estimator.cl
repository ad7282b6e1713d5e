/* Estimator kernels: each work item turns the M set sums of each channel of
 * EST_VECTOR_WIDTH consecutive pixels into the requested passes (passes.h:
 * estimates, their standard errors, diagnostics), one pixel per vector
 * lane, with the host's code (estimators.h, estimate_lanes).
 *
 * Compile-time constants (build options):
 *   EST_SETS          M, 1..64
 *   EST_GINI_MODE     EST_GINI_PER_CHANNEL (default), _PER_PIXEL, EST_SORT_BY_LUMINANCE
 *   EST_PASSES        the passes computed (a mask of PASS_BIT, passes.h;
 *                     default none)
 *   EST_STDERR        1: also the standard errors of its estimates
 *   EST_FIRST_SET     (first sample index) mod M of a render of a sample
 *                     range: logical set j is stored set (j + EST_FIRST_SET)
 *                     mod M, so that the counts fall right (default 0)
 *   EST_VECTOR_WIDTH  pixels per work item: 1 (default), 2, 4, 8 or 16
 *   EST_PREFETCH      CPU devices only: prefetch the input this many work
 *                     items ahead (default 0: none)
 * The global size must cover ceil(pixel_count / EST_VECTOR_WIDTH) work items
 * (more are allowed); the last one may hold fewer pixels. The host
 * (host/estimator/estimator_cl.c) picks the width per device.
 * Inputs are planes [set][channel][pixel], so a work item's pixels are
 * consecutive values. Output: one buffer of RGB planes, pixel-interleaved,
 * in the order of pass_slot and stderr_slot (passes.h); trim counts are
 * ints. */
#include "estimators.h"

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif
#ifndef EST_GINI_MODE
#define EST_GINI_MODE EST_GINI_PER_CHANNEL
#endif

#ifndef EST_PASSES
#define EST_PASSES 0u /* no image: for accumulate_stream alone (tests) */
#endif
#ifndef EST_STDERR
#define EST_STDERR 0
#endif
#ifndef EST_FIRST_SET
#define EST_FIRST_SET 0
#endif
/* Stored set of logical set j (a constant when j is). */
#define STORED_SET(j) (((j) + EST_FIRST_SET) % EST_SETS)

/* The general path cannot unroll its loops (m is not a constant there);
 * clang would say so. */
#ifdef __clang__
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

#define LANES EST_VECTOR_WIDTH /* pixels per work item */
#ifndef EST_PREFETCH
#define EST_PREFETCH 0
#endif

#if LANES == 1
#define LOAD_LANES(p) (*(p))
#define STORE_LANES(x, p) (*(p) = (x))
#else
#define LOAD_LANES(p) EST_PASTE(vload, LANES)(0, p)
#define STORE_LANES(x, p) EST_PASTE(vstore, LANES)(x, 0, p)
#endif

/* Lanes from `count` (1..LANES) consecutive values at p; lanes past count repeat
 * the last value (their results are not stored). */
KERNEL_FN est_float load_float_lanes(__global const float *p, int count)
{
    float lanes[LANES];
    for (int l = 0; l < LANES; ++l)
        lanes[l] = p[l < count ? l : count - 1];
    return LOAD_LANES(lanes);
}

KERNEL_FN est_ulong load_ulong_lanes(__global const ulong *p, int count)
{
    ulong lanes[LANES];
    for (int l = 0; l < LANES; ++l)
        lanes[l] = p[l < count ? l : count - 1];
    return LOAD_LANES(lanes);
}

/* Writes the first `count` lanes of an RGB image's three channels. A full
 * work item of 16 lanes interleaves the channels in registers (clang's
 * shuffles) and writes three whole vectors. */
#if LANES == 16 && defined(__clang__)
#define STORE_RGB16(image, first, rgb, vstore)                                                                         \
    vstore(__builtin_shufflevector(                                                                                    \
               __builtin_shufflevector(rgb[0], rgb[1], 0, 16, 0, 1, 17, 0, 2, 18, 0, 3, 19, 0, 4, 20, 0, 5), rgb[2],   \
               0, 1, 16, 3, 4, 17, 6, 7, 18, 9, 10, 19, 12, 13, 20, 15),                                               \
           0, image + (first)*EST_CHANNELS);                                                                           \
    vstore(__builtin_shufflevector(                                                                                    \
               __builtin_shufflevector(rgb[0], rgb[1], 21, 0, 6, 22, 0, 7, 23, 0, 8, 24, 0, 9, 25, 0, 10, 26), rgb[2], \
               0, 21, 2, 3, 22, 5, 6, 23, 8, 9, 24, 11, 12, 25, 14, 15),                                               \
           0, image + (first)*EST_CHANNELS + 16);                                                                      \
    vstore(__builtin_shufflevector(                                                                                    \
               __builtin_shufflevector(rgb[0], rgb[1], 0, 11, 27, 0, 12, 28, 0, 13, 29, 0, 14, 30, 0, 15, 31, 0),      \
               rgb[2], 26, 1, 2, 27, 4, 5, 28, 7, 8, 29, 10, 11, 30, 13, 14, 31),                                      \
           0, image + (first)*EST_CHANNELS + 32);
#endif

KERNEL_FN void store_rgb(__global float *image, ulong first, int count, const est_float *rgb)
{
#ifdef STORE_RGB16
    if (count == LANES) {
        STORE_RGB16(image, first, rgb, vstore16)
        return;
    }
#endif
    float lanes[EST_CHANNELS][LANES];
    for (int c = 0; c < EST_CHANNELS; ++c)
        STORE_LANES(rgb[c], lanes[c]);
    for (int l = 0; l < count; ++l)
        for (int c = 0; c < EST_CHANNELS; ++c)
            image[(first + l) * EST_CHANNELS + c] = lanes[c][l];
}

KERNEL_FN void store_rgb_int(__global int *image, ulong first, int count, const est_int *rgb)
{
#ifdef STORE_RGB16
    if (count == LANES) {
        STORE_RGB16(image, first, rgb, vstore16)
        return;
    }
#endif
    int lanes[EST_CHANNELS][LANES];
    for (int c = 0; c < EST_CHANNELS; ++c)
        STORE_LANES(rgb[c], lanes[c]);
    for (int l = 0; l < count; ++l)
        for (int c = 0; c < EST_CHANNELS; ++c)
            image[(first + l) * EST_CHANNELS + c] = lanes[c][l];
}

/* Writes every requested image of a work item's pixels. */
KERNEL_FN void store_estimates(const LaneEstimates *e, ulong pixel_count, ulong first, int count,
                               __global float *images)
{
    const ulong plane = pixel_count * EST_CHANNELS;
    EST_UNROLL
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(EST_PASSES & PASS_BIT(p)))
            continue;
        __global float *image = images + (ulong)pass_slot(EST_PASSES, p) * plane;
        if (p == PASS_TRIM) {
            est_int trim[EST_CHANNELS];
            for (int c = 0; c < EST_CHANNELS; ++c)
                trim[c] = EST_INT_FROM_FLOAT(e->value[p][c]);
            store_rgb_int((__global int *)image, first, count, trim);
        } else {
            store_rgb(image, first, count, e->value[p]);
        }
        if (EST_STDERR && (PASSES_ESTIMATES & PASS_BIT(p)))
            store_rgb(images + (ulong)stderr_slot(EST_PASSES, p) * plane, first, count, e->error[p]);
    }
}

/* EST_PREFETCH (CPU devices only, set by the host): prefetch the input of
 * the work item that many ahead, which the same thread runs soon after (a
 * CPU runtime runs a work group's items in order), so that memory works
 * while this one computes: the input is M * 3 streams, more than hardware
 * prefetchers follow. The address goes through an integer because the
 * builtin takes a generic pointer; on a CPU every address space is the same
 * memory. */
#if defined(EST_PREFETCH) && EST_PREFETCH > 0
#ifndef EST_PREFETCH_LOCALITY
#define EST_PREFETCH_LOCALITY 3
#endif
#define PREFETCH(address) __builtin_prefetch((const void *)(ulong)(address), 0, EST_PREFETCH_LOCALITY)
#else
#define PREFETCH(address)
#endif

/* Channel c of one work item's set sums, pixels first .. first + count - 1
 * (count: 1..LANES; lanes past count repeat the last pixel), from float set
 * sums or (from_accumulators) exact accumulators converted to the nearest
 * floats. */
EST_INLINE void load_channel(__global const void *input, int from_accumulators, ulong pixel_count, ulong first,
                             int count, uint c, est_float *sums)
{
    EST_UNROLL
    for (uint j = 0; j < EST_SETS; ++j) {
        if (from_accumulators) {
            __global const ulong *a = (__global const ulong *)input;
            __global const ulong *lo = a + accumulator_index(STORED_SET(j), c, 0, first, pixel_count);
            __global const ulong *hi = a + accumulator_index(STORED_SET(j), c, 1, first, pixel_count);
            sums[j] = count == LANES ? fixed_to_float_lanes(LOAD_LANES(lo), LOAD_LANES(hi))
                                     : fixed_to_float_lanes(load_ulong_lanes(lo, count), load_ulong_lanes(hi, count));
        } else {
            __global const float *p =
                (__global const float *)input + set_sum_index(STORED_SET(j), c, first, pixel_count);
            sums[j] = count == LANES ? LOAD_LANES(p) : load_float_lanes(p, count);
        }
    }
}

/* The grid exponents of a work item's pixels (lanes past count repeat the
 * last pixel). */
EST_INLINE est_int load_grid_exponents(__global const void *accumulators, ulong first, int count)
{
    __global const ulong *grid = (__global const ulong *)accumulators + grid_index(first);
    est_uint word = EST_UINT_FROM_ULONG(count == LANES ? LOAD_LANES(grid) : load_ulong_lanes(grid, count));
    return EST_SELECT(word == 0u, EST_INTS(0), EST_INT_FROM_UINT(word) - EST_GRID_BIAS);
}

/* Prefetches (EST_PREFETCH) channel c of the input of the work item at
 * pixel `first`: every cache line of each of its vectors (an accumulator
 * vector of 16 lanes is 128 bytes; any vector may straddle lines). */
EST_INLINE void prefetch_channel(__global const void *input, int from_accumulators, ulong pixel_count, ulong first,
                                 uint c)
{
    EST_UNROLL
    for (uint j = 0; j < EST_SETS; ++j) {
        if (from_accumulators) {
            EST_UNROLL
            for (uint word = 0; word < 2; ++word) {
                __global const ulong *p =
                    (__global const ulong *)input + accumulator_index(j, c, word, first, pixel_count);
                EST_UNROLL
                for (uint l = 0; l < LANES; l += 8)
                    PREFETCH(p + l);
                PREFETCH(p + LANES - 1);
            }
        } else {
            __global const float *p = (__global const float *)input + set_sum_index(j, c, first, pixel_count);
            EST_UNROLL
            for (uint l = 0; l < LANES; l += 16)
                PREFETCH(p + l);
            PREFETCH(p + LANES - 1);
        }
    }
}

/* A work item of the general case: fewer samples than sets (the start of a
 * render: m = sample_count sets are non-empty) or fewer than LANES pixels (the
 * last work item). The same code as the common case, with m and count not
 * constants: not inlined, as its loops do not unroll. */
static __attribute__((noinline)) void estimate_in_general(__global const void *input, int from_accumulators,
                                                          ulong pixel_count, ulong sample_count, ulong first,
                                                          const EstimatorParams *params, __global float *images)
{
    int count = pixel_count - first < LANES ? (int)(pixel_count - first) : LANES;
    int m = sample_count < EST_SETS ? (int)sample_count : EST_SETS;
    est_float sums[EST_CHANNELS][EST_SETS];
    for (uint c = 0; c < EST_CHANNELS; ++c)
        load_channel(input, from_accumulators, pixel_count, first, count, c, sums[c]);
    LaneEstimates e;
    est_int grid = from_accumulators ? load_grid_exponents(input, first, count) : EST_INTS(0);
    estimate_lanes(sums, sample_count, EST_SETS, m, EST_PASSES, EST_STDERR, EST_GINI_MODE, params, grid,
                   from_accumulators, &e);
    finish_estimates(&e, EST_PASSES, from_accumulators, grid);
    store_estimates(&e, pixel_count, first, count, images);
}

/* The common case: LANES pixels, every set non-empty (m = M, a constant). */
EST_INLINE void estimate_common(__global const void *input, int from_accumulators, ulong pixel_count,
                                ulong sample_count, ulong first, const EstimatorParams *params, __global float *images)
{
    const int prefetch = EST_PREFETCH > 0 && first + (EST_PREFETCH + 1) * LANES <= pixel_count;
    const ulong ahead = first + EST_PREFETCH * LANES;
    LaneEstimates e;
    est_int grid = from_accumulators ? load_grid_exponents(input, first, LANES) : EST_INTS(0);
    if (!channels_together(EST_PASSES, EST_STDERR, EST_GINI_MODE)) {
        /* estimate_lanes channel by channel (as it runs then), each
         * channel's input loaded just before it is needed, and the same
         * channel of a later work item prefetched (spread out, not all at
         * once). */
        const SetCounts k = est_set_counts(sample_count, EST_SETS, EST_SETS);
        EST_UNROLL
        for (uint c = 0; c < EST_CHANNELS; ++c) {
            if (prefetch)
                prefetch_channel(input, from_accumulators, pixel_count, ahead, c);
            est_float sums[EST_SETS];
            load_channel(input, from_accumulators, pixel_count, first, LANES, c, sums);
            estimate_channel_alone(&k, sums, from_accumulators, &e, (int)c);
        }
    } else {
        est_float sums[EST_CHANNELS][EST_SETS];
        EST_UNROLL
        for (uint c = 0; c < EST_CHANNELS; ++c) {
            if (prefetch)
                prefetch_channel(input, from_accumulators, pixel_count, ahead, c);
            load_channel(input, from_accumulators, pixel_count, first, LANES, c, sums[c]);
        }
        estimate_lanes(sums, sample_count, EST_SETS, EST_SETS, EST_PASSES, EST_STDERR, EST_GINI_MODE, params, grid,
                       from_accumulators, &e);
    }
    finish_estimates(&e, EST_PASSES, from_accumulators, grid);
    store_estimates(&e, pixel_count, first, LANES, images);
}

/* Input: float set sums, planes [set][channel][pixel]. */
__kernel void estimate_from_sums(__global const float *set_sums, ulong pixel_count, ulong sample_count,
                                 EstimatorParams params, __global float *images)
{
    ulong first = get_global_id(0) * LANES;
    if (first >= pixel_count)
        return;
    if (sample_count < EST_SETS || pixel_count - first < LANES)
        estimate_in_general(set_sums, 0, pixel_count, sample_count, first, &params, images);
    else
        estimate_common(set_sums, 0, pixel_count, sample_count, first, &params, images);
}

/* Input: the renderer's exact fixed-point accumulators (accumulate.h). */
__kernel void estimate_from_accumulators(__global const ulong *accumulators, ulong pixel_count, ulong sample_count,
                                         EstimatorParams params, __global float *images)
{
    ulong first = get_global_id(0) * LANES;
    if (first >= pixel_count)
        return;
    if (sample_count < EST_SETS || pixel_count - first < LANES)
        estimate_in_general(accumulators, 1, pixel_count, sample_count, first, &params, images);
    else
        estimate_common(accumulators, 1, pixel_count, sample_count, first, &params, images);
}

/* Drives the shared accumulation code from a sample stream (tests): work
 * item p adds samples[p][i] (RGB) as sample index first_sample + i of pixel
 * p, and counts the rejected ones: rejected holds two planes, the non-finite
 * samples and the rounded ones (accumulate.h). One pixel per work item whatever
 * EST_VECTOR_WIDTH is. */
__kernel void accumulate_stream(__global const float *samples, ulong stream_length, ulong first_sample,
                                __global ulong *accumulators, ulong pixel_count, __global uint *rejected)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    uint nonfinite = 0, rounded = 0;
    for (ulong i = 0; i < stream_length; ++i) {
        __global const float *rgb = samples + (pixel * stream_length + i) * EST_CHANNELS;
        uint set = set_of_sample(first_sample + i, EST_SETS);
        int added = accumulate_sample(accumulators, pixel, pixel_count, EST_SETS, set, rgb[0], rgb[1], rgb[2]);
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    accumulators_normalize(accumulators, pixel, pixel_count, EST_SETS);
    rejected[pixel] += nonfinite;
    rejected[pixel_count + pixel] += rounded;
}
