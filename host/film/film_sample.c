#include "film/film_sample.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

uint32_t film_sample_passes(const EstimatorSettings *s)
{
    return s->passes & PASSES_SAMPLE;
}

size_t film_sample_planes(const EstimatorSettings *s)
{
    const uint32_t passes = film_sample_passes(s);
    return sample_state_planes(passes, s->params.clamp_level_count, s->params.zirr_k) +
           sample_square_planes(passes, (uint32_t)s->set_count);
}

int film_sample_pass_images(const EstimatorSettings *s, int pass)
{
    return sample_pass_images(film_sample_passes(s), s->params.clamp_level_count, pass);
}

int film_sample_images(const EstimatorSettings *s)
{
    return sample_image_slot(film_sample_passes(s), s->params.clamp_level_count, PASS_COUNT, 0);
}

/* A float as an OpenCL C literal that is exactly it. */
static void float_literal(float x, char *text, size_t size)
{
    if (isinf(x))
        snprintf(text, size, "INFINITY");
    else
        snprintf(text, size, "%af", (double)x);
}

void film_sample_build_options(const EstimatorSettings *s, char *options, size_t size)
{
    const uint32_t passes = film_sample_passes(s);
    options[0] = '\0';
    if (!passes)
        return;
    int used = snprintf(options, size, " -DEST_SAMPLE_PASSES=0x%xu%s", (unsigned)passes,
                        film_sample_needs_double(s) ? " -DSAMPLE_SUMS_DOUBLE" : "");
    if (passes & PASS_BIT(PASS_CLAMP)) {
        used += snprintf(options + used, size - (size_t)used,
                         " -DEST_CLAMP_LEVEL_COUNT=%d -DEST_CLAMP_LEVEL_VALUES=", s->params.clamp_level_count);
        for (int i = 0; i < s->params.clamp_level_count && (size_t)used < size; ++i) {
            char literal[48];
            float_literal(s->params.clamp_levels[i], literal, sizeof literal);
            used += snprintf(options + used, size - (size_t)used, "%s%s", i ? "," : "", literal);
        }
    }
    if ((passes & PASS_BIT(PASS_CLAMP_SUM)) && (size_t)used < size) {
        char direct[48], indirect[48];
        float_literal(s->params.clamp_sum_direct, direct, sizeof direct);
        float_literal(s->params.clamp_sum_indirect, indirect, sizeof indirect);
        used += snprintf(options + used, size - (size_t)used, " -DEST_CLAMP_SUM_DIRECT=%s -DEST_CLAMP_SUM_INDIRECT=%s",
                         direct, indirect);
    }
    if ((passes & PASS_BIT(PASS_ZIRR)) && (size_t)used < size) {
        char base[48], kappa[48], emin[48];
        float_literal(s->params.zirr_base, base, sizeof base);
        float_literal(s->params.zirr_kappa, kappa, sizeof kappa);
        float_literal(s->params.zirr_emin, emin, sizeof emin);
        snprintf(options + used, size - (size_t)used,
                 " -DEST_ZIRR_COUNT=%d -DEST_ZIRR_BASE=%s -DEST_ZIRR_KAPPA=%s -DEST_ZIRR_EMIN=%s", s->params.zirr_k,
                 base, kappa, emin);
    }
}

int film_sample_needs_double(const EstimatorSettings *s)
{
    return (s->passes & (SAMPLE_MOMENT_PASSES | PASS_BIT(PASS_MEAN_OR_MON))) != 0;
}

int film_sample_needs_sets(const EstimatorSettings *s)
{
    return (s->passes & (PASS_BIT(PASS_GABMM) | PASS_BIT(PASS_MEAN_OR_MON))) != 0;
}

void film_sample_estimator_options(const EstimatorSettings *s, char *options, size_t size)
{
    film_sample_build_options(s, options, size);
    size_t used = strlen(options);
    if (film_sample_needs_double(s) && used < size)
        used += (size_t)snprintf(options + used, size - used, " -DSAMPLE_PASSES_DOUBLE");
    if (used < size) /* every pass reads the set sums */
        snprintf(options + used, size - used, " -DEST_SETS=%d", s->set_count);
}

void film_sample_layer_name(const EstimatorSettings *s, int pass, int index, char *name, size_t size)
{
    if (pass != PASS_CLAMP) {
        snprintf(name, size, "%s", pass_name(pass));
        return;
    }
    float level = s->params.clamp_levels[index];
    if (isinf(level)) {
        snprintf(name, size, "clamp-inf");
        return;
    }
    for (int digits = 1; digits <= 9; ++digits) {
        snprintf(name, size, "clamp-%.*g", digits, (double)level);
        if (strtof(name + 6, NULL) == level)
            return;
    }
}

int film_sample_select_film_clamp(EstimatorSettings *s, float level)
{
    EstimatorParams *p = &s->params;
    if (!(s->passes & PASS_BIT(PASS_CLAMP))) {
        /* The levels asked for are the defaults, not the user's: only V. */
        p->clamp_level_count = 0;
        s->passes |= PASS_BIT(PASS_CLAMP);
    }
    for (int i = 0; i < p->clamp_level_count; ++i)
        if (p->clamp_levels[i] == level)
            return i;
    if (p->clamp_level_count == EST_CLAMP_LEVELS_MAX)
        return -1;
    p->clamp_levels[p->clamp_level_count] = level;
    return p->clamp_level_count++;
}

void film_sample_memory_summary(const EstimatorSettings *s, char *line, size_t size)
{
    static const char *const block_names[SAMPLE_BLOCKS] = {"clamp", "clamp-sum", "shifts and sums of d^3", "zirr"};
    const uint32_t passes = film_sample_passes(s);
    size_t used = 0;
    line[0] = '\0';
    for (int block = 0; block < SAMPLE_BLOCKS && used < size; ++block) {
        size_t bytes =
            sample_block_planes(passes, s->params.clamp_level_count, s->params.zirr_k, block) * sizeof(uint64_t);
        if (!bytes)
            continue;
        if (block == SAMPLE_BLOCK_CLAMP)
            used += (size_t)snprintf(line + used, size - used, "%sclamp (%d level%s) %zu B", used ? ", " : "",
                                     s->params.clamp_level_count, s->params.clamp_level_count == 1 ? "" : "s", bytes);
        else if (block == SAMPLE_BLOCK_ZIRR)
            used += (size_t)snprintf(line + used, size - used, "%szirr (K = %d cascades) %zu B", used ? ", " : "",
                                     s->params.zirr_k, bytes);
        else
            used +=
                (size_t)snprintf(line + used, size - used, "%s%s %zu B", used ? ", " : "", block_names[block], bytes);
    }
    size_t squares = sample_square_planes(passes, (uint32_t)s->set_count) * sizeof(uint64_t);
    if (squares && used < size) {
        const uint32_t count = sample_square_count(passes, (uint32_t)s->set_count);
        snprintf(line + used, size - used, "%ssums of d^2 (%u set%s) %zu B", used ? ", " : "", count,
                 count == 1 ? "" : "s", squares);
    }
}

EstimatorStatus film_sample_estimate(const EstimatorSettings *s, const uint64_t *state, size_t state_length,
                                     const uint64_t *accumulators, size_t pixel_count, uint64_t sample_count,
                                     EstimatorImages *images, char *message, size_t message_size)
{
    const uint32_t passes = film_sample_passes(s);
    const size_t planes = film_sample_planes(s);
    if (!state || !accumulators || !images || state_length < planes * pixel_count ||
        images->length < pixel_count * EST_CHANNELS) {
        if (message && message_size)
            snprintf(message, message_size, "per-sample state, set sums or images missing or too short");
        return ESTIMATOR_INVALID_ARGUMENT;
    }
    const uint32_t pixel_passes = SAMPLE_PIXEL_PASSES(passes);
    const int levels = s->params.clamp_level_count;
    for (size_t p = 0; p < pixel_count; ++p) {
        float rgb[SAMPLE_PIXEL_IMAGES_MAX][EST_CHANNELS];
        sample_pixel_estimates(state, accumulators, p, pixel_count, passes, levels, s->params.zirr_k,
                               (uint32_t)s->set_count, s->first_sample, sample_count, rgb);
        for (int pass = PASS_CLAMP; pass < PASS_COUNT; ++pass)
            for (int i = 0; images->pass[pass] && i < sample_pass_images(pixel_passes, levels, pass); ++i)
                memcpy((float *)images->pass[pass] + ((size_t)i * pixel_count + p) * EST_CHANNELS,
                       rgb[sample_image_slot(pixel_passes, levels, pass, i)], sizeof rgb[0]);
    }
    return ESTIMATOR_OK;
}

const uint64_t *film_sample_zirr_block(const EstimatorSettings *s, const uint64_t *state, size_t pixel_count)
{
    return state +
           (size_t)sample_block_first_plane(film_sample_passes(s), s->params.clamp_level_count, SAMPLE_BLOCK_ZIRR) *
               pixel_count;
}

size_t film_sample_zirr_planes(const EstimatorSettings *s)
{
    return sample_block_planes(film_sample_passes(s), s->params.clamp_level_count, s->params.zirr_k, SAMPLE_BLOCK_ZIRR);
}

EstimatorStatus film_sample_estimate_zirr(const EstimatorSettings *s, const uint64_t *state, size_t state_length,
                                          const uint64_t *accumulators, uint32_t width, uint32_t height,
                                          uint64_t sample_count, float *image, char *message, size_t message_size)
{
    const size_t pixel_count = (size_t)width * height;
    if (!(film_sample_passes(s) & PASS_BIT(PASS_ZIRR)) || !state || !accumulators || !image || !pixel_count ||
        state_length < film_sample_planes(s) * pixel_count) {
        if (message && message_size)
            snprintf(message, message_size, "zirr not requested, or its state or image missing or too short");
        return ESTIMATOR_INVALID_ARGUMENT;
    }
    const EstimatorParams *p = &s->params;
    const uint64_t *cascades = film_sample_zirr_block(s, state, pixel_count);
    float *means = malloc(pixel_count * (size_t)p->zirr_k * EST_CHANNELS * sizeof(float));
    if (!means) {
        if (message && message_size)
            snprintf(message, message_size, "out of memory for zirr's cascade means");
        return ESTIMATOR_OUT_OF_MEMORY;
    }
    for (size_t pixel = 0; pixel < pixel_count; ++pixel)
        zirr_pixel_means(cascades, accumulators, (uint32_t)s->set_count, p->zirr_k, pixel, pixel_count, sample_count,
                         means);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            zirr_estimate(means, x, y, width, height, p->zirr_k, p->zirr_base, p->zirr_kappa, p->zirr_emin,
                          sample_count, image + ((size_t)y * width + x) * EST_CHANNELS);
    free(means);
    return ESTIMATOR_OK;
}

int film_sample_add(const EstimatorSettings *s, uint64_t *accumulators, uint64_t *state, size_t pixel,
                    size_t pixel_count, const SampleParts *sample)
{
    float x[EST_CHANNELS];
    sample_film_weighted(sample, x);
    accumulate_sample(accumulators, pixel, pixel_count, sample->set_count, sample->set, x[0], x[1], x[2]);
    return sample_passes_add(state, pixel, pixel_count, film_sample_passes(s), s->params.clamp_level_count,
                             s->params.clamp_levels, s->params.clamp_sum_direct, s->params.clamp_sum_indirect,
                             s->params.zirr_k, s->params.zirr_base, sample);
}

int film_sample_add_splat(const EstimatorSettings *s, uint64_t *accumulators, uint64_t *state, size_t pixel,
                          size_t pixel_count, uint32_t set, uint32_t set_count, const float *rgb)
{
    const SampleParts sample = splat_sample_parts(rgb, set, set_count);
    return film_sample_add(s, accumulators, state, pixel, pixel_count, &sample);
}
