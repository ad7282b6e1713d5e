/* Deterministic random numbers and sample streams for tests and benchmarks
 * (host only; long double and libm are fine here). */
#ifndef TESTS_SUPPORT_SAMPLE_STREAMS_H
#define TESTS_SUPPORT_SAMPLE_STREAMS_H

#include <stdint.h>

typedef struct {
    uint64_t state;
} TestRng;

TestRng test_rng(uint64_t seed);
uint64_t test_rng_next(TestRng *rng);
/* Uniform in (0, 1]: never 0, so Pareto draws stay finite. */
double test_rng_uniform(TestRng *rng);
double test_rng_gaussian(TestRng *rng);

/* Pareto with x_min = 1 and tail index alpha: mean alpha / (alpha - 1). */
double test_pareto(TestRng *rng, double alpha);

/* 1.0, except a spike of `spike` with probability p. */
double test_spiky(TestRng *rng, double spike, double p);

#endif
