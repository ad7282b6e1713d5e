/* Scene data shared by the host (which builds it) and the kernels (which
 * trace it): plain fixed-width structs, 16-byte aligned members, no float3
 * (its size differs between C and OpenCL). Sizes are checked on the host. */
#ifndef KERNELS_SCENE_TYPES_H
#define KERNELS_SCENE_TYPES_H

#include "compat.h"
#include "feature_mask.h"

/* Primitive kinds. */
#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u

/* A triangle (a is its first vertex, b and c the edges to the second and
 * third, which saves the intersection test two subtractions) or a sphere
 * (a is the centre, b[0] the radius). 48 bytes. */
typedef struct {
    float a[3];
    uint32_t kind;
    float b[3];
    int32_t material; /* index into the material array */
    float c[3];
    int32_t emitter; /* index into the emitter array, or -1 */
} Primitive;

/* The BVH, an 8-wide tree flattened into an array of BvhNode blocks (block 0
 * is the root). A node holds the boxes of up to 8 children, which a kernel
 * tests at once with 8-wide vector operations, structure of arrays. A child
 * is an inner node or a leaf of 1..8 primitives [first, first + count) of the
 * reordered primitive array; an all-triangle leaf also has a packet of its
 * triangles, in a block of its own, for an 8-wide intersection test. */
#define BVH_WIDTH 8

typedef struct {
    float lower[3][BVH_WIDTH]; /* [axis][child] */
    float upper[3][BVH_WIDTH];
    int32_t child[BVH_WIDTH];  /* an inner child's block; a leaf's first primitive */
    int32_t count[BVH_WIDTH];  /* 0: inner node; 1..BVH_WIDTH: a leaf; -1: no child */
    int32_t packet[BVH_WIDTH]; /* a leaf's triangle packet block, or -1: test one by one */
} BvhWideNode;

/* A leaf's triangles as Primitive stores them ([component][triangle]); lanes
 * past the leaf's count have zero edges, which never hit. */
typedef struct {
    float a[3][BVH_WIDTH];
    float b[3][BVH_WIDTH];
    float c[3][BVH_WIDTH];
} TrianglePacket;

/* 288 bytes. */
typedef union {
    BvhWideNode node;
    TrianglePacket triangles;
} BvhNode;

/* Primitive.kind: the shape in the low byte, flags above it. */
#define PRIM_KIND_MASK 0xffu
#define PRIM_FLIP_NORMAL 0x100u /* ReverseOrientation (or a handedness swap) */

/* With one shape kind in the build (feature_mask.h) the test folds away. */
KERNEL_FN int is_sphere(const GLOBAL Primitive *p)
{
    return GMON_HAS_SPHERES && (!GMON_HAS_TRIANGLES || (p->kind & PRIM_KIND_MASK) == PRIM_SPHERE);
}

/* Material types. */
#define MAT_DIFFUSE 0u
#define MAT_DIELECTRIC 1u
#define MAT_CONDUCTOR 2u
#define MAT_COATED_DIFFUSE 3u

/* 64 bytes. alpha_x/alpha_y are GGX roughnesses; below SMOOTH_ALPHA the
 * surface is treated as perfectly smooth (a delta lobe). */
typedef struct {
    uint32_t type;
    float alpha_x;
    float alpha_y;
    float eta;            /* dielectric / coating index of refraction */
    float reflectance[3]; /* diffuse albedo, coated base albedo */
    float pad0;
    float conductor_eta[3];
    float pad1;
    float conductor_k[3];
    float pad2;
} Material;

#define SMOOTH_ALPHA 1e-3f

/* An area light: one emitting primitive. 32 bytes. */
typedef struct {
    float radiance[3];
    int32_t primitive; /* index into the (BVH-ordered) primitive array */
    float area;
    uint32_t two_sided;
    float pick_probability; /* chance that light sampling picks it */
    float pick_cdf;         /* running sum of pick probabilities, inclusive */
} Emitter;

/* Render parameters, one per render. 96 bytes. The camera looks along
 * `forward`; `right` and `up` are scaled by the tangents of the half fields
 * of view, so a pixel's ray is forward + x * right + y * up for x, y in
 * [-1, 1] (x to the right, y up in the image). */
#define RENDER_NEE 1u /* next-event estimation with MIS; else BSDF sampling only */

typedef struct {
    float camera_position[3];
    uint32_t width;
    float camera_right[3];
    uint32_t height;
    float camera_up[3];
    uint32_t max_depth;
    float camera_forward[3];
    uint32_t seed;
    float environment[3]; /* constant infinite light radiance */
    uint32_t emitter_count;
    float environment_pick; /* chance light sampling picks the environment */
    uint32_t flags;
    uint32_t pad[2];
} RenderParams;

#ifndef __OPENCL_C_VERSION__
_Static_assert(sizeof(Primitive) == 48, "Primitive must match the kernel's layout");
_Static_assert(sizeof(BvhNode) == 288, "BvhNode must match the kernel's layout");
_Static_assert(sizeof(Material) == 64, "Material must match the kernel's layout");
_Static_assert(sizeof(Emitter) == 32, "Emitter must match the kernel's layout");
_Static_assert(sizeof(RenderParams) == 96, "RenderParams must match the kernel's layout");
#endif

#endif
