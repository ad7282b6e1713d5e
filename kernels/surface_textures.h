/* Textures at a ray's hit: the surface's (u, v) and tangents
 * (surface_uv.h), the texture context, a material's textured parameters,
 * and bump and normal mapping of the shading normal (pbrt-v4's BumpMap and
 * NormalMap). Compiled only into builds with textures. */
#ifndef KERNELS_SURFACE_TEXTURES_H
#define KERNELS_SURFACE_TEXTURES_H

#include "bsdf.h"
#include "scene.h"
#include "surface_uv.h"
#include "texture.h"

KERNEL_FN TextureArrays scene_texture_arrays(const Scene *scene)
{
    TextureArrays a;
    a.nodes = scene->textures;
    a.bytes = scene->texture_bytes;
    a.floats = scene->texture_floats;
    return a;
}

/* The surface's (u, v) at world point p of a hit. */
KERNEL_FN SurfaceUv surface_uv(const Scene *scene, const Hit *hit, __global const Primitive *prim, Vec3 p)
{
    return surface_uv_at(scene->surface_uvs, hit->primitive, hit->u, hit->v, prim, p);
}

/* The texture context at a hit: footprint is the ray's footprint width
 * across the surface there (world units). */
KERNEL_FN TextureContext surface_texture_context(const SurfaceUv *uv, Vec3 p, Vec3 ns, float footprint)
{
    TextureContext c;
    c.p = p;
    c.n = ns;
    c.u = uv->u;
    c.v = uv->v;
    c.footprint = footprint;
    c.uv_density = uv->density;
    return c;
}

KERNEL_FN float roughness_to_alpha(float roughness, uint32_t remap)
{
    roughness = roughness > 0.0f ? roughness : 0.0f;
    return remap ? sqrt_float(roughness) : roughness;
}

/* pbrt-v4's BumpMap: the displaced surface's normal from finite
 * differences of the displacement half the footprint apart in u and v
 * (0.0005 without a footprint), on the side of ns. */
KERNEL_FN Vec3 bump_normal(const TextureArrays *a, int32_t displacement, const TextureContext *c, const SurfaceUv *uv,
                           Vec3 ns)
{
    float du = 0.5f * c->footprint * c->uv_density;
    du = du > 0.0f ? du : 0.0005f;
    TextureContext shifted = *c;
    shifted.p = v_add(c->p, v_scale(uv->dpdu, du));
    shifted.u = c->u + du;
    float u_displace = texture_evaluate_float(a, displacement, &shifted);
    shifted = *c;
    shifted.p = v_add(c->p, v_scale(uv->dpdv, du));
    shifted.v = c->v + du;
    float v_displace = texture_evaluate_float(a, displacement, &shifted);
    float displace = texture_evaluate_float(a, displacement, c);
    Vec3 dpdu = v_add(v_add(uv->dpdu, v_scale(ns, (u_displace - displace) / du)), v_scale(uv->dndu, displace));
    Vec3 dpdv = v_add(v_add(uv->dpdv, v_scale(ns, (v_displace - displace) / du)), v_scale(uv->dndv, displace));
    Vec3 bumped = v_cross(dpdu, dpdv);
    float length2 = v_dot(bumped, bumped);
    if (!(length2 > 0.0f) || !(length2 < INFINITY))
        return ns;
    bumped = v_scale(bumped, 1.0f / sqrt_float(length2));
    return v_dot(bumped, ns) < 0.0f ? v_scale(bumped, -1.0f) : bumped;
}

/* pbrt-v4's NormalMap: the image's RGB at (u, v) as a tangent-space
 * normal 2 rgb - 1 in the frame (dpdu made orthogonal to ns, ns x it, ns).
 * An image of (0.5, 0.5, 1) gives ns itself, bit for bit. */
KERNEL_FN Vec3 normal_map_normal(const TextureArrays *a, int32_t normal_map, const TextureContext *c,
                                 const SurfaceUv *uv, Vec3 ns)
{
    Vec3 rgb = texture_evaluate(a, normal_map, c);
    Vec3 tangent_space = vec3(2.0f * rgb.x - 1.0f, 2.0f * rgb.y - 1.0f, 2.0f * rgb.z - 1.0f);
    float length2 = v_dot(tangent_space, tangent_space);
    if (!(length2 > 0.0f))
        return ns;
    tangent_space = v_scale(tangent_space, 1.0f / sqrt_float(length2));
    Vec3 x = v_sub(uv->dpdu, v_scale(ns, v_dot(ns, uv->dpdu))), y;
    float x2 = v_dot(x, x);
    if (x2 > 0.0f && x2 < INFINITY) {
        x = v_scale(x, 1.0f / sqrt_float(x2));
        y = v_cross(ns, x);
    } else {
        v_basis(ns, &x, &y);
    }
    /* Unit as the frame is (not renormalised, so that (0, 0, 1) gives ns). */
    return v_add(v_add(v_scale(x, tangent_space.x), v_scale(y, tangent_space.y)), v_scale(ns, tangent_space.z));
}

/* The material at a hit with its textured parameters evaluated into *m
 * (a private copy of the scene's), and the shading normal *ns bump or
 * normal mapped. footprint as for surface_texture_context. */
KERNEL_FN void material_apply_textures(const Scene *scene, int32_t material, const Hit *hit,
                                       __global const Primitive *prim, Vec3 p, float footprint, Material *m, Vec3 *ns)
{
    __global const MaterialTextures *t = scene->material_textures + material;
    if ((t->reflectance & t->roughness[0] & t->roughness[1] & t->eta & t->conductor_eta & t->conductor_k &
         t->displacement & t->normal_map) < 0)
        return; /* every slot -1: an untextured material */
    SurfaceUv uv = surface_uv(scene, hit, prim, p);
    TextureContext c = surface_texture_context(&uv, p, *ns, footprint);
    TextureArrays a = scene_texture_arrays(scene);
    if (GMON_HAS_BUMP_MAP && t->displacement >= 0) {
        *ns = bump_normal(&a, t->displacement, &c, &uv, *ns);
        c.n = *ns;
    }
    if (GMON_HAS_NORMAL_MAP && t->normal_map >= 0) {
        *ns = normal_map_normal(&a, t->normal_map, &c, &uv, *ns);
        c.n = *ns;
    }
    if (t->reflectance >= 0) {
        Vec3 r = texture_evaluate(&a, t->reflectance, &c);
        r = vec3(clamp01(r.x), clamp01(r.y), clamp01(r.z));
        m->reflectance[0] = r.x;
        m->reflectance[1] = r.y;
        m->reflectance[2] = r.z;
        /* a conductor (or a coated conductor's base) by its reflectance r:
         * eta 1 and the k of normal-incidence reflectance r, as pbrt-v4 */
        if (m->type == MAT_CONDUCTOR || m->type == MAT_COATED_CONDUCTOR)
            for (int i = 0; i < 3; ++i) {
                float ri = m->reflectance[i] < 0.9999f ? m->reflectance[i] : 0.9999f;
                m->conductor_eta[i] = 1.0f;
                m->conductor_k[i] = 2.0f * sqrt_float(ri) / sqrt_float(1.0f - ri);
            }
    }
    if (t->roughness[0] >= 0)
        m->alpha_x = roughness_to_alpha(texture_evaluate_float(&a, t->roughness[0], &c), t->remap_roughness);
    if (t->roughness[1] >= 0)
        m->alpha_y = roughness_to_alpha(texture_evaluate_float(&a, t->roughness[1], &c), t->remap_roughness);
    if (t->eta >= 0) {
        float eta = texture_evaluate_float(&a, t->eta, &c);
        m->eta = eta > 0.0f ? eta : 1.0f;
    }
    if (t->conductor_eta >= 0) {
        Vec3 e = texture_evaluate(&a, t->conductor_eta, &c);
        m->conductor_eta[0] = e.x;
        m->conductor_eta[1] = e.y;
        m->conductor_eta[2] = e.z;
    }
    if (t->conductor_k >= 0) {
        Vec3 k = texture_evaluate(&a, t->conductor_k, &c);
        m->conductor_k[0] = k.x;
        m->conductor_k[1] = k.y;
        m->conductor_k[2] = k.z;
    }
}

#endif
