/* Scene data shared by the host (which builds it) and the kernels (which
 * trace it): plain fixed-width structs, 16-byte aligned members, no float3
 * (its size differs between C and OpenCL). Sizes are checked on the host. */
#ifndef KERNELS_SCENE_TYPES_H
#define KERNELS_SCENE_TYPES_H

#include "compat.h"

/* Primitive kinds. */
#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u

/* A triangle (a, b, c are its vertices) or a sphere (a is the centre,
 * b[0] the radius). 48 bytes. */
typedef struct {
    float a[3];
    uint32_t kind;
    float b[3];
    int32_t material; /* index into the material array */
    float c[3];
    int32_t emitter; /* index into the emitter array, or -1 */
} Primitive;

/* A flattened BVH node, 32 bytes. Leaves (count > 0) hold primitives
 * [first, first + count) of the reordered primitive array. Interior nodes
 * have count = -(split axis + 1), their left child right after them and
 * their right child at `first`. */
typedef struct {
    float lower[3];
    int32_t first;
    float upper[3];
    int32_t count;
} BvhNode;

#ifndef __OPENCL_C_VERSION__
_Static_assert(sizeof(Primitive) == 48, "Primitive must match the kernel's layout");
_Static_assert(sizeof(BvhNode) == 32, "BvhNode must match the kernel's layout");
#endif

#endif
