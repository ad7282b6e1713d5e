/* A PLY mesh reader for Shape "plymesh": ASCII and binary (little and big
 * endian) files with a "vertex" element (x, y, z as float or double; nx, ny,
 * nz read when all three are present, and texture coordinates) and a "face" element whose
 * vertex_indices (or vertex_index) list holds triangles or quads, quads
 * split into two triangles. Other elements and properties are skipped. */
#ifndef HOST_SCENE_PLY_H
#define HOST_SCENE_PLY_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    float *positions; /* 3 per vertex, as stored; finite */
    float *normals;   /* 3 per vertex, or NULL */
    float *uvs;       /* 2 per vertex (u v, s t, texture_u texture_v or texture_s texture_t), or NULL */
    size_t vertex_count;
    uint32_t *indices; /* 3 per triangle, each below vertex_count */
    size_t triangle_count;
} PlyMesh;

/* Returns 0, or -1 with a message (naming the header line or the element
 * and item that is wrong, without the path) in `error`. */
int ply_read(const char *path, PlyMesh *mesh, char *error, size_t error_size);
void ply_mesh_destroy(PlyMesh *mesh);

#endif
