/* The per-sample estimators (passes.h, kind PASS_SAMPLE): the state the
 * path tracer updates with each sample beside the set sums, and the
 * estimates from it (ESTIMATORS.md, "Needing more per-pixel state").
 *
 *   clamp      pbrt-v4's Film "maxcomponentvalue": a sample whose largest
 *              component exceeds V is scaled by V / max, at each of the
 *              levels V of clamp.levels; one sum per level
 *   clamp-sum  Cycles' sample clamping: if |r| + |g| + |b| > L the sample
 *              is scaled by L / that sum, with L = clamp-sum.direct for
 *              its direct light and clamp-sum.indirect for the rest (0: no
 *              clamping); one sum
 * Both clamp the film's response to the radiance before the pixel filter's
 * weight multiplies it, as pbrt-v4 does.
 *
 * Every sum is an exact fixed-point sum as the set sums are (accumulate.h):
 * a pass's sums form one block laid out as an accumulator of that many
 * "sets" (its own grid plane, then its sums), so the state depends only on
 * the samples, never on devices, pass batching or pixel moves. The blocks of
 * the requested passes follow each other in one buffer of uint64 planes.
 *
 * Valid C11 and OpenCL C 1.2 (host/film/film_sample.c is the host side, the
 * reference the kernels are tested against). In the path tracer and in
 * kernels/sample_estimator.cl EST_SAMPLE_PASSES is the mask of requested
 * passes and EST_CLAMP_LEVEL_VALUES their levels (build options); the host
 * passes both at run time. */
#ifndef KERNELS_SAMPLE_PASSES_H
#define KERNELS_SAMPLE_PASSES_H

#include "accumulate.h"
#include "estimator_numerics.h"
#include "passes.h"

/* RGB sums a pass keeps per pixel. */
KERNEL_FN uint32_t sample_pass_sums(uint32_t passes, int level_count, int pass)
{
    if (!(passes & PASS_BIT(pass)))
        return 0;
    return pass == PASS_CLAMP ? (uint32_t)level_count : 1u;
}

/* uint64 planes of a pass's block (0 if not requested). */
KERNEL_FN uint32_t sample_pass_planes(uint32_t passes, int level_count, int pass)
{
    uint32_t sums = sample_pass_sums(passes, level_count, pass);
    return sums ? accumulator_planes(sums) : 0u;
}

/* The first plane of a pass's block. */
KERNEL_FN uint32_t sample_pass_first_plane(uint32_t passes, int level_count, int pass)
{
    uint32_t plane = 0;
    for (int q = PASS_CLAMP; q < pass; ++q)
        plane += sample_pass_planes(passes, level_count, q);
    return plane;
}

/* Planes of the whole per-sample state. */
KERNEL_FN uint32_t sample_state_planes(uint32_t passes, int level_count)
{
    return sample_pass_first_plane(passes, level_count, PASS_COUNT);
}

/* RGB images a pass produces: one per clamp level, else one. */
KERNEL_FN int sample_pass_images(uint32_t passes, int level_count, int pass)
{
    return (int)sample_pass_sums(passes, level_count, pass);
}

/* The image slot of image `index` of a pass among all per-sample images. */
KERNEL_FN int sample_image_slot(uint32_t passes, int level_count, int pass, int index)
{
    int slot = index;
    for (int q = PASS_CLAMP; q < pass; ++q)
        slot += sample_pass_images(passes, level_count, q);
    return slot;
}

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

/* Cycles' rule: scaled by L / (|r| + |g| + |b|) when that exceeds L > 0. */
KERNEL_FN void clamp_component_sum(float *rgb, float limit)
{
    float sum = abs_float(rgb[0]) + abs_float(rgb[1]) + abs_float(rgb[2]);
    if (limit > 0.0f && sum > limit) {
        float scale = limit / sum;
        for (int c = 0; c < EST_CHANNELS; ++c)
            rgb[c] *= scale;
    }
}

/* One sample: its film response `film` (clamp's input) and that of its
 * direct and indirect parts (clamp-sum's), each multiplied by the pixel
 * filter's `weight` after clamping. */
typedef struct {
    float film[EST_CHANNELS];
    float direct[EST_CHANNELS];
    float indirect[EST_CHANNELS];
    float weight;
} SampleParts;

/* Adds one sample to the per-sample state of `pixel`. Returns EST_ADD_*
 * (the worst of its sums: non-finite samples are added to none). */
KERNEL_FN int sample_passes_add(GLOBAL uint64_t *state, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                int level_count, const float *levels, float direct_limit, float indirect_limit,
                                const SampleParts *s)
{
    int result = EST_ADD_EXACT;
    if (passes & PASS_BIT(PASS_CLAMP)) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_pass_first_plane(passes, level_count, PASS_CLAMP) * pixel_count;
        for (int level = 0; level < level_count; ++level) {
            float rgb[EST_CHANNELS];
            for (int c = 0; c < EST_CHANNELS; ++c)
                rgb[c] = s->film[c];
            clamp_largest_component(rgb, levels[level]);
            int added = accumulate_sample(block, pixel, pixel_count, (uint32_t)level_count, (uint32_t)level,
                                          rgb[0] * s->weight, rgb[1] * s->weight, rgb[2] * s->weight);
            result = added > result ? added : result;
        }
    }
    if (passes & PASS_BIT(PASS_CLAMP_SUM)) {
        GLOBAL uint64_t *block =
            state + (uint64_t)sample_pass_first_plane(passes, level_count, PASS_CLAMP_SUM) * pixel_count;
        float direct[EST_CHANNELS], indirect[EST_CHANNELS];
        for (int c = 0; c < EST_CHANNELS; ++c) {
            direct[c] = s->direct[c];
            indirect[c] = s->indirect[c];
        }
        clamp_component_sum(direct, direct_limit);
        clamp_component_sum(indirect, indirect_limit);
        int added = accumulate_sample(block, pixel, pixel_count, 1u, 0u, (direct[0] + indirect[0]) * s->weight,
                                      (direct[1] + indirect[1]) * s->weight, (direct[2] + indirect[2]) * s->weight);
        result = added > result ? added : result;
    }
    return result;
}

/* Image `index` of `pass` at `pixel` after sample_count samples: the sum's
 * mean, as the mean of a render of one set computes it (so that clamp at
 * V = INFINITY equals that mean bit for bit). */
KERNEL_FN void sample_pass_estimate(GLOBAL const uint64_t *state, uint64_t pixel, uint64_t pixel_count, uint32_t passes,
                                    int level_count, uint64_t sample_count, int pass, int index, float *rgb)
{
    GLOBAL const uint64_t *block = state + (uint64_t)sample_pass_first_plane(passes, level_count, pass) * pixel_count;
    int exponent = grid_exponent(block[grid_index(pixel)]);
    for (int c = 0; c < EST_CHANNELS; ++c) {
        uint64_t i = accumulator_index((uint32_t)index, (uint32_t)c, 0, pixel, pixel_count);
        float sum = fixed_to_float_lanes(block[i], block[i + pixel_count]);
        float mean = sample_count > 0 ? sum / (float)sample_count : 0.0f;
        rgb[c] = scale_by_grid(mean, exponent);
    }
}

#endif /* KERNELS_SAMPLE_PASSES_H */
