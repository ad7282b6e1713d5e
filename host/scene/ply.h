/* A PLY mesh reader for Shape "plymesh": ASCII and binary (little and big
 * endian) files with a "vertex" element (x, y, z as float or double; nx, ny,
 * nz read when all three are present, and texture coordinates) and a "face" element whose
 * vertex_indices (or vertex_index) list holds triangles or quads, quads
 * split into two triangles. Other elements and properties are skipped. */
#ifndef HOST_SCENE_PLY_H
#define HOST_SCENE_PLY_H

#include "scene/shape_mesh.h"

/* positions (finite) and normals as stored, uvs, 3 indices per triangle
 * (each below vertex_count); free with shape_mesh_free. */
typedef ShapeMesh PlyMesh;

/* Returns 0, or -1 with a message (naming the header line or the element
 * and item that is wrong, without the path) in `error`. */
int ply_read(const char *path, PlyMesh *mesh, char *error, size_t error_size);

#endif
