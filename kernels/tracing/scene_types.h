/* Scene data shared by the host (which builds it) and the kernels (which
 * trace it): plain fixed-width structs, 16-byte aligned members, no float3
 * (its size differs between C and OpenCL). Sizes are checked on the host. */
#ifndef KERNELS_SCENE_TYPES_H
#define KERNELS_SCENE_TYPES_H

#include "../common/compat.h"
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

/* A shape's alpha (FEATURE_ALPHA): `value`, or when texture >= 0 the
 * value at the hit of the float texture program starting at
 * textures[texture] (FEATURE_ALPHA_TEXTURE). 8 bytes. */
typedef struct {
    float value;
    int32_t texture;
} AlphaSlot;

/* With one shape kind in the build (feature_mask.h) the test folds away. */
KERNEL_FN int is_sphere(const GLOBAL Primitive *p)
{
    return !GMON_HAS_SPHERES ? 0 : !GMON_HAS_TRIANGLES ? 1 : (p->kind & PRIM_KIND_MASK) == PRIM_SPHERE;
}

/* Material types. */
#define MAT_DIFFUSE 0u
#define MAT_DIELECTRIC 1u
#define MAT_CONDUCTOR 2u
#define MAT_COATED_DIFFUSE 3u
#define MAT_DIFFUSE_TRANSMISSION 4u
#define MAT_MIX 5u /* resolved to one of its two materials at each hit */
#define MAT_COATED_CONDUCTOR 6u
#define MAT_THIN_DIELECTRIC 7u
#define MAT_INTERFACE 8u  /* no surface: a boundary between media (FEATURE_MEDIA); else the host drops its shapes */
#define MIX_MAX_NESTING 8 /* mixes of mixes, at most */

/* 128 bytes. alpha_x/alpha_y are GGX roughnesses (of the coating for the
 * coated materials); below SMOOTH_ALPHA the surface is treated as
 * perfectly smooth (a delta lobe). The coated materials are pbrt-v4's
 * layered BSDFs: a dielectric coating (eta, alpha) over a diffuse base
 * (reflectance) or a conductor (conductor_eta/k, base_alpha), `thickness`
 * apart, with a medium of `albedo` and Henyey-Greenstein asymmetry g
 * between them, evaluated by random walks of up to max_depth scatterings,
 * sample_count of them per evaluation. */
typedef struct {
    uint32_t type;
    float alpha_x;
    float alpha_y;
    float eta;            /* dielectric / coating index of refraction */
    float reflectance[3]; /* diffuse albedo, coated base albedo, diffuse transmission's reflection */
    float pad0;
    float conductor_eta[3];
    float pad1;
    float conductor_k[3];
    float pad2;
    float transmittance[3]; /* diffuse transmission */
    float mix_amount;       /* mix: the chance of mix_materials[1] */
    float albedo[3];        /* layered: the medium between coating and base */
    float thickness;
    float g;
    uint32_t max_depth;
    uint32_t sample_count;
    int32_t mix_materials[2]; /* mix: indices into the material array */
    float base_alpha_x;       /* coated conductor: the conductor's roughness */
    float base_alpha_y;
    float pad3;
} Material;

#define SMOOTH_ALPHA 1e-3f

/* Textures. A material parameter given by a texture names a texture
 * program: TextureNode blocks [first, first + program_length) of the
 * textures array (program_length is set on the first), evaluated in order
 * (kernels/tracing/texture.h), each node's operands being earlier nodes of the
 * same program (their slot in it, 0-based) or its constants; the last
 * node's value is the parameter's. pbrt-v4's textures referencing textures
 * (scale, mix, ...) become one program each, without recursion. */
#define TEXTURE_MAX_PROGRAM 16 /* nodes (the scene reader checks it) */
#define TEXTURE_CONSTANT 0u
#define TEXTURE_IMAGE 1u        /* "imagemap" */
#define TEXTURE_CHECKERBOARD 2u /* 2D, or 3D when mapping is TEXTURE_MAP_3D */
#define TEXTURE_SCALE 3u        /* operand 0 times operand 2 */
#define TEXTURE_MIX 4u          /* (1 - amount) operand 0 + amount operand 1; amount is operand 2 */
#define TEXTURE_DIRECTION_MIX 5u
#define TEXTURE_BILERP 6u
/* pbrt-v4's procedural textures (FEATURE_PROCEDURAL_TEXTURES; Perlin noise,
 * kernels/tracing/texture.h). dots: operand 0 inside a dot, 1 outside, a 2D
 * mapping. The others a 3D mapping (the point in texture space) and
 * value[3] = (omega, variation, octaves): fbm, wrinkled (turbulence),
 * windy, marble (also `scale`, an RGB texture). */
#define TEXTURE_DOTS 7u
#define TEXTURE_FBM 8u
#define TEXTURE_WRINKLED 9u
#define TEXTURE_WINDY 10u
#define TEXTURE_MARBLE 11u

/* How a hit becomes texture coordinates (s, t) (pbrt-v4's mappings). */
#define TEXTURE_MAP_UV 0u        /* (uscale u + udelta, vscale v + vdelta) */
#define TEXTURE_MAP_SPHERICAL 1u /* of the point in texture space (texture_from_world) */
#define TEXTURE_MAP_CYLINDRICAL 2u
#define TEXTURE_MAP_PLANAR 3u /* rows 0 and 1 of texture_from_world, plus map_delta */
#define TEXTURE_MAP_3D 4u     /* the point in texture space */

#define TEXTURE_WRAP_REPEAT 0u
#define TEXTURE_WRAP_BLACK 1u
#define TEXTURE_WRAP_CLAMP 2u
#define TEXTURE_WRAP_OCTAHEDRAL_SPHERE 3u

#define TEXTURE_FILTER_POINT 0u
#define TEXTURE_FILTER_BILINEAR 1u
#define TEXTURE_FILTER_TRILINEAR 2u /* also pbrt-v4's "ewa" */

/* Texels of an image: 8-bit values decoded through a 256-entry table of
 * floats (the image's encoding: sRGB, linear or gamma), or floats. */
#define TEXEL_BYTES 0u
#define TEXEL_FLOATS 1u

/* One node of a texture program. 224 bytes. Operands: operand[i] >= 0 is
 * a slot of the program, -1 the constant value[i]. An image is a MIP
 * pyramid of `levels` levels, level k of max(1, width >> k) x max(1,
 * height >> k) texels of `channels` (1 or 3) values each, row 0 at the top,
 * one level after the other from texel_offset in texture_bytes or
 * texture_floats (texel_format); 8-bit texels decode through
 * texture_floats[decode_offset + byte]. */
typedef struct {
    uint32_t type;
    uint32_t program_length; /* on a program's first node */
    uint32_t mapping;
    uint32_t spectrum;              /* 1: an RGB texture; 0: float (channel 0) */
    float map_scale[2];             /* uv: uscale, vscale */
    float map_delta[2];             /* uv and planar: udelta, vdelta */
    float texture_from_world[3][4]; /* rows of an affine map (TEXTURE_MAP_SPHERICAL, ... ) */
    float value[4][4];              /* constants: operands 0..2; bilerp: v00, v01, v10, v11; noise: [3] (above) */
    int32_t operand[3];
    float pad0;
    float direction[4]; /* direction mix: unit, world space */
    uint32_t width, height, levels, channels;
    uint32_t texel_offset, texel_format, decode_offset, wrap;
    uint32_t filter, invert;
    float scale; /* an image's, or marble's */
    uint32_t pad;
} TextureNode;

/* A material's parameters given by textures (materials[i]'s at
 * material_textures[i]): a texture program's first node, or -1 for the
 * Material's constant. Present only when the scene has textures. 80 bytes. */
typedef struct {
    int32_t reflectance;  /* diffuse, coated and diffuse transmission albedo; a conductor's "reflectance" */
    int32_t roughness[2]; /* u, v (pbrt's roughness: remapped to alpha when remap_roughness) */
    int32_t eta;          /* dielectric, coating */
    int32_t conductor_eta, conductor_k;
    int32_t displacement;         /* bump mapping */
    int32_t normal_map;           /* an RGB image of tangent-space normals */
    int32_t transmittance;        /* diffuse transmission */
    int32_t mix_amount;           /* mix: evaluated at the hit before the choice (mix_resolve_at_hit) */
    int32_t thickness, g, albedo; /* the coated ones' layer and medium */
    int32_t base_roughness[2];    /* coated conductor: the conductor's u, v */
    uint32_t remap_roughness;
    float scale; /* diffuse transmission: its "scale" on its textured reflectance and transmittance */
    uint32_t pad[3];
} MaterialTextures;

/* Light types (Light.type), one row each: LIGHT(id, feature, sample)
 *   id       LIGHT_<id>, the value of Light.type
 *   feature  the FEATURE_* bit that compiles its code in (feature_mask.h)
 *   sample   the kernel function that samples a direction toward it, in
 *            its header kernels/light_<kind>.h (lights.h dispatches)
 * Area lights are emitting primitives; the infinite lights come first in
 * the light array (BackgroundData). */
#define GMON_LIGHT_TYPES(LIGHT)                                                                                        \
    LIGHT(AREA, FEATURE_AREA_LIGHTS, area_light_sample, area_light_emission)                                           \
    LIGHT(POINT, FEATURE_POINT_LIGHTS, point_light_sample, point_light_emission)                                       \
    LIGHT(SPOT, FEATURE_SPOT_LIGHTS, point_light_sample, point_light_emission)                                         \
    LIGHT(DISTANT, FEATURE_DISTANT_LIGHTS, distant_light_sample, light_emission_none)                                  \
    LIGHT(UNIFORM_INFINITE, FEATURE_ENVIRONMENT, uniform_infinite_light_sample, light_emission_none)                   \
    LIGHT(IMAGE_INFINITE, FEATURE_ENVIRONMENT_MAP, image_infinite_light_sample, light_emission_none)                   \
    LIGHT(GONIOMETRIC, FEATURE_GONIOMETRIC_LIGHTS, point_light_sample, point_light_emission)                           \
    LIGHT(PROJECTION, FEATURE_PROJECTION_LIGHTS, point_light_sample, point_light_emission)

#define LIGHT_ENUM_(id, feature, sample, emit) LIGHT_##id,
enum { GMON_LIGHT_TYPES(LIGHT_ENUM_) LIGHT_TYPE_COUNT };
#undef LIGHT_ENUM_

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
 *   distributions[distribution_offset...] (light_infinite.h);
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

/* The light tree (light_tree.h): a binary tree over the bounded lights
 * (all but the infinite and distant ones), each node the bounds of the
 * light it holds or of its two children: a box, the luminous power, and
 * the cone of directions the emitters face (axis and half-angle theta_o,
 * plus theta_e: how far past theta_o they still emit). Node 0 is the root,
 * an inner node's first child is the next node and `second` the other; a
 * leaf's `second` is its light's index, as ~index. 64 bytes. Each bounded
 * light's leaf is found from the root by its trail (light_trails, indexed
 * by the light's index less the unbounded count): bit k is the side taken
 * at depth k, above a leading 1. */
typedef struct {
    float lower[3];
    float power;
    float upper[3];
    float cos_theta_o;
    float axis[3];
    float cos_theta_e;
    int32_t second;
    uint32_t two_sided;
    uint32_t pad[2];
} LightNode;

/* The light samplers (IntegratorData.light_sampler; pbrt-v4's
 * "lightsampler"): each light's fixed chance (uniform or by power), or the
 * light tree's chances at the shading point. */
#define LIGHT_SAMPLER_UNIFORM 0u
#define LIGHT_SAMPLER_POWER 1u
#define LIGHT_SAMPLER_TREE 2u
#define LIGHT_SAMPLER_COUNT 3u

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

/* The constants of one render, by concern. 256 bytes in all.
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
 * identity for pbrt-v4's default film). max_component_value is pbrt-v4's
 * "maxcomponentvalue" (INFINITY when not given): the host turns it into the
 * per-sample estimator clamp at that level (sample_passes.h); the kernels
 * do not read it. */
typedef struct {
    float from_radiance[3][4];
    float max_component_value;
    uint32_t pad[3];
} FilmData;

#define RENDER_NEE 1u      /* next-event estimation with MIS; else BSDF sampling only */
#define RENDER_TEXTURES 2u /* the scene has texture programs (a kernel with every feature must know) */
/* The integrators with light subpaths (kernels/tracing/bdpt.cl): pbrt-v4's
 * light tracer (light subpaths connected to the camera only), and its
 * bidirectional path tracer. Neither: the path tracer. */
#define RENDER_LIGHTPATH 4u
#define RENDER_BDPT 8u
#define RENDER_REGULARIZE 16u /* bdpt's "regularize": near-specular lobes widened after a rough bounce */

/* rr_threshold is pbrt-v4's "rrthreshold": Russian roulette applies where
 * the path's throughput (times the squared eta ratio) has its largest
 * component below it, from the second bounce on; at most 1 (the host clamps
 * it: above 1 pbrt-v4's roulette never terminates a path), 0 turns it off. */
typedef struct {
    uint32_t max_depth;
    uint32_t flags;
    uint32_t light_count;
    uint32_t seed;
    float rr_threshold;
    uint32_t sampler;          /* SAMPLER_* (sampler.h); the kernels are built for it */
    uint32_t light_sampler;    /* LIGHT_SAMPLER_* */
    uint32_t unbounded_lights; /* lights[0, this): the infinite, then the distant ones */
} IntegratorData;

/* Medium.type */
#define MEDIUM_HOMOGENEOUS 0u
#define MEDIUM_UNIFORM_GRID 1u /* sigma_a, sigma_s, emission times a density grid (and a Lescale grid) */
#define MEDIUM_RGB_GRID 2u     /* RGB grids of sigma_a, sigma_s and Le */
#define MEDIUM_CLOUD 3u        /* pbrt-v4's procedural cloud: sigma_a, sigma_s times its density */
#define MEDIUM_NANOVDB 4u      /* NanoVDB grids: sigma_a, sigma_s times the density grid; blackbody emission */

/* A participating medium (FEATURE_MEDIA): absorption and scattering
 * coefficients per unit of world length, per channel, the radiance it
 * emits (per unit of absorption, as pbrt-v4's Le) and the
 * Henyey-Greenstein asymmetry g. Grids (media.h, medium_at): their values
 * in medium_values, size[0] x size[1] x size[2] cells (x fastest) over the
 * unit cube that medium_from_world (rows of an affine map) takes world
 * points to; uniformgrid: the density grid at `density` multiplies sigma_a,
 * sigma_s and emission, the emission also the le_size grid at `le_scale`;
 * rgbgrid: RGB grids (3 values a cell, or -1: sigma 1, Le 0) times
 * sigma_a[0], sigma_s[0] ("scale"), emission[0] ("Lescale"); cloud: at
 * `density` its density, wispiness, frequency, then its box's lower corner
 * and extent in the medium's space (9 values); nanovdb: the NanoVDB grid of
 * density at `density`, of temperature at `le_scale` (-1: none), its
 * parameters (nanovdb.h) at `rgb_le`. The
 * majorant grid, MEDIUM_MAJORANT_GRID^3 values at `majorants` (x fastest),
 * bounds sigma_t in every channel over each of its cells of the cube (as
 * pbrt-v4's MajorantGrid); `majorant` over the whole cube. 144 bytes. */
#define MEDIUM_MAJORANT_GRID 16
typedef struct {
    float sigma_a[3];
    float g;
    float sigma_s[3];
    uint32_t type;
    float emission[3];
    float majorant;
    float medium_from_world[3][4];
    uint32_t size[3];
    int32_t density;
    uint32_t le_size[3];
    int32_t le_scale;
    int32_t rgb_sigma_a, rgb_sigma_s, rgb_le;
    int32_t majorants;
} Medium;

/* primitive_media[i], primitive i's (in the BVH's order) MediumInterface:
 * the medium behind it (against its normal) in the low 16 bits, the one in
 * front in the high 16, each an index into media or MEDIUM_VACUUM; equal
 * halves: no boundary, the ray keeps its medium. */
#define MEDIUM_VACUUM 0xffffu
#define MEDIUM_MAX_COUNT 0xffffu

/* The media (FEATURE_MEDIA): `count` media, and the one the camera sees
 * through (-1: vacuum). count 0: no media (primitive_media is empty). */
typedef struct {
    uint32_t count;
    int32_t camera_medium;
    uint32_t pad[2];
} MediaData;

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
    MediaData media;
} SceneConstants;

/* The scene's arrays, in the order the path tracer takes them after the
 * constants: ARRAY(name, element type). The kernel's signature, the
 * kernel's Scene and the host's upload (host/render/scene_upload.c) all
 * come from this one list. `distributions` holds the lights' and the
 * pixel filter's sampling distributions, `texels` the lights' images (RGB
 * floats), `shading_normals` the vertex normals of triangles flagged
 * PRIM_SHADING_NORMAL (9 floats a primitive, in the BVH's order; empty
 * when no triangle has them). With textures: `textures` the texture
 * programs, `material_textures` which material parameters they give,
 * `texture_bytes` and `texture_floats` the images' texels (and 8-bit
 * decoding tables), `surface_uvs` SURFACE_UV_FLOATS a primitive in the BVH's
 * order: a triangle's vertex uvs (u0 v0 u1 v1 u2 v2) and its uv density,
 * sqrt(uv area / world area) (spheres compute theirs); all empty without
 * textures. */
#define SURFACE_UV_FLOATS 8
#define GMON_SCENE_ARRAYS(ARRAY)                                                                                       \
    ARRAY(nodes, BvhNode)                                                                                              \
    ARRAY(primitives, Primitive)                                                                                       \
    ARRAY(materials, Material)                                                                                         \
    ARRAY(lights, Light)                                                                                               \
    ARRAY(light_nodes, LightNode)                                                                                      \
    ARRAY(light_trails, uint64_t)                                                                                      \
    ARRAY(distributions, float)                                                                                        \
    ARRAY(texels, float)                                                                                               \
    ARRAY(shading_normals, float)                                                                                      \
    ARRAY(textures, TextureNode)                                                                                       \
    ARRAY(material_textures, MaterialTextures)                                                                         \
    ARRAY(texture_bytes, uint8_t)                                                                                      \
    ARRAY(texture_floats, float)                                                                                       \
    ARRAY(surface_uvs, float)                                                                                          \
    ARRAY(instances, Instance)                                                                                         \
    ARRAY(alphas, AlphaSlot)                                                                                           \
    ARRAY(media, Medium)                                                                                               \
    ARRAY(primitive_media, uint32_t)                                                                                   \
    ARRAY(medium_values, float)

#ifndef __OPENCL_C_VERSION__
_Static_assert(sizeof(Primitive) == 48, "Primitive must match the kernel's layout");
_Static_assert(sizeof(BvhNode) == 288, "BvhNode must match the kernel's layout");
_Static_assert(sizeof(Material) == 128, "Material must match the kernel's layout");
_Static_assert(sizeof(TextureNode) == 224, "TextureNode must match the kernel's layout");
_Static_assert(sizeof(MaterialTextures) == 80, "MaterialTextures must match the kernel's layout");
_Static_assert(sizeof(Instance) == 64, "Instance must match the kernel's layout");
_Static_assert(sizeof(AlphaSlot) == 8, "AlphaSlot must match the kernel's layout");
_Static_assert(sizeof(Light) == 128, "Light must match the kernel's layout");
_Static_assert(sizeof(LightNode) == 64, "LightNode must match the kernel's layout");
_Static_assert(sizeof(Medium) == 144, "Medium must match the kernel's layout");
_Static_assert(sizeof(SceneConstants) == 256, "SceneConstants must match the kernel's layout");
#endif

#endif
