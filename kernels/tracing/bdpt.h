/* Bidirectional path tracing's subpaths and multiple importance sampling
 * (pbrt-v4's BDPT, for the kernels of bdpt.cl; valid C11 too, for the
 * tests): path vertices with their forward and reverse densities (area
 * measure), the random walk that makes a subpath, the connection of a
 * light subpath's s vertices to a camera subpath's t, and the weight of
 * that strategy among all those that make the same path (pbrt-v4's
 * MISWeight: the balance heuristic over the ratios of densities, with
 * specular vertices and point lights, which no connection can reach,
 * left out). */
#ifndef KERNELS_BDPT_H
#define KERNELS_BDPT_H

#include "bsdf.h"
#include "camera.h"
#include "lights.h"
#include "scene.h"
#include "surface.h"

#define VERTEX_CAMERA 0
#define VERTEX_LIGHT 1
#define VERTEX_SURFACE 2

/* One vertex of a subpath. The camera's is a point of its lens; a light's
 * the point the light subpath leaves (a point light's position, with no
 * normal); a surface's holds the surface and its resolved material. */
typedef struct {
    Surface surface; /* p, n (0: not on a surface), ns and the material */
    Vec3 wo;         /* a surface's direction toward the vertex before it */
    Vec3 beta;       /* the subpath's throughput up to here (a light's: its emission) */
    float pdf_fwd;   /* density of this vertex, area measure, sampled from the one before */
    float pdf_rev;   /* the same sampled from the one after, the other way */
    int type;
    int delta;    /* sampled through a specular BSDF lobe */
    int light;    /* the light it lies on (a light vertex, or a surface of an area light), else -1 */
    int radiance; /* its subpath's transport: 1 from the camera, 0 from a light */
} PathVertex;

KERNEL_FN int vertex_on_surface(const PathVertex *v)
{
    return v_dot(v->surface.n, v->surface.n) > 0.0f;
}

/* A light vertex of a point-like light (a delta position): no strategy
 * reaches it but connecting to it. */
KERNEL_FN int vertex_is_delta_light(const Scene *scene, const PathVertex *v)
{
    return v->type == VERTEX_LIGHT && scene->lights[v->light].type != LIGHT_AREA;
}

/* Whether a connection may start or end at v. */
KERNEL_FN int vertex_connectible(const PathVertex *v)
{
    return v->type != VERTEX_SURFACE || !bsdf_is_delta(&v->surface.material);
}

/* A solid angle density at `from` toward `to` as an area density at `to`. */
KERNEL_FN float convert_density(const PathVertex *from, float pdf, const PathVertex *to)
{
    Vec3 w = v_sub(to->surface.p, from->surface.p);
    float distance2 = v_dot(w, w);
    if (!(distance2 > 0.0f))
        return 0.0f;
    if (vertex_on_surface(to))
        pdf *= fabs(v_dot(to->surface.n, w)) / sqrt_float(distance2);
    return pdf / distance2;
}

/* The BSDF at surface vertex v from its wo toward `next`, in its subpath's
 * transport (with the shading-normal correction of importance). */
KERNEL_FN Vec3 vertex_f(const PathVertex *v, const PathVertex *next)
{
    Vec3 wi = v_sub(next->surface.p, v->surface.p);
    float length2 = v_dot(wi, wi);
    if (!(length2 > 0.0f))
        return vec3(0.0f, 0.0f, 0.0f);
    wi = v_scale(wi, 1.0f / sqrt_float(length2));
    float pdf;
    Vec3 f = bsdf_eval_transport(&v->surface.material, surface_to_local(&v->surface, v->wo),
                                 surface_to_local(&v->surface, wi), &pdf, v->radiance);
    return v_scale(f, shading_correction(&v->surface, v->wo, wi, v->radiance));
}

/* The density with which light vertex (or emitting surface) v sends its
 * emission toward `next`, area measure at next (pbrt-v4's PDFLight). */
KERNEL_FN float vertex_pdf_light(const Scene *scene, const PathVertex *v, const PathVertex *next)
{
    GLOBAL const Light *light = scene->lights + v->light;
    Vec3 w = v_sub(next->surface.p, v->surface.p);
    float distance2 = v_dot(w, w);
    if (!(distance2 > 0.0f))
        return 0.0f;
    w = v_scale(w, 1.0f / sqrt_float(distance2));
    float pdf = light->type == LIGHT_AREA ? area_light_pdf_direction(light, v->surface.n, w)
                                          : point_light_pdf_direction(light, w);
    pdf /= distance2;
    return vertex_on_surface(next) ? pdf * fabs(v_dot(next->surface.n, w)) : pdf;
}

/* The density of v's position as the start of a light subpath: the
 * light's chance times its area density (1 for a delta position). */
KERNEL_FN float vertex_pdf_light_origin(const Scene *scene, const PathVertex *v)
{
    GLOBAL const Light *light = scene->lights + v->light;
    return light->pick_probability * (light->type == LIGHT_AREA ? 1.0f / light->area : 1.0f);
}

/* The density with which v, reached from `prev` (none for the camera),
 * samples `next`, area measure at next (pbrt-v4's Vertex::PDF). */
KERNEL_FN float vertex_pdf(const Scene *scene, const PathVertex *prev, const PathVertex *v, const PathVertex *next)
{
    if (v->type == VERTEX_LIGHT)
        return vertex_pdf_light(scene, v, next);
    Vec3 wn = v_sub(next->surface.p, v->surface.p);
    if (!(v_dot(wn, wn) > 0.0f))
        return 0.0f;
    wn = v_normalize(wn);
    float pdf = 0.0f;
    if (v->type == VERTEX_CAMERA) {
        pdf = camera_pdf_direction(&scene->constants->camera, wn);
    } else {
        Vec3 wp = v_sub(prev->surface.p, v->surface.p);
        if (!(v_dot(wp, wp) > 0.0f))
            return 0.0f;
        wp = v_normalize(wp);
        bsdf_eval_transport(&v->surface.material, surface_to_local(&v->surface, wp), surface_to_local(&v->surface, wn),
                            &pdf, 1);
    }
    return convert_density(v, pdf, next);
}

/* Radiance an emitting vertex sends toward unit direction w. */
KERNEL_FN Vec3 vertex_le(const Scene *scene, const PathVertex *v, Vec3 w)
{
    if (v->light < 0)
        return vec3(0.0f, 0.0f, 0.0f);
    GLOBAL const Light *light = scene->lights + v->light;
    if (light->type != LIGHT_AREA)
        return point_light_intensity(scene, light, w);
    if (!light->two_sided && v_dot(v->surface.n, w) <= 0.0f)
        return vec3(0.0f, 0.0f, 0.0f);
    return vec3_from_global(light->radiance);
}

/* pbrt-v4's BSDF regularization (Integrator "regularize"): a near-specular
 * microfacet lobe, alpha below 0.3, is widened to 2 alpha within
 * [0.1, 0.3], so that connections can reach paths it would make nearly
 * specular (biased, consistent). */
KERNEL_FN float regularized_alpha(float alpha)
{
    return alpha < 0.3f ? fmin(fmax(2.0f * alpha, 0.1f), 0.3f) : alpha;
}

KERNEL_FN void material_regularize(Material *m)
{
    if (m->type == MAT_DIELECTRIC || m->type == MAT_CONDUCTOR || m->type == MAT_COATED_DIFFUSE ||
        m->type == MAT_COATED_CONDUCTOR) {
        m->alpha_x = regularized_alpha(m->alpha_x);
        m->alpha_y = regularized_alpha(m->alpha_y);
    }
}

KERNEL_FN float remap0(float pdf)
{
    return pdf != 0.0f ? pdf : 1.0f;
}

/* The weight of strategy (s, t) among those that make the same path
 * (pbrt-v4's MISWeight): light[0..s) and camera[0..t) as sampled, with
 * `sampled` standing for light[s - 1] when s = 1 (a light sampled from
 * camera[t - 1], t > 1) or for camera[0] when t = 1 (the camera reached
 * from light[s - 1]). The vertices' reverse densities and delta flags are
 * changed for the connection and restored before returning. */
KERNEL_FN float mis_weight(const Scene *scene, PathVertex *light, PathVertex *camera, const PathVertex *sampled, int s,
                           int t)
{
    if (s + t == 2)
        return 1.0f;
    PathVertex *qs = s > 0 ? light + s - 1 : 0, *pt = camera + t - 1;
    PathVertex *qs_minus = s > 1 ? light + s - 2 : 0, *pt_minus = t > 1 ? camera + t - 2 : 0;
    PathVertex saved_qs, saved_pt;
    float saved_pt_minus = 0.0f, saved_qs_minus = 0.0f;
    if (qs)
        saved_qs = *qs;
    saved_pt = *pt;
    if (pt_minus)
        saved_pt_minus = pt_minus->pdf_rev;
    if (qs_minus)
        saved_qs_minus = qs_minus->pdf_rev;
    if (t == 1)
        *pt = *sampled;
    else if (s == 1)
        *qs = *sampled;
    pt->delta = 0;
    if (qs)
        qs->delta = 0;
    float pt_rev = s > 0 ? vertex_pdf(scene, qs_minus, qs, pt) : vertex_pdf_light_origin(scene, pt);
    float pt_minus_rev = 0.0f, qs_rev = 0.0f, qs_minus_rev = 0.0f;
    if (pt_minus)
        pt_minus_rev = s > 0 ? vertex_pdf(scene, qs, pt, pt_minus) : vertex_pdf_light(scene, pt, pt_minus);
    if (qs)
        qs_rev = vertex_pdf(scene, pt_minus, pt, qs);
    if (qs_minus)
        qs_minus_rev = vertex_pdf(scene, pt, qs, qs_minus);
    pt->pdf_rev = pt_rev;
    if (pt_minus)
        pt_minus->pdf_rev = pt_minus_rev;
    if (qs)
        qs->pdf_rev = qs_rev;
    if (qs_minus)
        qs_minus->pdf_rev = qs_minus_rev;

    float sum = 0.0f, ri = 1.0f;
    for (int i = t - 1; i > 0; --i) {
        ri *= remap0(camera[i].pdf_rev) / remap0(camera[i].pdf_fwd);
        if (!camera[i].delta && !camera[i - 1].delta)
            sum += ri;
    }
    ri = 1.0f;
    for (int i = s - 1; i >= 0; --i) {
        ri *= remap0(light[i].pdf_rev) / remap0(light[i].pdf_fwd);
        int delta_before = i > 0 ? light[i - 1].delta : vertex_is_delta_light(scene, light);
        if (!light[i].delta && !delta_before)
            sum += ri;
    }

    if (qs)
        *qs = saved_qs;
    *pt = saved_pt;
    if (pt_minus)
        pt_minus->pdf_rev = saved_pt_minus;
    if (qs_minus)
        qs_minus->pdf_rev = saved_qs_minus;
    return 1.0f / (1.0f + sum);
}

/* Whether the segment between vertices a and b is unoccluded (each
 * offset off its surface). */
KERNEL_FN int vertices_see(const Scene *scene, const PathVertex *a, const PathVertex *b)
{
    Vec3 d = v_sub(b->surface.p, a->surface.p);
    Vec3 from = vertex_on_surface(a) ? offset_origin(a->surface.p, a->surface.n, d) : a->surface.p;
    Vec3 to = vertex_on_surface(b) ? offset_origin(b->surface.p, b->surface.n, v_scale(d, -1.0f)) : b->surface.p;
    Vec3 between = v_sub(to, from);
    float distance = v_length(between);
    if (!(distance > 0.0f))
        return 0;
    return !occluded(scene, from, v_scale(between, 1.0f / distance), distance);
}

/* Random dimensions of the subpaths (sampler.h), the camera's after its
 * image position (0, 1), the light's apart from them: camera vertex k >= 1
 * takes CAMERA_DIMS_PER_VERTEX from 2 + (k - 1) times that (its BSDF's
 * lobe and direction, then the light pick and point of strategy s = 1);
 * the light subpath takes the light's pick, the ray's origin (2D) and
 * direction (2D), the lens point of the light's own connection to the
 * camera (2D), then light vertex k >= 1 LIGHT_DIMS_PER_VERTEX from
 * LIGHT_DIMENSION + 7 + (k - 1) times that (the lens point of its
 * connection to the camera, its BSDF's lobe and direction). */
#define CAMERA_DIMS_PER_VERTEX 6u
#define LIGHT_DIMENSION 0x40000000u
#define LIGHT_DIMS_START 7u
#define LIGHT_DIMS_PER_VERTEX 5u

KERNEL_FN uint32_t vertex_dimension(int radiance, int k)
{
    return radiance ? 2u + (uint32_t)(k - 1) * CAMERA_DIMS_PER_VERTEX
                    : LIGHT_DIMENSION + LIGHT_DIMS_START + (uint32_t)(k - 1) * LIGHT_DIMS_PER_VERTEX;
}

/* Extends a subpath of `count` vertices (path[count - 1] its last, which
 * sent the ray from origin along unit direction with solid angle density
 * pdf, throughput beta after it) by a random walk, to at most `most`
 * vertices (pbrt-v4's RandomWalk: no Russian roulette). Returns the
 * vertex count. */
KERNEL_FN int random_walk(const Scene *scene, const SampleStream *stream, PathVertex *path, int count, int most,
                          Vec3 origin, Vec3 direction, Vec3 beta, float pdf, int radiance, uint32_t *rays)
{
    int regularize = (scene->constants->integrator.flags & RENDER_REGULARIZE) != 0, any_rough = 0;
    float pdf_fwd = pdf;
    while (count < most) {
        Ray ray = make_ray(origin, direction);
        Hit hit;
        ++*rays;
        if (!scene_intersect(scene, &ray, 0.0f, INFINITY, 0, &hit))
            break;
        PathVertex *v = path + count, *prev = path + count - 1;
        surface_at_hit(scene, &hit, origin, direction, 0.0f, &v->surface);
        if (regularize && any_rough)
            material_regularize(&v->surface.material);
        v->type = VERTEX_SURFACE;
        v->wo = v_scale(direction, -1.0f);
        v->beta = beta;
        v->pdf_fwd = convert_density(prev, pdf_fwd, v);
        v->pdf_rev = 0.0f;
        v->delta = 0;
        v->light = scene->primitives[hit.primitive].light;
        v->radiance = radiance;
        if (++count >= most)
            break;
        uint32_t dim = vertex_dimension(radiance, count - 1) + (radiance ? 0u : 2u);
        float u1, u2;
        sample_2d(stream, dim + 1u, &u1, &u2);
        BsdfSample bs;
        Vec3 wo = surface_to_local(&v->surface, v->wo);
        if (!bsdf_sample_transport(&v->surface.material, wo, sample_1d(stream, dim), u1, u2, &bs, radiance) ||
            !(bs.pdf > 0.0f))
            break;
        Vec3 wi = surface_to_world(&v->surface, bs.wi);
        beta =
            v_mul(beta, v_scale(bs.f, fabs(bs.wi.z) * shading_correction(&v->surface, v->wo, wi, radiance) / bs.pdf));
        float pdf_rev = 0.0f;
        pdf_fwd = bs.pdf;
        bsdf_eval_transport(&v->surface.material, bs.wi, wo, &pdf_rev, !radiance);
        if (bs.is_delta) {
            v->delta = 1;
            pdf_fwd = pdf_rev = 0.0f;
        }
        any_rough |= !bs.is_delta;
        prev->pdf_rev = convert_density(v, pdf_rev, prev);
        direction = wi;
        origin = offset_origin(v->surface.p, v->surface.n, direction);
        if (!(v_max_component(beta) > 0.0f))
            break;
    }
    return count;
}

/* The light subpath of a sample: a light picked by its fixed chance and a
 * ray leaving it, then a random walk, at most `most` vertices. Returns the
 * vertex count (0: none). */
KERNEL_FN int light_subpath(const Scene *scene, const SampleStream *stream, PathVertex *path, int most, uint32_t *rays)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    if (integrator->light_count == 0 || most < 1)
        return 0;
    int index = pick_light(scene->lights, integrator->light_count, sample_1d(stream, LIGHT_DIMENSION));
    GLOBAL const Light *light = scene->lights + index;
    float pick = light->pick_probability, u1, u2, u3, u4;
    sample_2d(stream, LIGHT_DIMENSION + 1u, &u1, &u2);
    sample_2d(stream, LIGHT_DIMENSION + 3u, &u3, &u4);
    LightEmission e;
    if (!(pick > 0.0f) || !light_sample_emission(scene, light, u1, u2, u3, u4, &e))
        return 0;
    PathVertex *v = path;
    v->type = VERTEX_LIGHT;
    v->surface.p = e.origin;
    v->surface.n = e.normal;
    v->surface.ns = e.normal;
    v->beta = e.radiance;
    v->pdf_fwd = pick * e.pdf_position;
    v->pdf_rev = 0.0f;
    v->delta = 0;
    v->light = index;
    v->radiance = 0;
    float cos_out = e.delta_position ? 1.0f : fabs(v_dot(e.normal, e.direction));
    Vec3 beta = v_scale(e.radiance, cos_out / (v->pdf_fwd * e.pdf_direction));
    Vec3 origin = e.delta_position ? e.origin : offset_origin(e.origin, e.normal, e.direction);
    return random_walk(scene, stream, path, 1, most, origin, e.direction, beta, e.pdf_direction, 0, rays);
}

/* Strategy t = 1: light vertex s - 1 connected to the camera (the lens
 * point drawn from (u1, u2)). Returns its unweighted contribution and the
 * camera vertex in *sampled, with where it lands (*px, *py); 0 where the
 * camera does not see the vertex. */
KERNEL_FN Vec3 connect_to_camera(const Scene *scene, const PathVertex *qs, float u1, float u2, PathVertex *sampled,
                                 float *px, float *py, uint32_t *rays)
{
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
    CameraConnection c;
    if (!vertex_connectible(qs) || vertex_is_delta_light(scene, qs) ||
        !camera_connect(&scene->constants->camera, &scene->constants->filter, qs->surface.p, u1, u2, &c))
        return zero;
    sampled->type = VERTEX_CAMERA;
    sampled->surface.p = c.lens_point;
    sampled->surface.n = zero;
    sampled->surface.ns = zero;
    sampled->beta = v_scale(vec3(1.0f, 1.0f, 1.0f), c.importance / c.pdf);
    sampled->pdf_fwd = sampled->pdf_rev = 0.0f;
    sampled->delta = 0;
    sampled->light = -1;
    sampled->radiance = 1;
    Vec3 L;
    if (qs->type == VERTEX_LIGHT)
        L = v_scale(vertex_le(scene, qs, c.wi), fabs(v_dot(c.wi, qs->surface.n)));
    else
        L = v_scale(v_mul(qs->beta, vertex_f(qs, sampled)), fabs(v_dot(c.wi, qs->surface.ns)));
    if (qs->type == VERTEX_LIGHT)
        L = v_scale(L, 1.0f / qs->pdf_fwd);
    L = v_mul(L, sampled->beta);
    if (!(v_max_component(L) > 0.0f))
        return zero;
    ++*rays;
    if (!vertices_see(scene, qs, sampled))
        return zero;
    *px = c.px;
    *py = c.py;
    return L;
}

#endif
