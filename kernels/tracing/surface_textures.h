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

#if GMON_HAS_INSTANCING
/* The rows of M v for the 3x3 part M of an instance's object_from_world. */
KERNEL_FN Vec3 instance_apply(__global const Instance *instance, Vec3 v)
{
    float in[3] = {v.x, v.y, v.z}, out[3];
    for (int r = 0; r < 3; ++r) {
        __global const float *m = instance->object_from_world[r];
        out[r] = m[0] * in[0] + m[1] * in[1] + m[2] * in[2];
    }
    return vec3(out[0], out[1], out[2]);
}

/* The surface of a hit in an instance: (u, v) in object space, where the
 * primitive lies (a sphere's angles about its object-space centre, so the
 * texture turns with the instance, as pbrt-v4's does); tangents taken to
 * the world by the inverse of M (object_from_world's 3x3 part), the normal's
 * change as a normal (M^T, over the normal's length there), and the uv
 * density divided by the instance's scale across the surface: a surface
 * element of object area A and unit normal n has world area
 * A |M^T n| / |det M|. */
KERNEL_FN SurfaceUv instanced_surface_uv(const Scene *scene, const Hit *hit, __global const Primitive *prim, Vec3 p)
{
    __global const Instance *instance = scene->instances + hit->instance;
    float world[3] = {p.x, p.y, p.z}, object[3];
    instance_point(instance, world, object);
    Vec3 q = vec3(object[0], object[1], object[2]);
    SurfaceUv s = surface_uv_at(scene->surface_uvs, hit->primitive, hit->u, hit->v, prim, q);
    Vec3 n = v_normalize(is_sphere(prim) ? v_sub(q, vec3_from_global(prim->a))
                                         : v_cross(vec3_from_global(prim->b), vec3_from_global(prim->c)));
    float normal_scale = v_length(instance_normal_v(instance, n));
    Vec3 r0 = vec3_from_global(instance->object_from_world[0]), r1 = vec3_from_global(instance->object_from_world[1]),
         r2 = vec3_from_global(instance->object_from_world[2]);
    /* M^-1 = adj(M) / det M: its columns are the rows' cross products. */
    Vec3 c0 = v_cross(r1, r2), c1 = v_cross(r2, r0), c2 = v_cross(r0, r1);
    float det = v_dot(r0, c0), inv = 1.0f / det;
    Vec3 d[2] = {s.dpdu, s.dpdv};
    for (int k = 0; k < 2; ++k)
        d[k] = v_scale(v_add(v_add(v_scale(c0, d[k].x), v_scale(c1, d[k].y)), v_scale(c2, d[k].z)), inv);
    s.dpdu = d[0];
    s.dpdv = d[1];
    s.dndu = v_scale(instance_normal_v(instance, s.dndu), 1.0f / normal_scale);
    s.dndv = v_scale(instance_normal_v(instance, s.dndv), 1.0f / normal_scale);
    s.density *= sqrt_float(abs_float(det) / normal_scale);
    return s;
}
#endif

/* The surface's (u, v) at world point p of a hit. */
KERNEL_FN SurfaceUv surface_uv(const Scene *scene, const Hit *hit, __global const Primitive *prim, Vec3 p)
{
#if GMON_HAS_INSTANCING
    if (hit->instance >= 0)
        return instanced_surface_uv(scene, hit, prim, p);
#endif
    return surface_uv_at(scene->surface_uvs, hit->primitive, hit->u, hit->v, prim, p);
}

/* A float texture at a hit (a mix's amount): `texture` a program's first
 * node, n the shading normal. */
KERNEL_FN float scene_texture_float(const Scene *scene, int32_t texture, const Hit *hit, __global const Primitive *prim,
                                    Vec3 p, Vec3 n, float footprint)
{
    SurfaceUv uv = surface_uv(scene, hit, prim, p);
    TextureContext c = surface_texture_context(&uv, p, n, footprint);
    TextureArrays a = scene_texture_arrays(scene);
    return texture_evaluate_float(&a, texture, &c);
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
    /* (0, 0, z > 0) is ns exactly; tested apart because the render kernels'
     * unsafe-math 1/sqrt(1) may be 1 - 2^-24 on some devices. */
    if (!(length2 > 0.0f) || (tangent_space.x == 0.0f && tangent_space.y == 0.0f && tangent_space.z > 0.0f))
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
    /* Unit as the frame is (not renormalised). */
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
         t->displacement & t->normal_map & t->transmittance & t->thickness & t->g & t->albedo & t->base_roughness[0] &
         t->base_roughness[1]) < 0)
        return; /* every slot -1 (mix_amount is mix_resolve_at_hit's): an untextured material */
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
        /* scale: diffuse transmission's "scale" (1 for the others) */
        Vec3 r = v_scale(texture_evaluate(&a, t->reflectance, &c), t->scale);
        r = vec3(clamp01(r.x), clamp01(r.y), clamp01(r.z));
        m->reflectance[0] = r.x;
        m->reflectance[1] = r.y;
        m->reflectance[2] = r.z;
        /* a conductor (or a coated conductor's base) by its reflectance */
        if (m->type == MAT_CONDUCTOR || m->type == MAT_COATED_CONDUCTOR)
            conductor_from_reflectance(m, m->reflectance);
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
    if (t->transmittance >= 0) {
        Vec3 r = v_scale(texture_evaluate(&a, t->transmittance, &c), t->scale);
        m->transmittance[0] = clamp01(r.x);
        m->transmittance[1] = clamp01(r.y);
        m->transmittance[2] = clamp01(r.z);
    }
    if (t->base_roughness[0] >= 0)
        m->base_alpha_x = roughness_to_alpha(texture_evaluate_float(&a, t->base_roughness[0], &c), t->remap_roughness);
    if (t->base_roughness[1] >= 0)
        m->base_alpha_y = roughness_to_alpha(texture_evaluate_float(&a, t->base_roughness[1], &c), t->remap_roughness);
    /* The layer as pbrt-v4: thickness at least the smallest normal float,
     * albedo clamped to [0, 1]; g kept within [-1, 1] (0 for NaN), where
     * the Henyey-Greenstein phase function is defined. */
    if (t->thickness >= 0)
        m->thickness = fmax(texture_evaluate_float(&a, t->thickness, &c), FLT_MIN);
    if (t->g >= 0) {
        float g = texture_evaluate_float(&a, t->g, &c);
        m->g = g >= -1.0f ? (g <= 1.0f ? g : 1.0f) : (g < -1.0f ? -1.0f : 0.0f);
    }
    if (t->albedo >= 0) {
        Vec3 albedo = texture_evaluate(&a, t->albedo, &c);
        m->albedo[0] = clamp01(albedo.x);
        m->albedo[1] = clamp01(albedo.y);
        m->albedo[2] = clamp01(albedo.z);
    }
}

/* mix_resolve with each mix's textured "amount" evaluated at the hit (as
 * pbrt-v4's MixMaterial::ChooseMaterial: before the choice, so that the
 * chance is the texture's there). n: the shading normal, footprint as for
 * surface_texture_context. */
KERNEL_FN __global const Material *mix_resolve_at_hit(const Scene *scene, __global const Material *m, const Hit *hit,
                                                      __global const Primitive *prim, Vec3 p, Vec3 wo, Vec3 n,
                                                      float footprint)
{
    for (int level = 0; level < MIX_MAX_NESTING && m->type == MAT_MIX; ++level) {
        int32_t amount_texture = scene->material_textures[m - scene->materials].mix_amount;
        float amount =
            amount_texture < 0 ? m->mix_amount : scene_texture_float(scene, amount_texture, hit, prim, p, n, footprint);
        m = mix_choose(scene->materials, m, amount, p, wo);
    }
    return m;
}

#endif
