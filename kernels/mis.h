/* Multiple importance sampling weights, shared by the path tracer and the
 * layered BSDFs' random walks (host and kernels). */
#ifndef KERNELS_MIS_H
#define KERNELS_MIS_H

#include "compat.h"

/* The power heuristic (exponent 2) for one sample of each strategy. */
KERNEL_FN float power_heuristic(float a, float b)
{
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

#endif
