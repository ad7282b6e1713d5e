/* Instancing and alpha cut-outs end to end: an instanced scene renders bit
 * for bit as the same scene flattened (for transforms float arithmetic does
 * exactly: tests/data/scenes/instances.pbrt says why); a fully transparent
 * quad changes nothing; a quad of alpha 0.5 blocks half the light its
 * opaque twin blocks, within standard errors; "texture alpha" of 0 and 1
 * (a checkerboard, an image) casts the shadow of the geometry it keeps. */
#include "io/exr_image.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "test_device.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static void load(const char *path, unsigned size, RenderScene *scene)
{
    char error[1024];
    SceneSummary summary;
    if (scene_convert_load(path, 0, size, size, 1, scene, &summary, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
}

static void render_file(const char *path, unsigned size, uint64_t samples, RenderOutput *out, uint64_t *features)
{
    RenderScene scene;
    load(path, size, &scene);
    *features = render_scene_features(&scene);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = samples;
    settings.seed = 7;
    char error[1024];
    if (renderer_run(&test_device, 1, &scene, &settings, out, error, sizeof error))
        fail_msg("%s", error);
    render_scene_destroy(&scene);
}

/* How many of the mean pass's values differ in their bits. */
static size_t differing_values(const RenderOutput *a, const RenderOutput *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    size_t n = 3 * (size_t)a->width * a->height, differ = 0;
    const float *x = a->pass[PASS_MEAN], *y = b->pass[PASS_MEAN];
    for (size_t i = 0; i < n; ++i)
        differ += memcmp(&x[i], &y[i], sizeof x[i]) != 0;
    return differ;
}

static void test_instanced_scene_renders_as_flattened(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderOutput instanced, flat;
    uint64_t instanced_features, flat_features;
    render_file(GMON_SOURCE_DIR "/tests/data/scenes/instances.pbrt", 32, 16, &instanced, &instanced_features);
    render_file(GMON_SOURCE_DIR "/tests/data/scenes/instances-flat.pbrt", 32, 16, &flat, &flat_features);
    assert_true(instanced_features & FEATURE_INSTANCING);
    assert_false(flat_features & FEATURE_INSTANCING);
    size_t differ = differing_values(&instanced, &flat);
    printf("  instances.pbrt vs instances-flat.pbrt: %zu of %u values differ\n", differ,
           3 * instanced.width * instanced.height);
    assert_int_equal(differ, 0);
    render_output_free(&instanced);
    render_output_free(&flat);
}

/* The same through gmonrt: the images it writes hold the same layers, bit
 * for bit (the files differ: they name their scenes). */
static void test_cli_renders_instanced_as_flattened(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const char *names[2] = {"instances", "instances-flat"};
    ExrImage images[2];
    for (int i = 0; i < 2; ++i) {
        char command[2048], path[1024], error[1024];
        snprintf(path, sizeof path, "%s/test_render_instancing_%s.exr", GMON_BINARY_DIR, names[i]);
        snprintf(command, sizeof command,
                 "'%s' --spp 8 --seed 3 --resolution 24x24 --quiet --outfile '%s' '%s/tests/data/scenes/%s.pbrt' "
                 ">/dev/null 2>&1",
                 GMONRT, path, GMON_SOURCE_DIR, names[i]);
        assert_int_equal(system(command), 0);
        if (exr_image_read(path, &images[i], error, sizeof error) != IMAGE_IO_OK)
            fail_msg("%s", error);
    }
    assert_int_equal(images[0].layer_count, images[1].layer_count);
    assert_true(images[0].layer_count > 0);
    size_t values = 3 * (size_t)images[0].width * images[0].height;
    for (int l = 0; l < images[0].layer_count; ++l) {
        const ExrRgbLayer *a = &images[0].layers[l], *b = exr_image_layer(&images[1], a->name);
        assert_non_null(b);
        assert_memory_equal(a->data, b->data, values * 4);
    }
    printf("  gmonrt: %d layers of %zu values equal bit for bit\n", images[0].layer_count, values);
    exr_image_free(&images[0]);
    exr_image_free(&images[1]);
}

/* The Cornell box with `occluder` (shapes and textures) between its light
 * and the floor, written beside the build. */
static void write_cornell_scene(const char *path, const char *occluder)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f,
            "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ]\n"
            "Include \"%s/scenes/include/cornell-camera.pbrt\"\n"
            "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
            "WorldBegin\n"
            "Include \"%s/scenes/include/cornell-walls.pbrt\"\n"
            "AttributeBegin\n"
            "  AreaLightSource \"diffuse\" \"rgb L\" [ 17 12 4 ]\n"
            "  Shape \"trianglemesh\" \"point3 P\" [ -0.3 1.9 -0.3  0.3 1.9 -0.3  -0.3 1.9 0.3  0.3 1.9 0.3 ]\n"
            "    \"integer indices\" [ 0 1 2  2 1 3 ]\n"
            "AttributeEnd\n%s",
            GMON_SOURCE_DIR, GMON_SOURCE_DIR, occluder);
    fclose(f);
}

/* The quad x, z in [-0.6, 0.6] at y = 1.2 (u along x, v along z), with
 * `params` after its geometry. */
static const char *occluder_quad(const char *params)
{
    static char text[1024];
    snprintf(text, sizeof text,
             "Shape \"trianglemesh\" \"point3 P\" [ -0.6 1.2 -0.6  0.6 1.2 -0.6  -0.6 1.2 0.6  0.6 1.2 0.6 ]\n"
             "  \"integer indices\" [ 0 1 2  2 1 3 ] \"point2 uv\" [ 0 0  1 0  0 1  1 1 ] %s\n",
             params);
    return text;
}

/* The Cornell box with a quad of the given alpha (or none: alpha < 0)
 * between its light and the floor. */
static void write_occluder_scene(const char *path, float alpha)
{
    char params[64] = "";
    snprintf(params, sizeof params, "\"float alpha\" [ %.9g ]", (double)alpha);
    write_cornell_scene(path, alpha >= 0.0f ? occluder_quad(params) : "");
}

static void render_occluded(float alpha, uint64_t samples, RenderOutput *out, uint64_t *features)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/test_render_instancing_alpha.pbrt", GMON_BINARY_DIR);
    write_occluder_scene(path, alpha);
    render_file(path, 64, samples, out, features);
}

static void test_transparent_quad_changes_nothing(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderOutput without, transparent;
    uint64_t features;
    render_occluded(-1.0f, 16, &without, &features);
    assert_false(features & FEATURE_ALPHA);
    render_occluded(0.0f, 16, &transparent, &features);
    assert_true(features & FEATURE_ALPHA);
    size_t differ = differing_values(&without, &transparent);
    printf("  a quad of alpha 0 in front of the light: %zu values differ\n", differ);
    assert_int_equal(differ, 0);
    render_output_free(&without);
    render_output_free(&transparent);
}

static void test_half_alpha_halves_occlusion(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* One sample a pixel, the same in the three renders (the seed): a
     * pixel's open - opaque is B, the light its sample's rays lose to the
     * quad (depth 1: the shadow ray, and the BSDF ray to the light); with
     * alpha 0.5 it loses B with probability 1/2 (the ray's hash), so
     * open - half has mean B / 2 and variance B^2 / 4, independently
     * from pixel to pixel. Channels summed: they are lost together. */
    RenderOutput open, opaque, half;
    uint64_t features;
    render_occluded(-1.0f, 1, &open, &features);
    render_occluded(1.0f, 1, &opaque, &features);
    render_occluded(0.5f, 1, &half, &features);
    size_t pixels = (size_t)open.width * open.height, blocked_pixels = 0;
    const float *o = open.pass[PASS_MEAN], *q = opaque.pass[PASS_MEAN], *h = half.pass[PASS_MEAN];
    double blocked = 0.0, lost = 0.0, variance = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
        double b = 0.0, l = 0.0;
        for (int c = 0; c < 3; ++c) {
            b += (double)o[3 * p + c] - q[3 * p + c];
            l += (double)o[3 * p + c] - h[3 * p + c];
        }
        blocked += b;
        lost += l;
        variance += b * b / 4.0;
        blocked_pixels += b > 0.0;
    }
    double standard_error = sqrt(variance);
    printf("  light lost to the quad, summed over %zu pixels (%zu shadowed): opaque %.3f, alpha 0.5 %.3f "
           "(expected %.3f, standard error %.3f: %.2f standard errors off)\n",
           pixels, blocked_pixels, blocked, lost, blocked / 2.0, standard_error,
           fabs(lost - blocked / 2.0) / standard_error);
    assert_true(blocked_pixels > pixels / 10); /* the quad does occlude */
    assert_true(fabs(lost - blocked / 2.0) <= 4.0 * standard_error);
    render_output_free(&open);
    render_output_free(&opaque);
    render_output_free(&half);
}

/* What a checkerboard of alpha 1 and 0 (2 x 2 squares) on the quad leaves:
 * its squares of alpha 1, (u, v) < 0.5 and > 0.5, as geometry. */
static const char *cut_squares =
    "Shape \"trianglemesh\" \"point3 P\" [ -0.6 1.2 -0.6  0 1.2 -0.6  -0.6 1.2 0  0 1.2 0 ]\n"
    "  \"integer indices\" [ 0 1 2  2 1 3 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ 0 1.2 0  0.6 1.2 0  0 1.2 0.6  0.6 1.2 0.6 ]\n"
    "  \"integer indices\" [ 0 1 2  2 1 3 ]\n";

static const char *checker_alpha =
    "Texture \"checks\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2\n";

static void render_cornell(const char *name, const char *occluder, uint64_t samples, RenderOutput *out,
                           uint64_t *features)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/test_render_instancing_%s.pbrt", GMON_BINARY_DIR, name);
    write_cornell_scene(path, occluder);
    render_file(path, 64, samples, out, features);
}

/* Alpha 0 and 1 decide without the hash: the quad with a checkerboard alpha
 * casts the shadow of the squares it keeps, for camera, shadow and BSDF
 * rays alike (depth 1: the light is reached by both of the latter). Rays
 * meet the two in different triangles, so values may differ by rounding,
 * which the light's spherical triangle sampling (lights.h) amplifies: for
 * u1 near 0 its point moves by up to 1e-3 of the light's size when the
 * shading point moves by an ulp. Compared within 1e-2 relative, all but
 * rays grazing the squares' edges (a square cast wrongly differs by all
 * the light it blocks). */
static void test_checkerboard_alpha_is_the_cut_geometry(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderOutput textured, cut, open;
    uint64_t features;
    char occluder[2048];
    snprintf(occluder, sizeof occluder, "%s%s", checker_alpha, occluder_quad("\"texture alpha\" \"checks\""));
    render_cornell("checker_alpha", occluder, 8, &textured, &features);
    assert_true(features & FEATURE_ALPHA_TEXTURE);
    assert_true(features & FEATURE_ALPHA);
    render_cornell("cut_squares", cut_squares, 8, &cut, &features);
    assert_false(features & (FEATURE_ALPHA | FEATURE_ALPHA_TEXTURE));
    render_cornell("open", "", 8, &open, &features);
    size_t n = 3 * (size_t)cut.width * cut.height, differ = 0, shadowed = 0;
    const float *x = textured.pass[PASS_MEAN], *y = cut.pass[PASS_MEAN], *o = open.pass[PASS_MEAN];
    for (size_t i = 0; i < n; ++i) {
        differ += fabs((double)x[i] - y[i]) > 1e-2 * fmax(fabs((double)y[i]), 1e-3);
        shadowed += y[i] < o[i];
    }
    printf("  checkerboard alpha vs the cut squares: %zu of %zu values differ (%zu shadowed by the squares)\n", differ,
           n, shadowed);
    assert_true(shadowed > n / 10);
    assert_true(differ <= n / 1000);
    render_output_free(&textured);
    render_output_free(&cut);
    render_output_free(&open);
}

/* The same alpha from an image (2 x 2 texels, point lookups): the same
 * hits, so the same image bit for bit as the checkerboard's. */
static void test_image_alpha_is_the_checkerboard(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    char pfm[256];
    snprintf(pfm, sizeof pfm, "%s/test_render_instancing_alpha.pfm", GMON_BINARY_DIR);
    FILE *f = fopen(pfm, "wb");
    assert_non_null(f);
    /* Rows from the bottom: (u < 0.5, v < 0.5) is the bottom left texel. */
    const float texels[4] = {1, 0, 0, 1};
    fprintf(f, "Pf\n2 2\n-1\n");
    assert_int_equal(fwrite(texels, sizeof texels[0], 4, f), 4);
    fclose(f);
    char occluder[2048];
    snprintf(occluder, sizeof occluder,
             "Texture \"mask\" \"float\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"point\"\n%s", pfm,
             occluder_quad("\"texture alpha\" \"mask\""));
    RenderOutput image, checker;
    uint64_t features;
    render_cornell("image_alpha", occluder, 8, &image, &features);
    assert_true(features & FEATURE_IMAGE_TEXTURES);
    snprintf(occluder, sizeof occluder, "%s%s", checker_alpha, occluder_quad("\"texture alpha\" \"checks\""));
    render_cornell("checker_alpha", occluder, 8, &checker, &features);
    size_t differ = differing_values(&image, &checker);
    printf("  image alpha vs checkerboard alpha: %zu values differ\n", differ);
    assert_int_equal(differ, 0);
    render_output_free(&image);
    render_output_free(&checker);
}

/* Textured shapes in an instance (scaled by 4, moved) render as the same
 * shapes flattened: the sphere's (u, v) about its centre in object space,
 * the quad's MIP level from its size in the world (the instance's scale
 * divides its uv density), its tangents in world space. A trilinear image
 * of single-texel checks (whose coarser levels are grey) on the quad, a
 * uv checkerboard on the sphere. */
static void test_instanced_textures_render_as_flattened(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    char pfm[512];
    snprintf(pfm, sizeof pfm, "%s/test_render_instancing_checks.pfm", GMON_BINARY_DIR);
    FILE *f = fopen(pfm, "wb");
    assert_non_null(f);
    fprintf(f, "Pf\n16 16\n-1\n"); /* a texel about a pixel wide on the quad */
    for (int i = 0; i < 16 * 16; ++i) {
        float v = (float)((i / 16 + i % 16) & 1);
        assert_int_equal(fwrite(&v, sizeof v, 1, f), 1);
    }
    fclose(f);
    char textures[1024];
    snprintf(textures, sizeof textures,
             "Texture \"image\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"trilinear\"\n"
             "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 4 "
             "\"rgb tex1\" [ 0.8 0.1 0.1 ] \"rgb tex2\" [ 0.1 0.1 0.8 ]\n",
             pfm);
    /* Object space: the quad x, y in [-0.125, 0.125] at z = 0, a ball of
     * radius 1/32 at (1/16, 1/16, 1/16); the world: 4 times, moved to the
     * back wall (z = -1 + 1/64), facing the camera. */
    const char *object =
        "Material \"diffuse\" \"texture reflectance\" \"image\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -0.125 -0.125 0  0.125 -0.125 0  -0.125 0.125 0  "
        "0.125 0.125 0 ]\n  \"integer indices\" [ 0 1 2  2 1 3 ] \"point2 uv\" [ 0 0  1 0  0 1  1 1 ]\n"
        "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
        "Translate 0.0625 0.0625 0.0625\nShape \"sphere\" \"float radius\" 0.03125\n";
    const char *flat =
        "Material \"diffuse\" \"texture reflectance\" \"image\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -0.5 0.5 -0.984375  0.5 0.5 -0.984375  -0.5 1.5 -0.984375  "
        "0.5 1.5 -0.984375 ]\n  \"integer indices\" [ 0 1 2  2 1 3 ] \"point2 uv\" [ 0 0  1 0  0 1  1 1 ]\n"
        "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
        "Translate 0.25 1.25 -0.734375\nShape \"sphere\" \"float radius\" 0.125\n";
    char instanced_text[4096], flat_text[4096];
    snprintf(instanced_text, sizeof instanced_text,
             "%sObjectBegin \"textured\"\n%sObjectEnd\nAttributeBegin\n  Translate 0 1 -0.984375\n  Scale 4 4 4\n"
             "  ObjectInstance \"textured\"\nAttributeEnd\n",
             textures, object);
    snprintf(flat_text, sizeof flat_text, "%sAttributeBegin\n%sAttributeEnd\n", textures, flat);
    RenderOutput instanced, flattened;
    uint64_t features;
    render_cornell("textured_instance", instanced_text, 8, &instanced, &features);
    assert_true(features & FEATURE_INSTANCING);
    assert_true(features & FEATURE_IMAGE_TEXTURES);
    render_cornell("textured_flat", flat_text, 8, &flattened, &features);
    assert_false(features & FEATURE_INSTANCING);
    size_t n = 3 * (size_t)instanced.width * instanced.height, differ = 0;
    const float *x = instanced.pass[PASS_MEAN], *y = flattened.pass[PASS_MEAN];
    double largest = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d = fabs((double)x[i] - y[i]) / fmax(fabs((double)y[i]), 1e-3);
        differ += d > 1e-5;
        largest = fmax(largest, d);
    }
    printf("  textured instance vs flattened: %zu of %zu values differ by more than 1e-5 relative (largest %.3g)\n",
           differ, n, largest);
    assert_true(differ <= n / 1000);
    render_output_free(&instanced);
    render_output_free(&flattened);
}

/* The Cornell box with `count` copies of `copy` appended after `before`. */
static void write_copies(const char *path, const char *before, const char *copy, int count)
{
    write_cornell_scene(path, before);
    FILE *f = fopen(path, "a");
    assert_non_null(f);
    for (int i = 0; i < count; ++i)
        fputs(copy, f);
    fclose(f);
}

#define QUAD                                                                                                           \
    "Shape \"trianglemesh\" \"point3 P\" [ -0.4 0.3 -0.4  0.4 0.3 -0.4  -0.4 0.9 0.2  0.4 0.9 0.2 ]"                   \
    " \"integer indices\" [ 0 1 2  2 1 3 ]\n"

/* 20,000 instances of one quad, all in one place: their boxes share a
 * centroid, so the top level cannot split them by position (in one leaf,
 * they overflowed the traversal stack and crashed the kernel). They render
 * bit for bit as the 20,000 quads flattened. */
static void test_identical_instances_render_as_flattened(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { COUNT = 20000 };
    char instanced_path[1024], flat_path[1024];
    snprintf(instanced_path, sizeof instanced_path, "%s/test_render_instancing_identical.pbrt", GMON_BINARY_DIR);
    snprintf(flat_path, sizeof flat_path, "%s/test_render_instancing_identical_flat.pbrt", GMON_BINARY_DIR);
    write_copies(instanced_path, "ObjectBegin \"quad\"\nNamedMaterial \"red\"\n" QUAD "ObjectEnd\n",
                 "ObjectInstance \"quad\"\n", COUNT);
    write_copies(flat_path, "NamedMaterial \"red\"\n", QUAD, COUNT);
    RenderOutput instanced, flat;
    uint64_t instanced_features, flat_features;
    render_file(instanced_path, 8, 2, &instanced, &instanced_features);
    render_file(flat_path, 8, 2, &flat, &flat_features);
    assert_true(instanced_features & FEATURE_INSTANCING);
    size_t differ = differing_values(&instanced, &flat);
    printf("  %d identical instances vs flattened: %zu of %u values differ\n", COUNT, differ,
           3 * instanced.width * instanced.height);
    assert_int_equal(differ, 0);
    render_output_free(&instanced);
    render_output_free(&flat);
}

/* Thousands of copies of a sphere scaled about its centre (nested, one
 * centroid) render, as the same spheres flattened up to rounding. */
static void test_scaled_copies_about_one_point_render(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { COUNT = 3000 };
    char instanced_path[1024], flat_path[1024];
    snprintf(instanced_path, sizeof instanced_path, "%s/test_render_instancing_scaled.pbrt", GMON_BINARY_DIR);
    snprintf(flat_path, sizeof flat_path, "%s/test_render_instancing_scaled_flat.pbrt", GMON_BINARY_DIR);
    FILE *files[2] = {fopen(instanced_path, "w"), fopen(flat_path, "w")};
    assert_non_null(files[0]);
    assert_non_null(files[1]);
    fclose(files[0]);
    fclose(files[1]);
    write_copies(instanced_path, "ObjectBegin \"ball\"\nNamedMaterial \"red\"\nShape \"sphere\"\nObjectEnd\n", "", 0);
    write_copies(flat_path, "NamedMaterial \"red\"\n", "", 0);
    files[0] = fopen(instanced_path, "a");
    files[1] = fopen(flat_path, "a");
    for (int i = 0; i < COUNT; ++i) {
        double scale = 0.05 + 0.35 * i / COUNT;
        for (int k = 0; k < 2; ++k)
            fprintf(files[k], "AttributeBegin\nTranslate 0 0.6 0\nScale %.9g %.9g %.9g\n%s\nAttributeEnd\n", scale,
                    scale, scale, k == 0 ? "ObjectInstance \"ball\"" : "Shape \"sphere\"");
    }
    fclose(files[0]);
    fclose(files[1]);
    RenderOutput instanced, flat;
    uint64_t instanced_features, flat_features;
    render_file(instanced_path, 8, 2, &instanced, &instanced_features);
    render_file(flat_path, 8, 2, &flat, &flat_features);
    assert_true(instanced_features & FEATURE_INSTANCING);
    size_t n = 3 * (size_t)instanced.width * instanced.height, differ = differing_values(&instanced, &flat);
    const float *x = instanced.pass[PASS_MEAN], *y = flat.pass[PASS_MEAN];
    double sum[2] = {0.0, 0.0};
    for (size_t i = 0; i < n; ++i) {
        assert_true(isfinite(x[i]));
        sum[0] += x[i];
        sum[1] += y[i];
    }
    printf("  %d scaled copies vs flattened: %zu of %zu values differ; means %.6g and %.6g\n", COUNT, differ, n,
           sum[0] / n, sum[1] / n);
    assert_true(fabs(sum[0] - sum[1]) <= 0.02 * sum[1]);
    render_output_free(&instanced);
    render_output_free(&flat);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_instanced_scene_renders_as_flattened),
        cmocka_unit_test(test_cli_renders_instanced_as_flattened),
        cmocka_unit_test(test_transparent_quad_changes_nothing),
        cmocka_unit_test(test_half_alpha_halves_occlusion),
        cmocka_unit_test(test_checkerboard_alpha_is_the_cut_geometry),
        cmocka_unit_test(test_image_alpha_is_the_checkerboard),
        cmocka_unit_test(test_instanced_textures_render_as_flattened),
        cmocka_unit_test(test_identical_instances_render_as_flattened),
        cmocka_unit_test(test_scaled_copies_about_one_point_render),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
