/* The scene as read from a pbrt-v4 file (the subset in docs/scenes.md):
 * camera, film, sampling settings, materials and shapes, flattened into world
 * space. Plain data owned by the Scene; the renderer converts it to the
 * device layout (kernels/tracing/scene_types.h). */
#ifndef HOST_SCENE_SCENE_H
#define HOST_SCENE_SCENE_H

#include <stddef.h>
#include <stdint.h>
#include "scene/nanovdb_file.h"

/* The renderer intersects rays in single precision, squaring distances
 * and multiplying a triangle's two edges by a third length. Beyond these
 * limits those products overflow a float, so scene_load rejects world-space
 * coordinates (vertices, a sphere's extent, the camera) larger in magnitude
 * than SCENE_MAX_COORDINATE, and triangles whose edges from their first
 * vertex have lengths multiplying to more than SCENE_MAX_EDGE_PRODUCT. */
#define SCENE_MAX_COORDINATE 1e18
#define SCENE_MAX_EDGE_PRODUCT 1e19

/* Scene.light_subpaths: the integrators gmonrt renders with light
 * subpaths (kernels/tracing/bdpt.cl). */
#define SCENE_LIGHTPATH 1
#define SCENE_BDPT 2

typedef struct {
    /* Downgrade unsupported features to warnings, each with the substitute
     * docs/scenes.md lists (unknown material: grey diffuse; unknown shape or
     * light: skipped; ...). */
    int allow_unsupported;
    /* `gmonrt check`: go on past every unsupported feature (using its
     * substitute) and every missing file (skipping what needs it), and
     * record each in Scene.diagnostics instead of a warning or an error. */
    int check;
} SceneLoadOptions;

typedef enum {
    SCENE_DIAGNOSTIC_UNSUPPORTED,  /* a feature gmonrt lacks */
    SCENE_DIAGNOSTIC_MISSING_FILE, /* a file the scene names that does not exist */
} SceneDiagnosticKind;

/* What check mode records, once for each distinct one. */
typedef struct {
    SceneDiagnosticKind kind;
    char *file; /* the scene file naming it */
    int line;   /* 0: the file as a whole */
    char *message;
    char *substitute; /* unsupported: what --allow-unsupported uses instead; missing: NULL */
    char *path;       /* missing: the path pbrt-v4 would open; unsupported: NULL */
} SceneDiagnostic;

typedef enum {
    SCENE_CAMERA_PERSPECTIVE,
    SCENE_CAMERA_ORTHOGRAPHIC,
} SceneProjection;

/* A perspective or orthographic camera. pbrt's camera space is
 * left-handed: +z looks into the scene, +x is the image's right and +y its
 * top (as viewed). */
typedef struct {
    SceneProjection projection;
    float world_from_camera[4][4]; /* column-major, [column][row] like cglm's mat4 */
    float position[3];
    float forward[3]; /* unit, camera +z */
    float right[3];   /* unit, camera +x: toward the image's right */
    float up[3];      /* unit, camera +y: toward the image's top */
    float fov;        /* perspective: degrees, across the shorter image axis */
    /* Tangents of the half fields of view (x, y) of the default screen
     * window for the film's size; a ray through image point (sx, sy) in
     * [-1, 1]^2 (sy = 1 at the top) has direction forward + sx * t[0] *
     * right + sy * t[1] * up. */
    float tan_half_fov[2];
    float scale; /* the camera transform's (mean) scale: camera-space lengths times it are world lengths */
    /* A thin lens (lens_radius > 0): the lens radius and the distance of
     * the plane in focus, in world units (the camera-space values times
     * scale). */
    float lens_radius;
    float focal_distance;
    float frame_aspect_ratio; /* "frameaspectratio"; 0: the film's width / height */
    int has_screen_window;
    float screen_window[4]; /* "screenwindow" as written: x_min x_max y_min y_max */
} SceneCamera;

typedef enum {
    SCENE_FILTER_BOX,
    SCENE_FILTER_GAUSSIAN,
    SCENE_FILTER_MITCHELL,
    SCENE_FILTER_LANCZOS, /* pbrt-v4's "sinc" */
    SCENE_FILTER_TRIANGLE,
} SceneFilterType;

/* The renderer's largest filter radius (PIXEL_FILTER_MAX_RADIUS). */
#define SCENE_MAX_FILTER_RADIUS 32.0f

/* PixelFilter: radius in pixels (x, y); sigma applies to the gaussian, b
 * and c to mitchell, tau to sinc. */
typedef struct {
    SceneFilterType type;
    float radius[2];
    float sigma;
    float b, c;
    float tau;
} SceneFilter;

typedef enum {
    SCENE_MATERIAL_DIFFUSE,
    SCENE_MATERIAL_DIELECTRIC,
    SCENE_MATERIAL_CONDUCTOR,
    SCENE_MATERIAL_COATED_DIFFUSE,
    SCENE_MATERIAL_DIFFUSE_TRANSMISSION,
    SCENE_MATERIAL_MIX,
    SCENE_MATERIAL_INTERFACE, /* no surface: its shapes are left out of the render */
    SCENE_MATERIAL_COATED_CONDUCTOR,
    SCENE_MATERIAL_THIN_DIELECTRIC,
} SceneMaterialType;

/* A material's parameters that may be textures (SceneMaterial.textures). */
typedef enum {
    SCENE_SLOT_REFLECTANCE,      /* spectrum: diffuse, coated albedo; conductor "reflectance" */
    SCENE_SLOT_ROUGHNESS_U,      /* float: uroughness (or roughness) */
    SCENE_SLOT_ROUGHNESS_V,      /* float: vroughness (or roughness) */
    SCENE_SLOT_ETA,              /* float: dielectric eta */
    SCENE_SLOT_CONDUCTOR_ETA,    /* spectrum */
    SCENE_SLOT_CONDUCTOR_K,      /* spectrum */
    SCENE_SLOT_DISPLACEMENT,     /* float: bump mapping */
    SCENE_SLOT_NORMAL_MAP,       /* spectrum: the image "string normalmap" names */
    SCENE_SLOT_TRANSMITTANCE,    /* spectrum: diffusetransmission */
    SCENE_SLOT_MIX_AMOUNT,       /* float: mix */
    SCENE_SLOT_THICKNESS,        /* float: the coated ones' layer */
    SCENE_SLOT_ALBEDO,           /* spectrum: the coated ones' medium */
    SCENE_SLOT_G,                /* float: the coated ones' medium */
    SCENE_SLOT_BASE_ROUGHNESS_U, /* float: coatedconductor conductor.uroughness (or conductor.roughness) */
    SCENE_SLOT_BASE_ROUGHNESS_V, /* float: coatedconductor conductor.vroughness (or conductor.roughness) */
    SCENE_SLOT_COUNT
} SceneMaterialSlot;

#define SCENE_MIX_MAX_NESTING 8

/* A material as pbrt-v4 gives it. The coated ones are layered BSDFs: the
 * coating (eta, roughness) over the base (coateddiffuse: reflectance;
 * coatedconductor: conductor_eta/k or reflectance, base_roughness), with
 * thickness, albedo, g, max_depth and sample_count as pbrt-v4's
 * "thickness", "albedo", "g", "maxdepth", "nsamples". */
typedef struct {
    SceneMaterialType type;
    int textures[SCENE_SLOT_COUNT]; /* index into Scene.textures, or -1: the constant below */
    float reflectance[3];   /* diffuse, coateddiffuse and diffusetransmission albedo; conductors when use_reflectance */
    float eta;              /* dielectric, thindielectric, the coatings */
    float conductor_eta[3]; /* conductors, unless use_reflectance (default: copper) */
    float conductor_k[3];
    int use_reflectance;     /* conductor given by "reflectance" instead of eta and k */
    float roughness[2];      /* u, v as written (uroughness/vroughness, else roughness); the coating's */
    int remap_roughness;     /* pbrt's remaproughness: see scene_material_alpha */
    float transmittance[3];  /* diffusetransmission (scaled by its "scale", as reflectance) */
    float scale;             /* diffusetransmission: its "scale", which also multiplies its textures */
    int mix_materials[2];    /* mix: indices into Scene.materials, mixes nested at most SCENE_MIX_MAX_NESTING deep */
    float mix_amount;        /* mix: the chance of mix_materials[1] */
    float base_roughness[2]; /* coatedconductor: the conductor's, as roughness */
    float thickness, g, albedo[3];
    int max_depth, sample_count;
} SceneMaterial;

typedef enum {
    SCENE_TEXTURE_CONSTANT,
    SCENE_TEXTURE_IMAGE,
    SCENE_TEXTURE_CHECKERBOARD,
    SCENE_TEXTURE_SCALE,
    SCENE_TEXTURE_MIX,
    SCENE_TEXTURE_DIRECTION_MIX,
    SCENE_TEXTURE_BILERP,
    SCENE_TEXTURE_DOTS,
    SCENE_TEXTURE_FBM,
    SCENE_TEXTURE_WRINKLED,
    SCENE_TEXTURE_WINDY,
    SCENE_TEXTURE_MARBLE,
} SceneTextureClass;

typedef enum {
    SCENE_MAPPING_UV,
    SCENE_MAPPING_SPHERICAL,
    SCENE_MAPPING_CYLINDRICAL,
    SCENE_MAPPING_PLANAR,
    SCENE_MAPPING_3D, /* checkerboard "dimension" 3 */
} SceneTextureMapping;

typedef enum { SCENE_ENCODING_SRGB, SCENE_ENCODING_LINEAR, SCENE_ENCODING_GAMMA } SceneTextureEncoding;
typedef enum { SCENE_WRAP_REPEAT, SCENE_WRAP_BLACK, SCENE_WRAP_CLAMP, SCENE_WRAP_OCTAHEDRAL_SPHERE } SceneTextureWrap;
typedef enum {
    SCENE_TEXTURE_FILTER_POINT,
    SCENE_TEXTURE_FILTER_BILINEAR,
    SCENE_TEXTURE_FILTER_TRILINEAR,
} SceneTextureFilter;

/* A texture's input: a constant (a float in all three) or a texture. */
typedef struct {
    float value[3];
    int texture; /* index into Scene.textures, or -1 */
} SceneTextureInput;

/* One Texture directive (host/scene/textures.c), pbrt-v4's parameters
 * applied. Inputs: tex1 (scale: tex), tex2, amount (scale: scale). */
typedef struct {
    char *name;
    int is_spectrum;
    SceneTextureClass texture_class;
    SceneTextureMapping mapping;
    float map_scale[2], map_delta[2]; /* uv: uscale vscale udelta vdelta; planar: udelta vdelta */
    /* spherical, cylindrical, 3D: the inverse of the CTM at the directive
     * (rows of an affine map); planar: rows 0 and 1 are v1 and v2 times it. */
    float texture_from_world[3][4];
    SceneTextureInput input[3];
    float bilerp[4][3]; /* v00 v01 v10 v11 */
    /* fbm, wrinkled, marble: "octaves", "roughness" (omega); marble: "variation" (and scale) */
    int octaves;
    float omega, variation;
    float direction[3]; /* directionmix: unit, world space */
    /* imagemap */
    char *filename; /* resolved */
    SceneTextureFilter filter;
    SceneTextureWrap wrap;
    SceneTextureEncoding encoding;
    float gamma;
    float scale;
    int invert;
    int single_level; /* a normal map: bilinear on the image itself, as pbrt-v4 reads one */
    char *origin;     /* "file:line" of the directive, for messages */
    /* A name a material or shape used before its Texture directive: pbrt-v4
     * binds those once the whole scene is read, so it gets this placeholder,
     * which the directive of that name and kind fills in. Until then origin
     * is the first use's owner (`Material "diffuse"`), use_parameter its
     * parameter, at use_file:use_line (valid while the scene is read). */
    int placeholder;
    char *use_parameter;
    const char *use_file;
    int use_line;
} SceneTexture;

typedef enum {
    SCENE_SHAPE_TRIANGLES,
    SCENE_SHAPE_SPHERE,
} SceneShapeKind;

/* One Shape directive. Its surface's front (where its normal points, and
 * the side a one-sided emitter lights) is, unless flip_normal:
 * for triangles cross(v1 - v0, v2 - v0) of the world-space vertices, for a
 * sphere outward. flip_normal is pbrt's ReverseOrientation, for triangles
 * XOR a handedness-swapping transform (pbrt's rule). */
typedef struct {
    SceneShapeKind kind;
    int material;   /* index into Scene.materials */
    int area_light; /* index into Scene.area_lights, or -1 */
    int flip_normal;
    int has_uvs;  /* its vertices have texture coordinates in Scene.uvs (pbrt's own for the tessellated shapes) */
    size_t first; /* triangles [first, first + count); a sphere: its index, count 1 */
    size_t count;
    int object;        /* the object (Scene.objects) it belongs to, or -1: the world's */
    float alpha;       /* "float alpha": 1 opaque, else a cut-out (pbrt-v4's stochastic alpha) */
    int alpha_texture; /* "texture alpha": a float texture (Scene.textures) in place of alpha, or -1 */
    /* The MediumInterface in force: the media (Scene.media, or -1: vacuum)
     * behind the surface (against its normal) and in front of it. Where
     * the two are equal the shape is no boundary between media. */
    int medium_inside, medium_outside;
} SceneShape;

/* ObjectBegin "name" ... ObjectEnd: shapes [first_shape, first_shape +
 * shape_count) of Scene.shapes, in the space the CTM inside the definition
 * gives them ("object space"), drawn only by instances. An area light
 * inside is ignored with a warning, as pbrt-v4 does. */
typedef struct {
    char *name;
    size_t first_shape, shape_count;
} SceneObject;

/* ObjectInstance "name": the object drawn with world_from_object, the
 * CTM at the directive (column-major, [column][row] like cglm's mat4). */
typedef struct {
    int object; /* index into Scene.objects */
    float world_from_object[4][4];
} SceneInstance;

typedef struct {
    uint32_t vertex[3]; /* indices into Scene.positions (and normals) */
    uint32_t shape;     /* index into Scene.shapes */
} SceneTriangle;

typedef struct {
    float center[3];
    float radius;
    uint32_t shape;
} SceneSphere;

/* AreaLightSource "diffuse" on one shape: radiance = L * scale, or with
 * "power" P, L * scale * P / (pi * sides * the shape's area), pbrt-v4's
 * rule, applied by the renderer's conversion (it knows the area). pbrt-v4
 * gives each triangle of a mesh (each bilinear patch, PLY face) a light of
 * its own, so with "power" the parser makes each one a shape. */
typedef struct {
    float radiance[3];
    int two_sided;
    float power;  /* -1: none */
    int shape;    /* index into Scene.shapes */
    char *origin; /* with power: "file:line" of its AreaLightSource, for messages; else NULL */
} SceneAreaLight;

/* LightSource directives (area lights are SceneAreaLight). pbrt-v4's
 * parameters are applied here (scale, power, illuminance, from/to, the
 * CTM), except an image light's illuminance, which needs the image:
 * scene_convert loads the image and applies it. */
typedef enum {
    SCENE_LIGHT_POINT,
    SCENE_LIGHT_SPOT,
    SCENE_LIGHT_DISTANT,
    SCENE_LIGHT_INFINITE, /* uniform */
    SCENE_LIGHT_IMAGE,    /* infinite, from an equal-area square image */
    SCENE_LIGHT_GONIOMETRIC,
    SCENE_LIGHT_PROJECTION,
} SceneLightType;

typedef struct {
    SceneLightType type;
    float radiance[3];                        /* I (point, spot), L (distant, infinite), the image's scale; all RGB */
    float position[3];                        /* point, spot: world space */
    float direction[3];                       /* spot: unit, the way it shines; distant: unit, toward the light */
    float cos_falloff_start, cos_total_width; /* spot */
    float light_from_world[3][3];             /* image, goniometric, projection: rows of the rotation */
    char *filename;                           /* image, goniometric, projection: the path to open */
    float illuminance;                        /* image: target illuminance (pbrt-v4's), or -1 */
    float power;                              /* goniometric, projection: target power, or -1 */
    float fov;                                /* projection: degrees, across the image's shorter axis */
    char *origin;                             /* "file:line" of the directive, for messages */
} SceneLight;

/* MakeNamedMedium's types (pbrt-v4's). */
typedef enum {
    SCENE_MEDIUM_HOMOGENEOUS,
    SCENE_MEDIUM_UNIFORM_GRID,
    SCENE_MEDIUM_RGB_GRID,
    SCENE_MEDIUM_CLOUD,
    SCENE_MEDIUM_NANOVDB,
} SceneMediumType;

/* A participating medium. Homogeneous: absorption and scattering
 * coefficients (per unit of world length: "sigma_a", "sigma_s" or a
 * "preset", times "scale"), emitted radiance ("Le" normalised as an
 * emitter's, times "Lescale") and the Henyey-Greenstein asymmetry "g".
 * Grids have size[0] x size[1] x size[2] cells (x fastest) over the box
 * bounds[0]..bounds[1] ("p0", "p1") of the medium's space, placed in the
 * world by world_from_medium (the CTM at MakeNamedMedium), looked up as
 * pbrt-v4 does (trilinear between cell centres, 0 outside). uniformgrid:
 * sigma_a, sigma_s and emission are per unit of `density` (one value a
 * cell) and the emission is scaled by the `le_scale` grid ("Lescale",
 * le_size cells; one cell of 1 when not given). rgbgrid: rgb_sigma_a,
 * rgb_sigma_s, rgb_le (3 values a cell; NULL: 1, 1 and 0), sigma_a and
 * sigma_s holding "scale" and emission "Lescale" in each channel. cloud:
 * pbrt-v4's procedural cloud over bounds, `cloud` its density, wispiness
 * and frequency, sigma_a and sigma_s per unit of its density. A
 * uniformgrid with a "temperature" grid is read as the rgbgrid of its
 * cells' blackbody emission (media.c). nanovdb: the float grids read from
 * its file (nanovdb_file.h), looked up as pbrt-v4 does (trilinear between
 * voxels at integer index points) over bounds, the world box of their
 * active voxels, sigma_a and sigma_s per unit of density, emission[0]
 * "Lescale" times the blackbody of the temperature grid's
 * (t - temperature_offset) * temperature_scale kelvin (none at 100 K or
 * below, or without a temperature grid: its data NULL). `rendered` 0: a
 * medium whose file check mode found missing (vacuum). */
typedef struct {
    char *name;
    SceneMediumType type;
    int rendered;
    float sigma_a[3], sigma_s[3];
    float emission[3];
    float g;
    int size[3];
    float *density;
    int le_size[3];
    float *le_scale;
    float *rgb_sigma_a, *rgb_sigma_s, *rgb_le;
    float cloud[3];
    NanoGrid nanovdb_density, nanovdb_temperature;
    float temperature_offset, temperature_scale;
    float bounds[2][3];
    float world_from_medium[4][4]; /* column-major, [column][row] like cglm's mat4 */
    char *origin;                  /* "file:line" of its MakeNamedMedium */
} SceneMedium;

typedef struct {
    SceneCamera camera;
    SceneFilter filter;     /* pbrt-v4's default: gaussian, radius 1.5, sigma 0.5 */
    unsigned width, height; /* Film xresolution, yresolution */
    /* Film "cropwindow" (or "pixelbounds" as fractions): x0 x1 y0 y1 of the
     * image, (0, 1, 0, 1) for all of it. The renderer renders and writes
     * pixels [ceil(W x0), ceil(W x1)) x [ceil(H y0), ceil(H y1)) of the
     * W x H image, as pbrt-v4 does. */
    float crop_window[4];
    char *film_filename;
    /* The film's sensor reduced to what an RGB renderer applies to each
     * sample (docs/scenes.md, "The film's response"): the image's linear sRGB is
     * film_from_radiance[row][column] times the sample's radiance (the
     * sensor's response, white balance and pbrt-v4's imaging ratio
     * shutter time * iso / 100 combined; identity for the default film).
     * pbrt-v4 scales a sample whose largest sensor component (XYZ for the
     * default sensor) exceeds max_component_value down to it. */
    float film_from_radiance[3][3];
    float max_component_value; /* INFINITY when not given */
    int save_fp16;             /* Film "savefp16", pbrt-v4's default 1 */
    float film_diagonal;       /* mm (default 35): recorded, only pbrt's realistic camera reads it */
    char *sampler;             /* the Sampler's name as written; the renderer samples independently */
    unsigned spp;              /* Sampler pixelsamples */
    int max_depth;             /* Integrator maxdepth */
    int regularize;            /* Integrator "regularize": applied by bdpt only */
    int light_subpaths;        /* SCENE_LIGHTPATH or SCENE_BDPT for those integrators, else 0: the path tracer */
    float rr_threshold;        /* Integrator "rrthreshold" (default 1): where Russian roulette starts */
    char *light_sampler;       /* Integrator "lightsampler" as written (NULL: pbrt-v4's default, bvh) */
    /* The integrator renders participating media (pbrt-v4's volpath, its
     * default, simplevolpath, bdpt, mlt); pbrt-v4's path and the others
     * ignore them, and so does the renderer then. */
    int integrator_media;
    SceneMedium *media;
    size_t medium_count;
    int camera_medium; /* the outside medium of the MediumInterface in force at Camera, or -1 */

    SceneMaterial *materials;
    size_t material_count;
    SceneTexture *textures;
    size_t texture_count;
    SceneShape *shapes;
    size_t shape_count;
    SceneAreaLight *area_lights;
    size_t area_light_count;

    float *positions; /* world space, 3 floats per vertex */
    float *normals;   /* NULL, or 3 per vertex: world space, unit; zero where a mesh has none */
    float *uvs;       /* NULL, or 2 per vertex: (u, v); zero where a mesh has none (SceneShape.has_uvs) */
    size_t vertex_count;
    SceneTriangle *triangles;
    size_t triangle_count;
    SceneSphere *spheres;
    size_t sphere_count;

    SceneLight *lights;
    size_t light_count;

    SceneObject *objects;
    size_t object_count;
    SceneInstance *instances;
    size_t instance_count;

    char **warnings; /* "file:line: warning: ..." lines, each once, for the renderer to print */
    size_t warning_count;
    char **notes; /* "file:line: note: ..." lines: what is done differently without changing the image */
    size_t note_count;
    SceneDiagnostic *diagnostics; /* check mode only */
    size_t diagnostic_count;
} Scene;

/* Reads `path` (and the files it includes) into *scene. Returns 0, or -1 with
 * a one-line "file:line: ..." message in `error` and *scene empty, except in
 * check mode, where it keeps the warnings, notes and diagnostics found before
 * the error (scene_destroy frees them). options may be NULL (everything
 * unsupported is an error). */
int scene_load(const char *path, const SceneLoadOptions *options, Scene *scene, char *error, size_t error_size);

/* Frees everything the scene owns and empties it; safe on an empty scene. */
void scene_destroy(Scene *scene);

/* pbrt's rule: fov spans the shorter image axis. Writes the tangents of the
 * half fields of view along x and y for a width x height image. */
void scene_camera_tan_half_fov(float fov_degrees, unsigned width, unsigned height, float tan_half[2]);

/* The image's extent [x_min, x_max, y_min, y_max] along the camera's right
 * and up for a width x height film: pbrt's screen window ("screenwindow";
 * else [-frame, frame] x [-1, 1] for a frame, "frameaspectratio" or else
 * width / height, wider than tall, and [-1, 1] x [-1 / frame, 1 / frame]
 * otherwise) times tan(fov / 2) for the perspective camera (the image
 * plane at distance 1) or times the camera's scale for the orthographic
 * one (world lengths). */
void scene_camera_window(const SceneCamera *camera, unsigned width, unsigned height, float window[4]);

/* The GGX (Trowbridge-Reitz) alpha along u and v as pbrt-v4 derives it:
 * sqrt(roughness) when remap_roughness, else roughness itself. */
void scene_roughness_alpha(const float roughness[2], int remap_roughness, float alpha[2]);
void scene_material_alpha(const SceneMaterial *material, float alpha[2]);

#endif
