/* Unidirectional path tracer: one work item per pixel renders a run of
 * samples and adds each to set (sample index mod M) of its pixel through the
 * shared accumulation code (accumulate.h).
 *
 * With RENDER_NEE: next-event estimation on every light (lights.h),
 * combined with BSDF sampling by multiple importance sampling (power
 * heuristic), as pbrt-v4's "path" integrator. Without: BSDF sampling only,
 * the firefly-prone estimator experiments need.
 *
 * With FEATURE_MEDIA it is pbrt-v4's volpath for homogeneous media
 * (media.h): each ray segment is in a medium (the camera's, then the one
 * each boundary's MediumInterface gives), which emits, scatters (distance
 * sampling, Henyey-Greenstein phase function, next-event estimation through
 * media and "interface" boundaries, MIS between phase and light sampling)
 * and attenuates.
 *
 * Build options: -DEST_SETS=M, -DGMON_FEATURES=<mask> to compile out
 * what the scene does not use (feature_mask.h), and with per-sample
 * estimators -DEST_SAMPLE_PASSES=<mask> and their parameters
 * (sample_passes.h): without it none of their code or state exists; with
 * abmm, gabmm or mean-or-mon -DSAMPLE_SUMS_DOUBLE (their moments' double
 * sums: the device needs cl_khr_fp64). */
#ifdef SAMPLE_SUMS_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#include "../film/accumulate.h"
#include "bsdf.h"
#include "camera.h"
#include "lights.h"
#include "scene.h"
#include "surface.h"
#if GMON_HAS_MEDIA
#include "media.h"
#endif

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif

#ifdef EST_SAMPLE_PASSES
#include "../film/sample_passes.h"
#define SAMPLE_PASSES EST_SAMPLE_PASSES
/* clamp-sum needs a sample's direct and indirect light apart. */
#define TRACK_DIRECT ((SAMPLE_PASSES & PASS_BIT(PASS_CLAMP_SUM)) != 0)
#else
#define SAMPLE_PASSES 0u
#define TRACK_DIRECT 0
#endif
#ifndef EST_CLAMP_LEVEL_COUNT
#define EST_CLAMP_LEVEL_COUNT 0
#endif
#ifndef EST_CLAMP_SUM_DIRECT
#define EST_CLAMP_SUM_DIRECT 0.0f
#define EST_CLAMP_SUM_INDIRECT 0.0f
#endif
#ifndef EST_ZIRR_COUNT
#define EST_ZIRR_COUNT 2
#define EST_ZIRR_BASE 8.0f
#endif

#ifndef GMON_SAMPLER
#define GMON_SAMPLER SAMPLER_INDEPENDENT
#endif
/* The M the sampler deals samples to: the render's --sets even where only
 * the mean is kept (EST_SETS = 1), so that render draws the same samples. */
#ifndef GMON_SAMPLER_SETS
#define GMON_SAMPLER_SETS EST_SETS
#endif

/* Random dimensions (sampler.h): 2 for the image position, then
 * DIMS_PER_BOUNCE a bounce: the light's pick, a point on it (2D), the
 * BSDF's lobe, its direction (2D), Russian roulette (and 2 for the lens,
 * past them: camera.h). */
#define DIMS_PER_BOUNCE 7

/* Radiance leaving area light `light` at normal n toward direction w (unit). */
KERNEL_FN Vec3 emitted(__global const Light *light, Vec3 n, Vec3 w)
{
    if (!light->two_sided && v_dot(n, w) <= 0.0f)
        return vec3(0.0f, 0.0f, 0.0f);
    return vec3_from_global(light->radiance);
}

/* Whether light reaches along the shadow ray; with media, s->radiance is
 * scaled by the transmittance, from `medium`, or from the side of
 * `primitive` (-1: none, a point in a medium) the ray leaves to. */
KERNEL_FN int light_visible(const Scene *scene, Vec3 origin, float distance, int32_t primitive, Vec3 n, int medium,
                            const SampleStream *stream, uint *dimension, LightSample *s, uint *rays)
{
#if GMON_HAS_MEDIA
    if (primitive >= 0)
        medium = medium_after(scene, primitive, n, s->wi, medium);
    s->radiance =
        v_mul(s->radiance, shadow_transmittance(scene, origin, s->wi, distance, medium, stream, dimension, rays));
    return v_max_component(s->radiance) > 0.0f;
#else
    (void)primitive, (void)n, (void)medium, (void)stream, (void)dimension, (void)rays;
    return !occluded(scene, origin, s->wi, distance);
#endif
}

/* Next-event estimation at a surface (of primitive `primitive`, normal n)
 * or at a point in a medium (n = 0, primitive -1): picks a light
 * (pick_light_at) and samples it; its radiance reaching p and density
 * (solid angle, with the pick). Grid media's transmittance draws random
 * numbers from stream at *dimension on. Returns 0 if none. */
KERNEL_FN int sample_light(const Scene *scene, Vec3 p, Vec3 n, int32_t primitive, int medium, float u_pick, float u1,
                           float u2, const SampleStream *stream, uint *dimension, LightSample *s, uint *rays)
{
    if (scene->constants->integrator.light_count == 0)
        return 0;
    float pick;
    int index = pick_light_at(scene, p, n, u_pick, &pick);
    if (index < 0)
        return 0;
    __global const Light *light = scene->lights + index;
    if (!light_sample(scene, light, p, u1, u2, s))
        return 0;
    s->pdf *= pick;
    if (!(s->pdf > 0.0f) || v_max_component(s->radiance) <= 0.0f)
        return 0;
    ++*rays;
    Vec3 origin = offset_origin(p, n, s->wi);
    if (!(s->distance < INFINITY))
        return light_visible(scene, origin, INFINITY, primitive, n, medium, stream, dimension, s, rays);
    /* Aim from the offset origin at the sampled point itself: a ray
     * parallel to p's would cross a light's plane before that point at
     * grazing angles (by offset / cos), and the light would shadow itself. */
    Vec3 to_light = v_sub(v_add(p, v_scale(s->wi, s->distance)), origin);
    float distance = sqrt(v_dot(to_light, to_light));
    if (!(distance > 0.0f))
        return 0;
    s->wi = v_scale(to_light, 1.0f / distance);
    return light_visible(scene, origin, distance * (1.0f - 1e-4f), primitive, n, medium, stream, dimension, s, rays);
}

/* Adds a contribution to the radiance and, with TRACK_DIRECT, to its
 * direct or indirect part (Cycles' classes: emission seen from the camera
 * and light reached after the first surface, by its light sample or its
 * BSDF sample, are direct; everything after the first bounce indirect). */
#define ADD_LIGHT(c, is_direct)                                                                                        \
    do {                                                                                                               \
        Vec3 contribution_ = (c);                                                                                      \
        radiance = v_add(radiance, contribution_);                                                                     \
        if (TRACK_DIRECT) {                                                                                            \
            if (is_direct)                                                                                             \
                parts[0] = v_add(parts[0], contribution_);                                                             \
            else                                                                                                       \
                parts[1] = v_add(parts[1], contribution_);                                                             \
        }                                                                                                              \
    } while (0)

/* Russian roulette on the throughput without the radiance scaling of
 * refraction, after the first bounces (IntegratorData). Returns 0 when the
 * path ends. */
KERNEL_FN int roulette_survives(Vec3 *throughput, float eta_scale, uint depth, float threshold,
                                const SampleStream *stream, uint dimension)
{
    float q = v_max_component(*throughput) * eta_scale;
    if (depth >= 1 && q < threshold) {
        float survive = fmax(q, 0.05f);
        if (sample_1d(stream, dimension) >= survive)
            return 0;
        *throughput = v_scale(*throughput, 1.0f / survive);
    }
    return 1;
}

/* One path sample along a camera ray; returns its radiance (with
 * TRACK_DIRECT also its direct and indirect parts in parts[0], parts[1]).
 * Texture filtering follows a ray cone: its width grows by cone_spread per
 * unit length from cone_width at the camera, along the whole path (as if
 * every bounce were a mirror's). */
KERNEL_FN Vec3 trace_path(const Scene *scene, Vec3 origin, Vec3 direction, float cone_width, float cone_spread,
                          const SampleStream *stream, uint *rays, Vec3 *parts)
{
    __global const IntegratorData *integrator = &scene->constants->integrator;
    const int use_nee = GMON_HAS_NEE && (integrator->flags & RENDER_NEE) != 0;

    Vec3 radiance = vec3(0.0f, 0.0f, 0.0f), throughput = vec3(1.0f, 1.0f, 1.0f);
    float previous_pdf = 1.0f, eta_scale = 1.0f;
    /* The last bounce's shading point and normal: light sampling there set
     * the density MIS weighs a light hit against (the light's chance, and
     * for a sphere the cone it saw). */
    Vec3 previous_point = origin, previous_normal = vec3(0.0f, 0.0f, 0.0f);
    int specular_bounce = 0;
#if GMON_HAS_MEDIA
    int medium = scene->constants->media.count > 0 ? scene->constants->media.camera_medium : -1;
    uint medium_dimension = MEDIUM_DIMENSION; /* the next of the media's own random dimensions */
#else
    const int medium = -1;
    uint medium_dimension = 0;
#endif
    for (uint depth = 0;; ++depth) {
        Hit hit;
        int unweighted = !use_nee || depth == 0 || specular_bounce;
        uint dim = 2 + depth * DIMS_PER_BOUNCE;
#if GMON_HAS_MEDIA
        /* Along the ray through media and "interface" boundaries to where
         * it scatters: in a medium, or at a surface with a material. */
        int found, scattered = 0;
        for (int crossings = 0;; ++crossings) {
            Ray ray = make_ray(origin, direction);
            ++*rays;
            found = scene_intersect(scene, &ray, 0.0f, INFINITY, 0, &hit);
            if (medium >= 0) {
                __global const Medium *m = scene->media + medium;
                float t_max = found ? hit.t : INFINITY, t = 0.0f;
                int emit = depth < integrator->max_depth; /* as pbrt-v4: no emission past the last bounce */
                if (m->type == MEDIUM_HOMOGENEOUS) {
                    float u1, u2;
                    if (emit)
                        ADD_LIGHT(v_mul(throughput, medium_emission(m, t_max)), depth <= 1);
                    sample_2d(stream, medium_dimension, &u1, &u2);
                    medium_dimension += 2u;
                    Vec3 weight;
                    scattered = medium_sample_distance(m, t_max, throughput, u1, u2, &t, &weight);
                    throughput = v_mul(throughput, weight);
                } else {
                    Vec3 emitted = vec3(0.0f, 0.0f, 0.0f);
                    scattered = grid_sample_distance(scene, m, origin, direction, t_max, stream, &medium_dimension,
                                                     emit, &throughput, &emitted, &t);
                    if (emit)
                        ADD_LIGHT(emitted, depth <= 1);
                }
                if (scattered) {
                    origin = v_add(origin, v_scale(direction, t));
                    break;
                }
            }
            if (!found || scene->materials[scene->primitives[hit.primitive].material].type != MAT_INTERFACE)
                break;
            if (crossings >= MEDIUM_MAX_CROSSINGS) {
                throughput = vec3(0.0f, 0.0f, 0.0f); /* ends the path below */
                break;
            }
            __global const Primitive *boundary = scene->primitives + hit.primitive;
            Vec3 p = v_add(origin, v_scale(direction, hit.t));
            Vec3 n = hit_normal(scene, &hit, boundary, p);
            medium = medium_after(scene, hit.primitive, n, direction, medium);
            origin = offset_origin(p, n, direction);
        }
        if (scattered) {
            if (depth >= integrator->max_depth)
                break;
            /* Light sampling and phase sampling, combined by MIS; the phase
             * function's sample weighs f / pdf = 1. */
            Vec3 wo = v_scale(direction, -1.0f);
            float g = scene->media[medium].g, u1, u2;
            if (use_nee) {
                LightSample ls;
                sample_2d(stream, dim + 1, &u1, &u2);
                if (sample_light(scene, origin, vec3(0.0f, 0.0f, 0.0f), -1, medium, sample_1d(stream, dim), u1, u2,
                                 stream, &medium_dimension, &ls, rays)) {
                    float phase = hg_phase(wo, ls.wi, g);
                    float weight = ls.is_delta ? 1.0f : power_heuristic(ls.pdf, phase);
                    ADD_LIGHT(v_scale(v_mul(throughput, ls.radiance), phase * weight / ls.pdf), depth == 0);
                }
            }
            sample_2d(stream, dim + 4, &u1, &u2);
            direction = v_normalize(hg_sample(wo, g, u1, u2));
            previous_pdf = hg_phase(wo, direction, g);
            previous_point = origin;
            previous_normal = vec3(0.0f, 0.0f, 0.0f);
            specular_bounce = 0;
            if (!roulette_survives(&throughput, eta_scale, depth, integrator->rr_threshold, stream, dim + 6))
                break;
            continue;
        }
        if (!(v_max_component(throughput) > 0.0f))
            break;
#else
        Ray ray = make_ray(origin, direction);
        ++*rays;
        int found = scene_intersect(scene, &ray, 0.0f, INFINITY, 0, &hit);
#endif
        if (!found) {
            if (GMON_HAS_INFINITE_LIGHTS)
                ADD_LIGHT(v_mul(throughput, infinite_radiance(scene, direction, previous_pdf, unweighted)), depth <= 1);
            break;
        }
        __global const Primitive *prim = scene->primitives + hit.primitive;
        Surface surface;
        surface_point(scene, &hit, origin, direction, &surface);
        Vec3 p = surface.p, n = surface.n;
        Vec3 wo_world = v_scale(direction, -1.0f);

        if (GMON_HAS_AREA_LIGHTS && prim->light >= 0) {
            __global const Light *light = scene->lights + prim->light;
            Vec3 le = emitted(light, n, wo_world);
            float weight = 1.0f;
            if (!unweighted) {
                float cos_light = fabs(v_dot(n, wo_world));
#if GMON_HAS_MEDIA
                float distance = v_length(v_sub(p, previous_point)); /* the ray may have crossed interfaces */
#else
                float distance = hit.t;
#endif
                float light_pdf = cos_light > 0.0f
                                      ? light_pick_pmf(scene, light, previous_point, previous_normal) *
                                            area_light_pdf(scene, light, previous_point, distance, cos_light)
                                      : 0.0f;
                weight = cos_light > 0.0f ? power_heuristic(previous_pdf, light_pdf) : 0.0f;
            }
            ADD_LIGHT(v_scale(v_mul(throughput, le), weight), depth <= 1);
        }
        if (depth >= integrator->max_depth)
            break;

#if GMON_HAS_TEXTURES
        cone_width += cone_spread * hit.t;
#endif
        surface_shade(scene, &hit, direction, cone_width, &surface);
        const Material *material = &surface.material;
        Vec3 ns = surface.ns, s = surface.s, t = surface.t;
        Vec3 wo = vec3(v_dot(wo_world, s), v_dot(wo_world, t), v_dot(wo_world, ns));

        /* Next-event estimation (not for perfectly smooth surfaces). */
        if (use_nee && !bsdf_is_delta(material)) {
            LightSample ls;
            float u1, u2;
            sample_2d(stream, dim + 1, &u1, &u2);
            if (sample_light(scene, p, n, hit.primitive, medium, sample_1d(stream, dim), u1, u2, stream,
                             &medium_dimension, &ls, rays)) {
                Vec3 wi = vec3(v_dot(ls.wi, s), v_dot(ls.wi, t), v_dot(ls.wi, ns));
                float bsdf_pdf = 0.0f;
                Vec3 f = bsdf_eval(material, wo, wi, &bsdf_pdf);
                float weight = ls.is_delta ? 1.0f : power_heuristic(ls.pdf, bsdf_pdf);
                Vec3 contribution = v_scale(v_mul(f, ls.radiance), fabs(wi.z) * weight / ls.pdf);
                ADD_LIGHT(v_mul(throughput, contribution), depth == 0);
            }
        }

        BsdfSample bs;
        float u1, u2;
        sample_2d(stream, dim + 4, &u1, &u2);
        if (!bsdf_sample(material, wo, sample_1d(stream, dim + 3), u1, u2, &bs))
            break;
        throughput = v_mul(throughput, v_scale(bs.f, fabs(bs.wi.z) / bs.pdf));
        previous_pdf = bs.pdf;
        previous_point = p;
        previous_normal = n;
        specular_bounce = bs.is_delta;
        if (bs.is_transmission)
            eta_scale *= bs.etap * bs.etap;
        direction = v_normalize(v_add(v_add(v_scale(s, bs.wi.x), v_scale(t, bs.wi.y)), v_scale(ns, bs.wi.z)));
        origin = offset_origin(p, n, direction);
#if GMON_HAS_MEDIA
        medium = medium_after(scene, hit.primitive, n, direction, medium);
#endif
        if (!roulette_survives(&throughput, eta_scale, depth, integrator->rr_threshold, stream, dim + 6))
            break;
    }
    return radiance;
}

/* Renders samples [first_sample, first_sample + sample_count) of pixels
 * [first_pixel, first_pixel + pixel_count) of the image. Accumulators and
 * counters cover pixels [buffer_first_pixel, buffer_first_pixel +
 * buffer_pixel_count), one device's share, which holds the rendered ones.
 * The host binds the arguments in host/render/scene_upload.c. */
__kernel void render_samples(__global const SceneConstants *constants,
                             GMON_SCENE_ARRAYS(SCENE_ARRAY_PARAMETER) __global ulong *accumulators,
                             __global uint *rejected, __global ulong *ray_counts, ulong first_sample, uint sample_count,
                             ulong first_pixel, ulong pixel_count, ulong buffer_first_pixel, ulong buffer_pixel_count
#if SAMPLE_PASSES
                             ,
                             __global ulong *sample_state
#endif
)
{
    if (get_global_id(0) >= pixel_count)
        return;
    Scene scene;
    scene.constants = constants;
    GMON_SCENE_ARRAYS(SCENE_ARRAY_ASSIGN)
    ulong pixel = first_pixel + get_global_id(0);
    ulong local_pixel = pixel - buffer_first_pixel;
    uint width = constants->camera.width;
    uint x = (uint)(pixel % width), y = (uint)(pixel / width);
    uint nonfinite = 0, rounded = 0, rays = 0;
    for (uint i = 0; i < sample_count; ++i) {
        ulong sample_index = first_sample + i;
        SampleStream stream =
            sample_stream(GMON_SAMPLER, constants->integrator.seed, pixel, sample_index, GMON_SAMPLER_SETS);
        CameraRay camera = camera_ray(&constants->camera, &constants->filter, distributions, x, y, &stream);
        Vec3 parts[2] = {vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 0.0f)};
        Vec3 L = film_response(&constants->film, trace_path(&scene, camera.origin, camera.direction, camera.cone_width,
                                                            camera.cone_spread, &stream, &rays, parts));
        const uint set = set_of_sample(sample_index, EST_SETS);
#if SAMPLE_PASSES
        SampleParts sample;
        sample.film[0] = L.x;
        sample.film[1] = L.y;
        sample.film[2] = L.z;
        if (TRACK_DIRECT) {
            Vec3 direct = film_response(&constants->film, parts[0]);
            Vec3 indirect = film_response(&constants->film, parts[1]);
            sample.direct[0] = direct.x;
            sample.direct[1] = direct.y;
            sample.direct[2] = direct.z;
            sample.indirect[0] = indirect.x;
            sample.indirect[1] = indirect.y;
            sample.indirect[2] = indirect.z;
        }
        sample.weight = GMON_HAS_PIXEL_FILTER ? camera.weight : 1.0f;
        sample.set = set;
        sample.set_count = EST_SETS;
#endif
        if (GMON_HAS_PIXEL_FILTER)
            L = v_scale(L, camera.weight); /* after the clamp of the per-sample passes, as pbrt-v4 weighs samples */
        int added = accumulate_sample(accumulators, local_pixel, buffer_pixel_count, EST_SETS, set, L.x, L.y, L.z);
#if SAMPLE_PASSES
        {
#if EST_CLAMP_LEVEL_COUNT > 0
            const float levels[EST_CLAMP_LEVEL_COUNT] = {EST_CLAMP_LEVEL_VALUES};
#else
            const float levels[1] = {0.0f};
#endif
            sample_passes_add(sample_state, local_pixel, buffer_pixel_count, SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT,
                              levels, EST_CLAMP_SUM_DIRECT, EST_CLAMP_SUM_INDIRECT, EST_ZIRR_COUNT, EST_ZIRR_BASE,
                              &sample);
        }
#endif
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    /* Two planes: non-finite samples, then rounded ones (accumulate.h). */
    rejected[local_pixel] += nonfinite;
    rejected[buffer_pixel_count + local_pixel] += rounded;
    ray_counts[local_pixel] += rays;
}
