/* The per-pixel estimators (mean, MoN, G-MoN) on the host: the reference the
 * OpenCL kernels are tested against, and what re-estimates a saved render.
 * Both run the one implementation in kernels/estimator_core.h.
 *
 * Set sums are planes [set][channel][pixel] of floats; accumulators are the
 * renderer's exact sums, accumulator_planes(M) planes of uint64 (the grid
 * plane, then [set][channel][word][pixel]: kernels/estimator_core.h). Every
 * pixel has sample_count samples, sample s in set s mod M. */
#ifndef HOST_ESTIMATOR_ESTIMATOR_H
#define HOST_ESTIMATOR_ESTIMATOR_H

#include <stddef.h>
#include <stdint.h>

#define ESTIMATOR_DEFAULT_SETS 21

typedef enum {
    GINI_PER_CHANNEL = 0, /* default */
    GINI_PER_PIXEL = 1,
    SORT_BY_LUMINANCE = 2,
} GiniMode;

/* Which images to compute (a kernel's EST_OUTPUTS). */
enum {
    ESTIMATOR_OUTPUT_MEAN = 1,
    ESTIMATOR_OUTPUT_MON = 2,
    ESTIMATOR_OUTPUT_GMON = 4,
    ESTIMATOR_OUTPUT_DIAGNOSTICS = 8, /* Gini G and trim count c */
    ESTIMATOR_OUTPUT_ALL = 15,
};

typedef struct {
    int set_count; /* M, 1..64 */
    GiniMode gini_mode;
    /* Index of the input's first sample (a render of a sample range): its
     * sets fill from set first_sample mod M on, which decides which sets
     * hold one sample more when n is not a multiple of M. */
    uint64_t first_sample;
} EstimatorSettings;

/* Output images, 3 values (RGB) per pixel; NULL where not wanted. */
typedef struct {
    float *mean;
    float *mon;
    float *gmon;
    float *gini;   /* diagnostics: G used per channel */
    int32_t *trim; /* diagnostics: sets trimmed at each end, per channel */
    size_t length; /* elements in each non-NULL buffer, >= 3 * pixel_count */
} EstimatorImages;

typedef enum {
    ESTIMATOR_OK = 0,
    ESTIMATOR_INVALID_ARGUMENT = 1,
} EstimatorStatus;

/* Estimates every pixel from float set sums (set_sums_length >= M * 3 *
 * pixel_count). On a bad argument returns ESTIMATOR_INVALID_ARGUMENT and puts
 * a one-line reason in `message` (may be NULL). */
EstimatorStatus estimator_from_sums(const EstimatorSettings *settings, const float *set_sums, size_t set_sums_length,
                                    size_t pixel_count, uint64_t sample_count, EstimatorImages *images, char *message,
                                    size_t message_size);

/* The same from exact accumulators (length >= accumulator_planes(M) *
 * pixel_count). */
EstimatorStatus estimator_from_accumulators(const EstimatorSettings *settings, const uint64_t *accumulators,
                                            size_t accumulators_length, size_t pixel_count, uint64_t sample_count,
                                            EstimatorImages *images, char *message, size_t message_size);

/* Converts accumulators to float set sums (nearest float, as the kernels
 * do; a sum above FLT_MAX becomes infinite). */
EstimatorStatus estimator_sums_from_accumulators(int set_count, const uint64_t *accumulators,
                                                 size_t accumulators_length, size_t pixel_count, float *set_sums,
                                                 size_t set_sums_length, char *message, size_t message_size);

#endif
