/* Loop subdivision on index arrays: each level finds the edges by sorting
 * half-edges, moves the old ("even") vertices and adds one ("odd") vertex
 * per edge, and splits each triangle into four. Computed in double. */
#include "scene/loop_subdiv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define NO_VERTEX UINT32_MAX

typedef struct {
    double *p; /* 3 per vertex */
    size_t vertex_count;
    uint32_t *tri; /* 3 per face */
    size_t face_count;
} Level;

typedef struct {
    uint32_t a, b;        /* endpoints */
    uint32_t opposite[2]; /* each face's third vertex; [1] is NO_VERTEX on a boundary */
} Edge;

typedef struct {
    uint32_t lo, hi;
    uint32_t corner; /* 3 * face + k: the edge from corner k to corner k + 1 */
} HalfEdge;

typedef struct {
    Edge *edges;
    size_t edge_count;
    uint32_t *edge_of; /* per corner: the edge from it to the next corner */
} Edges;

static void level_free(Level *m)
{
    free(m->p);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

static void edges_free(Edges *e)
{
    free(e->edges);
    free(e->edge_of);
    memset(e, 0, sizeof *e);
}

static int compare_half_edges(const void *x, const void *y)
{
    const HalfEdge *a = x, *b = y;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return 0;
}

/* Pairs up the faces' edges. Returns 0, or -1 with a message: an edge in
 * more than two faces, or two faces that traverse it the same way. */
static int find_edges(const Level *m, Edges *out, char *error, size_t error_size)
{
    size_t corners = 3 * m->face_count;
    HalfEdge *half = malloc(corners * sizeof *half + 1);
    out->edges = malloc(corners * sizeof *out->edges + 1);
    out->edge_of = malloc(corners * sizeof *out->edge_of + 1);
    out->edge_count = 0;
    if (!half || !out->edges || !out->edge_of) {
        free(half);
        snprintf(error, error_size, "out of memory");
        return -1;
    }
    for (size_t c = 0; c < corners; ++c) {
        uint32_t from = m->tri[c], to = m->tri[c - c % 3 + (c + 1) % 3];
        half[c] = (HalfEdge){from < to ? from : to, from < to ? to : from, (uint32_t)c};
    }
    qsort(half, corners, sizeof *half, compare_half_edges);
    for (size_t i = 0; i < corners;) {
        size_t j = i + 1;
        while (j < corners && compare_half_edges(&half[i], &half[j]) == 0)
            ++j;
        if (j - i > 2) {
            snprintf(error, error_size,
                     "the edge between vertices %u and %u is in %zu triangles (Loop subdivision needs a manifold "
                     "mesh)",
                     half[i].lo, half[i].hi, j - i);
            free(half);
            return -1;
        }
        Edge *e = &out->edges[out->edge_count];
        e->opposite[1] = NO_VERTEX;
        for (size_t k = i; k < j; ++k) {
            uint32_t c = half[k].corner, first = (uint32_t)(c - c % 3);
            uint32_t from = m->tri[c], to = m->tri[first + (c + 1) % 3];
            if (k == i) {
                e->a = from;
                e->b = to;
            } else if (from != e->b) {
                snprintf(error, error_size,
                         "the two triangles at the edge between vertices %u and %u are wound in the same direction "
                         "(Loop subdivision needs consistently oriented triangles)",
                         half[i].lo, half[i].hi);
                free(half);
                return -1;
            }
            e->opposite[k - i] = m->tri[first + (c + 2) % 3];
            out->edge_of[c] = (uint32_t)out->edge_count;
        }
        out->edge_count++;
        i = j;
    }
    free(half);
    return 0;
}

/* Per vertex: the sum of its neighbours, their number, and the sum and
 * number of its neighbours along boundary edges. */
typedef struct {
    double *sum, *boundary_sum; /* 3 per vertex */
    uint32_t *valence, *boundary_count;
} Neighbours;

static void neighbours_free(Neighbours *n)
{
    free(n->sum);
    free(n->boundary_sum);
    free(n->valence);
    free(n->boundary_count);
}

static int gather_neighbours(const Level *m, const Edges *e, Neighbours *n)
{
    size_t v = m->vertex_count;
    n->sum = calloc(3 * v + 1, sizeof *n->sum);
    n->boundary_sum = calloc(3 * v + 1, sizeof *n->boundary_sum);
    n->valence = calloc(v + 1, sizeof *n->valence);
    n->boundary_count = calloc(v + 1, sizeof *n->boundary_count);
    if (!n->sum || !n->boundary_sum || !n->valence || !n->boundary_count)
        return -1;
    for (size_t i = 0; i < e->edge_count; ++i) {
        uint32_t ends[2] = {e->edges[i].a, e->edges[i].b};
        int boundary = e->edges[i].opposite[1] == NO_VERTEX;
        for (int s = 0; s < 2; ++s) {
            const double *other = m->p + 3 * (size_t)ends[1 - s];
            for (int k = 0; k < 3; ++k) {
                n->sum[3 * (size_t)ends[s] + (size_t)k] += other[k];
                if (boundary)
                    n->boundary_sum[3 * (size_t)ends[s] + (size_t)k] += other[k];
            }
            n->valence[ends[s]]++;
            n->boundary_count[ends[s]] += (uint32_t)boundary;
        }
    }
    return 0;
}

/* pbrt's Loop weight for an interior vertex of valence n (Warren's). */
static double loop_beta(uint32_t n)
{
    return n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
}

/* (1 - n w) p + w sum, or on a boundary (1 - 2 wb) p + wb boundary_sum. */
static void weigh(const Neighbours *n, size_t v, const double *p, double interior_weight, double boundary_weight,
                  double *out)
{
    int boundary = n->boundary_count[v] > 0;
    double w = boundary ? boundary_weight : interior_weight;
    double centre = 1.0 - (boundary ? 2.0 : (double)n->valence[v]) * w;
    const double *sum = boundary ? n->boundary_sum + 3 * v : n->sum + 3 * v;
    for (int k = 0; k < 3; ++k)
        out[k] = n->valence[v] == 0 ? p[k] : centre * p[k] + w * sum[k];
}

/* One level of subdivision of *m into *next. */
static int subdivide_once(const Level *m, const Edges *e, const Neighbours *n, Level *next)
{
    next->vertex_count = m->vertex_count + e->edge_count;
    next->face_count = 4 * m->face_count;
    next->p = malloc(3 * next->vertex_count * sizeof *next->p + 1);
    next->tri = malloc(3 * next->face_count * sizeof *next->tri + 1);
    if (!next->p || !next->tri)
        return -1;
    for (size_t v = 0; v < m->vertex_count; ++v)
        weigh(n, v, m->p + 3 * v, loop_beta(n->valence[v]), 1.0 / 8.0, next->p + 3 * v);
    for (size_t i = 0; i < e->edge_count; ++i) {
        const Edge *edge = &e->edges[i];
        const double *a = m->p + 3 * (size_t)edge->a, *b = m->p + 3 * (size_t)edge->b;
        double *out = next->p + 3 * (m->vertex_count + i);
        for (int k = 0; k < 3; ++k) {
            if (edge->opposite[1] == NO_VERTEX)
                out[k] = 0.5 * (a[k] + b[k]);
            else
                out[k] = 3.0 / 8.0 * (a[k] + b[k]) + 1.0 / 8.0 *
                                                         (m->p[3 * (size_t)edge->opposite[0] + (size_t)k] +
                                                          m->p[3 * (size_t)edge->opposite[1] + (size_t)k]);
        }
    }
    for (size_t f = 0; f < m->face_count; ++f) {
        const uint32_t *v = m->tri + 3 * f;
        uint32_t mid[3]; /* mid[k]: the new vertex on the edge from corner k to k + 1 */
        for (int k = 0; k < 3; ++k)
            mid[k] = (uint32_t)(m->vertex_count + e->edge_of[3 * f + (size_t)k]);
        const uint32_t children[4][3] = {
            {v[0], mid[0], mid[2]}, {mid[0], v[1], mid[1]}, {mid[2], mid[1], v[2]}, {mid[0], mid[1], mid[2]}};
        memcpy(next->tri + 12 * f, children, sizeof children);
    }
    return 0;
}

/* The faces around each vertex, as corner numbers (3 * face + k). */
typedef struct {
    size_t *start; /* vertex v's corners: corner[start[v] .. start[v + 1]) */
    uint32_t *corner;
} Incidence;

static int build_incidence(const Level *m, Incidence *inc)
{
    inc->start = calloc(m->vertex_count + 2, sizeof *inc->start);
    inc->corner = malloc(3 * m->face_count * sizeof *inc->corner + 1);
    if (!inc->start || !inc->corner)
        return -1;
    for (size_t c = 0; c < 3 * m->face_count; ++c)
        inc->start[m->tri[c] + 2]++;
    for (size_t v = 0; v < m->vertex_count; ++v)
        inc->start[v + 2] += inc->start[v + 1];
    for (size_t c = 0; c < 3 * m->face_count; ++c)
        inc->corner[inc->start[m->tri[c] + 1]++] = (uint32_t)c;
    return 0;
}

/* Writes v's neighbours into ring in pbrt's one-ring order: around an
 * interior vertex from face to face across the edge to each face's next
 * corner; around a boundary vertex from one boundary neighbour to the other
 * the opposite way. Returns the count (0 for an unused vertex), or -1 when
 * its faces do not form one fan (two cones meeting at a vertex). */
static int vertex_ring(const Level *m, const Incidence *inc, size_t v, uint32_t *ring, int *boundary)
{
    const uint32_t *corners = inc->corner + inc->start[v];
    size_t count = inc->start[v + 1] - inc->start[v];
    if (count == 0)
        return 0;
#define NEXT_OF(c) m->tri[(c) - (c) % 3 + ((c) + 1) % 3]
#define PREV_OF(c) m->tri[(c) - (c) % 3 + ((c) + 2) % 3]
    /* A fan's first face (on a boundary) has a previous corner that is no face's next corner. */
    size_t start = 0;
    *boundary = 0;
    for (size_t i = 0; i < count && !*boundary; ++i) {
        int follows = 0;
        for (size_t j = 0; j < count && !follows; ++j)
            follows = NEXT_OF(corners[j]) == PREV_OF(corners[i]);
        if (!follows) {
            start = i;
            *boundary = 1;
        }
    }
    size_t n = 0, visited = 0, face = start;
    if (*boundary)
        ring[n++] = PREV_OF(corners[start]);
    for (;;) {
        ring[n++] = NEXT_OF(corners[face]);
        if (++visited > count)
            return -1;
        size_t following = count;
        for (size_t j = 0; j < count && following == count; ++j)
            if (PREV_OF(corners[j]) == NEXT_OF(corners[face]))
                following = j;
        if (following == count || following == start)
            break;
        face = following;
    }
#undef NEXT_OF
#undef PREV_OF
    if (visited != count)
        return -1;
    for (size_t i = 0; *boundary && i < n / 2; ++i) {
        uint32_t t = ring[i];
        ring[i] = ring[n - 1 - i];
        ring[n - 1 - i] = t;
    }
    return (int)n;
}

/* Checks every vertex's faces form one fan (at the input level). */
static int check_fans(const Level *m, char *error, size_t error_size)
{
    Incidence inc = {0};
    uint32_t *ring = malloc((3 * m->face_count + 1) * sizeof *ring);
    int result = ring && build_incidence(m, &inc) == 0 ? 0 : -1;
    if (result)
        snprintf(error, error_size, "out of memory");
    for (size_t v = 0; result == 0 && v < m->vertex_count; ++v) {
        int boundary;
        if (vertex_ring(m, &inc, v, ring, &boundary) < 0) {
            snprintf(error, error_size,
                     "the triangles around vertex %zu do not form one fan (Loop subdivision needs a manifold mesh)", v);
            result = -1;
        }
    }
    free(ring);
    free(inc.start);
    free(inc.corner);
    return result;
}

/* pbrt's limit tangents from the ordered ring; their cross product is the normal. */
static void limit_normal(const double *p, const double *positions, const uint32_t *ring, int n, int boundary,
                         double normal[3])
{
    double s[3] = {0, 0, 0}, t[3] = {0, 0, 0};
#define RING(i, k) (positions[3 * (size_t)ring[i] + (size_t)(k)] - p[k])
    for (int k = 0; k < 3; ++k) {
        if (!boundary) {
            for (int j = 0; j < n; ++j) {
                s[k] += cos(2.0 * PI * j / n) * RING(j, k);
                t[k] += sin(2.0 * PI * j / n) * RING(j, k);
            }
            continue;
        }
        s[k] = RING(n - 1, k) - RING(0, k);
        if (n == 2)
            t[k] = RING(0, k) + RING(1, k);
        else if (n == 3)
            t[k] = RING(1, k);
        else if (n == 4)
            t[k] = -RING(0, k) + 2.0 * RING(1, k) + 2.0 * RING(2, k) - RING(3, k);
        else {
            double theta = PI / (n - 1);
            t[k] = sin(theta) * (RING(0, k) + RING(n - 1, k));
            for (int j = 1; j < n - 1; ++j)
                t[k] += (2.0 * cos(theta) - 2.0) * sin(j * theta) * RING(j, k);
            t[k] = -t[k];
        }
    }
#undef RING
    normal[0] = s[1] * t[2] - s[2] * t[1];
    normal[1] = s[2] * t[0] - s[0] * t[2];
    normal[2] = s[0] * t[1] - s[1] * t[0];
}

/* Pushes the final level to the limit surface and writes *out. */
static int write_limit_mesh(const Level *m, const Neighbours *n, ShapeMesh *out)
{
    Incidence inc = {0};
    double *limit = malloc(3 * m->vertex_count * sizeof *limit + 1);
    uint32_t *ring = malloc((3 * m->face_count + 1) * sizeof *ring);
    out->vertex_count = m->vertex_count;
    out->index_count = 3 * m->face_count;
    out->positions = malloc(3 * m->vertex_count * sizeof *out->positions + 1);
    out->normals = malloc(3 * m->vertex_count * sizeof *out->normals + 1);
    out->indices = malloc(out->index_count * sizeof *out->indices + 1);
    int result =
        limit && ring && out->positions && out->normals && out->indices && build_incidence(m, &inc) == 0 ? 0 : -1;
    for (size_t v = 0; result == 0 && v < m->vertex_count; ++v) {
        uint32_t valence = n->valence[v];
        double gamma = valence ? 1.0 / (valence + 3.0 / (8.0 * loop_beta(valence))) : 0.0;
        weigh(n, v, m->p + 3 * v, gamma, 1.0 / 5.0, limit + 3 * v);
    }
    for (size_t v = 0; result == 0 && v < m->vertex_count; ++v) {
        int boundary = 0, count = vertex_ring(m, &inc, v, ring, &boundary);
        double normal[3] = {0, 0, 0};
        if (count > 0)
            limit_normal(limit + 3 * v, limit, ring, count, boundary, normal);
        for (int k = 0; k < 3; ++k) {
            out->positions[3 * v + (size_t)k] = (float)limit[3 * v + (size_t)k];
            out->normals[3 * v + (size_t)k] = (float)normal[k];
        }
    }
    /* Wound against the input, to agree with pbrt's limit normals. */
    for (size_t f = 0; result == 0 && f < m->face_count; ++f) {
        out->indices[3 * f] = m->tri[3 * f];
        out->indices[3 * f + 1] = m->tri[3 * f + 2];
        out->indices[3 * f + 2] = m->tri[3 * f + 1];
    }
    free(limit);
    free(ring);
    free(inc.start);
    free(inc.corner);
    return result;
}

int loop_subdivide(const float *positions, size_t vertex_count, const uint32_t *indices, size_t triangle_count,
                   int levels, ShapeMesh *out, char *error, size_t error_size)
{
    memset(out, 0, sizeof *out);
    for (size_t f = 0; f < triangle_count; ++f) {
        const uint32_t *t = indices + 3 * f;
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
            snprintf(error, error_size, "triangle %zu repeats a vertex (%u %u %u)", f, t[0], t[1], t[2]);
            return -1;
        }
    }
    double made = (double)triangle_count * pow(4.0, levels);
    if (made > (double)SHAPE_MAX_TRIANGLES) {
        snprintf(error, error_size, "%d levels make %.4g triangles from %zu, over the limit of %zu", levels, made,
                 triangle_count, SHAPE_MAX_TRIANGLES);
        return -1;
    }
    Level m = {malloc(3 * vertex_count * sizeof(double) + 1), vertex_count,
               malloc(3 * triangle_count * sizeof(uint32_t) + 1), triangle_count};
    if (!m.p || !m.tri) {
        level_free(&m);
        snprintf(error, error_size, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < 3 * vertex_count; ++i)
        m.p[i] = positions[i];
    memcpy(m.tri, indices, 3 * triangle_count * sizeof *indices);
    int result = 0;
    for (int level = 0; result == 0; ++level) {
        Edges e = {0};
        Neighbours n = {0};
        result = find_edges(&m, &e, error, error_size);
        if (result == 0 && level == 0)
            result = check_fans(&m, error, error_size);
        if (result == 0 && gather_neighbours(&m, &e, &n)) {
            snprintf(error, error_size, "out of memory");
            result = -1;
        }
        int last = level == levels;
        Level next = {0};
        if (result == 0 && (last ? write_limit_mesh(&m, &n, out) : subdivide_once(&m, &e, &n, &next))) {
            snprintf(error, error_size, "out of memory");
            result = -1;
        }
        edges_free(&e);
        neighbours_free(&n);
        level_free(&m);
        m = next;
        if (last)
            break;
    }
    level_free(&m);
    if (result)
        shape_mesh_free(out);
    return result;
}
