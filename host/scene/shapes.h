/* The pbrt-v4 shapes the renderer has no primitive for ("disk", "cylinder",
 * "bilinearmesh", "loopsubdiv"), built as object-space triangle meshes for
 * the parser's mesh path (world transform, orientation, degenerate
 * triangles, area lights). Tessellation and accuracy: README.md here. */
#ifndef HOST_SCENE_SHAPES_H
#define HOST_SCENE_SHAPES_H

#include "scene/params.h"

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

/* Builds a shape from its parameters (read and checked here; unknown ones
 * left for params_check_unused). Returns 0, or -1 with a "file:line:
 * Shape "...": ..." error (`line` is the directive's) and *mesh empty. */
typedef int (*ShapeBuilder)(ParamList *params, int line, ShapeMesh *mesh);

/* The builder for a shape name, or NULL. */
ShapeBuilder shape_builder(const char *name);

void shape_mesh_free(ShapeMesh *mesh);

/* Converts `per_item`-tuples of vertex indices (an "integer indices" array)
 * to uint32, checking each is in [0, vertex_count). Returns 0 or -1. */
int shape_read_indices(ParamList *params, const Param *indices, size_t vertex_count, size_t per_item, uint32_t *out);

/* Reads pbrt's per-vertex texture coordinates, "point2 uv" (or "point2 st",
 * pbrt-v3's name), for vertex_count vertices: 1 with *uv set, 0 when
 * absent, -1 on an error (both given, or a count that does not match). */
int shape_read_uv(ParamList *params, size_t vertex_count, const Param **uv);

#endif
