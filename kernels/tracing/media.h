/* Participating media (FEATURE_MEDIA): which medium a ray is in, distance
 * sampling, transmittance and emission of homogeneous and grid media, for the
 * volumetric path tracer in path_tracer.cl (docs/design.md, "Participating
 * media"). Host-buildable for the tests.
 *
 * RGB media have one extinction per channel, so no single exponential
 * distance matches all three. A distance is sampled from one channel's
 * exponential, the channel picked with a chance proportional to the path's
 * throughput in it, and weighed by the density of the mixture of the
 * three (the balance heuristic over the channels, the one-sample spectral
 * MIS of pbrt-v4's hero wavelength, with three channels): each channel's
 * estimate is unbiased, whichever channel was picked, and the
 * throughput's channel sum never grows. A homogeneous medium's transmittance and emission along a
 * segment have closed forms (ratio tracking against a majorant equal to
 * the extinction would return them exactly), so they carry no noise.
 *
 * Grid media are tracked against grey majorants, the largest extinction of
 * any channel in each cell of a 16^3 majorant grid over the medium's box
 * (pbrt-v4's MajorantGrid, walked by a DDA): weighted delta tracking
 * samples tentative collisions from them, and at each one scatters,
 * goes on (a null collision) or is absorbed with chances proportional to
 * beta . sigma_s, beta . sigma_n and beta . sigma_a (beta the path's
 * throughput, sigma_n = majorant - sigma_t), weighing the path per channel
 * by sigma / (majorant P) of the event (Kutz et al. 2017's spectral
 * tracking): unbiased per channel, and the throughput's channel sum never
 * grows. Emission is added at every tentative collision, weighed by
 * sigma_a Le / majorant. Shadow rays use ratio tracking: the product of
 * (majorant - sigma_t) / majorant over the tentative collisions. Both
 * track only where the ray is inside the grid's box. */
#ifndef KERNELS_MEDIA_H
#define KERNELS_MEDIA_H

#include "sampler.h"
#include "scene.h"
#include "texture.h" /* Perlin noise, for clouds */
#if GMON_HAS_NANOVDB
#include "nanovdb.h"
#endif

/* Each medium segment of a path takes its two random numbers from its own
 * dimensions, past any bounce's (camera.h keeps the lens higher still). */
#define MEDIUM_DIMENSION 0x80000000u

/* A ray crossing more interface boundaries than this in one step (a ray
 * caught between coincident boundaries) ends: no infinite loop. */
#define MEDIUM_MAX_CROSSINGS 256

KERNEL_FN Vec3 medium_sigma_t(GLOBAL const Medium *m)
{
    return v_add(vec3_from_global(m->sigma_a), vec3_from_global(m->sigma_s));
}

/* A grid's value at u (unit-cube coordinates) as pbrt-v4's SampledGrid
 * looks it up: trilinear between the cells' centres, cells outside the
 * grid 0. `channels` values a cell (1: the value in all three). */
KERNEL_FN Vec3 grid_lookup(GLOBAL const float *values, GLOBAL const uint32_t *size, int channels, Vec3 u)
{
    float p[3] = {u.x * (float)size[0] - 0.5f, u.y * (float)size[1] - 0.5f, u.z * (float)size[2] - 0.5f};
    int cell[3];
    float d[3];
    for (int k = 0; k < 3; ++k) {
        cell[k] = (int)p[k];
        cell[k] -= (float)cell[k] > p[k]; /* floor */
        d[k] = p[k] - (float)cell[k];
    }
    Vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    for (int corner = 0; corner < 8; ++corner) {
        int x = cell[0] + (corner & 1), y = cell[1] + ((corner >> 1) & 1), z = cell[2] + (corner >> 2);
        if (x < 0 || y < 0 || z < 0 || x >= (int)size[0] || y >= (int)size[1] || z >= (int)size[2])
            continue;
        float w = ((corner & 1) ? d[0] : 1.0f - d[0]) * (((corner >> 1) & 1) ? d[1] : 1.0f - d[1]) *
                  ((corner >> 2) ? d[2] : 1.0f - d[2]);
        GLOBAL const float *v =
            values + ((size_t)((uint32_t)z * size[1] + (uint32_t)y) * size[0] + (uint32_t)x) * (size_t)channels;
        sum = v_add(sum, v_scale(channels == 3 ? vec3(v[0], v[1], v[2]) : vec3(v[0], v[0], v[0]), w));
    }
    return sum;
}

/* A grid medium's point in its unit cube. */
KERNEL_FN Vec3 grid_point(GLOBAL const Medium *m, Vec3 p)
{
    GLOBAL const float(*r)[4] = m->medium_from_world;
    return vec3(r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + r[0][3],
                r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + r[1][3],
                r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + r[2][3]);
}

/* pbrt-v4's procedural cloud density at p (the medium's space): noise
 * octaves at a point perturbed by noise's gradient (finite differences of
 * 0.01, as pbrt-v4's DNoise), thinning with height, in [0, 1]. */
KERNEL_FN float cloud_density(Vec3 p, float density, float wispiness, float frequency)
{
    Vec3 pp = v_scale(p, frequency);
    float omega = 0.05f * wispiness, lambda = 10.0f;
    for (int i = 0; i < 2 && wispiness > 0.0f; ++i) {
        Vec3 q = v_scale(pp, lambda);
        float n = noise_at(q);
        Vec3 gradient = vec3((noise_at(v_add(q, vec3(0.01f, 0.0f, 0.0f))) - n) / 0.01f,
                             (noise_at(v_add(q, vec3(0.0f, 0.01f, 0.0f))) - n) / 0.01f,
                             (noise_at(v_add(q, vec3(0.0f, 0.0f, 0.01f))) - n) / 0.01f);
        pp = v_add(pp, v_scale(gradient, omega));
        omega *= 0.5f;
        lambda *= 1.99f;
    }
    float d = 0.0f;
    omega = 0.5f;
    lambda = 1.0f;
    for (int i = 0; i < 5; ++i) {
        d += omega * noise_at(v_scale(pp, lambda));
        omega *= 0.5f;
        lambda *= 1.99f;
    }
    d = fmin(fmax((1.0f - p.y) * 4.5f * density * d, 0.0f), 1.0f);
    d += 2.0f * fmax(0.0f, 0.5f - p.y);
    return fmin(fmax(d, 0.0f), 1.0f);
}

/* A grid medium's coefficients and emitted radiance at world point p. */
KERNEL_FN void grid_medium_at(const Scene *scene, GLOBAL const Medium *m, Vec3 p, Vec3 *sigma_a, Vec3 *sigma_s,
                              Vec3 *le)
{
    Vec3 u = grid_point(m, p), one = vec3(1.0f, 1.0f, 1.0f);
    GLOBAL const float *values = scene->medium_values;
    if (m->type == MEDIUM_CLOUD) {
        GLOBAL const float *c = values + m->density;
        Vec3 q = vec3(c[3] + u.x * c[6], c[4] + u.y * c[7], c[5] + u.z * c[8]);
        float d = cloud_density(q, c[0], c[1], c[2]);
        *sigma_a = v_scale(vec3_from_global(m->sigma_a), d);
        *sigma_s = v_scale(vec3_from_global(m->sigma_s), d);
        *le = vec3(0.0f, 0.0f, 0.0f);
        return;
    }
#if GMON_HAS_NANOVDB
    if (m->type == MEDIUM_NANOVDB) {
        float density = nanovdb_medium_at(values, m->density, m->le_scale, m->rgb_le, u, le);
        *sigma_a = v_scale(vec3_from_global(m->sigma_a), density);
        *sigma_s = v_scale(vec3_from_global(m->sigma_s), density);
        *le = v_scale(*le, m->emission[0]);
        return;
    }
#endif
    if (m->type == MEDIUM_UNIFORM_GRID) {
        float density = grid_lookup(values + m->density, m->size, 1, u).x;
        *sigma_a = v_scale(vec3_from_global(m->sigma_a), density);
        *sigma_s = v_scale(vec3_from_global(m->sigma_s), density);
        *le = v_scale(vec3_from_global(m->emission), grid_lookup(values + m->le_scale, m->le_size, 1, u).x);
        return;
    }
    *sigma_a = v_scale(m->rgb_sigma_a >= 0 ? grid_lookup(values + m->rgb_sigma_a, m->size, 3, u) : one, m->sigma_a[0]);
    *sigma_s = v_scale(m->rgb_sigma_s >= 0 ? grid_lookup(values + m->rgb_sigma_s, m->size, 3, u) : one, m->sigma_s[0]);
    *le = m->rgb_le >= 0 ? v_scale(grid_lookup(values + m->rgb_le, m->size, 3, u), m->emission[0])
                         : vec3(0.0f, 0.0f, 0.0f);
}

/* Where the ray origin + t direction, t in [0, t_max), is inside the grid's
 * box: [*t0, *t1). Returns 0 when nowhere. */
KERNEL_FN int grid_span(GLOBAL const Medium *m, Vec3 origin, Vec3 direction, float t_max, float *t0, float *t1)
{
    GLOBAL const float(*r)[4] = m->medium_from_world;
    Vec3 o = grid_point(m, origin);
    float o3[3] = {o.x, o.y, o.z}, near = 0.0f, far = t_max;
    for (int k = 0; k < 3; ++k) {
        float d = r[k][0] * direction.x + r[k][1] * direction.y + r[k][2] * direction.z;
        if (d == 0.0f) {
            if (o3[k] < 0.0f || o3[k] > 1.0f)
                return 0;
            continue;
        }
        float a = -o3[k] / d, b = (1.0f - o3[k]) / d;
        near = fmax(near, fmin(a, b));
        far = fmin(far, fmax(a, b));
    }
    *t0 = near;
    *t1 = far;
    return near < far;
}

/* A walk through the majorant grid's cells along a ray (a 3D DDA): the
 * current cell, where the ray enters it (t) and the next crossing of
 * each axis' cell planes. */
typedef struct {
    float t, t1;
    int cell[3], step[3];
    float next[3], delta[3];
} MajorantWalk;

KERNEL_FN void majorant_walk_start(GLOBAL const Medium *m, Vec3 origin, Vec3 direction, float t0, float t1,
                                   MajorantWalk *w)
{
    GLOBAL const float(*r)[4] = m->medium_from_world;
    const float cells = (float)MEDIUM_MAJORANT_GRID;
    Vec3 o = grid_point(m, v_add(origin, v_scale(direction, t0)));
    float p[3] = {o.x, o.y, o.z};
    w->t = t0;
    w->t1 = t1;
    for (int k = 0; k < 3; ++k) {
        float d = r[k][0] * direction.x + r[k][1] * direction.y + r[k][2] * direction.z;
        int c = (int)(p[k] * cells);
        c = c < 0 ? 0 : (c > MEDIUM_MAJORANT_GRID - 1 ? MEDIUM_MAJORANT_GRID - 1 : c);
        w->cell[k] = c;
        w->step[k] = d > 0.0f ? 1 : -1;
        w->next[k] = d > 0.0f   ? t0 + ((float)(c + 1) / cells - p[k]) / d
                     : d < 0.0f ? t0 + ((float)c / cells - p[k]) / d
                                : INFINITY;
        w->delta[k] = d != 0.0f ? 1.0f / (cells * fabs(d)) : INFINITY;
    }
}

/* The current cell's majorant, and where along the ray the ray leaves it. */
KERNEL_FN float majorant_cell(const Scene *scene, GLOBAL const Medium *m, const MajorantWalk *w, float *end)
{
    *end = fmin(fmin(w->next[0], w->next[1]), fmin(w->next[2], w->t1));
    int index = (w->cell[2] * MEDIUM_MAJORANT_GRID + w->cell[1]) * MEDIUM_MAJORANT_GRID + w->cell[0];
    return scene->medium_values[m->majorants + index];
}

/* Moves to the next cell; 0 when the walk is past t1 or the grid. */
KERNEL_FN int majorant_walk_next(MajorantWalk *w)
{
    int axis = w->next[0] < w->next[1] ? (w->next[0] < w->next[2] ? 0 : 2) : (w->next[1] < w->next[2] ? 1 : 2);
    if (!(w->next[axis] < w->t1))
        return 0;
    w->t = w->next[axis];
    w->cell[axis] += w->step[axis];
    w->next[axis] += w->delta[axis];
    return w->cell[axis] >= 0 && w->cell[axis] < MEDIUM_MAJORANT_GRID;
}

/* Weighted delta tracking through a grid medium along [0, t_max) (see
 * the top): returns 1 with *t where the path scatters, 0 when it passes;
 * *beta takes the weights, *emitted (with emit) the emission times *beta.
 * Each tentative collision draws two numbers at *dimension. */
KERNEL_FN int grid_sample_distance(const Scene *scene, GLOBAL const Medium *m, Vec3 origin, Vec3 direction, float t_max,
                                   const SampleStream *stream, uint32_t *dimension, int emit, Vec3 *beta, Vec3 *emitted,
                                   float *t)
{
    float t0, t1;
    if (!(m->majorant > 0.0f) || !grid_span(m, origin, direction, t_max, &t0, &t1))
        return 0;
    MajorantWalk walk;
    majorant_walk_start(m, origin, direction, t0, t1, &walk);
    do {
        float end, majorant = majorant_cell(scene, m, &walk, &end);
        /* Exponential steps are memoryless: each cell starts afresh. */
        for (float s = walk.t; majorant > 0.0f;) {
            float u1, u2;
            sample_2d(stream, *dimension, &u1, &u2);
            *dimension += 2u;
            s -= log_float(1.0f - u1) / majorant;
            if (!(s < end))
                break;
            Vec3 sigma_a, sigma_s, le;
            grid_medium_at(scene, m, v_add(origin, v_scale(direction, s)), &sigma_a, &sigma_s, &le);
            if (emit)
                *emitted = v_add(*emitted, v_scale(v_mul(*beta, v_mul(sigma_a, le)), 1.0f / majorant));
            /* Spectral tracking: each event's chance is its coefficient
             * weighed by the throughput's channels. */
            Vec3 sigma_n = v_sub(vec3(majorant, majorant, majorant), v_add(sigma_a, sigma_s));
            sigma_n = vec3(fmax(sigma_n.x, 0.0f), fmax(sigma_n.y, 0.0f), fmax(sigma_n.z, 0.0f));
            float total = majorant * (beta->x + beta->y + beta->z);
            float scatter = v_dot(*beta, sigma_s) / total, go_on = v_dot(*beta, sigma_n) / total;
            if (u2 < scatter) {
                *beta = v_scale(v_mul(*beta, sigma_s), 1.0f / (majorant * scatter));
                *t = s;
                return 1;
            }
            if (!(u2 < scatter + go_on) || !(go_on > 0.0f)) { /* absorbed */
                *beta = vec3(0.0f, 0.0f, 0.0f);
                return 0;
            }
            *beta = v_scale(v_mul(*beta, sigma_n), 1.0f / (majorant * go_on));
        }
    } while (majorant_walk_next(&walk));
    return 0;
}

/* Ratio tracking through a grid medium along [0, t_max): its
 * transmittance, estimated. */
KERNEL_FN Vec3 grid_transmittance(const Scene *scene, GLOBAL const Medium *m, Vec3 origin, Vec3 direction, float t_max,
                                  const SampleStream *stream, uint32_t *dimension)
{
    float t0, t1;
    Vec3 tr = vec3(1.0f, 1.0f, 1.0f);
    if (!(m->majorant > 0.0f) || !grid_span(m, origin, direction, t_max, &t0, &t1))
        return tr;
    MajorantWalk walk;
    majorant_walk_start(m, origin, direction, t0, t1, &walk);
    do {
        float end, majorant = majorant_cell(scene, m, &walk, &end);
        for (float s = walk.t; majorant > 0.0f;) {
            s -= log_float(1.0f - sample_1d(stream, *dimension)) / majorant;
            *dimension += 2u;
            if (!(s < end))
                break;
            Vec3 sigma_a, sigma_s, le;
            grid_medium_at(scene, m, v_add(origin, v_scale(direction, s)), &sigma_a, &sigma_s, &le);
            Vec3 sigma_n = v_sub(vec3(majorant, majorant, majorant), v_add(sigma_a, sigma_s));
            tr = v_mul(tr, v_scale(vec3(fmax(sigma_n.x, 0.0f), fmax(sigma_n.y, 0.0f), fmax(sigma_n.z, 0.0f)),
                                   1.0f / majorant));
            if (!(v_max_component(tr) > 0.0f))
                return tr;
        }
    } while (majorant_walk_next(&walk));
    return tr;
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

/* Samples where along a segment [0, t_max) of medium m a path of
 * throughput beta scatters (t_max INFINITY: no surface behind). Channel c
 * is picked with chance q_c = beta_c / sum(beta). Returns 1 with *t the
 * distance when it scatters there, *weight = T(t) sigma_s / p(t); 0 when it
 * passes the segment, *weight = T(t_max) / P(pass); p(t) is the sum over
 * the channels of q_c sigma_t exp(-sigma_t t), P(pass) that of
 * q_c exp(-sigma_t t_max). So the new throughput's channels sum to at most
 * the old's. A medium that does not scatter is passed with its
 * transmittance. */
KERNEL_FN int medium_sample_distance(GLOBAL const Medium *m, float t_max, Vec3 beta, float u_channel, float u_distance,
                                     float *t, Vec3 *weight)
{
    Vec3 sigma_t = medium_sigma_t(m), sigma_s = vec3_from_global(m->sigma_s);
    float total = beta.x + beta.y + beta.z;
    if (v_max_component(sigma_s) <= 0.0f || !(total > 0.0f)) {
        *weight = medium_transmittance(sigma_t, t_max);
        return 0;
    }
    Vec3 q = v_scale(beta, 1.0f / total);
    float channel = u_channel < q.x ? sigma_t.x : (u_channel < q.x + q.y ? sigma_t.y : sigma_t.z);
    float sampled = channel > 0.0f ? -log_float(1.0f - u_distance) / channel : INFINITY;
    if (sampled < t_max) {
        Vec3 tr = medium_transmittance(sigma_t, sampled);
        float pdf = v_dot(q, v_mul(sigma_t, tr));
        *t = sampled;
        *weight = pdf > 0.0f ? v_scale(v_mul(tr, sigma_s), 1.0f / pdf) : vec3(0.0f, 0.0f, 0.0f);
        return 1;
    }
    Vec3 tr = medium_transmittance(sigma_t, t_max);
    float pass = v_dot(q, tr);
    *weight = pass > 0.0f ? v_scale(tr, 1.0f / pass) : vec3(0.0f, 0.0f, 0.0f);
    return 0;
}

/* Transmittance from origin along unit direction over `distance`
 * (INFINITY: to infinity) starting in `medium`: 0 where a surface with a
 * material blocks it, else the product of the media's transmittances over
 * the segments between interface surfaces, which it passes. */
KERNEL_FN Vec3 shadow_transmittance(const Scene *scene, Vec3 origin, Vec3 direction, float distance, int medium,
                                    const SampleStream *stream, uint32_t *dimension, uint32_t *rays)
{
    Vec3 tr = vec3(1.0f, 1.0f, 1.0f);
    Vec3 target = v_add(origin, v_scale(direction, distance));
    for (int crossing = 0; crossing < MEDIUM_MAX_CROSSINGS; ++crossing) {
        Ray ray = make_ray(origin, direction);
        Hit hit;
        int found = scene_intersect(scene, &ray, 0.0f, distance, 0, &hit);
        if (medium >= 0) {
            GLOBAL const Medium *m = scene->media + medium;
            float t = found ? hit.t : distance;
            tr = v_mul(tr, m->type == MEDIUM_HOMOGENEOUS
                               ? medium_transmittance(medium_sigma_t(m), t)
                               : grid_transmittance(scene, m, origin, direction, t, stream, dimension));
        }
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
