/* Participating media (FEATURE_MEDIA): which medium a ray is in, distance
 * sampling, transmittance and emission of homogeneous media, for the
 * volumetric path tracer in path_tracer.cl (docs/design.md, "Participating
 * media"). Host-buildable for the tests.
 *
 * RGB media have one extinction per channel, so no single exponential
 * distance matches all three. A distance is sampled from one channel's
 * exponential, the channel picked uniformly, and weighed by the density of
 * the mixture of the three (the balance heuristic over the channels, the
 * one-sample spectral MIS of pbrt-v4's hero wavelength, with three
 * channels): each channel's estimate is unbiased, whichever channel was
 * picked. A homogeneous medium's transmittance and emission along a
 * segment have closed forms (ratio tracking against a majorant equal to
 * the extinction would return them exactly), so they carry no noise. */
#ifndef KERNELS_MEDIA_H
#define KERNELS_MEDIA_H

#include "scene.h"

/* Each medium segment of a path takes its two random numbers from its own
 * dimensions, past any bounce's (camera.h keeps the lens higher still). */
#define MEDIUM_DIMENSION 0x80000000u

KERNEL_FN Vec3 medium_sigma_t(GLOBAL const Medium *m)
{
    return v_add(vec3_from_global(m->sigma_a), vec3_from_global(m->sigma_s));
}

/* exp(-sigma_t t) per channel; 1 where sigma_t is 0 (also for t infinite). */
KERNEL_FN Vec3 medium_transmittance(Vec3 sigma_t, float t)
{
    return vec3(sigma_t.x > 0.0f ? exp_float(-sigma_t.x * t) : 1.0f,
                sigma_t.y > 0.0f ? exp_float(-sigma_t.y * t) : 1.0f,
                sigma_t.z > 0.0f ? exp_float(-sigma_t.z * t) : 1.0f);
}

/* The medium a ray is in after leaving a point of primitive `primitive`
 * (geometric normal n, oriented) along w: the interface's side w points
 * to, or `current` where the primitive bounds no media. */
KERNEL_FN int medium_after(const Scene *scene, int32_t primitive, Vec3 n, Vec3 w, int current)
{
    if (scene->constants->media.count == 0)
        return current;
    uint32_t pair = scene->primitive_media[primitive];
    uint32_t inside = pair & 0xffffu, outside = pair >> 16;
    if (inside == outside)
        return current;
    uint32_t m = v_dot(w, n) > 0.0f ? outside : inside;
    return m == MEDIUM_VACUUM ? -1 : (int)m;
}

/* The radiance the medium emits along a segment of length t_max toward
 * its start: the integral of T(t) sigma_a Le over [0, t_max), per channel
 * sigma_a Le (1 - exp(-sigma_t t_max)) / sigma_t. */
KERNEL_FN Vec3 medium_emission(GLOBAL const Medium *m, float t_max)
{
    Vec3 sigma_t = medium_sigma_t(m), tr = medium_transmittance(sigma_t, t_max);
    Vec3 le = v_mul(vec3_from_global(m->emission), vec3_from_global(m->sigma_a));
    return vec3(sigma_t.x > 0.0f ? le.x * (1.0f - tr.x) / sigma_t.x : 0.0f,
                sigma_t.y > 0.0f ? le.y * (1.0f - tr.y) / sigma_t.y : 0.0f,
                sigma_t.z > 0.0f ? le.z * (1.0f - tr.z) / sigma_t.z : 0.0f);
}

/* Samples where along a segment [0, t_max) of medium m a ray scatters
 * (t_max INFINITY: no surface behind). Returns 1 with *t the distance when
 * it scatters there, *weight = T(t) sigma_s / p(t); 0 when it passes the
 * segment, *weight = T(t_max) / P(pass). p(t) is the mean over the channels
 * of sigma_t exp(-sigma_t t), P(pass) the mean of exp(-sigma_t t_max). A
 * medium that does not scatter is passed with its transmittance. */
KERNEL_FN int medium_sample_distance(GLOBAL const Medium *m, float t_max, float u_channel, float u_distance, float *t,
                                     Vec3 *weight)
{
    Vec3 sigma_t = medium_sigma_t(m), sigma_s = vec3_from_global(m->sigma_s);
    if (v_max_component(sigma_s) <= 0.0f) {
        *weight = medium_transmittance(sigma_t, t_max);
        return 0;
    }
    float channel = u_channel < 1.0f / 3.0f ? sigma_t.x : (u_channel < 2.0f / 3.0f ? sigma_t.y : sigma_t.z);
    float sampled = channel > 0.0f ? -log_float(1.0f - u_distance) / channel : INFINITY;
    if (sampled < t_max) {
        Vec3 tr = medium_transmittance(sigma_t, sampled);
        float pdf = (sigma_t.x * tr.x + sigma_t.y * tr.y + sigma_t.z * tr.z) / 3.0f;
        *t = sampled;
        *weight = pdf > 0.0f ? v_scale(v_mul(tr, sigma_s), 1.0f / pdf) : vec3(0.0f, 0.0f, 0.0f);
        return 1;
    }
    Vec3 tr = medium_transmittance(sigma_t, t_max);
    float pass = (tr.x + tr.y + tr.z) / 3.0f;
    *weight = pass > 0.0f ? v_scale(tr, 1.0f / pass) : vec3(0.0f, 0.0f, 0.0f);
    return 0;
}

/* Transmittance from origin along unit direction over `distance`
 * (INFINITY: to infinity) starting in `medium`: 0 where a surface with a
 * material blocks it, else the product of the media's transmittances over
 * the segments between interface surfaces, which it passes. */
KERNEL_FN Vec3 shadow_transmittance(const Scene *scene, Vec3 origin, Vec3 direction, float distance, int medium,
                                    uint32_t *rays)
{
    Vec3 tr = vec3(1.0f, 1.0f, 1.0f);
    Vec3 target = v_add(origin, v_scale(direction, distance));
    for (int crossing = 0; crossing < 256; ++crossing) {
        Ray ray = make_ray(origin, direction);
        Hit hit;
        int found = scene_intersect(scene, &ray, 0.0f, distance, 0, &hit);
        if (medium >= 0)
            tr = v_mul(tr, medium_transmittance(medium_sigma_t(scene->media + medium), found ? hit.t : distance));
        if (!found)
            return tr;
        GLOBAL const Primitive *prim = scene->primitives + hit.primitive;
        if (scene->materials[prim->material].type != MAT_INTERFACE || v_max_component(tr) <= 0.0f)
            return vec3(0.0f, 0.0f, 0.0f);
        Vec3 p = v_add(origin, v_scale(direction, hit.t));
        Vec3 n = hit_normal(scene, &hit, prim, p);
        medium = medium_after(scene, hit.primitive, n, direction, medium);
        origin = offset_origin(p, n, direction);
        if (distance < INFINITY)
            distance = v_length(v_sub(target, origin));
        ++*rays;
    }
    return vec3(0.0f, 0.0f, 0.0f);
}

#endif
