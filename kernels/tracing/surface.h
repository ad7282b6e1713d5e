/* The surface a ray hit, as the integrators see it (path_tracer.cl,
 * bdpt.cl): its point, geometric and shading normals with the shading
 * frame, and its material resolved at the hit (a mix's choice, textures). */
#ifndef KERNELS_SURFACE_H
#define KERNELS_SURFACE_H

#include "bsdf.h"
#include "scene.h"
/* Textures are the kernels' alone (surface_textures.h): host tests see
 * untextured materials. */
#if GMON_HAS_TEXTURES && defined(__OPENCL_C_VERSION__)
#define SURFACE_TEXTURES 1
#include "surface_textures.h"
#else
#define SURFACE_TEXTURES 0
#endif

typedef struct {
    Vec3 p, n;     /* the point, the geometric normal */
    Vec3 ns, s, t; /* the shading frame */
    Material material;
} Surface;

/* The point and geometric normal of `hit` on the ray from origin along
 * unit direction (enough to add an emitter's light). */
KERNEL_FN void surface_point(const Scene *scene, const Hit *hit, Vec3 origin, Vec3 direction, Surface *surface)
{
    GLOBAL const Primitive *prim = scene->primitives + hit->primitive;
    surface->p = v_add(origin, v_scale(direction, hit->t));
    surface->n = hit_normal(scene, hit, prim, surface->p);
}

/* The rest of the surface after surface_point: its shading normal and
 * frame, its material resolved at the hit (a mix's choice, textures);
 * cone_width: the ray cone's width there (texture filtering). */
KERNEL_FN void surface_shade(const Scene *scene, const Hit *hit, Vec3 direction, float cone_width, Surface *surface)
{
    GLOBAL const Primitive *prim = scene->primitives + hit->primitive;
    Vec3 p = surface->p, n = surface->n;
    Vec3 wo_world = v_scale(direction, -1.0f);
    /* The BSDF's frame is the shading normal's; rays leave by the
     * geometric one. */
    Vec3 ns = shading_normal(scene, hit, prim, n);
    GLOBAL const Material *stored = scene->materials + prim->material;
#if SURFACE_TEXTURES
    float footprint = cone_width / fmax(fabs(v_dot(n, direction)), 0.01f);
    int textured = (scene->constants->integrator.flags & RENDER_TEXTURES) != 0;
    /* A mix's textured amount is the texture's at this hit. */
    if (GMON_HAS_MIX && textured)
        stored = mix_resolve_at_hit(scene, stored, hit, prim, p, wo_world, ns, footprint);
#else
    const int textured = 0;
    (void)cone_width;
#endif
    if (GMON_HAS_MIX ? !textured : 0) /* not &&: textured may be the constant 0 */
        stored = mix_resolve(scene->materials, stored, p, wo_world);
    /* A private copy: textures give some of its parameters. */
    surface->material = *stored;
#if SURFACE_TEXTURES
    if (textured)
        material_apply_textures(scene, (int)(stored - scene->materials), hit, prim, p, footprint, &surface->material,
                                &ns);
#endif
    surface->ns = ns;
    v_basis(ns, &surface->s, &surface->t);
}

/* surface_point and surface_shade. */
KERNEL_FN void surface_at_hit(const Scene *scene, const Hit *hit, Vec3 origin, Vec3 direction, float cone_width,
                              Surface *surface)
{
    surface_point(scene, hit, origin, direction, surface);
    surface_shade(scene, hit, direction, cone_width, surface);
}

KERNEL_FN Vec3 surface_to_local(const Surface *surface, Vec3 w)
{
    return vec3(v_dot(w, surface->s), v_dot(w, surface->t), v_dot(w, surface->ns));
}

KERNEL_FN Vec3 surface_to_world(const Surface *surface, Vec3 w)
{
    return v_normalize(v_add(v_add(v_scale(surface->s, w.x), v_scale(surface->t, w.y)), v_scale(surface->ns, w.z)));
}

/* pbrt-v4's correction of shading normals for importance transport: the
 * adjoint BSDF with shading normals is f |wo.ns| |wi.n| / (|wo.n| |wi.ns|)
 * (Veach's thesis, 5.3); 1 for radiance, and without shading normals. */
KERNEL_FN float shading_correction(const Surface *surface, Vec3 wo, Vec3 wi, int radiance)
{
    if (!GMON_HAS_SHADING_NORMALS)
        return 1.0f;
    if (radiance)
        return 1.0f;
    float denominator = fabs(v_dot(wo, surface->n)) * fabs(v_dot(wi, surface->ns));
    return denominator > 0.0f ? fabs(v_dot(wo, surface->ns)) * fabs(v_dot(wi, surface->n)) / denominator : 0.0f;
}

#endif
