/* Camera rays: where a sample lies on the image (the pixel filter, sampled
 * by importance) and the ray through it (perspective or orthographic, with
 * an optional thin lens), as CameraData and FilterData describe them.
 * Shared by the path tracer and the host tests.
 *
 * Random dimensions: 0 and 1 place the sample on the image (the box of
 * radius 0.5 uses them as the renderer always did, so its images are
 * unchanged); the lens uses the fixed dimensions CAMERA_LENS_DIMENSION and
 * the next, past any path's (a path uses 2 + DIMS_PER_BOUNCE a bounce), so
 * adding a lens leaves every other random number of a sample as it was. */
#ifndef KERNELS_CAMERA_H
#define KERNELS_CAMERA_H

#include "distribution.h"
#include "feature_mask.h"
#include "sampler.h"
#include "scene_types.h"
#include "../common/vec3.h"

#define CAMERA_LENS_DIMENSION 0xfffffff0u

typedef struct {
    Vec3 origin;
    Vec3 direction; /* unit */
    float weight;   /* the filter's: scales the sample's radiance */
    /* A cone around the ray about a pixel wide, for texture filtering: its
     * width at the origin and its growth per unit length. */
    float cone_width, cone_spread;
} CameraRay;

/* A point of the unit disk from (u1, u2) in [0, 1)^2 by Shirley and
 * Chiu's concentric mapping (pbrt-v4's SampleUniformDiskConcentric), which
 * keeps strata compact. */
KERNEL_FN void sample_disk_concentric(float u1, float u2, float *x, float *y)
{
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0.0f && b == 0.0f) {
        *x = *y = 0.0f;
        return;
    }
    float r, theta;
    if (fabs(a) > fabs(b)) {
        r = a;
        theta = 0.25f * PI_F * (b / a);
    } else {
        r = b;
        theta = 0.5f * PI_F - 0.25f * PI_F * (a / b);
    }
    *x = r * cos_float(theta);
    *y = r * sin_float(theta);
}

/* An offset from the pixel's centre drawn from the tabulated |f| (in
 * pixels, y down the image as the table's rows); returns the sample's
 * weight, sign(f) * filter->weight. */
KERNEL_FN float filter_sample(const GLOBAL FilterData *filter, const GLOBAL float *distributions, float u1, float u2,
                              float *dx, float *dy)
{
    const GLOBAL float *d = distributions + filter->distribution_offset;
    uint32_t width = filter->table_width, height = filter->table_height, row, column;
    float v = cdf_sample(d + 1, height, u2, &row);
    float u = cdf_sample(d + 1 + (height + 1u) + row * (width + 1u), width, u1, &column);
    *dx = (2.0f * u - 1.0f) * filter->radius[0];
    *dy = (2.0f * v - 1.0f) * filter->radius[1];
    float f = d[DISTRIBUTION_FUNCTION(width, height) + row * width + column];
    return f < 0.0f ? -filter->weight : filter->weight;
}

/* The camera ray of the sample drawing from `stream` in pixel (x, y). */
KERNEL_FN CameraRay camera_ray(const GLOBAL CameraData *camera, const GLOBAL FilterData *filter,
                               const GLOBAL float *distributions, uint32_t x, uint32_t y, const SampleStream *stream)
{
    CameraRay ray;
    ray.weight = 1.0f;
    float px, py; /* the image position, in pixels from the top left */
    float u, v;
    sample_2d(stream, 0u, &u, &v);
    if (GMON_HAS_PIXEL_FILTER && filter->table_width > 0u) {
        float dx, dy;
        ray.weight = filter_sample(filter, distributions, u, v, &dx, &dy);
        px = (float)x + 0.5f + dx;
        py = (float)y + 0.5f + dy;
    } else {
        px = (float)x + u;
        py = (float)y + v;
    }
    float sx = 2.0f * px / (float)camera->width - 1.0f;
    float sy = 1.0f - 2.0f * py / (float)camera->height;
    Vec3 position = vec3_from_global(camera->position), forward = vec3_from_global(camera->forward);
    Vec3 offset = v_add(v_scale(vec3_from_global(camera->right), sx), v_scale(vec3_from_global(camera->up), sy));
    Vec3 direction;
    float pixel = 2.0f * v_length(vec3_from_global(camera->up)) / (float)camera->height;
    if (GMON_HAS_ORTHOGRAPHIC && camera->projection == CAMERA_ORTHOGRAPHIC) {
        ray.origin = v_add(position, offset);
        direction = forward;
        ray.cone_width = pixel;
        ray.cone_spread = 0.0f;
    } else {
        ray.origin = position;
        direction = v_add(forward, offset);
        ray.cone_width = 0.0f;
        ray.cone_spread = pixel;
    }
    if (GMON_HAS_THIN_LENS && camera->lens_radius > 0.0f) {
        float lx, ly;
        sample_2d(stream, CAMERA_LENS_DIMENSION, &u, &v);
        sample_disk_concentric(u, v, &lx, &ly);
        Vec3 focus = v_add(ray.origin, v_scale(direction, camera->focal_distance));
        ray.origin = v_add(position, v_add(v_scale(vec3_from_global(camera->lens_right), lx),
                                           v_scale(vec3_from_global(camera->lens_up), ly)));
        direction = v_sub(focus, ray.origin);
    }
    ray.direction = v_normalize(direction);
    return ray;
}

#endif
