/* The path tracer's view of the scene: the constants and the typed arrays
 * of scene_types.h's list, and the geometric queries on them. */
#ifndef KERNELS_SCENE_H
#define KERNELS_SCENE_H

#include "feature_mask.h"
#include "intersect.h"
#include "scene_types.h"
#include "../common/vec3.h"

#define SCENE_ARRAY_MEMBER(name, type) GLOBAL const type *name;
typedef struct {
    GLOBAL const SceneConstants *constants;
    GMON_SCENE_ARRAYS(SCENE_ARRAY_MEMBER)
} Scene;
#undef SCENE_ARRAY_MEMBER

/* The kernel parameters for the list, each followed by a comma. */
#define SCENE_ARRAY_PARAMETER(name, type) GLOBAL const type *name,
#define SCENE_ARRAY_ASSIGN(name, type) scene.name = name;

KERNEL_FN Geometry scene_geometry(const Scene *scene)
{
    Geometry g = {scene->nodes,    scene->primitives,    scene->instances,      scene->alphas,
                  scene->textures, scene->texture_bytes, scene->texture_floats, scene->surface_uvs};
    return g;
}

KERNEL_FN int scene_intersect(const Scene *scene, const Ray *ray, float t_min, float t_max, int any_hit, Hit *hit)
{
    Geometry g = scene_geometry(scene);
    return bvh_intersect(&g, ray, t_min, t_max, any_hit, hit);
}

KERNEL_FN Vec3 surface_normal(GLOBAL const Primitive *p, Vec3 position)
{
    Vec3 n;
    if (is_sphere(p))
        n = v_normalize(v_sub(position, vec3_from_global(p->a)));
    else
        n = v_normalize(v_cross(vec3_from_global(p->b), vec3_from_global(p->c)));
    return (p->kind & PRIM_FLIP_NORMAL) ? v_scale(n, -1.0f) : n;
}

#if GMON_HAS_INSTANCING
KERNEL_FN Vec3 instance_normal_v(GLOBAL const Instance *instance, Vec3 n)
{
    float object[3] = {n.x, n.y, n.z}, world[3];
    instance_normal(instance, object, world);
    return vec3(world[0], world[1], world[2]);
}
#endif

/* The geometric normal (unit, world space) at a hit at `position`. In an
 * instance, the object-space normal before its normalization is taken to
 * world space and normalized there: for the transforms float arithmetic
 * does exactly (power-of-two scales, axis swaps, mirrors) it is then the
 * very normal of the flattened triangle. (pbrt-v4's rule on handedness
 * holds without a flag: the transformed cross product turns with it.) */
KERNEL_FN Vec3 hit_normal(const Scene *scene, const Hit *hit, GLOBAL const Primitive *p, Vec3 position)
{
#if GMON_HAS_INSTANCING
    if (hit->instance >= 0) {
        GLOBAL const Instance *instance = scene->instances + hit->instance;
        Vec3 n;
        if (is_sphere(p)) {
            float world[3] = {position.x, position.y, position.z}, object[3];
            instance_point(instance, world, object);
            n = v_sub(vec3(object[0], object[1], object[2]), vec3_from_global(p->a));
        } else {
            n = v_cross(vec3_from_global(p->b), vec3_from_global(p->c));
        }
        n = v_normalize(instance_normal_v(instance, n));
        return (p->kind & PRIM_FLIP_NORMAL) ? v_scale(n, -1.0f) : n;
    }
#else
    (void)scene, (void)hit;
#endif
    return surface_normal(p, position);
}

/* The shading normal at a hit: a triangle's vertex normals interpolated
 * at the hit's barycentrics, turned to the side of the geometric normal n
 * (pbrt-v4 turns the geometric one; the two agree on which side is the
 * front, as the scene reader orients meshes by their vertex normals), or n. */
KERNEL_FN Vec3 shading_normal(const Scene *scene, const Hit *hit, GLOBAL const Primitive *p, Vec3 n)
{
    if (!GMON_HAS_SHADING_NORMALS || !(p->kind & PRIM_SHADING_NORMAL))
        return n;
    GLOBAL const float *v = scene->shading_normals + 9 * (size_t)hit->primitive;
    float b0 = 1.0f - hit->u - hit->v;
    Vec3 ns = vec3(b0 * v[0] + hit->u * v[3] + hit->v * v[6], b0 * v[1] + hit->u * v[4] + hit->v * v[7],
                   b0 * v[2] + hit->u * v[5] + hit->v * v[8]);
#if GMON_HAS_INSTANCING
    if (hit->instance >= 0)
        ns = instance_normal_v(scene->instances + hit->instance, ns);
#endif
    float length2 = v_dot(ns, ns);
    if (!(length2 > 0.0f))
        return n;
    ns = v_scale(ns, 1.0f / sqrt(length2));
    return v_dot(ns, n) < 0.0f ? v_scale(ns, -1.0f) : ns;
}

/* A point uniformly distributed over a primitive's area. */
KERNEL_FN Vec3 sample_primitive(GLOBAL const Primitive *p, float u1, float u2)
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
    return scene_intersect(scene, &ray, 0.0f, distance, 1, &hit);
}

#endif
