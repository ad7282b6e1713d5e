/* libFuzzer harness: a PLY file -> ply_read (host/scene/ply.c). A mesh read
 * without error must own as many values as its counts say. */
#include "fuzz_input.h"
#include "scene/ply.h"

static const char *ply_path;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    ply_path = fuzz_input_path("mesh.ply");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_write_file(ply_path, data, size);
    PlyMesh mesh;
    char error[256];
    if (ply_read(ply_path, &mesh, error, sizeof error) == 0) {
        fuzz_touch(mesh.positions, 3 * mesh.vertex_count * sizeof *mesh.positions);
        if (mesh.normals)
            fuzz_touch(mesh.normals, 3 * mesh.vertex_count * sizeof *mesh.normals);
        fuzz_touch(mesh.indices, mesh.index_count * sizeof *mesh.indices);
    }
    shape_mesh_free(&mesh);
    return 0;
}
