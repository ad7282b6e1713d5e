/* Kernel specialization: the host computes one bit mask of what a render
 * uses (shapes, materials, lights, integrator mode, camera, pixel filter)
 * from the scene, and builds the path tracer with -DGMON_FEATURES=<mask>. This header turns the bits into GMON_HAS_*
 * macros (0 or 1) for `#if` guards and constant conditions, so code a render does not need is compiled out. Without the
 * define (host code, tests, the all-features build) every feature is in. */
#ifndef KERNELS_FEATURES_H
#define KERNELS_FEATURES_H

/* (The estimator kernel is specialized by its passes instead: passes.h.) */
#define FEATURE_TRIANGLES 0x10ul
#define FEATURE_SPHERES 0x20ul
#define FEATURE_DIFFUSE 0x40ul
#define FEATURE_DIELECTRIC 0x80ul
#define FEATURE_CONDUCTOR 0x100ul
#define FEATURE_COATED_DIFFUSE 0x200ul
#define FEATURE_ROUGH 0x400ul        /* GGX lobes (any material with roughness) */
#define FEATURE_AREA_LIGHTS 0x800ul  /* emitting shapes */
#define FEATURE_ENVIRONMENT 0x1000ul /* a constant infinite light */
#define FEATURE_NEE 0x2000ul         /* next-event estimation with MIS; else BSDF sampling only */
#define FEATURE_POINT_LIGHTS 0x4000ul
#define FEATURE_SPOT_LIGHTS 0x8000ul
#define FEATURE_DISTANT_LIGHTS 0x10000ul
#define FEATURE_ENVIRONMENT_MAP 0x20000ul /* an infinite light with an image */
#define FEATURE_FILM_MATRIX 0x40000ul     /* a film that is not the identity on radiance */
/* 0x80000ul is free (it was Film "maxcomponentvalue": now the per-sample
 * estimator clamp, sample_passes.h). */
#define FEATURE_SHADING_NORMALS 0x100000ul /* meshes with vertex normals */
#define FEATURE_GONIOMETRIC_LIGHTS 0x200000ul
#define FEATURE_PROJECTION_LIGHTS 0x400000ul
#define FEATURE_THIN_LENS 0x800000ul            /* a camera with lensradius > 0 */
#define FEATURE_ORTHOGRAPHIC 0x1000000ul        /* Camera "orthographic" */
#define FEATURE_PIXEL_FILTER 0x2000000ul        /* a filter other than the box of radius 0.5 */
#define FEATURE_IMAGE_TEXTURES 0x4000000ul      /* Texture "imagemap" */
#define FEATURE_PROCEDURAL_TEXTURES 0x8000000ul /* every other Texture class (constant, scale, mix, ...) */
#define FEATURE_BUMP_MAP 0x10000000ul           /* a material's "displacement" */
#define FEATURE_NORMAL_MAP 0x20000000ul         /* a material's "normalmap" */
#define FEATURE_INSTANCING 0x40000000ul         /* ObjectInstance: a two-level BVH */
#define FEATURE_ALPHA 0x80000000ul              /* shapes with alpha cut-outs */
/* 64 bits ("ul": OpenCL C's long and LP64 hosts' long are both 64 bits). */
#define FEATURE_DIFFUSE_TRANSMISSION 0x100000000ul
#define FEATURE_MIX 0x200000000ul
#define FEATURE_COATED_CONDUCTOR 0x400000000ul
#define FEATURE_THIN_DIELECTRIC 0x800000000ul
#define FEATURE_LAYERED 0x1000000000ul       /* the layered random walk: coated diffuse or coated conductor */
#define FEATURE_ALPHA_TEXTURE 0x2000000000ul /* "texture alpha": cut-outs whose alpha is a float texture */
#define FEATURE_MEDIA 0x4000000000ul         /* participating media: the volumetric path tracer (media.h) */
#define FEATURE_NANOVDB 0x8000000000ul       /* "nanovdb" media (nanovdb.h) */
#define FEATURES_ALL 0xfffff7fff0ul          /* bits 4..39 but 19 */

#ifndef GMON_FEATURES
#define GMON_FEATURES FEATURES_ALL
#endif

#define GMON_HAS(bit) ((GMON_FEATURES & (bit)) != 0)
#define GMON_HAS_TRIANGLES GMON_HAS(FEATURE_TRIANGLES)
#define GMON_HAS_SPHERES GMON_HAS(FEATURE_SPHERES)
#define GMON_HAS_DIFFUSE GMON_HAS(FEATURE_DIFFUSE)
#define GMON_HAS_DIELECTRIC GMON_HAS(FEATURE_DIELECTRIC)
#define GMON_HAS_CONDUCTOR GMON_HAS(FEATURE_CONDUCTOR)
#define GMON_HAS_COATED_DIFFUSE GMON_HAS(FEATURE_COATED_DIFFUSE)
#define GMON_HAS_ROUGH GMON_HAS(FEATURE_ROUGH)
#define GMON_HAS_AREA_LIGHTS GMON_HAS(FEATURE_AREA_LIGHTS)
#define GMON_HAS_ENVIRONMENT GMON_HAS(FEATURE_ENVIRONMENT)
#define GMON_HAS_NEE GMON_HAS(FEATURE_NEE)
#define GMON_HAS_POINT_LIGHTS GMON_HAS(FEATURE_POINT_LIGHTS)
#define GMON_HAS_SPOT_LIGHTS GMON_HAS(FEATURE_SPOT_LIGHTS)
#define GMON_HAS_DISTANT_LIGHTS GMON_HAS(FEATURE_DISTANT_LIGHTS)
#define GMON_HAS_ENVIRONMENT_MAP GMON_HAS(FEATURE_ENVIRONMENT_MAP)
#define GMON_HAS_INFINITE_LIGHTS (GMON_HAS_ENVIRONMENT || GMON_HAS_ENVIRONMENT_MAP)
#define GMON_HAS_FILM_MATRIX GMON_HAS(FEATURE_FILM_MATRIX)
#define GMON_HAS_SHADING_NORMALS GMON_HAS(FEATURE_SHADING_NORMALS)
#define GMON_HAS_GONIOMETRIC_LIGHTS GMON_HAS(FEATURE_GONIOMETRIC_LIGHTS)
#define GMON_HAS_PROJECTION_LIGHTS GMON_HAS(FEATURE_PROJECTION_LIGHTS)
#define GMON_HAS_THIN_LENS GMON_HAS(FEATURE_THIN_LENS)
#define GMON_HAS_ORTHOGRAPHIC GMON_HAS(FEATURE_ORTHOGRAPHIC)
#define GMON_HAS_PIXEL_FILTER GMON_HAS(FEATURE_PIXEL_FILTER)
#define GMON_HAS_DIFFUSE_TRANSMISSION GMON_HAS(FEATURE_DIFFUSE_TRANSMISSION)
#define GMON_HAS_MIX GMON_HAS(FEATURE_MIX)
#define GMON_HAS_COATED_CONDUCTOR GMON_HAS(FEATURE_COATED_CONDUCTOR)
#define GMON_HAS_THIN_DIELECTRIC GMON_HAS(FEATURE_THIN_DIELECTRIC)
#define GMON_HAS_LAYERED GMON_HAS(FEATURE_LAYERED)
#define GMON_HAS_IMAGE_TEXTURES GMON_HAS(FEATURE_IMAGE_TEXTURES)
#define GMON_HAS_PROCEDURAL_TEXTURES GMON_HAS(FEATURE_PROCEDURAL_TEXTURES)
#define GMON_HAS_BUMP_MAP GMON_HAS(FEATURE_BUMP_MAP)
#define GMON_HAS_NORMAL_MAP GMON_HAS(FEATURE_NORMAL_MAP)
/* Any texture: materials read their parameters through texture programs. */
#define GMON_HAS_TEXTURES (GMON_HAS_IMAGE_TEXTURES || GMON_HAS_PROCEDURAL_TEXTURES)
#define GMON_HAS_INSTANCING GMON_HAS(FEATURE_INSTANCING)
#define GMON_HAS_ALPHA GMON_HAS(FEATURE_ALPHA)
#define GMON_HAS_ALPHA_TEXTURE GMON_HAS(FEATURE_ALPHA_TEXTURE)
#define GMON_HAS_MEDIA GMON_HAS(FEATURE_MEDIA)
#define GMON_HAS_NANOVDB GMON_HAS(FEATURE_NANOVDB)

#endif
