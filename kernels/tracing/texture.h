/* Texture evaluation (pbrt-v4's textures, TextureNode in scene_types.h):
 * mappings, image lookups (point, bilinear, trilinear over a MIP pyramid
 * with wrap modes) and the program of nodes a parameter's texture is.
 * Shared by the kernels and the host tests; no scene access beyond the
 * arrays in TextureArrays.
 *
 * Filtering: the caller gives the width of the ray's footprint on the
 * surface (a ray cone from the camera, path_tracer.cl) and the surface's
 * uv density; the MIP level is chosen as pbrt-v4 chooses it from ray
 * differentials: log2 of twice the footprint in texels. */
#ifndef KERNELS_TEXTURE_H
#define KERNELS_TEXTURE_H

#include "../common/compat.h"
#include "equal_area.h"
#include "feature_mask.h"
#include "scene_types.h"
#include "../common/vec3.h"

#ifndef __OPENCL_C_VERSION__
#define floor_float(x) floorf(x)
#define atan2_float(y, x) atan2f(y, x)
#else
#define floor_float(x) floor(x)
#define atan2_float(y, x) atan2(y, x)
#endif

typedef struct {
    const GLOBAL TextureNode *nodes;
    const GLOBAL uint8_t *bytes;
    const GLOBAL float *floats;
} TextureArrays;

/* What a texture sees of a surface point. */
typedef struct {
    Vec3 p;           /* world position */
    Vec3 n;           /* shading normal (direction mix) */
    float u, v;       /* the surface's (u, v) */
    float footprint;  /* world width of the ray's footprint on the surface, along its longer axis */
    float uv_density; /* uv units per world length there */
} TextureContext;

/* Maps an integer texel position into the image by the wrap mode (as
 * pbrt-v4's RemapPixelCoords). Returns 0 where the texel is black. */
KERNEL_FN int texture_wrap(uint32_t wrap, int32_t width, int32_t height, int32_t *x, int32_t *y)
{
    if (wrap == TEXTURE_WRAP_REPEAT) {
        *x %= width;
        *y %= height;
        *x += *x < 0 ? width : 0;
        *y += *y < 0 ? height : 0;
        return 1;
    }
    if (wrap == TEXTURE_WRAP_BLACK)
        return *x >= 0 && *x < width && *y >= 0 && *y < height;
    if (wrap == TEXTURE_WRAP_OCTAHEDRAL_SPHERE) {
        /* Mirrored about the square's edges, as the equal-area octahedral
         * square continues across them. */
        if (*x < 0) {
            *x = -*x;
            *y = height - 1 - *y;
        } else if (*x >= width) {
            *x = 2 * width - 1 - *x;
            *y = height - 1 - *y;
        }
        if (*y < 0) {
            *x = width - 1 - *x;
            *y = -*y;
        } else if (*y >= height) {
            *x = width - 1 - *x;
            *y = 2 * height - 1 - *y;
        }
    }
    *x = *x < 0 ? 0 : (*x >= width ? width - 1 : *x); /* clamp, and the rest of the above */
    *y = *y < 0 ? 0 : (*y >= height ? height - 1 : *y);
    return 1;
}

KERNEL_FN uint32_t texture_level_size(uint32_t size, uint32_t level)
{
    uint32_t s = size >> level;
    return s > 0u ? s : 1u;
}

/* Texel (x, y) of a level (already wrapped): 1 or 3 channels as RGB. */
KERNEL_FN Vec3 texture_texel(const TextureArrays *a, const GLOBAL TextureNode *node, uint32_t level, int32_t x,
                             int32_t y)
{
    size_t offset = node->texel_offset;
    for (uint32_t k = 0; k < level; ++k)
        offset += (size_t)texture_level_size(node->width, k) * texture_level_size(node->height, k) * node->channels;
    uint32_t width = texture_level_size(node->width, level);
    offset += ((size_t)y * width + (size_t)x) * node->channels;
    float c[3];
    for (uint32_t i = 0; i < 3u; ++i) {
        size_t at = offset + (node->channels == 3u ? i : 0u);
        c[i] = node->texel_format == TEXEL_BYTES ? a->floats[node->decode_offset + a->bytes[at]] : a->floats[at];
    }
    return vec3(c[0], c[1], c[2]);
}

KERNEL_FN Vec3 texture_texel_wrapped(const TextureArrays *a, const GLOBAL TextureNode *node, uint32_t level, int32_t x,
                                     int32_t y)
{
    int32_t w = (int32_t)texture_level_size(node->width, level), h = (int32_t)texture_level_size(node->height, level);
    if (!texture_wrap(node->wrap, w, h, &x, &y))
        return vec3(0.0f, 0.0f, 0.0f);
    return texture_texel(a, node, level, x, y);
}

/* Image coordinates far outside [0, 1] are brought near it first, where
 * the wrap mode makes no difference (repeat) or the result is the same
 * (clamp, black), so that the texel index fits an int. */
KERNEL_FN float texture_bound_coordinate(float s)
{
    return s < -4.0f ? -4.0f - (s - floor_float(s)) : (s > 4.0f ? 4.0f + (s - floor_float(s)) : s);
}

/* (s, t) brought to where texel indices fit an int, the lookup unchanged. */
KERNEL_FN void texture_fold_coordinates(const GLOBAL TextureNode *node, float *s, float *t)
{
    if (node->wrap == TEXTURE_WRAP_REPEAT) {
        *s -= floor_float(*s);
        *t -= floor_float(*t);
    } else {
        *s = texture_bound_coordinate(*s);
        *t = texture_bound_coordinate(*t);
    }
}

/* The texel containing (s, t) of a level. */
KERNEL_FN Vec3 texture_nearest(const TextureArrays *a, const GLOBAL TextureNode *node, uint32_t level, float s, float t)
{
    float w = (float)texture_level_size(node->width, level), h = (float)texture_level_size(node->height, level);
    texture_fold_coordinates(node, &s, &t);
    return texture_texel_wrapped(a, node, level, (int32_t)floor_float(s * w), (int32_t)floor_float(t * h));
}

/* Bilinear interpolation of a level's texel centres (pbrt-v4's Bilerp). */
KERNEL_FN Vec3 texture_bilinear(const TextureArrays *a, const GLOBAL TextureNode *node, uint32_t level, float s,
                                float t)
{
    float w = (float)texture_level_size(node->width, level), h = (float)texture_level_size(node->height, level);
    texture_fold_coordinates(node, &s, &t);
    float x = s * w - 0.5f, y = t * h - 0.5f;
    float x0 = floor_float(x), y0 = floor_float(y);
    float dx = x - x0, dy = y - y0;
    int32_t xi = (int32_t)x0, yi = (int32_t)y0;
    Vec3 v00 = texture_texel_wrapped(a, node, level, xi, yi), v10 = texture_texel_wrapped(a, node, level, xi + 1, yi);
    Vec3 v01 = texture_texel_wrapped(a, node, level, xi, yi + 1),
         v11 = texture_texel_wrapped(a, node, level, xi + 1, yi + 1);
    /* As two lerps, a + t (b - a): exact where the texels are equal (a flat
     * normal map gives its normal exactly). */
    Vec3 top = v_add(v00, v_scale(v_sub(v10, v00), dx)), bottom = v_add(v01, v_scale(v_sub(v11, v01), dx));
    return v_add(top, v_scale(v_sub(bottom, top), dy));
}

/* log2(x) for x >= 1, piecewise linear between powers of two (exact at
 * them): the exponent plus the mantissa's fraction. Exact arithmetic only,
 * so every build (and the host) picks the same levels; library log2
 * differs in its last bits between pocl's vectorized and scalar code. */
KERNEL_FN float texture_log2(float x)
{
    uint32_t bits = float_bits(x);
    float exponent = (float)((int32_t)(bits >> 23) - 127);
    return exponent + (float_from_bits((bits & 0x7fffffu) | 0x3f800000u) - 1.0f);
}

/* The MIP level (fractional, in [0, levels - 1]) for a footprint of
 * `width` in (s, t) units: pbrt-v4's level, log2 of the width in texels
 * of the finest level. */
KERNEL_FN float texture_mip_level(const GLOBAL TextureNode *node, float width)
{
    uint32_t size = node->width > node->height ? node->width : node->height;
    float texels = width * (float)size;
    float level = texels > 1.0f ? texture_log2(texels < 1e30f ? texels : 1e30f) : 0.0f;
    float top = (float)(node->levels - 1u);
    return level < top ? level : top;
}

/* An image's value at (s, t) for a footprint of `width` (s, t) units. */
KERNEL_FN Vec3 texture_image_lookup(const TextureArrays *a, const GLOBAL TextureNode *node, float s, float t,
                                    float width)
{
    float level = texture_mip_level(node, width);
    uint32_t base = (uint32_t)level;
    if (node->filter == TEXTURE_FILTER_POINT)
        return texture_nearest(a, node, base, s, t);
    Vec3 value = texture_bilinear(a, node, base, s, t);
    float fraction = level - (float)base;
    if (node->filter == TEXTURE_FILTER_TRILINEAR && fraction > 0.0f && base + 1u < node->levels)
        value = v_add(v_scale(value, 1.0f - fraction), v_scale(texture_bilinear(a, node, base + 1u, s, t), fraction));
    return value;
}

/* The point in the node's texture space. */
KERNEL_FN Vec3 texture_space_point(const GLOBAL TextureNode *node, Vec3 p)
{
    const GLOBAL float(*m)[4] = node->texture_from_world;
    return vec3(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]);
}

/* The node's (s, t) at the context's point and the width of the footprint
 * in (s, t) units (twice its largest derivative, as pbrt-v4 widens it). */
KERNEL_FN void texture_map(const GLOBAL TextureNode *node, const TextureContext *c, float *s, float *t, float *width)
{
    float density = c->uv_density;
    if (node->mapping == TEXTURE_MAP_UV) {
        *s = node->map_scale[0] * c->u + node->map_delta[0];
        *t = node->map_scale[1] * c->v + node->map_delta[1];
        float su = abs_float(node->map_scale[0]), sv = abs_float(node->map_scale[1]);
        density *= su > sv ? su : sv;
    } else if (node->mapping == TEXTURE_MAP_PLANAR) {
        Vec3 p = c->p;
        const GLOBAL float(*m)[4] = node->texture_from_world;
        *s = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3] + node->map_delta[0];
        *t = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3] + node->map_delta[1];
        float ls = v_length(vec3_from_global(m[0])), lt = v_length(vec3_from_global(m[1]));
        density = ls > lt ? ls : lt;
    } else {
        Vec3 q = texture_space_point(node, c->p);
        float r = v_length(q);
        if (node->mapping == TEXTURE_MAP_SPHERICAL) {
            equal_area_sphere_to_square(r > 0.0f ? v_scale(q, 1.0f / r) : vec3(0.0f, 0.0f, 1.0f), s, t);
            density = r > 0.0f ? 1.0f / (r * 3.5449077f) : 0.0f; /* the unit sphere's 4 pi onto the unit square */
        } else {
            *s = (PI_F + atan2_float(q.y, q.x)) * (0.5f / PI_F);
            *t = q.z;
            float rho = sqrt_float(q.x * q.x + q.y * q.y);
            density = rho > 0.0f && 1.0f / (2.0f * PI_F * rho) > 1.0f ? 1.0f / (2.0f * PI_F * rho) : 1.0f;
        }
    }
    *width = 2.0f * c->footprint * density;
}

/* ---- Perlin noise and the procedural textures (pbrt-v4's Noise, FBm,
 * Turbulence; textures.cpp's dots, fbm, wrinkled, windy, marble) ---- */

#ifdef __OPENCL_C_VERSION__
#define NOISE_TABLE __constant
#define sin_precise(x) sin(x)
#else
#define NOISE_TABLE static const
#define sin_precise(x) sinf(x)
#endif

/* The permutation of 0..255 of Ken Perlin's reference implementation of
 * "Improving Noise" (SIGGRAPH 2002, mrl.cs.nyu.edu/~perlin/noise/), the
 * table pbrt-v4 uses; typed as data (indices are taken mod 256, so the
 * doubled copy of the reference is not needed). */
NOISE_TABLE uint8_t noise_permutation[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103, 30,  69,  142,
    8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,  197, 62,  94,  252, 219, 203,
    117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165,
    71,  134, 139, 48,  27,  166, 77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,
    55,  46,  245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,
    18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250,
    124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,  182, 189,
    28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,
    129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,
    181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114,
    67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156, 180};

/* The gradient at lattice point (x, y, z) (each mod 256) dotted with the
 * offset (dx, dy, dz) from it: one of the 12 edge directions of a cube
 * (4 of them twice), chosen by the permuted hash, as pbrt-v4 chooses. */
KERNEL_FN float noise_gradient(int32_t x, int32_t y, int32_t z, float dx, float dy, float dz)
{
    int32_t h = noise_permutation[(noise_permutation[(noise_permutation[x & 255] + y) & 255] + z) & 255] & 15;
    float u = h < 8 || h == 12 || h == 13 ? dx : dy;
    float v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

/* Perlin's quintic fade 6 t^5 - 15 t^4 + 10 t^3. */
KERNEL_FN float noise_fade(float t)
{
    float t3 = t * t * t, t4 = t3 * t;
    return 6.0f * t4 * t - 15.0f * t4 + 10.0f * t3;
}

KERNEL_FN float noise_lerp(float t, float a, float b)
{
    return (1.0f - t) * a + t * b;
}

/* A coordinate's lattice cell mod 256 and the offset in it. Exact for every
 * float (floor, a division by 256 and products of integers), so no integer
 * conversion overflows: pbrt-v4 first takes x mod 2^30, which gives the
 * same cell mod 256 and offset. */
KERNEL_FN int32_t noise_cell(float x, float *offset)
{
    float cell = floor_float(x);
    *offset = x - cell;
    return (int32_t)(cell - 256.0f * floor_float(cell * (1.0f / 256.0f)));
}

/* Perlin's improved noise at (x, y, z): 0 at every lattice point, within
 * about [-1, 1]. */
KERNEL_FN float noise3(float x, float y, float z)
{
    float dx, dy, dz;
    int32_t ix = noise_cell(x, &dx), iy = noise_cell(y, &dy), iz = noise_cell(z, &dz);
    float w000 = noise_gradient(ix, iy, iz, dx, dy, dz);
    float w100 = noise_gradient(ix + 1, iy, iz, dx - 1.0f, dy, dz);
    float w010 = noise_gradient(ix, iy + 1, iz, dx, dy - 1.0f, dz);
    float w110 = noise_gradient(ix + 1, iy + 1, iz, dx - 1.0f, dy - 1.0f, dz);
    float w001 = noise_gradient(ix, iy, iz + 1, dx, dy, dz - 1.0f);
    float w101 = noise_gradient(ix + 1, iy, iz + 1, dx - 1.0f, dy, dz - 1.0f);
    float w011 = noise_gradient(ix, iy + 1, iz + 1, dx, dy - 1.0f, dz - 1.0f);
    float w111 = noise_gradient(ix + 1, iy + 1, iz + 1, dx - 1.0f, dy - 1.0f, dz - 1.0f);
    float wx = noise_fade(dx), wy = noise_fade(dy), wz = noise_fade(dz);
    float y0 = noise_lerp(wy, noise_lerp(wx, w000, w100), noise_lerp(wx, w010, w110));
    float y1 = noise_lerp(wy, noise_lerp(wx, w001, w101), noise_lerp(wx, w011, w111));
    return noise_lerp(wz, y0, y1);
}

KERNEL_FN float noise_at(Vec3 p)
{
    return noise3(p.x, p.y, p.z);
}

KERNEL_FN float texture_smooth_step(float x, float a, float b)
{
    float t = (x - a) / (b - a);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    return t * t * (3.0f - 2.0f * t);
}

/* How many octaves of noise a footprint of squared length len2 (texture
 * units) resolves: pbrt-v4's clamp(-1 - log2(len2) / 2, 0, octaves), so
 * that no octave finer than the footprint aliases. log2 is texture_log2's
 * (exact at powers of two, linear between), as for the MIP level: every
 * build counts the same octaves. No footprint: all of them. */
KERNEL_FN float noise_octaves(float len2, float octaves)
{
    if (!(len2 > 0.0f))
        return octaves;
    float n = -1.0f - 0.5f * texture_log2(len2 < 1e30f ? (len2 > 1e-30f ? len2 : 1e-30f) : 1e30f);
    return n < 0.0f ? 0.0f : (n > octaves ? octaves : n);
}

/* pbrt-v4's FBm: sum over octaves i of omega^i noise(1.99^i p), the last,
 * fractional, octave faded in by smoothstep(0.3, 0.7) of its fraction. */
KERNEL_FN float noise_fbm(Vec3 p, float len2, float omega, float octaves)
{
    float n = noise_octaves(len2, octaves);
    int32_t whole = (int32_t)n;
    float sum = 0.0f, lambda = 1.0f, o = 1.0f;
    for (int32_t i = 0; i < whole; ++i) {
        sum += o * noise_at(v_scale(p, lambda));
        lambda *= 1.99f;
        o *= omega;
    }
    return sum + o * texture_smooth_step(n - (float)whole, 0.3f, 0.7f) * noise_at(v_scale(p, lambda));
}

/* pbrt-v4's Turbulence: FBm of |noise|, the octaves past the footprint
 * counted at their average 0.2 (from the fractional one on, as pbrt-v4). */
KERNEL_FN float noise_turbulence(Vec3 p, float len2, float omega, float octaves)
{
    float n = noise_octaves(len2, octaves);
    int32_t whole = (int32_t)n;
    float sum = 0.0f, lambda = 1.0f, o = 1.0f;
    for (int32_t i = 0; i < whole; ++i) {
        sum += o * abs_float(noise_at(v_scale(p, lambda)));
        lambda *= 1.99f;
        o *= omega;
    }
    sum += o *
           noise_lerp(texture_smooth_step(n - (float)whole, 0.3f, 0.7f), 0.2f, abs_float(noise_at(v_scale(p, lambda))));
    for (int32_t i = whole; i < (int32_t)octaves; ++i) {
        sum += o * 0.2f;
        o *= omega;
    }
    return sum;
}

/* pbrt-v4's InsidePolkaDot: a dot of radius 0.35 in each unit cell
 * centred on integer (s, t) where the cell's noise is positive, moved by
 * up to 0.15 by two more noise values. */
KERNEL_FN int noise_inside_dot(float s, float t)
{
    float cell_s = floor_float(s + 0.5f), cell_t = floor_float(t + 0.5f);
    if (!(noise3(cell_s + 0.5f, cell_t + 0.5f, 0.5f) > 0.0f))
        return 0;
    const float radius = 0.35f, shift = 0.5f - radius;
    float centre_s = cell_s + shift * noise3(cell_s + 1.5f, cell_t + 2.8f, 0.5f);
    float centre_t = cell_t + shift * noise3(cell_s + 4.5f, cell_t + 9.8f, 0.5f);
    float ds = s - centre_s, dt = t - centre_t;
    return ds * ds + dt * dt < radius * radius;
}

/* pbrt-v4's marble colour at t in [0, 1]: 1.5 times a spline of cubic
 * Bezier segments over its 9 knots (segment floor(6 t), de Casteljau). */
KERNEL_FN Vec3 noise_marble_colour(float t)
{
    const float knots[9][3] = {{0.58f, 0.58f, 0.6f}, {0.58f, 0.58f, 0.6f}, {0.58f, 0.58f, 0.6f},
                               {0.5f, 0.5f, 0.5f},   {0.6f, 0.59f, 0.58f}, {0.58f, 0.58f, 0.6f},
                               {0.58f, 0.58f, 0.6f}, {0.2f, 0.2f, 0.33f},  {0.58f, 0.58f, 0.6f}};
    float scaled = t * 6.0f;
    int32_t first = (int32_t)floor_float(scaled);
    first = first < 0 ? 0 : (first > 5 ? 5 : first);
    float u = scaled - (float)first, rgb[3];
    for (int c = 0; c < 3; ++c) {
        float a = noise_lerp(u, knots[first][c], knots[first + 1][c]);
        float b = noise_lerp(u, knots[first + 1][c], knots[first + 2][c]);
        float d = noise_lerp(u, knots[first + 2][c], knots[first + 3][c]);
        rgb[c] = 1.5f * noise_lerp(u, noise_lerp(u, a, b), noise_lerp(u, b, d));
    }
    return vec3(rgb[0], rgb[1], rgb[2]);
}

/* How much texture space stretches world lengths, at most (the longest of
 * its axes' images): a footprint's length in texture space is at most the
 * world one times this. */
KERNEL_FN float texture_space_stretch(const GLOBAL TextureNode *node)
{
    const GLOBAL float(*m)[4] = node->texture_from_world;
    float largest = 0.0f;
    for (int c = 0; c < 3; ++c) {
        float length2 = m[0][c] * m[0][c] + m[1][c] * m[1][c] + m[2][c] * m[2][c];
        largest = length2 > largest ? length2 : largest;
    }
    return sqrt_float(largest);
}

/* A 3D noise texture (fbm, wrinkled, windy, marble) at the context's point:
 * the float in all three channels, or marble's RGB. The footprint is the
 * world footprint's length in texture space (pbrt-v4's dpdx and dpdy,
 * here one isotropic width). */
KERNEL_FN Vec3 texture_noise_evaluate(const GLOBAL TextureNode *node, const TextureContext *c)
{
    Vec3 p = texture_space_point(node, c->p);
    float len = c->footprint * texture_space_stretch(node), len2 = len * len;
    float omega = node->value[3][0], variation = node->value[3][1], octaves = node->value[3][2];
    float v;
    if (node->type == TEXTURE_FBM) {
        v = noise_fbm(p, len2, omega, octaves);
    } else if (node->type == TEXTURE_WRINKLED) {
        v = noise_turbulence(p, len2, omega, octaves);
    } else if (node->type == TEXTURE_WINDY) {
        float wind = noise_fbm(v_scale(p, 0.1f), 0.01f * len2, 0.5f, 3.0f);
        v = abs_float(wind) * noise_fbm(p, len2, 0.5f, 6.0f);
    } else { /* TEXTURE_MARBLE */
        float scale = node->scale;
        p = v_scale(p, scale);
        float marble = p.y + variation * noise_fbm(p, scale * scale * len2, omega, octaves);
        return noise_marble_colour(0.5f + 0.5f * sin_precise(marble));
    }
    return vec3(v, v, v);
}

/* Whether floor(x) is odd, for any x (no integer conversion to overflow). */
KERNEL_FN int texture_is_odd(float x)
{
    float f = floor_float(x);
    return f - 2.0f * floor_float(0.5f * f) != 0.0f;
}

/* A node's operand: an earlier slot of the program or its constant. */
KERNEL_FN Vec3 texture_operand(const GLOBAL TextureNode *node, const Vec3 *slots, int i)
{
    return node->operand[i] >= 0 ? slots[node->operand[i]] : vec3_from_global(node->value[i]);
}

KERNEL_FN Vec3 texture_node_evaluate(const TextureArrays *a, const GLOBAL TextureNode *node, const Vec3 *slots,
                                     const TextureContext *c)
{
    if (node->type == TEXTURE_CONSTANT)
        return vec3_from_global(node->value[0]);
    if (node->type == TEXTURE_SCALE)
        return v_mul(texture_operand(node, slots, 0), texture_operand(node, slots, 2));
    if (node->type == TEXTURE_MIX || node->type == TEXTURE_DIRECTION_MIX) {
        float amount = node->type == TEXTURE_MIX ? texture_operand(node, slots, 2).x
                                                 : abs_float(v_dot(c->n, vec3_from_global(node->direction)));
        if (node->type == TEXTURE_DIRECTION_MIX) /* pbrt-v4: amount weighs tex1 */
            amount = 1.0f - amount;
        return v_add(v_scale(texture_operand(node, slots, 0), 1.0f - amount),
                     v_scale(texture_operand(node, slots, 1), amount));
    }
    if (node->type == TEXTURE_CHECKERBOARD && node->mapping == TEXTURE_MAP_3D) {
        Vec3 q = texture_space_point(node, c->p);
        int odd = texture_is_odd(q.x) ^ texture_is_odd(q.y) ^ texture_is_odd(q.z);
        return texture_operand(node, slots, odd);
    }
    if (GMON_HAS_PROCEDURAL_TEXTURES && node->type >= TEXTURE_FBM)
        return texture_noise_evaluate(node, c);
    float s, t, width;
    texture_map(node, c, &s, &t, &width);
    if (GMON_HAS_PROCEDURAL_TEXTURES && node->type == TEXTURE_DOTS)
        return texture_operand(node, slots, noise_inside_dot(s, t) ? 0 : 1);
    if (node->type == TEXTURE_CHECKERBOARD) {
        return texture_operand(node, slots, texture_is_odd(s) ^ texture_is_odd(t));
    }
    if (node->type == TEXTURE_BILERP) {
        Vec3 v00 = vec3_from_global(node->value[0]), v01 = vec3_from_global(node->value[1]);
        Vec3 v10 = vec3_from_global(node->value[2]), v11 = vec3_from_global(node->value[3]);
        return v_add(v_add(v_scale(v00, (1.0f - s) * (1.0f - t)), v_scale(v01, (1.0f - s) * t)),
                     v_add(v_scale(v10, s * (1.0f - t)), v_scale(v11, s * t)));
    }
    /* TEXTURE_IMAGE: rows from the top, so t runs up from the bottom. */
    Vec3 value = v_scale(texture_image_lookup(a, node, s, 1.0f - t, width), node->scale);
    if (node->invert)
        value = v_sub(vec3(1.0f, 1.0f, 1.0f), value);
    return vec3(value.x > 0.0f ? value.x : 0.0f, value.y > 0.0f ? value.y : 0.0f, value.z > 0.0f ? value.z : 0.0f);
}

/* The value of the texture program starting at node `first`: RGB for a
 * spectrum texture, the float in all three for a float one. */
KERNEL_FN Vec3 texture_evaluate(const TextureArrays *a, int32_t first, const TextureContext *c)
{
    Vec3 slots[TEXTURE_MAX_PROGRAM];
#ifndef __OPENCL_C_VERSION__
    memset(slots, 0, sizeof slots); /* gcc cannot see that operands precede their node */
#endif
    const GLOBAL TextureNode *program = a->nodes + first;
    uint32_t n = program->program_length;
    for (uint32_t i = 0; i < n; ++i)
        slots[i] = texture_node_evaluate(a, program + i, slots, c);
    return slots[n - 1u];
}

/* A float texture's value: what the alpha cut-outs and bump maps read. */
KERNEL_FN float texture_evaluate_float(const TextureArrays *a, int32_t first, const TextureContext *c)
{
    return texture_evaluate(a, first, c).x;
}

#endif
