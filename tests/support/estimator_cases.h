/* The estimator's test inputs, shared by the kernel == host tests and the
 * long-double reference tests: float set sums, planes [set][channel][pixel],
 * for one M. */
#ifndef TESTS_SUPPORT_ESTIMATOR_CASES_H
#define TESTS_SUPPORT_ESTIMATOR_CASES_H

#include <stddef.h>
#include <stdint.h>

typedef enum {
    CASE_RANDOM,
    CASE_ZEROS,
    CASE_ALL_EQUAL,
    CASE_ONE_OUTLIER,
    CASE_FLT_MAX,
    CASE_DENORMALS,
    CASE_WIDE_MAGNITUDES, /* 1e-30 .. 1e30 in one pixel */
    CASE_NEGATIVE,        /* all means negative */
    CASE_MIXED_SIGNS,
    CASE_FEWER_SAMPLES_THAN_SETS,
    CASE_COUNT
} EstimatorCaseKind;

typedef struct {
    EstimatorCaseKind kind;
    const char *name;
    int set_count;
    size_t pixel_count;
    uint64_t sample_count;
    float *sums; /* set_count * 3 * pixel_count, malloc'd */
} EstimatorCase;

/* Builds case `kind` for M = set_count, deterministic in seed. */
EstimatorCase estimator_case_make(EstimatorCaseKind kind, int set_count, uint64_t seed);
void estimator_case_free(EstimatorCase *c);

/* Set j's sample count for n samples in M sets: ceil((n - j) / M). */
uint64_t estimator_case_set_samples(uint64_t sample_count, int set_count, int set);

#endif
