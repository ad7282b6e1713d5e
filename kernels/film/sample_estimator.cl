/* The per-sample estimators' images from their state (sample_passes.h),
 * one work item per pixel, with the host's code (host/film/film_sample.c).
 *
 * Build options: -DEST_SAMPLE_PASSES=<mask of PASS_BIT> (the requested
 * per-sample passes), -DEST_SETS=M (the render's sets: every pass reads the
 * set sums), -DEST_CLAMP_LEVEL_COUNT=L and -DEST_CLAMP_LEVEL_VALUES=<L
 * floats, comma-separated> (clamp's levels); with abmm, gabmm or
 * mean-or-mon -DSAMPLE_SUMS_DOUBLE -DSAMPLE_PASSES_DOUBLE (the device needs
 * cl_khr_fp64); with
 * zirr -DEST_ZIRR_COUNT=K -DEST_ZIRR_BASE=b -DEST_ZIRR_KAPPA=kappa
 * -DEST_ZIRR_EMIN=emin. */
#ifdef SAMPLE_SUMS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
/* The estimator core's loops run to a pixel's set count m, known here only
 * at run time (the estimator kernel knows it at compile time): not
 * unrolled. */
#define EST_UNROLL_MAX_SETS 0
#include "sample_passes.h"

#if !defined(EST_SAMPLE_PASSES) || !defined(EST_SETS)
#error "build with -DEST_SAMPLE_PASSES=<mask> -DEST_SETS=M"
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
 * sample_image_slot of SAMPLE_PIXEL_PASSES. accumulators: the render's set
 * sums, of sets starting at sample first_sample. */
__kernel void estimate_sample_passes(__global const ulong *state, __global const ulong *accumulators, ulong pixel_count,
                                     ulong sample_count, ulong first_sample, __global float *images)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    float rgb[SAMPLE_PIXEL_IMAGES_MAX][EST_CHANNELS];
    sample_pixel_estimates(state, accumulators, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT,
                           EST_ZIRR_COUNT, EST_SETS, first_sample, sample_count, rgb);
    const int images_of_pixel =
        sample_image_slot(SAMPLE_PIXEL_PASSES(EST_SAMPLE_PASSES), EST_CLAMP_LEVEL_COUNT, PASS_COUNT, 0);
    for (int slot = 0; slot < images_of_pixel; ++slot)
        for (int c = 0; c < EST_CHANNELS; ++c)
            images[((ulong)slot * pixel_count + pixel) * EST_CHANNELS + c] = rgb[slot][c];
}

/* zirr's image from the cascades (the state's zirr block) and set sums of
 * a whole width x height image (its neighbourhoods cross any split of the
 * pixels among devices), in two steps, one work item a pixel each: the
 * cascades' means (K RGB floats a pixel), then the image (RGB,
 * pixel-interleaved). */
__kernel void zirr_means(__global const ulong *cascades, __global const ulong *accumulators, ulong pixel_count,
                         ulong sample_count, __global float *cascade_means)
{
    ulong pixel = get_global_id(0);
    if (pixel >= pixel_count)
        return;
    zirr_pixel_means(cascades, accumulators, EST_SETS, EST_ZIRR_COUNT, pixel, pixel_count, sample_count, cascade_means);
}

__kernel void estimate_zirr(__global const float *cascade_means, uint width, uint height, ulong sample_count,
                            __global float *image)
{
    ulong pixel = get_global_id(0);
    if (pixel >= (ulong)width * height)
        return;
    float rgb[EST_CHANNELS];
    zirr_estimate(cascade_means, (uint)(pixel % width), (uint)(pixel / width), width, height, EST_ZIRR_COUNT,
                  EST_ZIRR_BASE, EST_ZIRR_KAPPA, EST_ZIRR_EMIN, sample_count, rgb);
    for (int c = 0; c < EST_CHANNELS; ++c)
        image[pixel * EST_CHANNELS + c] = rgb[c];
}

/* Drives the accumulation from a stream (tests): work item p adds
 * parts[p][i] (SampleParts as 10 floats: film RGB, direct RGB, indirect
 * RGB, weight) to pixel p, as sample first_sample + i, to the set sums
 * `accumulators` (EST_SETS sets) and the per-sample state, as the path
 * tracer adds a sample. */
__kernel void accumulate_sample_stream(__global const float *parts, ulong stream_length, __global ulong *accumulators,
                                       __global ulong *state, ulong pixel_count, float direct_limit,
                                       float indirect_limit, ulong first_sample)
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
        s.set = set_of_sample(first_sample + i, EST_SETS);
        s.set_count = EST_SETS;
        float x[EST_CHANNELS];
        sample_film_weighted(&s, x);
        accumulate_sample(accumulators, pixel, pixel_count, EST_SETS, s.set, x[0], x[1], x[2]);
        sample_passes_add(state, pixel, pixel_count, EST_SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT, levels, direct_limit,
                          indirect_limit, EST_ZIRR_COUNT, EST_ZIRR_BASE, &s);
    }
}
