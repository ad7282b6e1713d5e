/* Estimator kernels: one work item per pixel turns the M set sums of each
 * channel into the mean, MoN and G-MoN images (and diagnostics).
 *
 * Compile-time constants (build options):
 *   EST_SETS      M, 1..64
 *   EST_GINI_MODE EST_GINI_PER_CHANNEL (default), _PER_PIXEL, EST_SORT_BY_LUMINANCE
 *   EST_OUTPUTS   bit mask of images written: EST_OUTPUT_* below (default all)
 * Output images are RGB floats, pixel-interleaved; trim counts are ints. */
#include "estimator_core.h"

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif
#ifndef EST_GINI_MODE
#define EST_GINI_MODE EST_GINI_PER_CHANNEL
#endif

#define EST_OUTPUT_MEAN 1
#define EST_OUTPUT_MON 2
#define EST_OUTPUT_GMON 4
#define EST_OUTPUT_DIAGNOSTICS 8
#ifndef EST_OUTPUTS
#define EST_OUTPUTS 15
#endif

KERNEL_FN void store_estimates(const PixelEstimates *e, ulong pixel, __global float *mean, __global float *mon,
                               __global float *gmon, __global float *gini, __global int *trim)
{
    for (int c = 0; c < EST_CHANNELS; ++c) {
        ulong i = pixel * EST_CHANNELS + c;
#if EST_OUTPUTS & EST_OUTPUT_MEAN
        mean[i] = e->mean[c];
#endif
#if EST_OUTPUTS & EST_OUTPUT_MON
        mon[i] = e->mon[c];
#endif
#if EST_OUTPUTS & EST_OUTPUT_GMON
        gmon[i] = e->gmon[c];
#endif
#if EST_OUTPUTS & EST_OUTPUT_DIAGNOSTICS
        gini[i] = e->gini[c];
        trim[i] = e->trim[c];
#endif
    }
}

/* Input: float set sums, planes [set][channel][pixel]. */
__kernel void estimate_from_sums(__global const float *set_sums, ulong pixel_count, ulong sample_count,
                                 __global float *mean, __global float *mon, __global float *gmon,
                                 __global float *gini, __global int *trim)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    float sums[EST_CHANNELS][EST_SETS];
    for (uint j = 0; j < EST_SETS; ++j)
        for (uint c = 0; c < EST_CHANNELS; ++c)
            sums[c][j] = set_sums[set_sum_index(j, c, pixel, pixel_count)];
    PixelEstimates e = estimate_pixel(sums, sample_count, EST_SETS, EST_GINI_MODE);
    store_estimates(&e, pixel, mean, mon, gmon, gini, trim);
}

/* Input: the renderer's exact fixed-point accumulators (estimator.h). */
__kernel void estimate_from_accumulators(__global const ulong *accumulators, ulong pixel_count,
                                         ulong sample_count, __global float *mean, __global float *mon,
                                         __global float *gmon, __global float *gini, __global int *trim)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    float sums[EST_CHANNELS][EST_SETS];
    for (uint j = 0; j < EST_SETS; ++j)
        for (uint c = 0; c < EST_CHANNELS; ++c) {
            FixedSum s;
            s.lo = accumulators[accumulator_index(j, c, 0, pixel, pixel_count)];
            s.hi = accumulators[accumulator_index(j, c, 1, pixel, pixel_count)];
            sums[c][j] = fixed_to_float(s);
        }
    PixelEstimates e = estimate_pixel(sums, sample_count, EST_SETS, EST_GINI_MODE);
    store_estimates(&e, pixel, mean, mon, gmon, gini, trim);
}

/* Drives the shared accumulation code from a sample stream (tests): work
 * item p adds samples[p][i] (RGB) as sample index first_sample + i of pixel
 * p, and counts the rejected ones. */
__kernel void accumulate_stream(__global const float *samples, ulong stream_length, ulong first_sample,
                                __global ulong *accumulators, ulong pixel_count, __global uint *rejected)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    uint rejected_here = 0;
    for (ulong i = 0; i < stream_length; ++i) {
        __global const float *rgb = samples + (pixel * stream_length + i) * EST_CHANNELS;
        uint set = set_of_sample(first_sample + i, EST_SETS);
        rejected_here += accumulate_sample(accumulators, pixel, pixel_count, set, rgb[0], rgb[1], rgb[2]);
    }
    rejected[pixel] += rejected_here;
}
