/* The light types against closed forms, rendered by the path tracer: a
 * diffuse plane of albedo rho lit by a point, spot or distant light
 * reflects rho / pi times the irradiance; an environment image lights a
 * diffuse plane with rho / pi times its cosine-weighted integral, computed
 * here by quadrature over the image, the same with light sampling (the
 * image's distribution) and without (BSDF sampling only). The image mean
 * must lie within 5 standard errors (from the pixels) of the value. */
#include "cl/cl_device.h"
#include "equal_area.h"
#include "lights.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "sample_streams.h"
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

/* A diffuse material of reflectance rho (0 for emitters); its index. */
static int diffuse_material(RenderScene *scene, float rho)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_DIFFUSE;
    m.reflectance[0] = m.reflectance[1] = m.reflectance[2] = rho;
    return render_scene_add_material(scene, &m);
}

/* A diffuse square [-10, 10]^2 at z = 0 facing +z, seen from (x, 0, 2)
 * looking straight down through a narrow field of view. */
static void plane_scene(RenderScene *scene, float x)
{
    render_scene_init(scene);
    int material = diffuse_material(scene, RHO);
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

/* Renders (direct light only unless max_depth says more) and checks the
 * image mean of the green channel against `expected`; returns its
 * per-pixel variance. */
static double render_checked(RenderScene *scene, int nee, unsigned spp, double expected, const char *name)
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
    double mean = sum / (double)pixels, variance = fmax(sum2 / (double)pixels - mean * mean, 0.0);
    double standard_error = sqrt(variance / (double)pixels);
    printf("  %-44s mean %.6f expected %.6f (standard error %.6f)\n", name, mean, expected, standard_error);
    assert_true(fabs(mean - expected) <= 5.0 * standard_error + 2e-4 * expected);
    render_output_free(&out);
    return variance;
}

/* render_checked, then the scene is destroyed. */
static void render_and_check(RenderScene *scene, int nee, unsigned spp, double expected, const char *name)
{
    render_checked(scene, nee, spp, expected, name);
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

/* A sphere light of radiance L, radius r and centre at height h over the
 * plane, fully above its horizon (h > r), lights the point seen as a
 * point light of intensity pi r^2 L at its centre would: E = pi L r^2 h /
 * d^3 at distance d (L is chosen to make the pixel 0.1). Found by light
 * sampling (the cone the sphere subtends, with MIS against BSDF sampling,
 * whose density at a hit must be the cone's for the sum to be right) and
 * by BSDF sampling alone; the light one-sided, two-sided, and one-sided
 * turned inward (ReverseOrientation), which leaves the plane dark. Close
 * to a small sphere (the first case) sampling by area was noisy: the
 * standard errors printed compare. */
static void test_sphere_light(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const struct {
        float x, h, radius;
        const char *name;
    } cases[] = {{0.3f, 0.25f, 0.1f, "close"}, {2.0f, 1.5f, 0.2f, "far"}, {30.0f, 40.0f, 0.05f, "very far"}};
    const char *sides[] = {"1-sided", "2-sided", "inward"};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k)
        for (int nee = 1; nee >= 0; --nee)
            for (int side = 0; side < 3; ++side) {
                /* BSDF sampling alone rarely finds the very far one. */
                if (!nee && k == 2)
                    continue;
                RenderScene scene;
                plane_scene(&scene, 0.0f);
                int material = diffuse_material(&scene, 0.0f);
                double d = sqrt((double)cases[k].x * cases[k].x + (double)cases[k].h * cases[k].h);
                double lit = RHO * cases[k].radius * cases[k].radius * cases[k].h / (d * d * d);
                const float L = (float)(0.1 / lit), centre[3] = {cases[k].x, 0.0f, cases[k].h}, emission[3] = {L, L, L};
                assert_int_equal(
                    render_scene_add_sphere(&scene, centre, cases[k].radius, material, emission, side == 1, side == 2),
                    0);
                char name[96];
                snprintf(name, sizeof name, "%s sphere, %s, %s", cases[k].name, sides[side],
                         nee ? "light sampling" : "BSDF sampling");
                render_and_check(&scene, nee, nee ? 16 : 256, side == 2 ? 0.0 : lit * L, name);
            }
}

/* Veach's row: a diffuse plane lit by two small close spheres and one far
 * sphere 200 times as powerful as both, beside a one-sided triangle light
 * facing away. Picking by power sends nearly every light sample to the far
 * sphere; the light tree (pbrt-v4's bvh) weighs the close ones by their
 * distance and leaves the triangle out. Both find each sphere's closed
 * form (test_sphere_light), the tree with at least 4 times less variance. */
static void test_light_tree_on_veach_row(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const struct {
        float x, y, h, radius;
        double power; /* relative: L r^2 */
    } spheres[] = {{0.3f, 0.0f, 0.25f, 0.05f, 1.0}, {-0.6f, 0.4f, 0.7f, 0.15f, 1.0}, {8.0f, 0.0f, 10.0f, 1.0f, 400.0}};
    double variance[2], expected = 0.0;
    for (int tree = 0; tree <= 1; ++tree) {
        RenderScene scene;
        plane_scene(&scene, 0.0f);
        int material = diffuse_material(&scene, 0.0f);
        expected = 0.0;
        for (size_t k = 0; k < sizeof spheres / sizeof *spheres; ++k) {
            double d = sqrt((double)spheres[k].x * spheres[k].x + (double)spheres[k].y * spheres[k].y +
                            (double)spheres[k].h * spheres[k].h);
            float L = (float)(spheres[k].power / (spheres[k].radius * spheres[k].radius));
            const float centre[3] = {spheres[k].x, spheres[k].y, spheres[k].h}, emission[3] = {L, L, L};
            assert_int_equal(render_scene_add_sphere(&scene, centre, spheres[k].radius, material, emission, 0, 0), 0);
            expected += RHO * spheres[k].radius * spheres[k].radius * spheres[k].h / (d * d * d) * L;
        }
        const float a[3] = {-2.0f, 0.0f, 1.0f}, b[3] = {-1.5f, 0.0f, 1.0f}, c[3] = {-2.0f, 0.5f, 1.0f};
        const float bright[3] = {1e3f, 1e3f, 1e3f};
        assert_int_equal(render_scene_add_triangle(&scene, a, b, c, material, bright, 0, 0), 0); /* faces +z */
        scene.constants.integrator.light_sampler = tree ? LIGHT_SAMPLER_TREE : LIGHT_SAMPLER_POWER;
        variance[tree] =
            render_checked(&scene, 1, 16, expected, tree ? "Veach's row, light tree" : "Veach's row, by power");
        render_scene_destroy(&scene);
    }
    printf("  per-pixel variance: by power %.4g, light tree %.4g (%.1fx less)\n", variance[0], variance[1],
           variance[0] / variance[1]);
    assert_true(variance[1] * 4.0 < variance[0]);
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

/* --- Sphere lights: cone sampling (lights.h) on the host. --- */

typedef struct {
    double x, y, z;
} Vec3d;

static Vec3d vec3d(Vec3 v)
{
    Vec3d d = {v.x, v.y, v.z};
    return d;
}

static Vec3d d_sub(Vec3d a, Vec3d b)
{
    Vec3d d = {a.x - b.x, a.y - b.y, a.z - b.z};
    return d;
}

static double d_dot(Vec3d a, Vec3d b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static double d_length(Vec3d a)
{
    return sqrt(d_dot(a, a));
}

/* The angle between a and b, by atan2 of |a x b| and a . b: precise for the
 * tiny angles of a far sphere's cone, where acos of the dot product is not. */
static double d_angle(Vec3d a, Vec3d b)
{
    Vec3d c = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return atan2(d_length(c), d_dot(a, b));
}

/* One emitting sphere (the only primitive) as light_sample sees it. */
typedef struct {
    Primitive sphere;
    Light light;
    Scene scene;
} SphereLight;

static void sphere_light(SphereLight *l, const float centre[3], float radius, int two_sided)
{
    memset(l, 0, sizeof *l);
    memcpy(l->sphere.a, centre, sizeof l->sphere.a);
    l->sphere.b[0] = radius;
    l->sphere.kind = PRIM_SPHERE;
    l->sphere.light = 0;
    l->light.type = LIGHT_AREA;
    l->light.primitive = 0;
    l->light.area = (float)(4.0 * PI * radius * radius);
    l->light.two_sided = two_sided ? 1u : 0u;
    l->light.pick_probability = 1.0f;
    l->light.radiance[0] = l->light.radiance[1] = l->light.radiance[2] = 1.0f;
    l->scene.primitives = &l->sphere;
}

/* The first hit (t > 0) along the ray p + t w (w unit) of the sphere, in
 * double, and the square root of the discriminant (small for a grazing ray,
 * whose t rounding moves far); 0 if it misses. */
static int hit_sphere(const SphereLight *l, Vec3 p, Vec3 w, double *t, double *root)
{
    Vec3d to_centre = d_sub(vec3d(vec3_from(l->sphere.a)), vec3d(p)), wd = vec3d(w);
    double r = l->sphere.b[0], b = d_dot(wd, to_centre) / d_length(wd);
    double c = (d_length(to_centre) - r) * (d_length(to_centre) + r);
    double discriminant = b * b - c;
    if (discriminant < 0.0 || (c > 0.0 && b <= 0.0))
        return 0;
    *root = sqrt(discriminant);
    /* Outside, the nearer root without cancellation; inside, the positive one. */
    *t = c > 0.0 ? c / (b + *root) : b + *root;
    return 1;
}

/* From points at distances d (in radii) from a sphere light, from the
 * margin of its surface (d^2 = 1.0002) to 10^5 (a cone of 10^-5 radians):
 * every sample lies in the cone of directions the sphere subtends and
 * reaches its near side at the reported distance; the density is the cone's
 * uniform 1 / (2 pi (1 - cos theta_max)) and is the one area_light_pdf gives
 * the hit (as MIS needs); and (1 - cos theta) / (1 - cos theta_max) and phi
 * are uniform over the cone (8 x 8 cells of a stratified grid of samples
 * hold within 15% of their share). */
static void test_sphere_light_cone_sampling(void **state)
{
    (void)state;
    const float centre[3] = {0.3f, -0.2f, 0.5f}, radius = 0.25f;
    const double distances[] = {sqrt(1.0002), 1.01, 1.5, 3.0, 30.0, 1e3, 1e5};
    SphereLight l;
    sphere_light(&l, centre, radius, 0);
    const Vec3d c = vec3d(vec3_from(centre));
    for (size_t k = 0; k < sizeof distances / sizeof *distances; ++k) {
        /* p along an arbitrary direction from the centre. */
        Vec3d away = {0.48, -0.6, 0.64};
        Vec3 p = vec3((float)(c.x + radius * distances[k] * away.x), (float)(c.y + radius * distances[k] * away.y),
                      (float)(c.z + radius * distances[k] * away.z));
        Vec3d to_centre = d_sub(c, vec3d(p));
        double d = d_length(to_centre), sin_max = radius / d;
        double theta_max = asin(sin_max), one_minus_cos_max = 2.0 * sin(theta_max / 2.0) * sin(theta_max / 2.0);
        double expected_pdf = 1.0 / (2.0 * PI * one_minus_cos_max);
        Vec3d s_axis, t_axis;
        {
            Vec3 axis = v_normalize(vec3((float)to_centre.x, (float)to_centre.y, (float)to_centre.z)), s, t;
            v_basis(axis, &s, &t);
            s_axis = vec3d(s);
            t_axis = vec3d(t);
        }
        enum { GRID = 128, CELLS = 8 };
        int counts[CELLS][CELLS] = {{0}};
        double worst_angle = 0.0, worst_distance = 0.0, worst_pdf = 0.0;
        for (int i = 0; i < GRID; ++i)
            for (int j = 0; j < GRID; ++j) {
                LightSample ls;
                float u1 = (i + 0.5f) / GRID, u2 = (j + 0.5f) / GRID;
                assert_int_equal(light_sample(&l.scene, &l.light, p, u1, u2, &ls), 1);
                Vec3d wi = vec3d(ls.wi);
                double theta = d_angle(wi, to_centre);
                /* Inside the cone, to float rounding of wi (about 1e-7). */
                worst_angle = fmax(worst_angle, theta - theta_max);
                assert_true(theta <= theta_max * (1.0 + 1e-3) + 3e-7);
                /* The reported distance is the near side's: the ray, in
                 * double, hits the sphere first there (checked where not
                 * grazing; a grazing ray may even miss by rounding: then
                 * the point must be on the silhouette). */
                double t, root;
                Vec3d q = {p.x + ls.distance * wi.x, p.y + ls.distance * wi.y, p.z + ls.distance * wi.z};
                Vec3d normal = d_sub(q, c);
                double on_sphere = fabs(d_length(normal) - radius) / radius;
                assert_true(on_sphere < 1e-6 * (1.0 + d / radius));
                /* The near side: no farther than the silhouette's tangent
                 * points (the far side is all farther). */
                assert_true(ls.distance <= sqrt(d * d - (double)radius * radius) * (1.0 + 1e-5));
                if (!hit_sphere(&l, p, ls.wi, &t, &root))
                    assert_true(theta >= theta_max * (1.0 - 1e-3) - 3e-7);
                else if (root > 0.1 * radius)
                    /* Relative, or to the sphere's size where p nearly touches it
                     * (the rounding of p's coordinates alone is 1e-3 of the
                     * distance there). */
                    worst_distance = fmax(worst_distance, fabs(t - ls.distance) / (ls.distance + 1e-2 * radius));
                /* The density: the cone's, and area_light_pdf's for the hit. */
                worst_pdf = fmax(worst_pdf, fabs(ls.pdf - expected_pdf) / expected_pdf);
                Vec3 n = v_normalize(vec3((float)normal.x, (float)normal.y, (float)normal.z));
                float cos_light = -v_dot(n, ls.wi);
                assert_true(area_light_pdf(&l.scene, &l.light, p, ls.distance, fmaxf(cos_light, 1e-6f)) == ls.pdf);
                /* The cell of (1 - cos theta) / (1 - cos theta_max), phi. */
                double one_minus_cos = 2.0 * sin(theta / 2.0) * sin(theta / 2.0);
                double phi = atan2(d_dot(wi, t_axis), d_dot(wi, s_axis));
                int a = (int)(one_minus_cos / one_minus_cos_max * CELLS);
                int b = (int)((phi < 0.0 ? phi + 2.0 * PI : phi) / (2.0 * PI) * CELLS);
                ++counts[a < CELLS ? a : CELLS - 1][b < CELLS ? b : CELLS - 1];
            }
        int fewest = GRID * GRID, most = 0;
        for (int a = 0; a < CELLS; ++a)
            for (int b = 0; b < CELLS; ++b) {
                fewest = counts[a][b] < fewest ? counts[a][b] : fewest;
                most = counts[a][b] > most ? counts[a][b] : most;
            }
        const double share = (double)(GRID * GRID) / (CELLS * CELLS);
        printf("  d = %-9.6g r: theta_max %.3g, pdf error %.2g, distance error %.2g, past the cone by %.2g rad, "
               "cells %d..%d of %.0f\n",
               distances[k], theta_max, worst_pdf, worst_distance, worst_angle, fewest, most, share);
        assert_true(worst_pdf < 1e-5);
        assert_true(worst_distance < 1e-3);
        assert_true(fewest >= 0.85 * share && most <= 1.15 * share);
    }
}

/* The cone density integrates to 1 over the directions that reach the
 * sphere: the mean of 4 pi area_light_pdf over uniform directions (0 for
 * those that miss it) is 1 within 5 standard errors. Inside the sphere the
 * density is the area one, light_sample's and area_light_pdf's alike. */
static void test_sphere_light_density(void **state)
{
    (void)state;
    const float centre[3] = {0.3f, -0.2f, 0.5f}, radius = 0.25f;
    SphereLight l;
    sphere_light(&l, centre, radius, 0);
    const double distances[] = {1.01, 1.5, 3.0};
    TestRng rng = test_rng(5);
    for (size_t k = 0; k < sizeof distances / sizeof *distances; ++k) {
        Vec3 p = vec3(centre[0], centre[1] + (float)(radius * distances[k]), centre[2]);
        const int n = 400000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            double z = 1.0 - 2.0 * test_rng_uniform(&rng), phi = 2.0 * PI * test_rng_uniform(&rng);
            double r = sqrt(fmax(0.0, 1.0 - z * z));
            Vec3 w = vec3((float)(r * cos(phi)), (float)(r * sin(phi)), (float)z);
            double t, root;
            if (!hit_sphere(&l, p, w, &t, &root))
                continue;
            Vec3 q = v_add(p, v_scale(w, (float)t));
            float cos_light = -v_dot(surface_normal(&l.sphere, q), w);
            double f = 4.0 * PI * area_light_pdf(&l.scene, &l.light, p, (float)t, fmaxf(cos_light, 1e-6f));
            sum += f;
            sum2 += f * f;
        }
        double mean = sum / n, standard_error = sqrt((sum2 / n - mean * mean) / n);
        printf("  d = %.2f r: integral of the density %.5f (standard error %.5f)\n", distances[k], mean,
               standard_error);
        assert_true(fabs(mean - 1.0) <= 5.0 * standard_error);
    }

    /* Inside: area sampling, the same density both ways. */
    Vec3 inside = vec3(centre[0] + 0.1f, centre[1], centre[2] - 0.05f);
    for (int i = 0; i < 64; ++i) {
        LightSample ls;
        l.light.two_sided = 1u;
        if (!light_sample(&l.scene, &l.light, inside, (i + 0.5f) / 64.0f, (float)test_rng_uniform(&rng), &ls))
            continue;
        Vec3 q = v_add(inside, v_scale(ls.wi, ls.distance));
        float cos_light = fabsf(v_dot(surface_normal(&l.sphere, q), ls.wi));
        float pdf = area_light_pdf(&l.scene, &l.light, inside, ls.distance, cos_light);
        assert_true(fabsf(pdf - ls.pdf) <= 1e-4f * ls.pdf);
        assert_true(fabsf(ls.pdf - ls.distance * ls.distance / (cos_light * l.light.area)) <= 1e-4f * ls.pdf);
    }
}

/* --- Triangle lights: spherical triangle sampling (lights.h) on the host. --- */

static Vec3d d_cross(Vec3d a, Vec3d b)
{
    Vec3d c = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return c;
}

static Vec3d d_unit(Vec3d a)
{
    double l = d_length(a);
    Vec3d u = {a.x / l, a.y / l, a.z / l};
    return u;
}

/* The solid angle of triangle (v0, v1, v2) from p, in double. */
static double solid_angle_d(Vec3d p, Vec3d v0, Vec3d v1, Vec3d v2)
{
    Vec3d a = d_unit(d_sub(v0, p)), b = d_unit(d_sub(v1, p)), c = d_unit(d_sub(v2, p));
    return fabs(2.0 * atan2(d_dot(a, d_cross(b, c)), 1.0 + d_dot(a, b) + d_dot(a, c) + d_dot(b, c)));
}

static Vec3d d_mid(Vec3d a, Vec3d b)
{
    Vec3d m = {(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
    return m;
}

/* One emitting triangle (the only primitive) as light_sample sees it. */
typedef struct {
    Primitive triangle;
    Light light;
    Scene scene;
    Vec3d v[3];
} TriangleLight;

static void triangle_light(TriangleLight *l, const float v[3][3], int two_sided)
{
    memset(l, 0, sizeof *l);
    for (int k = 0; k < 3; ++k) {
        l->triangle.a[k] = v[0][k];
        l->triangle.b[k] = v[1][k] - v[0][k];
        l->triangle.c[k] = v[2][k] - v[0][k];
    }
    l->triangle.kind = PRIM_TRIANGLE;
    for (int i = 0; i < 3; ++i)
        l->v[i] = vec3d(vec3_from(v[i]));
    l->light.type = LIGHT_AREA;
    l->light.primitive = 0;
    l->light.area = (float)(0.5 * d_length(d_cross(d_sub(l->v[1], l->v[0]), d_sub(l->v[2], l->v[0]))));
    l->light.two_sided = two_sided ? 1u : 0u;
    l->light.pick_probability = 1.0f;
    l->light.radiance[0] = l->light.radiance[1] = l->light.radiance[2] = 1.0f;
    l->scene.primitives = &l->triangle;
}

/* The barycentrics (of v1, v2) and distance of the ray p + t w's meeting
 * with the triangle's plane, in double (Moller-Trumbore); 0 if parallel. */
static int ray_triangle(const TriangleLight *l, Vec3d p, Vec3d w, double *b1, double *b2, double *t)
{
    Vec3d e1 = d_sub(l->v[1], l->v[0]), e2 = d_sub(l->v[2], l->v[0]), s = d_sub(p, l->v[0]);
    Vec3d s1 = d_cross(w, e2), s2 = d_cross(s, e1);
    double divisor = d_dot(s1, e1);
    if (divisor == 0.0)
        return 0;
    *b1 = d_dot(s, s1) / divisor;
    *b2 = d_dot(w, s2) / divisor;
    *t = d_dot(e2, s2) / divisor;
    return 1;
}

/* From points whose view of a triangle light spans 1e-5 to 2 pi - 0.01
 * steradians: light_sample's density is area_light_pdf's for the same hit
 * (as MIS needs); where it samples by solid angle (between pbrt-v4's limits,
 * 3e-4 and 6.22 sr, and close: area > 0.1 distance^2) it is uniform in
 * solid angle, 1 / (solid angle), and the samples reach the triangle's four
 * half-size corner and middle triangles in proportion to their solid
 * angles (to 0.01, on a stratified 128 x 128 grid); elsewhere it is the
 * area density, and they reach each a quarter. The spherical triangle
 * sampler alone is checked the same way wherever pbrt-v4 would use it. */
static void test_triangle_light_sampling(void **state)
{
    (void)state;
    const float v[3][3] = {{-0.5f, -0.3f, 1.0f}, {0.6f, -0.2f, 1.2f}, {0.1f, 0.7f, 0.9f}};
    TriangleLight l;
    triangle_light(&l, v, 1);
    Vec3d centroid = {(l.v[0].x + l.v[1].x + l.v[2].x) / 3, (l.v[0].y + l.v[1].y + l.v[2].y) / 3,
                      (l.v[0].z + l.v[1].z + l.v[2].z) / 3};
    /* Along the normal (roughly) from the centroid, at these distances. */
    Vec3d normal = d_unit(d_cross(d_sub(l.v[1], l.v[0]), d_sub(l.v[2], l.v[0])));
    const double heights[] = {-0.002, -0.05, 0.3, -1.0, 3.0, 30.0, -300.0};
    for (size_t k = 0; k < sizeof heights / sizeof *heights; ++k) {
        Vec3d pd = {centroid.x + heights[k] * (normal.x + 0.1), centroid.y + heights[k] * (normal.y - 0.2),
                    centroid.z + heights[k] * normal.z};
        Vec3 p = vec3((float)pd.x, (float)pd.y, (float)pd.z);
        pd = vec3d(p);
        double solid_angle = solid_angle_d(pd, l.v[0], l.v[1], l.v[2]);
        int in_range = solid_angle >= 3e-4 && solid_angle <= 6.22;
        int close = l.light.area > 0.1 * d_dot(d_sub(centroid, pd), d_sub(centroid, pd));
        /* The corner triangles (at v0, v1, v2) and the middle one. */
        Vec3d m01 = d_mid(l.v[0], l.v[1]), m12 = d_mid(l.v[1], l.v[2]), m20 = d_mid(l.v[2], l.v[0]);
        double parts[4] = {solid_angle_d(pd, l.v[0], m01, m20), solid_angle_d(pd, m01, l.v[1], m12),
                           solid_angle_d(pd, m20, m12, l.v[2]), solid_angle_d(pd, m01, m12, m20)};
        /* light_sample, then (sampler_alone) the spherical sampler. */
        for (int sampler_alone = 0; sampler_alone <= in_range; ++sampler_alone) {
            int spherical = sampler_alone || (in_range && close);
            Vec3 dirs[3];
            for (int c = 0; c < 3; ++c)
                dirs[c] = v_normalize(v_sub(vec3((float)l.v[c].x, (float)l.v[c].y, (float)l.v[c].z), p));
            enum { GRID = 128 };
            int counts[4] = {0};
            double worst_pdf = 0.0, worst_outside = 0.0, worst_match = 0.0;
            for (int i = 0; i < GRID; ++i)
                for (int j = 0; j < GRID; ++j) {
                    LightSample ls;
                    float u1 = (i + 0.5f) / GRID, u2 = (j + 0.5f) / GRID;
                    if (sampler_alone) {
                        assert_true(sample_spherical_triangle(dirs[0], dirs[1], dirs[2], u1, u2, &ls.wi));
                        Vec3 to_light = v_sub(triangle_point_along(&l.triangle, p, ls.wi), p);
                        ls.distance = v_length(to_light);
                        ls.wi = v_scale(to_light, 1.0f / ls.distance);
                        ls.pdf = (float)(1.0 / solid_angle);
                    } else {
                        assert_int_equal(light_sample(&l.scene, &l.light, p, u1, u2, &ls), 1);
                    }
                    double b1, b2, t;
                    assert_true(ray_triangle(&l, pd, vec3d(ls.wi), &b1, &b2, &t));
                    /* The sample's ray meets the triangle at the sample. */
                    worst_outside = fmax(worst_outside, fmax(-fmin(b1, b2), b1 + b2 - 1.0));
                    worst_match = fmax(worst_match, fabs(t - ls.distance) / ls.distance);
                    float cos_light =
                        fabsf(v_dot(surface_normal(&l.triangle, v_add(p, v_scale(ls.wi, ls.distance))), ls.wi));
                    float pdf = area_light_pdf(&l.scene, &l.light, p, ls.distance, cos_light);
                    double expected =
                        spherical ? 1.0 / solid_angle : ls.distance * ls.distance / (cos_light * l.light.area);
                    if (!sampler_alone)
                        assert_true(fabsf(pdf - ls.pdf) <= 1e-6f * ls.pdf);
                    worst_pdf = fmax(worst_pdf, fabs(ls.pdf - expected) / expected);
                    double b0 = 1.0 - b1 - b2;
                    ++counts[b0 > 0.5 ? 0 : b1 > 0.5 ? 1 : b2 > 0.5 ? 2 : 3];
                }
            double worst_share = 0.0;
            for (int c = 0; c < 4; ++c) {
                double share = spherical ? parts[c] / solid_angle : 0.25;
                worst_share = fmax(worst_share, fabs(counts[c] / (double)(GRID * GRID) - share));
            }
            printf("  height %-7g: solid angle %.3g sr (%s), pdf error %.2g, outside by %.2g, distance error %.2g, "
                   "shares off by %.3f\n",
                   heights[k], solid_angle,
                   sampler_alone ? "the spherical sampler alone"
                   : spherical   ? "spherical"
                                 : "by area",
                   worst_pdf, worst_outside, worst_match, worst_share);
            assert_true(worst_pdf < (spherical ? 2e-3 : 1e-4));
            assert_true(worst_outside < 1e-4 && worst_match < 1e-3);
            assert_true(worst_share < 0.01);
        }
    }

    /* One-sided: dark from behind, lit from the front, either way. */
    triangle_light(&l, v, 0);
    for (int side = -1; side <= 1; side += 2) {
        for (int near = 0; near <= 1; ++near) {
            double h = side * (near ? 0.3 : 300.0);
            Vec3 p = vec3((float)(centroid.x + h * normal.x), (float)(centroid.y + h * normal.y),
                          (float)(centroid.z + h * normal.z));
            LightSample ls;
            assert_int_equal(light_sample(&l.scene, &l.light, p, 0.3f, 0.6f, &ls), side > 0);
        }
    }
}

/* The density integrates to 1 over the directions that reach the triangle,
 * by solid angle and by area: the mean of 4 pi area_light_pdf over uniform
 * directions (0 for those that miss) is 1 within 5 standard errors. */
static void test_triangle_light_density(void **state)
{
    (void)state;
    const float v[3][3] = {{-0.5f, -0.3f, 1.0f}, {0.6f, -0.2f, 1.2f}, {0.1f, 0.7f, 0.9f}};
    TriangleLight l;
    triangle_light(&l, v, 1);
    /* Spherical, spherical, by area (6.22 sr and more, just off the centroid). */
    const Vec3 points[] = {vec3(0.0f, 0.0f, 0.0f), vec3(0.05f, 0.05f, 1.06f), vec3(0.0663f, 0.0671f, 1.0352f)};
    TestRng rng = test_rng(9);
    for (size_t k = 0; k < sizeof points / sizeof *points; ++k) {
        const int n = 400000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            double z = 1.0 - 2.0 * test_rng_uniform(&rng), phi = 2.0 * PI * test_rng_uniform(&rng);
            double r = sqrt(fmax(0.0, 1.0 - z * z));
            Vec3 w = vec3((float)(r * cos(phi)), (float)(r * sin(phi)), (float)z);
            double b1, b2, t;
            if (!ray_triangle(&l, vec3d(points[k]), vec3d(w), &b1, &b2, &t) || t <= 0.0 || b1 < 0.0 || b2 < 0.0 ||
                b1 + b2 > 1.0)
                continue;
            float cos_light = fabsf(v_dot(surface_normal(&l.triangle, points[k]), w));
            double f = 4.0 * PI * area_light_pdf(&l.scene, &l.light, points[k], (float)t, cos_light);
            sum += f;
            sum2 += f * f;
        }
        double mean = sum / n, standard_error = sqrt((sum2 / n - mean * mean) / n);
        Vec3d pd = vec3d(points[k]);
        printf("  solid angle %.3g sr: integral of the density %.5f (standard error %.5f)\n",
               solid_angle_d(pd, l.v[0], l.v[1], l.v[2]), mean, standard_error);
        assert_true(fabs(mean - 1.0) <= 5.0 * standard_error + 1e-6);
    }
}

/* The irradiance at the origin (normal +z) from a polygon of radiance L
 * (Lambert's formula): L / 2 times the sum over its edges of the angle
 * they subtend times the z of their plane's unit normal. */
static double polygon_irradiance(const double (*v)[3], int count, double L)
{
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        Vec3d a = {v[i][0], v[i][1], v[i][2]},
              b = {v[(i + 1) % count][0], v[(i + 1) % count][1], v[(i + 1) % count][2]};
        Vec3d n = d_unit(d_cross(a, b));
        sum += d_angle(a, b) * n.z;
    }
    return 0.5 * L * fabs(sum);
}

/* A rectangle light of two one-sided triangles facing down at height h
 * over the plane, beside the point seen: rho / pi times its irradiance
 * (polygon_irradiance). Close it is sampled by solid angle (spherical
 * triangles), farther by area; by light sampling with MIS (the densities
 * must agree for the sum to be right) and, close, by BSDF sampling alone;
 * facing up instead, it leaves the plane dark. */
static void test_triangle_light(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const struct {
        double x0, x1, half_y, h;
        const char *name;
    } cases[] = {{0.1, 0.8, 0.4, 0.3, "close"}, {3.0, 3.2, 0.1, 2.0, "middle"}, {30.0, 30.2, 0.1, 20.0, "far"}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k)
        for (int nee = 1; nee >= 0; --nee)
            for (int up = 0; up <= 1; ++up) {
                /* BSDF sampling alone rarely finds the smaller ones. */
                if (!nee && k > 0)
                    continue;
                double x0 = cases[k].x0, x1 = cases[k].x1, y = cases[k].half_y, h = cases[k].h;
                const double corners[4][3] = {{x0, -y, h}, {x0, y, h}, {x1, y, h}, {x1, -y, h}};
                double lit = RHO / PI * polygon_irradiance(corners, 4, 1.0);
                RenderScene scene;
                plane_scene(&scene, 0.0f);
                int material = diffuse_material(&scene, 0.0f);
                const float L = (float)(0.1 / lit), emission[3] = {L, L, L};
                float c[4][3];
                for (int i = 0; i < 4; ++i)
                    for (int j = 0; j < 3; ++j)
                        c[i][j] = (float)corners[i][j];
                /* Clockwise from above: the normal points down (up: reversed). */
                int b = up ? 3 : 1, d = up ? 1 : 3;
                assert_int_equal(render_scene_add_triangle(&scene, c[0], c[b], c[2], material, emission, 0, 0), 0);
                assert_int_equal(render_scene_add_triangle(&scene, c[0], c[2], c[d], material, emission, 0, 0), 0);
                char name[96];
                snprintf(name, sizeof name, "%s rectangle, %s, %s", cases[k].name, up ? "facing up" : "facing down",
                         nee ? "light sampling" : "BSDF sampling");
                render_and_check(&scene, nee, nee ? 16 : 256, up ? 0.0 : lit * L, name);
            }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equal_area_mapping),
        cmocka_unit_test(test_sphere_light_cone_sampling),
        cmocka_unit_test(test_sphere_light_density),
        cmocka_unit_test(test_triangle_light_sampling),
        cmocka_unit_test(test_triangle_light_density),
        cmocka_unit_test(test_point_light),
        cmocka_unit_test(test_spot_light),
        cmocka_unit_test(test_distant_light),
        cmocka_unit_test(test_vertex_normals_shade),
        cmocka_unit_test(test_film_response),
        cmocka_unit_test(test_goniometric_and_projection_lights),
        cmocka_unit_test(test_environment_image),
        cmocka_unit_test(test_sphere_light),
        cmocka_unit_test(test_light_tree_on_veach_row),
        cmocka_unit_test(test_triangle_light),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
