/* pbrt-v4's equal-area octahedral mapping between the unit square and the
 * unit sphere (Clarberg's), used by its environment maps: equal areas of
 * the square map to equal solid angles, so a density p over the square is
 * p / (4 pi) over directions. Shared by the host (which builds the
 * sampling distribution) and the kernels. (u, v) in [0, 1]^2. */
#ifndef KERNELS_EQUAL_AREA_H
#define KERNELS_EQUAL_AREA_H

#include "../common/compat.h"
#include "../common/vec3.h"

#ifdef __OPENCL_C_VERSION__
#define ea_atan(x) atan(x)
#define ea_copysign(x, y) copysign(x, y)
#else
#define ea_atan(x) atanf(x)
#define ea_copysign(x, y) copysignf(x, y)
#endif

KERNEL_FN Vec3 equal_area_square_to_sphere(float u, float v)
{
    float x = 2.0f * u - 1.0f, y = 2.0f * v - 1.0f;
    float ax = fabs(x), ay = fabs(y);
    float signed_distance = 1.0f - (ax + ay);
    float r = 1.0f - fabs(signed_distance);
    float phi = (r == 0.0f ? 1.0f : (ay - ax) / r + 1.0f) * (PI_F / 4.0f);
    float z = ea_copysign(1.0f - r * r, signed_distance);
    float cos_phi = ea_copysign(cos_float(phi), x), sin_phi = ea_copysign(sin_float(phi), y);
    float s = r * sqrt_float(fmax(0.0f, 2.0f - r * r));
    return vec3(cos_phi * s, sin_phi * s, z);
}

/* The inverse, for a unit direction d. */
KERNEL_FN void equal_area_sphere_to_square(Vec3 d, float *u_out, float *v_out)
{
    float x = fabs(d.x), y = fabs(d.y), z = fabs(d.z);
    float r = sqrt_float(fmax(0.0f, 1.0f - z));
    float a = fmax(x, y), b = fmin(x, y);
    b = a == 0.0f ? 0.0f : b / a;
    float phi = ea_atan(b) * (2.0f / PI_F);
    if (x < y)
        phi = 1.0f - phi;
    float v = phi * r, u = r - v;
    if (d.z < 0.0f) {
        float swap = u;
        u = 1.0f - v;
        v = 1.0f - swap;
    }
    u = ea_copysign(u, d.x);
    v = ea_copysign(v, d.y);
    *u_out = 0.5f * (u + 1.0f);
    *v_out = 0.5f * (v + 1.0f);
}

#endif
