/* The light types against closed forms, rendered by the path tracer: a
 * diffuse plane of albedo rho lit by a point, spot or distant light
 * reflects rho / pi times the irradiance; an environment image lights a
 * diffuse plane with rho / pi times its cosine-weighted integral, computed
 * here by quadrature over the image, the same with light sampling (the
 * image's distribution) and without (BSDF sampling only). The image mean
 * must lie within 5 standard errors (from the pixels) of the value. */
#include "cl/cl_device.h"
#include "equal_area.h"
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

#define PI 3.14159265358979323846
#define RHO 0.5f

/* A diffuse square [-10, 10]^2 at z = 0 facing +z, seen from (x, 0, 2)
 * looking straight down through a narrow field of view. */
static void plane_scene(RenderScene *scene, float x)
{
    render_scene_init(scene);
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_DIFFUSE;
    m.reflectance[0] = m.reflectance[1] = m.reflectance[2] = RHO;
    int material = render_scene_add_material(scene, &m);
    const float a[3] = {-10, -10, 0}, b[3] = {10, -10, 0}, c[3] = {10, 10, 0}, d[3] = {-10, 10, 0};
    assert_int_equal(render_scene_add_triangle(scene, a, b, c, material, NULL, 0, 0), 0);
    assert_int_equal(render_scene_add_triangle(scene, a, c, d, material, NULL, 0, 0), 0);
    const float position[3] = {x, 0, 2}, forward[3] = {0, 0, -1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 1e-4f, 1e-4f, 16, 16);
    render_scene_set_camera(scene, &camera);
}

static Light light_of(uint32_t type, float radiance)
{
    Light light;
    memset(&light, 0, sizeof light);
    light.type = type;
    light.primitive = -1;
    light.radiance[0] = light.radiance[1] = light.radiance[2] = radiance;
    return light;
}

/* Renders (direct light only unless max_depth says more) and returns the
 * image mean of the green channel; checks it against `expected`. */
static void render_and_check(RenderScene *scene, int nee, unsigned spp, double expected, const char *name)
{
    char error[256];
    scene->constants.integrator.max_depth = 1;
    scene->constants.integrator.flags = nee ? RENDER_NEE : 0u;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = spp;
    settings.seed = 11;
    RenderOutput out;
    if (renderer_run(&test_device, 1, scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s: %s", name, error);
    size_t pixels = (size_t)out.width * out.height;
    double sum = 0.0, sum2 = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
        double v = ((const float *)out.pass[PASS_MEAN])[3 * p + 1];
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / (double)pixels, variance = sum2 / (double)pixels - mean * mean;
    double standard_error = sqrt(variance > 0.0 ? variance / (double)pixels : 0.0);
    printf("  %-44s mean %.6f expected %.6f (standard error %.6f)\n", name, mean, expected, standard_error);
    assert_true(fabs(mean - expected) <= 5.0 * standard_error + 2e-4 * expected);
    render_output_free(&out);
    render_scene_destroy(scene);
}

/* Intensity I at height h over the point seen: E = I / h^2. */
static void test_point_light(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    plane_scene(&scene, 0.0f);
    Light light = light_of(LIGHT_POINT, 3.0f);
    light.position[2] = 1.5f;
    assert_int_equal(render_scene_add_light(&scene, &light), 0);
    render_and_check(&scene, 1, 4, RHO / PI * 3.0 / (1.5 * 1.5), "point light over a diffuse plane");
}

/* The film's response: its matrix scales every sample (iso 300 is 3 x the
 * identity), and maxcomponentvalue selects clamp at that level (the mean
 * stays unclamped). */
static void test_film_response(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const double lit = RHO / PI * 3.0 / (1.5 * 1.5);
    for (int clamp = 0; clamp <= 1; ++clamp) {
        RenderScene scene;
        plane_scene(&scene, 0.0f);
        Light light = light_of(LIGHT_POINT, 3.0f);
        light.position[2] = 1.5f;
        assert_int_equal(render_scene_add_light(&scene, &light), 0);
        for (int i = 0; i < 3; ++i)
            scene.constants.film.from_radiance[i][i] = 3.0f;
        if (clamp)
            scene.constants.film.max_component_value = 0.25f;
        if (!clamp) {
            render_and_check(&scene, 1, 4, 3.0 * lit, "film matrix 3 I");
            continue;
        }
        /* maxcomponentvalue is the per-sample estimator clamp at 0.25: the
         * mean stays unclamped. */
        char error[256];
        scene.constants.integrator.max_depth = 1;
        scene.constants.integrator.flags = RENDER_NEE;
        assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
        RenderSettings settings;
        render_settings_default(&settings);
        settings.sample_count = 4;
        RenderOutput out;
        if (renderer_run(&test_device, 1, &scene, &settings, &out, error, sizeof error) != 0)
            fail_msg("film clamp: %s", error);
        assert_int_equal(out.estimator.params.clamp_level_count, 1);
        const size_t pixels = (size_t)out.width * out.height;
        double clamped = 0.0, mean = 0.0;
        for (size_t p = 0; p < pixels; ++p) {
            clamped += ((const float *)out.pass[PASS_CLAMP])[3 * p + 1];
            mean += ((const float *)out.pass[PASS_MEAN])[3 * p + 1];
        }
        printf("  film clamp: layer clamp-0.25 %.6f, mean %.6f (expected %.6f)\n", clamped / (double)pixels,
               mean / (double)pixels, 3.0 * lit);
        assert_true(fabs(clamped / (double)pixels - 0.25) < 1e-6);
        assert_true(fabs(mean / (double)pixels - 3.0 * lit) < 0.05 * 3.0 * lit);
        render_output_free(&out);
        render_scene_destroy(&scene);
    }
}

/* A spot light pointing down: full intensity inside the inner cone,
 * pbrt-v4's smoothstep between the cones, nothing outside. */
static void test_spot_light(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const double h = 1.0, inner = 20.0 * PI / 180.0, outer = 30.0 * PI / 180.0;
    const double angles[] = {0.0, 25.0 * PI / 180.0, 35.0 * PI / 180.0};
    for (int i = 0; i < 3; ++i) {
        double x = h * tan(angles[i]), cos_theta = cos(angles[i]), d2 = h * h + x * x;
        double t = (cos_theta - cos(outer)) / (cos(inner) - cos(outer));
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        double falloff = t * t * (3.0 - 2.0 * t);
        RenderScene scene;
        plane_scene(&scene, (float)x);
        Light light = light_of(LIGHT_SPOT, 2.0f);
        light.position[2] = (float)h;
        light.direction[2] = -1.0f;
        light.cos_falloff_start = (float)cos(inner);
        light.cos_total_width = (float)cos(outer);
        assert_int_equal(render_scene_add_light(&scene, &light), 0);
        char name[64];
        snprintf(name, sizeof name, "spot light, %.0f degrees off its axis", angles[i] * 180.0 / PI);
        render_and_check(&scene, 1, 4, RHO / PI * 2.0 * falloff * cos_theta / d2, name);
    }
}

/* A distant light of radiance L from 60 degrees off the normal: E = L cos. */
static void test_distant_light(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    plane_scene(&scene, 0.0f);
    Light light = light_of(LIGHT_DISTANT, 4.0f);
    light.direction[0] = (float)sin(PI / 3.0);
    light.direction[2] = (float)cos(PI / 3.0);
    assert_int_equal(render_scene_add_light(&scene, &light), 0);
    render_and_check(&scene, 1, 4, RHO / PI * 4.0 * 0.5, "distant light at 60 degrees");
}

/* A goniometric light with a constant image is a point light of that
 * intensity; a projection light lights a point with the texel its
 * direction projects to. */
static void test_goniometric_and_projection_lights(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    char error[256];
    float grey[4 * 4 * 3];
    for (int i = 0; i < 4 * 4 * 3; ++i)
        grey[i] = 2.0f;
    RenderScene scene;
    plane_scene(&scene, 0.0f);
    Light light = light_of(LIGHT_GONIOMETRIC, 1.5f);
    light.position[2] = 1.0f;
    for (int i = 0; i < 3; ++i)
        light.light_from_world[i][i] = 1.0f;
    assert_int_equal(render_scene_add_image_light(&scene, &light, 4, 4, grey, error, sizeof error), 0);
    render_and_check(&scene, 1, 4, RHO / PI * 1.5 * 2.0, "goniometric light, constant image");

    /* Pointing down (light +z is world -z), fov 90, from (0, -0.2, 1): the
     * point at x = 0.2 is seen along light-space (0.2, 0.2, 1), in the 2x2
     * image's texel (column 1, row 1), which alone is green. */
    float slide[2 * 2 * 3] = {0};
    slide[3 * 3 + 1] = 3.0f;
    plane_scene(&scene, 0.2f);
    light = light_of(LIGHT_PROJECTION, 1.0f);
    light.position[1] = -0.2f;
    light.position[2] = 1.0f;
    light.light_from_world[0][0] = light.light_from_world[1][1] = 1.0f;
    light.light_from_world[2][2] = -1.0f;
    light.screen_half[0] = light.screen_half[1] = 1.0f;
    assert_int_equal(render_scene_add_image_light(&scene, &light, 2, 2, slide, error, sizeof error), 0);
    double d2 = 1.0 + 2.0 * 0.2 * 0.2;
    render_and_check(&scene, 1, 4, RHO / PI * 3.0 / sqrt(d2) / d2, "projection light, one texel");
}

/* Vertex normals shade: the plane's normals tilted 60 degrees toward a
 * distant light at 60 degrees make it lit as if head-on (E = L), while
 * the geometry (and so the ray offsets) stays flat. */
static void test_vertex_normals_shade(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderScene scene;
    plane_scene(&scene, 0.0f);
    const float tilted[3] = {(float)sin(PI / 3.0), 0.0f, (float)cos(PI / 3.0)};
    /* Both triangles of the plane get the same tilted normals. */
    RenderScene shaded;
    render_scene_init(&shaded);
    shaded.constants = scene.constants;
    for (int i = 0; i < scene.material_count; ++i)
        assert_true(render_scene_add_material(&shaded, &scene.materials[i]) >= 0);
    for (int i = 0; i < scene.primitive_count; ++i) {
        const Primitive *p = &scene.primitives[i];
        float a[3], b[3], c[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = p->a[k];
            b[k] = p->a[k] + p->b[k];
            c[k] = p->a[k] + p->c[k];
        }
        assert_int_equal(render_scene_add_triangle(&shaded, a, b, c, p->material, NULL, 0, 0), 0);
        assert_int_equal(render_scene_set_vertex_normals(&shaded, tilted, tilted, tilted), 0);
    }
    render_scene_destroy(&scene);
    Light light = light_of(LIGHT_DISTANT, 4.0f);
    memcpy(light.direction, tilted, sizeof light.direction);
    assert_int_equal(render_scene_add_light(&shaded, &light), 0);
    render_and_check(&shaded, 1, 4, RHO / PI * 4.0, "vertex normals facing the distant light");
}

/* An N x N environment image: `background` everywhere, one texel `bright`. */
static float *environment(int n, float background, int bright_x, int bright_y, float bright)
{
    float *rgb = malloc((size_t)n * n * 3 * sizeof *rgb);
    for (int i = 0; i < n * n * 3; ++i)
        rgb[i] = background;
    for (int c = 0; c < 3; ++c)
        rgb[3 * (bright_y * n + bright_x) + c] = bright;
    return rgb;
}

/* rho / pi times the image's radiance times max(0, z), integrated over the
 * sphere by the midpoint rule on 64 x 64 points per texel (the mapping is
 * equal-area: each point stands for 4 pi / (points) steradians). */
static double plane_under_image(const float *rgb, int n)
{
    const int sub = 64;
    double sum = 0.0;
    for (int y = 0; y < n * sub; ++y)
        for (int x = 0; x < n * sub; ++x) {
            Vec3 w = equal_area_square_to_sphere((x + 0.5f) / (float)(n * sub), (y + 0.5f) / (float)(n * sub));
            if (w.z > 0.0f)
                sum += rgb[3 * ((y / sub) * n + x / sub) + 1] * w.z;
        }
    return RHO / PI * sum * 4.0 * PI / ((double)n * sub * n * sub);
}

static void image_light_case(const float *rgb, int n, int nee, unsigned spp, const char *name)
{
    RenderScene scene;
    plane_scene(&scene, 0.0f);
    Light light = light_of(LIGHT_IMAGE_INFINITE, 1.0f);
    for (int i = 0; i < 3; ++i)
        light.light_from_world[i][i] = 1.0f;
    char error[256];
    assert_int_equal(render_scene_add_image_light(&scene, &light, (uint32_t)n, (uint32_t)n, rgb, error, sizeof error),
                     0);
    render_and_check(&scene, nee, spp, plane_under_image(rgb, n), name);
}

/* A constant image is a uniform infinite light; a single bright texel is
 * found by both light sampling and BSDF sampling. */
static void test_environment_image(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    float *constant = environment(8, 2.0f, 0, 0, 2.0f);
    image_light_case(constant, 8, 1, 16, "constant image, light sampling");
    image_light_case(constant, 8, 0, 16, "constant image, BSDF sampling");
    free(constant);
    float *bright = environment(16, 0.1f, 9, 6, 1000.0f);
    image_light_case(bright, 16, 1, 64, "one bright texel, light sampling");
    image_light_case(bright, 16, 0, 256, "one bright texel, BSDF sampling");
    free(bright);
}

/* The mapping round-trips and is equal-area: uniform points of the square
 * give directions whose z and z^2 average 0 and 1/3. */
static void test_equal_area_mapping(void **state)
{
    (void)state;
    const int n = 512;
    double z = 0.0, z2 = 0.0, worst = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            float u = (x + 0.5f) / n, v = (y + 0.5f) / n, u2, v2;
            Vec3 w = equal_area_square_to_sphere(u, v);
            assert_true(fabs(w.x * w.x + w.y * w.y + w.z * w.z - 1.0) < 1e-5);
            equal_area_sphere_to_square(w, &u2, &v2);
            worst = fmax(worst, fmax(fabs(u2 - u), fabs(v2 - v)));
            z += w.z;
            z2 += w.z * w.z;
        }
    z /= (double)n * n;
    z2 /= (double)n * n;
    printf("  round trip error %.2g, mean z %.2g, mean z^2 %.6f\n", worst, z, z2);
    assert_true(worst < 1e-5);
    assert_true(fabs(z) < 1e-4 && fabs(z2 - 1.0 / 3.0) < 1e-4);
    /* pbrt-v4's orientation: the square's centre is +z, its corners -z. */
    assert_true(equal_area_square_to_sphere(0.5f, 0.5f).z > 0.9999f);
    assert_true(equal_area_square_to_sphere(0.0f, 0.0f).z < -0.9999f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equal_area_mapping),
        cmocka_unit_test(test_point_light),
        cmocka_unit_test(test_spot_light),
        cmocka_unit_test(test_distant_light),
        cmocka_unit_test(test_vertex_normals_shade),
        cmocka_unit_test(test_film_response),
        cmocka_unit_test(test_goniometric_and_projection_lights),
        cmocka_unit_test(test_environment_image),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
