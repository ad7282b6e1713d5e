/* The path tracer's input, as uploaded: the constants and the typed arrays
 * of kernels/tracing/scene_types.h's GMON_SCENE_ARRAYS list. The only place that
 * creates the scene's device buffers and binds the path tracer's
 * arguments; the scene hash is taken from exactly the uploaded bytes. */
#ifndef HOST_RENDER_SCENE_UPLOAD_H
#define HOST_RENDER_SCENE_UPLOAD_H

#include "render/render_scene.h"

#include <CL/cl.h>
#include <stddef.h>
#include <stdint.h>

#define SCENE_ARRAY_INDEX(name, type) SCENE_ARRAY_##name,
enum { GMON_SCENE_ARRAYS(SCENE_ARRAY_INDEX) SCENE_ARRAY_COUNT };
#undef SCENE_ARRAY_INDEX

/* Buffer 0 holds the constants, buffers 1.. the arrays in list order. */
#define SCENE_BUFFERS (1 + SCENE_ARRAY_COUNT)

typedef struct {
    SceneConstants constants; /* the scene's, with the render's seed */
    const void *data[SCENE_BUFFERS];
    size_t bytes[SCENE_BUFFERS];
} SceneUpload;

/* Points at the scene's arrays (which must outlive the upload). */
void scene_upload_init(SceneUpload *u, const RenderScene *scene, uint32_t seed);

/* The bytes all buffers take on a device (an empty array takes 8). */
size_t scene_upload_bytes(const SceneUpload *u);

/* Names the scene's largest buffers with their sizes, largest first (at
 * most `most`), e.g. "image texels 1.50 GiB, the BVH 204.8 MiB", for
 * messages about memory. */
void scene_upload_describe(const SceneUpload *u, int most, char *out, size_t size);

/* What determines every sample: the uploaded bytes (scene, camera, film,
 * resolution, max depth, integrator, seed) and the M the sampler deals
 * samples to (--sets, even where only the mean is kept), as 16 hex digits. */
void scene_upload_hash(const SceneUpload *u, int sets, char *hex, size_t size);

/* Creates the buffers on a context and binds them as the path tracer's
 * first arguments. On failure the buffers made are released and zeroed. */
cl_int scene_upload_create(const SceneUpload *u, cl_context context, cl_kernel kernel, cl_mem buffers[SCENE_BUFFERS]);

/* Binds buffers made by scene_upload_create as another kernel's first
 * arguments (bdpt.cl's splat_samples takes the scene as render_samples). */
cl_int scene_upload_bind(cl_kernel kernel, const cl_mem buffers[SCENE_BUFFERS]);

/* The path tracer's per-pass arguments, after the scene's. */
typedef struct {
    cl_mem accumulators, rejected, rays;
    cl_ulong first_sample;
    cl_uint sample_count;
    cl_ulong first_pixel, pixel_count;               /* the pixels to render */
    cl_ulong buffer_first_pixel, buffer_pixel_count; /* the pixels the state buffers cover */
    cl_mem samples; /* per-sample state (film_sample.h); NULL: the kernel has no such argument */
} RenderPassArguments;

cl_int scene_upload_bind_pass(cl_kernel kernel, const RenderPassArguments *a);

#endif
