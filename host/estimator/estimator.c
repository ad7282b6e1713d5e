#include "estimator/estimator.h"

#include "estimator_core.h" /* kernels/: the shared core */

#include <stdarg.h>
#include <stdio.h>

static EstimatorStatus invalid(char *message, size_t message_size, const char *format, ...)
{
    if (message && message_size > 0) {
        va_list args;
        va_start(args, format);
        vsnprintf(message, message_size, format, args);
        va_end(args);
    }
    return ESTIMATOR_INVALID_ARGUMENT;
}

/* accumulators: the input is accumulators (else float set sums). */
static EstimatorStatus check_common(const EstimatorSettings *settings, size_t input_length, int accumulators,
                                    size_t pixel_count, const EstimatorImages *images, char *message,
                                    size_t message_size)
{
    if (!settings)
        return invalid(message, message_size, "settings is NULL");
    if (settings->set_count < 1 || settings->set_count > EST_MAX_SETS)
        return invalid(message, message_size, "set count M = %d is out of range 1..%d", settings->set_count,
                       EST_MAX_SETS);
    if (settings->gini_mode != GINI_PER_CHANNEL && settings->gini_mode != GINI_PER_PIXEL &&
        settings->gini_mode != SORT_BY_LUMINANCE)
        return invalid(message, message_size, "unknown Gini mode %d", (int)settings->gini_mode);
    size_t needed =
        accumulators ? accumulator_planes((uint32_t)settings->set_count) : (size_t)settings->set_count * EST_CHANNELS;
    if (pixel_count > SIZE_MAX / needed)
        return invalid(message, message_size, "pixel count %zu is too large", pixel_count);
    if (input_length < needed * pixel_count)
        return invalid(message, message_size, "input holds %zu values, %zu needed (M = %d, %zu pixels)", input_length,
                       needed * pixel_count, settings->set_count, pixel_count);
    if (!images)
        return invalid(message, message_size, "images is NULL");
    if (!images->mean && !images->mon && !images->gmon && !images->gini && !images->trim)
        return invalid(message, message_size, "no output image requested");
    if (images->length / EST_CHANNELS < pixel_count)
        return invalid(message, message_size, "output images hold %zu values, %zu needed", images->length,
                       pixel_count * EST_CHANNELS);
    return ESTIMATOR_OK;
}

static void store(const PixelEstimates *e, size_t pixel, EstimatorImages *images)
{
    for (int c = 0; c < EST_CHANNELS; ++c) {
        size_t i = pixel * EST_CHANNELS + (size_t)c;
        if (images->mean)
            images->mean[i] = e->mean[c];
        if (images->mon)
            images->mon[i] = e->mon[c];
        if (images->gmon)
            images->gmon[i] = e->gmon[c];
        if (images->gini)
            images->gini[i] = e->gini[c];
        if (images->trim)
            images->trim[i] = e->trim[c];
    }
}

EstimatorStatus estimator_from_sums(const EstimatorSettings *settings, const float *set_sums, size_t set_sums_length,
                                    size_t pixel_count, uint64_t sample_count, EstimatorImages *images, char *message,
                                    size_t message_size)
{
    if (!set_sums)
        return invalid(message, message_size, "set sums are NULL");
    EstimatorStatus status = check_common(settings, set_sums_length, 0, pixel_count, images, message, message_size);
    if (status != ESTIMATOR_OK)
        return status;
    const uint32_t m = (uint32_t)settings->set_count;
    const uint32_t first_set = (uint32_t)(settings->first_sample % m);
    for (size_t p = 0; p < pixel_count; ++p) {
        float sums[EST_CHANNELS][EST_CAPACITY];
        for (uint32_t j = 0; j < m; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c)
                sums[c][j] = set_sums[set_sum_index((j + first_set) % m, c, p, pixel_count)];
        PixelEstimates e = estimate_pixel(sums, sample_count, (int)m, (int)settings->gini_mode);
        store(&e, p, images);
    }
    return ESTIMATOR_OK;
}

/* The sums of one pixel in grid units, sums[c][j] from set (j + first_set)
 * mod m (so that j counts sets in the order the samples filled them); returns
 * the pixel's grid exponent. */
static int sums_of_pixel(const uint64_t *accumulators, uint32_t m, uint32_t first_set, size_t pixel, size_t pixel_count,
                         float sums[EST_CHANNELS][EST_CAPACITY])
{
    for (uint32_t j = 0; j < m; ++j)
        for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
            FixedSum s;
            uint32_t set = (j + first_set) % m;
            s.lo = accumulators[accumulator_index(set, c, 0, pixel, pixel_count)];
            s.hi = accumulators[accumulator_index(set, c, 1, pixel, pixel_count)];
            sums[c][j] = fixed_to_float(s);
        }
    return grid_exponent(accumulators[grid_index(pixel)]);
}

EstimatorStatus estimator_from_accumulators(const EstimatorSettings *settings, const uint64_t *accumulators,
                                            size_t accumulators_length, size_t pixel_count, uint64_t sample_count,
                                            EstimatorImages *images, char *message, size_t message_size)
{
    if (!accumulators)
        return invalid(message, message_size, "accumulators are NULL");
    EstimatorStatus status = check_common(settings, accumulators_length, 1, pixel_count, images, message, message_size);
    if (status != ESTIMATOR_OK)
        return status;
    const uint32_t m = (uint32_t)settings->set_count;
    const uint32_t first_set = (uint32_t)(settings->first_sample % m);
    for (size_t p = 0; p < pixel_count; ++p) {
        float sums[EST_CHANNELS][EST_CAPACITY];
        int exponent = sums_of_pixel(accumulators, m, first_set, p, pixel_count, sums);
        PixelEstimates e = estimate_pixel(sums, sample_count, (int)m, (int)settings->gini_mode);
        estimates_to_grid(&e, exponent);
        store(&e, p, images);
    }
    return ESTIMATOR_OK;
}

EstimatorStatus estimator_sums_from_accumulators(int set_count, const uint64_t *accumulators,
                                                 size_t accumulators_length, size_t pixel_count, float *set_sums,
                                                 size_t set_sums_length, char *message, size_t message_size)
{
    if (!accumulators || !set_sums)
        return invalid(message, message_size, "accumulators or set sums are NULL");
    if (set_count < 1 || set_count > EST_MAX_SETS)
        return invalid(message, message_size, "set count M = %d is out of range 1..%d", set_count, EST_MAX_SETS);
    size_t values = (size_t)set_count * EST_CHANNELS, planes = accumulator_planes((uint32_t)set_count);
    if (pixel_count > SIZE_MAX / planes)
        return invalid(message, message_size, "pixel count %zu is too large", pixel_count);
    if (accumulators_length < planes * pixel_count || set_sums_length < values * pixel_count)
        return invalid(message, message_size, "buffers too short for M = %d and %zu pixels", set_count, pixel_count);
    for (size_t p = 0; p < pixel_count; ++p) {
        float sums[EST_CHANNELS][EST_CAPACITY];
        int exponent = sums_of_pixel(accumulators, (uint32_t)set_count, 0, p, pixel_count, sums);
        for (uint32_t j = 0; j < (uint32_t)set_count; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c)
                set_sums[set_sum_index(j, c, p, pixel_count)] = scale_by_grid(sums[c][j], exponent);
    }
    return ESTIMATOR_OK;
}
