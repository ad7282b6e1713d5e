/* The pbrt-v4 scene reader: every directive and parameter type, transform
 * math against hand-computed values, ASCII and binary PLY, Include/Import
 * paths, and bad inputs, each of which must fail with a "file:line:"
 * message (never a crash: this test runs under ASan and UBSan). */
#define _POSIX_C_SOURCE 200809L

#include "scene/scene.h"
#include "scene/read_file.h" /* scene_read_file, for its size limit on gzip data */
#include "scene/spectrum.h"
#include "nanovdb.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <zlib.h>

#include "scene_fixture.h"

#ifndef GMON_SOURCE_DIR
#define GMON_SOURCE_DIR "."
#endif

#define WORLD "WorldBegin\n"
#define TRIANGLE "Shape \"trianglemesh\" \"point3 P\" [ 1 0 0  0 1 0  0 0 1 ] \"integer indices\" [ 0 1 2 ]\n"

/* --------------------------------------------------- camera and options */

static void test_defaults(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD, &s);
    assert_int_equal(s.width, 1280);
    assert_int_equal(s.height, 720);
    assert_string_equal(s.film_filename, "pbrt.exr");
    assert_string_equal(s.sampler, "zsobol");
    assert_int_equal(s.spp, 16);
    assert_int_equal(s.max_depth, 5);
    assert_int_equal(s.regularize, 0);
    assert_near(s.rr_threshold, 1, 0);
    assert_near(s.camera.fov, 90, 0);
    assert_vec3(s.camera.position, 0, 0, 0);
    assert_vec3(s.camera.forward, 0, 0, 1);
    assert_vec3(s.camera.right, 1, 0, 0);
    assert_vec3(s.camera.up, 0, 1, 0);
    assert_near(s.camera.tan_half_fov[1], 1.0, 1e-6); /* 90 degrees across the shorter (vertical) axis */
    assert_near(s.camera.tan_half_fov[0], 1280.0 / 720.0, 1e-6);
    assert_int_equal(s.shape_count, 0);
    assert_int_equal(s.light_count, 0);
    scene_destroy(&s);
}

/* pbrt's LookAt is left-handed: right = up x forward. Looking down -z with
 * +y up, the image's right is world -x (the Cornell box's red wall at
 * x = +1 appears on the left). */
static void test_look_at_basis(void **state)
{
    (void)state;
    Scene s;
    load_ok("LookAt 0 1 3.9   0 1 0   0 1 0\nCamera \"perspective\" \"float fov\" [ 36 ]\n" WORLD, &s);
    assert_vec3(s.camera.position, 0, 1, 3.9);
    assert_vec3(s.camera.forward, 0, 0, -1);
    assert_vec3(s.camera.right, -1, 0, 0);
    assert_vec3(s.camera.up, 0, 1, 0);
    assert_near(s.camera.fov, 36, 1e-6);
    /* world_from_camera maps camera-space points: (1, 0, 0) is one unit to the right. */
    float(*m)[4] = s.camera.world_from_camera;
    assert_near(m[0][0] + m[3][0], -1, 1e-6);
    assert_near(m[0][1] + m[3][1], 1, 1e-6);
    assert_near(m[0][2] + m[3][2], 3.9, 1e-6);
    scene_destroy(&s);

    /* A general view: an orthonormal basis with pbrt's left-handed rule
     * up x forward = right. */
    load_ok("LookAt 1 2 3  4 -2 5  0 0 1\nCamera \"perspective\"\n" WORLD, &s);
    const float *f = s.camera.forward, *r = s.camera.right, *u = s.camera.up;
    double len = sqrt(9.0 + 16.0 + 4.0);
    assert_vec3(f, 3 / len, -4 / len, 2 / len);
    assert_vec3(r, u[1] * f[2] - u[2] * f[1], u[2] * f[0] - u[0] * f[2], u[0] * f[1] - u[1] * f[0]);
    assert_near(r[0] * f[0] + r[1] * f[1] + r[2] * f[2], 0, 1e-6);
    assert_true(u[2] > 0); /* the up hint is +z */
    scene_destroy(&s);
}

static void test_fov_spans_shorter_axis(void **state)
{
    (void)state;
    Scene s;
    double t30 = tan(30.0 * 3.14159265358979323846 / 180.0);
    load_ok("Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
            "Camera \"perspective\" \"float fov\" 60\n" WORLD,
            &s);
    assert_near(s.camera.tan_half_fov[0], 2 * t30, 1e-6);
    assert_near(s.camera.tan_half_fov[1], t30, 1e-6);
    scene_destroy(&s);
    load_ok("Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 200\n"
            "Camera \"perspective\" \"float fov\" 60\n" WORLD,
            &s);
    assert_near(s.camera.tan_half_fov[0], t30, 1e-6);
    assert_near(s.camera.tan_half_fov[1], 2 * t30, 1e-6);
    scene_destroy(&s);
    float t[2];
    scene_camera_tan_half_fov(90, 64, 64, t);
    assert_near(t[0], 1, 1e-6);
    assert_near(t[1], 1, 1e-6);
}

static void test_camera_transforms(void **state)
{
    (void)state;
    Scene s;
    /* The CTM at Camera is camera-from-world: Translate 0 0 5 puts the
     * world 5 units ahead, so the camera sits at z = -5. */
    load_ok("Translate 0 0 5\nCamera \"perspective\"\n" WORLD, &s);
    assert_vec3(s.camera.position, 0, 0, -5);
    assert_vec3(s.camera.forward, 0, 0, 1);
    scene_destroy(&s);
    /* Scale -1 1 1 before LookAt mirrors the image, as in pbrt. */
    load_ok("Scale -1 1 1\nLookAt 0 1 3.9   0 1 0   0 1 0\nCamera \"perspective\"\n" WORLD, &s);
    assert_vec3(s.camera.right, 1, 0, 0);
    assert_vec3(s.camera.forward, 0, 0, -1);
    assert_vec3(s.camera.position, 0, 1, 3.9);
    scene_destroy(&s);
    /* A non-uniform scale in the camera transform is a warning. */
    assert_int_equal(load_text("cam.pbrt", "Scale 1 2 1\nCamera \"perspective\"\n" WORLD, &s, 0), 0);
    assert_true(has_warning(&s, "camera transform"));
    scene_destroy(&s);
}

/* Camera transforms whose float arithmetic overflows or underflows: an
 * error at the directive, or (computed in double) the right camera, never
 * a camera of NaNs and a black image. */
static void test_camera_precision(void **state)
{
    (void)state;
    Scene s;
    /* A tiny Scale underflows a float inverse; in double it is exact. */
    load_ok("Scale 1e-30 1e-30 1e-30\nLookAt 0 1 5  0 1 0  0 1 0\nCamera \"perspective\"\n" WORLD, &s);
    assert_vec3(s.camera.position, 0, 1, 5);
    assert_vec3(s.camera.forward, 0, 0, -1);
    assert_vec3(s.camera.right, -1, 0, 0);
    scene_destroy(&s);
    /* A look-at point 1e20 away: its squared distance overflows a float. */
    load_ok("LookAt 0 0 0  1e20 0 0  0 1 0\nCamera \"perspective\"\n" WORLD, &s);
    assert_vec3(s.camera.forward, 1, 0, 0);
    assert_vec3(s.camera.up, 0, 1, 0);
    scene_destroy(&s);

    load_fails("Scale 1e-40 1e-40 1e-40\nCamera \"perspective\"\n" WORLD, 2, "inverse overflows single precision");
    load_fails("Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 0 ]\nCamera \"perspective\"\n" WORLD, 2, "singular");
    load_fails("LookAt 3e38 1 5  -3e38 1 0  0 1 0\nCamera \"perspective\"\n" WORLD, 2,
               "the camera is at (3e+38, 1, 5), beyond 1e+18 from the origin");
    load_fails("Scale 1e30 1e30 1e30\nScale 1e30 1 1\n" WORLD, 2, "Scale: the transform overflows single precision");
    load_fails("Translate 3e38 0 0\nTranslate 3e38 0 0\n" WORLD, 2, "Translate: the transform overflows");
    load_fails("Scale 1e20 1e20 1e20\nConcatTransform [ 1e20 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1 ]\n" WORLD, 2,
               "ConcatTransform: the transform overflows");
    load_fails(WORLD "Scale 1e30 1e30 1e30\nRotate 45 0 0 1\nScale 1e10 1 1\n", 4, "Scale: the transform overflows");
}

/* Thin lens, screen window and frame aspect ratio, as pbrt-v4 reads them;
 * camera-space lengths scale with the camera transform. */
static void test_camera_lens_and_window(void **state)
{
    (void)state;
    Scene s;
    load_ok("Camera \"perspective\"\n" WORLD, &s);
    assert_int_equal(s.camera.projection, SCENE_CAMERA_PERSPECTIVE);
    assert_near(s.camera.lens_radius, 0, 0);
    assert_near(s.camera.focal_distance, 1e6, 0); /* pbrt-v4's default */
    assert_int_equal(s.camera.has_screen_window, 0);
    scene_destroy(&s);

    load_ok("Scale 2 2 2\nCamera \"perspective\" \"float lensradius\" 0.1 \"float focaldistance\" 3\n" WORLD, &s);
    assert_near(s.camera.scale, 0.5, 1e-7); /* world from camera halves lengths */
    assert_near(s.camera.lens_radius, 0.05, 1e-8);
    assert_near(s.camera.focal_distance, 1.5, 1e-7);
    scene_destroy(&s);

    load_ok("Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
            "Camera \"perspective\" \"float fov\" 90 \"float screenwindow\" [ 0 1 -0.5 0.25 ]\n" WORLD,
            &s);
    assert_int_equal(s.camera.has_screen_window, 1);
    float window[4];
    scene_camera_window(&s.camera, 200, 100, window);
    assert_near(window[0], 0, 1e-7); /* tan 45 = 1 times the window */
    assert_near(window[1], 1, 1e-6);
    assert_near(window[2], -0.5, 1e-6);
    assert_near(window[3], 0.25, 1e-6);
    scene_destroy(&s);

    /* frameaspectratio replaces the film's in the default window. */
    load_ok("Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
            "Camera \"perspective\" \"float fov\" 90 \"float frameaspectratio\" 0.5\n" WORLD,
            &s);
    scene_camera_window(&s.camera, 200, 100, window);
    assert_near(window[1], 1, 1e-6);
    assert_near(window[3], 2, 1e-6);
    scene_destroy(&s);

    load_fails("\nCamera \"perspective\" \"float lensradius\" -0.1\n" WORLD, 2,
               "Camera \"perspective\": lensradius -0.1 is negative");
    load_fails("Camera \"orthographic\" \"float focaldistance\" 0\n" WORLD, 1,
               "Camera \"orthographic\": focaldistance 0 is not positive");
    load_fails("Camera \"perspective\" \"float frameaspectratio\" 0\n" WORLD, 1, "frameaspectratio 0 is not positive");
    load_fails("Camera \"perspective\" \"float screenwindow\" [ -1 1 -1 1 0 ]\n" WORLD, 1, "expected 4 values");
    load_fails("Camera \"perspective\" \"float screenwindow\" [ 1 1 -1 1 ]\n" WORLD, 1, "the window is empty");
    load_fails("Camera \"orthographic\" \"float fov\" 45\n" WORLD, 1, "unsupported parameter \"float fov\"");
}

/* The orthographic window is in camera-space units: the camera's scale
 * makes them world lengths. */
static void test_orthographic_camera(void **state)
{
    (void)state;
    Scene s;
    load_ok("Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 32\n"
            "Scale 0.5 0.5 0.5\nCamera \"orthographic\" \"float lensradius\" 0.25\n" WORLD,
            &s);
    assert_int_equal(s.camera.projection, SCENE_CAMERA_ORTHOGRAPHIC);
    assert_near(s.camera.scale, 2, 1e-6);
    assert_near(s.camera.lens_radius, 0.5, 1e-7);
    float window[4];
    scene_camera_window(&s.camera, 64, 32, window); /* [-2, 2] x [-1, 1] camera units */
    assert_near(window[0], -4, 1e-6);
    assert_near(window[1], 4, 1e-6);
    assert_near(window[2], -2, 1e-6);
    assert_near(window[3], 2, 1e-6);
    scene_destroy(&s);
}

/* Each of pbrt-v4's filters with its defaults and its parameters; without
 * a PixelFilter, pbrt-v4's gaussian. */
static void test_pixel_filters(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD, &s);
    assert_int_equal(s.filter.type, SCENE_FILTER_GAUSSIAN);
    assert_near(s.filter.radius[0], 1.5, 0);
    assert_near(s.filter.sigma, 0.5, 0);
    scene_destroy(&s);
    static const struct {
        const char *text;
        SceneFilterType type;
        float radius[2];
    } cases[] = {
        {"PixelFilter \"box\"\n", SCENE_FILTER_BOX, {0.5f, 0.5f}},
        {"PixelFilter \"box\" \"float xradius\" 1 \"float yradius\" 2\n", SCENE_FILTER_BOX, {1, 2}},
        {"PixelFilter \"gaussian\" \"float sigma\" 0.25\n", SCENE_FILTER_GAUSSIAN, {1.5f, 1.5f}},
        {"PixelFilter \"mitchell\" \"float B\" 0.5 \"float C\" 0.25\n", SCENE_FILTER_MITCHELL, {2, 2}},
        {"PixelFilter \"sinc\" \"float tau\" 2\n", SCENE_FILTER_LANCZOS, {4, 4}},
        {"PixelFilter \"lanczos\" \"float xradius\" 3\n", SCENE_FILTER_LANCZOS, {3, 4}},
        {"PixelFilter \"triangle\"\n", SCENE_FILTER_TRIANGLE, {2, 2}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char text[256];
        snprintf(text, sizeof text, "%s" WORLD, cases[i].text);
        load_ok(text, &s);
        assert_int_equal(s.filter.type, cases[i].type);
        assert_near(s.filter.radius[0], cases[i].radius[0], 0);
        assert_near(s.filter.radius[1], cases[i].radius[1], 0);
        scene_destroy(&s);
    }
    load_ok("PixelFilter \"gaussian\" \"float sigma\" 0.25\n" WORLD, &s);
    assert_near(s.filter.sigma, 0.25, 0);
    scene_destroy(&s);
    load_ok("PixelFilter \"mitchell\" \"float B\" 0.5 \"float C\" 0.25\n" WORLD, &s);
    assert_near(s.filter.b, 0.5, 0);
    assert_near(s.filter.c, 0.25, 0);
    scene_destroy(&s);
    load_ok("PixelFilter \"sinc\" \"float tau\" 2\n" WORLD, &s);
    assert_near(s.filter.tau, 2, 0);
    scene_destroy(&s);

    load_fails("\nPixelFilter \"catmull-rom\"\n" WORLD, 2, "PixelFilter \"catmull-rom\" is not supported");
    load_fails("PixelFilter \"gaussian\" \"float xradius\" 0\n" WORLD, 1,
               "PixelFilter \"gaussian\": xradius 0 is not in (0, 32]");
    load_fails("PixelFilter \"box\" \"float yradius\" -1\n" WORLD, 1, "yradius -1 is not in (0, 32]");
    load_fails("PixelFilter \"triangle\" \"float xradius\" 33\n" WORLD, 1, "xradius 33 is not in (0, 32]");
    load_fails("PixelFilter \"gaussian\" \"float sigma\" 0\n" WORLD, 1, "sigma 0 is not in");
    load_fails("PixelFilter \"sinc\" \"float tau\" -1\n" WORLD, 1, "tau -1 is not in");
    load_fails("PixelFilter \"box\" \"float sigma\" 1\n" WORLD, 1, "unsupported parameter \"float sigma\"");
}

static void test_film_sampler_integrator_filter(void **state)
{
    (void)state;
    Scene s;
    load_ok("Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 32 ] \"string filename\" \"o.exr\"\n"
            "Sampler \"halton\" \"integer pixelsamples\" 8 \"integer seed\" 3\n"
            "Integrator \"path\" \"integer maxdepth\" [ 7 ] \"bool regularize\" true \"string lightsampler\" \"bvh\"\n"
            "PixelFilter \"box\"\n" WORLD,
            &s);
    assert_int_equal(s.width, 64);
    assert_int_equal(s.height, 32);
    assert_string_equal(s.film_filename, "o.exr");
    assert_string_equal(s.sampler, "halton");
    assert_int_equal(s.spp, 8);
    assert_int_equal(s.max_depth, 7);
    assert_int_equal(s.regularize, 1);
    scene_destroy(&s);
    load_fails("Film \"rgb\" \"integer xresolution\" 0\n" WORLD, 1, "resolution");
    load_fails("Sampler \"independent\" \"integer pixelsamples\" 0\n" WORLD, 1, "pixelsamples");
    load_fails("Integrator \"ambientocclusion\"\n" WORLD, 1, "its image differs");
    load_fails("Camera \"realistic\"\n" WORLD, 1, "only \"perspective\" and \"orthographic\"");
    load_fails(WORLD "Camera \"perspective\"\n", 2, "before WorldBegin");
    assert_int_equal(load_text("opt.pbrt", "Integrator \"volpath\"\nFilm \"gbuffer\"\n" WORLD, &s, 1), 0);
    assert_int_equal(s.warning_count, 1);
    assert_int_equal(s.note_count, 0); /* volpath: the path tracer, volumetric where there are media */
    scene_destroy(&s);
}

/* pbrt-v4's integrators that render the path tracer's expected image are
 * accepted with a note; those whose image differs are unsupported;
 * lightpath and bdpt are gmonrt's light tracer and bdpt, mlt and sppm
 * render with bdpt (with a note). */
static void test_integrators(void **state)
{
    (void)state;
    /* Those that render media in pbrt-v4 are rendered as volpath. */
    static const char *const same[] = {"simplevolpath", "simplepath", "randomwalk"};
    for (size_t i = 0; i < sizeof same / sizeof same[0]; ++i) {
        Scene s;
        char text[256], note[160];
        snprintf(text, sizeof text, "Integrator \"%s\" \"integer maxdepth\" 3\n" WORLD, same[i]);
        load_ok(text, &s);
        assert_int_equal(s.max_depth, 3);
        assert_int_equal(s.note_count, 1);
        assert_int_equal(s.integrator_media, i < 1);
        snprintf(note, sizeof note, ":1: note: Integrator \"%s\" is rendered by the path tracer (\"%s\")", same[i],
                 i < 1 ? "volpath" : "path");
        if (!strstr(s.notes[0], note) || !strstr(s.notes[0], "the expected image is the same"))
            fail_msg("note \"%s\" lacks \"%s\"", s.notes[0], note);
        scene_destroy(&s);
    }
    Scene s;
    load_ok("Integrator \"lightpath\" \"integer maxdepth\" 4\n" WORLD, &s); /* the light tracer: no note */
    assert_int_equal(s.note_count, 0);
    assert_int_equal(s.light_subpaths, SCENE_LIGHTPATH);
    assert_int_equal(s.max_depth, 4);
    scene_destroy(&s);
    load_ok("Integrator \"path\"\n" WORLD, &s);
    assert_int_equal(s.note_count, 0);
    assert_int_equal(s.light_subpaths, 0);
    scene_destroy(&s);
    load_ok("Integrator \"bdpt\" \"bool regularize\" true\n" WORLD, &s); /* bidirectional: no note */
    assert_int_equal(s.note_count, 0);
    assert_int_equal(s.light_subpaths, SCENE_BDPT);
    assert_int_equal(s.regularize, 1);
    scene_destroy(&s);
    static const char *const bidirectional[] = {"mlt", "sppm"}; /* rendered by bdpt, with a note */
    for (size_t i = 0; i < 2; ++i) {
        char text[256];
        snprintf(text, sizeof text, "Integrator \"%s\"\n" WORLD, bidirectional[i]);
        load_ok(text, &s);
        assert_int_equal(s.light_subpaths, SCENE_BDPT);
        assert_int_equal(s.note_count, 1);
        assert_non_null(strstr(s.notes[0], "bidirectional path tracing"));
        scene_destroy(&s);
    }
    load_ok("Integrator \"volpath\"\n" WORLD, &s);
    assert_int_equal(s.note_count, 0);
    assert_int_equal(s.integrator_media, 1);
    scene_destroy(&s);
    load_ok(WORLD, &s);
    assert_int_equal(s.integrator_media, 1); /* pbrt-v4's default integrator is volpath */
    scene_destroy(&s);
    load_ok("Integrator \"path\"\n" WORLD, &s);
    assert_int_equal(s.note_count, 0);
    assert_int_equal(s.integrator_media, 0);
    assert_string_equal(s.light_sampler, "bvh"); /* pbrt-v4's default */
    scene_destroy(&s);
    /* Parameters that only tune convergence are accepted. */
    load_ok("Integrator \"mlt\" \"integer mutationsperpixel\" 10 \"float largestepprobability\" 0.2 "
            "\"integer chains\" 100 \"integer bootstrapsamples\" 10 \"float sigma\" 0.01\n" WORLD,
            &s);
    scene_destroy(&s);
    load_ok("Integrator \"sppm\" \"integer photonsperiteration\" 100 \"float radius\" 1 \"integer seed\" 2\n" WORLD,
            &s);
    scene_destroy(&s);
    load_fails("Integrator \"bdpt\" \"bool visualizestrategies\" true\n" WORLD, 1, "visualizestrategies");
    load_fails("Integrator \"aov\"\n" WORLD, 1, "Integrator \"aov\" is not supported: its image differs");
    load_fails("Integrator \"volpath\" \"float cossample\" 1\n" WORLD, 1, "cossample");
    assert_int_equal(load_text("ao.pbrt", "Integrator \"ambientocclusion\"\n" WORLD, &s, 1), 0);
    assert_true(has_warning(&s, "Integrator \"ambientocclusion\" is not supported: its image differs from the path "
                                "tracer's"));
    assert_true(has_warning(&s, "; \"path\" is used"));
    scene_destroy(&s);

    /* lightsampler: recorded; exhaustive, which the light tree renders,
     * with a note. */
    static const char *const samplers[] = {"bvh", "uniform", "power", "exhaustive"};
    for (size_t i = 0; i < 4; ++i) {
        char text[256];
        snprintf(text, sizeof text, "Integrator \"path\" \"string lightsampler\" \"%s\"\n" WORLD, samplers[i]);
        load_ok(text, &s);
        assert_string_equal(s.light_sampler, samplers[i]);
        assert_int_equal(s.note_count, i == 3 ? 1 : 0);
        if (i == 3)
            assert_non_null(strstr(s.notes[0], "rendered with gmonrt's light tree"));
        scene_destroy(&s);
    }
    load_fails("Integrator \"path\" \"string lightsampler\" \"spatial\"\n" WORLD, 1,
               "\"lightsampler\" \"spatial\" is not bvh, exhaustive, power or uniform");

    /* rrthreshold: path and volpath (transparent-machines sets 0). */
    load_ok("Integrator \"volpath\" \"float rrthreshold\" 0\n" WORLD, &s);
    assert_near(s.rr_threshold, 0, 0);
    scene_destroy(&s);
    load_ok("Integrator \"path\" \"float rrthreshold\" 0.25\n" WORLD, &s);
    assert_near(s.rr_threshold, 0.25, 0);
    scene_destroy(&s);
    load_fails("Integrator \"path\" \"float rrthreshold\" -1\n" WORLD, 1, "rrthreshold -1 must not be negative");
    load_fails("Integrator \"bdpt\" \"float rrthreshold\" 0\n" WORLD, 1, "rrthreshold");
}

/* ----------------------------------------------------------- transforms */

static void test_translate_then_scale(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Translate 1 2 3\nScale 2 2 2\n" TRIANGLE, &s);
    assert_int_equal(s.triangle_count, 1);
    assert_int_equal(s.vertex_count, 3);
    /* x_world = T * S * x: scale first, then translate. */
    assert_vec3(vertex(&s, 0, 0), 3, 2, 3);
    assert_vec3(vertex(&s, 0, 1), 1, 4, 3);
    assert_vec3(vertex(&s, 0, 2), 1, 2, 5);
    scene_destroy(&s);
}

static void test_rotate(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Rotate 90 0 0 1\n" TRIANGLE, &s);
    assert_vec3(vertex(&s, 0, 0), 0, 1, 0);
    assert_vec3(vertex(&s, 0, 1), -1, 0, 0);
    assert_vec3(vertex(&s, 0, 2), 0, 0, 1);
    scene_destroy(&s);
    load_ok(WORLD "Rotate 90 0 2 0\n" TRIANGLE, &s); /* the axis is normalized */
    assert_vec3(vertex(&s, 0, 0), 0, 0, -1);
    assert_vec3(vertex(&s, 0, 2), 1, 0, 0);
    scene_destroy(&s);
}

static void test_transform_concat_identity(void **state)
{
    (void)state;
    Scene s;
    /* The matrix is listed column by column: the translation comes last. */
    load_ok(WORLD "Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\n" TRIANGLE
                  "ConcatTransform 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1\n" TRIANGLE "Identity\n" TRIANGLE
                  "Translate 9 9 9\nTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1 ]\n" TRIANGLE,
            &s);
    assert_int_equal(s.triangle_count, 4);
    assert_vec3(vertex(&s, 0, 0), 6, 6, 7);
    assert_vec3(vertex(&s, 1, 0), 7, 6, 7);
    assert_vec3(vertex(&s, 1, 1), 5, 8, 7);
    assert_vec3(vertex(&s, 2, 0), 1, 0, 0);
    assert_vec3(vertex(&s, 3, 0), 1, 0, 0); /* Transform replaces the CTM */
    scene_destroy(&s);
}

static void test_attribute_and_transform_blocks(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "AttributeBegin\n  Translate 1 0 0\n  Material \"dielectric\"\n" TRIANGLE "AttributeEnd\n" TRIANGLE
                  "TransformBegin\n  Translate 0 5 0\n  Material \"conductor\"\n" TRIANGLE "TransformEnd\n" TRIANGLE,
            &s);
    assert_int_equal(s.shape_count, 4);
    assert_vec3(vertex(&s, 0, 0), 2, 0, 0);
    assert_int_equal(s.materials[s.shapes[0].material].type, SCENE_MATERIAL_DIELECTRIC);
    assert_vec3(vertex(&s, 1, 0), 1, 0, 0); /* restored transform and material */
    assert_int_equal(s.materials[s.shapes[1].material].type, SCENE_MATERIAL_DIFFUSE);
    assert_near(s.materials[s.shapes[1].material].reflectance[0], 0.5, 0);
    assert_vec3(vertex(&s, 2, 0), 1, 5, 0);
    assert_vec3(vertex(&s, 3, 0), 1, 0, 0); /* TransformEnd restores only the transform */
    assert_int_equal(s.materials[s.shapes[3].material].type, SCENE_MATERIAL_CONDUCTOR);
    scene_destroy(&s);
    load_fails(WORLD "AttributeBegin\nTransformEnd\n", 3, "AttributeBegin");
    load_fails(WORLD "AttributeEnd\n", 2, "without a matching");
    load_fails(WORLD "\nAttributeBegin\n" TRIANGLE, 3, "without a matching end");
    load_fails("AttributeBegin\nWorldBegin\nAttributeEnd\n", 2, "inside the AttributeBegin");
}

/* pbrt-v4's named coordinate systems: CoordinateSystem saves the CTM,
 * CoordSysTransform restores it; "camera" (camera to world) is defined at
 * Camera and "world" at WorldBegin; an unknown name is a warning. */
static void test_coordinate_systems(void **state)
{
    (void)state;
    Scene s;
    load_ok("LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\n" WORLD "Translate 1 2 3\nCoordinateSystem \"mine\"\n"
            "CoordSysTransform \"camera\"\n" TRIANGLE "Identity\nCoordSysTransform \"mine\"\n" TRIANGLE
            "CoordSysTransform \"world\"\n" TRIANGLE,
            &s);
    assert_int_equal(s.triangle_count, 3);
    assert_vec3(vertex(&s, 0, 0), 1, 0, -5); /* camera space: +x right, +z forward from (0, 0, -5) */
    assert_vec3(vertex(&s, 0, 2), 0, 0, -4);
    assert_vec3(vertex(&s, 1, 0), 2, 2, 3); /* "mine": Translate 1 2 3 */
    assert_vec3(vertex(&s, 2, 0), 1, 0, 0); /* "world": the identity */
    scene_destroy(&s);

    /* Before WorldBegin the CTM is the camera transform. */
    load_ok("Translate 0 0 7\nCoordinateSystem \"early\"\nIdentity\nCamera \"perspective\"\n" WORLD
            "CoordSysTransform \"early\"\n" TRIANGLE,
            &s);
    assert_vec3(vertex(&s, 0, 0), 1, 0, 7);
    scene_destroy(&s);

    assert_int_equal(load_text("cs.pbrt", WORLD "Translate 1 0 0\nCoordSysTransform \"nowhere\"\n" TRIANGLE, &s, 0), 0);
    assert_int_equal(s.warning_count, 1);
    assert_true(has_warning(&s, "cs.pbrt:3: warning: CoordSysTransform: no coordinate system named \"nowhere\""));
    assert_vec3(vertex(&s, 0, 0), 2, 0, 0); /* unchanged */
    scene_destroy(&s);
    load_fails(WORLD "CoordSysTransform camera\n", 2, "quoted string");
    /* pbrt-v4 has no CameraTransform directive. */
    load_fails(WORLD "CameraTransform\n", 2, "unknown directive 'CameraTransform'");
}

/* ActiveTransform and TransformTimes: gmonrt renders the start time (the
 * start transform) with one warning once the two transforms differ. */
static void test_active_transform(void **state)
{
    (void)state;
    Scene s;
    load_ok("TransformTimes 0 1\n" WORLD "ActiveTransform EndTime\nActiveTransform All\nTranslate 1 0 0\n" TRIANGLE
            "AttributeBegin\n  ActiveTransform StartTime\nAttributeEnd\nTranslate 1 0 0\n" TRIANGLE,
            &s);
    assert_vec3(vertex(&s, 0, 0), 2, 0, 0);
    assert_vec3(vertex(&s, 1, 0), 3, 0, 0); /* AttributeEnd restored All */
    scene_destroy(&s);

    const char *moving = "TransformTimes 0 1\n" WORLD "AttributeBegin\n  ActiveTransform EndTime\n  Translate 10 0 0\n"
                         "  Rotate 90 0 0 1\n  ActiveTransform All\n  Scale 2 2 2\n  " TRIANGLE "AttributeEnd\n"
                         "ActiveTransform StartTime\nTranslate 0 5 0\nActiveTransform All\n" TRIANGLE;
    assert_int_equal(load_text("moving.pbrt", moving, &s, 0), 0);
    assert_vec3(vertex(&s, 0, 0), 2, 0, 0); /* the start transform: Scale 2 only */
    assert_vec3(vertex(&s, 1, 0), 1, 5, 0);
    assert_int_equal(s.warning_count, 1); /* one for the whole scene */
    assert_true(has_warning(&s, "moving.pbrt:9: warning: Shape: its transforms at the start and end times differ"));
    assert_true(has_warning(&s, "motion is not rendered"));
    scene_destroy(&s);

    /* A moving camera: rendered from where it starts. */
    assert_int_equal(load_text("camera.pbrt",
                               "ActiveTransform EndTime\nTranslate 0 0 -3\nActiveTransform All\nTranslate 0 0 2\n"
                               "Camera \"perspective\"\n" WORLD,
                               &s, 0),
                     0);
    assert_vec3(s.camera.position, 0, 0, -2);
    assert_true(has_warning(&s, "camera.pbrt:5: warning: Camera: its transforms"));
    scene_destroy(&s);

    /* TransformBegin/End restore both transforms and ActiveTransform; a
     * transform that moves nothing is not warned about. */
    load_ok(WORLD "TransformBegin\n  ActiveTransform EndTime\n  Translate 4 0 0\nTransformEnd\n" TRIANGLE, &s);
    assert_vec3(vertex(&s, 0, 0), 1, 0, 0);
    scene_destroy(&s);

    load_fails(WORLD "ActiveTransform Sometimes\n", 2, "expected All, StartTime or EndTime, got 'Sometimes'");
    load_fails(WORLD "TransformTimes 0 1\n", 2, "before WorldBegin");
    load_fails("TransformTimes 0\n" WORLD, 2, "expected 2 numbers");
}

/* ------------------------------------------------------------ materials */

static const SceneMaterial *material_of_shape(const Scene *s, size_t shape)
{
    return &s->materials[s->shapes[shape].material];
}

static void test_materials(void **state)
{
    (void)state;
    Scene s;
    load_ok(
        WORLD
        "Material \"diffuse\" \"rgb reflectance\" [ 0.1 0.2 0.3 ]\n" TRIANGLE
        "Material \"dielectric\" \"float eta\" 1.33 \"float roughness\" 0.25 \"bool remaproughness\" false\n" TRIANGLE
        "Material \"dielectric\" \"float uroughness\" 0.04 \"float vroughness\" 0.09\n" TRIANGLE
        "Material \"conductor\" \"rgb eta\" [ 0.2 0.9 1.1 ] \"rgb k\" [ 3.9 2.4 2.1 ] \"float roughness\" "
        "0.1\n" TRIANGLE "Material \"conductor\" \"rgb reflectance\" [ 0.9 0.8 0.5 ]\n" TRIANGLE
        "Material \"conductor\"\n" TRIANGLE
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.4 0.5 0.6 ] \"float roughness\" 0 "
        "\"float eta\" 1.6 \"float thickness\" 0.02\n" TRIANGLE,
        &s);
    assert_int_equal(s.shape_count, 7);
    const SceneMaterial *m = material_of_shape(&s, 0);
    assert_int_equal(m->type, SCENE_MATERIAL_DIFFUSE);
    assert_vec3(m->reflectance, 0.1, 0.2, 0.3);

    float alpha[2];
    m = material_of_shape(&s, 1);
    assert_int_equal(m->type, SCENE_MATERIAL_DIELECTRIC);
    assert_near(m->eta, 1.33, 1e-6);
    assert_near(m->roughness[0], 0.25, 1e-7);
    assert_near(m->roughness[1], 0.25, 1e-7);
    assert_int_equal(m->remap_roughness, 0);
    scene_material_alpha(m, alpha);
    assert_near(alpha[0], 0.25, 1e-7);

    m = material_of_shape(&s, 2);
    assert_near(m->eta, 1.5, 0); /* pbrt's default */
    assert_int_equal(m->remap_roughness, 1);
    scene_material_alpha(m, alpha);
    assert_near(alpha[0], 0.2, 1e-6); /* sqrt(0.04) */
    assert_near(alpha[1], 0.3, 1e-6);

    m = material_of_shape(&s, 3);
    assert_int_equal(m->type, SCENE_MATERIAL_CONDUCTOR);
    assert_int_equal(m->use_reflectance, 0);
    assert_vec3(m->conductor_eta, 0.2, 0.9, 1.1);
    assert_vec3(m->conductor_k, 3.9, 2.4, 2.1);
    assert_near(m->roughness[0], 0.1, 1e-7);

    m = material_of_shape(&s, 4);
    assert_int_equal(m->use_reflectance, 1);
    assert_vec3(m->reflectance, 0.9, 0.8, 0.5);

    m = material_of_shape(&s, 5); /* pbrt's default conductor: copper */
    assert_int_equal(m->use_reflectance, 0);
    assert_true(m->conductor_k[0] > m->conductor_k[2] && m->conductor_eta[0] < m->conductor_eta[2]);

    m = material_of_shape(&s, 6);
    assert_int_equal(m->type, SCENE_MATERIAL_COATED_DIFFUSE);
    assert_vec3(m->reflectance, 0.4, 0.5, 0.6);
    assert_near(m->eta, 1.6, 1e-6);
    scene_destroy(&s);

    load_fails(WORLD "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"rgb k\" [ 1 1 1 ]\n", 2, "either");
    load_fails(WORLD "Material \"diffuse\" \"rgb reflectance\" [ 1.5 0 0 ]\n", 2, "above 1");
    load_fails(WORLD "Material \"dielectric\" \"float eta\" -1\n", 2, "eta");
    load_fails(WORLD "Material \"dielectric\" \"spectrum eta\" \"glass-XX\"\n", 2, "not a named spectrum");
    load_fails(WORLD "Material \"diffuse\" \"texture reflectance\" \"checks\"\n", 2, "texture");
    load_fails(WORLD "Material \"mix\"\n", 2, "Material \"mix\": needs \"string materials\" with two material names");
    load_fails("Material \"diffuse\"\n" WORLD, 1, "after WorldBegin");
}

/* The materials of pbrt-v4 beyond the basic four: parameters, pbrt-v4's
 * defaults, and errors. */
static void test_layered_mix_and_transmission_materials(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD
            "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
            "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
            "MakeNamedMaterial \"glass\" \"string type\" \"interface\"\n"
            "Material \"coatedconductor\" \"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" "
            "\"metal-Au-k\" \"float interface.roughness\" 0.04 \"float conductor.uroughness\" 0.09 "
            "\"float conductor.vroughness\" 0.16 \"float interface.eta\" 1.4\n" TRIANGLE
            "Material \"coatedconductor\" \"rgb reflectance\" [ 0.9 0.5 0.2 ] \"integer maxdepth\" 4\n" TRIANGLE
            "Material \"coateddiffuse\" \"rgb albedo\" [ 0.2 0.3 0.4 ] \"float g\" -0.5 \"float thickness\" 0.5 "
            "\"integer nsamples\" 3 \"bool remaproughness\" false \"float roughness\" 0.3\n" TRIANGLE
            "Material \"diffusetransmission\"\n" TRIANGLE
            "Material \"diffusetransmission\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"rgb transmittance\" [ 1 0.5 0 ] "
            "\"float scale\" 0.5\n" TRIANGLE
            "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 0.3\n" TRIANGLE
            "Material \"mix\" \"string materials\" [ \"b\" \"a\" ]\n" TRIANGLE
            "Material \"thindielectric\" \"float eta\" 1.33\n" TRIANGLE "NamedMaterial \"glass\"\n" TRIANGLE,
            &s);
    const SceneMaterial *m = material_of_shape(&s, 0);
    float alpha[2];
    assert_int_equal(m->type, SCENE_MATERIAL_COATED_CONDUCTOR);
    assert_near(m->eta, 1.4, 1e-6);
    assert_int_equal(m->use_reflectance, 0);
    assert_near(m->conductor_eta[0], 0.282615, 1e-3); /* gold, as the conductor test's */
    scene_material_alpha(m, alpha);
    assert_near(alpha[0], 0.2, 1e-6);
    scene_roughness_alpha(m->base_roughness, m->remap_roughness, alpha);
    assert_near(alpha[0], 0.3, 1e-6);
    assert_near(alpha[1], 0.4, 1e-6);
    assert_near(m->thickness, 0.01, 1e-9); /* pbrt-v4's defaults */
    assert_int_equal(m->max_depth, 10);
    assert_int_equal(m->sample_count, 1);
    assert_vec3(m->albedo, 0, 0, 0);
    m = material_of_shape(&s, 1);
    assert_int_equal(m->use_reflectance, 1);
    assert_vec3(m->reflectance, 0.9, 0.5, 0.2);
    assert_near(m->eta, 1.5, 0);
    assert_int_equal(m->max_depth, 4);
    m = material_of_shape(&s, 2);
    assert_int_equal(m->type, SCENE_MATERIAL_COATED_DIFFUSE);
    assert_vec3(m->albedo, 0.2, 0.3, 0.4);
    assert_near(m->g, -0.5, 0);
    assert_near(m->thickness, 0.5, 0);
    assert_int_equal(m->sample_count, 3);
    scene_material_alpha(m, alpha);
    assert_near(alpha[0], 0.3, 1e-7);
    m = material_of_shape(&s, 3);
    assert_int_equal(m->type, SCENE_MATERIAL_DIFFUSE_TRANSMISSION);
    assert_vec3(m->reflectance, 0.25, 0.25, 0.25);
    assert_vec3(m->transmittance, 0.25, 0.25, 0.25);
    m = material_of_shape(&s, 4);
    assert_vec3(m->reflectance, 0.25, 0.25, 0.25); /* scaled */
    assert_vec3(m->transmittance, 0.5, 0.25, 0);
    m = material_of_shape(&s, 5);
    assert_int_equal(m->type, SCENE_MATERIAL_MIX);
    assert_int_equal(s.materials[m->mix_materials[0]].type, SCENE_MATERIAL_DIFFUSE);
    assert_int_equal(s.materials[m->mix_materials[1]].type, SCENE_MATERIAL_CONDUCTOR);
    assert_near(m->mix_amount, 0.3, 1e-7);
    m = material_of_shape(&s, 6);
    assert_int_equal(s.materials[m->mix_materials[0]].type, SCENE_MATERIAL_CONDUCTOR);
    assert_near(m->mix_amount, 0.5, 0);
    m = material_of_shape(&s, 7);
    assert_int_equal(m->type, SCENE_MATERIAL_THIN_DIELECTRIC);
    assert_near(m->eta, 1.33, 1e-6);
    assert_int_equal(material_of_shape(&s, 8)->type, SCENE_MATERIAL_INTERFACE);
    scene_destroy(&s);

    load_fails(WORLD "Material \"mix\" \"string materials\" [ \"a\" ]\n", 2, "two material names");
    load_fails(WORLD "Material \"mix\" \"string materials\" [ \"a\" \"b\" ]\n", 2, "no material named \"a\"");
    load_fails(WORLD "MakeNamedMaterial \"i\" \"string type\" \"interface\"\n"
                     "Material \"mix\" \"string materials\" [ \"i\" \"i\" ]\n",
               3, "a mix cannot hold");
    load_fails(WORLD "Material \"coateddiffuse\" \"float thickness\" 0\n", 2, "thickness > 0");
    load_fails(WORLD "Material \"coatedconductor\" \"integer nsamples\" 0\n", 2, "nsamples");
    load_fails(WORLD "Material \"coatedconductor\" \"rgb reflectance\" [ 1 1 1 ] \"rgb conductor.k\" [ 1 1 1 ]\n", 2,
               "either \"reflectance\" or \"conductor.eta\"");
    load_fails(WORLD "Material \"diffusetransmission\" \"float scale\" 3\n", 2, "scatter more than it receives");
    load_fails(WORLD "Material \"thindielectric\" \"float roughness\" 0.1\n", 2, "unsupported parameter");
    load_fails(WORLD "Material \"hair\"\n", 2, "Material \"hair\" is not supported");
    load_fails(WORLD "Material \"measured\" \"string filename\" \"x.bsdf\"\n", 2,
               "Material \"measured\" is not supported");
    load_fails(WORLD "MakeNamedMaterial \"i\" \"string type\" \"interface\"\nNamedMaterial \"i\"\n"
                     "AreaLightSource \"diffuse\"\n" TRIANGLE,
               5, "an area light on a shape of Material \"interface\"");
    /* Mixes of mixes, up to the kernel's limit. */
    char text[4096] = WORLD "MakeNamedMaterial \"m0\" \"string type\" \"diffuse\"\n";
    for (int i = 1; i <= SCENE_MIX_MAX_NESTING + 1; ++i)
        snprintf(text + strlen(text), sizeof text - strlen(text),
                 "MakeNamedMaterial \"m%d\" \"string type\" \"mix\" \"string materials\" [ \"m%d\" \"m0\" ]\n", i,
                 i - 1);
    load_fails(text, SCENE_MIX_MAX_NESTING + 3, "mixes nested deeper than 8");

    /* Substitutes with allow_unsupported: a diffuse of the reflectance. */
    assert_int_equal(
        load_text("subst.pbrt",
                  WORLD "Material \"subsurface\" \"rgb reflectance\" [ 0.2 0.4 0.6 ] \"float eta\" 1.33\n" TRIANGLE
                        "Material \"hair\"\n" TRIANGLE,
                  &s, 1),
        0);
    assert_int_equal(material_of_shape(&s, 0)->type, SCENE_MATERIAL_DIFFUSE);
    assert_vec3(material_of_shape(&s, 0)->reflectance, 0.2, 0.4, 0.6);
    assert_vec3(material_of_shape(&s, 1)->reflectance, 0.5, 0.5, 0.5);
    assert_true(has_warning(&s, "Material \"subsurface\" is not supported; a diffuse of its \"reflectance\""));
    scene_destroy(&s);
    /* ... also a textured one. */
    assert_int_equal(load_text("subst-texture.pbrt",
                               WORLD "Texture \"skin\" \"spectrum\" \"constant\" \"rgb value\" [ 0.3 0.2 0.1 ]\n"
                                     "Material \"subsurface\" \"texture reflectance\" \"skin\"\n" TRIANGLE,
                               &s, 1),
                     0);
    assert_int_equal(material_of_shape(&s, 0)->type, SCENE_MATERIAL_DIFFUSE);
    assert_int_equal(material_of_shape(&s, 0)->textures[SCENE_SLOT_REFLECTANCE], 0);
    scene_destroy(&s);
}

static void test_named_materials(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.6 0.1 0.1 ]\n"
                  "MakeNamedMaterial \"glass\" \"string type\" [ \"dielectric\" ]\n"
                  "NamedMaterial \"red\"\n" TRIANGLE "NamedMaterial \"glass\"\n" TRIANGLE,
            &s);
    assert_vec3(material_of_shape(&s, 0)->reflectance, 0.6, 0.1, 0.1);
    assert_int_equal(material_of_shape(&s, 1)->type, SCENE_MATERIAL_DIELECTRIC);
    scene_destroy(&s);
    load_fails(WORLD "NamedMaterial \"nothing\"\n", 2, "no material named \"nothing\"");
    load_fails(WORLD "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                     "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n",
               3, "defined twice");
    load_fails(WORLD "MakeNamedMaterial \"a\" \"rgb reflectance\" [ 1 1 1 ]\n", 2, "string type");
}

/* --------------------------------------------------------------- lights */

static void test_area_lights_and_orientation(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD
            "AttributeBegin\n"
            "  AreaLightSource \"diffuse\" \"rgb L\" [ 1 2 3 ] \"float scale\" 2 \"bool twosided\" \"true\"\n" TRIANGLE
            "AttributeEnd\n"
            "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n  ReverseOrientation\n" TRIANGLE
            "AttributeEnd\n" TRIANGLE                   /* 2: no light, not reversed */
            "AttributeBegin\n  Scale -1 1 1\n" TRIANGLE /* 3: a mirror flips a mesh's normal back (pbrt) */
            "  Shape \"sphere\"\n"                      /* 4: spheres stay outward under mirrors */
            "  ReverseOrientation\n" TRIANGLE           /* 5: both: not flipped */
            "AttributeEnd\n"
            "AttributeBegin\n  ReverseOrientation\n  Shape \"sphere\"\nAttributeEnd\n", /* 6 */
            &s);
    assert_int_equal(s.shape_count, 7);
    assert_int_equal(s.area_light_count, 2);
    const SceneAreaLight *light = &s.area_lights[s.shapes[0].area_light];
    assert_vec3(light->radiance, 2, 4, 6);
    assert_int_equal(light->two_sided, 1);
    assert_int_equal(light->shape, 0);
    assert_int_equal(s.shapes[0].flip_normal, 0);
    light = &s.area_lights[s.shapes[1].area_light];
    assert_vec3(light->radiance, 4, 4, 4);
    assert_int_equal(light->two_sided, 0);
    assert_int_equal(light->shape, 1);
    assert_int_equal(s.shapes[1].flip_normal, 1);
    assert_int_equal(s.shapes[2].area_light, -1);
    assert_int_equal(s.shapes[2].flip_normal, 0);
    assert_int_equal(s.shapes[3].flip_normal, 1);
    assert_int_equal(s.shapes[4].kind, SCENE_SHAPE_SPHERE);
    assert_int_equal(s.shapes[4].flip_normal, 0);
    assert_int_equal(s.shapes[5].flip_normal, 0);
    assert_int_equal(s.shapes[6].flip_normal, 1);
    scene_destroy(&s);
    load_fails(WORLD "AreaLightSource \"diffuse\" \"blackbody L\" [ 0 ]\n", 2, "not positive");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"rgb L\" [ 1 -1 1 ]\n", 2, "negative");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"float power\" -10\n", 2, "power must be positive");
    load_fails(WORLD "AreaLightSource \"projector\"\n", 2, "projector");
    /* L * scale must fit a float (an infinite radiance renders black). */
    load_fails(WORLD "\nAreaLightSource \"diffuse\" \"rgb L\" [ 3e38 1 1 ] \"float scale\" 10\n", 3,
               "AreaLightSource: the radiance L * scale, 3e+39, overflows single precision");
}

static const SceneLight *only_light(const Scene *s, SceneLightType type)
{
    assert_int_equal(s->light_count, 1);
    assert_int_equal(s->lights[0].type, type);
    return &s->lights[0];
}

static void test_infinite_light(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "LightSource \"infinite\" \"rgb L\" [ 0.5 0.25 1 ] \"float scale\" [ 2 ]\n", &s);
    assert_vec3(only_light(&s, SCENE_LIGHT_INFINITE)->radiance, 1, 0.5, 2);
    scene_destroy(&s);
    load_ok(WORLD "LightSource \"infinite\"\n", &s); /* pbrt's default: L = 1 */
    assert_vec3(only_light(&s, SCENE_LIGHT_INFINITE)->radiance, 1, 1, 1);
    scene_destroy(&s);
    /* illuminance E: a uniform sky of radiance E / pi gives E. */
    load_ok(WORLD "LightSource \"infinite\" \"float illuminance\" 3.14159265\n", &s);
    assert_vec3(only_light(&s, SCENE_LIGHT_INFINITE)->radiance, 1, 1, 1);
    scene_destroy(&s);
    load_fails(WORLD "LightSource \"infinite\" \"string filename\" \"sky.exr\"\n", 2, "cannot find");
    load_fails(WORLD "LightSource \"infinite\" \"string filename\" \"sky.exr\" \"rgb L\" [1 1 1]\n", 2,
               "both \"L\" and \"filename\"");
    /* Spectra are normalised to luminance 1 (pbrt-v4's SpectrumToPhotometric):
     * D65 is then white, a flat spectrum slightly pink. */
    load_ok(WORLD "LightSource \"infinite\" \"spectrum L\" \"stdillum-D65\" \"float scale\" 2\n", &s);
    assert_vec3(only_light(&s, SCENE_LIGHT_INFINITE)->radiance, 2, 2, 2);
    scene_destroy(&s);
    load_ok(WORLD "LightSource \"point\" \"spectrum I\" [ 300 1 800 1 ]\n", &s);
    const float *flat = only_light(&s, SCENE_LIGHT_POINT)->radiance;
    assert_near(0.2126 * flat[0] + 0.7152 * flat[1] + 0.0722 * flat[2], 1.0, 2e-3);
    assert_true(flat[0] > flat[1]);
    scene_destroy(&s);
    load_fails("Film \"rgb\" \"float cropwindow\" [ 0 1 0 ]\n" WORLD, 1, "expected 4 values");
    load_fails("Film \"rgb\" \"float cropwindow\" [ 0.5 0.5 0 1 ]\n" WORLD, 1, "the crop window leaves no pixel");
    load_fails("Film \"rgb\" \"integer pixelbounds\" [ 2000 3000 0 10 ]\n" WORLD, 1, "pixel bounds leaves no pixel");
    load_fails(WORLD "LightSource \"sun\"\n", 2, "LightSource \"sun\" is not supported");
    load_fails(WORLD "LightSource \"projection\"\n", 2, "missing \"string filename\"");
    load_fails(WORLD "LightSource \"projection\" \"string filename\" \"slide.png\" \"float fov\" 180\n", 2,
               "fov must be in (0, 180)");
    load_fails(WORLD "LightSource \"goniometric\" \"string filename\" \"missing.exr\"\n", 2, "cannot find");
    load_fails(WORLD "LightSource \"infinite\" \"rgb L\" [ 3e38 3e38 3e38 ] \"float scale\" 10\n", 2,
               "overflows single precision");
    load_fails(WORLD "LightSource \"infinite\" \"float illuminance\" 0\n", 2, "must be positive");
}

/* Point and spot lights: I * scale at the CTM applied to "from"; "power"
 * replaces the scale by power / (solid angle the light covers). */
static void test_point_and_spot_lights(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD
            "Translate 1 2 3\nLightSource \"point\" \"rgb I\" [ 1 2 3 ] \"float scale\" 2 \"point3 from\" [ 0 0 1 ]\n",
            &s);
    const SceneLight *l = only_light(&s, SCENE_LIGHT_POINT);
    assert_vec3(l->radiance, 2, 4, 6);
    assert_vec3(l->position, 1, 2, 4);
    scene_destroy(&s);
    load_ok(WORLD "LightSource \"point\" \"float power\" 12.566370614\n", &s);
    assert_vec3(only_light(&s, SCENE_LIGHT_POINT)->radiance, 1, 1, 1); /* 4 pi I = power */
    scene_destroy(&s);
    load_ok(WORLD "Rotate 90 0 1 0\nLightSource \"spot\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0 0 5 ] "
                  "\"float coneangle\" 60 \"float conedeltaangle\" 20\n",
            &s);
    l = only_light(&s, SCENE_LIGHT_SPOT);
    assert_vec3(l->direction, 1, 0, 0); /* +z rotated 90 degrees about +y */
    assert_near(l->cos_total_width, 0.5, 1e-6);
    assert_near(l->cos_falloff_start, cos(40.0 * 3.14159265358979 / 180.0), 1e-6);
    scene_destroy(&s);
    /* power: 2 pi I ((1 - cos start) + (cos start - cos end) / 2) = power */
    load_ok(WORLD "LightSource \"spot\" \"float coneangle\" 90 \"float conedeltaangle\" 0 \"float power\" "
                  "6.283185307\n",
            &s);
    assert_vec3(only_light(&s, SCENE_LIGHT_SPOT)->radiance, 1, 1, 1);
    scene_destroy(&s);
    load_fails(WORLD "LightSource \"spot\" \"float coneangle\" 10 \"float conedeltaangle\" 20\n", 2,
               "conedeltaangle in [0, coneangle]");
    load_fails(WORLD "LightSource \"spot\" \"point3 from\" [ 1 1 1 ] \"point3 to\" [ 1 1 1 ]\n", 2, "no direction");
    load_fails(WORLD "LightSource \"point\" \"point3 from\" [ 1 1 ]\n", 2, "point3 from");
    load_fails(WORLD "LightSource \"point\" \"float power\" 0\n", 2, "must be positive");
    load_fails(WORLD "LightSource \"point\" \"rgb L\" [ 1 1 1 ]\n", 2, "rgb L");
}

/* A distant light shines from "from" toward "to": its direction (toward
 * the light) is from - to through the CTM; illuminance replaces scale. */
static void test_distant_light(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Scale 1 -1 1\nLightSource \"distant\" \"point3 from\" [ 0 4 0 ] \"point3 to\" [ 0 0 0 ] "
                  "\"rgb L\" [ 1 2 3 ] \"float illuminance\" 2\n",
            &s);
    const SceneLight *l = only_light(&s, SCENE_LIGHT_DISTANT);
    assert_vec3(l->direction, 0, -1, 0);
    assert_vec3(l->radiance, 2, 4, 6);
    scene_destroy(&s);
    load_ok(WORLD "LightSource \"distant\"\n", &s); /* pbrt's default: from the origin toward +z */
    assert_vec3(only_light(&s, SCENE_LIGHT_DISTANT)->direction, 0, 0, -1);
    scene_destroy(&s);
}

/* --------------------------------------------------------------- shapes */

static void test_spheres(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD
            "Shape \"sphere\"\n"
            "AttributeBegin\n  Translate 1 2 3\n  Scale 2 2 2\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
            "AttributeBegin\n  Rotate 30 1 1 0\n  Scale -3 -3 -3\n  Shape \"sphere\" \"float radius\" [ 2 ]\n"
            "AttributeEnd\n",
            &s);
    assert_int_equal(s.sphere_count, 3);
    assert_vec3(s.spheres[0].center, 0, 0, 0);
    assert_near(s.spheres[0].radius, 1, 0);
    assert_vec3(s.spheres[1].center, 1, 2, 3);
    assert_near(s.spheres[1].radius, 1, 1e-6);
    assert_near(s.spheres[2].radius, 6, 1e-5);
    for (uint32_t i = 0; i < 3; ++i) {
        assert_int_equal(s.spheres[i].shape, i);
        assert_int_equal(s.shapes[i].kind, SCENE_SHAPE_SPHERE);
        assert_int_equal(s.shapes[i].first, i);
        assert_int_equal(s.shapes[i].count, 1);
    }
    scene_destroy(&s);
    load_fails(WORLD "Scale 1 2 1\nShape \"sphere\"\n", 3, "non-uniform");
    load_fails(WORLD "Scale 0 0 0\nShape \"sphere\"\n", 3, "singular");
    load_fails(WORLD "Scale 1 0 1\nShape \"sphere\"\n", 3, "singular");
    load_fails(WORLD "Shape \"sphere\" \"float radius\" 0\n", 2, "radius");
    load_fails(WORLD "Shape \"sphere\" \"float zmax\" 0.5\n", 2, "unsupported parameter \"float zmax\"");
    /* The renderer squares distances in single precision. */
    load_fails(WORLD "Shape \"sphere\" \"float radius\" 1e20\n", 2, "reaches beyond 1e+18 from the origin");
    load_fails(WORLD "Translate 0 -2e18 0\nShape \"sphere\"\n", 3, "centre (0, -2e+18, 0)");
    assert_int_equal(load_text("ellipsoid.pbrt", WORLD "Scale 1 2 1\nShape \"sphere\"\n", &s, 1), 0);
    assert_true(has_warning(&s, "non-uniform"));
    assert_near(s.spheres[0].radius, cbrt(2.0), 1e-6);
    scene_destroy(&s);
}

static void test_trianglemesh_normals_and_uv(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "AttributeBegin\n  Scale 2 1 1\n"
                  "  Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n" /* indices optional for 3 */
                  "    \"normal N\" [ 1 1 0  0 0 1  0 0 2 ] \"point2 uv\" [ 0 0 1 0 0 1 ]\n"
                  "AttributeEnd\n" TRIANGLE "ReverseOrientation\n"
                  "Shape \"trianglemesh\" \"point P\" [ 0 0 0  1 0 0  0 1 0 ] \"normal3 N\" [ 0 0 1 0 0 1 0 0 1 ]\n",
            &s);
    assert_int_equal(s.shape_count, 3);
    assert_non_null(s.normals);
    /* The inverse transpose of diag(2, 1, 1) turns (1, 1, 0) into (0.5, 1, 0). */
    double n = sqrt(1.25);
    assert_vec3(s.normals + 0, 0.5 / n, 1 / n, 0);
    assert_vec3(s.normals + 3, 0, 0, 1);
    assert_vec3(s.normals + 6, 0, 0, 1);   /* normalized */
    assert_vec3(s.normals + 9, 0, 0, 0);   /* the second mesh has none */
    assert_vec3(s.normals + 18, 0, 0, -1); /* ReverseOrientation flips normals, as pbrt-v4 does */
    assert_vec3(vertex(&s, 0, 1), 2, 0, 0);
    scene_destroy(&s);
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"normal N\" [ 0 0 1 ]\n", 2,
               "normals for 3 vertices");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 1 ]\n", 2, "indices");
    load_fails(WORLD "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ]\n", 2, "point3 P");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ ]\n", 2,
               "no triangles");
    load_fails(WORLD "Shape \"curve\"\n", 2, "Shape \"curve\" is not supported");
}

static void test_bad_mesh_data(void **state)
{
    (void)state;
    load_fails(WORLD "Shape \"trianglemesh\"\n  \"point3 P\" [ 0 0 0  1 0 0  nan 1 0 ] \"integer indices\" [ 0 1 2 ]\n",
               3, "finite number");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  inf 1 0 ] \"integer indices\" [ 0 1 2 ]\n", 2,
               "finite number");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  1e39 1 0 ] \"integer indices\" [ 0 1 2 ]\n",
               2, "too large");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1 3 ]\n", 2,
               "out of range");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1 -1 ]\n", 2,
               "negative");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1 2 0 ]\n", 2,
               "not a multiple of 3");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1.5 2 ]\n", 2,
               "integer");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 ] \"integer indices\" [ 0 1 2 ]\n", 2,
               "multiple of 3");
}

/* World-space geometry beyond what single-precision intersection handles. */
static void test_geometry_range(void **state)
{
    (void)state;
    load_fails(WORLD "Translate 2e18 0 0\n" TRIANGLE, 3, "vertex 0 is at (2e+18, 0, 0) in world space, beyond 1e+18");
    load_fails(WORLD "Scale 1e10 1e10 1e10\n" TRIANGLE, 3,
               "triangle 0 is too large for single precision: its edges from its first vertex are 1.41421e+10 and "
               "1.41421e+10 long, a product over 1e+19");
    /* A large triangle within the limit loads. */
    Scene s;
    load_ok(WORLD "Scale 2e9 2e9 2e9\n" TRIANGLE, &s);
    assert_int_equal(s.triangle_count, 1);
    scene_destroy(&s);
}

/* Geometry far from the origin for its size: a warning with the reason. */
static void test_precision_warnings(void **state)
{
    (void)state;
    Scene s;
    /* At 1e10 floats are 1024 apart: a unit triangle rounds to a point. */
    assert_int_equal(load_text("far.pbrt", WORLD "Translate 1e10 1e10 1e10\n" TRIANGLE, &s, 0), 0);
    assert_int_equal(s.triangle_count, 0);
    assert_int_equal(s.warning_count, 1);
    assert_non_null(strstr(s.warnings[0], "skipped 1 degenerate (zero-area) triangle of 1; 1 of them lost their "
                                          "area to single-precision rounding in world space (at coordinates up to "
                                          "1e+10 floats are 1024 apart)"));
    scene_destroy(&s);
    /* A scene of size 1e6 at 1e10: kept, but ray offsets of 1e5 are 10%
     * of its size. */
    assert_int_equal(load_text("offset.pbrt", WORLD "Translate 1e10 1e10 1e10\nScale 1e6 1e6 1e6\n" TRIANGLE, &s, 0),
                     0);
    assert_int_equal(s.triangle_count, 1);
    assert_int_equal(s.warning_count, 1);
    char location[600];
    snprintf(location, sizeof location,
             "%s: warning: the geometry lies up to 1.0001e+10 from the origin but spans only 1.00",
             temp_path("offset.pbrt"));
    if (strncmp(s.warnings[0], location, strlen(location)) != 0)
        fail_msg("warning \"%s\" does not start with \"%s\"", s.warnings[0], location);
    assert_non_null(strstr(s.warnings[0], "offset by 1e-5 of their distance from the origin (up to 100010,"));
    scene_destroy(&s);
    /* 1e3 times its size from the origin is still fine (offsets of 1%). */
    load_ok(WORLD "Translate 500 0 0\n" TRIANGLE, &s);
    scene_destroy(&s);
}

static void test_degenerate_triangles_are_skipped(void **state)
{
    (void)state;
    Scene s;
    const char *text =
        WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  2 0 0 ]\n"
              "  \"integer indices\" [ 0 1 2   0 0 1   0 1 3   2 1 0 ]\n" /* repeated, collinear */
              "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 1 1  2 2 2 ] \"integer indices\" [ 0 1 2 ]\n"
              "Scale 1 0 0\n" TRIANGLE; /* flattened to a line */
    assert_int_equal(load_text("degenerate.pbrt", text, &s, 0), 0);
    assert_int_equal(s.triangle_count, 2);
    assert_int_equal(s.shape_count, 1); /* shapes with nothing left are dropped */
    assert_int_equal(s.shapes[0].count, 2);
    assert_int_equal(s.warning_count, 3);
    char location[600];
    snprintf(location, sizeof location, "%s:2: warning: ", temp_path("degenerate.pbrt"));
    assert_true(strncmp(s.warnings[0], location, strlen(location)) == 0);
    assert_non_null(strstr(s.warnings[0], "skipped 2 degenerate (zero-area) triangles of 4"));
    assert_non_null(strstr(s.warnings[1], "skipped 1 degenerate (zero-area) triangle of 1"));
    /* A singular transform, not rounding, flattens the last one. */
    assert_null(strstr(s.warnings[2], "rounding"));
    assert_vec3(vertex(&s, 1, 0), 0, 1, 0); /* the kept "2 1 0" */
    scene_destroy(&s);
}

/* ---------------------------------------------------- parameter syntax */

static void test_parameter_syntax(void **state)
{
    (void)state;
    Scene s;
    load_ok("# a comment line\n"
            "Film \"rgb\" \"integer xresolution\" 10 # trailing comment\n"
            "  \"integer yresolution\" [ 20 ] \"string filename\" \"a \\\"quoted\\\" name.exr\"\n"
            "Camera \"perspective\" \"float fov\" [45]\n" WORLD
            "AreaLightSource \"diffuse\" \"color L\" [1 1 1] \"bool twosided\" [ true ]\n"
            "Shape \"sphere\" \"float radius\" 2\n"
            "AreaLightSource \"diffuse\" \"bool twosided\" \"false\"\n"
            "Shape \"sphere\" \"float radius\" 1e-1\n"
            "Shape\"sphere\"\"float radius\"[3]\n", /* no spaces needed around strings and brackets */
            &s);
    assert_int_equal(s.width, 10);
    assert_int_equal(s.height, 20);
    assert_string_equal(s.film_filename, "a \"quoted\" name.exr");
    assert_near(s.camera.fov, 45, 0);
    assert_int_equal(s.area_lights[0].two_sided, 1);
    assert_int_equal(s.area_lights[1].two_sided, 0);
    assert_near(s.spheres[0].radius, 2, 0);
    assert_near(s.spheres[1].radius, 0.1, 1e-7);
    assert_near(s.spheres[2].radius, 3, 0);
    scene_destroy(&s);
}

static void test_wrong_parameters(void **state)
{
    (void)state;
    load_fails("Camera \"perspective\" \"float fov\" [ \"x\" ]\n" WORLD, 1,
               "\"float fov\": expected a finite number, got \"x\"");
    load_fails(WORLD "\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 ]\n", 3, "\"rgb L\": expected a multiple of 3");
    load_fails("Camera \"perspective\" \"integer fov\" 45\n" WORLD, 1, "wrong type, expected \"float fov\"");
    load_fails("Camera \"perspective\" \"float fov\" [ 45 50 ]\n" WORLD, 1, "expected 1 value, got 2");
    load_fails("Camera \"perspective\" \"floot fov\" 45\n" WORLD, 1, "unknown parameter type \"floot\"");
    load_fails("Camera \"perspective\" \"fov\" 45\n" WORLD, 1, "malformed parameter");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"bool twosided\" 1\n", 2, "true or false");
    load_fails("Film \"rgb\" \"string filename\" out.exr\n" WORLD, 1, "quoted string");
    load_fails("Camera \"perspective\" \"float fov\" 190\n" WORLD, 1, "fov");
    load_fails("Camera \"perspective\" \"float screenwindow\" [ -1 1 -1 ]\n" WORLD, 1,
               "\"float screenwindow\": expected 4 values (x_min x_max y_min y_max), got 3");
    load_fails("Camera perspective\n" WORLD, 1, "quoted string");
    load_fails("LookAt 0 0 0  0 0 1  0 0 1\n" WORLD, 1, "parallel");
    load_fails("LookAt 0 0 0  0 0 0  0 1 0\n" WORLD, 1, "same");
    load_fails("Translate 1 2\n" WORLD, 2, "expected 3 numbers");
    load_fails("Rotate 10 0 0 0\n" WORLD, 1, "axis");
    load_fails("Transform [ 1 0 0 0 ]\n" WORLD, 1, "expected 16 numbers");
    load_fails("Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1 ]\n" WORLD, 1, "expected ']'");
}

static void test_truncated_and_malformed_files(void **state)
{
    (void)state;
    load_fails(WORLD "Shape \"sphere\" \"float radius\" [ 1", 2, "unterminated '['");
    load_fails(WORLD "Shape \"sphere\" \"float radius\" [ 1\nShape \"sphere\"\n", 2, "unterminated '['");
    load_fails("Film \"rgb\" \"string filename\" \"abc\n" WORLD, 1, "unterminated string");
    load_fails("Film \"rgb\" \"string filename\" \"abc", 1, "unterminated string");
    load_fails(WORLD "Shape", 2, "expected the shape type as a quoted string, got end of file");
    load_fails(WORLD "Shape \"sphere\" \"float radius\"", 2, "expected a value or '[', got end of file");
    load_fails("LookAt 0 0 0  0 0 1", 1, "expected 9 numbers, got end of file");
    load_fails("Camera \"perspective\"\n\n", 3, "end of file before WorldBegin");
    load_fails("WorldBegin\nWorldBegin\n", 2, "twice");
    load_fails(WORLD "Frobnicate 1 2\n", 2, "unknown directive 'Frobnicate'");
    load_fails(WORLD "\"sphere\"\n", 2, "expected a directive");
    load_fails(WORLD "]\n", 2, "expected a directive");
    load_fails(WORLD "Shape \"sphere\" \"float radius\" [ [ 1 ] ]\n", 2, "inside a list");
    load_fails("Film \"rgb\" \"string filename\" \"bad \\q escape\"\n" WORLD, 1, "escape");
    load_fails(WORLD "Texture \"t\" \"spectrum\" \"ptex\"\n", 2, "texture class \"ptex\" is not supported");
    load_fails(WORLD "ObjectBegin \"o\"\n", 2, "without a matching end");
    load_fails(WORLD "Shape \"sphere\" \"float radius\" [ 1 ] ]\n", 2, "expected a directive, got ']'");
}

/* ObjectBegin / ObjectEnd / ObjectInstance: the object's shapes keep the
 * CTM inside the definition, each instance the CTM at its directive; an
 * instance may come before its object, as in pbrt-v4. */
static void test_object_instances(void **state)
{
    (void)state;
    Scene s;
    const char *text = WORLD "ObjectInstance \"late\"\n"
                             "ObjectBegin \"thing\"\n  Translate 0 0 2\n  " TRIANGLE
                             "  Shape \"sphere\" \"float radius\" 0.5\nObjectEnd\n" TRIANGLE
                             "AttributeBegin\n  Translate 5 0 0\n  ObjectInstance \"thing\"\nAttributeEnd\n"
                             "Scale 2 2 2\nObjectInstance \"thing\"\n"
                             "ObjectBegin \"late\"\nObjectEnd\n";
    assert_int_equal(load_text("instances.pbrt", text, &s, 0), 0);
    assert_int_equal(s.object_count, 2);
    assert_string_equal(s.objects[0].name, "thing");
    assert_int_equal(s.objects[0].first_shape, 0);
    assert_int_equal(s.objects[0].shape_count, 2);
    assert_int_equal(s.objects[1].shape_count, 0);
    assert_int_equal(s.shape_count, 3);
    assert_int_equal(s.shapes[0].object, 0);
    assert_int_equal(s.shapes[1].object, 0);
    assert_int_equal(s.shapes[2].object, -1);
    assert_float_equal(s.spheres[0].center[2], 2.0f, 0.0f); /* the CTM inside the definition */
    assert_int_equal(s.instance_count, 3);
    assert_int_equal(s.instances[0].object, 1);
    assert_int_equal(s.instances[1].object, 0);
    assert_float_equal(s.instances[1].world_from_object[3][0], 5.0f, 0.0f); /* column 3: the translation */
    assert_float_equal(s.instances[2].world_from_object[0][0], 2.0f, 0.0f);
    assert_float_equal(s.instances[2].world_from_object[3][0], 0.0f, 0.0f); /* outside the AttributeBegin */
    scene_destroy(&s);
}

static void test_object_instance_errors(void **state)
{
    (void)state;
    load_fails(WORLD "ObjectInstance \"nothing\"\n", 2, "no object \"nothing\" is defined");
    load_fails(WORLD "ObjectEnd\n", 2, "ObjectEnd without a matching ObjectBegin");
    load_fails(WORLD "ObjectBegin \"a\"\nObjectBegin \"b\"\n", 3, "inside the ObjectBegin at");
    load_fails(WORLD "ObjectBegin \"a\"\nObjectEnd\nObjectBegin \"b\"\nObjectInstance \"a\"\n", 5,
               "ObjectInstance inside the ObjectBegin");
    load_fails(WORLD "ObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\"\nObjectEnd\n", 4, "defined already");
    load_fails(WORLD "ObjectBegin \"a\"\nAttributeEnd\n", 3, "closes the ObjectBegin");
    load_fails(WORLD "AttributeBegin\nObjectBegin \"a\"\nAttributeEnd\n", 4, "closes the ObjectBegin");
    load_fails("ObjectBegin \"a\"\n", 1, "WorldBegin");
}

/* An instance's transform is refused at its ObjectInstance, as a shape's
 * is at its Shape, where the renderer's single precision cannot take it:
 * the kernels intersect the object with the ray in object space (a scale
 * past 1e18 either way overflows or underflows the ray's squares there;
 * a singular one has no object space), and the world-space box must stay
 * within SCENE_MAX_COORDINATE. The shapes inside ObjectBegin meet the
 * limits of any shape under their own CTM. */
static void test_instance_transform_errors(void **state)
{
    (void)state;
#define OBJECT "ObjectBegin \"a\"\n" TRIANGLE "ObjectEnd\n"
    load_fails(WORLD OBJECT "Scale 1e30 1e30 1e30\nObjectInstance \"a\"\n", 6,
               "ObjectInstance \"a\": the transform scales lengths by 1e+30, outside [1e-18, 1e+18]");
    load_fails(WORLD OBJECT "Scale 1e-20 1e-20 1e-20\nObjectInstance \"a\"\n", 6,
               "ObjectInstance \"a\": the transform scales lengths by 1e-20");
    load_fails(WORLD OBJECT "Scale 1 1e-25 1\nObjectInstance \"a\"\n", 6, "scales lengths by 1e-25");
    load_fails(WORLD OBJECT "Scale 0 0 0\nObjectInstance \"a\"\n", 6,
               "ObjectInstance \"a\": the transform is singular");
    load_fails(WORLD OBJECT "Scale 1 1 0\nObjectInstance \"a\"\n", 6, "singular");
    load_fails(WORLD OBJECT "ConcatTransform [ 1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1 ]\nObjectInstance \"a\"\n", 6,
               "ObjectInstance \"a\": a projective transform is not supported");
    load_fails(WORLD OBJECT "Translate 2e18 0 0\nObjectInstance \"a\"\n", 6,
               "ObjectInstance \"a\": the instance reaches (2e+18, 0, 0) in world space, beyond 1e+18");
    load_fails(WORLD OBJECT "Translate 0 0 9.5e17\nScale 1e17 1e17 1e17\nObjectInstance \"a\"\n", 7,
               "reaches (0, 0, 1.05e+18)");
    /* Before its object's definition: the ObjectInstance's line. */
    load_fails(WORLD "Scale 1e30 1e30 1e30\nObjectInstance \"a\"\nIdentity\n" OBJECT, 3, "scales lengths by 1e+30");
    /* Inside ObjectBegin, the shape's own checks. */
    load_fails(WORLD "ObjectBegin \"a\"\nScale 1e30 1e30 1e30\n" TRIANGLE "ObjectEnd\n", 4,
               "beyond 1e+18 from the origin");
    load_fails(WORLD "ObjectBegin \"a\"\nScale 0 0 0\nShape \"sphere\"\nObjectEnd\n", 4, "Shape \"sphere\"");
    load_fails(WORLD "ObjectBegin \"a\"\nConcatTransform [ 1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1 ]\nShape \"sphere\"\n",
               4, "projective transform is not supported");
#undef OBJECT
    /* At the limits, and an empty object anywhere: accepted. */
    Scene s;
    assert_int_equal(load_text("limits.pbrt",
                               WORLD
                               "ObjectBegin \"a\"\n" TRIANGLE "ObjectEnd\nObjectBegin \"none\"\nObjectEnd\n"
                               "AttributeBegin\nScale 1e17 1e17 1e17\nTranslate -0.5 -0.5 -0.5\nObjectInstance \"a\"\n"
                               "AttributeEnd\nScale 1e-18 1e-18 1e-18\nObjectInstance \"a\"\n"
                               "Translate 1e30 0 0\nObjectInstance \"none\"\n",
                               &s, 0),
                     0);
    assert_int_equal(s.instance_count, 3);
    scene_destroy(&s);
}

/* pbrt-v4 ignores area lights in object instances, with a warning. */
static void test_area_light_in_object_is_ignored(void **state)
{
    (void)state;
    Scene s;
    const char *text = WORLD "ObjectBegin \"lamp\"\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n  " TRIANGLE
                             "ObjectEnd\nObjectInstance \"lamp\"\n";
    assert_int_equal(load_text("lamp.pbrt", text, &s, 0), 0);
    assert_int_equal(s.area_light_count, 0);
    assert_int_equal(s.shapes[0].area_light, -1);
    assert_true(has_warning(&s, "area light inside ObjectBegin is ignored"));
    scene_destroy(&s);
}

/* "float alpha" on shapes, and "texture alpha" naming a float texture. */
static void test_shape_alpha(void **state)
{
    (void)state;
    Scene s;
    const char *text = WORLD TRIANGLE "Shape \"sphere\" \"float alpha\" 0.25\n";
    assert_int_equal(load_text("alpha.pbrt", text, &s, 0), 0);
    assert_float_equal(s.shapes[0].alpha, 1.0f, 0.0f);
    assert_float_equal(s.shapes[1].alpha, 0.25f, 0.0f);
    assert_int_equal(s.shapes[1].alpha_texture, -1);
    scene_destroy(&s);
    text = WORLD "Texture \"leaves\" \"float\" \"constant\"\nShape \"sphere\" \"texture alpha\" \"leaves\"\n";
    assert_int_equal(load_text("alpha.pbrt", text, &s, 0), 0);
    assert_int_equal(s.shapes[0].alpha_texture, 0);
    assert_float_equal(s.shapes[0].alpha, 1.0f, 0.0f);
    scene_destroy(&s);
    load_fails(WORLD "Shape \"sphere\" \"texture alpha\" \"leaves\"\n", 2, "no float texture named \"leaves\"");
    load_fails(WORLD "Texture \"leaves\" \"spectrum\" \"constant\"\nShape \"sphere\" \"texture alpha\" \"leaves\"\n", 3,
               "\"leaves\" is a spectrum texture");
    load_fails(WORLD "Shape \"sphere\" \"float alpha\" [ 1 2 ]\n", 2, "alpha");
}

static void test_allow_unsupported_substitutes(void **state)
{
    (void)state;
    Scene s;
    const char *text =
        WORLD "Texture \"checks\" \"spectrum\" \"ptex\" \"float uscale\" [ 4 ] \"rgb tex1\" [ 1 0 0 ]\n"
              "Material \"hair\" \"float eumelanin\" 1\n" TRIANGLE                 /* grey diffuse */
              "Material \"diffuse\" \"texture reflectance\" \"checks\"\n" TRIANGLE /* a constant texture */
              "Shape \"curve\" \"float width\" 1\n"                                /* skipped */
              "LightSource \"sun\" \"rgb I\" [ 1 1 1 ]\n"                          /* skipped */
              "AreaLightSource \"goniometric\"\n" TRIANGLE                         /* does not emit */
              "Shape \"sphere\" \"float phimax\" 180\n";                           /* full sphere */
    assert_int_equal(load_text("allow.pbrt", text, &s, 1), 0);
    assert_int_equal(s.shape_count, 4);
    assert_int_equal(s.triangle_count, 3);
    assert_int_equal(s.sphere_count, 1);
    assert_int_equal(s.area_light_count, 0);
    assert_int_equal(s.light_count, 0);
    assert_int_equal(material_of_shape(&s, 0)->type, SCENE_MATERIAL_DIFFUSE);
    assert_vec3(material_of_shape(&s, 0)->reflectance, 0.5, 0.5, 0.5);
    assert_vec3(material_of_shape(&s, 1)->reflectance, 0.5, 0.5, 0.5);
    assert_int_equal(material_of_shape(&s, 1)->textures[SCENE_SLOT_REFLECTANCE], 0);
    assert_int_equal(s.textures[0].texture_class, SCENE_TEXTURE_CONSTANT);
    assert_true(has_warning(&s, "texture class \"ptex\" is not supported (constant, scale, mix, directionmix, "
                                "checkerboard, bilerp, imagemap, dots, fbm, wrinkled, windy, marble); a constant 0.5 "
                                "is used instead"));
    assert_true(has_warning(&s, "Material \"hair\" is not supported"));
    assert_true(has_warning(&s, "Shape \"curve\" is not supported"));
    assert_true(has_warning(&s, "LightSource \"sun\""));
    assert_true(has_warning(&s, "goniometric"));
    assert_true(has_warning(&s, "phimax"));
    for (size_t i = 0; i < s.warning_count; ++i)
        assert_true(strncmp(s.warnings[i], temp_path("allow.pbrt"), strlen(temp_path("allow.pbrt"))) == 0);
    scene_destroy(&s);
}

/* ---------------------------------------------------------------- media */

#define FOG "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" "

/* MakeNamedMedium's types and parameters, MediumInterface on the shapes
 * and at the Camera, names bound at the end. */
static void test_media(void **state)
{
    (void)state;
    Scene s;
    load_ok(FOG "\"rgb sigma_a\" [ 0.5 0.25 1 ] \"rgb sigma_s\" [ 2 0 1 ] \"float scale\" 2 \"float g\" 0.5 "
                "\"rgb Le\" [ 1 2 3 ] \"float Lescale\" 0.5\n"
                "MediumInterface \"\" \"fog\"\nCamera \"perspective\"\n" WORLD
                "AttributeBegin\nMediumInterface \"glass\" \"fog\"\n" TRIANGLE "AttributeEnd\n"
                "MediumInterface \"fog\"\n" TRIANGLE
                "MakeNamedMedium \"glass\" \"string type\" \"homogeneous\" \"string preset\" \"Skin1\"\n"
                "MakeNamedMedium \"plain\" \"string type\" \"homogeneous\"\n",
            &s);
    assert_int_equal(s.medium_count, 3);
    const SceneMedium *fog = &s.media[0], *glass = &s.media[1], *plain = &s.media[2];
    assert_string_equal(fog->name, "fog");
    assert_int_equal(fog->type, SCENE_MEDIUM_HOMOGENEOUS);
    assert_vec3(fog->sigma_a, 1, 0.5, 2); /* times scale */
    assert_vec3(fog->sigma_s, 4, 0, 2);
    assert_vec3(fog->emission, 0.5, 1, 1.5); /* an rgb Le as given, times Lescale */
    assert_near(fog->g, 0.5, 0);
    assert_string_equal(glass->name, "glass"); /* named before its definition */
    assert_vec3(glass->sigma_s, 0.74, 0.88, 1.01);
    assert_vec3(glass->sigma_a, 0.032, 0.17, 0.48);
    assert_vec3(plain->sigma_a, 1, 1, 1); /* pbrt-v4's defaults */
    assert_vec3(plain->sigma_s, 1, 1, 1);
    assert_vec3(plain->emission, 0, 0, 0);
    assert_near(plain->g, 0, 0);
    assert_int_equal(s.camera_medium, 0); /* the outside medium at Camera */
    assert_int_equal(s.shape_count, 2);
    assert_int_equal(s.shapes[0].medium_inside, 1);
    assert_int_equal(s.shapes[0].medium_outside, 0);
    /* WorldBegin keeps the interface ("" "fog"); one name sets both sides. */
    assert_int_equal(s.shapes[1].medium_inside, 0);
    assert_int_equal(s.shapes[1].medium_outside, 0);
    assert_int_equal(s.integrator_media, 1);
    scene_destroy(&s);

    /* pbrt-v4's path integrator ignores media: a note says so. */
    load_ok("Integrator \"path\"\n" FOG "\nMediumInterface \"\" \"fog\"\nCamera \"perspective\"\n" WORLD, &s);
    assert_int_equal(s.integrator_media, 0);
    assert_int_equal(s.note_count, 1);
    assert_non_null(strstr(s.notes[0], "the integrator ignores the scene's participating media"));
    scene_destroy(&s);

    /* An unknown preset: pbrt-v4 warns and takes sigma_a, sigma_s. */
    assert_int_equal(load_text("preset.pbrt", FOG "\"string preset\" \"Fog\" \"rgb sigma_a\" [ 2 2 2 ]\n" WORLD, &s, 0),
                     0);
    assert_true(has_warning(&s, "preset \"Fog\" is not one of pbrt-v4's"));
    assert_vec3(s.media[0].sigma_a, 2, 2, 2);
    scene_destroy(&s);

    /* Grids: their values, box and transform kept. */
    load_ok("Translate 1 2 3\nMakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" "
            "[ 0.5 1 ] \"float Lescale\" [ 1 2 ] \"rgb Le\" [ 1 1 1 ] \"point3 p0\" [ -1 0 0 ] \"point3 p1\" [ 1 2 4 ] "
            "\"rgb sigma_a\" [ 1 2 3 ] \"float scale\" 2\n"
            "MakeNamedMedium \"n\" \"string type\" \"uniformgrid\" \"float density\" [ 3 ]\n"
            "MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"integer ny\" 2 \"rgb sigma_s\" [ 1 1 1 2 2 2 ] "
            "\"float Lescale\" 3 \"float scale\" 0.5\n" WORLD,
            &s);
    const SceneMedium *grid = &s.media[0];
    assert_int_equal(grid->type, SCENE_MEDIUM_UNIFORM_GRID);
    assert_int_equal(grid->rendered, 1);
    assert_int_equal(grid->size[0], 2);
    assert_int_equal(grid->size[1] * grid->size[2], 1);
    assert_near(grid->density[0], 0.5, 0);
    assert_near(grid->density[1], 1, 0);
    assert_near(grid->le_scale[1], 2, 0);
    assert_int_equal(grid->le_size[0], 2);
    assert_vec3(grid->sigma_a, 2, 4, 6);
    assert_vec3(grid->sigma_s, 2, 2, 2);
    assert_vec3(grid->emission, 1, 1, 1);
    assert_vec3(grid->bounds[0], -1, 0, 0);
    assert_vec3(grid->bounds[1], 1, 2, 4);
    assert_vec3(grid->world_from_medium[3], 1, 2, 3); /* the CTM's translation */
    assert_int_equal(s.media[1].le_size[0] * s.media[1].le_size[1] * s.media[1].le_size[2], 1); /* Lescale: 1 */
    assert_near(s.media[1].le_scale[0], 1, 0);
    assert_vec3(s.media[1].bounds[1], 1, 1, 1);
    const SceneMedium *rgb = &s.media[2];
    assert_int_equal(rgb->type, SCENE_MEDIUM_RGB_GRID);
    assert_null(rgb->rgb_sigma_a);
    assert_near(rgb->rgb_sigma_s[3], 2, 0);
    assert_vec3(rgb->sigma_s, 0.5, 0.5, 0.5);
    assert_vec3(rgb->emission, 3, 3, 3);
    scene_destroy(&s);
    load_ok("MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float density\" 2 \"float wispiness\" 0.5 \"float "
            "frequency\" 4 "
            "\"point3 p1\" [ 2 1 1 ]\nMakeNamedMedium \"d\" \"string type\" \"cloud\"\n" WORLD,
            &s);
    assert_int_equal(s.media[0].type, SCENE_MEDIUM_CLOUD);
    assert_int_equal(s.media[0].rendered, 1);
    assert_vec3(s.media[0].cloud, 2, 0.5, 4);
    assert_vec3(s.media[0].bounds[1], 2, 1, 1);
    assert_vec3(s.media[1].cloud, 1, 1, 5); /* pbrt-v4's defaults */
    scene_destroy(&s);

    /* A temperature grid: the rgbgrid of its cells' blackbody emission
     * (T = (t - offset) * scale, none at 100 K or below) times "Lescale",
     * sigma_a and sigma_s per cell times the density. */
    load_ok("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nz\" 3 \"float density\" [ 0.5 1 2 ] "
            "\"float temperature\" [ 900 1000 140 ] \"float temperaturescale\" 2 \"float temperatureoffset\" 100 "
            "\"float Lescale\" [ 1 3 1 ] \"rgb sigma_a\" [ 1 2 3 ]\n" WORLD,
            &s);
    grid = &s.media[0];
    assert_int_equal(grid->type, SCENE_MEDIUM_RGB_GRID);
    assert_int_equal(grid->rendered, 1);
    assert_vec3(grid->sigma_a, 1, 1, 1);
    assert_vec3(grid->emission, 1, 1, 1);
    assert_vec3(grid->rgb_sigma_a, 0.5, 1, 1.5);
    assert_vec3(grid->rgb_sigma_s + 6, 2, 2, 2);
    {
        static const double kelvin[2] = {1600.0, 1800.0}, cell_scale[2] = {1.0, 3.0};
        double srgb_from_xyz[3][3];
        spectrum_srgb_from_xyz(srgb_from_xyz);
        for (int i = 0; i < 2; ++i) {
            Spectrum b;
            double xyz[3];
            spectrum_blackbody(kelvin[i], &b);
            spectrum_to_xyz(&b, xyz);
            for (int k = 0; k < 3; ++k) {
                double rgb = srgb_from_xyz[k][0] * xyz[0] + srgb_from_xyz[k][1] * xyz[1] + srgb_from_xyz[k][2] * xyz[2];
                assert_float_equal(grid->rgb_le[3 * i + k], fmax(0.0, rgb) * cell_scale[i], 1e-6 + 1e-5 * fabs(rgb));
            }
        }
        assert_true(grid->rgb_le[0] > grid->rgb_le[2]); /* red hot */
        assert_vec3(grid->rgb_le + 6, 0, 0, 0);         /* 80 K: none */
    }
    scene_destroy(&s);
    load_ok("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" 1 \"float temperature\" 900 "
            "\"float temperaturecutoff\" 850\n" WORLD,
            &s); /* the offset defaults to the cutoff: 50 K, no emission */
    assert_vec3(s.media[0].rgb_le, 0, 0, 0);
    scene_destroy(&s);

    /* Bad input: file:line errors. */
    load_fails("MakeNamedMedium \"m\" \"string type\" \"fog\"\n" WORLD, 1, "unknown type \"fog\"");
    load_fails("MakeNamedMedium \"m\" \"float scale\" 1\n" WORLD, 1, "missing \"string type\"");
    load_fails(WORLD "\n" FOG "\"rgb sigma_a\" [ -1 0 0 ]\n", 3, "negative");
    load_fails(FOG "\"spectrum sigma_s\" [ 400 -1 700 1 ]\n" WORLD, 1, "negative");
    load_fails(FOG "\"float scale\" -1\n" WORLD, 1, "\"scale\" -1 must lie in");
    load_fails(FOG "\"float Lescale\" -1\n" WORLD, 1, "\"Lescale\" -1 must lie in");
    load_fails(FOG "\"float g\" 1\n" WORLD, 1, "\"g\" 1 must lie in");
    load_fails(FOG "\"float density\" 1\n" WORLD, 1, "density");
    load_fails(FOG "\n" FOG "\n" WORLD, 2, "\"fog\" is defined twice");
    load_fails("MakeNamedMedium \"\" \"string type\" \"homogeneous\"\n" WORLD, 1, "must not be empty");
    load_fails(WORLD "\nMediumInterface \"nope\"\n" TRIANGLE, 3, "medium \"nope\" is not defined");
    load_fails("MediumInterface \"\" \"nope\"\nCamera \"perspective\"\n" WORLD, 1, "medium \"nope\" is not defined");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [ 1 ]\n" WORLD,
               1, "1 values for a grid of 2 (nx * ny * nz)");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 0 \"float density\" [ 1 ]\n" WORLD,
               1, "\"nx\" must be at least 1");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ -1 ]\n" WORLD, 1,
               "is negative");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\"\n" WORLD, 1, "\"density\" values are required");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ] \"float temperature\" "
               "[ 1 ] \"rgb Le\" [ 1 1 1 ]\n" WORLD,
               1, "both \"Le\" and \"temperature\"");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer ny\" 2 \"float density\" [ 1 1 ] "
               "\"float Lescale\" [ 1 ]\n" WORLD,
               1, "1 values for a grid of 2");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_s\" [ 1 1 1 ]\n" WORLD,
               1, "1 values for a grid of 2");
    load_fails(
        "MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb Le\" [ 1 1 1 ] \"rgb sigma_s\" [ 1 1 1 ]\n" WORLD, 1,
        "\"Le\" needs \"sigma_a\"");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\"\n" WORLD, 1, "\"sigma_a\" or \"sigma_s\" values");
    load_fails(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ] \"point3 p1\" [ 1 0 1 ]\n" WORLD,
        1, "\"p1\" must exceed \"p0\"");
    load_fails("Scale 1 0 1\nMakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ]\n" WORLD, 2,
               "the transform is singular");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"nanovdb\"\n" WORLD, 1, "\"filename\" is required");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"none.nvdb\"\n" WORLD, 1,
               "cannot open");
    write_text("corrupt.nvdb", "not a grid at all");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"corrupt.nvdb\"\n" WORLD, 1,
               "not a NanoVDB file (no magic number)");
    write_text("short.nvdb", "Nano");
    load_fails("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"short.nvdb\"\n" WORLD, 1,
               "truncated segment header");
}

static unsigned char *read_whole(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    rewind(f);
    unsigned char *data = malloc(*size);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, *size, f), *size);
    fclose(f);
    return data;
}

#define NANOVDB_MEDIUM "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" "

/* The NanoVDB files written by NanoVDB's own builder (tests/support/
 * write_nvdb.cpp): read with pbrt-v4's parameters, the three codecs
 * alike, lookups equal to NanoVDB's trilinear sampler, bad files refused. */
static void test_nanovdb(void **state)
{
    (void)state;
    Scene s;
    char text[1024];
    snprintf(text, sizeof text,
             "Translate 1 0 0\n" NANOVDB_MEDIUM "\"%s/box.nvdb\" \"float Lescale\" 2 \"float temperaturecutoff\" 100 "
             "\"float temperaturescale\" 1.5 \"rgb sigma_a\" [ 1 2 3 ] \"float scale\" 2 \"float g\" 0.5\n" WORLD,
             GMON_NVDB_DIR);
    assert_int_equal(load_text("nanovdb.pbrt", text, &s, 0), 0);
    assert_int_equal(s.medium_count, 1);
    const SceneMedium *m = &s.media[0];
    assert_int_equal(m->type, SCENE_MEDIUM_NANOVDB);
    assert_int_equal(m->rendered, 1);
    for (int k = 0; k < 3; ++k) {
        assert_float_equal(m->bounds[0][k], -0.5f, 1e-6f);
        assert_float_equal(m->bounds[1][k], 0.5f, 1e-6f);
        assert_float_equal(m->sigma_a[k], 2.0f * (float)(k + 1), 0.0f);
        assert_float_equal(m->sigma_s[k], 2.0f, 0.0f);
        assert_float_equal(m->emission[k], 2.0f, 0.0f);
    }
    assert_float_equal(m->world_from_medium[3][0], 1.0f, 0.0f);
    assert_float_equal(m->g, 0.5f, 0.0f);
    assert_float_equal(m->temperature_offset, 100.0f, 0.0f); /* the cutoff's */
    assert_float_equal(m->temperature_scale, 1.5f, 0.0f);
    assert_non_null(m->nanovdb_temperature.data);
    assert_float_equal(m->nanovdb_density.largest, 1.0f, 0.0f);
    assert_float_equal(m->nanovdb_temperature.largest, 3000.0f, 0.0f);
    NanoGrid box = m->nanovdb_density;
    static const char *const compressed[] = {"box-zip.nvdb", "box-blosc.nvdb"};
    for (int i = 0; i < 2; ++i) {
        char path[512], error[256];
        NanoGrid same;
        snprintf(path, sizeof path, "%s/%s", GMON_NVDB_DIR, compressed[i]);
        if (nanovdb_read(path, "density", &same, error, sizeof error))
            fail_msg("%s: %s", compressed[i], error);
        assert_int_equal(same.size, box.size);
        assert_memory_equal(same.data, box.data, box.size);
        nanovdb_free(&same);
    }
    scene_destroy(&s);

    /* Lookups: NanoVDB's sampler at 400 points of a grid over leaves and
     * nodes on both sides of 0, against nanovdb_trilinear (the kernels'). */
    char path[512], error[256];
    snprintf(path, sizeof path, "%s/lumpy.nvdb", GMON_NVDB_DIR);
    NanoGrid lumpy;
    if (nanovdb_read(path, "density", &lumpy, error, sizeof error))
        fail_msg("lumpy.nvdb: %s", error);
    double matrix[9], inverse[9], translation[3];
    nanovdb_map(&lumpy, matrix, inverse, translation);
    snprintf(path, sizeof path, "%s/lumpy-samples.txt", GMON_NVDB_DIR);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    int count = 0, nonzero = 0;
    double world[3], expected;
    while (fscanf(f, "%lf %lf %lf %lf", &world[0], &world[1], &world[2], &expected) == 4) {
        double index[3];
        for (int k = 0; k < 3; ++k)
            index[k] = inverse[3 * k] * (world[0] - translation[0]) + inverse[3 * k + 1] * (world[1] - translation[1]) +
                       inverse[3 * k + 2] * (world[2] - translation[2]);
        float got = nanovdb_trilinear(lumpy.data, vec3((float)index[0], (float)index[1], (float)index[2]));
        if (!(fabs(got - expected) <= 1e-4 * (1.0 + expected)))
            fail_msg("at (%g, %g, %g): %.7g, NanoVDB's sampler %.7g", world[0], world[1], world[2], got, expected);
        ++count;
        nonzero += expected > 0.0;
    }
    fclose(f);
    assert_int_equal(count, 400);
    assert_true(nonzero > 200);
    nanovdb_free(&lumpy);

    /* Bad files: file:line errors. */
    snprintf(text, sizeof text, NANOVDB_MEDIUM "\"%s/box.nvdb\" \"string gridname\" \"smoke\"\n" WORLD, GMON_NVDB_DIR);
    load_fails(text, 1, "has no grid \"smoke\"");
    snprintf(text, sizeof text, NANOVDB_MEDIUM "\"%s/vector.nvdb\"\n" WORLD, GMON_NVDB_DIR);
    load_fails(text, 1, "is not of 32-bit floats");
    snprintf(text, sizeof text, NANOVDB_MEDIUM "\"%s/box.nvdb\" \"float temperaturescale\" -1\n" WORLD, GMON_NVDB_DIR);
    load_fails(text, 1, "\"temperaturescale\" -1 must lie in");
    size_t size;
    snprintf(path, sizeof path, "%s/box.nvdb", GMON_NVDB_DIR);
    unsigned char *bytes = read_whole(path, &size);
    write_bytes("truncated.nvdb", bytes, size / 2);
    load_fails(NANOVDB_MEDIUM "\"truncated.nvdb\"\n" WORLD, 1, "truncated grid data");
    unsigned char *changed = malloc(size);
    assert_non_null(changed);
    memcpy(changed, bytes, size);
    uint32_t version = 31u << 21;
    memcpy(changed + 8, &version, sizeof version);
    write_bytes("old.nvdb", changed, size);
    load_fails(NANOVDB_MEDIUM "\"old.nvdb\"\n" WORLD, 1, "NanoVDB file format 31.0, not 32.x");
    /* The density grid's bytes follow the header and both grids' metadata
     * and names; its root's offset made to point past its end. */
    size_t grid = 16 + (176 + sizeof "density") + (176 + sizeof "temperature");
    uint64_t far = (uint64_t)1 << 40;
    memcpy(changed, bytes, size);
    memcpy(changed + grid + sizeof(cnanovdb_griddata) + 3 * sizeof(uint64_t), &far, sizeof far);
    write_bytes("corrupt-root.nvdb", changed, size);
    load_fails(NANOVDB_MEDIUM "\"corrupt-root.nvdb\"\n" WORLD, 1, "is corrupt (a node outside the grid)");
    free(changed);
    free(bytes);
}

/* ------------------------------------------------------------------ PLY */

static void test_ply_ascii(void **state)
{
    (void)state;
    write_text("mesh/ascii.ply", "ply\r\n"
                                 "format ascii 1.0\n"
                                 "comment made by hand, with words like element and property\n"
                                 "element vertex 5\n"
                                 "property float x\nproperty float y\nproperty double z\n"
                                 "property float nx\nproperty float ny\nproperty float nz\n"
                                 "property float u\n"
                                 "element face 2\n"
                                 "property list uchar int vertex_indices\n"
                                 "property int flags\n"
                                 "element edge 1\n"
                                 "property int vertex1\nproperty int vertex2\n"
                                 "end_header\n"
                                 "0 0 0  0 0 1  0.5\n1 0 0 0 0 1 0\n1 1 0 0 0 1 0\n0 1 0 0 0 1 0\n2 2 2 0 0 1 0\n"
                                 "4 0 1 2 3  7\n"
                                 "3 4 0 1  0\n"
                                 "0 1\n");
    Scene s;
    load_ok(WORLD "Translate 0 0 1\nShape \"plymesh\" \"string filename\" \"mesh/ascii.ply\"\n", &s);
    assert_int_equal(s.vertex_count, 5);
    assert_int_equal(s.triangle_count, 3); /* the quad is two triangles */
    assert_vec3(vertex(&s, 0, 0), 0, 0, 1);
    assert_vec3(vertex(&s, 0, 1), 1, 0, 1);
    assert_vec3(vertex(&s, 0, 2), 1, 1, 1);
    assert_vec3(vertex(&s, 1, 0), 0, 0, 1);
    assert_vec3(vertex(&s, 1, 1), 1, 1, 1);
    assert_vec3(vertex(&s, 1, 2), 0, 1, 1);
    assert_vec3(vertex(&s, 2, 0), 2, 2, 3);
    assert_non_null(s.normals);
    assert_vec3(s.normals + 3 * 4, 0, 0, 1);
    scene_destroy(&s);
}

static size_t put(unsigned char *out, const void *value, size_t size, int big_endian)
{
    const unsigned char *bytes = value;
    uint16_t one = 1;
    int host_little = *(const unsigned char *)&one == 1;
    for (size_t i = 0; i < size; ++i)
        out[i] = (big_endian == host_little) ? bytes[size - 1 - i] : bytes[i];
    return size;
}

/* A binary PLY: a unit quad (as one quad face) plus a triangle, positions
 * as float or double, indices as a `list_type` list of `index_type`. */
static size_t binary_ply(unsigned char *out, int big_endian, int doubles, const char *count_type,
                         const char *index_type, float poison)
{
    int n = sprintf((char *)out,
                    "ply\nformat %s 1.0\nelement vertex 5\nproperty %s x\nproperty %s y\nproperty %s z\n"
                    "property uchar red\nelement face 2\nproperty list %s %s vertex_indices\nend_header\n",
                    big_endian ? "binary_big_endian" : "binary_little_endian", doubles ? "double" : "float",
                    doubles ? "double" : "float", doubles ? "double" : "float", count_type, index_type);
    size_t size = (size_t)n;
    const float p[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, poison}};
    for (int v = 0; v < 5; ++v) {
        for (int k = 0; k < 3; ++k) {
            if (doubles) {
                double d = p[v][k];
                size += put(out + size, &d, 8, big_endian);
            } else {
                size += put(out + size, &p[v][k], 4, big_endian);
            }
        }
        out[size++] = 200; /* red */
    }
    const int faces[2][5] = {{4, 0, 1, 2, 3}, {3, 4, 0, 1, 0}};
    for (int f = 0; f < 2; ++f)
        for (int k = 0; k <= faces[f][0]; ++k) {
            const char *type = k == 0 ? count_type : index_type;
            uint32_t value = (uint32_t)faces[f][k];
            if (strcmp(type, "uchar") == 0) {
                out[size++] = (unsigned char)value;
            } else if (strcmp(type, "ushort") == 0) {
                uint16_t v16 = (uint16_t)value;
                size += put(out + size, &v16, 2, big_endian);
            } else {
                size += put(out + size, &value, 4, big_endian);
            }
        }
    return size;
}

static void test_ply_binary(void **state)
{
    (void)state;
    static const struct {
        int big_endian, doubles;
        const char *count_type, *index_type;
    } cases[] = {
        {0, 0, "uchar", "int"}, {0, 1, "uchar", "uint"},  {1, 0, "uchar", "int"},
        {1, 1, "int", "uint"},  {0, 0, "uint", "ushort"}, {1, 0, "uchar", "uchar"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        unsigned char data[1024];
        size_t size =
            binary_ply(data, cases[c].big_endian, cases[c].doubles, cases[c].count_type, cases[c].index_type, 5.0f);
        write_bytes("binary.ply", data, size);
        Scene s;
        load_ok(WORLD "Scale 2 2 2\nShape \"plymesh\" \"string filename\" [ \"binary.ply\" ]\n", &s);
        assert_int_equal(s.vertex_count, 5);
        assert_int_equal(s.triangle_count, 3);
        assert_null(s.normals);
        assert_vec3(vertex(&s, 0, 2), 2, 2, 0);
        assert_vec3(vertex(&s, 1, 2), 0, 2, 0);
        assert_vec3(vertex(&s, 2, 0), 0, 0, 10);
        scene_destroy(&s);

        /* Every truncation is an error, never a crash. */
        for (size_t cut = 0; cut < size; cut += 1 + cut / 64) {
            write_bytes("binary.ply", data, cut);
            assert_int_equal(
                load_text("cut.pbrt", WORLD "Shape \"plymesh\" \"string filename\" \"binary.ply\"\n", &s, 0), -1);
            assert_non_null(strstr(error, "cut.pbrt:2: "));
        }
    }
}

/* data[0, size) compressed as one gzip member into out (malloc'd). */
static size_t gzip_bytes(const void *data, size_t size, unsigned char **out)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    assert_int_equal(deflateInit2(&z, 9, Z_DEFLATED, 16 + MAX_WBITS, 9, Z_DEFAULT_STRATEGY), Z_OK);
    size_t capacity = deflateBound(&z, (uLong)size);
    *out = malloc(capacity);
    z.next_in = (Bytef *)data;
    z.avail_in = (uInt)size;
    z.next_out = *out;
    z.avail_out = (uInt)capacity;
    assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
    size_t length = capacity - z.avail_out;
    deflateEnd(&z);
    return length;
}

static const char *write_gzip(const char *relative, const char *text)
{
    unsigned char *packed;
    size_t length = gzip_bytes(text, strlen(text), &packed);
    const char *path = write_bytes(relative, packed, length);
    free(packed);
    return path;
}

/* gzip files (pbrt-v4 reads .pbrt.gz and .ply.gz) are recognised by their
 * magic bytes, whatever their name; corrupt or truncated data is an error,
 * and the size limit applies to the inflated data. */
static void test_gzip_files(void **state)
{
    (void)state;
    const char *ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    write_gzip("gz/mesh.ply.gz", ply);
    write_gzip("gz/named-plainly.ply", ply);
    write_gzip("gz/part.pbrt.gz", "Translate 0 0 2\nShape \"plymesh\" \"string filename\" \"mesh.ply.gz\"\n");
    const char *main_path =
        write_gzip("gz/main.pbrt.gz", WORLD "Include \"part.pbrt.gz\"\n"
                                            "Shape \"plymesh\" \"string filename\" \"named-plainly.ply\"\n");
    Scene s;
    if (scene_load(main_path, NULL, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(s.triangle_count, 2);
    assert_vec3(vertex(&s, 0, 1), 1, 0, 2);
    assert_vec3(vertex(&s, 1, 2), 0, 1, 2); /* the Translate of part.pbrt.gz still applies */
    scene_destroy(&s);

    /* Two members, as `cat a.gz b.gz` makes: the text of both. */
    unsigned char *first, *second;
    size_t first_length = gzip_bytes(WORLD, strlen(WORLD), &first);
    size_t second_length = gzip_bytes(TRIANGLE, strlen(TRIANGLE), &second);
    unsigned char both[1024];
    assert_true(first_length + second_length <= sizeof both);
    memcpy(both, first, first_length);
    memcpy(both + first_length, second, second_length);
    assert_int_equal(
        scene_load(write_bytes("gz/two.pbrt", both, first_length + second_length), NULL, &s, error, sizeof error), 0);
    assert_int_equal(s.triangle_count, 1);
    scene_destroy(&s);

    /* Corrupt and truncated data. */
    unsigned char *packed;
    size_t length = gzip_bytes(ply, strlen(ply), &packed);
    write_bytes("gz/truncated.ply", packed, length / 2);
    memset(packed + 10, 0xff, 8); /* the first deflate block's header and codes */
    write_bytes("gz/corrupt.ply", packed, length);
    free(packed);
    load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"gz/corrupt.ply\"\n", 2,
               "gz/corrupt.ply\": cannot read: corrupt gzip data: invalid");
    load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"gz/truncated.ply\"\n", 2,
               "cannot read: corrupt gzip data: the file ends inside the compressed stream");
    free(first);
    free(second);

    /* A small file that inflates to far more than the limit stops there. */
    size_t big = (size_t)1 << 22;
    char *zeros = calloc(big, 1);
    length = gzip_bytes(zeros, big, &packed);
    free(zeros);
    assert_true(length < 8192);
    const char *bomb = write_bytes("gz/bomb.ply", packed, length);
    free(packed);
    char *data, why[128];
    size_t size;
    assert_int_equal(scene_read_file(bomb, big - 1, &data, &size, why, sizeof why), -1);
    assert_string_equal(why, "over the 4194303 bytes limit once uncompressed");
    assert_null(data);
    assert_int_equal(scene_read_file(bomb, big, &data, &size, why, sizeof why), 0);
    assert_int_equal(size, big);
    assert_int_equal(data[big - 1], 0);
    free(data);
}

static void test_ply_errors(void **state)
{
    (void)state;
    unsigned char data[1024];
    size_t size = binary_ply(data, 0, 0, "uchar", "int", NAN);
    write_bytes("nan.ply", data, size);
    /* Errors in the data name the PLY file and the element's index. */
    load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"nan.ply\"\n", 2,
               "nan.ply\": vertex 4 has a non-finite position");
    load_fails(WORLD "\nShape \"plymesh\" \"string filename\" \"missing.ply\"\n", 3, "missing.ply");

    static const struct {
        const char *text, *needle;
    } bad[] = {
        {"hello\n", "not a PLY file"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty flt x\nend_header\n", "header line 4"},
        {"ply\nformat ascii 2.0\nend_header\n", "header line 2"},
        {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "property before any element"},
        {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "bad element"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "without end_header"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n0 0\n",
         "lacks x, y or z"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n",
         "integer list"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n5 0 1 2 0 1\n",
         "only triangles and quads"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n3 0 1 3\n",
         "bad.ply\": face 1: vertex index 3 is out of range (3 vertices)"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 x 0 1 0\n3 0 1 2\n",
         "malformed number"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n3 0 1\n",
         "unexpected end of file"},
        {"ply\nformat ascii 1.0\nelement vertex 99999999\nproperty float x\nproperty float y\n"
         "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
         "more than the file holds"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n0 0 0 1 0 0 0 1 0\n",
         "no face element"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        write_text("bad.ply", bad[i].text);
        load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"bad.ply\"\n", 2, bad[i].needle);
    }
}

/* ------------------------------------------------------ Include, Import */

static void test_include_and_import(void **state)
{
    (void)state;
    Scene s;
    /* tests/data/scenes: main.pbrt includes sub/camera.pbrt, imports
     * sub/geometry.pbrt, which includes part.pbrt and reads quad.ply, both
     * beside it in sub/. */
    SceneLoadOptions options = {0};
    int result = scene_load(GMON_SOURCE_DIR "/tests/data/scenes/main.pbrt", &options, &s, error, sizeof error);
    if (result)
        fail_msg("%s", error);
    assert_int_equal(s.warning_count, 0);
    assert_vec3(s.camera.position, 0, 0, -5);
    assert_int_equal(s.spp, 4);
    assert_int_equal(s.triangle_count, 3);   /* part.pbrt's triangle and quad.ply's two */
    assert_vec3(vertex(&s, 0, 0), 11, 0, 0); /* the including file's Translate applies */
    assert_int_equal(s.materials[s.shapes[1].material].type, SCENE_MATERIAL_DIELECTRIC);
    scene_destroy(&s);
    load_fails(WORLD "\nInclude \"inc/none.pbrt\"\n", 3, "none.pbrt");
}

/* pbrt-v4 resolves a relative path against the main file's directory
 * (ResolveFilename); gmonrt then tries the including file's directory. A
 * missing file is reported under the main file's directory. */
static void test_paths_resolve_as_pbrt(void **state)
{
    (void)state;
    Scene s;
    write_text("res/part.pbrt", "Translate 5 0 0\n");
    write_text("res/sub/part.pbrt", "Translate 9 0 0\n");
    write_text("res/sub/child.pbrt", "Include \"part.pbrt\"\n" TRIANGLE);
    write_text("res/sub/only.pbrt", "Translate 7 0 0\n");
    write_text("res/sub/child2.pbrt", "Include \"only.pbrt\"\n" TRIANGLE);
    const char *main_path =
        write_text("res/main.pbrt",
                   WORLD "AttributeBegin\nInclude \"sub/child.pbrt\"\nAttributeEnd\nInclude \"sub/child2.pbrt\"\n");
    SceneLoadOptions options = {0};
    if (scene_load(main_path, &options, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_vec3(vertex(&s, 0, 0), 6, 0, 0); /* res/part.pbrt, as pbrt-v4 reads it */
    assert_vec3(vertex(&s, 1, 0), 8, 0, 0); /* only beside child2.pbrt */
    scene_destroy(&s);

    write_text("res/sub/mesh.pbrt", "Shape \"plymesh\" \"string filename\" \"mesh.ply\"\n");
    main_path = write_text("res/main2.pbrt", WORLD "Include \"sub/mesh.pbrt\"\n");
    assert_int_equal(scene_load(main_path, &options, &s, error, sizeof error), -1);
    char expected[600];
    snprintf(expected, sizeof expected, "%s:1: Shape \"plymesh\": \"%s\": cannot read: No such file",
             temp_path("res/sub/mesh.pbrt"), temp_path("res/mesh.ply"));
    if (strncmp(error, expected, strlen(expected)) != 0)
        fail_msg("error \"%s\"; expected \"%s\"", error, expected);
}

/* pbrt-v4 binds NamedMaterial names after the whole scene is read:
 * contemporary-bathroom names "light" before the Include that defines it. */
static void test_named_material_before_definition(void **state)
{
    (void)state;
    Scene s;
    write_text("named/materials.pbrt", "MakeNamedMaterial \"light\" \"string type\" \"conductor\"\n"
                                       "MakeNamedMaterial \"wall\" \"string type\" \"diffuse\" "
                                       "\"rgb reflectance\" [ 0.1 0.2 0.3 ]\n");
    const char *main_path =
        write_text("named/main.pbrt", WORLD "NamedMaterial \"light\"\n" TRIANGLE "NamedMaterial \"wall\"\n" TRIANGLE
                                            "Include \"materials.pbrt\"\n"
                                            "NamedMaterial \"light\"\n" TRIANGLE);
    SceneLoadOptions options = {0};
    if (scene_load(main_path, &options, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(s.shape_count, 3);
    assert_int_equal(material_of_shape(&s, 0)->type, SCENE_MATERIAL_CONDUCTOR);
    assert_int_equal(material_of_shape(&s, 1)->type, SCENE_MATERIAL_DIFFUSE);
    assert_vec3(material_of_shape(&s, 1)->reflectance, 0.1, 0.2, 0.3);
    assert_int_equal(s.shapes[2].material, s.shapes[0].material); /* one material, bound once */
    assert_int_equal(s.material_count, 2);
    scene_destroy(&s);

    /* A name the whole scene never defines: an error at its NamedMaterial. */
    load_fails(WORLD TRIANGLE "NamedMaterial \"nowhere\"\n" TRIANGLE
                              "MakeNamedMaterial \"elsewhere\" \"string type\" \"diffuse\"\n",
               3, "NamedMaterial: no material named \"nowhere\" is defined (MakeNamedMaterial) in the scene");
    /* Defined twice stays an error, also after an early use. */
    load_fails(WORLD "NamedMaterial \"m\"\n" TRIANGLE "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
                     "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n",
               5, "\"m\" is defined twice");
}

/* A file included twice says the same warning twice: it is kept once. */
static void test_warnings_once(void **state)
{
    (void)state;
    Scene s;
    write_text("twice/curve.pbrt", "Shape \"curve\"\n");
    assert_int_equal(
        load_text("twice/main.pbrt", WORLD "Include \"curve.pbrt\"\nInclude \"curve.pbrt\"\nShape \"curve\"\n", &s, 1),
        0);
    assert_int_equal(s.warning_count, 2); /* curve.pbrt:1 once, main.pbrt:4 */
    scene_destroy(&s);
}

/* Check mode: every unsupported feature and every missing file is recorded
 * (kind, file, line, message, substitute or path) and parsing goes on. */
static void test_check_mode(void **state)
{
    (void)state;
    write_text("check/inc.pbrt", "Shape \"curve\" \"float width\" 2\n");
    const char *text = "Film \"spectral\"\n" WORLD "Shape \"curve\"\n"
                       "Shape \"plymesh\" \"string filename\" \"geometry/gone.ply\"\n"
                       "Include \"gone.pbrt\"\n"
                       "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"textures/gone.png\"\n"
                       "Include \"inc.pbrt\"\nInclude \"inc.pbrt\"\n" TRIANGLE;
    const char *path = write_text("check/main.pbrt", text);
    SceneLoadOptions options = {.check = 1};
    Scene s;
    if (scene_load(path, &options, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(s.triangle_count, 1); /* parsing went on to the end */
    assert_int_equal(s.warning_count, 0);
    assert_int_equal(s.diagnostic_count, 6);
    const struct {
        SceneDiagnosticKind kind;
        const char *file;
        int line;
        const char *message, *detail; /* the substitute, or the missing path */
    } expected[] = {
        {SCENE_DIAGNOSTIC_UNSUPPORTED, "check/main.pbrt", 1, "only \"rgb\" and \"gbuffer\"", "\"rgb\" film"},
        {SCENE_DIAGNOSTIC_UNSUPPORTED, "check/main.pbrt", 3, "Shape \"curve\" is not supported", "skipped"},
        {SCENE_DIAGNOSTIC_MISSING_FILE, "check/main.pbrt", 4, "Shape \"plymesh\"", "check/geometry/gone.ply"},
        {SCENE_DIAGNOSTIC_MISSING_FILE, "check/main.pbrt", 5, "Include", "check/gone.pbrt"},
        {SCENE_DIAGNOSTIC_MISSING_FILE, "check/main.pbrt", 6, "Texture \"t\"", "check/textures/gone.png"},
        {SCENE_DIAGNOSTIC_UNSUPPORTED, "check/inc.pbrt", 1, "Shape \"curve\"", "skipped"}, /* once */
    };
    for (size_t i = 0; i < 6; ++i) {
        const SceneDiagnostic *d = &s.diagnostics[i];
        int missing = expected[i].kind == SCENE_DIAGNOSTIC_MISSING_FILE;
        const char *detail = missing ? d->path : d->substitute;
        if (d->kind != expected[i].kind || strcmp(d->file, temp_path(expected[i].file)) != 0 ||
            d->line != expected[i].line || !strstr(d->message, expected[i].message) || !detail ||
            !strstr(detail, missing ? temp_path(expected[i].detail) : expected[i].detail) ||
            (missing ? d->substitute != NULL : d->path != NULL))
            fail_msg("diagnostic %zu: kind %d, %s:%d, \"%s\", \"%s\"", i, (int)d->kind, d->file, d->line, d->message,
                     detail ? detail : "(null)");
    }
    scene_destroy(&s);
    /* The parameters of a directive begun in a missing Include file (as
     * smoke-plume's density grid) are skipped up to the next directive. */
    path = write_text("check/main3.pbrt", WORLD "Include \"gone.pbrt\"\n"
                                                "  \"spectrum sigma_a\" [ 300 20 830 20 ] \"bool b\" true\n" TRIANGLE);
    if (scene_load(path, &options, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(s.triangle_count, 1);
    assert_int_equal(s.diagnostic_count, 1);
    assert_int_equal(s.diagnostics[0].kind, SCENE_DIAGNOSTIC_MISSING_FILE);
    scene_destroy(&s);
    /* Without check, the missing file is the error, as before. */
    options.check = 0;
    assert_int_equal(scene_load(path, &options, &s, error, sizeof error), -1);
    assert_non_null(strstr(error, "gone.pbrt"));
    options.check = 1;
    /* A file that cannot be read for another reason is still an error. */
    write_text("check/bad.ply", "ply\nformat ascii 1.0\nend_header\n");
    path = write_text("check/main2.pbrt", WORLD "Shape \"plymesh\" \"string filename\" \"bad.ply\"\n");
    assert_int_equal(scene_load(path, &options, &s, error, sizeof error), -1);
    assert_non_null(strstr(error, "bad.ply"));
}

/* Forms of the public pbrt-v4 scenes (docs/scene-coverage.md) read as
 * pbrt-v4 reads them. */
static void test_pbrt_v4_scene_forms(void **state)
{
    (void)state;
    Scene s;
    /* Accelerator: its build parameters change the speed, not the image. */
    load_ok("Accelerator \"bvh\" \"integer maxnodeprims\" 4 \"string splitmethod\" \"sah\"\n" WORLD, &s);
    assert_int_equal(s.note_count, 1);
    assert_non_null(strstr(s.notes[0], ":1: note: Accelerator \"bvh\": gmonrt builds its own BVH"));
    scene_destroy(&s);
    load_ok("Accelerator \"kdtree\" \"integer maxprims\" 1 \"float emptybonus\" 0.5\n" WORLD, &s);
    scene_destroy(&s);
    load_fails("Accelerator \"octree\"\n" WORLD, 1, "Accelerator \"octree\" is not pbrt-v4's \"bvh\" or \"kdtree\"");
    load_fails("Accelerator \"bvh\" \"integer maxprims\" 1\n" WORLD, 1, "unsupported parameter \"integer maxprims\"");
    load_fails(WORLD "Accelerator \"bvh\"\n", 2, "before WorldBegin");

    /* Material "" and "none" (also as a named material's type): no
     * material, as "interface". */
    load_ok(WORLD "Material \"\"\n" TRIANGLE "Material \"none\"\n" TRIANGLE
                  "MakeNamedMaterial \"n\" \"string type\" \"\"\nNamedMaterial \"n\"\n" TRIANGLE,
            &s);
    for (size_t i = 0; i < 3; ++i)
        assert_int_equal(material_of_shape(&s, i)->type, SCENE_MATERIAL_INTERFACE);
    scene_destroy(&s);

    /* A parameter given twice: pbrt-v4's lookup finds the last one. */
    assert_int_equal(load_text("twice.pbrt",
                               "Camera \"perspective\" \"float fov\" 45 \"float lensradius\" 0.1\n"
                               "  \"float fov\" 50\n" WORLD,
                               &s, 0),
                     0);
    assert_near(s.camera.fov, 50, 1e-6);
    assert_int_equal(s.warning_count, 1);
    assert_true(has_warning(&s, "twice.pbrt:2: warning: Camera \"perspective\": parameter \"fov\" given twice (first "
                                "at line 1): the last one is used"));
    scene_destroy(&s);

    /* Another camera: unsupported, a perspective one with allow_unsupported
     * (the lens parameters are not reported one by one). */
    load_fails("Camera \"realistic\" \"string lensfile\" \"wide.dat\"\n" WORLD, 1,
               "Camera \"realistic\" is not supported (only \"perspective\" and \"orthographic\")");
    assert_int_equal(load_text("lens.pbrt",
                               "Camera \"realistic\" \"string lensfile\" \"wide.dat\" \"float aperturediameter\" 2 "
                               "\"float shutterclose\" 0.5\n" WORLD,
                               &s, 1),
                     0);
    assert_int_equal(s.camera.projection, SCENE_CAMERA_PERSPECTIVE);
    assert_near(s.camera.fov, 90, 0);
    assert_int_equal(s.warning_count, 1);
    assert_true(has_warning(&s, "lens.pbrt:1: warning: Camera \"realistic\" is not supported"));
    assert_true(has_warning(&s, "a \"perspective\" camera (fov 90) is used"));
    scene_destroy(&s);

    /* Brass, pbrt-v4's metal-CuZn: fitted as the other metals
     * (tests/support/spectrum_reference.py). */
    load_ok(WORLD
            "Material \"conductor\" \"spectrum eta\" \"metal-CuZn-eta\" \"spectrum k\" \"metal-CuZn-k\"\n" TRIANGLE,
            &s);
    assert_near(material_of_shape(&s, 0)->conductor_eta[0], 0.492838, 2e-3);
    assert_near(material_of_shape(&s, 0)->conductor_k[2], 1.761413, 6e-3);
    scene_destroy(&s);

    /* An unknown spectrum name is bad input; check mode lists it and goes on. */
    const char *text = WORLD "Material \"conductor\" \"spectrum eta\" \"metal-Xx-eta\"\n" TRIANGLE;
    load_fails(text, 2, "\"spectrum eta\": \"metal-Xx-eta\" is not a named spectrum");
    SceneLoadOptions options = {.check = 1};
    if (scene_load(write_text("check/spectrum.pbrt", text), &options, &s, error, sizeof error))
        fail_msg("%s", error);
    assert_int_equal(s.triangle_count, 1);
    assert_int_equal(s.diagnostic_count, 1);
    assert_int_equal(s.diagnostics[0].kind, SCENE_DIAGNOSTIC_UNSUPPORTED);
    assert_int_equal(s.diagnostics[0].line, 2);
    assert_non_null(strstr(s.diagnostics[0].message, "\"metal-Xx-eta\" is not a named spectrum"));
    assert_non_null(strstr(s.diagnostics[0].substitute, "check goes on"));
    scene_destroy(&s);
}

/* Only regular files are read, up to a size limit: /dev/zero would be read
 * forever and opening a FIFO would wait for a writer. */
static void test_only_regular_files_are_read(void **state)
{
    (void)state;
    load_fails(WORLD "Include \"/dev/zero\"\n", 2, "cannot read \"/dev/zero\": not a regular file");
    load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"/dev/zero\"\n", 2,
               "\"/dev/zero\": cannot read: not a regular file");
    const char *fifo = temp_path("fifo.pbrt");
    assert_int_equal(mkfifo(fifo, 0600), 0);
    remember(fifo);
    load_fails(WORLD "\nInclude \"fifo.pbrt\"\n", 3, "fifo.pbrt\": not a regular file");
    Scene s;
    assert_int_equal(scene_load(fifo, NULL, &s, error, sizeof error), -1);
    char expected[600];
    snprintf(expected, sizeof expected, "%s: cannot read: not a regular file", fifo);
    assert_true(strncmp(error, expected, strlen(expected)) == 0);

    /* Sparse files just over the limits: 1 GiB of scene text, 4 GiB of PLY. */
    const char *text = write_text("huge.pbrt", "");
    assert_int_equal(truncate(text, ((off_t)1 << 30) + 1), 0);
    load_fails(WORLD "Include \"huge.pbrt\"\n", 2, "huge.pbrt\": 1073741825 bytes, over the 1 GiB limit");
    const char *ply = write_text("huge.ply", "");
    assert_int_equal(truncate(ply, ((off_t)4 << 30) + 1), 0);
    load_fails(WORLD "Shape \"plymesh\" \"string filename\" \"huge.ply\"\n", 2,
               "huge.ply\": cannot read: 4294967297 bytes, over the 4 GiB limit");
}

/* An error inside an included file names that file and its line. */
static void test_error_in_included_file(void **state)
{
    (void)state;
    Scene s;
    char location[600];
    write_text("inc2/child.pbrt", "# child\n\nShape \"sphere\" \"float radius\" -1\n");
    assert_int_equal(load_text("top.pbrt", WORLD "Include \"inc2/child.pbrt\"\n", &s, 0), -1);
    snprintf(location, sizeof location, "%s:3: ", temp_path("inc2/child.pbrt"));
    if (strncmp(error, location, strlen(location)) != 0)
        fail_msg("error \"%s\" does not start with \"%s\"", error, location);

    write_text("cycle.pbrt", "\nInclude \"cycle.pbrt\"\n");
    assert_int_equal(load_text("top.pbrt", WORLD "Include \"cycle.pbrt\"\n", &s, 0), -1);
    snprintf(location, sizeof location, "%s:2: ", temp_path("cycle.pbrt"));
    if (strncmp(error, location, strlen(location)) != 0 || !strstr(error, "nested"))
        fail_msg("error \"%s\" does not start with \"%s\"", error, location);
}

/* ----------------------------------------------------- robustness, repo */

/* Every prefix of a valid scene loads or fails with file:line, never crashes. */
static void test_every_truncation_fails_cleanly(void **state)
{
    (void)state;
    const char *text = "LookAt 0 1 3.9   0 1 0   0 1 0\nCamera \"perspective\" \"float fov\" [ 36 ]\n"
                       "Film \"rgb\" \"string filename\" [ \"a.exr\" ]\n" WORLD
                       "MakeNamedMaterial \"white\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.7 ]\n"
                       "AttributeBegin\n  NamedMaterial \"white\"\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
                       "  Translate 1 0 0\n  " TRIANGLE "AttributeEnd\n";
    size_t length = strlen(text);
    char *prefix = malloc(length + 1);
    char location[600];
    snprintf(location, sizeof location, "%s:", temp_path("prefix.pbrt"));
    for (size_t n = 0; n <= length; ++n) {
        memcpy(prefix, text, n);
        prefix[n] = '\0';
        Scene s;
        if (load_text("prefix.pbrt", prefix, &s, 0) == 0) {
            scene_destroy(&s);
            continue;
        }
        if (strncmp(error, location, strlen(location)) != 0)
            fail_msg("prefix %zu: error \"%s\" lacks \"%s\"", n, error, location);
        const char *line = error + strlen(location);
        assert_true(*line >= '1' && *line <= '9');
    }
    free(prefix);
}

static void test_repository_scenes(void **state)
{
    (void)state;
    static const char *const names[] = {"cornell-diffuse", "cornell-glass", "narrow-gap", "furnace"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        char path[512];
        snprintf(path, sizeof path, "%s/scenes/%s.pbrt", GMON_SOURCE_DIR, names[i]);
        Scene s;
        if (scene_load(path, NULL, &s, error, sizeof error))
            fail_msg("%s", error);
        assert_int_equal(s.warning_count, 0);
        assert_true(s.shape_count > 0);
        assert_true(s.area_light_count > 0);
        if (strncmp(names[i], "cornell", 7) == 0) {
            assert_vec3(s.camera.right, -1, 0, 0); /* the red wall (x = +1) on the image's left */
            assert_int_equal(s.width, 256);
        }
        scene_destroy(&s);
    }
}

/* ------------------------------------------------------------- spectra */

/* The area light's radiance of the only emitter in `text`. */
static void area_radiance(const char *text, float rgb[3])
{
    Scene s;
    load_ok(text, &s);
    assert_int_equal(s.area_light_count, 1);
    memcpy(rgb, s.area_lights[0].radiance, 3 * sizeof(float));
    scene_destroy(&s);
}

static void test_spectral_emission(void **state)
{
    (void)state;
    float rgb[3];
    /* Values from tests/support/spectrum_reference.py (luminance 1). */
    area_radiance(WORLD "AreaLightSource \"diffuse\" \"blackbody L\" [ 5500 ] \"float scale\" 2\n" TRIANGLE, rgb);
    assert_near(rgb[0], 2 * 1.14427873, 5e-3);
    assert_near(rgb[1], 2 * 0.97107067, 5e-3);
    assert_near(rgb[2], 2 * 0.86233741, 5e-3);
    area_radiance(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-A\"\n" TRIANGLE, rgb);
    assert_near(rgb[0], 1.84512335, 4e-3);
    assert_near(rgb[2], 0.23338062, 1e-3);
    area_radiance(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"illum-acesD60\"\n" TRIANGLE, rgb);
    assert_near(rgb[0], 1.04692328, 3e-3);
    assert_near(rgb[1], 0.99465508, 3e-3);
    assert_near(rgb[2], 0.91537806, 3e-3);
    /* RGB emission is used as given (pbrt-v4 normalises it by D65 alone),
     * and pbrt-v4's default L is its colour space's illuminant: white. */
    area_radiance(WORLD "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"float scale\" [ 20 ]\n" TRIANGLE, rgb);
    assert_vec3(rgb, 20, 20, 20);
    area_radiance(WORLD "AreaLightSource \"diffuse\"\n" TRIANGLE, rgb);
    assert_vec3(rgb, 1, 1, 1);
    /* A flat inline spectrum is the equal-energy white: luminance 1. */
    area_radiance(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" [ 300 5  900 5 ]\n" TRIANGLE, rgb);
    assert_near(0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2], 1.0, 2e-3);
    assert_true(rgb[0] > 1.15 && rgb[2] < 0.95); /* equal energy is warmer than D65 */
}

static void test_spectral_materials(void **state)
{
    (void)state;
    /* An .spd beside the main file, named from an included file elsewhere:
     * resolved like Include (the naming file's directory, then the main file's). */
    write_text("spds/flat.spd", "# flat reflectance\n300 0.25\n900 0.25\n");
    write_text("inc/materials.pbrt", "Material \"diffuse\" \"spectrum reflectance\" \"spds/flat.spd\"\n" TRIANGLE);
    Scene s;
    load_ok(WORLD "Include \"inc/materials.pbrt\"\n"
                  "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n" TRIANGLE
                  "Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n" TRIANGLE
                  "Material \"coateddiffuse\" \"spectrum eta\" \"glass-F11\" \"spectrum reflectance\" [ 400 0.5 700 "
                  "0.5 ]\n" TRIANGLE,
            &s);
    assert_int_equal(s.material_count, 4);
    assert_vec3(s.materials[0].reflectance, 0.25, 0.25, 0.25);
    const SceneMaterial *gold = &s.materials[1];
    assert_int_equal(gold->type, SCENE_MATERIAL_CONDUCTOR);
    assert_near(gold->conductor_eta[0], 0.282615, 1e-3);
    assert_near(gold->conductor_eta[2], 1.435338, 4e-3);
    /* k fitted with eta so that the RGB Fresnel at normal incidence is the
     * sRGB of the spectral one (spectrum_reference.py) */
    assert_near(gold->conductor_k[1], 2.574626, 3e-3);
    assert_near(s.materials[2].eta, 1.51825, 1e-4);
    assert_true(s.materials[3].eta > 1.78 && s.materials[3].eta < 1.80); /* SF11 near 555 nm */
    assert_vec3(s.materials[3].reflectance, 0.5, 0.5, 0.5);
    scene_destroy(&s);
}

static void test_killeroo_gold_metal(void **state)
{
    (void)state;
    /* pbrt-v4-scenes' killeroo-gold: its gold from spds/Au.*.spd (its
     * texture is other work: skipped here). */
    char path[512];
    snprintf(path, sizeof path, "%s/../shared/scenes/killeroos/killeroo-gold.pbrt", GMON_SOURCE_DIR);
    if (access(path, R_OK) != 0) { /* the public scenes are not beside this checkout */
        print_message("%s is not there\n", path);
        skip();
    }
    SceneLoadOptions options = {.allow_unsupported = 1};
    Scene s;
    if (scene_load(path, &options, &s, error, sizeof error))
        fail_msg("%s", error);
    int conductors = 0;
    for (size_t i = 0; i < s.material_count; ++i)
        if (s.materials[i].type == SCENE_MATERIAL_CONDUCTOR) {
            conductors++;
            assert_near(s.materials[i].conductor_eta[1], 0.479352, 2e-3);
            assert_near(s.materials[i].conductor_k[1], 2.574626, 3e-3);
        }
    assert_int_equal(conductors, 1);
    assert_false(has_warning(&s, "spectrum"));
    scene_destroy(&s);
}

static void test_spectral_errors(void **state)
{
    (void)state;
    write_text("bad/odd.spd", "400 1 500\n");
    write_text("bad/order.spd", "400 1 400 2\n");
    write_text("bad/negative.spd", "400 1 500 -2\n");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"stdillum-Z\"\n", 2,
               "\"stdillum-Z\" is not a named spectrum, and cannot read");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 500 ]\n", 2, "(wavelength, value) pairs");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" [ 500 1 400 1 ]\n", 2, "do not increase at pair 2");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 500 -1 ]\n", 2, "negative value");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"bad/odd.spd\"\n", 2, "odd number of values");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"bad/order.spd\"\n", 2, "do not increase");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"bad/negative.spd\"\n", 2, "negative value");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"spectrum L\" \"bad/missing.spd\"\n", 2, "bad/missing.spd");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"blackbody L\" [ 5000 6000 ]\n", 2, "one temperature");
    load_fails(WORLD "AreaLightSource \"diffuse\" \"float L\" 1\n", 2, "expected \"rgb L\", \"spectrum L\"");
    load_fails(WORLD "Material \"diffuse\" \"spectrum reflectance\" [ 400 0.5 700 1.5 ]\n", 2, "above 1");
    load_fails(WORLD "Material \"dielectric\" \"rgb eta\" [ 1 1 1 ]\n", 2, "expected \"float eta\"");
    load_fails(WORLD "Material \"conductor\" \"spectrum eta\" \"metal-Xx-eta\"\n", 2, "not a named spectrum");
}

static void test_film_sensor(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD, &s);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            assert_near(s.film_from_radiance[r][c], r == c, 1e-6);
    assert_true(isinf(s.max_component_value));
    assert_int_equal(s.save_fp16, 1);
    assert_near(s.film_diagonal, 35, 0);
    scene_destroy(&s);

    /* pbrt-v4's imaging ratio: exposure (the camera's shutter) * iso / 100. */
    load_ok("Film \"rgb\" \"float iso\" 150 \"float maxcomponentvalue\" 10 \"bool savefp16\" false "
            "\"float diagonal\" 50\n"
            "Camera \"perspective\" \"float shutteropen\" 0.25 \"float shutterclose\" 0.75\n" WORLD,
            &s);
    assert_near(s.film_from_radiance[0][0], 0.75, 1e-6);
    assert_near(s.film_from_radiance[0][1], 0, 1e-6);
    assert_near(s.max_component_value, 10, 0);
    assert_int_equal(s.save_fp16, 0);
    assert_near(s.film_diagonal, 50, 0);
    scene_destroy(&s);

    /* The film's "scale" (zero-day's 3) multiplies the imaging ratio. */
    load_ok("Film \"rgb\" \"float scale\" 3 \"float iso\" 50\n" WORLD, &s);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            assert_near(s.film_from_radiance[r][c], r == c ? 1.5 : 0.0, 1e-6);
    scene_destroy(&s);

    /* White balance for 3000 K makes a blackbody neutral: below 4000 K
     * pbrt-v4 balances for a blackbody at 3000 * 1.4388 / 1.4380 K. */
    load_ok("Film \"rgb\" \"float whitebalance\" 3000\n" WORLD
            "AreaLightSource \"diffuse\" \"blackbody L\" 3001.669\n" TRIANGLE,
            &s);
    float out[3];
    for (int r = 0; r < 3; ++r)
        out[r] = s.film_from_radiance[r][0] * s.area_lights[0].radiance[0] +
                 s.film_from_radiance[r][1] * s.area_lights[0].radiance[1] +
                 s.film_from_radiance[r][2] * s.area_lights[0].radiance[2];
    assert_near(out[0], out[1], 2e-3);
    assert_near(out[2], out[1], 2e-3);
    scene_destroy(&s);

    if (load_text("gbuffer.pbrt", "Film \"gbuffer\" \"string coordinatesystem\" \"camera\"\n" WORLD, &s, 0))
        fail_msg("%s", error);
    assert_true(has_warning(&s, "rendered as \"rgb\""));
    scene_destroy(&s);

    /* A named camera sensor: pbrt-v4's fitted matrix (test_spectrum has its
     * values), at 6500 K unless whitebalance says otherwise. */
    load_ok("Film \"rgb\" \"string sensor\" \"nikon_d850\" \"float iso\" 200\n" WORLD, &s);
    float m[3][3];
    assert_int_equal(spectrum_film_from_radiance("nikon_d850", 2.0, 6500.0, m), 0);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            assert_near(s.film_from_radiance[r][c], m[r][c], 0);
    assert_true(fabsf(s.film_from_radiance[0][2]) > 0.1f); /* no longer the identity */
    scene_destroy(&s);
    load_fails("Film \"rgb\" \"string sensor\" \"canon_eos_999d\"\n" WORLD, 1,
               "unknown sensor \"canon_eos_999d\" (cie1931, canon_eos_100d");
    load_fails("Film \"rgb\" \"string sensor\" \"canon_eos_999d\"\n" WORLD, 1, "sony_ilce_7rm3, sony_ilce_9)");
    load_fails("Film \"rgb\" \"float iso\" 0\n" WORLD, 1, "iso");
    load_fails("Film \"rgb\" \"float scale\" 0\n" WORLD, 1, "scale 0 must be positive");
    load_fails("Film \"rgb\" \"float whitebalance\" -5\n" WORLD, 1, "whitebalance");
    load_fails("Film \"rgb\" \"float maxcomponentvalue\" 0\n" WORLD, 1, "maxcomponentvalue");
    load_fails("Film \"rgb\" \"float diagonal\" -1\n" WORLD, 1, "diagonal");
    load_fails("Film \"rgb\" \"float exposuretime\" 2\n" WORLD, 1, "exposuretime");
    load_fails("Film \"spectral\"\n" WORLD, 1, "only \"rgb\" and \"gbuffer\"");
    load_fails("Camera \"perspective\" \"float shutteropen\" 1 \"float shutterclose\" 1\n" WORLD, 1, "shutterclose");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_pbrt_v4_scene_forms),
        cmocka_unit_test(test_look_at_basis),
        cmocka_unit_test(test_fov_spans_shorter_axis),
        cmocka_unit_test(test_camera_transforms),
        cmocka_unit_test(test_camera_precision),
        cmocka_unit_test(test_camera_lens_and_window),
        cmocka_unit_test(test_orthographic_camera),
        cmocka_unit_test(test_pixel_filters),
        cmocka_unit_test(test_film_sampler_integrator_filter),
        cmocka_unit_test(test_media),
        cmocka_unit_test(test_nanovdb),
        cmocka_unit_test(test_translate_then_scale),
        cmocka_unit_test(test_rotate),
        cmocka_unit_test(test_transform_concat_identity),
        cmocka_unit_test(test_attribute_and_transform_blocks),
        cmocka_unit_test(test_coordinate_systems),
        cmocka_unit_test(test_active_transform),
        cmocka_unit_test(test_integrators),
        cmocka_unit_test(test_materials),
        cmocka_unit_test(test_named_materials),
        cmocka_unit_test(test_layered_mix_and_transmission_materials),
        cmocka_unit_test(test_area_lights_and_orientation),
        cmocka_unit_test(test_infinite_light),
        cmocka_unit_test(test_point_and_spot_lights),
        cmocka_unit_test(test_distant_light),
        cmocka_unit_test(test_spheres),
        cmocka_unit_test(test_trianglemesh_normals_and_uv),
        cmocka_unit_test(test_bad_mesh_data),
        cmocka_unit_test(test_geometry_range),
        cmocka_unit_test(test_precision_warnings),
        cmocka_unit_test(test_degenerate_triangles_are_skipped),
        cmocka_unit_test(test_parameter_syntax),
        cmocka_unit_test(test_wrong_parameters),
        cmocka_unit_test(test_truncated_and_malformed_files),
        cmocka_unit_test(test_allow_unsupported_substitutes),
        cmocka_unit_test(test_object_instances),
        cmocka_unit_test(test_object_instance_errors),
        cmocka_unit_test(test_instance_transform_errors),
        cmocka_unit_test(test_area_light_in_object_is_ignored),
        cmocka_unit_test(test_shape_alpha),
        cmocka_unit_test(test_ply_ascii),
        cmocka_unit_test(test_ply_binary),
        cmocka_unit_test(test_ply_errors),
        cmocka_unit_test(test_gzip_files),
        cmocka_unit_test(test_include_and_import),
        cmocka_unit_test(test_paths_resolve_as_pbrt),
        cmocka_unit_test(test_named_material_before_definition),
        cmocka_unit_test(test_warnings_once),
        cmocka_unit_test(test_check_mode),
        cmocka_unit_test(test_error_in_included_file),
        cmocka_unit_test(test_only_regular_files_are_read),
        cmocka_unit_test(test_every_truncation_fails_cleanly),
        cmocka_unit_test(test_repository_scenes),
        cmocka_unit_test(test_spectral_emission),
        cmocka_unit_test(test_spectral_materials),
        cmocka_unit_test(test_killeroo_gold_metal),
        cmocka_unit_test(test_spectral_errors),
        cmocka_unit_test(test_film_sensor),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
