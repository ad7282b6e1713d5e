/* The RenderScene's textures: programs, the per-material table, texels
 * with their MIP pyramids, and the triangles' uvs (render_scene.h). */
#include "render/render_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Grows *array to hold `needed` items of `size` bytes. */
static int grow(void **array, size_t *capacity, size_t needed, size_t size)
{
    if (needed <= *capacity)
        return 0;
    size_t grown = *capacity * 2 > needed ? *capacity * 2 : needed;
    if (grown > SIZE_MAX / size)
        return -1;
    void *p = realloc(*array, grown * size);
    if (!p)
        return -1;
    *array = p;
    *capacity = grown;
    return 0;
}

int render_scene_add_texture_program(RenderScene *scene, const TextureNode *nodes, int count)
{
    size_t capacity = (size_t)scene->texture_capacity;
    if (count <= 0 || grow((void **)&scene->textures, &capacity, (size_t)scene->texture_count + count, sizeof *nodes))
        return -1;
    scene->texture_capacity = (int)capacity;
    int first = scene->texture_count;
    memcpy(scene->textures + first, nodes, (size_t)count * sizeof *nodes);
    scene->textures[first].program_length = (uint32_t)count;
    scene->texture_count += count;
    return first;
}

static const MaterialTextures no_textures = {-1, {-1, -1}, -1, -1, -1,       -1, -1,   -1,
                                             -1, -1,       -1, -1, {-1, -1}, 0,  1.0f, {0, 0, 0}};

/* Extends the table to cover `count` materials, new ones untextured. */
static int cover_materials(RenderScene *scene, int count)
{
    if (count <= scene->material_texture_count)
        return 0;
    MaterialTextures *grown = realloc(scene->material_textures, (size_t)count * sizeof *grown);
    if (!grown)
        return -1;
    for (int i = scene->material_texture_count; i < count; ++i)
        grown[i] = no_textures;
    scene->material_textures = grown;
    scene->material_texture_count = count;
    return 0;
}

int render_scene_set_material_textures(RenderScene *scene, int material, const MaterialTextures *textures)
{
    if (cover_materials(scene, material + 1))
        return -1;
    scene->material_textures[material] = *textures;
    return 0;
}

int render_scene_set_uvs(RenderScene *scene, const float uv[6])
{
    size_t last = (size_t)scene->primitive_count - 1, capacity = (size_t)scene->primitive_capacity;
    if (capacity > scene->vertex_uv_capacity) {
        float *grown = realloc(scene->vertex_uvs, capacity * SURFACE_UV_FLOATS * sizeof *grown);
        if (!grown)
            return -1;
        memset(grown + SURFACE_UV_FLOATS * scene->vertex_uv_capacity, 0,
               (capacity - scene->vertex_uv_capacity) * SURFACE_UV_FLOATS * sizeof *grown);
        scene->vertex_uvs = grown;
        scene->vertex_uv_capacity = capacity;
    }
    float *v = scene->vertex_uvs + SURFACE_UV_FLOATS * last;
    memcpy(v, uv, 6 * sizeof *v);
    v[7] = 1.0f;
    return 0;
}

/* A triangle's uv entry: its uvs (or pbrt's default) and its uv density. */
static void triangle_uvs(const Primitive *p, const float *given, float *out)
{
    static const float pbrt_default[6] = {0, 0, 1, 0, 1, 1};
    memcpy(out, given && given[7] != 0.0f ? given : pbrt_default, 6 * sizeof *out);
    double e1[3], e2[3];
    for (int i = 0; i < 3; ++i) {
        e1[i] = p->b[i];
        e2[i] = p->c[i];
    }
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    double world = sqrt(cx * cx + cy * cy + cz * cz);
    double uv = fabs(((double)out[2] - out[0]) * ((double)out[5] - out[1]) -
                     ((double)out[4] - out[0]) * ((double)out[3] - out[1]));
    out[6] = world > 0.0 ? (float)sqrt(uv / world) : 0.0f;
    out[7] = 0.0f;
}

int render_scene_finalize_textures(RenderScene *scene, char *error, size_t error_size)
{
    free(scene->surface_uvs);
    scene->surface_uvs = NULL;
    scene->constants.integrator.flags &= ~RENDER_TEXTURES;
    if (scene->texture_count == 0)
        return 0;
    scene->constants.integrator.flags |= RENDER_TEXTURES;
    size_t count = (size_t)scene->bvh.primitive_count;
    if (cover_materials(scene, scene->material_count) ||
        !(scene->surface_uvs = calloc(SURFACE_UV_FLOATS * (count ? count : 1), sizeof *scene->surface_uvs))) {
        snprintf(error, error_size, "out of memory for the textures");
        return -1;
    }
    for (size_t i = 0; i < count; ++i) {
        const Primitive *p = &scene->bvh.primitives[i];
        if ((p->kind & PRIM_KIND_MASK) != PRIM_TRIANGLE)
            continue;
        size_t input = (size_t)scene->bvh.order[i];
        const float *given = input < scene->vertex_uv_capacity ? scene->vertex_uvs + SURFACE_UV_FLOATS * input : NULL;
        triangle_uvs(p, given, scene->surface_uvs + SURFACE_UV_FLOATS * i);
    }
    return 0;
}

size_t render_scene_texture_bytes(const RenderScene *scene)
{
    return (size_t)scene->texture_count * sizeof(TextureNode) +
           (size_t)scene->material_texture_count * sizeof(MaterialTextures) + scene->texture_byte_count +
           scene->texture_float_count * sizeof(float) +
           (scene->surface_uvs ? SURFACE_UV_FLOATS * (size_t)scene->bvh.primitive_count * sizeof(float) : 0);
}

/* The byte whose decoded value is nearest v (decode increasing). */
static uint8_t nearest_byte(const float *decode, float v)
{
    int lo = 0, hi = 255;
    while (lo < hi) { /* the first byte decoding to >= v */
        int mid = (lo + hi) / 2;
        if (decode[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo > 0 && v - decode[lo - 1] <= decode[lo] - v)
        --lo;
    return (uint8_t)lo;
}

static uint32_t level_size(uint32_t size, uint32_t level)
{
    uint32_t s = size >> level;
    return s > 0u ? s : 1u;
}

int render_scene_add_texture_texels(RenderScene *scene, const TextureTexels *texels, int single_level,
                                    TextureNode *node, char *error, size_t error_size)
{
    uint32_t w = texels->width, h = texels->height, channels = texels->channels;
    if (w == 0 || h == 0 || (uint64_t)w * h > ((uint64_t)1 << 31)) {
        snprintf(error, error_size, "an image of %ux%u texels (1 to 2^31 texels)", w, h);
        return -1;
    }
    uint32_t levels = 1;
    while (!single_level && ((w >> levels) > 0 || (h >> levels) > 0))
        ++levels;
    size_t total = 0;
    for (uint32_t k = 0; k < levels; ++k)
        total += (size_t)level_size(w, k) * level_size(h, k) * channels;
    size_t level0 = (size_t)w * h * channels;
    if (texels->floats)
        for (size_t i = 0; i < level0; ++i)
            if (!isfinite(texels->floats[i])) {
                snprintf(error, error_size, "texel %zu is not finite (%g)", i / channels, (double)texels->floats[i]);
                return -1;
            }
    int bytes = texels->bytes != NULL;
    size_t offset = bytes ? scene->texture_byte_count : scene->texture_float_count;
    size_t extra = bytes ? 256 : 0; /* the decoding table */
    if (offset + total > UINT32_MAX || scene->texture_float_count + extra > UINT32_MAX) {
        snprintf(error, error_size, "the textures exceed 2^32 texel values");
        return -1;
    }
    if (bytes ? grow((void **)&scene->texture_bytes, &scene->texture_byte_capacity, offset + total, 1)
              : grow((void **)&scene->texture_floats, &scene->texture_float_capacity, offset + total, sizeof(float))) {
        snprintf(error, error_size, "out of memory for %zu texels", total / channels);
        return -1;
    }
    if (bytes) {
        if (grow((void **)&scene->texture_floats, &scene->texture_float_capacity, scene->texture_float_count + 256,
                 sizeof(float))) {
            snprintf(error, error_size, "out of memory");
            return -1;
        }
        node->decode_offset = (uint32_t)scene->texture_float_count;
        memcpy(scene->texture_floats + scene->texture_float_count, texels->decode, 256 * sizeof(float));
        scene->texture_float_count += 256;
        memcpy(scene->texture_bytes + offset, texels->bytes, level0);
    } else {
        memcpy(scene->texture_floats + offset, texels->floats, level0 * sizeof(float));
    }
    /* Each level the 2x2 box average of the one above (the last row or
     * column of an odd size folded into its neighbour's box). */
    size_t source = offset;
    for (uint32_t k = 1; k < levels; ++k) {
        uint32_t sw = level_size(w, k - 1), sh = level_size(h, k - 1), dw = level_size(w, k), dh = level_size(h, k);
        size_t target = source + (size_t)sw * sh * channels;
        for (uint32_t y = 0; y < dh; ++y)
            for (uint32_t x = 0; x < dw; ++x)
                for (uint32_t c = 0; c < channels; ++c) {
                    uint32_t x0 = 2 * x < sw ? 2 * x : sw - 1, y0 = 2 * y < sh ? 2 * y : sh - 1;
                    uint32_t x1 = x0 + 1 < sw ? x0 + 1 : x0, y1 = y0 + 1 < sh ? y0 + 1 : y0;
                    if (x == dw - 1)
                        x1 = sw - 1;
                    if (y == dh - 1)
                        y1 = sh - 1;
                    double sum = 0.0;
                    int n = 0;
                    for (uint32_t yy = y0; yy <= y1; ++yy)
                        for (uint32_t xx = x0; xx <= x1; ++xx, ++n) {
                            size_t at = source + ((size_t)yy * sw + xx) * channels + c;
                            sum += bytes ? texels->decode[scene->texture_bytes[at]] : scene->texture_floats[at];
                        }
                    size_t out = target + ((size_t)y * dw + x) * channels + c;
                    if (bytes)
                        scene->texture_bytes[out] = nearest_byte(texels->decode, (float)(sum / n));
                    else
                        scene->texture_floats[out] = (float)(sum / n);
                }
        source = target;
    }
    if (bytes)
        scene->texture_byte_count = offset + total;
    else
        scene->texture_float_count = offset + total;
    node->width = w;
    node->height = h;
    node->levels = levels;
    node->channels = channels;
    node->texel_offset = (uint32_t)offset;
    node->texel_format = bytes ? TEXEL_BYTES : TEXEL_FLOATS;
    return 0;
}
