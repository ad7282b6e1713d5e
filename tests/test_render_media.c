/* Participating media rendered by the volumetric path tracer, against
 * closed forms: Beer-Lambert through an absorbing slab (also from a camera
 * inside the medium), the per-pixel transmittance of an absorbing sphere,
 * the furnace inside a scattering medium of albedo 1 (with per-channel
 * coefficients, for the spectral MIS), and emission: closed form where the
 * medium only absorbs, and the furnace again where emission balances
 * absorption; a temperature grid (from a scene file) emits its blackbody;
 * NanoVDB grids: transmittance through a box, and blackbody emission. */
#include "cl/cl_device.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "scene/spectrum.h"
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

#define SIZE 16 /* image side, pixels */

static int interface_material(RenderScene *scene)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_INTERFACE;
    return render_scene_add_material(scene, &m);
}

static int add_medium(RenderScene *scene, const float sigma_a[3], const float sigma_s[3], const float emission[3],
                      float g)
{
    Medium m;
    memset(&m, 0, sizeof m);
    memcpy(m.sigma_a, sigma_a, sizeof m.sigma_a);
    memcpy(m.sigma_s, sigma_s, sizeof m.sigma_s);
    if (emission)
        memcpy(m.emission, emission, sizeof m.emission);
    m.g = g;
    int index = render_scene_add_medium(scene, &m);
    assert_true(index >= 0);
    return index;
}

/* A sphere of medium `medium` inside, vacuum outside. */
static void medium_sphere(RenderScene *scene, const float centre[3], float radius, int medium)
{
    assert_int_equal(render_scene_add_sphere(scene, centre, radius, interface_material(scene), NULL, 0, 0), 0);
    assert_int_equal(render_scene_set_media(scene, medium, -1), 0);
}

/* Renders (spp samples) and returns the mean image (3 floats a pixel; free it). */
static float *render(RenderScene *scene, int nee, unsigned max_depth, unsigned spp)
{
    char error[256];
    scene->constants.integrator.max_depth = max_depth;
    scene->constants.integrator.flags = nee ? RENDER_NEE : 0u;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    assert_true((render_scene_features(scene) & FEATURE_MEDIA) != 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = spp;
    settings.seed = 3;
    RenderOutput out;
    if (renderer_run(&test_device, 1, scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s", error);
    assert_int_equal(out.rejected_total, 0);
    size_t n = 3 * (size_t)out.width * out.height;
    float *mean = malloc(n * sizeof *mean);
    assert_non_null(mean);
    memcpy(mean, out.pass[PASS_MEAN], n * sizeof *mean);
    render_output_free(&out);
    return mean;
}

static void orthographic(RenderScene *scene, float z)
{
    RenderCamera c;
    memset(&c, 0, sizeof c);
    c.projection = CAMERA_ORTHOGRAPHIC;
    c.position[2] = z;
    c.forward[2] = 1.0f;
    c.right[0] = 1.0f;
    c.up[1] = 1.0f;
    c.window[0] = c.window[2] = -0.5f;
    c.window[1] = c.window[3] = 0.5f;
    c.focal_distance = 1.0f;
    c.width = c.height = SIZE;
    render_scene_set_camera(scene, &c);
}

/* The plane z = z0 as two triangles 20 across, its normal along +z (up 1)
 * or -z, with medium `medium` behind it and vacuum in front. */
static void plane(RenderScene *scene, float z0, int up, int material, int medium)
{
    const float a[3] = {-10, -10, z0}, b[3] = {10, -10, z0}, c[3] = {10, 10, z0}, d[3] = {-10, 10, z0};
    assert_int_equal(render_scene_add_triangle(scene, a, up ? b : d, c, material, NULL, 0, 0), 0);
    assert_int_equal(render_scene_set_media(scene, medium, -1), 0);
    assert_int_equal(render_scene_add_triangle(scene, a, c, up ? d : b, material, NULL, 0, 0), 0);
    assert_int_equal(render_scene_set_media(scene, medium, -1), 0);
}

/* A slab 0 <= z <= 1 of an absorbing medium under a white sky, seen along
 * +z by an orthographic camera at z = camera_z: every sample is exactly
 * exp(-sigma_a * length in the slab) (Beer-Lambert). */
static void absorbing_slab(float camera_z, int camera_inside)
{
    const float sigma_a[3] = {0.5f, 1.0f, 2.0f}, none[3] = {0, 0, 0}, sky[3] = {1, 1, 1};
    RenderScene scene;
    render_scene_init(&scene);
    int medium = add_medium(&scene, sigma_a, none, NULL, 0.0f);
    int material = interface_material(&scene);
    plane(&scene, 0.0f, 0, material, medium); /* both face out of the slab */
    plane(&scene, 1.0f, 1, material, medium);
    assert_int_equal(render_scene_add_infinite_light(&scene, sky), 0);
    orthographic(&scene, camera_z);
    scene.constants.media.camera_medium = camera_inside ? medium : -1;
    float length = camera_inside ? 1.0f - camera_z : 1.0f;
    for (int nee = 0; nee <= 1; ++nee) {
        float *image = render(&scene, nee, 5, 4);
        double worst = 0.0;
        for (int p = 0; p < SIZE * SIZE; ++p)
            for (int c = 0; c < 3; ++c)
                worst = fmax(worst, fabs(image[3 * p + c] / exp(-(double)sigma_a[c] * length) - 1.0));
        printf("  absorbing slab, camera %s, %s: largest relative error %.3g\n", camera_inside ? "inside" : "outside",
               nee ? "NEE" : "no NEE", worst);
        /* Rays leave a boundary 1e-5 of its distance from the origin off
         * it (offset_origin): the slab looks that much thinner. */
        assert_true(worst < 1e-4);
        free(image);
    }
    render_scene_destroy(&scene);
}

static void test_absorbing_slab(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    absorbing_slab(-1.0f, 0);
    absorbing_slab(0.25f, 1); /* the camera's medium */
}

/* Cells of grids over the box [-3, 3]^3, GRID a side: the sphere of
 * radius 2 at the centre stays clear of the outer half cells, where
 * pbrt-v4's lookup fades to 0. */
#define GRID 6
#define CELLS (GRID * GRID * GRID)

static uint32_t lcg_state = 12345u;
static float random_in(float low, float high)
{
    lcg_state = lcg_state * 1664525u + 1013904223u;
    return low + (high - low) * (float)(lcg_state >> 8) / 16777216.0f;
}

/* A grid medium over [-3, 3]^3: uniformgrid (density: CELLS values; Le
 * scaled by a Lescale grid of one cell of 1) when rgb_sigma_a is NULL,
 * else rgbgrid (rgb_*: 3 CELLS values, rgb_le NULL for none). */
static int add_grid(RenderScene *scene, const float *density, const float sigma_a[3], const float sigma_s[3],
                    const float *le, const float *rgb_sigma_a, const float *rgb_sigma_s, const float *rgb_le, float g)
{
    Medium m;
    memset(&m, 0, sizeof m);
    m.g = g;
    for (int k = 0; k < 3; ++k) {
        m.medium_from_world[k][k] = 1.0f / 6.0f;
        m.medium_from_world[k][3] = 0.5f;
        m.size[k] = GRID;
        m.le_size[k] = 1;
    }
    m.density = m.le_scale = m.rgb_sigma_a = m.rgb_sigma_s = m.rgb_le = -1;
    if (!rgb_sigma_a) {
        const float one = 1.0f;
        m.type = MEDIUM_UNIFORM_GRID;
        memcpy(m.sigma_a, sigma_a, sizeof m.sigma_a);
        memcpy(m.sigma_s, sigma_s, sizeof m.sigma_s);
        if (le)
            memcpy(m.emission, le, sizeof m.emission);
        m.density = render_scene_add_medium_values(scene, density, CELLS);
        m.le_scale = render_scene_add_medium_values(scene, &one, 1);
    } else {
        m.type = MEDIUM_RGB_GRID;
        for (int k = 0; k < 3; ++k) {
            m.sigma_a[k] = m.sigma_s[k] = 1.0f; /* scale */
            m.emission[k] = 1.0f;               /* Lescale */
        }
        m.rgb_sigma_a = render_scene_add_medium_values(scene, rgb_sigma_a, 3 * CELLS);
        m.rgb_sigma_s = render_scene_add_medium_values(scene, rgb_sigma_s, 3 * CELLS);
        if (rgb_le)
            m.rgb_le = render_scene_add_medium_values(scene, rgb_le, 3 * CELLS);
    }
    int index = render_scene_add_medium(scene, &m);
    assert_true(index >= 0);
    return index;
}

/* A sphere of absorbing medium (radius 1) before a white sky, seen by a
 * pinhole camera from z = -3: each pixel is the average over its area of
 * exp(-sigma_a * chord), integrated here on a 16 x 16 grid of the pixel.
 * Homogeneous, every pixel must match; as a uniform grid of density 1
 * (ratio tracking: noisy), the mean difference from the closed forms must
 * be within 5 of its standard errors. */
static void absorbing_sphere(int as_grid)
{
    const float sigma_a[3] = {0.3f, 1.0f, 3.0f}, none[3] = {0, 0, 0}, sky[3] = {1, 1, 1}, centre[3] = {0, 0, 0};
    const float tan_half = 0.4f;
    RenderScene scene;
    render_scene_init(&scene);
    float density[CELLS];
    for (int i = 0; i < CELLS; ++i)
        density[i] = 1.0f;
    int medium = as_grid ? add_grid(&scene, density, sigma_a, none, NULL, NULL, NULL, NULL, 0.0f)
                         : add_medium(&scene, sigma_a, none, NULL, 0.0f);
    medium_sphere(&scene, centre, 1.0f, medium);
    assert_int_equal(render_scene_add_infinite_light(&scene, sky), 0);
    const float position[3] = {0, 0, -3}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, tan_half, tan_half, SIZE, SIZE);
    render_scene_set_camera(&scene, &camera);
    const unsigned spp = 256;
    float *image = render(&scene, 1, 5, spp);
    int sub = 16, far = 0;
    double total_error = 0.0, difference[3] = {0, 0, 0}, difference2[3] = {0, 0, 0};
    for (int y = 0; y < SIZE; ++y)
        for (int x = 0; x < SIZE; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0, sum2 = 0.0;
                for (int j = 0; j < sub; ++j)
                    for (int i = 0; i < sub; ++i) {
                        /* The ray through this point of the pixel; the scene is
                         * symmetric, so the image's orientation does not matter. */
                        double sx = (2.0 * (x + (i + 0.5) / sub) / SIZE - 1.0) * tan_half;
                        double sy = (2.0 * (y + (j + 0.5) / sub) / SIZE - 1.0) * tan_half;
                        double len = sqrt(sx * sx + sy * sy + 1.0);
                        double dx = sx / len, dy = sy / len, dz = 1.0 / len;
                        /* |o + t d|^2 = 1 with o = (0, 0, -3) */
                        double b = -3.0 * dz, disc = b * b - 8.0;
                        double chord = disc > 0.0 ? 2.0 * sqrt(disc) : 0.0;
                        (void)dx, (void)dy;
                        double v = exp(-(double)sigma_a[c] * chord);
                        sum += v;
                        sum2 += v * v;
                    }
                double n = (double)sub * sub, expected = sum / n;
                double deviation = sqrt(fmax(sum2 / n - expected * expected, 0.0));
                double error = fabs(image[3 * (y * SIZE + x) + c] - expected);
                total_error += error;
                difference[c] += image[3 * (y * SIZE + x) + c] - expected;
                difference2[c] += error * error;
                /* The pixel's only noise is where in it a sample lands. */
                if (error > 5.0 * deviation / sqrt((double)spp) + 2e-3)
                    ++far;
            }
    printf("  absorbing sphere%s: mean absolute error %.3g per value, %d of %d values off\n",
           as_grid ? " (uniform grid)" : "", total_error / (3.0 * SIZE * SIZE), far, 3 * SIZE * SIZE);
    if (!as_grid)
        assert_int_equal(far, 0);
    for (int c = 0; c < 3 && as_grid; ++c) {
        double n = SIZE * SIZE, mean = difference[c] / n;
        double standard_error = sqrt(fmax(difference2[c] / n - mean * mean, 0.0) / n);
        printf("    channel %d: mean difference %.5f (standard error %.5f)\n", c, mean, standard_error);
        assert_true(fabs(mean) <= 5.0 * standard_error + 1e-4);
    }
    free(image);
    render_scene_destroy(&scene);
}

static void test_absorbing_sphere_transmittance(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    absorbing_sphere(0);
    absorbing_sphere(1);
}

/* Renders and checks each channel's image mean against `expected`, within
 * 5 standard errors (from the pixels). */
static void check_mean(const float *image, const double expected[3], const char *name)
{
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0, sum2 = 0.0;
        for (int p = 0; p < SIZE * SIZE; ++p) {
            sum += image[3 * p + c];
            sum2 += (double)image[3 * p + c] * image[3 * p + c];
        }
        double n = SIZE * SIZE, mean = sum / n;
        double standard_error = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n);
        printf("  %-46s channel %d: mean %.5f expected %.5f (standard error %.5f)\n", name, c, mean, expected[c],
               standard_error);
        assert_true(fabs(mean - expected[c]) <= 5.0 * standard_error + 1e-4 * expected[c]);
    }
}

/* The camera inside a sphere (radius 2) of medium under a constant sky.
 * Where the medium scatters without absorbing, every direction sees the
 * sky's radiance; where its emission equals the sky's radiance, too.
 * furnace_in takes a scene holding medium `medium`, and destroys it. */
static void furnace_in(RenderScene *scene, int medium, int nee, const char *name)
{
    const float sky[3] = {1.5f, 1.5f, 1.5f}, centre[3] = {0, 0, 0};
    medium_sphere(scene, centre, 2.0f, medium);
    assert_int_equal(render_scene_add_infinite_light(scene, sky), 0);
    const float position[3] = {0, 0, 0}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 1.0f, 1.0f, SIZE, SIZE);
    render_scene_set_camera(scene, &camera);
    scene->constants.media.camera_medium = medium;
    scene->constants.integrator.rr_threshold = 0.0f; /* no roulette: its weights are not what is tested */
    float *image = render(scene, nee, 400, 64);
    const double expected[3] = {1.5, 1.5, 1.5};
    check_mean(image, expected, name);
    free(image);
    render_scene_destroy(scene);
}

static void furnace(const float sigma_a[3], const float sigma_s[3], const float *emission, float g, int nee,
                    const char *name)
{
    RenderScene scene;
    render_scene_init(&scene);
    furnace_in(&scene, add_medium(&scene, sigma_a, sigma_s, emission, g), nee, name);
}

static void test_scattering_furnace(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const float none[3] = {0, 0, 0}, grey[3] = {1, 1, 1}, coloured[3] = {0.5f, 1.0f, 2.0f};
    furnace(none, grey, NULL, 0.0f, 1, "furnace, isotropic, NEE");
    furnace(none, grey, NULL, 0.0f, 0, "furnace, isotropic, phase sampling only");
    furnace(none, coloured, NULL, 0.7f, 1, "furnace, per-channel sigma_s, g 0.7, NEE");
    furnace(none, coloured, NULL, -0.5f, 0, "furnace, per-channel sigma_s, g -0.5");
}

static void test_emission(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* Emission balancing absorption: L = Le = the sky's radiance. */
    const float sigma_a[3] = {0.5f, 1.0f, 0.2f}, sigma_s[3] = {0.5f, 0.3f, 1.0f}, le[3] = {1.5f, 1.5f, 1.5f};
    furnace(sigma_a, sigma_s, le, 0.3f, 1, "emitting furnace, NEE");
    furnace(sigma_a, sigma_s, le, 0.3f, 0, "emitting furnace, phase sampling only");

    /* An emitting, absorbing sphere (radius 2) around the camera, no sky:
     * every ray sees Le (1 - exp(-sigma_a 2)). */
    const float none[3] = {0, 0, 0}, centre[3] = {0, 0, 0}, emission[3] = {1, 2, 3};
    RenderScene scene;
    render_scene_init(&scene);
    int medium = add_medium(&scene, sigma_a, none, emission, 0.0f);
    medium_sphere(&scene, centre, 2.0f, medium);
    const float position[3] = {0, 0, 0}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 1.0f, 1.0f, SIZE, SIZE);
    render_scene_set_camera(&scene, &camera);
    scene.constants.media.camera_medium = medium;
    float *image = render(&scene, 1, 5, 4);
    double worst = 0.0;
    for (int p = 0; p < SIZE * SIZE; ++p)
        for (int c = 0; c < 3; ++c)
            worst = fmax(worst, fabs(image[3 * p + c] / (emission[c] * (1.0 - exp(-2.0 * (double)sigma_a[c]))) - 1.0));
    printf("  emitting absorbing sphere: largest relative error %.3g\n", worst);
    assert_true(worst < 1e-4);
    free(image);
    render_scene_destroy(&scene);
}

/* pbrt-v4's cloud (density 3, wispiness 1, frequency 5) over [-3, 3]^3. */
static int add_cloud(RenderScene *scene, const float sigma_a[3], const float sigma_s[3])
{
    Medium m;
    memset(&m, 0, sizeof m);
    m.type = MEDIUM_CLOUD;
    memcpy(m.sigma_a, sigma_a, sizeof m.sigma_a);
    memcpy(m.sigma_s, sigma_s, sizeof m.sigma_s);
    for (int k = 0; k < 3; ++k) {
        m.medium_from_world[k][k] = 1.0f / 6.0f;
        m.medium_from_world[k][3] = 0.5f;
    }
    const float cloud[9] = {3, 1, 5, -3, -3, -3, 6, 6, 6};
    m.density = render_scene_add_medium_values(scene, cloud, 9);
    m.le_scale = m.rgb_sigma_a = m.rgb_sigma_s = m.rgb_le = -1;
    int index = render_scene_add_medium(scene, &m);
    assert_true(index >= 0);
    return index;
}

/* Heterogeneous media: the furnace in a uniform grid of random densities
 * (scattering only), with emission balancing absorption in an RGB grid of
 * random coefficients per cell and channel, and in pbrt-v4's cloud. */
static void test_grid_furnace(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    float density[CELLS], rgb_a[3 * CELLS], rgb_s[3 * CELLS], rgb_le[3 * CELLS];
    for (int i = 0; i < CELLS; ++i)
        density[i] = random_in(0.2f, 1.0f);
    for (int i = 0; i < 3 * CELLS; ++i) {
        rgb_a[i] = random_in(0.0f, 1.0f);
        rgb_s[i] = random_in(0.0f, 1.5f);
        rgb_le[i] = 1.5f;
    }
    const float none[3] = {0, 0, 0}, coloured[3] = {0.5f, 1.0f, 2.0f};
    for (int nee = 1; nee >= 0; --nee) {
        RenderScene scene;
        render_scene_init(&scene);
        furnace_in(&scene, add_grid(&scene, density, none, coloured, NULL, NULL, NULL, NULL, 0.5f), nee,
                   nee ? "uniform grid furnace, NEE" : "uniform grid furnace, phase sampling only");
        render_scene_init(&scene);
        furnace_in(&scene, add_grid(&scene, NULL, NULL, NULL, NULL, rgb_a, rgb_s, rgb_le, -0.3f), nee,
                   nee ? "emitting RGB grid furnace, NEE" : "emitting RGB grid furnace, phase sampling only");
        render_scene_init(&scene);
        furnace_in(&scene, add_cloud(&scene, none, coloured), nee,
                   nee ? "cloud furnace, NEE" : "cloud furnace, phase sampling only");
    }
}

/* A scene file of `text` (after its header), rendered at SIZE x SIZE. */
static float *render_file(const char *name, const char *text)
{
    char path[512], error[1024];
    snprintf(path, sizeof path, "%s/%s", GMON_BINARY_DIR, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    RenderScene scene;
    SceneSummary summary;
    if (scene_convert_load(path, 0, SIZE, SIZE, 1, &scene, &summary, error, sizeof error))
        fail_msg("%s", error);
    float *image = render(&scene, 1, 5, 64);
    render_scene_destroy(&scene);
    return image;
}

/* A scene file: the camera at the origin inside a sphere (radius 2) of
 * medium `medium` (its MakeNamedMedium parameters), no light; rendered. */
static float *render_medium_file(const char *name, const char *medium)
{
    char text[4096];
    snprintf(text, sizeof text,
             "MediumInterface \"\" \"fire\"\nCamera \"perspective\" \"float fov\" 60\nWorldBegin\n"
             "MakeNamedMedium \"fire\" %s\nMediumInterface \"fire\" \"\"\nMaterial \"interface\"\n"
             "Shape \"sphere\" \"float radius\" 2\n",
             medium);
    return render_file(name, text);
}

/* Every pixel's ratio to expected[c] (independent, mean 1): their mean
 * within 4 standard errors of 1. */
static void assert_image_is(const float *image, const double expected[3], const char *what)
{
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0, squares = 0.0;
        for (int p = 0; p < SIZE * SIZE; ++p) {
            double r = image[3 * p + c] / expected[c];
            sum += r;
            squares += r * r;
        }
        double mean = sum / (SIZE * SIZE),
               error = sqrt(fmax(0.0, squares / (SIZE * SIZE) - mean * mean) / (SIZE * SIZE - 1));
        printf("  %s, channel %d: mean / expected %.5f (standard error %.5f)\n", what, c, mean, error);
        assert_true(error < 0.02);
        assert_true(fabs(mean - 1.0) < 4.0 * error + 1e-4); /* + float rounding where there is no noise */
    }
}

/* `scale` times the linear sRGB (negative channels 0) of pbrt-v4's
 * blackbody at `kelvin`, from the spectrum's XYZ. */
static void scaled_blackbody(double kelvin, double scale, double rgb[3])
{
    Spectrum b;
    double xyz[3], m[3][3];
    spectrum_blackbody(kelvin, &b);
    spectrum_to_xyz(&b, xyz);
    spectrum_srgb_from_xyz(m);
    for (int k = 0; k < 3; ++k)
        rgb[k] = scale * fmax(0.0, m[k][0] * xyz[0] + m[k][1] * xyz[1] + m[k][2] * xyz[2]);
}

static void test_temperature_grid(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* An absorbing grid at one temperature (T = (t - 100) * 2 = 3000 K)
     * over [-3, 3]^3 (constant within 2.25 of the centre) emits that
     * blackbody's RGB times Lescale as Le: every ray sees
     * Le (1 - exp(-2 sigma_a)), sigma_a = density * "sigma_a". */
    double le[3];
    scaled_blackbody(3000.0, 3.0, le);
    char grid[2048];
    int used = snprintf(grid, sizeof grid,
                        "\"string type\" \"uniformgrid\" \"integer nx\" 4 \"integer ny\" 4 \"integer nz\" 4 "
                        "\"point3 p0\" [ -3 -3 -3 ] \"point3 p1\" [ 3 3 3 ] \"rgb sigma_a\" [ 0.5 1 0.2 ] "
                        "\"rgb sigma_s\" [ 0 0 0 ] \"float temperatureoffset\" 100 \"float temperaturescale\" 2 "
                        "\"float density\" [");
    for (int i = 0; i < 64; ++i)
        used += snprintf(grid + used, sizeof grid - (size_t)used, " 0.5");
    used += snprintf(grid + used, sizeof grid - (size_t)used, " ] \"float Lescale\" [");
    for (int i = 0; i < 64; ++i)
        used += snprintf(grid + used, sizeof grid - (size_t)used, " 3");
    used += snprintf(grid + used, sizeof grid - (size_t)used, " ] \"float temperature\" [");
    for (int i = 0; i < 64; ++i)
        used += snprintf(grid + used, sizeof grid - (size_t)used, " 1600");
    snprintf(grid + used, sizeof grid - (size_t)used, " ]");
    float *a = render_medium_file("temperature-grid.pbrt", grid);
    const double sigma_a[3] = {0.25, 0.5, 0.1};
    assert_true(le[0] > le[1] && le[1] > le[2] && le[2] > 0.0);
    double expected[3];
    for (int c = 0; c < 3; ++c)
        expected[c] = le[c] * (1.0 - exp(-2.0 * sigma_a[c]));
    assert_image_is(a, expected, "temperature grid, mean / Le (1 - exp(-2 sigma_a))");
    free(a);
}

/* NanoVDB grids written by NanoVDB's own builder (build/nvdb, tests/support/
 * write_nvdb.cpp): box.nvdb's density is 1 in voxels [0, 15]^3 of side
 * 1/16 from (-0.5, -0.5, -0.5) and its box (pbrt-v4's: the active voxels'
 * world box) [-0.5, 0.5]^3; looked up trilinearly between voxels at their
 * corners, it falls to 0 over the last 1/16 before z = 0.5. An orthographic
 * camera looking along +z through it, at the constant environment of 1:
 * each pixel sees exp(-sigma_a (15.5 / 16)). The temperature grid is left
 * out by naming another. */
static void test_nanovdb_transmittance(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 -3  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [ -0.4 0.4 -0.4 0.4 ]\n"
             "Integrator \"volpath\"\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
             "MakeNamedMedium \"fog\" \"string type\" \"nanovdb\" \"string filename\" \"%s/nvdb/box.nvdb\" "
             "\"rgb sigma_a\" [ 1 2 3 ] \"rgb sigma_s\" [ 0 0 0 ] \"float scale\" 0.5 "
             "\"string temperaturename\" \"none\"\n"
             "MediumInterface \"fog\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 2\n",
             GMON_BINARY_DIR);
    float *image = render_file("nanovdb-box.pbrt", text);
    double expected[3];
    for (int c = 0; c < 3; ++c)
        expected[c] = exp(-0.5 * (c + 1) * 15.5 / 16.0);
    assert_image_is(image, expected, "nanovdb box, mean / exp(-sigma_a 15.5 / 16)");
    free(image);
}

/* box.nvdb's temperature grid is 3000 everywhere (its background): with
 * the offset 1000 and scale 1.25, 2500 K. The camera at its centre, in a
 * density so absorbing (sigma_a 200, at least 87 optical depths to the box's
 * side) that every ray sees Lescale times that blackbody's RGB. */
static void test_nanovdb_temperature(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    char medium[1024];
    snprintf(medium, sizeof medium,
             "\"string type\" \"nanovdb\" \"string filename\" \"%s/nvdb/box.nvdb\" \"rgb sigma_a\" [ 1 1 1 ] "
             "\"rgb sigma_s\" [ 0 0 0 ] \"float scale\" 200 \"float Lescale\" 3 \"float temperatureoffset\" 1000 "
             "\"float temperaturescale\" 1.25",
             GMON_BINARY_DIR);
    float *image = render_medium_file("nanovdb-temperature.pbrt", medium);
    double expected[3];
    scaled_blackbody(2500.0, 3.0, expected);
    assert_image_is(image, expected, "nanovdb temperature, mean / Lescale blackbody(2500 K)");
    free(image);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_absorbing_slab),        cmocka_unit_test(test_absorbing_sphere_transmittance),
        cmocka_unit_test(test_scattering_furnace),    cmocka_unit_test(test_emission),
        cmocka_unit_test(test_grid_furnace),          cmocka_unit_test(test_temperature_grid),
        cmocka_unit_test(test_nanovdb_transmittance), cmocka_unit_test(test_nanovdb_temperature),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
