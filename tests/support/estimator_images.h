/* Test images for every pass of an estimation (film.h's EstimatorImages),
 * allocated and compared as a whole. */
#ifndef TESTS_SUPPORT_ESTIMATOR_IMAGES_H
#define TESTS_SUPPORT_ESTIMATOR_IMAGES_H

#include "film/film.h"

#include <stddef.h>

/* Zeroed images for every pass in `passes` (and, with_stderr, the errors of
 * its estimates). */
EstimatorImages test_images_new(uint32_t passes, int with_stderr, size_t pixel_count);
void test_images_free(EstimatorImages *images);

/* The float image of pass p (NULL if absent). */
#define TEST_IMAGE(images, p) ((const float *)(images).pass[p])

/* Fails, naming the first differing value, unless every image present in
 * both is identical bit for bit (NaN included). */
void assert_images_identical(const EstimatorImages *a, const EstimatorImages *b, size_t pixel_count, const char *what);

#endif
