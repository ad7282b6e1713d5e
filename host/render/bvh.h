/* Bounding volume hierarchy over triangles and spheres, built on the host
 * with the surface area heuristic (binned) and flattened for the kernels
 * (kernels/intersect.h traverses it). */
#ifndef HOST_RENDER_BVH_H
#define HOST_RENDER_BVH_H

#include "intersect.h"

#include <stddef.h>

/* Deepest tree the kernels' traversal stack allows for. */
#define BVH_MAX_DEPTH (BVH_STACK_SIZE - 4)

typedef struct {
    BvhNode *nodes;
    int node_count;
    Primitive *primitives; /* reordered so leaves reference ranges */
    int primitive_count;
    int depth;
    int largest_leaf;
} Bvh;

/* Builds over a copy of `primitives`. Returns 0, or -1 with a message. An
 * empty scene gives one empty leaf. */
int bvh_build(const Primitive *primitives, int count, Bvh *bvh, char *error, size_t error_size);
void bvh_destroy(Bvh *bvh);

#endif
