/* Area lights: emitting spheres and triangles, sampled by the solid angle
 * they subtend where that is precise, else by area; and the density of
 * reaching one by a BSDF sample, for MIS. */
#ifndef KERNELS_LIGHT_AREA_H
#define KERNELS_LIGHT_AREA_H

#include "bsdf.h"
#include "light_common.h"

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

KERNEL_FN int area_light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2,
                                LightSample *s)
{
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

/* The density area_light_emission gives direction w leaving at normal n:
 * cosine-weighted over the side it leaves by (half for each side of a
 * two-sided light). */
KERNEL_FN float area_light_pdf_direction(GLOBAL const Light *light, Vec3 n, Vec3 w)
{
    float cos_theta = v_dot(n, w);
    if (!light->two_sided)
        return cos_theta > 0.0f ? cos_theta / PI_F : 0.0f;
    return 0.5f * fabs(cos_theta) / PI_F;
}

/* A ray leaving an area light: a point uniform over its area, a
 * cosine-weighted direction (as pbrt-v4's DiffuseAreaLight::SampleLe;
 * a two-sided light picks its side with u3). */
KERNEL_FN int area_light_emission(const Scene *scene, GLOBAL const Light *light, float u1, float u2, float u3, float u4,
                                  LightEmission *e)
{
    GLOBAL const Primitive *prim = scene->primitives + light->primitive;
    e->origin = sample_primitive(prim, u1, u2);
    e->normal = surface_normal(prim, e->origin);
    float side = 1.0f;
    if (light->two_sided) {
        side = u3 < 0.5f ? 1.0f : -1.0f;
        u3 = u3 < 0.5f ? 2.0f * u3 : 2.0f * u3 - 1.0f;
    }
    Vec3 w = cosine_hemisphere(fmin(u3, 0x1.fffffep-1f), u4), s, t, n = v_scale(e->normal, side);
    v_basis(n, &s, &t);
    e->direction = v_normalize(v_add(v_add(v_scale(s, w.x), v_scale(t, w.y)), v_scale(n, w.z)));
    e->radiance = vec3_from_global(light->radiance);
    e->pdf_position = 1.0f / light->area;
    e->pdf_direction = area_light_pdf_direction(light, e->normal, e->direction);
    e->delta_position = 0;
    return e->pdf_direction > 0.0f;
}

#endif
