/* Scene data shared by the host (which builds it) and the kernels (which
 * trace it): plain fixed-width structs, 16-byte aligned members, no float3
 * (its size differs between C and OpenCL). Sizes are checked on the host. */
#ifndef KERNELS_SCENE_TYPES_H
#define KERNELS_SCENE_TYPES_H

#include "compat.h"
#include "feature_mask.h"

/* Primitive kinds. */
#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u
#define PRIM_INSTANCE 2u /* FEATURE_INSTANCING: an object instance in the top-level tree */

/* A triangle (a is its first vertex, b and c the edges to the second and
 * third, which saves the intersection test two subtractions) or a sphere
 * (a is the centre, b[0] the radius), or an instance (a and b the lower and
 * upper corners of its world-space box, material its index in the instance
 * array). 48 bytes. */
typedef struct {
    float a[3];
    uint32_t kind;
    float b[3];
    int32_t material; /* index into the material array */
    float c[3];
    int32_t light; /* index into the light array (an area light), or -1 */
} Primitive;

/* The BVH, an 8-wide tree flattened into an array of BvhNode blocks (block 0
 * is the root). A node holds the boxes of up to 8 children, which a kernel
 * tests at once with 8-wide vector operations, structure of arrays. A child
 * is an inner node or a leaf of 1..8 primitives [first, first + count) of the
 * reordered primitive array; an all-triangle leaf also has a packet of its
 * triangles, in a block of its own, for an 8-wide intersection test. */
#define BVH_WIDTH 8

typedef struct {
    float lower[3][BVH_WIDTH]; /* [axis][child] */
    float upper[3][BVH_WIDTH];
    int32_t child[BVH_WIDTH];  /* an inner child's block; a leaf's first primitive */
    int32_t count[BVH_WIDTH];  /* 0: inner node; 1..BVH_WIDTH: a leaf; -1: no child */
    int32_t packet[BVH_WIDTH]; /* a leaf's triangle packet block, or -1: test one by one */
} BvhWideNode;

/* A leaf's triangles as Primitive stores them ([component][triangle]); lanes
 * past the leaf's count have zero edges, which never hit. */
typedef struct {
    float a[3][BVH_WIDTH];
    float b[3][BVH_WIDTH];
    float c[3][BVH_WIDTH];
} TrianglePacket;

/* 288 bytes. */
typedef union {
    BvhWideNode node;
    TrianglePacket triangles;
} BvhNode;

/* Primitive.kind: the shape in the low byte, flags above it. */
#define PRIM_KIND_MASK 0xffu
#define PRIM_FLIP_NORMAL 0x100u    /* ReverseOrientation (or a handedness swap) */
#define PRIM_SHADING_NORMAL 0x200u /* a triangle with vertex normals, in shading_normals */
/* FEATURE_ALPHA: a cut-out, whose alpha is alphas[kind >> PRIM_ALPHA_SHIFT]. */
#define PRIM_ALPHA 0x400u
#define PRIM_ALPHA_SHIFT 16
#define PRIM_MAX_ALPHA_SLOTS 0x10000u

/* An instance of an object (FEATURE_INSTANCING): the object's own BVH,
 * rooted at nodes[root] over its primitives (in the same arrays, reached
 * only through instances), seen through a transform. Rays are traced in
 * object space: object_from_world (rows of a 3x4 affine matrix) takes the
 * ray there; a ray's parameter t is the same in both spaces. Its transpose
 * takes object-space normals to world space (up to length). 64 bytes. */
typedef struct {
    float object_from_world[3][4];
    int32_t root;
    uint32_t pad[3];
} Instance;

/* A shape's alpha (FEATURE_ALPHA): `value`, or when texture >= 0 that
 * texture's value at the hit (the hook for float textures: not evaluated
 * yet, the scene reader refuses "texture alpha"). 8 bytes. */
typedef struct {
    float value;
    int32_t texture;
} AlphaSlot;

/* With one shape kind in the build (feature_mask.h) the test folds away. */
KERNEL_FN int is_sphere(const GLOBAL Primitive *p)
{
    return GMON_HAS_SPHERES && (!GMON_HAS_TRIANGLES || (p->kind & PRIM_KIND_MASK) == PRIM_SPHERE);
}

/* Material types. */
#define MAT_DIFFUSE 0u
#define MAT_DIELECTRIC 1u
#define MAT_CONDUCTOR 2u
#define MAT_COATED_DIFFUSE 3u

/* 64 bytes. alpha_x/alpha_y are GGX roughnesses; below SMOOTH_ALPHA the
 * surface is treated as perfectly smooth (a delta lobe). */
typedef struct {
    uint32_t type;
    float alpha_x;
    float alpha_y;
    float eta;            /* dielectric / coating index of refraction */
    float reflectance[3]; /* diffuse albedo, coated base albedo */
    float pad0;
    float conductor_eta[3];
    float pad1;
    float conductor_k[3];
    float pad2;
} Material;

#define SMOOTH_ALPHA 1e-3f

/* Light types (Light.type). Area lights are emitting primitives; the
 * infinite lights come first in the light array (BackgroundData). */
#define LIGHT_AREA 0u
#define LIGHT_POINT 1u
#define LIGHT_SPOT 2u
#define LIGHT_DISTANT 3u
#define LIGHT_UNIFORM_INFINITE 4u
#define LIGHT_IMAGE_INFINITE 5u
#define LIGHT_GONIOMETRIC 6u
#define LIGHT_PROJECTION 7u

/* One light, any type. 128 bytes.
 * - area: `radiance` leaves `primitive` (of `area`) on its front, or both
 *   sides when two_sided;
 * - point: intensity `radiance` at `position`;
 * - spot: as point, within a cone around `direction` (unit, the way it
 *   shines), fully bright inside cos_falloff_start and smoothly falling to 0
 *   at cos_total_width (pbrt-v4's smoothstep);
 * - distant: radiance `radiance` arriving from `direction` (unit, toward the
 *   light);
 * - uniform infinite: radiance `radiance` from every direction;
 * - image infinite: `radiance` scales the image of image_width x
 *   image_height RGB texels at texels[image_offset...] (pbrt-v4's
 *   equal-area octahedral square, row 0 at the top), looked up at the
 *   direction in light space (the rows light_from_world[0..2] rotate a world
 *   direction into it); its sampling distribution is at
 *   distributions[distribution_offset...] (lights.h);
 * - goniometric: a point light whose intensity `radiance` is scaled by its
 *   image (the same square, grey as RGB) at the light-space direction;
 * - projection: a point light projecting its image (image_width x
 *   image_height RGB texels, row 0 at the top) along light-space +z: a
 *   light-space direction w lands at (w.x / w.z, w.y / w.z) of the screen
 *   [-screen_half[0], screen_half[0]] x [-screen_half[1], screen_half[1]].
 * Every light has its chance of being picked and the running sum of the
 * chances (inclusive) over the light array. */
typedef struct {
    uint32_t type;
    int32_t primitive;
    float area;
    uint32_t two_sided;
    float radiance[3];
    float pick_probability;
    float position[3];
    float pick_cdf;
    float direction[3];
    float cos_falloff_start;
    float light_from_world[3][3]; /* rows */
    float cos_total_width;
    uint32_t image_width, image_height, image_offset, distribution_offset;
    float screen_half[2]; /* projection */
} Light;

/* An image light's sampling distribution over the square, at
 * distributions[distribution_offset...]: [0] the mean of the function f
 * over the square, then the marginal CDF of the rows (height + 1 values),
 * one CDF per row (width + 1 values each), and f itself (width * height,
 * row by row). f is the texel's channel average, so it is positive
 * wherever the light is. DISTRIBUTION_FUNCTION is where f starts. */
#define DISTRIBUTION_FUNCTION(width, height) (1u + ((height) + 1u) + (height) * ((width) + 1u))

/* Camera projections (CameraData.projection). */
#define CAMERA_PERSPECTIVE 0u
#define CAMERA_ORTHOGRAPHIC 1u

/* The constants of one render, by concern. 224 bytes in all.
 *
 * The camera: an image point (sx, sy) in [-1, 1]^2 (x to the right, y up
 * in the image) is, for the perspective camera, the ray from `position`
 * along forward + sx * right + sy * up (right and up scaled to the screen
 * window: to its half extents, with its centre folded into forward); for
 * the orthographic one, the ray from position + sx * right + sy * up (the
 * window's centre folded into position) along forward. forward is unit in
 * the orthographic case and has unit length along the view axis in both,
 * so that a ray reaches the plane of focus at focal_distance times it.
 * With lens_radius > 0 (a thin lens), the ray starts instead at a point
 * of the lens disk around `position`, spanned by lens_right and lens_up
 * (the unit axes times lens_radius), and passes through the point where
 * the pinhole ray meets the plane of focus, as pbrt-v4 does for both
 * projections. */
typedef struct {
    float position[3];
    uint32_t width;
    float right[3];
    uint32_t height;
    float up[3];
    uint32_t projection;
    float forward[3];
    float focal_distance;
    float lens_right[3];
    float lens_radius;
    float lens_up[3];
    uint32_t pad;
} CameraData;

/* The pixel filter, sampled by importance (filter importance sampling, as
 * pbrt-v4): a sample's image position is its pixel's centre plus an offset
 * in [-radius, radius] drawn from |f|, tabulated over table_width x
 * table_height cells as a 2D distribution at
 * distributions[distribution_offset...] (the layout of an image light's,
 * with f's sign kept in its function values), and the sample is scaled by
 * sign(f) * weight, weight = (integral of |f|) / (integral of f), so that
 * a pixel's mean is its filtered estimate. table_width 0: the box of
 * radius 0.5, a uniform position in the pixel and no scaling. */
typedef struct {
    float radius[2];
    uint32_t table_width, table_height;
    uint32_t distribution_offset;
    float weight;
    uint32_t pad[2];
} FilterData;

/* What the film does to each sample's radiance (linear sRGB) before it is
 * accumulated: the sensor's response as a 3x3 matrix (rows, padded; the
 * identity for pbrt-v4's default film), then, as pbrt-v4's
 * "maxcomponentvalue", a sample whose largest component exceeds
 * max_component_value is scaled down to it (INFINITY: never). */
typedef struct {
    float from_radiance[3][4];
    float max_component_value;
    uint32_t pad[3];
} FilmData;

#define RENDER_NEE 1u /* next-event estimation with MIS; else BSDF sampling only */

typedef struct {
    uint32_t max_depth;
    uint32_t flags;
    uint32_t light_count;
    uint32_t seed;
} IntegratorData;

/* The infinite lights: lights[0, infinite_count) of the light array. */
typedef struct {
    uint32_t infinite_count;
    uint32_t pad[3];
} BackgroundData;

typedef struct {
    CameraData camera;
    FilterData filter;
    FilmData film;
    IntegratorData integrator;
    BackgroundData background;
} SceneConstants;

/* The scene's arrays, in the order the path tracer takes them after the
 * constants: ARRAY(name, element type). The kernel's signature, the
 * kernel's Scene and the host's upload (host/render/scene_upload.c) all
 * come from this one list. `distributions` holds the lights' and the
 * pixel filter's sampling distributions, `texels` the lights' images (RGB
 * floats), `shading_normals` the vertex normals of triangles flagged
 * PRIM_SHADING_NORMAL (9 floats a primitive, in the BVH's order; empty
 * when no triangle has them), `instances` the object instances (empty
 * without FEATURE_INSTANCING), `alphas` the cut-outs' alphas (empty without
 * FEATURE_ALPHA). */
#define GMON_SCENE_ARRAYS(ARRAY)                                                                                       \
    ARRAY(nodes, BvhNode)                                                                                              \
    ARRAY(primitives, Primitive)                                                                                       \
    ARRAY(materials, Material)                                                                                         \
    ARRAY(lights, Light)                                                                                               \
    ARRAY(distributions, float)                                                                                        \
    ARRAY(texels, float)                                                                                               \
    ARRAY(shading_normals, float)                                                                                      \
    ARRAY(instances, Instance)                                                                                         \
    ARRAY(alphas, AlphaSlot)

#ifndef __OPENCL_C_VERSION__
_Static_assert(sizeof(Primitive) == 48, "Primitive must match the kernel's layout");
_Static_assert(sizeof(BvhNode) == 288, "BvhNode must match the kernel's layout");
_Static_assert(sizeof(Material) == 64, "Material must match the kernel's layout");
_Static_assert(sizeof(Instance) == 64, "Instance must match the kernel's layout");
_Static_assert(sizeof(AlphaSlot) == 8, "AlphaSlot must match the kernel's layout");
_Static_assert(sizeof(Light) == 128, "Light must match the kernel's layout");
_Static_assert(sizeof(SceneConstants) == 224, "SceneConstants must match the kernel's layout");
#endif

#endif
