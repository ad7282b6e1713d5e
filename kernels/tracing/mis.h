/* Multiple importance sampling weights, shared by the path tracer and the
 * layered BSDFs' random walks (host and kernels). */
#ifndef KERNELS_MIS_H
#define KERNELS_MIS_H

#include "../common/compat.h"

/* The power heuristic (exponent 2) for one sample of each strategy:
 * a^2 / (a^2 + b^2), as 1 / (1 + (b / a)^2) so that densities past 1e19
 * (a tiny light seen from afar) do not overflow their squares. */
KERNEL_FN float power_heuristic(float a, float b)
{
    if (!(a > 0.0f))
        return 0.0f;
    if (!(b > 0.0f))
        return 1.0f;
    if (b > a) {
        float r = a / b;
        return r * r / (1.0f + r * r);
    }
    float r = b / a;
    return 1.0f / (1.0f + r * r);
}

#endif
