/* Lights: for each type, sampling a direction toward it from a point
 * (light_sample), the radiance a ray escaping the scene receives from the
 * infinite ones (infinite_radiance) and their densities, for MIS. Types a
 * scene does not use are compiled out (feature_mask.h). The light to sample
 * is picked by the light sampler (pick_light_at): with a fixed chance each
 * (uniform or by power, computed by the host, host/render/render_scene.c),
 * or by the light tree (light_tree.h). */
#ifndef KERNELS_LIGHTS_H
#define KERNELS_LIGHTS_H

#include "distribution.h"
#include "equal_area.h"
#include "light_tree.h"
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
KERNEL_FN int pick_light(GLOBAL const Light *lights, uint32_t count, float u)
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

/* With the light tree, as pbrt-v4's "bvh" sampler: the tree (if there are
 * bounded lights) and each unbounded light have equal chances. */
KERNEL_FN float light_tree_share(const Scene *scene)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    return integrator->light_count > integrator->unbounded_lights ? 1.0f / (float)(integrator->unbounded_lights + 1u)
                                                                  : 0.0f;
}

/* The light to sample for shading point p of geometric normal n, and the
 * chance it was picked (*pmf); -1 if none may light p. */
KERNEL_FN int pick_light_at(const Scene *scene, Vec3 p, Vec3 n, float u, float *pmf)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    if (integrator->light_sampler != LIGHT_SAMPLER_TREE) {
        int i = pick_light(scene->lights, integrator->light_count, u);
        *pmf = scene->lights[i].pick_probability;
        return i;
    }
    float share = light_tree_share(scene);
    if (u < share) {
        int i = light_tree_sample(scene->light_nodes, p, n, fmin(u / share, 0x1.fffffep-1f), pmf);
        *pmf *= share;
        return i;
    }
    uint32_t unbounded = integrator->unbounded_lights;
    uint32_t i = (uint32_t)((u - share) / (1.0f - share) * (float)unbounded);
    i = i < unbounded ? i : unbounded - 1u;
    *pmf = scene->lights[i].pick_probability;
    return (int)i;
}

/* The chance pick_light_at picks `light` for shading point p of normal n. */
KERNEL_FN float light_pick_pmf(const Scene *scene, GLOBAL const Light *light, Vec3 p, Vec3 n)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    uint32_t index = (uint32_t)(light - scene->lights);
    if (integrator->light_sampler != LIGHT_SAMPLER_TREE || index < integrator->unbounded_lights)
        return light->pick_probability;
    return light_tree_share(scene) *
           light_tree_pmf(scene->light_nodes, scene->light_trails[index - integrator->unbounded_lights], p, n);
}

KERNEL_FN Vec3 rotate_rows(const GLOBAL float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[0][1] * w.y + rows[0][2] * w.z,
                rows[1][0] * w.x + rows[1][1] * w.y + rows[1][2] * w.z,
                rows[2][0] * w.x + rows[2][1] * w.y + rows[2][2] * w.z);
}

KERNEL_FN Vec3 rotate_columns(const GLOBAL float (*rows)[3], Vec3 w)
{
    return vec3(rows[0][0] * w.x + rows[1][0] * w.y + rows[2][0] * w.z,
                rows[0][1] * w.x + rows[1][1] * w.y + rows[2][1] * w.z,
                rows[0][2] * w.x + rows[1][2] * w.y + rows[2][2] * w.z);
}

KERNEL_FN uint32_t image_texel(GLOBAL const Light *light, float u, float v)
{
    /* Not OpenCL's min: this header also builds as host C (the tests). */
    uint32_t x = (uint32_t)(u * (float)light->image_width), y = (uint32_t)(v * (float)light->image_height);
    x = x < light->image_width ? x : light->image_width - 1u;
    y = y < light->image_height ? y : light->image_height - 1u;
    return y * light->image_width + x;
}

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

/* Sphere lights are sampled by the cone of directions they subtend from p
 * (as pbrt-v4's Sphere::Sample(ctx, u)): every sample then reaches the near
 * side, where sampling by area wastes half of them on the far side and is
 * very noisy close to a small sphere. Returns sin^2 of the cone's
 * half-angle, or 0 where p is inside the sphere or on it (the margin keeps
 * points of its own surface out of the cone's degenerate limit), which is
 * sampled by area. light_sample and area_light_pdf both decide by it, so
 * their densities agree. */
KERNEL_FN float sphere_cone_sin2(Vec3 centre, float radius, Vec3 p)
{
    Vec3 to_centre = v_sub(centre, p);
    float distance2 = v_dot(to_centre, to_centre), radius2 = radius * radius;
    return distance2 > 1.0001f * radius2 ? radius2 / distance2 : 0.0f;
}

/* 1 - cos(theta) from sin^2(theta) = sin2, theta <= pi / 2. Written as
 * sin2 / (1 + cos) it has no cancellation on narrow cones, where pbrt-v4
 * switches to the Taylor expansion sin2 / 2 (the same to first order). */
KERNEL_FN float one_minus_cos_from_sin2(float sin2)
{
    return sin2 / (1.0f + sqrt_float(fmax(0.0f, 1.0f - sin2)));
}

/* Cone sampling's density in solid angle: uniform over the cone. */
KERNEL_FN float sphere_cone_pdf(float sin2_max)
{
    return 1.0f / (2.0f * PI_F * one_minus_cos_from_sin2(sin2_max));
}

/* The outward unit normal at the point of the sphere (centre, seen from p
 * with sin^2 of the cone's half-angle sin2_max > 0) that the direction
 * uniform in the cone for (u1, u2) reaches first; the point is centre +
 * radius * normal. As pbrt-v4 does, the point comes from its angle alpha
 * at the centre (from the axis toward p), not from intersecting a ray,
 * so it lies on the sphere, on the near side, even for a tiny cone. */
KERNEL_FN Vec3 sphere_cone_sample(Vec3 centre, Vec3 p, float sin2_max, float u1, float u2)
{
    Vec3 axis = v_normalize(v_sub(centre, p)), s, t;
    v_basis(axis, &s, &t);
    /* 1 - cos(theta) uniform in [0, 1 - cos(theta_max)]: uniform in solid angle. */
    float one_minus_cos = u1 * one_minus_cos_from_sin2(sin2_max);
    float cos_theta = 1.0f - one_minus_cos, sin2 = one_minus_cos * (2.0f - one_minus_cos);
    /* (sin(theta) / sin(theta_max))^2: 1 on the silhouette. */
    float ratio = fmin(sin2 / sin2_max, 1.0f);
    float sin_max = sqrt_float(sin2_max), root = sqrt_float(1.0f - ratio);
    /* Both sums of non-negative terms, precise at either end of the cone
     * (sqrt(1 - cos^2) would not be near the axis): cos(alpha) is pbrt-v4's;
     * sin(alpha) = sin(theta) s / radius by the law of sines, with the
     * distance s to the near hit in its cancellation-free form
     * (d^2 - radius^2) / (d cos(theta) + sqrt(radius^2 - d^2 sin^2(theta))). */
    float cos_alpha = sin2 / sin_max + cos_theta * root;
    float sin_alpha = sqrt_float(ratio) * (1.0f - sin2_max) / (cos_theta + sin_max * root);
    float phi = 2.0f * PI_F * u2;
    Vec3 across = v_add(v_scale(s, cos_float(phi)), v_scale(t, sin_float(phi)));
    return v_normalize(v_add(v_scale(axis, -cos_alpha), v_scale(across, sin_alpha)));
}

/* Triangle lights are sampled uniformly in the solid angle they subtend
 * from p (Arvo 1995, as pbrt-v4's SampleSphericalTriangle) where it lies in
 * pbrt-v4's range (a smaller spherical triangle loses too much to float
 * rounding, its area being a difference of angles near pi; a larger one,
 * near a hemisphere, is better sampled by area) and, unlike pbrt-v4, only
 * where the triangle is close: area > SPHERICAL_TRIANGLE_MIN_CLOSENESS
 * times the squared distance to its centroid. Farther, the two samplers
 * differ little (the Cornell box's image had the same variance) and the
 * spherical one made the render 55% slower. */
#define SPHERICAL_TRIANGLE_MIN_SOLID_ANGLE 3e-4f
#define SPHERICAL_TRIANGLE_MAX_SOLID_ANGLE 6.22f
#define SPHERICAL_TRIANGLE_MIN_CLOSENESS 0.1f

/* The angle between unit vectors, precise near 0 and pi (unlike acos of
 * their dot product). */
KERNEL_FN float angle_between(Vec3 a, Vec3 b)
{
    if (v_dot(a, b) < 0.0f)
        return PI_F - 2.0f * asin(fmin(0.5f * v_length(v_add(a, b)), 1.0f));
    return 2.0f * asin(fmin(0.5f * v_length(v_sub(b, a)), 1.0f));
}

/* The solid angle the spherical triangle of unit vectors a, b, c covers
 * (Van Oosterom and Strackee 1983). */
KERNEL_FN float spherical_triangle_area(Vec3 a, Vec3 b, Vec3 c)
{
    return fabs(2.0f * atan2(v_dot(a, v_cross(b, c)), 1.0f + v_dot(a, b) + v_dot(a, c) + v_dot(b, c)));
}

/* The solid angle triangle `prim` (of area `area`) subtends from p when
 * light_sample samples it by solid angle, with the unit directions toward
 * its vertices in dirs; else 0 (sampled by area: also where p lies in its
 * plane, or on a vertex; dirs then unset). light_sample and area_light_pdf
 * both decide by it. */
KERNEL_FN float triangle_sampled_solid_angle(GLOBAL const Primitive *prim, float area, Vec3 p, Vec3 *dirs)
{
    Vec3 v0 = vec3_from_global(prim->a);
    Vec3 centroid = v_add(v0, v_scale(v_add(vec3_from_global(prim->b), vec3_from_global(prim->c)), 1.0f / 3.0f));
    Vec3 to_centroid = v_sub(centroid, p);
    if (!(area > SPHERICAL_TRIANGLE_MIN_CLOSENESS * v_dot(to_centroid, to_centroid)))
        return 0.0f;
    dirs[0] = v_normalize(v_sub(v0, p));
    dirs[1] = v_normalize(v_sub(v_add(v0, vec3_from_global(prim->b)), p));
    dirs[2] = v_normalize(v_sub(v_add(v0, vec3_from_global(prim->c)), p));
    float solid_angle = spherical_triangle_area(dirs[0], dirs[1], dirs[2]);
    /* NaN (a vertex at p) fails the test too. */
    return solid_angle >= SPHERICAL_TRIANGLE_MIN_SOLID_ANGLE && solid_angle <= SPHERICAL_TRIANGLE_MAX_SOLID_ANGLE
               ? solid_angle
               : 0.0f;
}

/* v less its component along unit u, normalized. */
KERNEL_FN Vec3 orthogonal_part(Vec3 v, Vec3 u)
{
    return v_normalize(v_sub(v, v_scale(u, v_dot(v, u))));
}

/* A direction uniform in the spherical triangle of unit vectors a, b, c
 * (Arvo 1995, in pbrt-v4's form): u1 picks the sub-triangle (a, b, c') of
 * area u1 times the whole, with c' on the arc from a to c, and u2 a point on
 * the arc from b to c' by its cosine. Returns 0 for a degenerate one. */
KERNEL_FN int sample_spherical_triangle(Vec3 a, Vec3 b, Vec3 c, float u1, float u2, Vec3 *w)
{
    Vec3 n_ab = v_cross(a, b), n_bc = v_cross(b, c), n_ca = v_cross(c, a);
    if (v_dot(n_ab, n_ab) == 0.0f || v_dot(n_bc, n_bc) == 0.0f || v_dot(n_ca, n_ca) == 0.0f)
        return 0;
    n_ab = v_normalize(n_ab);
    n_bc = v_normalize(n_bc);
    n_ca = v_normalize(n_ca);
    /* The angles at the vertices, between the planes of the edges. */
    float alpha = angle_between(n_ab, v_scale(n_ca, -1.0f));
    float beta = angle_between(n_bc, v_scale(n_ab, -1.0f));
    float gamma = angle_between(n_ca, v_scale(n_bc, -1.0f));
    float area_plus_pi = alpha + beta + gamma;
    if (!(area_plus_pi > PI_F))
        return 0;
    /* The sub-triangle's area plus pi, and its angle phi = that - alpha. */
    float sub_area_plus_pi = PI_F + u1 * (area_plus_pi - PI_F);
    float cos_alpha = cos_float(alpha), sin_alpha = sin_float(alpha);
    float sin_sub = sin_float(sub_area_plus_pi), cos_sub = cos_float(sub_area_plus_pi);
    float sin_phi = sin_sub * cos_alpha - cos_sub * sin_alpha;
    float cos_phi = cos_sub * cos_alpha + sin_sub * sin_alpha;
    float k1 = cos_phi + cos_alpha, k2 = sin_phi - sin_alpha * v_dot(a, b);
    /* The cosine of the arc from a to c'. */
    float cos_arc = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    cos_arc = fmin(fmax(cos_arc, -1.0f), 1.0f);
    float sin_arc = sqrt_float(fmax(0.0f, 1.0f - cos_arc * cos_arc));
    Vec3 c_sub = v_add(v_scale(a, cos_arc), v_scale(orthogonal_part(c, a), sin_arc));
    float cos_theta = 1.0f - u2 * (1.0f - v_dot(c_sub, b));
    float sin_theta = sqrt_float(fmax(0.0f, 1.0f - cos_theta * cos_theta));
    *w = v_normalize(v_add(v_scale(b, cos_theta), v_scale(orthogonal_part(c_sub, b), sin_theta)));
    return 1;
}

/* Where the ray from p along w meets triangle `prim`'s plane, clamped into
 * the triangle (rounding can leave a direction of its spherical triangle
 * just outside). */
KERNEL_FN Vec3 triangle_point_along(GLOBAL const Primitive *prim, Vec3 p, Vec3 w)
{
    Vec3 v0 = vec3_from_global(prim->a), e1 = vec3_from_global(prim->b), e2 = vec3_from_global(prim->c);
    Vec3 s1 = v_cross(w, e2), s = v_sub(p, v0);
    float divisor = v_dot(s1, e1);
    float b1 = 1.0f / 3.0f, b2 = 1.0f / 3.0f;
    if (divisor != 0.0f) {
        b1 = fmin(fmax(v_dot(s, s1) / divisor, 0.0f), 1.0f);
        b2 = fmin(fmax(v_dot(w, v_cross(s, e1)) / divisor, 0.0f), 1.0f);
        if (b1 + b2 > 1.0f) {
            float sum = b1 + b2;
            b1 /= sum;
            b2 /= sum;
        }
    }
    return v_add(v0, v_add(v_scale(e1, b1), v_scale(e2, b2)));
}

/* Samples light `light` from point p with normal n. Returns 0 when it
 * cannot light p. */
KERNEL_FN int light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2, LightSample *s)
{
    s->is_delta = 0;
    s->distance = INFINITY;
    uint32_t type = light->type;
    /* | rather than ||: a feature left out folds its term to a constant,
     * which a logical operator's right side would be warned about. */
    int point_like = (GMON_HAS_POINT_LIGHTS && type == LIGHT_POINT) | (GMON_HAS_SPOT_LIGHTS && type == LIGHT_SPOT) |
                     (GMON_HAS_GONIOMETRIC_LIGHTS && type == LIGHT_GONIOMETRIC) |
                     (GMON_HAS_PROJECTION_LIGHTS && type == LIGHT_PROJECTION);
    if (point_like) {
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
    if (!GMON_HAS_AREA_LIGHTS)
        return 0;
    GLOBAL const Primitive *prim = scene->primitives + light->primitive;
    float sin2_max = 0.0f, solid_angle = 0.0f;
    Vec3 q, nq, dirs[3], w;
    if (is_sphere(prim))
        sin2_max = sphere_cone_sin2(vec3_from_global(prim->a), prim->b[0], p);
    else
        solid_angle = triangle_sampled_solid_angle(prim, light->area, p, dirs);
    if (sin2_max > 0.0f) {
        Vec3 outward = sphere_cone_sample(vec3_from_global(prim->a), p, sin2_max, u1, u2);
        q = v_add(vec3_from_global(prim->a), v_scale(outward, prim->b[0]));
        nq = (prim->kind & PRIM_FLIP_NORMAL) ? v_scale(outward, -1.0f) : outward;
    } else if (solid_angle > 0.0f) {
        if (!sample_spherical_triangle(dirs[0], dirs[1], dirs[2], u1, u2, &w))
            return 0;
        q = triangle_point_along(prim, p, w);
        nq = surface_normal(prim, q);
    } else {
        q = sample_primitive(prim, u1, u2);
        nq = surface_normal(prim, q);
    }
    Vec3 to_light = v_sub(q, p);
    float distance2 = v_dot(to_light, to_light);
    if (distance2 == 0.0f)
        return 0;
    s->distance = sqrt(distance2);
    s->wi = v_scale(to_light, 1.0f / s->distance);
    float cos_light = v_dot(nq, s->wi); /* < 0: the light's front faces p */
    s->radiance = vec3_from_global(light->radiance);
    if (sin2_max > 0.0f || solid_angle > 0.0f) {
        /* The density does not depend on cos_light here; a one-sided light
         * gives nothing where `emitted` (path_tracer.cl) would not. */
        s->pdf = sin2_max > 0.0f ? sphere_cone_pdf(sin2_max) : 1.0f / solid_angle;
        return light->two_sided || cos_light < 0.0f;
    }
    if (cos_light == 0.0f || (!light->two_sided && cos_light > 0.0f))
        return 0;
    s->pdf = distance2 / (fabs(cos_light) * light->area);
    return 1;
}

/* The density (solid angle) with which light_sample from point `from`
 * reaches area light `light`, without the pick, at a hit at distance t and
 * cosine cos_light (> 0) with its normal. */
KERNEL_FN float area_light_pdf(const Scene *scene, GLOBAL const Light *light, Vec3 from, float t, float cos_light)
{
    if (!(cos_light > 0.0f))
        return 0.0f;
    GLOBAL const Primitive *prim = scene->primitives + light->primitive;
    if (is_sphere(prim)) {
        float sin2_max = sphere_cone_sin2(vec3_from_global(prim->a), prim->b[0], from);
        if (sin2_max > 0.0f)
            return sphere_cone_pdf(sin2_max);
    } else {
        Vec3 dirs[3];
        float solid_angle = triangle_sampled_solid_angle(prim, light->area, from, dirs);
        if (solid_angle > 0.0f)
            return 1.0f / solid_angle;
    }
    return t * t / (cos_light * light->area);
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
