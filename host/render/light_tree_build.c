#include "light_tree_build.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double pi = 3.14159265358979323846;

static void normalize(double v[3])
{
    double length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i)
        v[i] = length > 0.0 ? v[i] / length : (i == 2);
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void point_bounds(LightBounds *b, const float p[3])
{
    for (int i = 0; i < 3; ++i)
        b->lower[i] = b->upper[i] = p[i];
}

LightBounds light_bounds(const Light *light, const Primitive *primitives, double power)
{
    LightBounds b;
    memset(&b, 0, sizeof b);
    b.power = power;
    b.axis[2] = 1.0;
    b.theta_o = pi; /* every direction, unless known narrower */
    b.theta_e = pi / 2.0;
    if (light->type == LIGHT_AREA) {
        const Primitive *p = &primitives[light->primitive];
        b.two_sided = light->two_sided != 0;
        if (p->kind == PRIM_SPHERE) {
            for (int i = 0; i < 3; ++i) {
                b.lower[i] = (double)p->a[i] - p->b[0];
                b.upper[i] = (double)p->a[i] + p->b[0];
            }
        } else {
            /* Rounding of the vertices' box is a few ulps: widen by more. */
            for (int i = 0; i < 3; ++i) {
                double v[3] = {p->a[i], (double)p->a[i] + p->b[i], (double)p->a[i] + p->c[i]};
                double lo = fmin(v[0], fmin(v[1], v[2])), hi = fmax(v[0], fmax(v[1], v[2]));
                double slack = 1e-6 * (fabs(lo) + fabs(hi)) + 1e-30;
                b.lower[i] = lo - slack;
                b.upper[i] = hi + slack;
            }
            double e1[3] = {p->b[0], p->b[1], p->b[2]}, e2[3] = {p->c[0], p->c[1], p->c[2]};
            cross(e1, e2, b.axis);
            normalize(b.axis);
            if (p->kind & PRIM_FLIP_NORMAL)
                for (int i = 0; i < 3; ++i)
                    b.axis[i] = -b.axis[i];
            b.theta_o = 0.0;
        }
        return b;
    }
    point_bounds(&b, light->position);
    if (light->type == LIGHT_SPOT) {
        for (int i = 0; i < 3; ++i)
            b.axis[i] = light->direction[i];
        normalize(b.axis);
        b.theta_o = acos(fmax(-1.0, fmin(1.0, (double)light->cos_total_width)));
    }
    return b;
}

/* The cone around axis a of half-angle theta_a and the one around b of
 * theta_b, both in one: axis `axis`, half-angle returned (pi: every
 * direction). */
static double cone_union(const double a[3], double theta_a, const double b[3], double theta_b, double axis[3])
{
    memcpy(axis, a, 3 * sizeof *axis);
    if (theta_a >= pi || theta_b >= pi)
        return pi;
    double between = acos(fmax(-1.0, fmin(1.0, dot(a, b))));
    if (fmin(between + theta_b, pi) <= theta_a)
        return theta_a;
    if (fmin(between + theta_a, pi) <= theta_b) {
        memcpy(axis, b, 3 * sizeof *axis);
        return theta_b;
    }
    double theta = (theta_a + between + theta_b) / 2.0;
    double turn_axis[3];
    cross(a, b, turn_axis);
    double sin_between = sqrt(dot(turn_axis, turn_axis));
    if (theta >= pi || sin_between < 1e-9)
        return pi;
    /* Turn a toward b by theta - theta_a, in their plane. */
    double turn = theta - theta_a, toward[3];
    cross(turn_axis, a, toward); /* perpendicular to a, toward b, of length sin_between */
    for (int i = 0; i < 3; ++i)
        axis[i] = a[i] * cos(turn) + toward[i] / sin_between * sin(turn);
    normalize(axis);
    /* Rounding of the turn: widen by a hair to hold both cones. */
    return fmin(pi, theta + 1e-6);
}

LightBounds light_bounds_union(const LightBounds *a, const LightBounds *b)
{
    LightBounds u;
    memset(&u, 0, sizeof u);
    for (int i = 0; i < 3; ++i) {
        u.lower[i] = fmin(a->lower[i], b->lower[i]);
        u.upper[i] = fmax(a->upper[i], b->upper[i]);
    }
    u.power = a->power + b->power;
    u.theta_o = cone_union(a->axis, a->theta_o, b->axis, b->theta_o, u.axis);
    u.theta_e = fmax(a->theta_e, b->theta_e);
    u.two_sided = a->two_sided || b->two_sided;
    return u;
}

typedef struct {
    const LightBounds *bounds;
    int first_light;
    LightNode *nodes;
    int node_count;
    uint64_t *trails;
} Build;

static const LightBounds *sort_bounds;
static int sort_axis;

static int by_centre(const void *a, const void *b)
{
    const LightBounds *x = &sort_bounds[*(const int *)a], *y = &sort_bounds[*(const int *)b];
    double cx = x->lower[sort_axis] + x->upper[sort_axis], cy = y->lower[sort_axis] + y->upper[sort_axis];
    if (cx != cy)
        return cx < cy ? -1 : 1;
    return *(const int *)a - *(const int *)b; /* a total order: the same tree every time */
}

static void store_node(LightNode *node, const LightBounds *b)
{
    memset(node, 0, sizeof *node);
    for (int i = 0; i < 3; ++i) {
        node->lower[i] = (float)b->lower[i];
        node->upper[i] = (float)b->upper[i];
        node->axis[i] = (float)b->axis[i];
    }
    /* Round outward, so the stored box still holds the lights. */
    for (int i = 0; i < 3; ++i) {
        if (node->lower[i] > b->lower[i])
            node->lower[i] = nextafterf(node->lower[i], -INFINITY);
        if (node->upper[i] < b->upper[i])
            node->upper[i] = nextafterf(node->upper[i], INFINITY);
    }
    node->power = (float)b->power;
    node->cos_theta_o = b->theta_o >= pi ? -1.0f : (float)cos(b->theta_o);
    node->cos_theta_e = (float)cos(b->theta_e);
    node->two_sided = b->two_sided ? 1u : 0u;
}

/* The surface area orientation heuristic's measure of a subtree (Conty
 * Estevez and Kulla 2018): power times box area times the solid angle its
 * emitters' cone (widened by theta_e) covers, weighted by cosine. */
static double orientation_cost(const LightBounds *b)
{
    double d[3] = {b->upper[0] - b->lower[0], b->upper[1] - b->lower[1], b->upper[2] - b->lower[2]};
    double area = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
    double o = b->theta_o, w = fmin(o + b->theta_e, pi);
    double cone =
        2.0 * pi * (1.0 - cos(o)) + pi / 2.0 * (2.0 * w * sin(o) - cos(o - 2.0 * w) - 2.0 * o * sin(o) + cos(o));
    return b->power * area * cone;
}

static void sort_along(const LightBounds *bounds, int *order, int count, int axis)
{
    sort_bounds = bounds;
    sort_axis = axis;
    qsort(order, (size_t)count, sizeof *order, by_centre);
}

/* Orders order[0, count) and returns where to split it: the split along
 * an axis, between lights sorted by their centres, of least orientation
 * cost; at the median along the widest axis where the costs say nothing
 * (all zero: points) or where the depth left for the trail's 64 bits
 * calls for a balanced tree. */
static int split(const Build *b, int *order, int count, int depth)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            double c = b->bounds[order[i]].lower[k] + b->bounds[order[i]].upper[k];
            lo[k] = fmin(lo[k], c);
            hi[k] = fmax(hi[k], c);
        }
    int widest = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[widest] - lo[widest])
            widest = k;
    int levels = 0;
    while ((1 << levels) < count)
        ++levels;
    LightBounds *suffix = depth + levels < 56 ? malloc((size_t)count * sizeof *suffix) : NULL;
    double best = INFINITY;
    int best_axis = widest, best_split = count / 2;
    for (int axis = 0; suffix && axis < 3; ++axis) {
        sort_along(b->bounds, order, count, axis);
        suffix[count - 1] = b->bounds[order[count - 1]];
        for (int i = count - 2; i >= 0; --i)
            suffix[i] = light_bounds_union(&b->bounds[order[i]], &suffix[i + 1]);
        LightBounds prefix = b->bounds[order[0]];
        for (int k = 1; k < count; ++k) {
            double cost = orientation_cost(&prefix) + orientation_cost(&suffix[k]);
            if (cost < best) {
                best = cost;
                best_axis = axis;
                best_split = k;
            }
            prefix = light_bounds_union(&prefix, &b->bounds[order[k]]);
        }
    }
    free(suffix);
    if (!(best > 0.0 && best < INFINITY)) {
        best_axis = widest;
        best_split = count / 2;
    }
    sort_along(b->bounds, order, count, best_axis);
    return best_split;
}

/* The node for lights order[0, count), at depth `depth` along `trail`;
 * returns its bounds. */
static LightBounds build_node(Build *b, int *order, int count, uint64_t trail, int depth)
{
    int index = b->node_count++;
    if (count == 1) {
        const LightBounds *leaf = &b->bounds[order[0]];
        store_node(&b->nodes[index], leaf);
        b->nodes[index].second = ~(b->first_light + order[0]);
        b->trails[order[0]] = trail | (1ull << depth);
        return *leaf;
    }
    int half = split(b, order, count, depth);
    LightBounds first = build_node(b, order, half, trail, depth + 1);
    b->nodes[index].second = b->node_count;
    LightBounds second = build_node(b, order + half, count - half, trail | (1ull << depth), depth + 1);
    LightBounds both = light_bounds_union(&first, &second);
    int32_t second_index = b->nodes[index].second;
    store_node(&b->nodes[index], &both);
    b->nodes[index].second = second_index;
    return both;
}

int light_tree_build(const LightBounds *bounds, int count, int first_light, LightNode **nodes, int *node_count,
                     uint64_t **trails)
{
    *nodes = NULL;
    *trails = NULL;
    *node_count = 0;
    if (count <= 0)
        return 0;
    Build b = {bounds, first_light, malloc((size_t)(2 * count - 1) * sizeof(LightNode)), 0,
               malloc((size_t)count * sizeof(uint64_t))};
    int *order = malloc((size_t)count * sizeof *order);
    if (!b.nodes || !b.trails || !order) {
        free(b.nodes);
        free(b.trails);
        free(order);
        return -1;
    }
    for (int i = 0; i < count; ++i)
        order[i] = i;
    build_node(&b, order, count, 0u, 0);
    free(order);
    *nodes = b.nodes;
    *node_count = b.node_count;
    *trails = b.trails;
    return 0;
}
