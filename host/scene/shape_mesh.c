#include "scene/shape_mesh.h"

#include <stdlib.h>
#include <string.h>

void shape_mesh_free(ShapeMesh *mesh)
{
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->uvs);
    free(mesh->indices);
    free(mesh->parts);
    memset(mesh, 0, sizeof *mesh);
}
