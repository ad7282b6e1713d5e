#include "render/bvh.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BIN_COUNT 16
#define MAX_LEAF_SIZE BVH_WIDTH /* one triangle packet */
/* Past this depth, splits fall back to the object median, which halves the
 * count each level and so bounds the depth. */
#define SAH_DEPTH_LIMIT 48

typedef struct {
    float lower[3], upper[3];
} Box;

typedef struct {
    Box box;
    float centroid[3];
    int index;
} BuildItem;

/* A node of the binary tree: a leaf (count > 0) holds items [first, first +
 * count); an inner node has its left child next and its right at `first`. */
typedef struct {
    Box box;
    int first, count;
} BinaryNode;

typedef struct {
    BuildItem *items;
    BinaryNode *nodes;
    int node_count, node_capacity;
    int depth, largest_leaf;
    int instance_entry_need;     /* see Bvh */
    const Primitive *primitives; /* reordered */
    BvhNode *blocks;             /* the wide tree */
    int block_count, block_capacity;
} Builder;

static Box box_empty(void)
{
    Box b = {{FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}};
    return b;
}

static void box_grow_point(Box *b, const float *p)
{
    for (int i = 0; i < 3; ++i) {
        b->lower[i] = p[i] < b->lower[i] ? p[i] : b->lower[i];
        b->upper[i] = p[i] > b->upper[i] ? p[i] : b->upper[i];
    }
}

/* The union, per bound: growing by an empty box (an empty bin) changes
 * nothing, where growing by its corners as points would make it infinite. */
static void box_grow(Box *b, const Box *other)
{
    for (int i = 0; i < 3; ++i) {
        b->lower[i] = other->lower[i] < b->lower[i] ? other->lower[i] : b->lower[i];
        b->upper[i] = other->upper[i] > b->upper[i] ? other->upper[i] : b->upper[i];
    }
}

/* SAH cost of intersecting n primitives. A leaf is one 8-wide packet test,
 * but counting in fours (and a traversal cost of 0.5) keeps leaves tight:
 * measured faster than whole packets or single primitives, on the Cornell
 * box and on a 20k-triangle mesh. */
static float leaf_cost(int n)
{
    return (float)((n + 3) / 4);
}

static float box_area(const Box *b)
{
    float d[3];
    for (int i = 0; i < 3; ++i)
        d[i] = b->upper[i] > b->lower[i] ? b->upper[i] - b->lower[i] : 0.0f;
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

static Box primitive_box(const Primitive *p)
{
    Box b = box_empty();
    if ((p->kind & PRIM_KIND_MASK) == PRIM_INSTANCE) {
        box_grow_point(&b, p->a);
        box_grow_point(&b, p->b);
    } else if ((p->kind & PRIM_KIND_MASK) == PRIM_SPHERE) {
        for (int i = 0; i < 3; ++i) {
            b.lower[i] = p->a[i] - p->b[0];
            b.upper[i] = p->a[i] + p->b[0];
        }
    } else {
        float second[3], third[3];
        for (int i = 0; i < 3; ++i) {
            second[i] = p->a[i] + p->b[i];
            third[i] = p->a[i] + p->c[i];
        }
        box_grow_point(&b, p->a);
        box_grow_point(&b, second);
        box_grow_point(&b, third);
    }
    return b;
}

/* Whether a primitive's numbers and its box are finite (the box alone
 * misses a NaN, which every comparison growing it ignores). */
static int primitive_is_finite(const Primitive *p, const Box *box)
{
    int sphere = (p->kind & PRIM_KIND_MASK) == PRIM_SPHERE;
    for (int i = 0; i < 3; ++i)
        if (!isfinite(p->a[i]) || !isfinite(box->lower[i]) || !isfinite(box->upper[i]) ||
            (!sphere && (!isfinite(p->b[i]) || !isfinite(p->c[i]))))
            return 0;
    return !sphere || isfinite(p->b[0]);
}

/* Appends an element to a growing array; returns its index or -1. */
static int grow(void **array, int *count, int *capacity, size_t size)
{
    if (*count == *capacity) {
        int new_capacity = *capacity ? 2 * *capacity : 64;
        void *grown = realloc(*array, (size_t)new_capacity * size);
        if (!grown)
            return -1;
        *array = grown;
        *capacity = new_capacity;
    }
    return (*count)++;
}

static int new_node(Builder *b)
{
    return grow((void **)&b->nodes, &b->node_count, &b->node_capacity, sizeof *b->nodes);
}

static int new_block(Builder *b)
{
    int index = grow((void **)&b->blocks, &b->block_count, &b->block_capacity, sizeof *b->blocks);
    if (index >= 0)
        memset(&b->blocks[index], 0, sizeof *b->blocks);
    return index;
}

/* The bin of a centroid coordinate c in [lo, lo + span], in double: in
 * float, c - lo and span overflow to inf for coordinates beyond about
 * 1.7e38 and inf / inf is NaN, whose conversion to int is undefined. */
static int bin_of(float c, float lo, double span)
{
    double k = ((double)c - lo) / span * BIN_COUNT;
    return k >= BIN_COUNT ? BIN_COUNT - 1 : (k > 0.0 ? (int)k : 0);
}

/* qsort comparators by centroid along one axis, ties by index so the build
 * is deterministic. */
static int compare_along(const void *x, const void *y, int axis)
{
    const BuildItem *a = x, *b = y;
    if (a->centroid[axis] != b->centroid[axis])
        return a->centroid[axis] < b->centroid[axis] ? -1 : 1;
    return (a->index > b->index) - (a->index < b->index);
}
static int compare_x(const void *x, const void *y)
{
    return compare_along(x, y, 0);
}
static int compare_y(const void *x, const void *y)
{
    return compare_along(x, y, 1);
}
static int compare_z(const void *x, const void *y)
{
    return compare_along(x, y, 2);
}

/* Chooses a split of items [first, first + count): returns the count going
 * left (0 if a leaf is better) and the axis. */
static int choose_split(BuildItem *items, int count, const Box *bounds, int depth, int *axis_out)
{
    Box centroids = box_empty();
    for (int i = 0; i < count; ++i)
        box_grow_point(&centroids, items[i].centroid);
    int axis = 0;
    float extent = -1.0f;
    for (int i = 0; i < 3; ++i)
        if (centroids.upper[i] - centroids.lower[i] > extent) {
            extent = centroids.upper[i] - centroids.lower[i];
            axis = i;
        }
    *axis_out = axis;
    if (count <= MAX_LEAF_SIZE && (count <= 1 || extent <= 0.0f))
        return 0; /* identical centroids: nothing to split */
    if (extent <= 0.0f)
        return count / 2; /* identical centroids, too many for a leaf: halves by order, so leaves stay bounded */

    if (depth < SAH_DEPTH_LIMIT) {
        float best_cost = FLT_MAX;
        int best_axis = -1, best_bin = -1;
        for (int a = 0; a < 3; ++a) {
            float lo = centroids.lower[a];
            double span = (double)centroids.upper[a] - lo;
            if (span <= 0.0)
                continue;
            Box bin_box[BIN_COUNT];
            int bin_count[BIN_COUNT] = {0};
            for (int k = 0; k < BIN_COUNT; ++k)
                bin_box[k] = box_empty();
            for (int i = 0; i < count; ++i) {
                int k = bin_of(items[i].centroid[a], lo, span);
                bin_count[k]++;
                box_grow(&bin_box[k], &items[i].box);
            }
            /* Sweep from the right for suffix areas, then from the left. */
            float right_area[BIN_COUNT];
            int right_count[BIN_COUNT];
            Box acc = box_empty();
            int n = 0;
            for (int k = BIN_COUNT - 1; k > 0; --k) {
                box_grow(&acc, &bin_box[k]);
                n += bin_count[k];
                right_area[k] = box_area(&acc);
                right_count[k] = n;
            }
            acc = box_empty();
            n = 0;
            for (int k = 0; k < BIN_COUNT - 1; ++k) {
                box_grow(&acc, &bin_box[k]);
                n += bin_count[k];
                if (n == 0 || right_count[k + 1] == 0)
                    continue;
                float cost = box_area(&acc) * leaf_cost(n) + right_area[k + 1] * leaf_cost(right_count[k + 1]);
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = a;
                    best_bin = k;
                }
            }
        }
        float parent_area = box_area(bounds);
        float split_cost = parent_area > 0.0f ? 0.5f + best_cost / parent_area : FLT_MAX;
        if (best_axis >= 0 && (split_cost < leaf_cost(count) || count > MAX_LEAF_SIZE)) {
            float lo = centroids.lower[best_axis];
            double span = (double)centroids.upper[best_axis] - lo;
            int left = 0;
            for (int i = 0; i < count; ++i) {
                if (bin_of(items[i].centroid[best_axis], lo, span) <= best_bin) {
                    BuildItem t = items[i];
                    items[i] = items[left];
                    items[left++] = t;
                }
            }
            *axis_out = best_axis;
            return left;
        }
        if (count <= MAX_LEAF_SIZE)
            return 0;
    }
    /* Object median along the widest centroid axis. */
    int (*const compare[3])(const void *, const void *) = {compare_x, compare_y, compare_z};
    qsort(items, (size_t)count, sizeof *items, compare[axis]);
    return count / 2;
}

static int build_node(Builder *b, int first, int count, int depth)
{
    int index = new_node(b);
    if (index < 0)
        return -1;
    if (depth > b->depth)
        b->depth = depth;
    Box bounds = box_empty();
    for (int i = first; i < first + count; ++i)
        box_grow(&bounds, &b->items[i].box);
    int axis = 0;
    int left = choose_split(b->items + first, count, &bounds, depth, &axis);
    BinaryNode node = {bounds, 0, 0};
    if (left == 0 || left == count) {
        node.first = first;
        node.count = count;
        if (count > b->largest_leaf)
            b->largest_leaf = count;
        b->nodes[index] = node;
        return index;
    }
    if (build_node(b, first, left, depth + 1) < 0)
        return -1;
    int right = build_node(b, first + left, count - left, depth + 1);
    if (right < 0)
        return -1;
    node.first = right;
    node.count = 0;
    b->nodes[index] = node;
    return index;
}

/* Turns binary node `index` (the root may be a leaf) into a wide node: its
 * children, with the largest inner child replaced by its two while there is
 * room. Returns the wide node's block, or -1 out of memory; raises
 * *stack_need to the most traversal stack entries the subtree needs, given
 * `stack_base` entries below (a node pushes its children, then pops one),
 * and b->instance_entry_need (a popped leaf's entry is replaced by one per
 * instance in it, and the one entered by the entry that leaves it). */
static int collapse(Builder *b, int index, int stack_base, int *stack_need)
{
    int slots[BVH_WIDTH] = {index}, n = 1;
    if (b->nodes[index].count == 0) {
        slots[0] = index + 1;
        slots[n++] = b->nodes[index].first;
    }
    while (n < BVH_WIDTH) {
        int widest = -1;
        float widest_area = -1.0f;
        for (int j = 0; j < n; ++j)
            if (b->nodes[slots[j]].count == 0 && box_area(&b->nodes[slots[j]].box) > widest_area) {
                widest = j;
                widest_area = box_area(&b->nodes[slots[j]].box);
            }
        if (widest < 0)
            break;
        int parent = slots[widest];
        slots[widest] = parent + 1;
        slots[n++] = b->nodes[parent].first;
    }
    if (stack_base + n > *stack_need)
        *stack_need = stack_base + n;
    int block = new_block(b);
    if (block < 0)
        return -1;
    BvhWideNode wide; /* filled here as the recursion may move b->blocks */
    memset(&wide, 0, sizeof wide);
    for (int j = 0; j < BVH_WIDTH; ++j) {
        wide.count[j] = -1;
        wide.packet[j] = -1;
    }
    for (int j = 0; j < n; ++j) {
        const BinaryNode *child = &b->nodes[slots[j]];
        for (int i = 0; i < 3; ++i) {
            wide.lower[i][j] = child->box.lower[i];
            wide.upper[i][j] = child->box.upper[i];
        }
        wide.count[j] = child->count;
        if (child->count == 0) {
            wide.child[j] = collapse(b, slots[j], stack_base + n - 1, stack_need);
            if (wide.child[j] < 0)
                return -1;
            continue;
        }
        wide.child[j] = child->first;
        int instances = 0;
        for (int k = child->first; k < child->first + child->count; ++k)
            instances += (b->primitives[k].kind & PRIM_KIND_MASK) == PRIM_INSTANCE;
        if (instances > 0 && stack_base + n - 1 + instances > b->instance_entry_need)
            b->instance_entry_need = stack_base + n - 1 + instances;
        int triangles = 1;
        for (int k = child->first; k < child->first + child->count; ++k)
            triangles &=
                (b->primitives[k].kind & PRIM_KIND_MASK) == PRIM_TRIANGLE && !(b->primitives[k].kind & PRIM_ALPHA);
        if (!triangles || child->count > BVH_WIDTH)
            continue; /* spheres, instances and cut-outs: one by one */
        int packet = new_block(b);
        if (packet < 0)
            return -1;
        TrianglePacket *p = &b->blocks[packet].triangles;
        for (int k = 0; k < child->count; ++k)
            for (int i = 0; i < 3; ++i) {
                p->a[i][k] = b->primitives[child->first + k].a[i];
                p->b[i][k] = b->primitives[child->first + k].b[i];
                p->c[i][k] = b->primitives[child->first + k].c[i];
            }
        wide.packet[j] = packet;
    }
    b->blocks[block].node = wide;
    return block;
}

int bvh_build(const Primitive *primitives, int count, Bvh *bvh, char *error, size_t error_size)
{
    memset(bvh, 0, sizeof *bvh);
    Builder b = {0};
    b.items = malloc((size_t)(count > 0 ? count : 1) * sizeof *b.items);
    bvh->primitives = malloc((size_t)(count > 0 ? count : 1) * sizeof *bvh->primitives);
    bvh->order = malloc((size_t)(count > 0 ? count : 1) * sizeof *bvh->order);
    if (!b.items || !bvh->primitives || !bvh->order)
        goto out_of_memory;
    for (int i = 0; i < count; ++i) {
        Box *box = &b.items[i].box;
        *box = primitive_box(&primitives[i]);
        b.items[i].index = i;
        if (!primitive_is_finite(&primitives[i], box)) {
            snprintf(error, error_size, "primitive %d has non-finite bounds (NaN, or beyond the float range)", i);
            goto failed;
        }
        for (int k = 0; k < 3; ++k)
            b.items[i].centroid[k] = 0.5f * box->lower[k] + 0.5f * box->upper[k]; /* the sum may overflow */
    }
    if (count > 0 && build_node(&b, 0, count, 0) < 0)
        goto out_of_memory;
    if (b.depth >= BVH_MAX_DEPTH) {
        snprintf(error, error_size, "BVH depth %d exceeds the limit %d", b.depth, BVH_MAX_DEPTH);
        goto failed;
    }
    for (int i = 0; i < count; ++i) {
        bvh->order[i] = b.items[i].index;
        bvh->primitives[i] = primitives[b.items[i].index];
    }
    b.primitives = bvh->primitives;
    int stack_need = 0;
    if (count == 0) { /* a root without children */
        int root = new_block(&b);
        if (root < 0)
            goto out_of_memory;
        for (int j = 0; j < BVH_WIDTH; ++j)
            b.blocks[root].node.count[j] = -1;
    } else if (collapse(&b, 0, 0, &stack_need) < 0) {
        goto out_of_memory;
    }
    bvh->nodes = b.blocks;
    bvh->node_count = b.block_count;
    bvh->primitive_count = count;
    bvh->depth = b.depth;
    bvh->largest_leaf = b.largest_leaf;
    bvh->stack_need = stack_need;
    bvh->instance_entry_need = b.instance_entry_need;
    free(b.items);
    free(b.nodes);
    return 0;
out_of_memory:
    snprintf(error, error_size, "out of memory building the BVH over %d primitives", count);
failed:
    free(b.items);
    free(b.nodes);
    free(b.blocks);
    bvh_destroy(bvh);
    return -1;
}

void bvh_destroy(Bvh *bvh)
{
    free(bvh->nodes);
    free(bvh->primitives);
    free(bvh->order);
    memset(bvh, 0, sizeof *bvh);
}
