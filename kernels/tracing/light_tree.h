/* The light tree (LightNode, scene_types.h): picks a bounded light with a
 * chance that follows how much it may light a shading point, from the
 * bounds of each subtree (the importance of pbrt-v4's "bvh" light sampler,
 * Conty Estevez and Kulla's "Importance Sampling of Many Lights with
 * Adaptive Tree Splitting", 2018): power over squared distance, times the
 * cosine bounds of the emitters' facing and of the point's normal, each
 * widened by the angle the subtree's box subtends. The bounds are
 * conservative, so a light whose importance is 0 sends no light there,
 * and light_tree_pmf gives, for a light a BSDF ray hit, the chance the
 * walk down the tree would have picked it. Host-buildable for the tests. */
#ifndef KERNELS_LIGHT_TREE_H
#define KERNELS_LIGHT_TREE_H

#include "scene_types.h"
#include "../common/vec3.h"

/* cos(a - b) from the cosines of a and b in [0, pi], or 1 where a <= b. */
KERNEL_FN float cos_difference_clamped(float cos_a, float cos_b)
{
    if (cos_a >= cos_b)
        return 1.0f;
    float sin_a = sqrt(fmax(0.0f, 1.0f - cos_a * cos_a)), sin_b = sqrt(fmax(0.0f, 1.0f - cos_b * cos_b));
    return cos_a * cos_b + sin_a * sin_b;
}

/* How much the lights under `node` may light point p of normal n (n = 0:
 * no normal, as in a medium). */
KERNEL_FN float light_node_importance(GLOBAL const LightNode *node, Vec3 p, Vec3 n)
{
    Vec3 lower = vec3_from_global(node->lower), upper = vec3_from_global(node->upper);
    Vec3 centre = v_scale(v_add(lower, upper), 0.5f);
    Vec3 half_extent = v_scale(v_sub(upper, lower), 0.5f);
    float radius2 = v_dot(half_extent, half_extent);
    Vec3 from_centre = v_sub(p, centre);
    float distance2 = v_dot(from_centre, from_centre);
    /* Inside its bounding sphere a subtree may lie in any direction, and
     * its distance is no less than the sphere's radius. */
    if (distance2 <= radius2)
        return node->power / fmax(radius2, 1e-30f);
    float distance = sqrt(distance2);
    Vec3 w = v_scale(from_centre, 1.0f / distance); /* from the lights toward p */
    float cos_bound = sqrt(fmax(0.0f, 1.0f - radius2 / distance2));

    /* The emitters' directions nearest w: theta_w less theta_o less the
     * box's angle; past theta_e no light leaves toward p. */
    float cos_w = v_dot(vec3_from_global(node->axis), w);
    if (node->two_sided)
        cos_w = fabs(cos_w);
    float cos_facing = 1.0f;
    if (cos_w < node->cos_theta_o) {
        float cos_past = cos_w * node->cos_theta_o + sqrt(fmax(0.0f, 1.0f - cos_w * cos_w)) *
                                                         sqrt(fmax(0.0f, 1.0f - node->cos_theta_o * node->cos_theta_o));
        cos_facing = cos_difference_clamped(cos_past, cos_bound);
    }
    if (cos_facing <= node->cos_theta_e)
        return 0.0f;
    float importance = node->power * cos_facing / distance2;
    if (v_dot(n, n) > 0.0f)
        importance *= cos_difference_clamped(fabs(v_dot(n, w)), cos_bound);
    return fmax(importance, 0.0f);
}

/* The chance of the first child at an inner node, 0..1, or -1 if neither
 * may light p. */
KERNEL_FN float light_tree_first_chance(GLOBAL const LightNode *nodes, int32_t node, Vec3 p, Vec3 n)
{
    float first = light_node_importance(nodes + node + 1, p, n);
    float second = light_node_importance(nodes + nodes[node].second, p, n);
    float total = first + second;
    return total > 0.0f ? first / total : -1.0f;
}

/* Walks down from the root with u in [0, 1): the bounded light picked
 * (its index in the light array), and its chance in *pmf; -1 if the walk
 * reaches a node neither of whose children may light p. (The root's own
 * bounds are not asked: a tree of one light picks it anywhere.) */
KERNEL_FN int light_tree_sample(GLOBAL const LightNode *nodes, Vec3 p, Vec3 n, float u, float *pmf)
{
    int32_t node = 0;
    float chance = 1.0f;
    while (nodes[node].second >= 0) {
        float first = light_tree_first_chance(nodes, node, p, n);
        if (first < 0.0f)
            return -1;
        if (u < first) {
            u = fmin(u / first, 0x1.fffffep-1f);
            chance *= first;
            node = node + 1;
        } else {
            u = fmin((u - first) / (1.0f - first), 0x1.fffffep-1f);
            chance *= 1.0f - first;
            node = nodes[node].second;
        }
    }
    *pmf = chance;
    return ~nodes[node].second;
}

/* The chance light_tree_sample picks the bounded light with this trail. */
KERNEL_FN float light_tree_pmf(GLOBAL const LightNode *nodes, uint64_t trail, Vec3 p, Vec3 n)
{
    int32_t node = 0;
    float chance = 1.0f;
    for (; trail > 1u; trail >>= 1) {
        float first = light_tree_first_chance(nodes, node, p, n);
        if (first < 0.0f)
            return 0.0f;
        if (trail & 1u) {
            chance *= 1.0f - first;
            node = nodes[node].second;
        } else {
            chance *= first;
            node = node + 1;
        }
    }
    return chance;
}

#endif
