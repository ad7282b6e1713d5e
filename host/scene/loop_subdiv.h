/* Loop subdivision as pbrt-v4 applies it to Shape "loopsubdiv": `levels`
 * rounds of Loop's rules (pbrt's weights: beta = 3/16 at valence 3, else
 * 3/(8n); boundary edges and vertices follow the boundary curve), then
 * every vertex pushed to its limit position, with the limit normal from
 * the limit tangents. */
#ifndef HOST_SCENE_LOOP_SUBDIV_H
#define HOST_SCENE_LOOP_SUBDIV_H

#include "scene/shape_mesh.h"

#include <stddef.h>
#include <stdint.h>

/* Subdivides the triangles (indices below vertex_count) `levels` times into
 * *out: limit positions, limit normals, no uv. pbrt's limit normal points
 * against the input's winding (cross(v1 - v0, v2 - v0)); the output's
 * triangles are wound to agree with it, as pbrt turns a mesh's geometric
 * normal toward its vertex normals. Returns 0, or -1 with a message (a
 * non-manifold or inconsistently oriented input, more than
 * SHAPE_MAX_TRIANGLES triangles, out of memory) in `error`. */
int loop_subdivide(const float *positions, size_t vertex_count, const uint32_t *indices, size_t triangle_count,
                   int levels, ShapeMesh *out, char *error, size_t error_size);

#endif
