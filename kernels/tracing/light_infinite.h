/* Infinite lights: uniform (a constant radiance from every direction) and
 * image (an environment map, sampled by its texels' brightness), and what a
 * ray escaping the scene receives from them. */
#ifndef KERNELS_LIGHT_INFINITE_H
#define KERNELS_LIGHT_INFINITE_H

#include "distribution.h"
#include "equal_area.h"
#include "light_common.h"
#include "mis.h"

/* Radiance from an image light along light-space direction w, and its
 * density (solid angle) when sampled. */
KERNEL_FN Vec3 image_light_radiance(const Scene *scene, GLOBAL const Light *light, Vec3 w_light, float *pdf)
{
    float u, v;
    equal_area_sphere_to_square(w_light, &u, &v);
    uint32_t texel = image_texel(light, u, v);
    GLOBAL const float *d = scene->distributions + light->distribution_offset;
    float mean = d[0];
    float f = d[DISTRIBUTION_FUNCTION(light->image_width, light->image_height) + texel];
    *pdf = mean > 0.0f ? f / (mean * 4.0f * PI_F) : 0.0f;
    GLOBAL const float *rgb = scene->texels + light->image_offset + 3u * texel;
    return v_mul(vec3_from_global(light->radiance), vec3(rgb[0], rgb[1], rgb[2]));
}

/* Radiance from one infinite light along world direction w (unit), and the
 * density with which light_sample samples it. */
KERNEL_FN Vec3 infinite_light_radiance(const Scene *scene, GLOBAL const Light *light, Vec3 w, float *pdf)
{
    if (!GMON_HAS_ENVIRONMENT_MAP ? 0 : !GMON_HAS_ENVIRONMENT ? 1 : light->type == LIGHT_IMAGE_INFINITE)
        return image_light_radiance(scene, light, v_normalize(rotate_rows(light->light_from_world, w)), pdf);
    *pdf = 1.0f / (4.0f * PI_F);
    return vec3_from_global(light->radiance);
}

KERNEL_FN int uniform_infinite_light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2,
                                            LightSample *s)
{
    (void)scene;
    (void)p;
    float z = 1.0f - 2.0f * u1;
    float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
    s->wi = vec3(r * cos(phi), r * sin(phi), z);
    s->pdf = 1.0f / (4.0f * PI_F);
    s->radiance = vec3_from_global(light->radiance);
    return 1;
}

KERNEL_FN int image_infinite_light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2,
                                          LightSample *s)
{
    (void)p;
    GLOBAL const float *d = scene->distributions + light->distribution_offset;
    uint32_t width = light->image_width, height = light->image_height, row, column;
    float v = cdf_sample(d + 1, height, u2, &row);
    float u = cdf_sample(d + 1 + (height + 1u) + row * (width + 1u), width, u1, &column);
    float f = d[DISTRIBUTION_FUNCTION(width, height) + row * width + column];
    if (!(f > 0.0f))
        return 0;
    Vec3 w_light = equal_area_square_to_sphere(u, v);
    s->wi = v_normalize(rotate_columns(light->light_from_world, w_light));
    s->pdf = f / (d[0] * 4.0f * PI_F);
    GLOBAL const float *rgb = scene->texels + light->image_offset + 3u * (row * width + column);
    s->radiance = v_mul(vec3_from_global(light->radiance), vec3(rgb[0], rgb[1], rgb[2]));
    return 1;
}

/* What a ray leaving along w (unit) receives from the infinite lights,
 * each weighted against BSDF sampling of density bsdf_pdf (unless
 * unweighted). */
KERNEL_FN Vec3 infinite_radiance(const Scene *scene, Vec3 w, float bsdf_pdf, int unweighted)
{
    Vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    uint32_t count = scene->constants->background.infinite_count;
    for (uint32_t i = 0; i < count; ++i) {
        GLOBAL const Light *light = scene->lights + i;
        float pdf;
        Vec3 le = infinite_light_radiance(scene, light, w, &pdf);
        float weight = unweighted ? 1.0f : power_heuristic(bsdf_pdf, light->pick_probability * pdf);
        sum = v_add(sum, v_scale(le, weight));
    }
    return sum;
}

#endif
