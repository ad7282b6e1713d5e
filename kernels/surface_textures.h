/* Textures at a ray's hit: the surface's (u, v) and tangents as pbrt-v4
 * gives them (triangles: their vertex uvs, by default (0,0), (1,0), (1,1);
 * spheres: phi / 2 pi and 1 - theta / pi about the centre in world
 * space), the texture context, a material's textured parameters, and bump
 * and normal mapping of the shading normal (pbrt-v4's BumpMap and
 * NormalMap). Compiled only into builds with textures. */
#ifndef KERNELS_SURFACE_TEXTURES_H
#define KERNELS_SURFACE_TEXTURES_H

#include "bsdf.h"
#include "scene.h"
#include "texture.h"

typedef struct {
    float u, v;
    float density;   /* uv units per world length */
    Vec3 dpdu, dpdv; /* world-space tangents along u and v */
    Vec3 dndu, dndv; /* the normal's change along them (spheres; 0 on triangles) */
} SurfaceUv;

KERNEL_FN TextureArrays scene_texture_arrays(const Scene *scene)
{
    TextureArrays a;
    a.nodes = scene->textures;
    a.bytes = scene->texture_bytes;
    a.floats = scene->texture_floats;
    return a;
}

KERNEL_FN SurfaceUv surface_uv(const Scene *scene, const Hit *hit, __global const Primitive *prim, Vec3 p)
{
    SurfaceUv s;
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
    s.dndu = s.dndv = zero;
    if (is_sphere(prim)) {
        float r = prim->b[0];
        Vec3 d = v_sub(p, vec3_from_global(prim->a));
        float phi = atan2_float(d.y, d.x);
        phi = phi < 0.0f ? phi + 2.0f * PI_F : phi;
        float cos_theta = fmin(1.0f, fmax(-1.0f, d.z / r));
        float theta = acos(cos_theta), sin_theta = sqrt_float(fmax(0.0f, 1.0f - cos_theta * cos_theta));
        s.u = phi / (2.0f * PI_F);
        s.v = 1.0f - theta / PI_F;
        s.density = 1.0f / (PI_F * r);
        s.dpdu = vec3(-2.0f * PI_F * d.y, 2.0f * PI_F * d.x, 0.0f);
        s.dpdv = v_scale(vec3(d.z * cos(phi), d.z * sin(phi), -r * sin_theta), -PI_F);
        s.dndu = v_scale(s.dpdu, 1.0f / r);
        s.dndv = v_scale(s.dpdv, 1.0f / r);
        return s;
    }
    __global const float *uv = scene->surface_uvs + SURFACE_UV_FLOATS * (size_t)hit->primitive;
    float b0 = 1.0f - hit->u - hit->v;
    s.u = b0 * uv[0] + hit->u * uv[2] + hit->v * uv[4];
    s.v = b0 * uv[1] + hit->u * uv[3] + hit->v * uv[5];
    s.density = uv[6];
    /* pbrt-v4's triangle tangents from the uv differences to vertex 2. */
    float du02 = uv[0] - uv[4], dv02 = uv[1] - uv[5], du12 = uv[2] - uv[4], dv12 = uv[3] - uv[5];
    Vec3 e1 = vec3_from_global(prim->b), e2 = vec3_from_global(prim->c);
    Vec3 dp02 = v_scale(e2, -1.0f), dp12 = v_sub(e1, e2);
    float det = du02 * dv12 - dv02 * du12;
    if (abs_float(det) < 1e-9f) {
        v_basis(v_normalize(v_cross(e1, e2)), &s.dpdu, &s.dpdv);
    } else {
        float inv = 1.0f / det;
        s.dpdu = v_scale(v_sub(v_scale(dp02, dv12), v_scale(dp12, dv02)), inv);
        s.dpdv = v_scale(v_sub(v_scale(dp12, du02), v_scale(dp02, du12)), inv);
    }
    return s;
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

/* A float texture at a hit (for alpha cut-outs): `texture` a program's
 * first node (MaterialTextures' or a shape's), n the shading normal. */
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
