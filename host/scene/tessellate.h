/* The pbrt-v4 shapes the renderer has no primitive for ("disk", "cylinder",
 * "bilinearmesh", "loopsubdiv"), built as object-space triangle meshes for
 * the parser's mesh path (world transform, orientation, degenerate
 * triangles, area lights). Tessellation and accuracy: docs/scenes.md. */
#ifndef HOST_SCENE_TESSELLATE_H
#define HOST_SCENE_TESSELLATE_H

#include "scene/params.h"
#include "scene/shape_mesh.h"

#include <stddef.h>
#include <stdint.h>

/* Builds a shape from its parameters (read and checked here; unknown ones
 * left for params_check_unused). Returns 0, or -1 with a "file:line:
 * Shape "...": ..." error (`line` is the directive's) and *mesh empty. */
typedef int (*ShapeBuilder)(ParamList *params, int line, ShapeMesh *mesh);

/* The builder for a shape name, or NULL. */
ShapeBuilder shape_builder(const char *name);

/* Converts `per_item`-tuples of vertex indices (an "integer indices" array)
 * to uint32, checking each is in [0, vertex_count). Returns 0 or -1. */
int shape_read_indices(ParamList *params, const Param *indices, size_t vertex_count, size_t per_item, uint32_t *out);

/* Reads pbrt's per-vertex texture coordinates, "point2 uv" (or "point2 st",
 * pbrt-v3's name), for vertex_count vertices: 1 with *uv set, 0 when
 * absent, -1 on an error (both given, or a count that does not match). */
int shape_read_uv(ParamList *params, size_t vertex_count, const Param **uv);

#endif
