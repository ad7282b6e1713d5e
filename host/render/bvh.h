/* Bounding volume hierarchy over triangles and spheres, built on the host
 * as a binary tree with the surface area heuristic (binned), then collapsed
 * into the 8-wide tree the kernels traverse (kernels/intersect.h). */
#ifndef HOST_RENDER_BVH_H
#define HOST_RENDER_BVH_H

#include "intersect.h"

#include <stddef.h>

/* Deepest binary tree the builder accepts. */
#define BVH_MAX_DEPTH 92

typedef struct {
    BvhNode *nodes; /* wide nodes and triangle packets */
    int node_count;
    Primitive *primitives; /* reordered so leaves reference ranges */
    int *order;            /* primitives[i] is the input's primitive order[i] */
    int primitive_count;
    int depth; /* of the binary tree */
    int largest_leaf;
    int stack_need; /* traversal stack entries */
} Bvh;

/* Builds over a copy of `primitives`. Returns 0, or -1 with a message. An
 * empty scene gives one empty leaf. */
int bvh_build(const Primitive *primitives, int count, Bvh *bvh, char *error, size_t error_size);
void bvh_destroy(Bvh *bvh);

#endif
