/* A small 3-vector for shared host/kernel code (float3 differs in size
 * between C and OpenCL, so it is not used across the boundary). */
#ifndef KERNELS_VEC3_H
#define KERNELS_VEC3_H

#include "compat.h"

#ifndef __OPENCL_C_VERSION__
#define sqrt_float(x) sqrtf(x)
#define sin_float(x) sinf(x)
#define cos_float(x) cosf(x)
#define exp_float(x) expf(x)
#define log_float(x) logf(x)
#else
#define sqrt_float(x) sqrt(x)
#define exp_float(x) exp(x)
#define log_float(x) log(x)
/* Sampling angles in [0, 2 pi): pocl's native versions are within 1.2e-7
 * there and skip the full-range argument reduction (about 7% of a render). */
#define sin_float(x) native_sin(x)
#define cos_float(x) native_cos(x)
#endif

#define PI_F 3.14159265358979323846f

typedef struct {
    float x, y, z;
} Vec3;

KERNEL_FN Vec3 vec3(float x, float y, float z)
{
    Vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

KERNEL_FN Vec3 vec3_from(const float *p)
{
    return vec3(p[0], p[1], p[2]);
}

KERNEL_FN Vec3 vec3_from_global(const GLOBAL float *p)
{
    return vec3(p[0], p[1], p[2]);
}

KERNEL_FN Vec3 v_add(Vec3 a, Vec3 b)
{
    return vec3(a.x + b.x, a.y + b.y, a.z + b.z);
}

KERNEL_FN Vec3 v_sub(Vec3 a, Vec3 b)
{
    return vec3(a.x - b.x, a.y - b.y, a.z - b.z);
}

KERNEL_FN Vec3 v_mul(Vec3 a, Vec3 b)
{
    return vec3(a.x * b.x, a.y * b.y, a.z * b.z);
}

KERNEL_FN Vec3 v_scale(Vec3 a, float s)
{
    return vec3(a.x * s, a.y * s, a.z * s);
}

KERNEL_FN float v_dot(Vec3 a, Vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

KERNEL_FN Vec3 v_cross(Vec3 a, Vec3 b)
{
    return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

KERNEL_FN float v_length(Vec3 a)
{
    return sqrt_float(v_dot(a, a));
}

KERNEL_FN Vec3 v_normalize(Vec3 a)
{
    return v_scale(a, 1.0f / v_length(a));
}

KERNEL_FN float v_max_component(Vec3 a)
{
    float m = a.x > a.y ? a.x : a.y;
    return m > a.z ? m : a.z;
}

KERNEL_FN float v_luminance(Vec3 a)
{
    return 0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z;
}

/* An orthonormal basis around unit n (Duff et al. 2017). */
KERNEL_FN void v_basis(Vec3 n, Vec3 *s, Vec3 *t)
{
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    *s = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t = vec3(b, sign + n.y * n.y * a, -n.y);
}

#endif
