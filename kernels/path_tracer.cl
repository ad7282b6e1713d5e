/* Unidirectional path tracer: one work item per pixel renders a run of
 * samples and adds each to set (sample index mod M) of its pixel through the
 * shared accumulation code (accumulate.h).
 *
 * With RENDER_NEE: next-event estimation on area and environment lights,
 * combined with BSDF sampling by multiple importance sampling (power
 * heuristic), as pbrt-v4's "path" integrator. Without: BSDF sampling only,
 * the firefly-prone estimator experiments need.
 *
 * Build options: -DEST_SETS=M, and -DGMON_FEATURES=<mask> to compile out
 * what the scene does not use (feature_mask.h). */
#include "bsdf.h"
#include "accumulate.h"
#include "feature_mask.h"
#include "intersect.h"
#include "rng.h"
#include "scene_types.h"
#include "vec3.h"

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif

/* Random dimensions: 2 for the pixel position, then DIMS_PER_BOUNCE a bounce. */
#define DIMS_PER_BOUNCE 7

typedef struct {
    __global const RenderParams *params;
    __global const BvhNode *nodes;
    __global const Primitive *primitives;
    __global const Material *materials;
    __global const Emitter *emitters;
} Scene;

KERNEL_FN Vec3 surface_normal(__global const Primitive *p, Vec3 position)
{
    Vec3 n;
    if (is_sphere(p))
        n = v_normalize(v_sub(position, vec3_from_global(p->a)));
    else
        n = v_normalize(v_cross(vec3_from_global(p->b), vec3_from_global(p->c)));
    return (p->kind & PRIM_FLIP_NORMAL) ? v_scale(n, -1.0f) : n;
}

/* A point uniformly distributed over a primitive's area. */
KERNEL_FN Vec3 sample_primitive(__global const Primitive *p, float u1, float u2)
{
    if (is_sphere(p)) {
        float z = 1.0f - 2.0f * u1;
        float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
        return v_add(vec3_from_global(p->a), v_scale(vec3(r * cos(phi), r * sin(phi), z), p->b[0]));
    }
    /* Barycentrics (1 - su, u2 su, su - u2 su) are uniform over the area. */
    float su = sqrt(u1);
    float b1 = u2 * su, b2 = su - b1;
    return v_add(vec3_from_global(p->a),
                 v_add(v_scale(vec3_from_global(p->b), b1), v_scale(vec3_from_global(p->c), b2)));
}

/* Radiance leaving emitter `e` at normal n toward direction w (unit). */
KERNEL_FN Vec3 emitted(__global const Emitter *e, Vec3 n, Vec3 w)
{
    if (!e->two_sided && v_dot(n, w) <= 0.0f)
        return vec3(0.0f, 0.0f, 0.0f);
    return vec3_from_global(e->radiance);
}

/* Index of the emitter whose CDF interval holds u. */
KERNEL_FN int pick_emitter(__global const Emitter *emitters, uint count, float u)
{
    int lo = 0, hi = (int)count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (u < emitters[mid].pick_cdf)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

KERNEL_FN float power_heuristic(float a, float b)
{
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

/* Origin offset off a surface, to the side a direction leaves toward. */
KERNEL_FN Vec3 offset_origin(Vec3 p, Vec3 n, Vec3 w)
{
    float scale = 1e-5f * (1.0f + fmax(fmax(fabs(p.x), fabs(p.y)), fabs(p.z)));
    return v_add(p, v_scale(n, v_dot(n, w) > 0.0f ? scale : -scale));
}

KERNEL_FN Ray make_ray(Vec3 origin, Vec3 direction)
{
    Ray r;
    r.origin[0] = origin.x;
    r.origin[1] = origin.y;
    r.origin[2] = origin.z;
    r.direction[0] = direction.x;
    r.direction[1] = direction.y;
    r.direction[2] = direction.z;
    return r;
}

KERNEL_FN int occluded(const Scene *scene, Vec3 origin, Vec3 direction, float distance)
{
    Ray ray = make_ray(origin, direction);
    Hit hit;
    return bvh_intersect(scene->nodes, scene->primitives, &ray, 0.0f, distance, 1, &hit);
}

/* Light sampling at a surface: a direction toward a light, its unoccluded
 * radiance and pdf (solid angle, including the pick). Returns 0 if none. */
KERNEL_FN int sample_light(const Scene *scene, Vec3 p, Vec3 n, float u_pick, float u1, float u2, Vec3 *wi,
                           Vec3 *radiance, float *pdf, uint *rays)
{
    __global const RenderParams *params = scene->params;
    float environment_pick = GMON_HAS_ENVIRONMENT ? params->environment_pick : 0.0f;
    if (GMON_HAS_ENVIRONMENT && u_pick < environment_pick) {
        float z = 1.0f - 2.0f * u1;
        float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
        *wi = vec3(r * cos(phi), r * sin(phi), z);
        *pdf = environment_pick / (4.0f * PI_F);
        *radiance = vec3_from_global(params->environment);
        ++*rays;
        return !occluded(scene, offset_origin(p, n, *wi), *wi, INFINITY);
    }
    if (!GMON_HAS_AREA_LIGHTS || params->emitter_count == 0)
        return 0;
    float u = (u_pick - environment_pick) / (1.0f - environment_pick);
    __global const Emitter *e = scene->emitters + pick_emitter(scene->emitters, params->emitter_count, u);
    __global const Primitive *prim = scene->primitives + e->primitive;
    Vec3 q = sample_primitive(prim, u1, u2);
    Vec3 nq = surface_normal(prim, q);
    Vec3 origin = offset_origin(p, n, v_sub(q, p));
    Vec3 to_light = v_sub(q, origin);
    float distance2 = v_dot(to_light, to_light);
    if (distance2 == 0.0f)
        return 0;
    float distance = sqrt(distance2);
    *wi = v_scale(to_light, 1.0f / distance);
    float cos_light = fabs(v_dot(nq, *wi));
    if (cos_light == 0.0f)
        return 0;
    *radiance = emitted(e, nq, v_scale(*wi, -1.0f));
    if (v_max_component(*radiance) <= 0.0f)
        return 0;
    *pdf = (1.0f - environment_pick) * e->pick_probability * distance2 / (cos_light * e->area);
    ++*rays;
    return !occluded(scene, origin, *wi, distance * (1.0f - 1e-4f));
}

/* One path sample through pixel (x, y); returns its radiance. */
KERNEL_FN Vec3 trace_path(const Scene *scene, uint x, uint y, uint64_t key, uint *rays)
{
    __global const RenderParams *params = scene->params;
    const int use_nee = GMON_HAS_NEE && (params->flags & RENDER_NEE) != 0;
    float sx = 2.0f * ((float)x + rng_uniform(key, 0)) / (float)params->width - 1.0f;
    float sy = 1.0f - 2.0f * ((float)y + rng_uniform(key, 1)) / (float)params->height;
    Vec3 direction = v_normalize(
        v_add(vec3_from_global(params->camera_forward), v_add(v_scale(vec3_from_global(params->camera_right), sx),
                                                              v_scale(vec3_from_global(params->camera_up), sy))));
    Vec3 origin = vec3_from_global(params->camera_position);

    Vec3 radiance = vec3(0.0f, 0.0f, 0.0f), throughput = vec3(1.0f, 1.0f, 1.0f);
    float previous_pdf = 1.0f, eta_scale = 1.0f;
    int specular_bounce = 0;
    for (uint depth = 0;; ++depth) {
        Ray ray = make_ray(origin, direction);
        Hit hit;
        ++*rays;
        int unweighted = depth == 0 || specular_bounce || !use_nee;
        if (!bvh_intersect(scene->nodes, scene->primitives, &ray, 0.0f, INFINITY, 0, &hit)) {
            if (!GMON_HAS_ENVIRONMENT)
                break;
            Vec3 le = vec3_from_global(params->environment);
            float weight = unweighted ? 1.0f : power_heuristic(previous_pdf, params->environment_pick / (4.0f * PI_F));
            radiance = v_add(radiance, v_scale(v_mul(throughput, le), weight));
            break;
        }
        __global const Primitive *prim = scene->primitives + hit.primitive;
        Vec3 p = v_add(origin, v_scale(direction, hit.t));
        Vec3 n = surface_normal(prim, p);
        Vec3 wo_world = v_scale(direction, -1.0f);

        if (GMON_HAS_AREA_LIGHTS && prim->emitter >= 0) {
            __global const Emitter *e = scene->emitters + prim->emitter;
            Vec3 le = emitted(e, n, wo_world);
            float weight = 1.0f;
            if (!unweighted) {
                float cos_light = fabs(v_dot(n, wo_world));
                float light_pdf =
                    (1.0f - params->environment_pick) * e->pick_probability * hit.t * hit.t / (cos_light * e->area);
                weight = cos_light > 0.0f ? power_heuristic(previous_pdf, light_pdf) : 0.0f;
            }
            radiance = v_add(radiance, v_scale(v_mul(throughput, le), weight));
        }
        if (depth >= params->max_depth)
            break;

        __global const Material *material = scene->materials + prim->material;
        Vec3 s, t;
        v_basis(n, &s, &t);
        Vec3 wo = vec3(v_dot(wo_world, s), v_dot(wo_world, t), v_dot(wo_world, n));
        uint dim = 2 + depth * DIMS_PER_BOUNCE;

        /* Next-event estimation (not for perfectly smooth surfaces). */
        int delta_only = material->type != MAT_DIFFUSE && material->type != MAT_COATED_DIFFUSE &&
                         material->alpha_x < SMOOTH_ALPHA && material->alpha_y < SMOOTH_ALPHA;
        if (use_nee && !delta_only) {
            Vec3 wi_world, le;
            float light_pdf = 0.0f;
            if (sample_light(scene, p, n, rng_uniform(key, dim), rng_uniform(key, dim + 1), rng_uniform(key, dim + 2),
                             &wi_world, &le, &light_pdf, rays)) {
                Vec3 wi = vec3(v_dot(wi_world, s), v_dot(wi_world, t), v_dot(wi_world, n));
                float bsdf_pdf = 0.0f;
                Vec3 f = bsdf_eval(material, wo, wi, &bsdf_pdf);
                float weight = power_heuristic(light_pdf, bsdf_pdf);
                Vec3 contribution = v_scale(v_mul(f, le), fabs(wi.z) * weight / light_pdf);
                radiance = v_add(radiance, v_mul(throughput, contribution));
            }
        }

        BsdfSample bs;
        if (!bsdf_sample(material, wo, rng_uniform(key, dim + 3), rng_uniform(key, dim + 4), rng_uniform(key, dim + 5),
                         &bs))
            break;
        throughput = v_mul(throughput, v_scale(bs.f, fabs(bs.wi.z) / bs.pdf));
        previous_pdf = bs.pdf;
        specular_bounce = bs.is_delta;
        if (bs.is_transmission)
            eta_scale *= bs.etap * bs.etap;
        direction = v_normalize(v_add(v_add(v_scale(s, bs.wi.x), v_scale(t, bs.wi.y)), v_scale(n, bs.wi.z)));
        origin = offset_origin(p, n, direction);

        /* Russian roulette on the throughput without the radiance scaling
         * of refraction, after the first bounces. */
        float q = v_max_component(throughput) * eta_scale;
        if (depth >= 1 && q < 1.0f) {
            float survive = fmax(q, 0.05f);
            if (rng_uniform(key, dim + 6) >= survive)
                break;
            throughput = v_scale(throughput, 1.0f / survive);
        }
    }
    return radiance;
}

/* Renders samples [first_sample, first_sample + sample_count) of pixels
 * [first_pixel, first_pixel + pixel_count) of the image. Accumulators and
 * counters cover pixels [buffer_first_pixel, buffer_first_pixel +
 * buffer_pixel_count), one device's share, which holds the rendered ones. */
__kernel void render_samples(__global const RenderParams *params, __global const BvhNode *nodes,
                             __global const Primitive *primitives, __global const Material *materials,
                             __global const Emitter *emitters, __global ulong *accumulators, __global uint *rejected,
                             __global ulong *ray_counts, ulong first_sample, uint sample_count, ulong first_pixel,
                             ulong pixel_count, ulong buffer_first_pixel, ulong buffer_pixel_count)
{
    if (get_global_id(0) >= pixel_count)
        return;
    Scene scene;
    scene.params = params;
    scene.nodes = nodes;
    scene.primitives = primitives;
    scene.materials = materials;
    scene.emitters = emitters;
    ulong pixel = first_pixel + get_global_id(0);
    ulong local_pixel = pixel - buffer_first_pixel;
    uint x = (uint)(pixel % params->width), y = (uint)(pixel / params->width);
    uint nonfinite = 0, rounded = 0, rays = 0;
    for (uint i = 0; i < sample_count; ++i) {
        ulong sample_index = first_sample + i;
        uint64_t key = rng_sample_key(params->seed, pixel, sample_index);
        Vec3 L = trace_path(&scene, x, y, key, &rays);
        int added = accumulate_sample(accumulators, local_pixel, buffer_pixel_count, EST_SETS,
                                      set_of_sample(sample_index, EST_SETS), L.x, L.y, L.z);
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    /* Two planes: non-finite samples, then rounded ones (accumulate.h). */
    rejected[local_pixel] += nonfinite;
    rejected[buffer_pixel_count + local_pixel] += rounded;
    ray_counts[local_pixel] += rays;
}
