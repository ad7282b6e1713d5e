/* libFuzzer harness: scene text -> scene parser (host/scene) -> conversion
 * to the kernels' scene (host/render/scene_convert.c) -> BVH build and light
 * distribution (render_scene_finalize), without OpenCL. The input is the
 * main scene file; a small valid mesh.ply lies beside it for seeds that use
 * Shape "plymesh". Unsupported features are allowed (skipped or substituted)
 * so that more of the reader runs. */
#include "fuzz_input.h"
#include "render/render_scene.h"
#include "render/scene_convert.h"

static const char *scene_path;

static const char mesh_ply[] = "ply\n"
                               "format ascii 1.0\n"
                               "element vertex 4\n"
                               "property float x\n"
                               "property float y\n"
                               "property float z\n"
                               "element face 1\n"
                               "property list uchar int vertex_indices\n"
                               "end_header\n"
                               "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                               "4 0 1 2 3\n";

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    fuzz_write_file(fuzz_input_path("mesh.ply"), mesh_ply, sizeof mesh_ply - 1);
    scene_path = fuzz_input_path("scene.pbrt");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_write_file(scene_path, data, size);
    RenderScene scene;
    SceneSummary summary;
    char error[1024];
    if (scene_convert_load(scene_path, 1, 0, 0, 1, &scene, &summary, error, sizeof error) == 0) {
        render_scene_finalize(&scene, error, sizeof error);
        render_scene_destroy(&scene);
    }
    return 0;
}
