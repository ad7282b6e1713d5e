/* Bounding volume hierarchy over triangles and spheres, built on the host
 * as a binary tree with the surface area heuristic (binned), then collapsed
 * into the 8-wide tree the kernels traverse (kernels/tracing/intersect.h). */
#ifndef HOST_RENDER_BVH_H
#define HOST_RENDER_BVH_H

#include "intersect.h"

#include <stddef.h>

/* Deepest binary tree the builder accepts. */
#define BVH_MAX_DEPTH 92

/* Each wide level (at most one per binary level) leaves at most
 * BVH_WIDTH - 1 entries on the stack; an instance adds its leaf's others
 * and its own tree. The host's traversal has room for any of them. */
_Static_assert(2 * (BVH_WIDTH - 1) * BVH_MAX_DEPTH + 2 * BVH_WIDTH <= BVH_STACK_LIMIT,
               "BVH_STACK_LIMIT holds the deepest two-level BVH");

typedef struct {
    BvhNode *nodes; /* wide nodes and triangle packets */
    int node_count;
    Primitive *primitives; /* reordered so leaves reference ranges */
    int *order;            /* primitives[i] is the input's primitive order[i] */
    int primitive_count;
    int depth;        /* of the binary tree */
    int largest_leaf; /* at most BVH_WIDTH: identical centroids are split by order */
    int stack_need;   /* traversal stack entries */
    /* The most entries on the stack when the traversal enters an instance
     * (the entry that leaves it included); 0 without instances. */
    int instance_entry_need;
} Bvh;

/* Builds over a copy of `primitives`. Returns 0, or -1 with a message. An
 * empty scene gives one empty leaf. */
int bvh_build(const Primitive *primitives, int count, Bvh *bvh, char *error, size_t error_size);
void bvh_destroy(Bvh *bvh);

#endif
