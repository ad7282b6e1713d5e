/* Ray intersection with triangles, spheres and the BVH; shared by host
 * (tests, reference) and kernels. */
#ifndef KERNELS_INTERSECT_H
#define KERNELS_INTERSECT_H

#include "compat.h"
#include "scene_types.h"

#define BVH_STACK_SIZE 96

typedef struct {
    float origin[3];
    float direction[3];
} Ray;

typedef struct {
    float t; /* distance along the ray; t_max if no hit */
    int32_t primitive;
    float u, v; /* triangle barycentrics of b and c */
} Hit;

KERNEL_FN float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

KERNEL_FN void cross3(const float *a, const float *b, float *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Moller-Trumbore on a triangle stored as a vertex and two edges; hits in
 * (t_min, t_max) only. The barycentric tests run before the one division,
 * on values scaled by the determinant. */
KERNEL_FN int intersect_triangle(const Ray *ray, const GLOBAL Primitive *p, float t_min, float t_max, float *t_out,
                                 float *u_out, float *v_out)
{
    float e1[3], e2[3], s[3], pv[3], q[3];
    for (int i = 0; i < 3; ++i) {
        e1[i] = p->b[i];
        e2[i] = p->c[i];
        s[i] = ray->origin[i] - p->a[i];
    }
    cross3(ray->direction, e2, pv);
    float det = dot3(e1, pv);
    if (det == 0.0f)
        return 0;
    float sign = det < 0.0f ? -1.0f : 1.0f;
    det *= sign;
    float u = dot3(s, pv) * sign;
    if (u < 0.0f || u > det)
        return 0;
    cross3(s, e1, q);
    float v = dot3(ray->direction, q) * sign;
    if (v < 0.0f || u + v > det)
        return 0;
    float inv = 1.0f / det;
    float t = dot3(e2, q) * sign * inv;
    if (!(t > t_min && t < t_max))
        return 0;
    *t_out = t;
    *u_out = u * inv;
    *v_out = v * inv;
    return 1;
}

/* Nearest sphere hit in (t_min, t_max); solved relative to the centre for
 * precision. */
KERNEL_FN int intersect_sphere(const Ray *ray, const GLOBAL Primitive *p, float t_min, float t_max, float *t_out)
{
    float oc[3];
    for (int i = 0; i < 3; ++i)
        oc[i] = ray->origin[i] - p->a[i];
    float radius = p->b[0];
    float a = dot3(ray->direction, ray->direction);
    float half_b = dot3(oc, ray->direction);
    /* c - b^2/a computed as |oc - (oc.d/a) d|^2 (the squared distance from
     * the centre to the line), which does not cancel for far origins. */
    float k = half_b / a, perpendicular[3];
    for (int i = 0; i < 3; ++i)
        perpendicular[i] = oc[i] - k * ray->direction[i];
    float discriminant = radius * radius - dot3(perpendicular, perpendicular);
    if (discriminant < 0.0f)
        return 0;
    float root = sqrt(a * discriminant);
    float q = half_b < 0.0f ? -half_b + root : -half_b - root; /* -(b + sign(b) root) / 2 */
    float t0 = q / a, t1 = q != 0.0f ? (dot3(oc, oc) - radius * radius) / q : t0;
    float near_t = t0 < t1 ? t0 : t1, far_t = t0 < t1 ? t1 : t0;
    if (near_t > t_min && near_t < t_max) {
        *t_out = near_t;
        return 1;
    }
    if (far_t > t_min && far_t < t_max) {
        *t_out = far_t;
        return 1;
    }
    return 0;
}

/* Slab test against a node's box with the ray's reciprocal direction:
 * returns 1 and the entry distance if the ray meets the box before t_max. */
KERNEL_FN int intersect_box(const GLOBAL BvhNode *node, const float *origin, const float *inverse_direction,
                            float t_max, float *t_entry)
{
    float near_t = 0.0f, far_t = t_max;
    for (int i = 0; i < 3; ++i) {
        float t0 = (node->lower[i] - origin[i]) * inverse_direction[i];
        float t1 = (node->upper[i] - origin[i]) * inverse_direction[i];
        float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
        /* NaN (0 * inf on a slab plane) leaves the interval unchanged. */
        near_t = lo > near_t ? lo : near_t;
        far_t = hi < far_t ? hi : far_t;
    }
    *t_entry = near_t;
    return near_t <= far_t;
}

KERNEL_FN int intersect_primitive(const Ray *ray, const GLOBAL Primitive *p, float t_min, float t_max, Hit *hit)
{
    float t = 0.0f, u = 0.0f, v = 0.0f;
    int found = is_sphere(p) ? intersect_sphere(ray, p, t_min, t_max, &t)
                             : intersect_triangle(ray, p, t_min, t_max, &t, &u, &v);
    if (found) {
        hit->t = t;
        hit->u = u;
        hit->v = v;
    }
    return found;
}

/* Nearest hit in (t_min, t_max). With any_hit, returns at the first hit
 * (shadow rays). Returns 1 if something was hit. Children are tested from
 * their parent; the nearer one is visited first and the other is pushed
 * only if the ray meets it. */
KERNEL_FN int bvh_intersect(const GLOBAL BvhNode *nodes, const GLOBAL Primitive *primitives, const Ray *ray,
                            float t_min, float t_max, int any_hit, Hit *hit)
{
    float inverse_direction[3];
    for (int i = 0; i < 3; ++i)
        inverse_direction[i] = 1.0f / ray->direction[i];
    hit->t = t_max;
    hit->primitive = -1;
    hit->u = 0.0f;
    hit->v = 0.0f;
    int stack[BVH_STACK_SIZE];
    int top = 0;
    int node_index = 0;
    float entry = 0.0f;
    if (!intersect_box(nodes, ray->origin, inverse_direction, t_max, &entry))
        return 0;
    for (;;) {
        const GLOBAL BvhNode *node = nodes + node_index;
        if (node->count >= 0) { /* a leaf; 0 only in an empty scene */
            for (int i = node->first; i < node->first + node->count; ++i)
                if (intersect_primitive(ray, primitives + i, t_min, hit->t, hit)) {
                    hit->primitive = i;
                    if (any_hit)
                        return 1;
                }
        } else {
            int left = node_index + 1, right = node->first;
            float left_entry = 0.0f, right_entry = 0.0f;
            int hit_left = intersect_box(nodes + left, ray->origin, inverse_direction, hit->t, &left_entry);
            int hit_right = intersect_box(nodes + right, ray->origin, inverse_direction, hit->t, &right_entry);
            if (hit_left && hit_right) {
                int near_child = left_entry <= right_entry ? left : right;
                stack[top++] = near_child == left ? right : left; /* the builder bounds the depth */
                node_index = near_child;
                continue;
            }
            if (hit_left || hit_right) {
                node_index = hit_left ? left : right;
                continue;
            }
        }
        if (top == 0)
            break;
        node_index = stack[--top];
    }
    return hit->primitive >= 0;
}

#endif
