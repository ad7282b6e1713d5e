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

/* The film's response to a sample's radiance (FilmData). */
KERNEL_FN Vec3 film_response(const GLOBAL FilmData *film, Vec3 L)
{
    if (GMON_HAS_FILM_MATRIX) {
        const GLOBAL float(*m)[4] = film->from_radiance;
        L = vec3(m[0][0] * L.x + m[0][1] * L.y + m[0][2] * L.z, m[1][0] * L.x + m[1][1] * L.y + m[1][2] * L.z,
                 m[2][0] * L.x + m[2][1] * L.y + m[2][2] * L.z);
    }
    return L;
}

/* The perspective camera's view axis: unit, perpendicular to right and up,
 * on forward's side (forward may lean off it with an off-centre window). */
KERNEL_FN Vec3 camera_axis(const GLOBAL CameraData *camera)
{
    Vec3 axis = v_normalize(v_cross(vec3_from_global(camera->right), vec3_from_global(camera->up)));
    return v_dot(axis, vec3_from_global(camera->forward)) < 0.0f ? v_scale(axis, -1.0f) : axis;
}

/* A connection from a scene point to the perspective camera (pbrt-v4's
 * PerspectiveCamera::SampleWi): a point of the lens, the unit direction
 * from the scene point to it and their distance, the density of that
 * direction at the scene point (solid angle), the camera's importance
 * We along the ray, and where the ray lands on the image, in pixels from
 * the top left. Importance is normalized so that it integrates to 1 over
 * the image at unit distance times the lens (1/(A lens cos^4), A the image
 * window's area at unit distance); it is also defined a filter radius past
 * the image's edges, where camera samples of the edge pixels land too. */
typedef struct {
    Vec3 lens_point, wi;
    float distance, pdf, importance;
    float px, py;
} CameraConnection;

/* The raster position and importance of a ray leaving lens point `lens`
 * along unit d: 0 where it does not reach the image (with the filter's
 * margin) or leaves backward. */
KERNEL_FN int camera_importance(const GLOBAL CameraData *camera, const GLOBAL FilterData *filter, Vec3 lens, Vec3 d,
                                float *importance, float *px, float *py)
{
    Vec3 axis = camera_axis(camera), position = vec3_from_global(camera->position);
    float cos_theta = v_dot(d, axis);
    if (!(cos_theta > 0.0f))
        return 0;
    /* The pinhole ray through the point where this one meets the plane of
     * focus (with a lens), or this one. */
    Vec3 through = d;
    if (GMON_HAS_THIN_LENS && camera->lens_radius > 0.0f)
        through = v_sub(v_add(lens, v_scale(d, camera->focal_distance / cos_theta)), position);
    float along = v_dot(through, axis);
    Vec3 right = vec3_from_global(camera->right), up = vec3_from_global(camera->up);
    Vec3 q = v_sub(v_scale(through, 1.0f / along), vec3_from_global(camera->forward));
    float sx = v_dot(q, right) / v_dot(right, right), sy = v_dot(q, up) / v_dot(up, up);
    *px = 0.5f * (sx + 1.0f) * (float)camera->width;
    *py = 0.5f * (1.0f - sy) * (float)camera->height;
    float margin_x = 0.5f, margin_y = 0.5f;
    if (GMON_HAS_PIXEL_FILTER && filter->table_width > 0u) {
        margin_x = filter->radius[0];
        margin_y = filter->radius[1];
    }
    if (!(*px >= -margin_x && *px <= (float)camera->width + margin_x && *py >= -margin_y &&
          *py <= (float)camera->height + margin_y))
        return 0;
    float lens_area =
        GMON_HAS_THIN_LENS && camera->lens_radius > 0.0f ? PI_F * camera->lens_radius * camera->lens_radius : 1.0f;
    float window_area = 4.0f * v_length(right) * v_length(up);
    float cos2 = cos_theta * cos_theta;
    *importance = 1.0f / (window_area * lens_area * cos2 * cos2);
    return 1;
}

/* The density, in solid angle at the camera, with which a camera ray
 * leaves along unit d (pbrt-v4's PDF_We, direction part): 1/(A cos^3). */
KERNEL_FN float camera_pdf_direction(const GLOBAL CameraData *camera, Vec3 d)
{
    float cos_theta = v_dot(d, camera_axis(camera));
    if (!(cos_theta > 0.0f))
        return 0.0f;
    float window_area = 4.0f * v_length(vec3_from_global(camera->right)) * v_length(vec3_from_global(camera->up));
    return 1.0f / (window_area * cos_theta * cos_theta * cos_theta);
}

/* Connects scene point p to the camera, the lens point drawn from (u1, u2).
 * Returns 0 where the camera does not see p. */
KERNEL_FN int camera_connect(const GLOBAL CameraData *camera, const GLOBAL FilterData *filter, Vec3 p, float u1,
                             float u2, CameraConnection *c)
{
    c->lens_point = vec3_from_global(camera->position);
    float lens_area = 1.0f;
    if (GMON_HAS_THIN_LENS && camera->lens_radius > 0.0f) {
        float lx, ly;
        sample_disk_concentric(u1, u2, &lx, &ly);
        c->lens_point = v_add(c->lens_point, v_add(v_scale(vec3_from_global(camera->lens_right), lx),
                                                   v_scale(vec3_from_global(camera->lens_up), ly)));
        lens_area = PI_F * camera->lens_radius * camera->lens_radius;
    }
    Vec3 to_lens = v_sub(c->lens_point, p);
    float distance2 = v_dot(to_lens, to_lens);
    if (!(distance2 > 0.0f))
        return 0;
    c->distance = sqrt_float(distance2);
    c->wi = v_scale(to_lens, 1.0f / c->distance);
    Vec3 d = v_scale(c->wi, -1.0f);
    if (!camera_importance(camera, filter, c->lens_point, d, &c->importance, &c->px, &c->py))
        return 0;
    c->pdf = distance2 / (v_dot(d, camera_axis(camera)) * lens_area);
    return 1;
}

#endif
