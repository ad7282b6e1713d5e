/* A surface's (u, v) and tangents at a point as pbrt-v4 gives them
 * (triangles: their vertex uvs, by default (0,0), (1,0), (1,1); spheres:
 * phi / 2 pi and 1 - theta / pi about the centre), from the per-primitive
 * uv table (surface_uvs, SURFACE_UV_FLOATS a primitive). Shared by the
 * material textures (surface_textures.h) and the alpha cut-outs
 * (intersect.h), and by the host. */
#ifndef KERNELS_SURFACE_UV_H
#define KERNELS_SURFACE_UV_H

#include "../common/compat.h"
#include "scene_types.h"
#include "texture.h"
#include "../common/vec3.h"

#ifndef __OPENCL_C_VERSION__
#define surface_acos(x) acosf(x)
#define surface_cos(x) cosf(x)
#define surface_sin(x) sinf(x)
#else
#define surface_acos(x) acos(x)
#define surface_cos(x) cos(x)
#define surface_sin(x) sin(x)
#endif

typedef struct {
    float u, v;
    float density;   /* uv units per world length */
    Vec3 dpdu, dpdv; /* tangents along u and v (in the space of p and the primitive) */
    Vec3 dndu, dndv; /* the normal's change along them (spheres; 0 on triangles) */
} SurfaceUv;

/* The surface at point p of primitive `primitive` (its index in the
 * primitive array), whose hit had triangle barycentrics (b1, b2). p is in
 * the primitive's space (object space inside an instance). */
KERNEL_FN SurfaceUv surface_uv_at(const GLOBAL float *surface_uvs, int32_t primitive, float b1, float b2,
                                  const GLOBAL Primitive *prim, Vec3 p)
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
        float theta = surface_acos(cos_theta), sin_theta = sqrt_float(fmax(0.0f, 1.0f - cos_theta * cos_theta));
        s.u = phi / (2.0f * PI_F);
        s.v = 1.0f - theta / PI_F;
        s.density = 1.0f / (PI_F * r);
        s.dpdu = vec3(-2.0f * PI_F * d.y, 2.0f * PI_F * d.x, 0.0f);
        s.dpdv = v_scale(vec3(d.z * surface_cos(phi), d.z * surface_sin(phi), -r * sin_theta), -PI_F);
        s.dndu = v_scale(s.dpdu, 1.0f / r);
        s.dndv = v_scale(s.dpdv, 1.0f / r);
        return s;
    }
    const GLOBAL float *uv = surface_uvs + SURFACE_UV_FLOATS * (size_t)primitive;
    float b0 = 1.0f - b1 - b2;
    s.u = b0 * uv[0] + b1 * uv[2] + b2 * uv[4];
    s.v = b0 * uv[1] + b1 * uv[3] + b2 * uv[5];
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

#endif
