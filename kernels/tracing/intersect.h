/* Ray intersection with triangles, spheres and the BVH; shared by host
 * (tests, reference) and kernels. */
#ifndef KERNELS_INTERSECT_H
#define KERNELS_INTERSECT_H

#include "../common/compat.h"
#include "rng.h"
#include "scene_types.h"
#include "surface_uv.h"
#include "texture.h"

/* Traversal stack entries. The path tracer is built with what the
 * scene's BVH needs (-DBVH_STACK_SIZE from path_tracer_build_options); the
 * host, which traverses any tree, has room for the deepest the builder
 * makes (host/render/bvh.h checks the bound). */
#define BVH_STACK_LIMIT 1536
#ifndef BVH_STACK_SIZE
#define BVH_STACK_SIZE BVH_STACK_LIMIT
#endif
/* Called with the stack's height after each push; test_bvh watches it. */
#ifndef BVH_STACK_PUSHED
#define BVH_STACK_PUSHED(height) ((void)0)
#endif

typedef struct {
    float origin[3];
    float direction[3];
} Ray;

typedef struct {
    float t; /* distance along the ray; t_max if no hit */
    int32_t primitive;
    float u, v;       /* triangle barycentrics of b and c */
    int32_t instance; /* the instance the primitive was hit in, or -1: none */
} Hit;

/* What rays are traced against: the arrays of scene_types.h's list that
 * traversal reads. */
typedef struct {
    const GLOBAL BvhNode *nodes;
    const GLOBAL Primitive *primitives;
    const GLOBAL Instance *instances; /* FEATURE_INSTANCING */
    const GLOBAL AlphaSlot *alphas;   /* FEATURE_ALPHA */
    /* FEATURE_ALPHA_TEXTURE: the textures and surface uvs alpha textures read */
    const GLOBAL TextureNode *textures;
    const GLOBAL uint8_t *texture_bytes;
    const GLOBAL float *texture_floats;
    const GLOBAL float *surface_uvs;
} Geometry;

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

#ifdef __OPENCL_C_VERSION__
#define lowest_bit(x) (31 - (int)clz((x) & -(x)))

/* Bit i set where lane i of a vector comparison is true. */
KERNEL_FN int lane_bits(int8 mask)
{
    int8 bits = mask & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
    int4 four = bits.lo | bits.hi;
    int2 two = four.lo | four.hi;
    return two.x | two.y;
}

/* Narrows [near_t, far_t] to a slab's [t0, t1] (either order); NaN (0 * inf
 * on a slab plane) leaves it unchanged. */
KERNEL_FN void narrow_to_slab(float8 t0, float8 t1, float8 *near_t, float8 *far_t)
{
    float8 lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
    *near_t = lo > *near_t ? lo : *near_t;
    *far_t = hi < *far_t ? hi : *far_t;
}

/* Slab tests of a node's children with the ray's reciprocal direction: bit
 * i set if child i is met before t_max, its entry distance in entry[i]. */
KERNEL_FN int intersect_children(const GLOBAL BvhWideNode *node, const float *origin, const float *inverse_direction,
                                 float t_max, float *entry)
{
    /* Written out per axis: pocl leaves loops over arrays of vectors in memory. */
    float8 x0 = (vload8(0, node->lower[0]) - origin[0]) * inverse_direction[0];
    float8 x1 = (vload8(0, node->upper[0]) - origin[0]) * inverse_direction[0];
    float8 y0 = (vload8(0, node->lower[1]) - origin[1]) * inverse_direction[1];
    float8 y1 = (vload8(0, node->upper[1]) - origin[1]) * inverse_direction[1];
    float8 z0 = (vload8(0, node->lower[2]) - origin[2]) * inverse_direction[2];
    float8 z1 = (vload8(0, node->upper[2]) - origin[2]) * inverse_direction[2];
    float8 near_t = 0.0f, far_t = t_max;
    narrow_to_slab(x0, x1, &near_t, &far_t);
    narrow_to_slab(y0, y1, &near_t, &far_t);
    narrow_to_slab(z0, z1, &near_t, &far_t);
    vstore8(near_t, 0, entry);
    return lane_bits((near_t <= far_t) & (vload8(0, node->count) >= 0));
}

/* intersect_triangle on a packet's 8 triangles at once: the nearest hit's
 * lane (the first of equals, as a loop would find), or -1. */
KERNEL_FN int intersect_packet(const Ray *ray, const GLOBAL TrianglePacket *p, float t_min, float t_max, float *t_out,
                               float *u_out, float *v_out)
{
    float8 e1x = vload8(0, p->b[0]), e1y = vload8(0, p->b[1]), e1z = vload8(0, p->b[2]);
    float8 e2x = vload8(0, p->c[0]), e2y = vload8(0, p->c[1]), e2z = vload8(0, p->c[2]);
    float8 sx = ray->origin[0] - vload8(0, p->a[0]), sy = ray->origin[1] - vload8(0, p->a[1]),
           sz = ray->origin[2] - vload8(0, p->a[2]);
    float dx = ray->direction[0], dy = ray->direction[1], dz = ray->direction[2];
    float8 pvx = dy * e2z - dz * e2y, pvy = dz * e2x - dx * e2z, pvz = dx * e2y - dy * e2x;
    float8 det = e1x * pvx + e1y * pvy + e1z * pvz;
    float8 sign = det < 0.0f ? (float8)(-1.0f) : (float8)(1.0f);
    det *= sign;
    float8 u = (sx * pvx + sy * pvy + sz * pvz) * sign;
    float8 qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
    float8 v = (dx * qx + dy * qy + dz * qz) * sign;
    float8 inv = 1.0f / det;
    float8 t = (e2x * qx + e2y * qy + e2z * qz) * sign * inv;
    int8 hit = (det != 0.0f) & (u >= 0.0f) & (u <= det) & (v >= 0.0f) & (u + v <= det) & (t > t_min) & (t < t_max);
    if (!lane_bits(hit))
        return -1;
    float8 ts = hit ? t : (float8)(INFINITY);
    float4 m4 = fmin(ts.lo, ts.hi);
    float2 m2 = fmin(m4.lo, m4.hi);
    float nearest = fmin(m2.x, m2.y);
    int lane = lowest_bit(lane_bits(hit & (ts == nearest)));
    float lanes[8];
    *t_out = nearest;
    vstore8(u * inv, 0, lanes);
    *u_out = lanes[lane];
    vstore8(v * inv, 0, lanes);
    *v_out = lanes[lane];
    return lane;
}
#else
#define lowest_bit(x) __builtin_ctz((unsigned)(x))

/* Host versions of the above, one lane at a time, rounding as the scalar
 * tests do (test_bvh compares them with those bit for bit). */
KERNEL_FN int intersect_children(const BvhWideNode *node, const float *origin, const float *inverse_direction,
                                 float t_max, float *entry)
{
    int bits = 0;
    for (int j = 0; j < BVH_WIDTH; ++j) {
        float near_t = 0.0f, far_t = t_max;
        for (int i = 0; i < 3; ++i) {
            float t0 = (node->lower[i][j] - origin[i]) * inverse_direction[i];
            float t1 = (node->upper[i][j] - origin[i]) * inverse_direction[i];
            float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
            near_t = lo > near_t ? lo : near_t;
            far_t = hi < far_t ? hi : far_t;
        }
        entry[j] = near_t;
        bits |= (near_t <= far_t && node->count[j] >= 0) << j;
    }
    return bits;
}

KERNEL_FN int intersect_packet(const Ray *ray, const TrianglePacket *p, float t_min, float t_max, float *t_out,
                               float *u_out, float *v_out)
{
    int lane = -1;
    for (int j = 0; j < BVH_WIDTH; ++j) {
        Primitive triangle;
        for (int i = 0; i < 3; ++i) {
            triangle.a[i] = p->a[i][j];
            triangle.b[i] = p->b[i][j];
            triangle.c[i] = p->c[i][j];
        }
        if (intersect_triangle(ray, &triangle, t_min, t_max, t_out, u_out, v_out)) {
            t_max = *t_out;
            lane = j;
        }
    }
    return lane;
}
#endif

/* A world-space point in an instance's object space. */
KERNEL_FN void instance_point(const GLOBAL Instance *instance, const float *world, float *object)
{
    for (int r = 0; r < 3; ++r) {
        const GLOBAL float *m = instance->object_from_world[r];
        object[r] = m[0] * world[0] + m[1] * world[1] + m[2] * world[2] + m[3];
    }
}

/* The ray in an instance's object space. */
KERNEL_FN void instance_ray(const GLOBAL Instance *instance, const Ray *world, Ray *object)
{
    instance_point(instance, world->origin, object->origin);
    for (int r = 0; r < 3; ++r) {
        const GLOBAL float *m = instance->object_from_world[r];
        object->direction[r] = m[0] * world->direction[0] + m[1] * world->direction[1] + m[2] * world->direction[2];
    }
}

/* An object-space normal in world space (not unit): the transpose of
 * object_from_world is the inverse transpose of world_from_object. */
KERNEL_FN void instance_normal(const GLOBAL Instance *instance, const float *object, float *world)
{
    const GLOBAL float(*m)[4] = instance->object_from_world;
    for (int c = 0; c < 3; ++c)
        world[c] = m[0][c] * object[0] + m[1][c] * object[1] + m[2][c] * object[2];
}

/* A cut-out's alpha at a hit of `ray` (in the space of the tree
 * traversed: object space inside an instance) on primitive `primitive`:
 * its slot's constant, or its float texture at the hit's (u, v) and point
 * (FEATURE_ALPHA_TEXTURE). As in pbrt-v4, where the alpha texture sees the
 * shape's intersection before any ray differentials: no footprint (the
 * finest MIP level), the point and the geometric normal in the shape's own
 * space (so 3D textures of instanced shapes move with them). */
KERNEL_FN float alpha_at(const Geometry *geometry, const GLOBAL Primitive *p, int32_t primitive, const Ray *ray,
                         const Hit *hit)
{
    const GLOBAL AlphaSlot *slot = geometry->alphas + (p->kind >> PRIM_ALPHA_SHIFT);
#if GMON_HAS_ALPHA_TEXTURE
    if (slot->texture >= 0) {
        Vec3 o = vec3(ray->origin[0], ray->origin[1], ray->origin[2]);
        Vec3 d = vec3(ray->direction[0], ray->direction[1], ray->direction[2]);
        Vec3 at = v_add(o, v_scale(d, hit->t));
        SurfaceUv uv = surface_uv_at(geometry->surface_uvs, primitive, hit->u, hit->v, p, at);
        Vec3 n = v_normalize(is_sphere(p) ? v_sub(at, vec3_from_global(p->a))
                                          : v_cross(vec3_from_global(p->b), vec3_from_global(p->c)));
        TextureContext c = surface_texture_context(&uv, at, n, 0.0f);
        TextureArrays a;
        a.nodes = geometry->textures;
        a.bytes = geometry->texture_bytes;
        a.floats = geometry->texture_floats;
        return texture_evaluate_float(&a, slot->texture, &c);
    }
#else
    (void)primitive, (void)ray, (void)hit;
#endif
    return slot->value;
}

/* Uniform in [0, 1) from the world ray and the surface it met. */
KERNEL_FN float alpha_hash(const Ray *ray, int32_t primitive, int32_t instance)
{
    uint64_t h = rng_mix(((uint64_t)(uint32_t)primitive << 32 | (uint32_t)instance) ^ 0x9E3779B97F4A7C15ul);
    for (int i = 0; i < 3; ++i)
        h = rng_mix(h ^ ((uint64_t)float_bits(ray->origin[i]) << 32 | float_bits(ray->direction[i])));
    return (float)(uint32_t)(h >> 40) * (1.0f / 16777216.0f);
}

/* pbrt-v4's stochastic alpha (GeometricPrimitive::Intersect and
 * IntersectP): a hit on a cut-out of alpha a counts with probability a
 * (never for a <= 0, always for a >= 1), decided by a hash of the ray as
 * pbrt-v4 does. The hash also takes the surface, so that the decisions of
 * one ray at several cut-outs are independent, as pbrt-v4's are (it
 * re-spawns the ray past a skipped hit, which changes the hashed origin). */
KERNEL_FN int alpha_keeps_hit(const Geometry *geometry, const GLOBAL Primitive *p, const Ray *world_ray, const Ray *ray,
                              int32_t primitive, int32_t instance, const Hit *hit)
{
    float a = alpha_at(geometry, p, primitive, ray, hit);
    if (a >= 1.0f)
        return 1;
    return a > 0.0f && alpha_hash(world_ray, primitive, instance) <= a;
}

KERNEL_FN void inverse_direction_of(const Ray *ray, float *inverse_direction)
{
    for (int i = 0; i < 3; ++i)
        inverse_direction[i] = 1.0f / ray->direction[i];
}

/* Stack entries below 0 (FEATURE_INSTANCING): -1 returns to the world ray
 * from an instance's tree; -2 - i enters the instance of primitive i. */
#define STACK_LEAVE_INSTANCE (-1)

/* Nearest hit in (t_min, t_max). With any_hit, returns at the first hit
 * (shadow rays). Returns 1 if something was hit. A node's children are
 * tested together; those the ray meets are pushed nearest on top, and a
 * popped one is skipped if a hit nearer than its entry has been found.
 * An instance met in a leaf is pushed (at the leaf's entry distance); once
 * popped, its object's tree is traversed with the ray in object space, on
 * the same stack above an entry that brings the world ray back. */
KERNEL_FN int bvh_intersect(const Geometry *geometry, const Ray *world_ray, float t_min, float t_max, int any_hit,
                            Hit *hit)
{
    const GLOBAL BvhNode *nodes = geometry->nodes;
    const GLOBAL Primitive *primitives = geometry->primitives;
    const Ray *ray = world_ray; /* in the space of the tree being traversed */
#if GMON_HAS_INSTANCING
    Ray object_ray;
    int32_t instance = -1;
#else
    const int32_t instance = -1;
#endif
    float inverse_direction[3];
    inverse_direction_of(ray, inverse_direction);
    hit->t = t_max;
    hit->primitive = -1;
    hit->u = 0.0f;
    hit->v = 0.0f;
    hit->instance = -1;
    int stack[BVH_STACK_SIZE]; /* a child as its node's block * BVH_WIDTH + its lane */
    float stack_entry[BVH_STACK_SIZE];
    int top = 0;
    int node_index = 0;
    while (node_index >= 0) {
        float entry[BVH_WIDTH];
        int bits = intersect_children(&nodes[node_index].node, ray->origin, inverse_direction, hit->t, entry);
        for (int base = top; bits; bits &= bits - 1) { /* the stack holds what the tree needs (Bvh.stack_need) */
            int lane = lowest_bit(bits), i = top++;
            for (; i > base && stack_entry[i - 1] < entry[lane]; --i) {
                stack[i] = stack[i - 1];
                stack_entry[i] = stack_entry[i - 1];
            }
            stack[i] = node_index * BVH_WIDTH + lane;
            stack_entry[i] = entry[lane];
            BVH_STACK_PUSHED(top);
        }
        node_index = -1;
        while (top > 0 && node_index < 0) {
            --top;
            if (stack_entry[top] > hit->t)
                continue;
#if GMON_HAS_INSTANCING
            if (stack[top] < 0) {
                if (stack[top] == STACK_LEAVE_INSTANCE) {
                    ray = world_ray;
                    instance = -1;
                } else {
                    instance = primitives[-2 - stack[top]].material;
                    const GLOBAL Instance *entered = geometry->instances + instance;
                    instance_ray(entered, world_ray, &object_ray);
                    ray = &object_ray;
                    stack[top] = STACK_LEAVE_INSTANCE;
                    stack_entry[top++] = -INFINITY;
                    node_index = entered->root;
                }
                inverse_direction_of(ray, inverse_direction);
                continue;
            }
#endif
            const GLOBAL BvhWideNode *parent = &nodes[stack[top] / BVH_WIDTH].node;
            int lane = stack[top] % BVH_WIDTH, first = parent->child[lane], count = parent->count[lane];
            if (count == 0) {
                node_index = first;
                continue;
            }
            int found = 0;
            if (parent->packet[lane] >= 0) {
                float t = 0.0f, u = 0.0f, v = 0.0f;
                int k = intersect_packet(ray, &nodes[parent->packet[lane]].triangles, t_min, hit->t, &t, &u, &v);
                if (k >= 0) {
                    hit->t = t;
                    hit->u = u;
                    hit->v = v;
                    hit->primitive = first + k;
                    hit->instance = instance;
                    found = 1;
                }
            } else {
#if GMON_HAS_INSTANCING
                float leaf_entry = stack_entry[top];
#endif
                for (int i = first; i < first + count; ++i) {
                    const GLOBAL Primitive *p = primitives + i;
#if GMON_HAS_INSTANCING
                    if ((p->kind & PRIM_KIND_MASK) == PRIM_INSTANCE) {
                        stack[top] = -2 - i;
                        stack_entry[top++] = leaf_entry;
                        BVH_STACK_PUSHED(top);
                        continue;
                    }
#endif
#if GMON_HAS_ALPHA
                    Hit candidate;
                    if (!intersect_primitive(ray, p, t_min, hit->t, &candidate) ||
                        ((p->kind & PRIM_ALPHA) &&
                         !alpha_keeps_hit(geometry, p, world_ray, ray, i, instance, &candidate)))
                        continue;
                    hit->t = candidate.t;
                    hit->u = candidate.u;
                    hit->v = candidate.v;
#else
                    if (!intersect_primitive(ray, p, t_min, hit->t, hit))
                        continue;
#endif
                    hit->primitive = i;
                    hit->instance = instance;
                    found = 1;
                }
            }
            if (found && any_hit)
                return 1;
        }
    }
    return hit->primitive >= 0;
}

#endif
