/* Sampling a piecewise-constant 1D distribution by its CDF (n + 1 values,
 * 0 to 1): the image lights' and the pixel filter's 2D distributions are a
 * marginal CDF over rows and one CDF per row (scene_types.h). Host and
 * kernels share it (the host tests sample filters with it). */
#ifndef KERNELS_DISTRIBUTION_H
#define KERNELS_DISTRIBUTION_H

#include "../common/compat.h"

/* Index i of the interval [cdf[i], cdf[i + 1]) that holds u, among n. */
KERNEL_FN uint32_t cdf_find(const GLOBAL float *cdf, uint32_t n, float u)
{
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        uint32_t mid = (lo + hi + 1) / 2;
        if (cdf[mid] <= u)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* A position in [0, 1) distributed as the CDF says, uniform within its
 * interval, whose index it writes. */
KERNEL_FN float cdf_sample(const GLOBAL float *cdf, uint32_t n, float u, uint32_t *index)
{
    uint32_t i = cdf_find(cdf, n, u);
    float width = cdf[i + 1] - cdf[i];
    float offset = width > 0.0f ? (u - cdf[i]) / width : 0.5f;
    *index = i;
    return fmin(((float)i + fmin(offset, 0.99999994f)) / (float)n, 0.99999994f);
}

#endif
