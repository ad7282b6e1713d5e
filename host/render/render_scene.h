/* The scene as the kernels see it: primitives, materials, area lights and
 * render parameters, with the BVH built by render_scene_finalize. Filled by
 * the scene reader (or directly by tests). */
#ifndef HOST_RENDER_RENDER_SCENE_H
#define HOST_RENDER_RENDER_SCENE_H

#include "feature_mask.h"
#include "render/bvh.h"
#include "scene_types.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    RenderParams params;
    Material *materials;
    int material_count, material_capacity;
    Primitive *primitives;
    int primitive_count, primitive_capacity;
    Emitter *emitters;
    int emitter_count, emitter_capacity;
    Bvh bvh; /* valid after render_scene_finalize; owns the ordered primitives */
} RenderScene;

void render_scene_init(RenderScene *scene);
void render_scene_destroy(RenderScene *scene);

/* Returns the material's index, or -1 when out of memory. */
int render_scene_add_material(RenderScene *scene, const Material *material);

/* Adds a triangle or sphere with a material; `emission` (RGB radiance, or
 * NULL) makes it an area light, one-sided unless two_sided. flip_normal
 * reverses the surface's orientation. Returns 0, or -1 when out of memory. */
int render_scene_add_triangle(RenderScene *scene, const float a[3], const float b[3], const float c[3], int material,
                              const float *emission, int two_sided, int flip_normal);
int render_scene_add_sphere(RenderScene *scene, const float centre[3], float radius, int material,
                            const float *emission, int two_sided, int flip_normal);

/* The camera: position, unit forward/right/up (right to the image's right,
 * up to its top) and the tangents of the half fields of view. */
void render_scene_set_camera(RenderScene *scene, const float position[3], const float forward[3], const float right[3],
                             const float up[3], float tan_half_fov_x, float tan_half_fov_y, unsigned width,
                             unsigned height);

/* Builds the BVH and the light-picking distribution (by emitted power).
 * Returns 0, or -1 with a message. */
int render_scene_finalize(RenderScene *scene, char *error, size_t error_size);

/* The feature mask (kernels/feature_mask.h) of what rendering the scene uses. */
uint32_t render_scene_features(const RenderScene *scene);

#endif
