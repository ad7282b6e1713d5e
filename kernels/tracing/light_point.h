/* Point-like lights (point, spot, goniometric, projection): delta
 * positions, sampled by the direction to them, with a spot's falloff and
 * the goniometric and projection lights' images. */
#ifndef KERNELS_LIGHT_POINT_H
#define KERNELS_LIGHT_POINT_H

#include "equal_area.h"
#include "light_common.h"

/* A goniometric or projection light's RGB factor along light-space w. */
KERNEL_FN Vec3 light_image_factor(const Scene *scene, GLOBAL const Light *light, Vec3 w)
{
    float u, v;
    if (!GMON_HAS_PROJECTION_LIGHTS ? 0 : !GMON_HAS_GONIOMETRIC_LIGHTS ? 1 : light->type == LIGHT_PROJECTION) {
        if (w.z < 1e-3f)
            return vec3(0.0f, 0.0f, 0.0f);
        float x = w.x / (w.z * light->screen_half[0]), y = w.y / (w.z * light->screen_half[1]);
        if (!(fabs(x) <= 1.0f && fabs(y) <= 1.0f))
            return vec3(0.0f, 0.0f, 0.0f);
        u = 0.5f * (x + 1.0f);
        v = 0.5f * (y + 1.0f);
    } else {
        equal_area_sphere_to_square(w, &u, &v);
    }
    GLOBAL const float *rgb = scene->texels + light->image_offset + 3u * image_texel(light, u, v);
    return vec3(rgb[0], rgb[1], rgb[2]);
}

KERNEL_FN float smooth_step(float a, float b, float x)
{
    if (a == b)
        return x < a ? 0.0f : 1.0f;
    float t = fmin(fmax((x - a) / (b - a), 0.0f), 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

KERNEL_FN int point_light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2,
                                 LightSample *s)
{
    (void)u1;
    (void)u2;
    uint32_t type = light->type;
    Vec3 to_light = v_sub(vec3_from_global(light->position), p);
    float distance2 = v_dot(to_light, to_light);
    if (distance2 == 0.0f)
        return 0;
    s->distance = sqrt(distance2);
    s->wi = v_scale(to_light, 1.0f / s->distance);
    float falloff = 1.0f;
    if (GMON_HAS_SPOT_LIGHTS && type == LIGHT_SPOT)
        falloff = smooth_step(light->cos_total_width, light->cos_falloff_start,
                              -v_dot(s->wi, vec3_from_global(light->direction)));
    s->radiance = v_scale(vec3_from_global(light->radiance), falloff / distance2);
    if ((GMON_HAS_GONIOMETRIC_LIGHTS || GMON_HAS_PROJECTION_LIGHTS) &&
        (type == LIGHT_GONIOMETRIC || type == LIGHT_PROJECTION))
        s->radiance = v_mul(
            s->radiance, light_image_factor(scene, light, rotate_rows(light->light_from_world, v_scale(s->wi, -1.0f))));
    s->pdf = 1.0f;
    s->is_delta = 1;
    return falloff > 0.0f;
}

/* The intensity of a point-like light toward unit world direction w (away
 * from it): its spot falloff and image factor. */
KERNEL_FN Vec3 point_light_intensity(const Scene *scene, GLOBAL const Light *light, Vec3 w)
{
    Vec3 intensity = vec3_from_global(light->radiance);
    if (GMON_HAS_SPOT_LIGHTS && light->type == LIGHT_SPOT)
        intensity = v_scale(intensity, smooth_step(light->cos_total_width, light->cos_falloff_start,
                                                   v_dot(w, vec3_from_global(light->direction))));
    if ((GMON_HAS_GONIOMETRIC_LIGHTS || GMON_HAS_PROJECTION_LIGHTS) &&
        (light->type == LIGHT_GONIOMETRIC || light->type == LIGHT_PROJECTION))
        intensity = v_mul(intensity, light_image_factor(scene, light, rotate_rows(light->light_from_world, w)));
    return intensity;
}

/* The density point_light_emission gives direction w (unit, world). */
KERNEL_FN float point_light_pdf_direction(GLOBAL const Light *light, Vec3 w)
{
    if (GMON_HAS_SPOT_LIGHTS && light->type == LIGHT_SPOT)
        return v_dot(w, vec3_from_global(light->direction)) >= light->cos_total_width
                   ? 1.0f / (2.0f * PI_F * (1.0f - light->cos_total_width))
                   : 0.0f;
    return 1.0f / (4.0f * PI_F);
}

/* A ray leaving a point-like light: uniform in a spot's cone (as pbrt-v4),
 * else uniform over the sphere. */
KERNEL_FN int point_light_emission(const Scene *scene, GLOBAL const Light *light, float u1, float u2, float u3,
                                   float u4, LightEmission *e)
{
    (void)u3, (void)u4;
    Vec3 w = uniform_sphere(u1, u2);
    if (GMON_HAS_SPOT_LIGHTS && light->type == LIGHT_SPOT) {
        Vec3 axis = vec3_from_global(light->direction), s, t;
        v_basis(axis, &s, &t);
        float cos_theta = 1.0f - u1 * (1.0f - light->cos_total_width);
        float sin_theta = sqrt_float(fmax(0.0f, 1.0f - cos_theta * cos_theta)), phi = 2.0f * PI_F * u2;
        w = v_add(v_scale(axis, cos_theta),
                  v_add(v_scale(s, sin_theta * cos_float(phi)), v_scale(t, sin_theta * sin_float(phi))));
    }
    e->origin = vec3_from_global(light->position);
    e->direction = w;
    e->normal = vec3(0.0f, 0.0f, 0.0f);
    e->radiance = point_light_intensity(scene, light, w);
    e->pdf_position = 1.0f;
    e->pdf_direction = point_light_pdf_direction(light, w);
    e->delta_position = 1;
    return e->pdf_direction > 0.0f;
}

#endif
