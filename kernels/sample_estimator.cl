/* The per-sample estimators' images from their state (sample_passes.h),
 * one work item per pixel, with the host's code (host/film/film_sample.c).
 *
 * Build options: -DEST_SAMPLE_PASSES=<mask of PASS_BIT> (the requested
 * per-sample passes), -DEST_CLAMP_LEVEL_COUNT=L and
 * -DEST_CLAMP_LEVEL_VALUES=<L floats, comma-separated> (clamp's levels);
 * with abmm, gabmm or mean-or-mon -DSAMPLE_PASSES_DOUBLE (the device needs
 * cl_khr_fp64), with gabmm or mean-or-mon -DEST_SETS=M (they read the set
 * sums); with zirr -DEST_ZIRR_COUNT=K -DEST_ZIRR_BASE=b
 * -DEST_ZIRR_KAPPA=kappa -DEST_ZIRR_EMIN=emin. */
#ifdef SAMPLE_PASSES_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#include "sample_passes.h"

#ifndef EST_SAMPLE_PASSES
#error "build with -DEST_SAMPLE_PASSES=<mask>"
#endif
#ifndef EST_CLAMP_LEVEL_COUNT
#define EST_CLAMP_LEVEL_COUNT 0
#endif
#ifndef EST_ZIRR_COUNT
#define EST_ZIRR_COUNT 2
#define EST_ZIRR_BASE 8.0f
#define EST_ZIRR_KAPPA 1.0f
#define EST_ZIRR_EMIN 0.0f
#endif

/* Output: one buffer of RGB images, pixel-interleaved, in the order of
 * sample_image_slot of SAMPLE_PIXEL_PASSES. accumulators: the render's set sums (read by gabmm
 * and mean-or-mon only), of sets starting at sample first_sample. */
__kernel void estimate_sample_passes(__global const ulong *state, __global const ulong *accumulators, ulong pixel_count,
                                     ulong sample_count, ulong first_sample, __global float *images)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    const uint pixel_passes = SAMPLE_PIXEL_PASSES(EST_SAMPLE_PASSES);
    for (int pass = PASS_CLAMP; pass < PASS_COUNT; ++pass)
        for (int i = 0; i < sample_pass_images(pixel_passes, EST_CLAMP_LEVEL_COUNT, pass); ++i) {
            float rgb[EST_CHANNELS];
            if (pass == PASS_CLAMP || pass == PASS_CLAMP_SUM)
                sample_sum_estimate(state, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT, sample_count,
                                    pass, i, rgb);
#ifdef SAMPLE_PASSES_DOUBLE
#ifdef EST_SETS
            else if (pass == PASS_MEAN_OR_MON)
                mean_or_mon_estimate(state, accumulators, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT,
                                     EST_ZIRR_COUNT, EST_SETS, first_sample, sample_count, rgb);
#endif
            else
                moment_estimate(state, accumulators, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT,
#ifdef EST_SETS
                                EST_SETS,
#else
                                1,
#endif
                                first_sample, sample_count, pass, rgb);
#endif
            ulong slot = (ulong)sample_image_slot(pixel_passes, EST_CLAMP_LEVEL_COUNT, pass, i);
            for (int c = 0; c < EST_CHANNELS; ++c)
                images[(slot * pixel_count + pixel) * EST_CHANNELS + c] = rgb[c];
        }
}

/* zirr's image from the cascades (the state's zirr block) of a whole
 * width x height image (its neighbourhoods cross any split of the pixels
 * among devices), one work item a pixel; output pixel-interleaved RGB. */
__kernel void estimate_zirr(__global const ulong *cascades, uint width, uint height, ulong sample_count,
                            __global float *image)
{
    ulong pixel = get_global_id(0);
    if (pixel >= (ulong)width * height)
        return;
    float rgb[EST_CHANNELS];
    zirr_estimate(cascades, (uint)(pixel % width), (uint)(pixel / width), width, height, EST_ZIRR_COUNT, EST_ZIRR_BASE,
                  EST_ZIRR_KAPPA, EST_ZIRR_EMIN, sample_count, rgb);
    for (int c = 0; c < EST_CHANNELS; ++c)
        image[pixel * EST_CHANNELS + c] = rgb[c];
}

/* Drives the per-sample accumulation from a stream (tests): work item p
 * adds parts[p][i] (SampleParts as 10 floats: film RGB, direct RGB,
 * indirect RGB, weight) to pixel p, as sample first_sample + i (its set,
 * with -DEST_SETS=M, for mean-or-mon). */
__kernel void accumulate_sample_stream(__global const float *parts, ulong stream_length, __global ulong *state,
                                       ulong pixel_count, float direct_limit, float indirect_limit, ulong first_sample)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
#if EST_CLAMP_LEVEL_COUNT > 0
    const float levels[EST_CLAMP_LEVEL_COUNT] = {EST_CLAMP_LEVEL_VALUES};
#else
    const float levels[1] = {0.0f};
#endif
    for (ulong i = 0; i < stream_length; ++i) {
        __global const float *p = parts + (pixel * stream_length + i) * 10;
        SampleParts s;
        for (int c = 0; c < EST_CHANNELS; ++c) {
            s.film[c] = p[c];
            s.direct[c] = p[3 + c];
            s.indirect[c] = p[6 + c];
        }
        s.weight = p[9];
#ifdef EST_SETS
        s.set = set_of_sample(first_sample + i, EST_SETS);
        s.set_count = EST_SETS;
#else
        s.set = 0;
        s.set_count = 1;
        (void)first_sample;
#endif
        sample_passes_add(state, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT, levels, direct_limit,
                          indirect_limit, EST_ZIRR_COUNT, EST_ZIRR_BASE, &s);
    }
}
