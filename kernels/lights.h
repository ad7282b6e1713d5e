/* Lights: for each type, sampling a direction toward it from a point
 * (light_sample), the radiance a ray escaping the scene receives from the
 * infinite ones (infinite_radiance) and their densities, for MIS. Types a
 * scene does not use are compiled out (feature_mask.h). The light to sample
 * is picked in proportion to power (pick_light; chances computed by the
 * host, host/render/render_scene.c). */
#ifndef KERNELS_LIGHTS_H
#define KERNELS_LIGHTS_H

#include "distribution.h"
#include "equal_area.h"
#include "mis.h"
#include "scene.h"

typedef struct {
    Vec3 wi;       /* unit, toward the light */
    Vec3 radiance; /* arriving along -wi, unoccluded */
    float pdf;     /* solid angle density, without the pick; 1 for a delta light */
    float distance;
    int is_delta; /* point, spot, distant: no MIS, BSDF sampling cannot hit it */
} LightSample;

/* Index of the light whose CDF interval holds u. */
KERNEL_FN int pick_light(__global const Light *lights, uint count, float u)
{
    int lo = 0, hi = (int)count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (u < lights[mid].pick_cdf)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

KERNEL_FN Vec3 rotate_rows(const __global float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[0][1] * w.y + rows[0][2] * w.z,
                rows[1][0] * w.x + rows[1][1] * w.y + rows[1][2] * w.z,
                rows[2][0] * w.x + rows[2][1] * w.y + rows[2][2] * w.z);
}

KERNEL_FN Vec3 rotate_columns(const __global float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[1][0] * w.y + rows[2][0] * w.z,
                rows[0][1] * w.x + rows[1][1] * w.y + rows[2][1] * w.z,
                rows[0][2] * w.x + rows[1][2] * w.y + rows[2][2] * w.z);
}

KERNEL_FN uint image_texel(__global const Light *light, float u, float v)
{
    uint x = min((uint)(u * (float)light->image_width), light->image_width - 1u);
    uint y = min((uint)(v * (float)light->image_height), light->image_height - 1u);
    return y * light->image_width + x;
}

/* Radiance from an image light along light-space direction w, and its
 * density (solid angle) when sampled. */
KERNEL_FN Vec3 image_light_radiance(const Scene *scene, __global const Light *light, Vec3 w_light, float *pdf)
{
    float u, v;
    equal_area_sphere_to_square(w_light, &u, &v);
    uint texel = image_texel(light, u, v);
    __global const float *d = scene->distributions + light->distribution_offset;
    float mean = d[0];
    float f = d[DISTRIBUTION_FUNCTION(light->image_width, light->image_height) + texel];
    *pdf = mean > 0.0f ? f / (mean * 4.0f * PI_F) : 0.0f;
    __global const float *rgb = scene->texels + light->image_offset + 3u * texel;
    return v_mul(vec3_from_global(light->radiance), vec3(rgb[0], rgb[1], rgb[2]));
}

/* Radiance from one infinite light along world direction w (unit), and the
 * density with which light_sample samples it. */
KERNEL_FN Vec3 infinite_light_radiance(const Scene *scene, __global const Light *light, Vec3 w, float *pdf)
{
    if (GMON_HAS_ENVIRONMENT_MAP && (!GMON_HAS_ENVIRONMENT || light->type == LIGHT_IMAGE_INFINITE))
        return image_light_radiance(scene, light, v_normalize(rotate_rows(light->light_from_world, w)), pdf);
    *pdf = 1.0f / (4.0f * PI_F);
    return vec3_from_global(light->radiance);
}

/* A goniometric or projection light's RGB factor along light-space w. */
KERNEL_FN Vec3 light_image_factor(const Scene *scene, __global const Light *light, Vec3 w)
{
    float u, v;
    if (GMON_HAS_PROJECTION_LIGHTS && (!GMON_HAS_GONIOMETRIC_LIGHTS || light->type == LIGHT_PROJECTION)) {
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
    __global const float *rgb = scene->texels + light->image_offset + 3u * image_texel(light, u, v);
    return vec3(rgb[0], rgb[1], rgb[2]);
}

KERNEL_FN float smooth_step(float a, float b, float x)
{
    if (a == b)
        return x < a ? 0.0f : 1.0f;
    float t = clamp((x - a) / (b - a), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

/* Samples light `light` from point p with normal n. Returns 0 when it
 * cannot light p. */
KERNEL_FN int light_sample(const Scene *scene, __global const Light *light, Vec3 p, float u1, float u2, LightSample *s)
{
    s->is_delta = 0;
    s->distance = INFINITY;
    uint type = light->type;
    if ((GMON_HAS_POINT_LIGHTS && type == LIGHT_POINT) || (GMON_HAS_SPOT_LIGHTS && type == LIGHT_SPOT) ||
        (GMON_HAS_GONIOMETRIC_LIGHTS && type == LIGHT_GONIOMETRIC) ||
        (GMON_HAS_PROJECTION_LIGHTS && type == LIGHT_PROJECTION)) {
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
            s->radiance =
                v_mul(s->radiance,
                      light_image_factor(scene, light, rotate_rows(light->light_from_world, v_scale(s->wi, -1.0f))));
        s->pdf = 1.0f;
        s->is_delta = 1;
        return falloff > 0.0f;
    }
    if (GMON_HAS_DISTANT_LIGHTS && type == LIGHT_DISTANT) {
        s->wi = vec3_from_global(light->direction);
        s->radiance = vec3_from_global(light->radiance);
        s->pdf = 1.0f;
        s->is_delta = 1;
        return 1;
    }
    if (GMON_HAS_ENVIRONMENT && type == LIGHT_UNIFORM_INFINITE) {
        float z = 1.0f - 2.0f * u1;
        float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
        s->wi = vec3(r * cos(phi), r * sin(phi), z);
        s->pdf = 1.0f / (4.0f * PI_F);
        s->radiance = vec3_from_global(light->radiance);
        return 1;
    }
    if (GMON_HAS_ENVIRONMENT_MAP && type == LIGHT_IMAGE_INFINITE) {
        __global const float *d = scene->distributions + light->distribution_offset;
        uint width = light->image_width, height = light->image_height, row, column;
        float v = cdf_sample(d + 1, height, u2, &row);
        float u = cdf_sample(d + 1 + (height + 1u) + row * (width + 1u), width, u1, &column);
        float f = d[DISTRIBUTION_FUNCTION(width, height) + row * width + column];
        if (!(f > 0.0f))
            return 0;
        Vec3 w_light = equal_area_square_to_sphere(u, v);
        s->wi = v_normalize(rotate_columns(light->light_from_world, w_light));
        s->pdf = f / (d[0] * 4.0f * PI_F);
        __global const float *rgb = scene->texels + light->image_offset + 3u * (row * width + column);
        s->radiance = v_mul(vec3_from_global(light->radiance), vec3(rgb[0], rgb[1], rgb[2]));
        return 1;
    }
    if (!GMON_HAS_AREA_LIGHTS)
        return 0;
    __global const Primitive *prim = scene->primitives + light->primitive;
    Vec3 q = sample_primitive(prim, u1, u2);
    Vec3 nq = surface_normal(prim, q);
    Vec3 to_light = v_sub(q, p);
    float distance2 = v_dot(to_light, to_light);
    if (distance2 == 0.0f)
        return 0;
    s->distance = sqrt(distance2);
    s->wi = v_scale(to_light, 1.0f / s->distance);
    float cos_light = v_dot(nq, s->wi); /* < 0: the light's front faces p */
    if (cos_light == 0.0f || (!light->two_sided && cos_light > 0.0f))
        return 0;
    s->radiance = vec3_from_global(light->radiance);
    s->pdf = distance2 / (fabs(cos_light) * light->area);
    return 1;
}

/* The density of sampling area light `light` (picked, then a point on it)
 * at a hit at distance t, cosine cos_light with its normal. */
KERNEL_FN float area_light_pdf(__global const Light *light, float t, float cos_light)
{
    return cos_light > 0.0f ? light->pick_probability * t * t / (cos_light * light->area) : 0.0f;
}

/* What a ray leaving along w (unit) receives from the infinite lights,
 * each weighted against BSDF sampling of density bsdf_pdf (unless
 * unweighted). */
KERNEL_FN Vec3 infinite_radiance(const Scene *scene, Vec3 w, float bsdf_pdf, int unweighted)
{
    Vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    uint count = scene->constants->background.infinite_count;
    for (uint i = 0; i < count; ++i) {
        __global const Light *light = scene->lights + i;
        float pdf;
        Vec3 le = infinite_light_radiance(scene, light, w, &pdf);
        float weight = unweighted ? 1.0f : power_heuristic(bsdf_pdf, light->pick_probability * pdf);
        sum = v_add(sum, v_scale(le, weight));
    }
    return sum;
}

#endif
