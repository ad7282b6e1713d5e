/* From a pbrt-v4 scene file to the kernels' scene: reads it with the scene
 * parser (host/scene) and flattens shapes, materials and lights into a
 * RenderScene. */
#ifndef HOST_RENDER_SCENE_CONVERT_H
#define HOST_RENDER_SCENE_CONVERT_H

#include "render/render_scene.h"
#include "scene/scene.h"

#include <stddef.h>
#include <stdint.h>

/* What the renderer reports or uses from the scene besides its geometry. */
typedef struct {
    char film_filename[1024]; /* Film "filename", "" if none */
    uint64_t pixel_samples;   /* Sampler "pixelsamples", 0 if none */
    char sampler[64];         /* the Sampler's name, "" if none */
    int regularize;           /* Integrator "regularize" was set */
    int light_subpaths;       /* the scene's Integrator: SCENE_BDPT, SCENE_LIGHTPATH or 0 (the path tracer) */
    size_t texture_bytes;     /* texels (8-bit and float) and decoding tables uploaded for textures */
} SceneSummary;

/* Loads `path` into `scene` (initialized here, not finalized), at the
 * Film's resolution or width x height when both are non-zero. Warnings go
 * to stderr unless quiet. Returns 0, or -1 with a message naming file and
 * line. */
int scene_convert_load(const char *path, int allow_unsupported, unsigned width, unsigned height, int quiet,
                       RenderScene *scene, SceneSummary *summary, char *error, size_t error_size);

/* The same for a scene already loaded (from `path`, named in messages);
 * prints only the conversion's own warnings. */
int scene_convert(const Scene *in, const char *path, unsigned width, unsigned height, int quiet, RenderScene *out,
                  SceneSummary *summary, char *error, size_t error_size);

/* Sets `scene`'s integrator flags for light_subpaths (SCENE_BDPT,
 * SCENE_LIGHTPATH; 0: the path tracer), with bdpt's "regularize": the path
 * tracer instead, with a warning (unless quiet) naming `path`, where light
 * subpaths are not done yet (an orthographic camera, distant and infinite
 * lights). scene_convert does it for the scene's own Integrator. */
void scene_convert_light_subpaths(RenderScene *scene, int light_subpaths, int regularize, const char *path, int quiet);

#endif
