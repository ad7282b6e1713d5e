/* Textures: lookups against hand-computed texel values (nearest,
 * bilinear, every wrap mode, sRGB bytes), MIP pyramids and level
 * selection at a known distance, procedural textures and mappings at known
 * points (kernels/tracing/texture.h, included here as the kernels include it); the
 * scene reader's and converter's textures and their errors; "texture
 * alpha" in the host's ray traversal; and on a
 * device: a constant displacement changes nothing, a flat normal map is no
 * normal map bit for bit, a checkerboard shows its two colours. */
#define _POSIX_C_SOURCE 200809L

#include "camera.h"
#include "intersect.h"
#include "procedural_reference.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "test_device.h"
#include "texture.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

static char temp_dir[64];
static char error[1024];

/* A 4 x 2 grey float image, texel (x, y) = 10 y + x. */
static const float grey[8] = {0, 1, 2, 3, 10, 11, 12, 13};

static TextureNode image_node(uint32_t width, uint32_t height, uint32_t channels, uint32_t wrap)
{
    TextureNode node;
    memset(&node, 0, sizeof node);
    node.type = TEXTURE_IMAGE;
    node.width = width;
    node.height = height;
    node.levels = 1;
    node.channels = channels;
    node.texel_format = TEXEL_FLOATS;
    node.wrap = wrap;
    node.scale = 1.0f;
    node.map_scale[0] = node.map_scale[1] = 1.0f;
    for (int i = 0; i < 3; ++i)
        node.operand[i] = -1;
    return node;
}

static TextureArrays arrays_of(const TextureNode *nodes, const uint8_t *bytes, const float *floats)
{
    TextureArrays a = {nodes, bytes, floats};
    return a;
}

static void test_nearest_and_wrap(void **state)
{
    (void)state;
    TextureNode node = image_node(4, 2, 1, TEXTURE_WRAP_REPEAT);
    TextureArrays a = arrays_of(&node, NULL, grey);
    /* (0.3, 0.75): texel (floor(1.2), floor(1.5)) = (1, 1). */
    assert_float_equal(texture_nearest(&a, &node, 0, 0.3f, 0.75f).x, 11.0f, 0.0f);
    assert_float_equal(texture_nearest(&a, &node, 0, 1.3f, 0.75f).x, 11.0f, 0.0f);
    assert_float_equal(texture_nearest(&a, &node, 0, -0.7f, -0.25f).x, 11.0f, 0.0f);
    node.wrap = TEXTURE_WRAP_CLAMP; /* column 5 clamps to 3 */
    assert_float_equal(texture_nearest(&a, &node, 0, 1.3f, 0.75f).x, 13.0f, 0.0f);
    assert_float_equal(texture_nearest(&a, &node, 0, -1e30f, 0.25f).x, 0.0f, 0.0f);
    node.wrap = TEXTURE_WRAP_BLACK;
    assert_float_equal(texture_nearest(&a, &node, 0, 1.3f, 0.75f).x, 0.0f, 0.0f);
    assert_float_equal(texture_nearest(&a, &node, 0, 0.3f, 0.75f).x, 11.0f, 0.0f);
    /* pbrt-v4's octahedral wrap: past an edge, mirrored across it and
     * across the middle of the other axis. */
    int32_t x = -1, y = 0;
    assert_true(texture_wrap(TEXTURE_WRAP_OCTAHEDRAL_SPHERE, 4, 2, &x, &y));
    assert_int_equal(x, 1);
    assert_int_equal(y, 1);
    x = 4, y = 0;
    texture_wrap(TEXTURE_WRAP_OCTAHEDRAL_SPHERE, 4, 2, &x, &y);
    assert_int_equal(x, 3);
    assert_int_equal(y, 1);
    x = 1, y = 2;
    texture_wrap(TEXTURE_WRAP_OCTAHEDRAL_SPHERE, 4, 2, &x, &y);
    assert_int_equal(x, 2);
    assert_int_equal(y, 1);
    x = -3, y = 7;
    texture_wrap(TEXTURE_WRAP_REPEAT, 4, 2, &x, &y);
    assert_int_equal(x, 1);
    assert_int_equal(y, 1);
}

static void test_bilinear(void **state)
{
    (void)state;
    TextureNode node = image_node(4, 2, 1, TEXTURE_WRAP_REPEAT);
    TextureArrays a = arrays_of(&node, NULL, grey);
    /* (0.5, 0.5) lies between texel centres (1..2, 0..1): their mean. */
    assert_float_equal(texture_bilinear(&a, &node, 0, 0.5f, 0.5f).x, (1 + 2 + 11 + 12) / 4.0f, 1e-6f);
    /* (0.125, 0.25): texel (0, 0)'s centre exactly. */
    assert_float_equal(texture_bilinear(&a, &node, 0, 0.125f, 0.25f).x, 0.0f, 1e-6f);
    /* At s = 0, t = 0.75: half of column -1 and half of column 0, row 1. */
    assert_float_equal(texture_bilinear(&a, &node, 0, 0.0f, 0.75f).x, 0.5f * 13 + 0.5f * 10, 1e-6f);
    node.wrap = TEXTURE_WRAP_CLAMP;
    assert_float_equal(texture_bilinear(&a, &node, 0, 0.0f, 0.75f).x, 10.0f, 1e-6f);
    node.wrap = TEXTURE_WRAP_BLACK;
    assert_float_equal(texture_bilinear(&a, &node, 0, 0.0f, 0.75f).x, 5.0f, 1e-6f);
    /* A quarter of the way: 0.75 (1, 0) + 0.25 (2, 0) at x = 1.25 (s = 1.75 / 4). */
    node.wrap = TEXTURE_WRAP_REPEAT;
    assert_float_equal(texture_bilinear(&a, &node, 0, 1.75f / 4.0f, 0.25f).x, 0.75f * 1 + 0.25f * 2, 1e-6f);
}

/* The sRGB transfer function, in double, as the standard writes it. */
static double srgb_decode(int byte)
{
    double v = byte / 255.0;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

static void test_srgb_bytes_and_pyramid(void **state)
{
    (void)state;
    RenderScene scene;
    render_scene_init(&scene);
    float decode[256];
    for (int b = 0; b < 256; ++b)
        decode[b] = (float)srgb_decode(b);
    const uint8_t rgb[6] = {0, 128, 255, 64, 200, 10}; /* 2 x 1 */
    TextureTexels texels = {2, 1, 3, rgb, decode, NULL};
    TextureNode node = image_node(0, 0, 0, TEXTURE_WRAP_REPEAT);
    assert_int_equal(render_scene_add_texture_texels(&scene, &texels, 0, &node, error, sizeof error), 0);
    assert_int_equal(node.levels, 2); /* 2x1, 1x1 */
    assert_int_equal(node.texel_format, TEXEL_BYTES);
    assert_int_equal(scene.texture_byte_count, 6 + 3); /* 8-bit stays 8-bit */
    TextureArrays a = arrays_of(&node, scene.texture_bytes, scene.texture_floats);
    Vec3 left = texture_nearest(&a, &node, 0, 0.25f, 0.5f), right = texture_nearest(&a, &node, 0, 0.75f, 0.5f);
    assert_float_equal(left.y, 0.21586050f, 1e-7f); /* sRGB 128 */
    assert_float_equal(left.z, 1.0f, 0.0f);
    assert_float_equal(right.x, (float)srgb_decode(64), 0.0f);
    /* Level 1: each channel's linear mean, re-encoded to the nearest byte. */
    Vec3 top = texture_nearest(&a, &node, 1, 0.5f, 0.5f);
    const int channel_bytes[3][2] = {{0, 64}, {128, 200}, {255, 10}};
    float got[3] = {top.x, top.y, top.z};
    for (int c = 0; c < 3; ++c) {
        double mean = 0.5 * (srgb_decode(channel_bytes[c][0]) + srgb_decode(channel_bytes[c][1]));
        int best = 0;
        for (int b = 1; b < 256; ++b)
            if (fabs(srgb_decode(b) - mean) < fabs(srgb_decode(best) - mean))
                best = b;
        assert_float_equal(got[c], (float)srgb_decode(best), 0.0f);
    }
    render_scene_destroy(&scene);
}

static void test_mip_level_at_distance(void **state)
{
    (void)state;
    /* A 256 x 256 checker of single texels, 0 and 1: every coarser level is 0.5. */
    float *texels = malloc(256 * 256 * sizeof *texels);
    assert_non_null(texels);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            texels[y * 256 + x] = (float)((x + y) & 1);
    RenderScene scene;
    render_scene_init(&scene);
    TextureTexels image = {256, 256, 1, NULL, NULL, texels};
    TextureNode node = image_node(0, 0, 0, TEXTURE_WRAP_REPEAT);
    node.filter = TEXTURE_FILTER_POINT;
    assert_int_equal(render_scene_add_texture_texels(&scene, &image, 0, &node, error, sizeof error), 0);
    free(texels);
    assert_int_equal(node.levels, 9);
    /* The camera's cone: a pixel spans 2 tan(fov / 2) / height. */
    const float position[3] = {0, 0, 0}, forward[3] = {0, 0, -1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 0.5f, 0.5f, 128, 128);
    render_scene_set_camera(&scene, &camera);
    SampleStream stream = {1u, 0u, SAMPLER_INDEPENDENT};
    CameraRay ray = camera_ray(&scene.constants.camera, &scene.constants.filter, NULL, 64, 64, &stream);
    assert_float_equal(ray.cone_spread, 1.0f / 128.0f, 1e-9f);
    assert_float_equal(ray.cone_width, 0.0f, 0.0f);
    /* A 4 x 4 plane with uv 0..1 (0.25 uv a unit) facing the camera at
     * distance 8: the footprint is 8 / 128 wide, twice that is 1/32 of the
     * texture, 8 texels: level 3. At distance 1, 1 texel: level 0. */
    TextureContext c;
    memset(&c, 0, sizeof c);
    c.u = c.v = 0.3f;
    c.uv_density = 0.25f;
    c.footprint = 8.0f * ray.cone_spread;
    float s, t, width;
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(texture_mip_level(&node, width), 3.0f, 1e-6f);
    TextureArrays a = arrays_of(&node, NULL, scene.texture_floats);
    assert_float_equal(texture_image_lookup(&a, &node, s, t, width).x, 0.5f, 1e-6f);
    c.footprint = 1.0f * ray.cone_spread;
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(texture_mip_level(&node, width), 0.0f, 1e-6f);
    float fine = texture_image_lookup(&a, &node, s, t, width).x;
    assert_true(fine == 0.0f || fine == 1.0f);
    c.footprint = 1e6f; /* beyond the coarsest level: its 1x1 texel */
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(texture_mip_level(&node, width), 8.0f, 0.0f);
    /* Trilinear between levels 0 and 1 at 1.5 texels: level 0.5 (log2 is
     * linear between powers of two), half texel (0, 0) (0) and half 0.5. */
    node.filter = TEXTURE_FILTER_TRILINEAR;
    assert_float_equal(texture_log2(1.5f), 0.5f, 0.0f);
    assert_float_equal(texture_log2(12.0f), 3.5f, 0.0f);
    Vec3 v = texture_image_lookup(&a, &node, 0.5f / 256.0f, 0.5f / 256.0f, 1.5f / 256.0f);
    assert_float_equal(v.x, 0.5f * 0.0f + 0.5f * 0.5f, 1e-6f);
    render_scene_destroy(&scene);
}

static TextureNode procedural(uint32_t type)
{
    TextureNode node = image_node(0, 0, 0, 0);
    node.type = type;
    return node;
}

static void set_value(TextureNode *node, int i, float x, float y, float z)
{
    node->value[i][0] = x;
    node->value[i][1] = y;
    node->value[i][2] = z;
}

static void test_procedural_textures(void **state)
{
    (void)state;
    TextureContext c;
    memset(&c, 0, sizeof c);
    TextureNode checker = procedural(TEXTURE_CHECKERBOARD);
    checker.program_length = 1;
    checker.map_scale[0] = checker.map_scale[1] = 4.0f;
    set_value(&checker, 0, 1, 0, 0);
    set_value(&checker, 1, 0, 0, 1);
    TextureArrays a = arrays_of(&checker, NULL, NULL);
    c.u = 0.1f, c.v = 0.1f; /* (0.4, 0.4): square (0, 0), tex1 */
    assert_float_equal(texture_evaluate(&a, 0, &c).x, 1.0f, 0.0f);
    c.u = 0.3f; /* (1.2, 0.4): tex2 */
    assert_float_equal(texture_evaluate(&a, 0, &c).z, 1.0f, 0.0f);
    c.u = -0.1f; /* (-0.4, 0.4): square (-1, 0), tex2 */
    assert_float_equal(texture_evaluate(&a, 0, &c).z, 1.0f, 0.0f);
    c.u = 0.3f, c.v = 0.3f; /* (1.2, 1.2): tex1 */
    assert_float_equal(texture_evaluate(&a, 0, &c).x, 1.0f, 0.0f);
    c.u = 1e9f + 0.1f; /* far away still a square's parity (1e9 * 4 is even) */
    assert_float_equal(texture_evaluate(&a, 0, &c).x + texture_evaluate(&a, 0, &c).z, 1.0f, 0.0f);

    /* 3D: (0.5, 1.5, 0.5) in texture space (the identity): 0 + 1 + 0, odd. */
    checker.mapping = TEXTURE_MAP_3D;
    for (int i = 0; i < 3; ++i)
        checker.texture_from_world[i][i] = 1.0f;
    c.p = vec3(0.5f, 1.5f, 0.5f);
    assert_float_equal(texture_evaluate(&a, 0, &c).z, 1.0f, 0.0f);
    c.p = vec3(0.5f, 1.5f, 1.5f);
    assert_float_equal(texture_evaluate(&a, 0, &c).x, 1.0f, 0.0f);

    TextureNode bilerp = procedural(TEXTURE_BILERP);
    bilerp.program_length = 1;
    for (int i = 0; i < 4; ++i)
        set_value(&bilerp, i, (float)i, (float)i, (float)i);
    a = arrays_of(&bilerp, NULL, NULL);
    c.u = 0.25f, c.v = 0.75f; /* 0.75 * 0.75 * 1 + 0.25 * 0.25 * 2 + 0.25 * 0.75 * 3 */
    assert_float_equal(texture_evaluate_float(&a, 0, &c), 1.25f, 1e-6f);

    /* A program: mix(constant 2, constant 4, amount 0.25), scaled by 3. */
    TextureNode program[4] = {procedural(TEXTURE_CONSTANT), procedural(TEXTURE_CONSTANT), procedural(TEXTURE_MIX),
                              procedural(TEXTURE_SCALE)};
    program[0].program_length = 4;
    set_value(&program[0], 0, 2, 2, 2);
    set_value(&program[1], 0, 4, 4, 4);
    program[2].operand[0] = 0;
    program[2].operand[1] = 1;
    set_value(&program[2], 2, 0.25f, 0.25f, 0.25f);
    program[3].operand[0] = 2;
    set_value(&program[3], 2, 3, 3, 3);
    a = arrays_of(program, NULL, NULL);
    assert_float_equal(texture_evaluate_float(&a, 0, &c), 3.0f * (0.75f * 2 + 0.25f * 4), 1e-6f);

    /* directionmix: |n . dir| weighs tex1 (pbrt-v4). */
    TextureNode mix = procedural(TEXTURE_DIRECTION_MIX);
    mix.program_length = 1;
    set_value(&mix, 0, 1, 1, 1);
    set_value(&mix, 1, 5, 5, 5);
    mix.direction[1] = 1.0f;
    a = arrays_of(&mix, NULL, NULL);
    c.n = vec3(0.0f, 0.6f, 0.8f);
    assert_float_equal(texture_evaluate_float(&a, 0, &c), 0.6f * 1 + 0.4f * 5, 1e-6f);
}

/* ---- Perlin noise and the procedural textures, against
 * tests/support/procedural_reference.c ---- */

/* A reproducible uniform float in [lo, hi). */
static float uniform_in(uint64_t *state, float lo, float hi)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * (float)(*state >> 40) * (1.0f / 16777216.0f);
}

static void test_noise_properties(void **state)
{
    (void)state;
    /* Perlin's published table: a permutation of 0..255 that begins 151,
     * 160, 137, 91, 90, 15 and ends 156, 180. */
    int seen[256] = {0};
    for (int i = 0; i < 256; ++i)
        ++seen[noise_permutation[i]];
    for (int i = 0; i < 256; ++i)
        assert_int_equal(seen[i], 1);
    const uint8_t head[6] = {151, 160, 137, 91, 90, 15};
    assert_memory_equal(noise_permutation, head, 6);
    assert_int_equal(noise_permutation[254], 156);
    assert_int_equal(noise_permutation[255], 180);

    uint64_t rng = 1;
    for (int i = 0; i < 1000; ++i) { /* 0 at every lattice point, negative ones too */
        float x = floorf(uniform_in(&rng, -1000, 1000)), y = floorf(uniform_in(&rng, -1000, 1000)),
              z = floorf(uniform_in(&rng, -1000, 1000));
        assert_true(noise3(x, y, z) == 0.0f);
    }
    double largest_error = 0, largest = 0, sum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        float x = uniform_in(&rng, -50, 50), y = uniform_in(&rng, -50, 50), z = uniform_in(&rng, -50, 50);
        float v = noise3(x, y, z);
        long double r = ref_noise(noise_permutation, x, y, z);
        largest_error = fmax(largest_error, fabs((double)(v - r)));
        largest = fmax(largest, fabs(v));
        sum += v;
    }
    /* Beyond int range the cell is still found exactly (here x = 3e9 + ...: dx 0). */
    for (int i = 0; i < 100; ++i) {
        float x = 3e9f + 256.0f * (float)i, y = uniform_in(&rng, -5, 5), z = uniform_in(&rng, -5, 5);
        largest_error = fmax(largest_error, fabs((double)(noise3(x, y, z) - ref_noise(noise_permutation, x, y, z))));
    }
    printf("  noise at %d points: largest |error| %.3g against long double, largest |noise| %.4f, mean %.4f\n", n,
           largest_error, largest, sum / n);
    assert_true(largest_error < 5e-6); /* float rounding: the fade polynomial's terms reach 15 */
    assert_true(largest <= 1.05);      /* about [-1, 1] */
    assert_true(fabs(sum / n) < 0.01);
}

/* A noise texture node with texture space 2 p + (0.25, -0.5, 1). */
static TextureNode noise_node(uint32_t type, float omega, float octaves)
{
    TextureNode node = procedural(type);
    node.program_length = 1;
    node.mapping = TEXTURE_MAP_3D;
    for (int i = 0; i < 3; ++i)
        node.texture_from_world[i][i] = 2.0f;
    node.texture_from_world[0][3] = 0.25f;
    node.texture_from_world[1][3] = -0.5f;
    node.texture_from_world[2][3] = 1.0f;
    node.value[3][0] = omega;
    node.value[3][1] = 0.2f;
    node.value[3][2] = octaves;
    node.scale = 1.5f;
    return node;
}

static void texture_space(const TextureContext *c, long double q[3])
{
    q[0] = 2.0L * c->p.x + 0.25L;
    q[1] = 2.0L * c->p.y - 0.5L;
    q[2] = 2.0L * c->p.z + 1.0L;
}

static void test_procedural_noise_textures(void **state)
{
    (void)state;
    TextureNode fbm = noise_node(TEXTURE_FBM, 0.5f, 8), wrinkled = noise_node(TEXTURE_WRINKLED, 0.6f, 6),
                windy = noise_node(TEXTURE_WINDY, 0, 0), marble = noise_node(TEXTURE_MARBLE, 0.5f, 8);
    /* Footprints from none (all octaves) through fractional octave counts to
     * wider than every octave (none). */
    const float footprints[] = {0.0f, 1e-3f, 0.011f, 0.037f, 0.1f, 0.3f, 2.0f};
    uint64_t rng = 7;
    double errors[4] = {0, 0, 0, 0};
    TextureContext c;
    memset(&c, 0, sizeof c);
    for (int i = 0; i < 400; ++i) {
        c.p = vec3(uniform_in(&rng, -2, 2), uniform_in(&rng, -2, 2), uniform_in(&rng, -2, 2));
        c.footprint = footprints[i % 7];
        long double q[3], len2 = 4.0L * c.footprint * c.footprint, rgb[3];
        texture_space(&c, q);
        TextureArrays a = arrays_of(&fbm, NULL, NULL);
        errors[0] =
            fmax(errors[0],
                 fabs((double)(texture_evaluate_float(&a, 0, &c) - ref_fbm(noise_permutation, q, len2, 0.5L, 8))));
        a = arrays_of(&wrinkled, NULL, NULL);
        errors[1] = fmax(errors[1], fabs((double)(texture_evaluate_float(&a, 0, &c) -
                                                  ref_turbulence(noise_permutation, q, len2, 0.6f, 6))));
        a = arrays_of(&windy, NULL, NULL);
        errors[2] =
            fmax(errors[2], fabs((double)(texture_evaluate_float(&a, 0, &c) - ref_windy(noise_permutation, q, len2))));
        a = arrays_of(&marble, NULL, NULL);
        Vec3 m = texture_evaluate(&a, 0, &c);
        ref_marble(noise_permutation, q, len2, 0.5L, 8, 1.5L, 0.2f, rgb);
        errors[3] = fmax(errors[3], fmax(fabs((double)(m.x - rgb[0])),
                                         fmax(fabs((double)(m.y - rgb[1])), fabs((double)(m.z - rgb[2])))));
    }
    printf("  largest |error| against long double: fbm %.3g, wrinkled %.3g, windy %.3g, marble %.3g\n", errors[0],
           errors[1], errors[2], errors[3]);
    for (int k = 0; k < 4; ++k)
        assert_true(errors[k] < 1e-5);

    /* Past every octave: fbm 0, turbulence the octaves' average 0.2 sum_i omega^i. */
    c.p = vec3(0.3f, 0.7f, -0.2f);
    c.footprint = 100.0f;
    TextureArrays a = arrays_of(&fbm, NULL, NULL);
    assert_float_equal(texture_evaluate_float(&a, 0, &c), 0.0f, 0.0f);
    a = arrays_of(&wrinkled, NULL, NULL);
    double average = 0.2;
    for (int i = 0; i < 6; ++i)
        average += 0.2 * pow(0.6, i);
    assert_float_equal(texture_evaluate_float(&a, 0, &c), average, 1e-6);
    /* Octave count: 2^-8 wide in texture space is -1 - log2(2^-16) / 2 = 7 octaves. */
    assert_float_equal(noise_octaves(0x1p-16f, 8.0f), 7.0f, 0.0f);
    assert_float_equal(noise_octaves(0.0f, 8.0f), 8.0f, 0.0f);
    assert_float_equal(noise_octaves(1.0f, 8.0f), 0.0f, 0.0f);
    /* The marble spline passes through 1.5 times its end knots: t = 0 and 1. */
    Vec3 low = noise_marble_colour(0.0f), high = noise_marble_colour(1.0f);
    assert_float_equal(low.z, 1.5f * 0.6f, 1e-6f);
    assert_float_equal(high.x, 1.5f * 0.58f, 1e-6f);
}

static void test_dots(void **state)
{
    (void)state;
    TextureNode dots = procedural(TEXTURE_DOTS);
    dots.program_length = 1;
    dots.map_scale[0] = dots.map_scale[1] = 3.0f;
    set_value(&dots, 0, 0.9f, 0.1f, 0.1f); /* inside */
    set_value(&dots, 1, 0.0f, 0.0f, 0.5f); /* outside */
    TextureArrays a = arrays_of(&dots, NULL, NULL);
    TextureContext c;
    memset(&c, 0, sizeof c);
    uint64_t rng = 11;
    int inside = 0, outside = 0, undecided = 0;
    for (int i = 0; i < 4000; ++i) {
        c.u = uniform_in(&rng, -3, 3);
        c.v = uniform_in(&rng, -3, 3);
        long double margin;
        int expected = ref_inside_dot(noise_permutation, 3.0L * c.u, 3.0L * c.v, &margin);
        if (expected && margin < 1e-5L) {
            ++undecided;
            continue;
        }
        Vec3 v = texture_evaluate(&a, 0, &c);
        assert_float_equal(v.x, expected ? 0.9f : 0.0f, 0.0f);
        inside += expected;
        outside += !expected;
    }
    printf("  dots: %d points inside, %d outside as the reference says (%d within 1e-5 of an edge skipped)\n", inside,
           outside, undecided);
    assert_true(inside > 400 && outside > 400);
}

static void test_mappings(void **state)
{
    (void)state;
    TextureContext c;
    memset(&c, 0, sizeof c);
    TextureNode node = procedural(TEXTURE_BILERP);
    float s, t, width;
    node.map_scale[0] = 2.0f, node.map_scale[1] = 3.0f;
    node.map_delta[0] = 0.5f, node.map_delta[1] = -1.0f;
    c.u = 0.25f, c.v = 0.5f;
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(s, 1.0f, 0.0f);
    assert_float_equal(t, 0.5f, 0.0f);
    /* planar with v1 = x, v2 = z (folded into the rows by the reader). */
    node.mapping = TEXTURE_MAP_PLANAR;
    node.texture_from_world[0][0] = 1.0f;
    node.texture_from_world[1][2] = 1.0f;
    c.p = vec3(0.3f, 5.0f, 0.7f);
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(s, 0.8f, 1e-6f);
    assert_float_equal(t, -0.3f, 1e-6f);
    /* spherical: pbrt-v4's equal-area square of the direction; +z is its centre. */
    memset(node.texture_from_world, 0, sizeof node.texture_from_world);
    for (int i = 0; i < 3; ++i)
        node.texture_from_world[i][i] = 1.0f;
    node.texture_from_world[2][3] = -1.0f; /* centre at z = 1 */
    node.mapping = TEXTURE_MAP_SPHERICAL;
    c.p = vec3(0.0f, 0.0f, 3.0f);
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(s, 0.5f, 1e-6f);
    assert_float_equal(t, 0.5f, 1e-6f);
    /* cylindrical: ((pi + atan2(y, x)) / 2 pi, z). */
    node.mapping = TEXTURE_MAP_CYLINDRICAL;
    c.p = vec3(0.0f, 2.0f, 1.3f);
    texture_map(&node, &c, &s, &t, &width);
    assert_float_equal(s, 0.75f, 1e-6f);
    assert_float_equal(t, 0.3f, 1e-6f);
}

/* ---- the scene reader and converter ---- */

static int setup(void **state)
{
    (void)state;
    strcpy(temp_dir, "/tmp/gmon-textures-XXXXXX");
    return mkdtemp(temp_dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char command[128];
    snprintf(command, sizeof command, "rm -rf %s", temp_dir);
    return system(command);
}

static const char *write_file(const char *name, const void *data, size_t size)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", temp_dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
    return path;
}

/* A grey PFM of width x height texels all `value`. */
static void write_pfm(const char *name, int width, int height, float value)
{
    char header[64];
    int n = snprintf(header, sizeof header, "Pf\n%d %d\n-1\n", width, height);
    size_t count = (size_t)(width > 0 ? width : 0) * (height > 0 ? height : 0);
    unsigned char *data = malloc((size_t)n + 4 * count + 1);
    memcpy(data, header, (size_t)n);
    for (size_t i = 0; i < count; ++i)
        memcpy(data + n + 4 * i, &value, 4); /* little endian hosts */
    write_file(name, data, (size_t)n + 4 * count);
    free(data);
}

/* A scene: camera looking down -z at a 2x2 quad at z = 0 with uv 0..1,
 * a point light above; `material` (and `textures` before it) shade the quad. */
static const char *quad_scene(const char *name, const char *textures, const char *material)
{
    static char text[4096];
    snprintf(text, sizeof text,
             "LookAt 0 0 4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
             "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n"
             "WorldBegin\nLightSource \"point\" \"rgb I\" [ 4 4 4 ] \"point3 from\" [ 0.3 0.2 2 ]\n%s%s\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
             "  \"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n",
             textures, material);
    return write_file(name, text, strlen(text));
}

static int convert(const char *path, RenderScene *scene)
{
    SceneSummary summary;
    error[0] = '\0';
    if (scene_convert_load(path, 0, 16, 16, 1, scene, &summary, error, sizeof error))
        return -1;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    return 0;
}

static void convert_fails(const char *textures, const char *material, const char *needle)
{
    RenderScene scene;
    const char *path = quad_scene("bad.pbrt", textures, material);
    if (convert(path, &scene) == 0) {
        render_scene_destroy(&scene);
        fail_msg("converted, expected an error with \"%s\"", needle);
    }
    if (!strstr(error, needle) || !strstr(error, "bad.pbrt:"))
        fail_msg("error \"%s\" lacks \"%s\" or the file", error, needle);
}

static void test_scene_textures(void **state)
{
    (void)state;
    write_pfm("grey.pfm", 4, 2, 0.25f);
    RenderScene scene;
    const char *path =
        quad_scene("ok.pbrt",
                   "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"grey.pfm\" \"float uscale\" 2\n"
                   "Texture \"rough\" \"float\" \"imagemap\" \"string filename\" \"grey.pfm\"\n"
                   "Texture \"checks\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"img\" \"rgb tex2\" [ 0 1 0 ]\n",
                   "Material \"conductor\" \"texture reflectance\" \"checks\" \"texture roughness\" \"rough\"\n");
    assert_int_equal(convert(path, &scene), 0);
    /* checks is a program of 2 nodes (img, then the checkerboard); rough one. */
    assert_int_equal(scene.texture_count, 3);
    assert_int_equal(scene.textures[0].program_length, 2);
    assert_int_equal(scene.textures[0].type, TEXTURE_IMAGE);
    assert_float_equal(scene.textures[0].map_scale[0], 2.0f, 0.0f);
    assert_int_equal(scene.textures[1].type, TEXTURE_CHECKERBOARD);
    assert_int_equal(scene.textures[1].operand[0], 0);
    assert_int_equal(scene.textures[1].operand[1], -1);
    assert_float_equal(scene.textures[1].value[1][1], 1.0f, 0.0f);
    assert_int_equal(scene.textures[2].program_length, 1);
    /* The same file and decoding: its texels once (4x2, 2x1, 1x1 levels). */
    assert_int_equal(scene.textures[2].texel_offset, scene.textures[0].texel_offset);
    assert_int_equal(scene.texture_float_count, 8 + 2 + 1);
    assert_int_equal(scene.material_texture_count, 1);
    assert_int_equal(scene.material_textures[0].reflectance, 0);
    assert_int_equal(scene.material_textures[0].roughness[0], 2);
    assert_int_equal(scene.material_textures[0].roughness[1], 2);
    assert_int_equal(scene.material_textures[0].displacement, -1);
    uint64_t features = render_scene_features(&scene);
    assert_true(features & FEATURE_IMAGE_TEXTURES);
    assert_true(features & FEATURE_PROCEDURAL_TEXTURES);
    assert_true(features & FEATURE_ROUGH); /* from the texture: the constant roughness is 0 */
    assert_false(features & (FEATURE_BUMP_MAP | FEATURE_NORMAL_MAP));
    RenderSceneArrays arrays = render_scene_arrays(&scene);
    assert_int_equal(arrays.surface_uvs_count, SURFACE_UV_FLOATS * 2);
    /* The quad's uv density: 1 uv unit over 2 world units. */
    assert_float_equal(arrays.surface_uvs[6], 0.5f, 1e-6f);
    render_scene_destroy(&scene);

    /* The procedural ones: their parameters and defaults (pbrt-v4's), a 3D
     * mapping by the inverse of the CTM at the directive. */
    path = quad_scene("noise.pbrt",
                      "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" 5 \"float roughness\" 0.7\n"
                      "Texture \"w\" \"float\" \"wrinkled\"\n"
                      "Texture \"wind\" \"float\" \"windy\"\n"
                      "Texture \"d\" \"spectrum\" \"dots\" \"rgb inside\" [ 1 0 0 ] \"float uscale\" 4\n"
                      "Scale 2 2 2\n"
                      "Texture \"m\" \"spectrum\" \"marble\" \"float scale\" 3 \"float variation\" 0.5\n"
                      "Texture \"sum\" \"spectrum\" \"mix\" \"texture tex1\" \"d\" \"texture tex2\" \"m\" "
                      "\"texture amount\" \"f\"\n"
                      "Texture \"bumps\" \"float\" \"mix\" \"texture tex1\" \"w\" \"texture tex2\" \"wind\"\n",
                      "Material \"diffuse\" \"texture reflectance\" \"sum\" \"texture displacement\" \"bumps\"\n");
    assert_int_equal(convert(path, &scene), 0);
    /* sum: d, m, f, mix; bumps: w, wind, mix. */
    assert_int_equal(scene.texture_count, 7);
    const TextureNode *d = &scene.textures[0], *m = &scene.textures[1], *f = &scene.textures[2];
    assert_int_equal(d->type, TEXTURE_DOTS);
    assert_float_equal(d->value[0][0], 1.0f, 0.0f); /* inside */
    assert_float_equal(d->value[1][0], 0.0f, 0.0f); /* outside: 0 */
    assert_float_equal(d->map_scale[0], 4.0f, 0.0f);
    assert_int_equal(m->type, TEXTURE_MARBLE);
    assert_int_equal(m->mapping, TEXTURE_MAP_3D);
    assert_float_equal(m->scale, 3.0f, 0.0f);
    assert_float_equal(m->value[3][0], 0.5f, 0.0f); /* roughness */
    assert_float_equal(m->value[3][1], 0.5f, 0.0f); /* variation */
    assert_float_equal(m->value[3][2], 8.0f, 0.0f); /* octaves */
    assert_float_equal(m->texture_from_world[1][1], 0.5f, 0.0f);
    assert_int_equal(f->type, TEXTURE_FBM);
    assert_float_equal(f->value[3][0], 0.7f, 0.0f);
    assert_float_equal(f->value[3][2], 5.0f, 0.0f);
    assert_float_equal(f->texture_from_world[0][0], 1.0f, 0.0f);
    assert_int_equal(scene.textures[4].type, TEXTURE_WRINKLED);
    assert_float_equal(scene.textures[4].value[3][2], 8.0f, 0.0f);
    assert_int_equal(scene.textures[5].type, TEXTURE_WINDY);
    features = render_scene_features(&scene);
    assert_true(features & FEATURE_PROCEDURAL_TEXTURES);
    assert_false(features & FEATURE_IMAGE_TEXTURES);
    render_scene_destroy(&scene);

    /* Without textures nothing of them is made. */
    path = quad_scene("plain.pbrt", "", "Material \"diffuse\"\n");
    assert_int_equal(convert(path, &scene), 0);
    arrays = render_scene_arrays(&scene);
    assert_int_equal(arrays.textures_count + arrays.material_textures_count + arrays.texture_bytes_count +
                         arrays.texture_floats_count + arrays.surface_uvs_count,
                     0);
    assert_false(render_scene_features(&scene) &
                 (FEATURE_IMAGE_TEXTURES | FEATURE_PROCEDURAL_TEXTURES | FEATURE_BUMP_MAP | FEATURE_NORMAL_MAP));
    render_scene_destroy(&scene);
}

static void test_bad_textures(void **state)
{
    (void)state;
    convert_fails("", "Material \"diffuse\" \"texture reflectance\" \"nope\"\n", "no spectrum texture named \"nope\"");
    convert_fails("Texture \"f\" \"float\" \"constant\" \"float value\" 0.5\n",
                  "Material \"diffuse\" \"texture reflectance\" \"f\"\n",
                  "\"f\" is a float texture, \"reflectance\" takes a spectrum texture");
    convert_fails("Texture \"s\" \"spectrum\" \"constant\"\n", "Material \"diffuse\" \"texture displacement\" \"s\"\n",
                  "\"s\" is a spectrum texture, \"displacement\" takes a float texture");
    convert_fails("Texture \"t\" \"rgb\" \"constant\"\n", "", "must be \"float\" or \"spectrum\"");
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\"\n", "", "missing \"string filename\"");
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"g.pfm\" \"string wrap\" \"mirror\"\n",
                  "", "unknown \"wrap\" \"mirror\"");
    convert_fails(
        "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"g.pfm\" \"string encoding\" \"gamma\"\n", "",
        "unknown \"encoding\" \"gamma\"");
    convert_fails("Texture \"t\" \"spectrum\" \"checkerboard\" \"string mapping\" \"torus\"\n", "",
                  "unknown \"mapping\" \"torus\"");
    convert_fails("Texture \"t\" \"spectrum\" \"fbm\"\n", "", "\"fbm\" is a float texture in pbrt-v4");
    convert_fails("Texture \"t\" \"float\" \"marble\"\n", "", "\"marble\" is a spectrum texture in pbrt-v4");
    convert_fails("Texture \"t\" \"float\" \"wrinkled\" \"integer octaves\" -1\n", "", "expected 0 to 64");
    convert_fails("Texture \"t\" \"float\" \"fbm\" \"float roughness\" [ 1 2 ]\n", "", "roughness");
    convert_fails("Texture \"t\" \"float\" \"ptex\"\n", "", "texture class \"ptex\" is not supported");
    const char *use = "Material \"diffuse\" \"texture reflectance\" \"t\"\n";
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"gone.png\"\n", use, "gone.png");
    write_file("corrupt.png", "\x89PNG\r\n\x1a\nnot really", 18);
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"corrupt.png\"\n", use, "corrupt.png");
    write_file("odd.webp", "RIFF0000WEBPVP8 ", 16);
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"odd.webp\"\n", use, "odd.webp");
    write_pfm("nan.pfm", 2, 1, NAN);
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"nan.pfm\"\n", use, "not finite");
    write_pfm("empty.pfm", 0, 0, 0.0f);
    convert_fails("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"empty.pfm\"\n", use,
                  "gives an empty image (0x0)");
    /* More texels than 2^31: refused before any texel is read. */
    RenderScene scene;
    render_scene_init(&scene);
    TextureTexels huge = {65536, 65536, 1, NULL, NULL, NULL};
    TextureNode node = image_node(0, 0, 0, 0);
    assert_int_equal(render_scene_add_texture_texels(&scene, &huge, 0, &node, error, sizeof error), -1);
    assert_non_null(strstr(error, "2^31"));
    render_scene_destroy(&scene);
}

/* Whether a ray down -z from (x, y, 2) meets something (any_hit, as a
 * shadow ray) and the nearest hit's t (as a camera or BSDF ray). */
static int blocked_at(const RenderScene *scene, float x, float y, float *nearest)
{
    Geometry g = {.nodes = scene->bvh.nodes,
                  .primitives = scene->bvh.primitives,
                  .instances = scene->instances,
                  .alphas = scene->alphas,
                  .textures = scene->textures,
                  .texture_bytes = scene->texture_bytes,
                  .texture_floats = scene->texture_floats,
                  .surface_uvs = scene->surface_uvs};
    Ray ray = {{x, y, 2.0f}, {0.0f, 0.0f, -1.0f}};
    Hit hit;
    int any = bvh_intersect(&g, &ray, 1e-4f, 10.0f, 1, &hit);
    *nearest = bvh_intersect(&g, &ray, 1e-4f, 10.0f, 0, &hit) ? hit.t : INFINITY;
    return any;
}

/* pbrt-v4 binds the textures of materials and shapes once the whole
 * scene is read: a Texture may follow the material that names it. */
static void test_textures_bound_late(void **state)
{
    (void)state;
    const char *checks = "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0 0 ] \"float uscale\" 4\n";
    const char *use = "MakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"texture reflectance\" \"c\"\n"
                      "NamedMaterial \"m\"\n";
    RenderScene scene;
    assert_int_equal(convert(quad_scene("late.pbrt", use, checks), &scene), 0);
    assert_int_equal(scene.material_texture_count, 1);
    int reflectance = scene.material_textures[0].reflectance;
    assert_true(reflectance >= 0);
    assert_int_equal(scene.textures[reflectance].type, TEXTURE_CHECKERBOARD);
    assert_float_equal(scene.textures[reflectance].value[0][0], 1.0f, 0.0f);
    assert_float_equal(scene.textures[reflectance].map_scale[0], 4.0f, 0.0f);
    render_scene_destroy(&scene);

    /* Two uses of the name before its Texture share it; a texture's own
     * inputs are bound as read, as pbrt-v4 creates textures in order. */
    char text[1024];
    snprintf(text, sizeof text, "%sMaterial \"coateddiffuse\" \"texture reflectance\" \"c\"\n", use);
    assert_int_equal(convert(quad_scene("late-twice.pbrt", text, checks), &scene), 0);
    assert_int_equal(scene.texture_count, 1);
    render_scene_destroy(&scene);
    convert_fails("Texture \"s\" \"spectrum\" \"scale\" \"texture tex\" \"c\"\n", checks,
                  "Texture \"s\": parameter \"texture tex\": no spectrum texture named \"c\"");

    /* Never defined: an error at the use's line (line 6 of quad_scene's text). */
    convert_fails("", "Material \"diffuse\" \"texture reflectance\" \"later\"\n",
                  "bad.pbrt:6: Material \"diffuse\": parameter \"texture reflectance\": no spectrum texture named");
    convert_fails("Material \"diffuse\" \"texture reflectance\" \"f\"\n",
                  "Texture \"f\" \"float\" \"constant\" \"float value\" 0.5\n",
                  "\"f\" is a float texture, \"reflectance\" takes a spectrum texture");

    /* A shape's alpha texture after the shape: the checkerboard's cut-out. */
    snprintf(text, sizeof text,
             "Camera \"perspective\"\nWorldBegin\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
             "  \"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n"
             "  \"texture alpha\" \"a\"\n"
             "Texture \"a\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2\n");
    assert_int_equal(convert(write_file("alpha-late.pbrt", text, strlen(text)), &scene), 0);
    float t;
    assert_true(blocked_at(&scene, -0.5f, -0.5f, &t)); /* (u, v) = (0.25, 0.25): alpha 1 */
    assert_false(blocked_at(&scene, 0.5f, -0.5f, &t)); /* (0.75, 0.25): alpha 0 */
    render_scene_destroy(&scene);
}

/* "texture alpha" in the host's traversal: a 2 x 2 checkerboard of alpha
 * 1 and 0 on the quad [-1, 1]^2 at z = 0 stops rays over its squares of
 * alpha 1 only, and the second quad behind it (z = -1) is met through the
 * others. Inside an instance (moved by +0.5 in z, scaled by 2 in x and y),
 * the texture follows the object's uvs. */
static void test_alpha_texture_rays(void **state)
{
    (void)state;
    const char *checks = "Texture \"checks\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2\n";
    const char *quad = "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
                       "  \"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n"
                       "  \"texture alpha\" \"checks\"\n";
    const char *back = "Shape \"trianglemesh\" \"point3 P\" [ -9 -9 -1  9 -9 -1  9 9 -1  -9 9 -1 ]\n"
                       "  \"integer indices\" [ 0 1 2  0 2 3 ]\n";
    char text[4096];
    snprintf(text, sizeof text,
             "LookAt 0 0 4  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
             "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\n%s%s%s",
             checks, quad, back);
    RenderScene scene;
    assert_int_equal(convert(write_file("alpha.pbrt", text, strlen(text)), &scene), 0);
    assert_true(render_scene_features(&scene) & FEATURE_ALPHA_TEXTURE);
    float t;
    /* (u, v) = (0.25, 0.25) and (0.75, 0.75): alpha 1; the others 0. */
    assert_true(blocked_at(&scene, -0.5f, -0.5f, &t));
    assert_float_equal(t, 2.0f, 1e-6f);
    assert_true(blocked_at(&scene, 0.5f, 0.5f, &t));
    assert_float_equal(t, 2.0f, 1e-6f);
    assert_true(blocked_at(&scene, 0.5f, -0.5f, &t)); /* by the back quad only */
    assert_float_equal(t, 3.0f, 1e-6f);
    assert_true(blocked_at(&scene, -0.5f, 0.5f, &t));
    assert_float_equal(t, 3.0f, 1e-6f);
    render_scene_destroy(&scene);

    /* Without the back quad a ray through alpha 0 meets nothing. */
    snprintf(text, sizeof text, "Camera \"perspective\"\nWorldBegin\n%s%s", checks, quad);
    assert_int_equal(convert(write_file("alpha-alone.pbrt", text, strlen(text)), &scene), 0);
    assert_false(blocked_at(&scene, 0.5f, -0.5f, &t));
    assert_true(blocked_at(&scene, -0.5f, -0.5f, &t));
    render_scene_destroy(&scene);

    snprintf(text, sizeof text,
             "Camera \"perspective\"\nWorldBegin\n%sObjectBegin \"q\"\n%sObjectEnd\n"
             "AttributeBegin\n  Translate 0 0 0.5\n  Scale 2 2 1\n  ObjectInstance \"q\"\nAttributeEnd\n",
             checks, quad);
    assert_int_equal(convert(write_file("alpha-instance.pbrt", text, strlen(text)), &scene), 0);
    assert_true(render_scene_features(&scene) & FEATURE_INSTANCING);
    assert_true(blocked_at(&scene, -1.0f, -1.0f, &t)); /* object (-0.5, -0.5): alpha 1 */
    assert_float_equal(t, 1.5f, 1e-6f);
    assert_false(blocked_at(&scene, 1.0f, -1.0f, &t));
    assert_true(blocked_at(&scene, 1.0f, 1.0f, &t));
    assert_false(blocked_at(&scene, -0.5f, 1.5f, &t));
    render_scene_destroy(&scene);
}

/* ---- on a device ---- */

/* The mean pass of the scene at `path`, 16x16 at 4 spp (malloc'd). */
static float *render_mean(const char *path)
{
    RenderScene scene;
    if (convert(path, &scene))
        fail_msg("%s", error);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 4;
    settings.seed = 3;
    RenderOutput out;
    if (renderer_run(&test_device, 1, &scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s", error);
    size_t n = (size_t)out.width * out.height * 3;
    float *mean = malloc(n * sizeof *mean);
    memcpy(mean, out.pass[PASS_MEAN], n * sizeof *mean);
    render_output_free(&out);
    render_scene_destroy(&scene);
    return mean;
}

static void test_constant_displacement_changes_nothing(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    float *plain = render_mean(quad_scene("flat.pbrt", "", "Material \"diffuse\"\n"));
    float *bumped = render_mean(quad_scene("bumped.pbrt", "Texture \"d\" \"float\" \"constant\" \"float value\" 0.3\n",
                                           "Material \"diffuse\" \"texture displacement\" \"d\"\n"));
    /* The bumped normal is cross(dpdu, dpdv), the geometric normal up to rounding. */
    double largest = 0.0;
    for (size_t i = 0; i < 16 * 16 * 3; ++i)
        largest = fmax(largest, fabs((double)plain[i] - bumped[i]) / fmax(1e-3, fabs((double)plain[i])));
    printf("  constant displacement: largest relative difference %.3g\n", largest);
    assert_true(largest < 1e-5);
    free(plain);
    free(bumped);
}

static void test_flat_normal_map_is_no_normal_map(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* An RGB PFM of (0.5, 0.5, 1): the tangent-space normal (0, 0, 1). */
    char header[] = "PF\n2 2\n-1\n";
    unsigned char data[sizeof header - 1 + 4 * 12];
    memcpy(data, header, sizeof header - 1);
    for (int i = 0; i < 12; ++i) {
        float v = i % 3 == 2 ? 1.0f : 0.5f;
        memcpy(data + sizeof header - 1 + 4 * i, &v, 4);
    }
    write_file("flat.pfm", data, sizeof data);
    /* A textured reflectance in both, so that the two builds differ only by the normal map. */
    const char *texture = "Texture \"r\" \"spectrum\" \"checkerboard\" \"float uscale\" 3\n";
    float *plain =
        render_mean(quad_scene("none.pbrt", texture, "Material \"diffuse\" \"texture reflectance\" \"r\"\n"));
    float *mapped = render_mean(
        quad_scene("mapped.pbrt", texture,
                   "Material \"diffuse\" \"texture reflectance\" \"r\" \"string normalmap\" \"flat.pfm\"\n"));
    assert_memory_equal(plain, mapped, 16 * 16 * 3 * sizeof(float));
    free(plain);
    free(mapped);
}

static void test_checkerboard_on_device(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* Red and blue squares of the quad (2 x 2 of them), lit alike: each
     * pixel is all red or all blue. */
    float *image = render_mean(quad_scene("checks.pbrt",
                                          "Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 2 "
                                          "\"float vscale\" 2 \"rgb tex1\" [ 0.8 0 0 ] \"rgb tex2\" [ 0 0 0.8 ]\n",
                                          "Material \"diffuse\" \"texture reflectance\" \"c\"\n"));
    /* Pixels (4, 4) and (11, 4) see opposite upper squares (u < 0.5 and u > 0.5, v > 0.5). */
    const float *a = image + 3 * (4 * 16 + 4), *b = image + 3 * (4 * 16 + 11);
    int a_red = a[0] > 0.0f && a[1] == 0.0f && a[2] == 0.0f, a_blue = a[2] > 0.0f && a[0] == 0.0f && a[1] == 0.0f;
    int b_red = b[0] > 0.0f && b[1] == 0.0f && b[2] == 0.0f, b_blue = b[2] > 0.0f && b[0] == 0.0f && b[1] == 0.0f;
    assert_true((a_red && b_blue) || (a_blue && b_red));
    free(image);
}

/* A marble quad with a wrinkled bump map renders: finite, and the pixels
 * that see the quad differ (the texture varies over it). */
static void test_procedural_material_renders(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    float *image =
        render_mean(quad_scene("marble.pbrt",
                               "Texture \"m\" \"spectrum\" \"marble\" \"float scale\" 4\n"
                               "Texture \"w\" \"float\" \"wrinkled\" \"integer octaves\" 4\n"
                               "Texture \"d\" \"float\" \"scale\" \"texture tex\" \"w\" \"float scale\" 0.02\n",
                               "Material \"diffuse\" \"texture reflectance\" \"m\" \"texture displacement\" \"d\"\n"));
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < 16 * 16 * 3; ++i)
        assert_true(isfinite(image[i]));
    for (int y = 5; y < 11; ++y) /* pixels that see the quad */
        for (int x = 5; x < 11; ++x) {
            lo = fminf(lo, image[3 * (16 * y + x)]);
            hi = fmaxf(hi, image[3 * (16 * y + x)]);
        }
    printf("  marble quad: red from %.4f to %.4f over its central pixels\n", lo, hi);
    assert_true(hi > lo * 1.2f && lo > 0.0f);
    free(image);
}

/* The device evaluates the procedural textures as the host does: bit for
 * bit where only +, -, *, / and floor enter (dots, fbm, wrinkled, windy),
 * within float rounding for marble (sin). One program per texture, at 2000
 * points and footprints, through kernels/tracing/texture_probe.cl. */
static void test_procedural_textures_on_device(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { kinds = 5, points = 2000 };
    TextureNode nodes[kinds] = {noise_node(TEXTURE_FBM, 0.5f, 8), noise_node(TEXTURE_WRINKLED, 0.6f, 6),
                                noise_node(TEXTURE_WINDY, 0, 0), noise_node(TEXTURE_MARBLE, 0.5f, 8),
                                procedural(TEXTURE_DOTS)};
    nodes[4].program_length = 1;
    nodes[4].map_scale[0] = nodes[4].map_scale[1] = 3.0f;
    set_value(&nodes[4], 0, 0.9f, 0.1f, 0.1f);
    set_value(&nodes[4], 1, 0.0f, 0.0f, 0.5f);
    static float contexts[12 * points], device_out[3 * points];
    uint64_t rng = 5;
    const float footprints[] = {0.0f, 1e-3f, 0.011f, 0.037f, 0.1f, 0.3f, 2.0f};
    for (int i = 0; i < points; ++i) {
        float *c = contexts + 12 * i;
        memset(c, 0, 12 * sizeof *c);
        for (int k = 0; k < 3; ++k)
            c[k] = uniform_in(&rng, -4, 4);
        c[6] = uniform_in(&rng, -3, 3);
        c[7] = uniform_in(&rng, -3, 3);
        c[8] = footprints[i % 7];
    }
    cl_program program = cl_program_build(&test_device, "texture_probe", "", NULL);
    assert_non_null(program);
    cl_int err;
    cl_kernel kernel = clCreateKernel(program, "texture_probe", &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_context ctx = test_device.context;
    cl_mem node_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof nodes, nodes, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_mem context_buffer =
        clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof contexts, contexts, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_mem out_buffer = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof device_out, NULL, &err);
    assert_int_equal(err, CL_SUCCESS);
    cl_uint count = points;
    size_t global = points;
    int exact_kinds = 0;
    for (int k = 0; k < kinds; ++k) {
        cl_int first = k;
        assert_int_equal(clSetKernelArg(kernel, 0, sizeof node_buffer, &node_buffer), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 1, sizeof(cl_mem), NULL), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 2, sizeof(cl_mem), NULL), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 3, sizeof first, &first), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 4, sizeof context_buffer, &context_buffer), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 5, sizeof out_buffer, &out_buffer), CL_SUCCESS);
        assert_int_equal(clSetKernelArg(kernel, 6, sizeof count, &count), CL_SUCCESS);
        assert_int_equal(clEnqueueNDRangeKernel(test_device.queue, kernel, 1, NULL, &global, NULL, 0, NULL, NULL),
                         CL_SUCCESS);
        assert_int_equal(clEnqueueReadBuffer(test_device.queue, out_buffer, CL_TRUE, 0, sizeof device_out, device_out,
                                             0, NULL, NULL),
                         CL_SUCCESS);
        TextureArrays a = arrays_of(nodes, NULL, NULL);
        size_t differ = 0;
        double largest = 0.0;
        for (int i = 0; i < points; ++i) {
            const float *c = contexts + 12 * i;
            TextureContext tc = {vec3(c[0], c[1], c[2]), vec3(c[3], c[4], c[5]), c[6], c[7], c[8], c[9]};
            Vec3 host = texture_evaluate(&a, k, &tc);
            const float h[3] = {host.x, host.y, host.z};
            for (int j = 0; j < 3; ++j) {
                differ += memcmp(&h[j], &device_out[3 * i + j], sizeof h[j]) != 0;
                largest = fmax(largest, fabs((double)h[j] - device_out[3 * i + j]));
            }
        }
        printf("  texture type %u on %s: %zu of %d values differ from the host's, by at most %.3g\n", nodes[k].type,
               test_device.info.name, differ, 3 * points, largest);
        if (nodes[k].type == TEXTURE_MARBLE)
            assert_true(largest < 1e-6);
        else
            assert_int_equal(differ, 0);
        exact_kinds += differ == 0;
    }
    assert_true(exact_kinds >= kinds - 1);
    clReleaseMemObject(node_buffer);
    clReleaseMemObject(context_buffer);
    clReleaseMemObject(out_buffer);
    clReleaseKernel(kernel);
    clReleaseProgram(program);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(test_nearest_and_wrap),
        cmocka_unit_test(test_bilinear),
        cmocka_unit_test(test_srgb_bytes_and_pyramid),
        cmocka_unit_test(test_mip_level_at_distance),
        cmocka_unit_test(test_procedural_textures),
        cmocka_unit_test(test_noise_properties),
        cmocka_unit_test(test_procedural_noise_textures),
        cmocka_unit_test(test_dots),
        cmocka_unit_test(test_mappings),
        cmocka_unit_test(test_scene_textures),
        cmocka_unit_test(test_bad_textures),
        cmocka_unit_test(test_alpha_texture_rays),
        cmocka_unit_test(test_textures_bound_late),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(test_constant_displacement_changes_nothing),
        cmocka_unit_test(test_flat_normal_map_is_no_normal_map),
        cmocka_unit_test(test_checkerboard_on_device),
        cmocka_unit_test(test_procedural_textures_on_device),
        cmocka_unit_test(test_procedural_material_renders),
    };
    int failed = cmocka_run_group_tests_name("host", host, setup, teardown);
    if (setup(NULL))
        return 1;
    int status = test_device_setup(NULL);
    if (status == 0)
        failed += cmocka_run_group_tests_name("device", device, NULL, NULL);
    test_device_teardown(NULL);
    teardown(NULL);
    return failed || status;
}
