#include "render/scene_convert.h"

#include "bsdf.h"
#include "equal_area.h"
#include "nanovdb.h"
#include "io/image_read.h"
#include "scene/scene.h"
#include "scene/spectrum.h"
#include "scene/textures.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void conductor_index(const SceneMaterial *in, Material *m)
{
    if (in->use_reflectance) {
        conductor_from_reflectance(m, in->reflectance);
        return;
    }
    memcpy(m->conductor_eta, in->conductor_eta, sizeof m->conductor_eta);
    memcpy(m->conductor_k, in->conductor_k, sizeof m->conductor_k);
}

static Material convert_material(const SceneMaterial *in)
{
    static const uint32_t types[] = {
        [SCENE_MATERIAL_DIFFUSE] = MAT_DIFFUSE,
        [SCENE_MATERIAL_DIELECTRIC] = MAT_DIELECTRIC,
        [SCENE_MATERIAL_CONDUCTOR] = MAT_CONDUCTOR,
        [SCENE_MATERIAL_COATED_DIFFUSE] = MAT_COATED_DIFFUSE,
        [SCENE_MATERIAL_DIFFUSE_TRANSMISSION] = MAT_DIFFUSE_TRANSMISSION,
        [SCENE_MATERIAL_MIX] = MAT_MIX,
        [SCENE_MATERIAL_INTERFACE] = MAT_INTERFACE,
        [SCENE_MATERIAL_COATED_CONDUCTOR] = MAT_COATED_CONDUCTOR,
        [SCENE_MATERIAL_THIN_DIELECTRIC] = MAT_THIN_DIELECTRIC,
    };
    Material m;
    memset(&m, 0, sizeof m);
    m.type = types[in->type];
    float alpha[2];
    scene_material_alpha(in, alpha);
    m.alpha_x = alpha[0];
    m.alpha_y = alpha[1];
    m.eta = in->eta;
    memcpy(m.reflectance, in->reflectance, sizeof m.reflectance);
    memcpy(m.transmittance, in->transmittance, sizeof m.transmittance);
    memcpy(m.albedo, in->albedo, sizeof m.albedo);
    m.thickness = in->thickness;
    m.g = in->g;
    m.max_depth = (uint32_t)in->max_depth;
    m.sample_count = (uint32_t)in->sample_count;
    m.mix_amount = in->mix_amount;
    m.mix_materials[0] = in->mix_materials[0];
    m.mix_materials[1] = in->mix_materials[1];
    if (in->type == SCENE_MATERIAL_CONDUCTOR || in->type == SCENE_MATERIAL_COATED_CONDUCTOR)
        conductor_index(in, &m);
    if (in->type == SCENE_MATERIAL_COATED_CONDUCTOR) {
        scene_roughness_alpha(in->base_roughness, in->remap_roughness, alpha);
        m.base_alpha_x = alpha[0];
        m.base_alpha_y = alpha[1];
    }
    return m;
}

_Static_assert(SCENE_MIX_MAX_NESTING <= MIX_MAX_NESTING, "the kernel resolves every mix the parser accepts");

/* "interface" shapes bound media: without media in the render a ray
 * passes them unchanged, so they are left out. */
static int is_interface(const Scene *scene, const SceneShape *shape)
{
    return scene->materials[shape->material].type == SCENE_MATERIAL_INTERFACE;
}

/* pbrt-v4's decoding of an 8- or 16-bit value v in [0, 1]. */
static float decode_texel(const SceneTexture *t, float v)
{
    if (t->encoding == SCENE_ENCODING_SRGB)
        return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
    if (t->encoding == SCENE_ENCODING_GAMMA)
        return powf(v, t->gamma);
    return v;
}

typedef struct {
    const Scene *scene;
    RenderScene *out;
    TextureNode *images; /* per scene texture: its image fields, once loaded */
    int *loaded;
    int *program; /* per scene texture: its program's first node, or -1 */
    char *error;
    size_t error_size;
} TextureConversion;

/* The image fields of scene texture i's node: the image read (or shared
 * with an earlier texture of the same file and decoding). Returns 0 or -1. */
static int image_texels(TextureConversion *c, int i, TextureNode *node)
{
    const SceneTexture *t = &c->scene->textures[i];
    for (size_t j = 0; j < c->scene->texture_count && !c->loaded[i]; ++j) {
        const SceneTexture *u = &c->scene->textures[j];
        if (c->loaded[j] && strcmp(u->filename, t->filename) == 0 && u->encoding == t->encoding &&
            u->gamma == t->gamma && u->single_level == t->single_level) {
            c->images[i] = c->images[j];
            c->loaded[i] = 1;
        }
    }
    if (!c->loaded[i]) {
        TextureImage image;
        char why[512];
        if (image_read_texture(t->filename, &image, why, sizeof why) != IMAGE_IO_OK) {
            snprintf(c->error, c->error_size, "%s: Texture \"%s\": %s", t->origin, t->name, why);
            return -1;
        }
        float decode[256];
        for (int b = 0; b < 256; ++b)
            decode[b] = decode_texel(t, b / 255.0f);
        size_t n = (size_t)image.width * image.height * image.channels;
        for (size_t k = 0; image.needs_decoding && k < n; ++k)
            image.floats[k] = decode_texel(t, image.floats[k]);
        TextureTexels texels = {image.width, image.height, image.channels, image.bytes, decode, image.floats};
        memset(&c->images[i], 0, sizeof c->images[i]);
        int failed = render_scene_add_texture_texels(c->out, &texels, t->single_level, &c->images[i], why, sizeof why);
        texture_image_free(&image);
        if (failed) {
            snprintf(c->error, c->error_size, "%s: Texture \"%s\": %s: %s", t->origin, t->name, t->filename, why);
            return -1;
        }
        c->loaded[i] = 1;
    }
    const TextureNode *image = &c->images[i];
    node->width = image->width;
    node->height = image->height;
    node->levels = image->levels;
    node->channels = image->channels;
    node->texel_offset = image->texel_offset;
    node->texel_format = image->texel_format;
    node->decode_offset = image->decode_offset;
    return 0;
}

/* Appends scene texture i and its inputs to nodes[*count...] in the order
 * they are evaluated; its slot, or -1 on an error. */
static int emit_texture(TextureConversion *c, int i, TextureNode *nodes, int *count)
{
    static const uint32_t types[] = {
        [SCENE_TEXTURE_CONSTANT] = TEXTURE_CONSTANT,
        [SCENE_TEXTURE_IMAGE] = TEXTURE_IMAGE,
        [SCENE_TEXTURE_CHECKERBOARD] = TEXTURE_CHECKERBOARD,
        [SCENE_TEXTURE_SCALE] = TEXTURE_SCALE,
        [SCENE_TEXTURE_MIX] = TEXTURE_MIX,
        [SCENE_TEXTURE_DIRECTION_MIX] = TEXTURE_DIRECTION_MIX,
        [SCENE_TEXTURE_BILERP] = TEXTURE_BILERP,
        [SCENE_TEXTURE_DOTS] = TEXTURE_DOTS,
        [SCENE_TEXTURE_FBM] = TEXTURE_FBM,
        [SCENE_TEXTURE_WRINKLED] = TEXTURE_WRINKLED,
        [SCENE_TEXTURE_WINDY] = TEXTURE_WINDY,
        [SCENE_TEXTURE_MARBLE] = TEXTURE_MARBLE,
    };
    static const uint32_t mappings[] = {
        [SCENE_MAPPING_UV] = TEXTURE_MAP_UV,
        [SCENE_MAPPING_SPHERICAL] = TEXTURE_MAP_SPHERICAL,
        [SCENE_MAPPING_CYLINDRICAL] = TEXTURE_MAP_CYLINDRICAL,
        [SCENE_MAPPING_PLANAR] = TEXTURE_MAP_PLANAR,
        [SCENE_MAPPING_3D] = TEXTURE_MAP_3D,
    };
    static const uint32_t wraps[] = {
        [SCENE_WRAP_REPEAT] = TEXTURE_WRAP_REPEAT,
        [SCENE_WRAP_BLACK] = TEXTURE_WRAP_BLACK,
        [SCENE_WRAP_CLAMP] = TEXTURE_WRAP_CLAMP,
        [SCENE_WRAP_OCTAHEDRAL_SPHERE] = TEXTURE_WRAP_OCTAHEDRAL_SPHERE,
    };
    static const uint32_t filters[] = {
        [SCENE_TEXTURE_FILTER_POINT] = TEXTURE_FILTER_POINT,
        [SCENE_TEXTURE_FILTER_BILINEAR] = TEXTURE_FILTER_BILINEAR,
        [SCENE_TEXTURE_FILTER_TRILINEAR] = TEXTURE_FILTER_TRILINEAR,
    };
    const SceneTexture *t = &c->scene->textures[i];
    TextureNode node;
    memset(&node, 0, sizeof node);
    for (int k = 0; k < 3; ++k) {
        node.operand[k] = -1;
        if (t->input[k].texture >= 0 && (node.operand[k] = emit_texture(c, t->input[k].texture, nodes, count)) < 0)
            return -1;
        memcpy(node.value[k], t->input[k].value, sizeof t->input[k].value);
    }
    node.type = types[t->texture_class];
    node.mapping = mappings[t->mapping];
    node.spectrum = (uint32_t)t->is_spectrum;
    memcpy(node.map_scale, t->map_scale, sizeof node.map_scale);
    memcpy(node.map_delta, t->map_delta, sizeof node.map_delta);
    memcpy(node.texture_from_world, t->texture_from_world, sizeof node.texture_from_world);
    memcpy(node.direction, t->direction, sizeof t->direction);
    if (t->texture_class == SCENE_TEXTURE_BILERP)
        for (int k = 0; k < 4; ++k)
            memcpy(node.value[k], t->bilerp[k], sizeof t->bilerp[k]);
    if (t->texture_class >= SCENE_TEXTURE_FBM) { /* the noise textures */
        node.value[3][0] = t->omega;
        node.value[3][1] = t->variation;
        node.value[3][2] = (float)t->octaves;
        node.scale = t->scale;
    }
    if (t->texture_class == SCENE_TEXTURE_IMAGE) {
        node.wrap = wraps[t->wrap];
        node.filter = filters[t->filter];
        node.invert = (uint32_t)t->invert;
        node.scale = t->scale;
        if (image_texels(c, i, &node))
            return -1;
    }
    nodes[*count] = node;
    return (*count)++;
}

_Static_assert(SCENE_TEXTURE_MAX_NODES == TEXTURE_MAX_PROGRAM, "the scene reader checks the kernels' limit");

/* Scene texture i's program (made once), its first node; -1 on an error. */
static int texture_program(TextureConversion *c, int i)
{
    if (i < 0)
        return -1;
    if (c->program[i] < 0) {
        TextureNode nodes[TEXTURE_MAX_PROGRAM];
        int count = 0;
        if (emit_texture(c, i, nodes, &count) < 0)
            return -2;
        c->program[i] = render_scene_add_texture_program(c->out, nodes, count);
        if (c->program[i] < 0) {
            snprintf(c->error, c->error_size, "%s: out of memory", c->scene->textures[i].origin);
            return -2;
        }
    }
    return c->program[i];
}

/* The materials' texture programs, and alpha_programs[i] for each shape
 * i: its "texture alpha" program's first node, or -1. Returns 0 or -1. */
static int convert_textures(const Scene *scene, RenderScene *out, int *alpha_programs, char *error, size_t error_size)
{
    for (size_t i = 0; i < scene->shape_count; ++i)
        alpha_programs[i] = -1;
    if (scene->texture_count == 0)
        return 0;
    TextureConversion c = {scene,
                           out,
                           calloc(scene->texture_count, sizeof(TextureNode)),
                           calloc(scene->texture_count, sizeof(int)),
                           malloc(scene->texture_count * sizeof(int)),
                           error,
                           error_size};
    int failed = !c.images || !c.loaded || !c.program;
    if (failed)
        snprintf(error, error_size, "out of memory for the textures");
    for (size_t i = 0; !failed && i < scene->texture_count; ++i)
        c.program[i] = -1;
    for (size_t i = 0; i < scene->material_count && !failed; ++i) {
        const SceneMaterial *m = &scene->materials[i];
        int first[SCENE_SLOT_COUNT], any = 0;
        for (int k = 0; k < SCENE_SLOT_COUNT && !failed; ++k) {
            first[k] = texture_program(&c, m->textures[k]);
            failed = first[k] == -2;
            any |= first[k] >= 0;
        }
        MaterialTextures t = {first[SCENE_SLOT_REFLECTANCE],
                              {first[SCENE_SLOT_ROUGHNESS_U], first[SCENE_SLOT_ROUGHNESS_V]},
                              first[SCENE_SLOT_ETA],
                              first[SCENE_SLOT_CONDUCTOR_ETA],
                              first[SCENE_SLOT_CONDUCTOR_K],
                              first[SCENE_SLOT_DISPLACEMENT],
                              first[SCENE_SLOT_NORMAL_MAP],
                              first[SCENE_SLOT_TRANSMITTANCE],
                              first[SCENE_SLOT_MIX_AMOUNT],
                              first[SCENE_SLOT_THICKNESS],
                              first[SCENE_SLOT_G],
                              first[SCENE_SLOT_ALBEDO],
                              {first[SCENE_SLOT_BASE_ROUGHNESS_U], first[SCENE_SLOT_BASE_ROUGHNESS_V]},
                              (uint32_t)m->remap_roughness,
                              m->scale,
                              {0, 0, 0}};
        if (!failed && any && render_scene_set_material_textures(out, (int)i, &t)) {
            snprintf(error, error_size, "out of memory for the textures");
            failed = 1;
        }
    }
    for (size_t i = 0; i < scene->shape_count && !failed; ++i)
        failed = (alpha_programs[i] = texture_program(&c, scene->shapes[i].alpha_texture)) == -2;
    free(c.images);
    free(c.loaded);
    free(c.program);
    return failed ? -1 : 0;
}

/* Each area light's radiance, with "power" applied over its shape's area,
 * into *out (malloc'd; NULL when there are none). Returns 0, or -1 with a
 * message: out of memory, or a power whose radiance over a shape's area
 * overflows single precision or underflows it to 0 or a subnormal. */
static int area_light_emission(const Scene *scene, float (**out)[3], char *error, size_t error_size)
{
    *out = NULL;
    if (scene->area_light_count == 0)
        return 0;
    float(*emission)[3] = malloc(scene->area_light_count * sizeof *emission);
    double *area = calloc(scene->area_light_count, sizeof *area);
    if (!emission || !area) {
        free(emission);
        free(area);
        snprintf(error, error_size, "out of memory for the area lights");
        return -1;
    }
    for (size_t i = 0; i < scene->triangle_count; ++i) {
        const SceneTriangle *t = &scene->triangles[i];
        int light = scene->shapes[t->shape].area_light;
        if (light < 0)
            continue;
        const float *a = &scene->positions[3 * (size_t)t->vertex[0]], *b = &scene->positions[3 * (size_t)t->vertex[1]],
                    *c = &scene->positions[3 * (size_t)t->vertex[2]];
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)b[k] - a[k];
            e2[k] = (double)c[k] - a[k];
        }
        double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2], z = e1[0] * e2[1] - e1[1] * e2[0];
        area[light] += 0.5 * sqrt(x * x + y * y + z * z);
    }
    for (size_t i = 0; i < scene->sphere_count; ++i) {
        int light = scene->shapes[scene->spheres[i].shape].area_light;
        double r = scene->spheres[i].radius;
        if (light >= 0)
            area[light] += 4.0 * 3.14159265358979323846 * r * r;
    }
    for (size_t i = 0; i < scene->area_light_count; ++i) {
        const SceneAreaLight *light = &scene->area_lights[i];
        double k = 1.0;
        if (light->power > 0.0f && area[i] > 0.0)
            k = light->power / (3.14159265358979323846 * (light->two_sided ? 2.0 : 1.0) * area[i]);
        for (int c = 0; c < 3; ++c) {
            double radiance = light->radiance[c] * k;
            emission[i][c] = (float)radiance;
            if (light->radiance[c] > 0.0f && (radiance > FLT_MAX || radiance < FLT_MIN)) {
                snprintf(error, error_size,
                         "%s: AreaLightSource \"power\" %g over its shape's area %g gives a radiance of %g, which "
                         "%s single precision (%g to %g)",
                         light->origin ? light->origin : "AreaLightSource", (double)light->power, area[i], radiance,
                         radiance > FLT_MAX ? "overflows" : "underflows", (double)FLT_MIN, (double)FLT_MAX);
                free(emission);
                free(area);
                return -1;
            }
        }
    }
    free(area);
    *out = emission;
    return 0;
}

static int is_zero(const float v[3])
{
    return v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f;
}

/* Whether the triangle's cross(v1 - v0, v2 - v0) points away from the sum
 * of its vertex normals. */
static int faces_against(const float *v[3], const float *n[3])
{
    double e1[3], e2[3], dot = 0.0;
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)v[1][k] - v[0][k];
        e2[k] = (double)v[2][k] - v[0][k];
    }
    double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (int k = 0; k < 3; ++k)
        dot += g[k] * ((double)n[0][k] + n[1][k] + n[2][k]);
    return dot < 0.0;
}

/* The illuminance an image light of unit scale gives a surface facing its
 * light-space +z, as pbrt-v4 computes it for "illuminance". */
static double image_illuminance(const RgbImage *image)
{
    double sum = 0.0;
    for (uint32_t y = 0; y < image->height; ++y)
        for (uint32_t x = 0; x < image->width; ++x) {
            Vec3 w = equal_area_square_to_sphere((x + 0.5f) / (float)image->width, (y + 0.5f) / (float)image->height);
            const float *rgb = image->rgb + 3 * ((size_t)y * image->width + x);
            if (w.z > 0.0f)
                sum += (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) * w.z;
        }
    return sum * 2.0 * 3.14159265358979323846 / ((double)image->width * image->height);
}

/* A light with an image (infinite, goniometric, projection): its file
 * read, checked and uploaded. Returns 0 or -1. */
static int add_image_light(RenderScene *out, const SceneLight *in, Light *light, char *error, size_t error_size)
{
    RgbImage image;
    char why[512];
    if (image_read_rgb(in->filename, &image, why, sizeof why) != IMAGE_IO_OK) {
        snprintf(error, error_size, "%s: LightSource: %s", in->origin, why);
        return -1;
    }
    int result = 0;
    size_t n = (size_t)image.width * image.height * 3;
    if (image.width != image.height && in->type != SCENE_LIGHT_PROJECTION) {
        snprintf(error, error_size, "%s: LightSource: \"%s\" is %ux%u, not square: not an equal-area image", in->origin,
                 in->filename, image.width, image.height);
        result = -1;
    }
    for (size_t i = 0; i < n && !result; ++i)
        if (!isfinite(image.rgb[i])) {
            snprintf(error, error_size, "%s: LightSource: \"%s\" has non-finite texels", in->origin, in->filename);
            result = -1;
        } else if (image.rgb[i] < 0.0f) {
            image.rgb[i] = 0.0f; /* pbrt-v4 clamps them to zero */
        }
    for (size_t i = 0; in->type == SCENE_LIGHT_GONIOMETRIC && i < n; i += 3) {
        float grey = (image.rgb[i] + image.rgb[i + 1] + image.rgb[i + 2]) / 3.0f; /* pbrt-v4 averages them */
        image.rgb[i] = image.rgb[i + 1] = image.rgb[i + 2] = grey;
    }
    if (in->type == SCENE_LIGHT_PROJECTION) { /* fov spans the shorter axis */
        double t = tan(in->fov * 3.14159265358979323846 / 360.0), aspect = (double)image.width / image.height;
        light->screen_half[0] = (float)(aspect > 1.0 ? aspect * t : t);
        light->screen_half[1] = (float)(aspect > 1.0 ? t : t / aspect);
    }
    double target = in->type == SCENE_LIGHT_IMAGE ? in->illuminance : in->power;
    if (!result && target > 0.0) {
        Light unit_light = *light; /* the power or illuminance of unit scale */
        unit_light.radiance[0] = unit_light.radiance[1] = unit_light.radiance[2] = 1.0f;
        double unit = in->type == SCENE_LIGHT_IMAGE
                          ? image_illuminance(&image)
                          : render_scene_imaged_light_power(&unit_light, image.rgb, image.width, image.height);
        for (int c = 0; c < 3; ++c)
            light->radiance[c] = unit > 0.0 ? (float)(light->radiance[c] * target / unit) : 0.0f;
    }
    if (!result && render_scene_add_image_light(out, light, image.width, image.height, image.rgb, why, sizeof why)) {
        snprintf(error, error_size, "%s: LightSource: %s", in->origin, why);
        result = -1;
    }
    rgb_image_free(&image);
    return result;
}

/* One LightSource as the kernels take it. Returns 0, or -1 with a message. */
static int add_light(RenderScene *out, const SceneLight *in, char *error, size_t error_size)
{
    static const uint32_t types[] = {
        [SCENE_LIGHT_POINT] = LIGHT_POINT,           [SCENE_LIGHT_SPOT] = LIGHT_SPOT,
        [SCENE_LIGHT_DISTANT] = LIGHT_DISTANT,       [SCENE_LIGHT_INFINITE] = LIGHT_UNIFORM_INFINITE,
        [SCENE_LIGHT_IMAGE] = LIGHT_IMAGE_INFINITE,  [SCENE_LIGHT_GONIOMETRIC] = LIGHT_GONIOMETRIC,
        [SCENE_LIGHT_PROJECTION] = LIGHT_PROJECTION,
    };
    Light light;
    memset(&light, 0, sizeof light);
    light.type = types[in->type];
    light.primitive = -1;
    memcpy(light.radiance, in->radiance, sizeof light.radiance);
    memcpy(light.position, in->position, sizeof light.position);
    memcpy(light.direction, in->direction, sizeof light.direction);
    light.cos_falloff_start = in->cos_falloff_start;
    light.cos_total_width = in->cos_total_width;
    memcpy(light.light_from_world, in->light_from_world, sizeof light.light_from_world);
    if (in->filename)
        return add_image_light(out, in, &light, error, error_size);
    if (render_scene_add_light(out, &light)) {
        snprintf(error, error_size, "%s: out of memory", in->origin);
        return -1;
    }
    return 0;
}

_Static_assert((int)SCENE_MAX_FILTER_RADIUS == (int)PIXEL_FILTER_MAX_RADIUS, "the parser checks the renderer's limit");

/* The camera and the pixel filter, for a width x height image. Returns 0,
 * or -1 with the reason in `why`. */
/* ceil(size * fraction) in single precision, as pbrt-v4 computes pixel
 * bounds (in double, 30 * 0.1f is 3.00000004 and would round up to 4). */
static unsigned crop_pixel(unsigned size, float fraction)
{
    float product = (float)size * fraction;
    return (unsigned)ceilf(product);
}

static int convert_camera(const Scene *scene, unsigned width, unsigned height, RenderScene *out, char *why,
                          size_t why_size)
{
    const SceneCamera *in = &scene->camera;
    RenderCamera camera;
    memset(&camera, 0, sizeof camera);
    camera.projection = in->projection == SCENE_CAMERA_ORTHOGRAPHIC ? CAMERA_ORTHOGRAPHIC : CAMERA_PERSPECTIVE;
    memcpy(camera.position, in->position, sizeof camera.position);
    memcpy(camera.forward, in->forward, sizeof camera.forward);
    memcpy(camera.right, in->right, sizeof camera.right);
    memcpy(camera.up, in->up, sizeof camera.up);
    scene_camera_window(in, width, height, camera.window);
    /* A crop window: the pixels it covers, rendered with the part of the
     * screen window they see (raster y runs down, the window's y up). */
    const float *crop = scene->crop_window;
    unsigned x0 = crop_pixel(width, crop[0]), x1 = crop_pixel(width, crop[1]);
    unsigned y0 = crop_pixel(height, crop[2]), y1 = crop_pixel(height, crop[3]);
    if (x1 <= x0 || y1 <= y0) {
        snprintf(why, why_size, "Film: the crop window leaves no pixel at %ux%u", width, height);
        return -1;
    }
    float w[4];
    memcpy(w, camera.window, sizeof w);
    camera.window[0] = (float)(w[0] + (w[1] - (double)w[0]) * x0 / width);
    camera.window[1] = (float)(w[0] + (w[1] - (double)w[0]) * x1 / width);
    camera.window[2] = (float)(w[3] - (w[3] - (double)w[2]) * y1 / height);
    camera.window[3] = (float)(w[3] - (w[3] - (double)w[2]) * y0 / height);
    width = x1 - x0;
    height = y1 - y0;
    for (int i = 0; i < 4; ++i)
        if (!isfinite(camera.window[i])) {
            snprintf(why, why_size, "Camera: the screen window overflows single precision");
            return -1;
        }
    camera.lens_radius = in->lens_radius;
    camera.focal_distance = in->focal_distance;
    camera.width = width;
    camera.height = height;
    render_scene_set_camera(out, &camera);

    static const PixelFilterType types[] = {
        [SCENE_FILTER_BOX] = PIXEL_FILTER_BOX,           [SCENE_FILTER_GAUSSIAN] = PIXEL_FILTER_GAUSSIAN,
        [SCENE_FILTER_MITCHELL] = PIXEL_FILTER_MITCHELL, [SCENE_FILTER_LANCZOS] = PIXEL_FILTER_LANCZOS,
        [SCENE_FILTER_TRIANGLE] = PIXEL_FILTER_TRIANGLE,
    };
    const SceneFilter *f = &scene->filter;
    PixelFilter filter = {types[f->type], {f->radius[0], f->radius[1]}, f->sigma, f->b, f->c, f->tau};
    char reason[192];
    if (render_scene_set_filter(out, &filter, reason, sizeof reason)) {
        snprintf(why, why_size, "PixelFilter: %s", reason);
        return -1;
    }
    return 0;
}

/* medium_from_world of a grid medium: world points to the unit cube of
 * its box (rows of an affine map). Returns 0, or -1 when singular. */
static int grid_transform(const SceneMedium *in, float out[3][4])
{
    double m[3][4], inv[3][4]; /* world_from_medium's rows, and its inverse */
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            m[r][c] = in->world_from_medium[c][r];
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(fabs(det) > 1e-30))
        return -1;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det; /* cofactor, transposed */
        }
    for (int r = 0; r < 3; ++r)
        inv[r][3] = -(inv[r][0] * m[0][3] + inv[r][1] * m[1][3] + inv[r][2] * m[2][3]);
    for (int r = 0; r < 3; ++r) {
        double extent = (double)in->bounds[1][r] - in->bounds[0][r];
        for (int c = 0; c < 4; ++c)
            out[r][c] = (float)((inv[r][c] - (c == 3 ? in->bounds[0][r] : 0.0)) / extent);
    }
    return 0;
}

/* Rows of the affine map from the medium's unit cube (its bounds) to the
 * grid's index space, and back (NanoVDB maps index = inverse (world -
 * translation) in the medium's space). */
static void nanovdb_unit_maps(const SceneMedium *in, const NanoGrid *grid, float index_from_unit[12],
                              float unit_from_index[12])
{
    double matrix[9], inverse[9], translation[3];
    nanovdb_map(grid, matrix, inverse, translation);
    for (int k = 0; k < 3; ++k) {
        double constant = 0.0, extent = (double)in->bounds[1][k] - in->bounds[0][k];
        for (int j = 0; j < 3; ++j) {
            double e = (double)in->bounds[1][j] - in->bounds[0][j];
            index_from_unit[4 * k + j] = (float)(inverse[3 * k + j] * e);
            constant += inverse[3 * k + j] * ((double)in->bounds[0][j] - translation[j]);
            if (unit_from_index)
                unit_from_index[4 * k + j] = (float)(matrix[3 * k + j] / extent);
        }
        index_from_unit[4 * k + 3] = (float)constant;
        if (unit_from_index)
            unit_from_index[4 * k + 3] = (float)((translation[k] - in->bounds[0][k]) / extent);
    }
}

/* A nanovdb medium's largest density per majorant cell, gathered from the
 * grid's leaves and tiles: each widened by a voxel (a trilinear lookup
 * reads the voxels around it), taken to the unit cube, and raising every
 * cell its box overlaps (conservative for rotated grids). */
typedef struct {
    float largest[MEDIUM_MAJORANT_GRID * MEDIUM_MAJORANT_GRID * MEDIUM_MAJORANT_GRID];
    const float *unit_from_index; /* rows of an affine map */
} NanoMajorants;

static void raise_majorants(void *context, const int32_t lo[3], const int32_t hi[3], float value)
{
    enum { R = MEDIUM_MAJORANT_GRID };
    NanoMajorants *g = context;
    int all = lo[0] > hi[0], first[3] = {0, 0, 0}, last[3] = {R - 1, R - 1, R - 1};
    for (int k = 0; k < 3 && !all; ++k) {
        double low = INFINITY, high = -INFINITY;
        for (int corner = 0; corner < 8; ++corner) {
            double u = g->unit_from_index[4 * k + 3];
            for (int j = 0; j < 3; ++j)
                u += g->unit_from_index[4 * k + j] * ((corner >> j & 1) ? hi[j] + 1.0 : lo[j] - 1.0);
            low = fmin(low, u);
            high = fmax(high, u);
        }
        if (high < 0.0 || low > 1.0)
            return;
        first[k] = low <= 0.0 ? 0 : (int)fmin(floor(low * R), R - 1);
        last[k] = high >= 1.0 ? R - 1 : (int)floor(high * R);
    }
    for (int z = first[2]; z <= last[2]; ++z)
        for (int y = first[1]; y <= last[1]; ++y)
            for (int x = first[0]; x <= last[0]; ++x) {
                float *cell = &g->largest[(z * R + y) * R + x];
                *cell = fmaxf(*cell, value);
            }
}

/* Returns 0, or 1 when out of memory. */
static int nanovdb_majorants(const NanoGrid *grid, const float unit_from_index[12], RenderScene *scene, Medium *m)
{
    enum { N = MEDIUM_MAJORANT_GRID * MEDIUM_MAJORANT_GRID * MEDIUM_MAJORANT_GRID };
    NanoMajorants *g = calloc(1, sizeof *g);
    if (!g)
        return 1;
    g->unit_from_index = unit_from_index;
    nanovdb_visit(grid, raise_majorants, g);
    double sigma_t = 0.0, overall = 0.0;
    for (int k = 0; k < 3; ++k)
        sigma_t = fmax(sigma_t, (double)m->sigma_a[k] + m->sigma_s[k]);
    float cells[N];
    for (int i = 0; i < N; ++i) {
        double largest = (double)g->largest[i] * sigma_t;
        cells[i] = (float)(largest * (1.0 + 1e-5));
        overall = fmax(overall, largest);
    }
    free(g);
    m->majorant = (float)(overall * (1.0 + 1e-5));
    return (m->majorants = render_scene_add_medium_values(scene, cells, N)) < 0;
}

/* A nanovdb medium: its grids' bytes and its parameters (nanovdb.h), with
 * a table of the blackbody over the temperatures the grid can reach.
 * Returns 0, or 1 when out of memory. */
static int nanovdb_medium(const SceneMedium *in, RenderScene *out, Medium *m)
{
    enum { N = NANOVDB_BLACKBODY_ENTRIES };
    float q[NANOVDB_PARAMETER_COUNT + 3 * N];
    memset(q, 0, sizeof q);
    m->type = MEDIUM_NANOVDB;
    nanovdb_unit_maps(in, &in->nanovdb_density, q + NANOVDB_DENSITY_FROM_UNIT, q + NANOVDB_UNIT_FROM_DENSITY);
    const NanoGrid *t = &in->nanovdb_temperature;
    double hottest = t->data ? ((double)t->largest - in->temperature_offset) * in->temperature_scale : 0.0;
    int emits = t->data && hottest > NANOVDB_TEMPERATURE_MIN && isfinite(hottest) && in->emission[0] > 0.0f;
    if (emits) {
        nanovdb_unit_maps(in, t, q + NANOVDB_TEMPERATURE_FROM_UNIT, NULL);
        q[NANOVDB_TEMPERATURE_OFFSET] = in->temperature_offset;
        q[NANOVDB_TEMPERATURE_SCALE] = in->temperature_scale;
        q[NANOVDB_BLACKBODY_STEP] = (float)((hottest - NANOVDB_TEMPERATURE_MIN) / (N - 1));
        q[NANOVDB_BLACKBODY_COUNT] = (float)N;
        for (int i = 0; i < N; ++i) {
            double rgb[3];
            spectrum_blackbody_srgb(NANOVDB_TEMPERATURE_MIN + i * (double)q[NANOVDB_BLACKBODY_STEP], rgb);
            for (int k = 0; k < 3; ++k)
                q[NANOVDB_BLACKBODY + 3 * i + k] = (float)rgb[k];
        }
    }
    m->le_scale = -1;
    if ((m->density = render_scene_add_medium_bytes(out, in->nanovdb_density.data, in->nanovdb_density.size)) < 0 ||
        (emits && (m->le_scale = render_scene_add_medium_bytes(out, t->data, t->size)) < 0) ||
        (m->rgb_le = render_scene_add_medium_values(out, q, sizeof q / sizeof q[0])) < 0)
        return 1;
    return nanovdb_majorants(&in->nanovdb_density, q + NANOVDB_UNIT_FROM_DENSITY, out, m);
}

/* A grid medium's values (render_scene_add_medium adds its majorants).
 * Returns 0, or 1 when out of memory. */
static int grid_medium(const SceneMedium *in, RenderScene *out, Medium *m)
{
    size_t n = (size_t)in->size[0] * in->size[1] * in->size[2];
    for (int k = 0; k < 3; ++k) {
        m->size[k] = (uint32_t)in->size[k];
        m->le_size[k] = (uint32_t)in->le_size[k];
    }
    m->density = m->le_scale = m->rgb_sigma_a = m->rgb_sigma_s = m->rgb_le = -1;
    if (in->type == SCENE_MEDIUM_NANOVDB)
        return nanovdb_medium(in, out, m);
    if (in->type == SCENE_MEDIUM_CLOUD) {
        m->type = MEDIUM_CLOUD;
        float cloud[9];
        for (int k = 0; k < 3; ++k) {
            cloud[k] = in->cloud[k];
            cloud[3 + k] = in->bounds[0][k];
            cloud[6 + k] = in->bounds[1][k] - in->bounds[0][k];
        }
        if ((m->density = render_scene_add_medium_values(out, cloud, 9)) < 0)
            return 1;
    } else if (in->type == SCENE_MEDIUM_UNIFORM_GRID) {
        m->type = MEDIUM_UNIFORM_GRID;
        size_t le_n = (size_t)in->le_size[0] * in->le_size[1] * in->le_size[2];
        if ((m->density = render_scene_add_medium_values(out, in->density, n)) < 0 ||
            (m->le_scale = render_scene_add_medium_values(out, in->le_scale, le_n)) < 0)
            return 1;
    } else {
        m->type = MEDIUM_RGB_GRID;
        if ((in->rgb_sigma_a && (m->rgb_sigma_a = render_scene_add_medium_values(out, in->rgb_sigma_a, 3 * n)) < 0) ||
            (in->rgb_sigma_s && (m->rgb_sigma_s = render_scene_add_medium_values(out, in->rgb_sigma_s, 3 * n)) < 0) ||
            (in->rgb_le && (m->rgb_le = render_scene_add_medium_values(out, in->rgb_le, 3 * n)) < 0))
            return 1;
    }
    return 0;
}

/* The media the render traces: none unless the integrator renders media
 * and something (the camera, a shape's interface) is in one it renders;
 * the other types are vacuum (the reader allowed them as unsupported).
 * *map_out: per scene medium its render index or -1, NULL without media.
 * Returns 0, or 1 when out of memory. */
static int convert_media(const Scene *scene, RenderScene *out, int **map_out)
{
    *map_out = NULL;
    if (!scene->integrator_media || scene->medium_count == 0)
        return 0;
    int *map = malloc(scene->medium_count * sizeof *map);
    if (!map)
        return 1;
    int next = 0;
    for (size_t i = 0; i < scene->medium_count; ++i)
        map[i] = scene->media[i].rendered ? next++ : -1;
    int camera = scene->camera_medium >= 0 ? map[scene->camera_medium] : -1, used = camera >= 0;
    for (size_t i = 0; i < scene->shape_count && !used; ++i) {
        const SceneShape *shape = &scene->shapes[i];
        used = (shape->medium_inside >= 0 ? map[shape->medium_inside] : -1) !=
               (shape->medium_outside >= 0 ? map[shape->medium_outside] : -1);
    }
    for (size_t i = 0; i < scene->medium_count && used; ++i) {
        const SceneMedium *in = &scene->media[i];
        if (map[i] < 0)
            continue;
        Medium m;
        memset(&m, 0, sizeof m);
        memcpy(m.sigma_a, in->sigma_a, sizeof m.sigma_a);
        memcpy(m.sigma_s, in->sigma_s, sizeof m.sigma_s);
        memcpy(m.emission, in->emission, sizeof m.emission);
        m.g = in->g;
        m.type = MEDIUM_HOMOGENEOUS;
        if (in->type != SCENE_MEDIUM_HOMOGENEOUS &&
            (grid_transform(in, m.medium_from_world) || grid_medium(in, out, &m)))
            map[i] = -2; /* out of memory (the reader refuses singular transforms) */
        if (map[i] == -2 || render_scene_add_medium(out, &m) < 0) {
            free(map);
            return 1;
        }
    }
    if (!used) {
        free(map);
        return 0;
    }
    out->constants.media.camera_medium = camera;
    *map_out = map;
    return 0;
}

/* Adds shape `index`'s triangles or sphere (with its area light's
 * emission, its alpha: alpha_program its alpha texture's program or -1;
 * with media, medium_map maps its interface's media). Returns 0, or 1 when
 * out of memory. */
static int add_shape(const Scene *scene, size_t index, float (*emission)[3], int alpha_program, const int *medium_map,
                     RenderScene *out)
{
    const SceneShape *shape = &scene->shapes[index];
    if (!medium_map && is_interface(scene, shape))
        return 0;
    int inside = medium_map && shape->medium_inside >= 0 ? medium_map[shape->medium_inside] : -1;
    int outside = medium_map && shape->medium_outside >= 0 ? medium_map[shape->medium_outside] : -1;
    int textured = out->texture_count > 0;
    const SceneAreaLight *light = shape->area_light >= 0 ? &scene->area_lights[shape->area_light] : NULL;
    const float *radiance = light ? emission[shape->area_light] : NULL;
    int two_sided = light && light->two_sided, failed = 0;
    for (size_t i = shape->first; i < shape->first + shape->count && !failed; ++i) {
        if (shape->kind == SCENE_SHAPE_SPHERE) {
            const SceneSphere *sphere = &scene->spheres[i];
            failed = render_scene_add_sphere(out, sphere->center, sphere->radius, shape->material, radiance, two_sided,
                                             shape->flip_normal) != 0;
        } else {
            const SceneTriangle *t = &scene->triangles[i];
            const float *v[3], *n[3] = {NULL, NULL, NULL};
            for (int k = 0; k < 3; ++k) {
                v[k] = &scene->positions[3 * (size_t)t->vertex[k]];
                n[k] = scene->normals ? &scene->normals[3 * (size_t)t->vertex[k]] : NULL;
            }
            int flip = shape->flip_normal, shaded = n[0] && !is_zero(n[0]) && !is_zero(n[1]) && !is_zero(n[2]);
            if (shaded) /* pbrt-v4 turns the geometric normal to the vertex normals' side */
                flip = faces_against(v, n) ? !shape->flip_normal : shape->flip_normal;
            failed =
                render_scene_add_triangle(out, v[0], v[1], v[2], shape->material, radiance, two_sided, flip) != 0 ||
                (shaded && render_scene_set_vertex_normals(out, n[0], n[1], n[2]) != 0);
            if (!failed && textured && shape->has_uvs && scene->uvs) {
                float uv[6];
                for (int k = 0; k < 3; ++k) {
                    uv[2 * k] = scene->uvs[2 * (size_t)t->vertex[k]];
                    uv[2 * k + 1] = scene->uvs[2 * (size_t)t->vertex[k] + 1];
                }
                failed = render_scene_set_uvs(out, uv) != 0;
            }
        }
        failed = failed || ((shape->alpha < 1.0f || alpha_program >= 0) &&
                            render_scene_set_alpha(out, shape->alpha, alpha_program) != 0);
        failed = failed || (inside != outside && render_scene_set_media(out, inside, outside) != 0);
    }
    return failed;
}

/* The objects (their shapes have no area lights: the scene reader drops
 * them) and their instances. Returns 0, 1 when out of memory, or -1 with a
 * message. */
static int add_objects(const Scene *scene, const int *alpha_programs, const int *medium_map, RenderScene *out,
                       char *error, size_t error_size)
{
    for (size_t k = 0; k < scene->object_count; ++k) {
        const SceneObject *object = &scene->objects[k];
        if (render_scene_begin_object(out) < 0)
            return 1;
        for (size_t i = object->first_shape; i < object->first_shape + object->shape_count; ++i)
            if (add_shape(scene, i, NULL, alpha_programs[i], medium_map, out))
                return 1;
        render_scene_end_object(out);
    }
    for (size_t i = 0; i < scene->instance_count; ++i) {
        const SceneInstance *instance = &scene->instances[i];
        double m[3][4];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c)
                m[r][c] = instance->world_from_object[c][r];
        char why[160];
        if (render_scene_add_instance(out, instance->object, (const double(*)[4])m, why, sizeof why)) {
            snprintf(error, error_size, "ObjectInstance \"%s\": %s", scene->objects[instance->object].name, why);
            return -1;
        }
    }
    return 0;
}

int scene_convert_load(const char *path, int allow_unsupported, unsigned width, unsigned height, int quiet,
                       RenderScene *out, SceneSummary *summary, char *error, size_t error_size)
{
    memset(summary, 0, sizeof *summary);
    render_scene_init(out);
    Scene scene;
    SceneLoadOptions options = {.allow_unsupported = allow_unsupported};
    if (scene_load(path, &options, &scene, error, error_size))
        return -1;
    for (size_t i = 0; i < scene.warning_count && !quiet; ++i)
        fprintf(stderr, "%s\n", scene.warnings[i]); /* "file:line: warning: ..." */
    for (size_t i = 0; i < scene.note_count && !quiet; ++i)
        fprintf(stderr, "%s\n", scene.notes[i]); /* "file:line: note: ..." */
    int result = scene_convert(&scene, path, width, height, quiet, out, summary, error, error_size);
    scene_destroy(&scene);
    return result;
}

/* The light types whose rays leaving them the kernels sample (the emit
 * column of GMON_LIGHT_TYPES). */
static int light_emits(uint32_t type)
{
#define LIGHT_EMITS_(id, feature, sample, emit)                                                                        \
    if (type == LIGHT_##id)                                                                                            \
        return strcmp(#emit, "light_emission_none") != 0;
    GMON_LIGHT_TYPES(LIGHT_EMITS_)
#undef LIGHT_EMITS_
    return 0;
}

void scene_convert_light_subpaths(RenderScene *out, int light_subpaths, int regularize, const char *path, int quiet)
{
    out->constants.integrator.flags &= ~(RENDER_BDPT | RENDER_LIGHTPATH | RENDER_REGULARIZE);
    if (!light_subpaths)
        return;
    const char *name = light_subpaths == SCENE_BDPT ? "bdpt" : "lightpath", *why = NULL;
    if (out->constants.camera.projection != CAMERA_PERSPECTIVE)
        why = "an orthographic camera";
    else if (out->constants.media.count > 0)
        why = "participating media";
    for (int i = 0; i < out->light_count && !why; ++i)
        if (!light_emits(out->lights[i].type))
            why = "distant and infinite lights";
    if (why) {
        if (!quiet)
            fprintf(stderr,
                    "warning: %s: Integrator \"%s\" is rendered by the path tracer: gmonrt's %s does not "
                    "take %s yet\n",
                    path, name, name, why);
        return;
    }
    out->constants.integrator.flags |= light_subpaths == SCENE_BDPT ? RENDER_BDPT : RENDER_LIGHTPATH;
    if (light_subpaths == SCENE_BDPT && regularize)
        out->constants.integrator.flags |= RENDER_REGULARIZE;
}

int scene_convert(const Scene *in, const char *path, unsigned width, unsigned height, int quiet, RenderScene *out,
                  SceneSummary *summary, char *error, size_t error_size)
{
    memset(summary, 0, sizeof *summary);
    render_scene_init(out);
    const Scene scene = *in; /* a shallow copy: the body reads scene.field */
    if (scene.film_filename)
        snprintf(summary->film_filename, sizeof summary->film_filename, "%s", scene.film_filename);
    if (scene.sampler) {
        snprintf(summary->sampler, sizeof summary->sampler, "%s", scene.sampler);
        out->constants.integrator.sampler = sampler_for_scene(scene.sampler);
    }
    if (scene.light_sampler && light_sampler_from_name(scene.light_sampler) >= 0)
        out->constants.integrator.light_sampler = (uint32_t)light_sampler_from_name(scene.light_sampler);
    summary->pixel_samples = scene.spp;
    summary->regularize = scene.regularize;

    if (width == 0 || height == 0) {
        width = scene.width;
        height = scene.height;
    }
    char why[256];
    if (convert_camera(&scene, width, height, out, why, sizeof why)) {
        snprintf(error, error_size, "%s: %s", path, why);
        render_scene_destroy(out);
        return -1;
    }
    out->constants.integrator.max_depth = scene.max_depth >= 0 ? (uint32_t)scene.max_depth : 5u;
    out->constants.integrator.rr_threshold = fminf(scene.rr_threshold, 1.0f);
    FilmData *film = &out->constants.film;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            film->from_radiance[r][c] = scene.film_from_radiance[r][c];
    film->max_component_value = scene.max_component_value;
    if (scene.max_component_value < INFINITY && !quiet)
        fprintf(stderr,
                "note: %s: Film \"maxcomponentvalue\" %g: the mean pbrt-v4 writes is layer clamp-%g (each sample "
                "whose largest component exceeds it scaled down to it); the sets, the mean layer and the other "
                "estimators get the samples unclamped\n",
                path, (double)scene.max_component_value, (double)scene.max_component_value);

    int failed = 0;
    for (size_t i = 0; i < scene.light_count && !failed; ++i)
        failed = add_light(out, &scene.lights[i], error, error_size);
    if (failed < 0) {
        render_scene_destroy(out);
        return -1;
    }
    for (size_t i = 0; i < scene.material_count && !failed; ++i) {
        Material m = convert_material(&scene.materials[i]);
        failed = render_scene_add_material(out, &m) < 0;
    }
    int *alpha_programs = malloc((scene.shape_count ? scene.shape_count : 1) * sizeof *alpha_programs);
    if (!failed && (!alpha_programs || convert_textures(&scene, out, alpha_programs, error, error_size))) {
        if (!alpha_programs)
            snprintf(error, error_size, "%s: out of memory converting the scene", path);
        free(alpha_programs);
        render_scene_destroy(out);
        return -1;
    }
    float(*emission)[3] = NULL;
    int *medium_map = NULL;
    if (convert_media(&scene, out, &medium_map)) {
        snprintf(error, error_size, "%s: out of memory converting the media", path);
        free(alpha_programs);
        render_scene_destroy(out);
        return -1;
    }
    if (area_light_emission(&scene, &emission, error, error_size)) {
        free(medium_map);
        free(alpha_programs);
        render_scene_destroy(out);
        return -1;
    }
    /* All triangles before all spheres, as the shapes' order in the primitive
     * array decides the lights' (whose order decides which a random number picks). */
    for (int spheres = 0; spheres < 2; ++spheres)
        for (size_t i = 0; i < scene.shape_count && !failed; ++i)
            if (scene.shapes[i].object < 0 && (scene.shapes[i].kind == SCENE_SHAPE_SPHERE) == spheres)
                failed = add_shape(&scene, i, emission, alpha_programs[i], medium_map, out);
    if (!failed) /* -1 (its message written) must not become 1 (out of memory) */
        failed = add_objects(&scene, alpha_programs, medium_map, out, error, error_size);
    free(medium_map);
    free(emission);
    free(alpha_programs);
    if (failed < 0) {
        render_scene_destroy(out);
        return -1;
    }
    if (failed) {
        snprintf(error, error_size, "%s: out of memory converting the scene", path);
        render_scene_destroy(out);
        return -1;
    }
    summary->texture_bytes = out->texture_byte_count + out->texture_float_count * sizeof(float);
    if (out->texture_count > 0 && !quiet)
        fprintf(stderr, "note: %s: textures: %d texture nodes, %zu bytes of texels (%zu 8-bit, %zu float)\n", path,
                out->texture_count, summary->texture_bytes, out->texture_byte_count,
                out->texture_float_count * sizeof(float));
    if (out->light_count == 0 && !quiet)
        fprintf(stderr, "warning: %s: the scene has no light: the image will be black\n", path);
    summary->light_subpaths = scene.light_subpaths;
    scene_convert_light_subpaths(out, scene.light_subpaths, scene.regularize, path, quiet);
    return 0;
}
