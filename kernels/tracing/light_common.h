/* What every light's sampling shares (kernels/light_*.h): the sample it
 * returns, rotations into and out of a light's frame, and the texel of a
 * light's image. */
#ifndef KERNELS_LIGHT_COMMON_H
#define KERNELS_LIGHT_COMMON_H

#include "scene.h"

typedef struct {
    Vec3 wi;       /* unit, toward the light */
    Vec3 radiance; /* arriving along -wi, unoccluded */
    float pdf;     /* solid angle density, without the pick; 1 for a delta light */
    float distance;
    int is_delta; /* point, spot, distant: no MIS, BSDF sampling cannot hit it */
} LightSample;

/* A ray leaving a light, for light subpaths (bdpt.cl): its origin and
 * direction, the radiance (area) or intensity (point-like) along it, and
 * the densities of the origin (area measure; 1 for a delta position) and
 * of the direction (solid angle; 1 for a delta direction). */
typedef struct {
    Vec3 origin, direction;
    Vec3 normal; /* the emitter's surface normal; 0 for point-like lights */
    Vec3 radiance;
    float pdf_position, pdf_direction;
    int delta_position;
} LightEmission;

/* A direction uniform on the unit sphere. */
KERNEL_FN Vec3 uniform_sphere(float u1, float u2)
{
    float z = 1.0f - 2.0f * u1;
    float r = sqrt_float(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
    return vec3(r * cos_float(phi), r * sin_float(phi), z);
}

/* The emission sampler of the light types that have none yet
 * (GMON_LIGHT_TYPES): the host keeps them out of renders that need one. */
KERNEL_FN int light_emission_none(const Scene *scene, GLOBAL const Light *light, float u1, float u2, float u3, float u4,
                                  LightEmission *e)
{
    (void)scene, (void)light, (void)u1, (void)u2, (void)u3, (void)u4, (void)e;
    return 0;
}

KERNEL_FN Vec3 rotate_rows(const GLOBAL float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[0][1] * w.y + rows[0][2] * w.z,
                rows[1][0] * w.x + rows[1][1] * w.y + rows[1][2] * w.z,
                rows[2][0] * w.x + rows[2][1] * w.y + rows[2][2] * w.z);
}

KERNEL_FN Vec3 rotate_columns(const GLOBAL float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[1][0] * w.y + rows[2][0] * w.z,
                rows[0][1] * w.x + rows[1][1] * w.y + rows[2][1] * w.z,
                rows[0][2] * w.x + rows[1][2] * w.y + rows[2][2] * w.z);
}

KERNEL_FN uint32_t image_texel(GLOBAL const Light *light, float u, float v)
{
    /* Not OpenCL's min: this header also builds as host C (the tests). */
    uint32_t x = (uint32_t)(u * (float)light->image_width), y = (uint32_t)(v * (float)light->image_height);
    x = x < light->image_width ? x : light->image_width - 1u;
    y = y < light->image_height ? y : light->image_height - 1u;
    return y * light->image_width + x;
}

#endif
