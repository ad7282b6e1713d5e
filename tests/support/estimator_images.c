#include "estimator_images.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

EstimatorImages test_images_new(uint32_t passes, int with_stderr, size_t pixel_count)
{
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    images.length = pixel_count * 3;
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(passes & PASS_BIT(p)))
            continue;
        images.pass[p] = calloc(images.length, sizeof(float));
        assert_non_null(images.pass[p]);
        if (with_stderr && (PASSES_ESTIMATES & PASS_BIT(p))) {
            images.error[p] = calloc(images.length, sizeof(float));
            assert_non_null(images.error[p]);
        }
    }
    return images;
}

void test_images_free(EstimatorImages *images)
{
    for (int p = 0; p < PASS_COUNT; ++p) {
        free(images->pass[p]);
        free(images->error[p]);
    }
    memset(images, 0, sizeof *images);
}

static void assert_identical(const void *a, const void *b, size_t values, const char *what, const char *name,
                             int is_int)
{
    if (memcmp(a, b, values * 4) == 0)
        return;
    for (size_t k = 0; k < values; ++k) {
        uint32_t x, y;
        memcpy(&x, (const char *)a + 4 * k, 4);
        memcpy(&y, (const char *)b + 4 * k, 4);
        float fx, fy;
        memcpy(&fx, &x, 4);
        memcpy(&fy, &y, 4);
        if (x != y)
            fail_msg("%s: %s differs at pixel %zu channel %zu: %08x (%g) vs %08x (%g)", what, name, k / 3, k % 3, x,
                     is_int ? (double)(int32_t)x : (double)fx, y, is_int ? (double)(int32_t)y : (double)fy);
    }
}

void assert_images_identical(const EstimatorImages *a, const EstimatorImages *b, size_t pixel_count, const char *what)
{
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (a->pass[p] && b->pass[p])
            assert_identical(a->pass[p], b->pass[p], pixel_count * 3, what, pass_name(p), pass_type(p) == PASS_INT);
        if (a->error[p] && b->error[p]) {
            char name[64];
            snprintf(name, sizeof name, "%s.stderr", pass_name(p));
            assert_identical(a->error[p], b->error[p], pixel_count * 3, what, name, 0);
        }
    }
}
