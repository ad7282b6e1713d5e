/* An exact sum of floats, independent of the renderer's accumulator: a
 * 384-bit two's complement integer in units of 2^-160, wide enough for any
 * sum of up to 2^60 floats (a long accumulator, as Kulisch's), and the
 * correctly rounded float of it. Host only, for tests. */
#ifndef TESTS_SUPPORT_EXACT_SUM_H
#define TESTS_SUPPORT_EXACT_SUM_H

#include <stddef.h>
#include <stdint.h>

#define EXACT_SUM_WORDS 12

typedef struct {
    uint32_t words[EXACT_SUM_WORDS]; /* words[0] the lowest */
} ExactSum;

/* Adds a finite float. */
void exact_sum_add(ExactSum *sum, float x);

/* The sum rounded to the nearest float, ties to even (inf past FLT_MAX). */
float exact_sum_to_float(const ExactSum *sum);

/* The sum as a long double: its 64 leading bits, the last one sticky for
 * the rest (so within 2^-63 relative, and rounding to float correctly). */
long double exact_sum_to_long_double(const ExactSum *sum);

/* Set j, channel c of pixel p of an accumulation buffer (the renderer's
 * layout: kernels/film/accumulate.h) as a long double. */
long double test_set_sum(const uint64_t *accumulators, uint32_t set, uint32_t channel, size_t pixel,
                         size_t pixel_count);

#endif
