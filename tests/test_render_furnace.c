/* Furnace tests: scenes whose answer is known analytically, rendered by the
 * path tracer kernel. The mean over all pixels must lie within 5 standard
 * errors (estimated from the pixels) of the analytic value. */
#include "cl/cl_device.h"
#include "render/render_scene.h"
#include "render/renderer.h"
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

static Material diffuse(float albedo)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_DIFFUSE;
    m.reflectance[0] = m.reflectance[1] = m.reflectance[2] = albedo;
    return m;
}

static void look_along_z(RenderScene *scene, float z, float tan_half_fov)
{
    const float position[3] = {0, 0, z}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, tan_half_fov, tan_half_fov, 24, 24);
    render_scene_set_camera(scene, &camera);
}

/* Renders and checks every channel's image mean against `expected`. */
/* flags: IntegratorData's (RENDER_NEE, RENDER_BDPT, ...). */
static void render_and_check(RenderScene *scene, uint32_t flags, unsigned max_depth, double expected, const char *name)
{
    char error[256];
    scene->constants.integrator.max_depth = max_depth;
    scene->constants.integrator.flags = flags;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 64;
    settings.seed = 7;
    RenderOutput out;
    int status = renderer_run(&test_device, 1, scene, &settings, &out, error, sizeof error);
    if (status != 0)
        fail_msg("%s: %s", name, error);
    size_t pixels = (size_t)out.width * out.height;
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0, sum2 = 0.0;
        for (size_t p = 0; p < pixels; ++p) {
            double v = ((const float *)out.pass[PASS_MEAN])[3 * p + (size_t)c];
            sum += v;
            sum2 += v * v;
        }
        double mean = sum / (double)pixels;
        double variance = sum2 / (double)pixels - mean * mean;
        double standard_error = sqrt(variance > 0.0 ? variance / (double)pixels : 0.0);
        printf("  %-40s channel %d: mean %.5f expected %.5f (standard error %.5f)\n", name, c, mean, expected,
               standard_error);
        assert_true(fabs(mean - expected) <= 5.0 * standard_error + 1e-4 * expected);
    }
    assert_int_equal(out.sample_count, 64);
    assert_int_equal(out.rejected_total, 0);
    render_output_free(&out);
}

/* Inside a closed sphere that emits Le (both sides) and reflects with albedo
 * rho, radiance is Le * (1 + rho + ... + rho^D) for D bounces. */
static void closed_sphere(int nee, unsigned max_depth)
{
    const double rho = 0.5, le = 1.0;
    RenderScene scene;
    render_scene_init(&scene);
    Material m = diffuse((float)rho);
    int material = render_scene_add_material(&scene, &m);
    const float centre[3] = {0, 0, 0}, emission[3] = {(float)le, (float)le, (float)le};
    assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, emission, 1, 0), 0);
    look_along_z(&scene, 0.0f, 1.0f);
    double expected = le * (1.0 - pow(rho, max_depth + 1)) / (1.0 - rho);
    char name[96];
    snprintf(name, sizeof name, "closed sphere, %s, maxdepth %u", nee ? "NEE+MIS" : "BSDF only", max_depth);
    render_and_check(&scene, nee ? RENDER_NEE : 0u, max_depth, expected, name);
    render_scene_destroy(&scene);
}

/* The same closed sphere with light subpaths: bdpt (every strategy, MIS)
 * and the light tracer (the camera reached from the emitting walls). */
static void test_closed_emitting_sphere_bidirectional(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const double rho = 0.5, le = 1.0;
    const uint32_t integrators[] = {RENDER_BDPT, RENDER_LIGHTPATH};
    const unsigned depths[] = {0, 1, 5};
    for (int i = 0; i < 2; ++i)
        for (int d = 0; d < 3; ++d) {
            RenderScene scene;
            render_scene_init(&scene);
            Material m = diffuse((float)rho);
            int material = render_scene_add_material(&scene, &m);
            const float centre[3] = {0, 0, 0}, emission[3] = {(float)le, (float)le, (float)le};
            assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, emission, 1, 0), 0);
            look_along_z(&scene, 0.0f, 1.0f);
            double expected = le * (1.0 - pow(rho, depths[d] + 1)) / (1.0 - rho);
            char name[96];
            snprintf(name, sizeof name, "closed sphere, %s, maxdepth %u", i ? "lightpath" : "bdpt", depths[d]);
            render_and_check(&scene, RENDER_NEE | integrators[i], depths[d], expected, name);
            render_scene_destroy(&scene);
        }
}

static void test_closed_emitting_sphere(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    closed_sphere(1, 5);
    closed_sphere(0, 5);
    closed_sphere(1, 60);
    closed_sphere(0, 60);
}

/* Inside the closed emitting sphere, BSDF sampling of a diffuse surface
 * multiplies the throughput by exactly rho a bounce, so without Russian
 * roulette (rrthreshold 0) every sample is the closed form; with pbrt-v4's
 * default threshold 1 roulette makes the samples differ (and, unbiased, the
 * mean stays the closed form: test_closed_emitting_sphere). Returns the
 * largest distance of a pixel's mean from the closed form. */
static double closed_sphere_spread(float rr_threshold)
{
    const double rho = 0.5;
    const unsigned max_depth = 8;
    RenderScene scene;
    render_scene_init(&scene);
    Material m = diffuse((float)rho);
    int material = render_scene_add_material(&scene, &m);
    const float centre[3] = {0, 0, 0}, emission[3] = {1, 1, 1};
    assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, emission, 1, 0), 0);
    look_along_z(&scene, 0.0f, 1.0f);
    scene.constants.integrator.max_depth = max_depth;
    scene.constants.integrator.flags = 0u;
    scene.constants.integrator.rr_threshold = rr_threshold;
    char error[256];
    assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 4;
    settings.seed = 11;
    RenderOutput out;
    if (renderer_run(&test_device, 1, &scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s", error);
    double expected = (1.0 - pow(rho, max_depth + 1)) / (1.0 - rho), spread = 0.0;
    const float *mean = (const float *)out.pass[PASS_MEAN];
    for (size_t i = 0; i < (size_t)out.width * out.height * 3; ++i)
        spread = fmax(spread, fabs(mean[i] - expected));
    printf("  rrthreshold %g: largest pixel distance from %.6f: %.3g\n", (double)rr_threshold, expected, spread);
    render_output_free(&out);
    render_scene_destroy(&scene);
    return spread;
}

static void test_roulette_threshold(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    assert_true(closed_sphere_spread(0.0f) < 1e-5);
    assert_true(closed_sphere_spread(1.0f) > 0.05);
}

/* A convex diffuse object under a constant environment reflects rho * L. */
static void test_diffuse_sphere_in_environment(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    for (int nee = 0; nee <= 1; ++nee) {
        RenderScene scene;
        render_scene_init(&scene);
        Material m = diffuse(0.8f);
        int material = render_scene_add_material(&scene, &m);
        const float centre[3] = {0, 0, 0};
        assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, NULL, 0, 0), 0);
        const float sky[3] = {2.0f, 2.0f, 2.0f};
        assert_int_equal(render_scene_add_infinite_light(&scene, sky), 0);
        look_along_z(&scene, -3.0f, 0.15f); /* the sphere fills the view */
        render_and_check(&scene, nee ? RENDER_NEE : 0u, 8, 1.6,
                         nee ? "diffuse sphere in environment, NEE" : "diffuse sphere, BSDF");
        render_scene_destroy(&scene);
    }
}

/* Smooth glass neither absorbs nor emits: in a constant environment every
 * path returns the environment's radiance. */
static void test_glass_sphere_in_environment(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    render_scene_init(&scene);
    Material glass;
    memset(&glass, 0, sizeof glass);
    glass.type = MAT_DIELECTRIC;
    glass.eta = 1.5f;
    int material = render_scene_add_material(&scene, &glass);
    const float centre[3] = {0, 0, 0};
    assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, NULL, 0, 0), 0);
    const float sky[3] = {1.0f, 1.0f, 1.0f};
    assert_int_equal(render_scene_add_infinite_light(&scene, sky), 0);
    look_along_z(&scene, -3.0f, 0.3f);
    render_and_check(&scene, RENDER_NEE, 200, 1.0, "glass sphere in environment");
    render_scene_destroy(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_emitting_sphere),      cmocka_unit_test(test_closed_emitting_sphere_bidirectional),
        cmocka_unit_test(test_roulette_threshold),          cmocka_unit_test(test_diffuse_sphere_in_environment),
        cmocka_unit_test(test_glass_sphere_in_environment),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
