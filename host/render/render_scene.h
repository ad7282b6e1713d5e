/* The scene as the kernels see it: primitives, materials, lights (with
 * their images and sampling distributions) and the render constants, with
 * the BVH built by render_scene_finalize. Filled by the scene reader (or
 * directly by tests). */
#ifndef HOST_RENDER_RENDER_SCENE_H
#define HOST_RENDER_RENDER_SCENE_H

#include "feature_mask.h"
#include "render/bvh.h"
#include "render/pixel_filter.h"
#include "sampler.h"
#include "scene_types.h"

#include <stddef.h>
#include <stdint.h>

/* An object for instancing: primitives [first, first + count) of the input. */
typedef struct {
    int first, count;
} RenderObject;

typedef struct {
    int object;
    double world_from_object[3][4]; /* rows of an affine matrix */
} RenderInstance;

typedef struct {
    SceneConstants constants;
    Material *materials;
    int material_count, material_capacity;
    Primitive *primitives;
    int primitive_count, primitive_capacity;
    Light *lights; /* as added; render_scene_finalize puts the infinite, then the distant ones first */
    int light_count, light_capacity;
    LightNode *light_nodes; /* the light tree over the others (render_scene_finalize) */
    int light_node_count;
    uint64_t *light_trails;
    float *distributions;
    size_t distribution_count, distribution_capacity;
    float *texels;
    size_t texel_count, texel_capacity;
    float *vertex_normals;         /* 9 a primitive in input order, or NULL: none has any */
    size_t vertex_normal_capacity; /* in primitives */
    float *shading_normals;        /* vertex_normals in the BVH's order (render_scene_finalize) */
    /* Textures (render_textures.c): the programs' nodes, which material
     * parameters they give (NULL: none; else one a material, completed by
     * render_scene_finalize), the texels, and the triangles' uvs
     * (SURFACE_UV_FLOATS a primitive in input order, [7] = 1 where set;
     * surface_uvs in the BVH's order, made when there are textures). */
    TextureNode *textures;
    int texture_count, texture_capacity;
    MaterialTextures *material_textures;
    int material_texture_count;
    uint8_t *texture_bytes;
    size_t texture_byte_count, texture_byte_capacity;
    float *texture_floats;
    size_t texture_float_count, texture_float_capacity;
    float *vertex_uvs;
    size_t vertex_uv_capacity; /* in primitives */
    float *surface_uvs;
    RenderObject *objects;
    int object_count, object_capacity;
    int open_object; /* the object render_scene_begin_object opened, or -1 */
    RenderInstance *instance_inputs;
    int instance_input_count, instance_input_capacity;
    AlphaSlot *alphas;
    int alpha_count, alpha_capacity;
    Bvh bvh; /* valid after render_scene_finalize; owns the ordered primitives */
    /* After render_scene_finalize: bvh.primitives[0, world_primitive_count)
     * are the top-level tree's (the world's primitives and one PRIM_INSTANCE
     * for each instance), the objects' follow; their instances. */
    int world_primitive_count;
    Instance *instances;
    int instance_count;
    /* Participating media (FEATURE_MEDIA; constants.media.count of them):
     * each primitive's interface as primitive_media packs it, in input
     * order (NULL until render_scene_set_media) and in the BVH's order. */
    Medium *media;
    int medium_capacity;
    float *medium_values; /* the grids' values (Medium) */
    size_t medium_value_count, medium_value_capacity;
    uint32_t *medium_interfaces;
    size_t medium_interface_capacity; /* in primitives */
    uint32_t *primitive_media;
} RenderScene;

/* The arrays of kernels/tracing/scene_types.h's list, as the path tracer takes them. */
#define RENDER_SCENE_ARRAY(name, type)                                                                                 \
    const type *name;                                                                                                  \
    size_t name##_count;
typedef struct {
    GMON_SCENE_ARRAYS(RENDER_SCENE_ARRAY)
} RenderSceneArrays;
#undef RENDER_SCENE_ARRAY

RenderSceneArrays render_scene_arrays(const RenderScene *scene);

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

/* Gives the triangle just added vertex normals (unit, world space, on the
 * front's side): the kernel interpolates them as its shading normal.
 * Returns 0, or -1 when out of memory. */
int render_scene_set_vertex_normals(RenderScene *scene, const float na[3], const float nb[3], const float nc[3]);

/* Instancing: the primitives added between render_scene_begin_object
 * (which returns the object's index, or -1 when out of memory) and
 * render_scene_end_object are the object's, drawn only by its instances
 * (none of them may emit light); render_scene_add_instance draws the
 * object through world_from_object (rows of an affine matrix). Returns 0,
 * or -1 with a message (a singular transform, out of memory). */
int render_scene_begin_object(RenderScene *scene);
void render_scene_end_object(RenderScene *scene);
int render_scene_add_instance(RenderScene *scene, int object, const double world_from_object[3][4], char *error,
                              size_t error_size);

/* Makes the primitive just added a cut-out of alpha `alpha` in [0, 1)
 * (pbrt-v4's "float alpha"; 1 is opaque and needs no call), or with
 * texture >= 0 of the float texture program starting at that node
 * ("texture alpha"; alpha is then ignored). Returns 0, or -1 when out of
 * memory or past PRIM_MAX_ALPHA_SLOTS distinct alphas. */
int render_scene_set_alpha(RenderScene *scene, float alpha, int texture);

/* Participating media: render_scene_add_medium returns the medium's index
 * (-1 when out of memory or past MEDIUM_MAX_COUNT); for a grid (its
 * values added before) it computes the majorant grid and majorant;
 * render_scene_set_media gives the primitive just added its media behind
 * and in front of it (indices, or -1 for vacuum; primitives without one
 * keep the ray's medium); the camera's medium is constants.media's
 * camera_medium. Returns 0, or -1 when out of memory. */
int render_scene_add_medium(RenderScene *scene, const Medium *medium);
/* Appends a grid's values for a Medium; returns the first one's index, or
 * -1 when out of memory. */
int32_t render_scene_add_medium_values(RenderScene *scene, const float *values, size_t count);
/* `size` bytes (a NanoVDB grid) at an offset of NANOVDB_ALIGNMENT_FLOATS
 * floats' alignment; returns the offset, or -1 when out of memory. */
int32_t render_scene_add_medium_bytes(RenderScene *scene, const void *bytes, size_t size);
int render_scene_set_media(RenderScene *scene, int inside, int outside);

/* Adds a light that is not an area light (point, spot, distant, uniform
 * infinite: Light's fields as scene_types.h describes them; pick fields are
 * computed by render_scene_finalize). Returns 0, or -1 when out of memory. */
int render_scene_add_light(RenderScene *scene, const Light *light);

/* A uniform infinite light of the given radiance. */
int render_scene_add_infinite_light(RenderScene *scene, const float radiance[3]);

/* An image infinite light: `light` gives the radiance scale and the
 * rotation light_from_world; `rgb` the width x height RGB texels of an
 * equal-area square (row 0 at the top), non-negative and finite. Copies the
 * texels and builds the sampling distribution. Returns 0, or -1 with a
 * message. */
int render_scene_add_image_light(RenderScene *scene, const Light *light, uint32_t width, uint32_t height,
                                 const float *rgb, char *error, size_t error_size);

/* pbrt-v4's power of a goniometric light (4 pi times its mean intensity)
 * or a projection light (the screen's area times the mean over its texels
 * of luminance times cos^3, a texel's solid angle over its screen area),
 * for the light's radiance scale and its w x h RGB image. */
double render_scene_imaged_light_power(const Light *light, const float *rgb, uint32_t w, uint32_t h);

/* A camera, in world space. The image spans window = [x_min, x_max,
 * y_min, y_max] along right and up (pbrt's screen window): tangents for
 * the perspective camera (the image plane at distance 1), world lengths
 * for the orthographic one. */
typedef struct {
    uint32_t projection;                            /* CAMERA_PERSPECTIVE or CAMERA_ORTHOGRAPHIC */
    float position[3], forward[3], right[3], up[3]; /* unit axes; right to the image's right, up to its top */
    float window[4];
    float lens_radius;    /* 0: a pinhole */
    float focal_distance; /* the plane in focus, along forward (with a lens) */
    unsigned width, height;
} RenderCamera;

void render_scene_set_camera(RenderScene *scene, const RenderCamera *camera);

/* A perspective pinhole camera with the tangents of its half fields of
 * view (the window centred on forward). */
RenderCamera render_camera_pinhole(const float position[3], const float forward[3], const float right[3],
                                   const float up[3], float tan_half_fov_x, float tan_half_fov_y, unsigned width,
                                   unsigned height);

/* The pixel filter: the box of radius 0.5 is the renderer's plain uniform
 * position in the pixel (the default); any other is tabulated into the
 * distributions for importance sampling (FilterData). Returns 0, or -1
 * with a message (a radius out of (0, PIXEL_FILTER_MAX_RADIUS], a filter
 * whose integral is not positive). */
int render_scene_set_filter(RenderScene *scene, const PixelFilter *filter, char *error, size_t error_size);

/* Appends a texture program of `count` nodes (operands as slots of it;
 * program_length is set here). Returns its first node, or -1 when out of
 * memory. */
int render_scene_add_texture_program(RenderScene *scene, const TextureNode *nodes, int count);

/* The texture programs giving material `material`'s parameters. Returns 0,
 * or -1 when out of memory. */
int render_scene_set_material_textures(RenderScene *scene, int material, const MaterialTextures *textures);

/* Gives the triangle just added vertex uvs (u0 v0 u1 v1 u2 v2); triangles
 * without get pbrt's (0,0), (1,0), (1,1). Returns 0, or -1 when out of memory. */
int render_scene_set_uvs(RenderScene *scene, const float uv[6]);

/* An image's texels for a texture, decoded or kept 8-bit: width x height
 * texels of `channels` (1 or 3) values, rows from the top, either bytes
 * (decoded by the 256 floats of `decode`) or floats. */
typedef struct {
    uint32_t width, height, channels;
    const uint8_t *bytes;
    const float *decode; /* with bytes: byte -> linear value, increasing */
    const float *floats;
} TextureTexels;

/* Uploads the texels and their MIP pyramid (levels down to 1x1 by 2x2 box
 * averages, 8-bit levels re-encoded to the nearest byte; just the image
 * with single_level) and points node's image fields at them. Returns 0, or
 * -1 with a message (non-finite texels, too large). */
int render_scene_add_texture_texels(RenderScene *scene, const TextureTexels *texels, int single_level,
                                    TextureNode *node, char *error, size_t error_size);

/* Bytes of texels and programs uploaded for textures. */
size_t render_scene_texture_bytes(const RenderScene *scene);

/* render_scene_finalize's part for textures (after the BVH): the per-material table
 * and the uvs in the BVH's order. Returns 0, or -1 with a message. */
int render_scene_finalize_textures(RenderScene *scene, char *error, size_t error_size);

/* Builds the BVH, orders the lights (infinite, then distant first: the
 * unbounded ones), builds the light tree over the others and gives each
 * light its chance of being picked (render_scene_set_light_sampler).
 * Returns 0, or -1 with a message. */
int render_scene_finalize(RenderScene *scene, char *error, size_t error_size);

/* Sets the light sampler (LIGHT_SAMPLER_*) of a finalized scene and each
 * light's fixed chance: uniform; by power as pbrt-v4's "power" (infinite
 * and distant lights by the power they send through the scene's bounding
 * sphere); with the tree, the tree and each unbounded light an equal
 * share, as pbrt-v4's "bvh" (a bounded light's recorded chance is then its
 * power's share of the tree's: the kernel asks the tree at each point). */
void render_scene_set_light_sampler(RenderScene *scene, uint32_t light_sampler);

/* The light samplers by name, as pbrt-v4's "lightsampler" and
 * --light-sampler spell them ("bvh" is the tree): light_sampler_name of a
 * LIGHT_SAMPLER_* value, light_sampler_from_name of a name ("exhaustive",
 * pbrt-v4's exact form of bvh, is the tree too; -1: none). */
const char *light_sampler_name(uint32_t light_sampler);
int light_sampler_from_name(const char *name);

/* The samplers (kernels/tracing/sampler.h) by name, as --sampler and the EXR's
 * gmon.sampler spell them: sampler_name of a SAMPLER_* value, and
 * sampler_from_name of a name (-1: none). */
const char *sampler_name(uint32_t sampler);
int sampler_from_name(const char *name);

/* The sampler that renders a scene whose Sampler directive names `name`
 * ("" for none): "independent" is ours, every other (pbrt-v4's zsobol
 * default, sobol, paddedsobol, halton, pmj02bn, stratified) becomes
 * SAMPLER_DEFAULT, a low-discrepancy sampler whose sets stay independent. */
#define SAMPLER_DEFAULT SAMPLER_SOBOL_SETS
uint32_t sampler_for_scene(const char *name);

/* The feature mask (kernels/tracing/feature_mask.h) of what rendering the scene uses. */
uint64_t render_scene_features(const RenderScene *scene);

#endif
