/* The film: a render's per-set sums and the passes estimated from them
 * (kernels/film/passes.h lists every pass). This header is the host side of the
 * one estimation code in kernels/film/estimators.h: the settings (with the only
 * check of M's range), the pass and parameter names, and the host
 * estimation, the reference the kernels are tested against and what
 * re-estimates a saved render. estimator_program.h runs the same on a device,
 * film_merge.h adds renders of sample ranges, film_file.h is the render
 * file's schema.
 *
 * Set sums are planes [set][channel][pixel] of floats; accumulators are the
 * renderer's exact sums, accumulator_planes(M) planes of uint64 (the grid
 * plane, then [set][channel][word][pixel]: kernels/film/accumulate.h). Every
 * pixel has sample_count samples, sample s in set s mod M. */
#ifndef HOST_FILM_FILM_H
#define HOST_FILM_FILM_H

#include "accumulate.h" /* kernels/: EST_MAX_SETS */
#include "passes.h"

#include <stddef.h>
#include <stdint.h>

#define ESTIMATOR_DEFAULT_SETS 21
#define FILM_MAX_SETS EST_MAX_SETS

typedef enum {
    GINI_PER_CHANNEL = 0, /* default */
    GINI_PER_PIXEL = 1,
    SORT_BY_LUMINANCE = 2,
} GiniMode;

typedef struct {
    int set_count; /* M, 1..FILM_MAX_SETS */
    GiniMode gini_mode;
    /* Index of the input's first sample (a render of a sample range): its
     * sets fill from set first_sample mod M on, which decides which sets
     * hold one sample more when n is not a multiple of M. */
    uint64_t first_sample;
    uint32_t passes; /* PASS_BIT mask of the images wanted */
    int with_stderr; /* also <estimate>.stderr for each estimate in passes */
    EstimatorParams params;
} EstimatorSettings;

/* M = 21, per-channel Gini, mean + MoN + G-MoN, the parameters' defaults. */
void estimator_settings_default(EstimatorSettings *settings);

/* Checks M's range (the one place that does): 0, or -1 with a one-line
 * reason in message (may be NULL). */
int film_check_set_count(int set_count, char *message, size_t message_size);

/* Checks everything in settings: M, the Gini mode, the passes, the
 * parameters' ranges, and that standard errors are not asked for with
 * sort-by-luminance. 0, or -1 with a reason. */
int estimator_settings_check(const EstimatorSettings *settings, char *message, size_t message_size);

/* Pass names (passes.h): the name of a pass id; the id of a name, or -1. */
const char *pass_name(int pass);
int pass_from_name(const char *name);
int pass_type(int pass); /* PASS_FLOAT or PASS_INT */

/* Parses a comma-separated list of pass names, or "all" (every estimate),
 * into a mask. 0, or -1 with a reason naming the unknown name. */
int passes_from_list(const char *list, uint32_t *passes, char *message, size_t message_size);

/* Sets one parameter from "name=value" (GMON_ESTIMATOR_PARAMS in
 * passes.h). 0, or -1 with a reason. */
int estimator_param_set(EstimatorParams *params, const char *assignment, char *message, size_t message_size);

/* The parameters, one per line index: its name and its value as text
 * (floats exactly, as %.9g). Returns the number of parameters; 0 <= index
 * < that. */
int estimator_param_count(void);
void estimator_param_format(const EstimatorParams *params, int index, const char **name, char *value,
                            size_t value_size);

/* Output images, 3 values (RGB) per pixel; NULL where not wanted. A pass of
 * type PASS_INT holds int32_t values, the others floats. */
typedef struct {
    void *pass[PASS_COUNT];
    float *error[PASS_COUNT]; /* standard errors (settings.with_stderr) */
    size_t length;            /* elements in each non-NULL buffer, >= 3 * pixel_count */
} EstimatorImages;

typedef enum {
    ESTIMATOR_OK = 0,
    ESTIMATOR_INVALID_ARGUMENT = 1,
    ESTIMATOR_OUT_OF_MEMORY = 2, /* a working buffer could not be allocated */
} EstimatorStatus;

/* Estimates every pixel from float set sums (set_sums_length >= M * 3 *
 * pixel_count), each pass of settings.passes whose image is not NULL. On a
 * bad argument returns ESTIMATOR_INVALID_ARGUMENT and puts a one-line reason
 * in `message` (may be NULL). */
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
