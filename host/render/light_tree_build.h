/* The light tree's build (kernels/tracing/light_tree.h samples it). */
#ifndef HOST_RENDER_LIGHT_TREE_BUILD_H
#define HOST_RENDER_LIGHT_TREE_BUILD_H

#include <stddef.h>
#include <stdint.h>

#include "scene_types.h"

/* What a bounded light may light: its box, power (pbrt-v4's Phi, by
 * luminance), the cone its emitters face and whether they emit on both
 * sides (a LightNode's bounds). */
typedef struct {
    double lower[3], upper[3];
    double power;
    double axis[3];
    double theta_o, theta_e; /* radians */
    int two_sided;
} LightBounds;

/* A bounded light's bounds: `primitives` is the light's primitive array
 * (area lights). */
LightBounds light_bounds(const Light *light, const Primitive *primitives, double power);

/* Bounds holding both a and b. */
LightBounds light_bounds_union(const LightBounds *a, const LightBounds *b);

/* Builds the tree over the `count` bounded lights of the light array from
 * index first_light on, whose bounds are given in that order: *nodes
 * (2 count - 1 of them) and *trails (count; both NULL when count is 0).
 * Returns 0, or -1 out of memory. */
int light_tree_build(const LightBounds *bounds, int count, int first_light, LightNode **nodes, int *node_count,
                     uint64_t **trails);

#endif
