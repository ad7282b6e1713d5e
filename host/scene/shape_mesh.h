/* A shape as an object-space triangle mesh: what the shape builders
 * (tessellate.c), Loop subdivision and the PLY reader make, and the parser
 * takes to world space. */
#ifndef HOST_SCENE_SHAPE_MESH_H
#define HOST_SCENE_SHAPE_MESH_H

#include <stddef.h>
#include <stdint.h>

/* The most triangles one shape may become, 2^22 (4.2 million: pbrt's
 * killeroo subdivided 4 levels; each level multiplies the count by 4). Loop
 * subdivision takes about 200 bytes a triangle at its peak, and the
 * renderer's copy and BVH more: beyond this a mistyped "levels" (or many
 * curved bilinear patches) would exhaust memory instead of rendering. */
#define SHAPE_MAX_TRIANGLES ((size_t)1 << 22)

typedef struct {
    float *positions; /* 3 per vertex, object space */
    float *normals;   /* 3 per vertex, or NULL: flat */
    float *uvs;       /* 2 per vertex, or NULL */
    size_t vertex_count;
    uint32_t *indices; /* 3 per triangle; the front is cross(v1 - v0, v2 - v0) */
    size_t index_count;
    /* Which of pbrt-v4's shapes each triangle belongs to (pbrt-v4 makes an
     * area light per shape, and "power" is each one's): parts, one per
     * triangle, non-decreasing (a bilinear patch, a PLY quad), or NULL; with
     * parts NULL, one_part says the mesh is one shape (a disk, a cylinder),
     * else each triangle is one (a triangle mesh, a subdivision surface). */
    uint32_t *parts;
    int one_part;
} ShapeMesh;

/* Frees the arrays and empties the mesh. */
void shape_mesh_free(ShapeMesh *mesh);

#endif
