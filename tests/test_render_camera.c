/* Cameras and pixel filters. On the host (kernels/tracing/camera.h compiled as C):
 * the pinhole with the box filter makes exactly the rays it always made;
 * screen windows and the orthographic camera put image points where pbrt
 * puts them; thin-lens rays pass through the plane of focus; each filter's
 * sampling reproduces its normalised weights. On the device: the image of
 * a point on the plane of focus stays sharp and one off it spreads by the
 * circle of confusion; an orthographic view of a sphere lights exactly the
 * pixels under it; an edge seen through each filter has the filter's edge
 * response, negative lobes included. */
#define _POSIX_C_SOURCE 200809L

#include "camera.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "scene/scene.h"
#include "test_device.h"

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

static char error[1024];

/* Writes scene text to a temporary file; returns its path (static). */
static const char *write_scene(const char *text)
{
    static char path[64];
    strcpy(path, "/tmp/gmon-camera-XXXXXX");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Loads scene text at width x height through the scene reader, and the
 * reader's camera when `camera` is not NULL. */
static void load_scene(const char *text, unsigned width, unsigned height, RenderScene *scene, SceneCamera *camera)
{
    const char *path = write_scene(text);
    SceneSummary summary;
    int result = scene_convert_load(path, 0, width, height, 1, scene, &summary, error, sizeof error);
    if (result == 0 && camera) {
        Scene parsed;
        result = scene_load(path, NULL, &parsed, error, sizeof error);
        *camera = parsed.camera;
        scene_destroy(&parsed);
    }
    remove(path);
    if (result)
        fail_msg("%s", error);
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
}

static int same_bits(float a, float b)
{
    return float_bits(a) == float_bits(b);
}

static int same_vec3(Vec3 a, Vec3 b)
{
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

/* The ray of the independent sampler's sample with key `key`. */
static CameraRay ray_of(const RenderScene *scene, uint32_t x, uint32_t y, uint64_t key)
{
    SampleStream stream = {key, 0u, SAMPLER_INDEPENDENT};
    return camera_ray(&scene->constants.camera, &scene->constants.filter, scene->distributions, x, y, &stream);
}

/* The box filter of radius 0.5 and a pinhole: the camera constants and
 * every ray are, bit for bit, those the renderer made before cameras and
 * filters were added (its formulas written out here), for a wide and a
 * tall image; the kernels compile none of the new code. */
static void test_pinhole_box_rays_unchanged(void **state)
{
    (void)state;
    const char *text = "LookAt 0.3 1 3.9  0 1.1 0  0 1 0\nCamera \"perspective\" \"float fov\" 37.5\n"
                       "PixelFilter \"box\"\nWorldBegin\nShape \"sphere\"\n";
    const unsigned sizes[2][2] = {{24, 16}, {16, 24}};
    for (int s = 0; s < 2; ++s) {
        unsigned width = sizes[s][0], height = sizes[s][1];
        RenderScene scene;
        SceneCamera in;
        load_scene(text, width, height, &scene, &in);
        assert_int_equal(
            render_scene_features(&scene) & (FEATURE_THIN_LENS | FEATURE_ORTHOGRAPHIC | FEATURE_PIXEL_FILTER), 0);
        double t = tan(0.5 * 37.5 * 3.14159265358979323846 / 180.0), aspect = (double)width / (double)height;
        float tan_half[2] = {aspect > 1.0 ? (float)(t * aspect) : (float)t,
                             aspect > 1.0 ? (float)t : (float)(t / aspect)};
        const CameraData *c = &scene.constants.camera;
        for (int i = 0; i < 3; ++i) {
            assert_true(same_bits(c->position[i], in.position[i]));
            assert_true(same_bits(c->forward[i], in.forward[i]));
            assert_true(same_bits(c->right[i], in.right[i] * tan_half[0]));
            assert_true(same_bits(c->up[i], in.up[i] * tan_half[1]));
        }
        Vec3 forward = vec3_from(c->forward), right = vec3_from(c->right), up = vec3_from(c->up);
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x)
                for (uint64_t sample = 0; sample < 4; ++sample) {
                    uint64_t key = rng_sample_key(7, (uint64_t)y * width + x, sample);
                    float sx = 2.0f * ((float)x + rng_uniform(key, 0)) / (float)width - 1.0f;
                    float sy = 1.0f - 2.0f * ((float)y + rng_uniform(key, 1)) / (float)height;
                    Vec3 before = v_normalize(v_add(forward, v_add(v_scale(right, sx), v_scale(up, sy))));
                    CameraRay ray = ray_of(&scene, x, y, key);
                    assert_true(same_vec3(ray.direction, before));
                    assert_true(same_vec3(ray.origin, vec3_from(c->position)));
                    assert_true(ray.weight == 1.0f);
                }
        render_scene_destroy(&scene);
    }
}

/* The image point (px, py) pixels from the top left of a width x height
 * image, in pbrt's screen window [x0, x1] x [y0, y1] (y0 at the bottom). */
static void screen_point(const float window[4], double px, double py, unsigned width, unsigned height, double *x,
                         double *y)
{
    *x = window[0] + px / width * (window[1] - window[0]);
    *y = window[3] - py / height * (window[3] - window[2]);
}

/* Rays of a perspective camera with an off-centre screen window and of an
 * orthographic one: through (perspective) or from (orthographic) the point
 * of the screen window that pbrt's raster-to-screen transform gives. */
static void test_screen_window_and_orthographic_rays(void **state)
{
    (void)state;
    static const struct {
        const char *camera;
        int orthographic;
        float window[4]; /* expected: tangents, or world units */
    } cases[] = {
        {"Camera \"perspective\" \"float fov\" 90 \"float screenwindow\" [ 0 1 -0.5 0.25 ]", 0, {0, 1, -0.5f, 0.25f}},
        {"Camera \"perspective\" \"float fov\" 60 \"float frameaspectratio\" 2",
         0,
         {-1.1547005f, 1.1547005f, -0.57735027f, 0.57735027f}},
        {"Camera \"orthographic\"", 1, {-2, 2, -1, 1}},
        {"Camera \"orthographic\" \"float screenwindow\" [ 1 3 0 2 ]", 1, {2, 6, 0, 4}},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        char text[512];
        /* The last case with a camera transform that halves lengths. */
        snprintf(text, sizeof text,
                 "%sLookAt 1 2 3  1 2 10  0 1 0\n%s\nPixelFilter \"box\"\nWorldBegin\nShape \"sphere\"\n",
                 k == 3 ? "Scale 0.5 0.5 0.5\n" : "", cases[k].camera);
        RenderScene scene;
        load_scene(text, 32, 16, &scene, NULL);
        assert_int_equal((render_scene_features(&scene) & FEATURE_ORTHOGRAPHIC) != 0, cases[k].orthographic);
        /* LookAt along +z with +y up: the image's right is world +x (pbrt's up x forward). */
        for (uint32_t pixel = 0; pixel < 32 * 16; pixel += 7) {
            uint32_t x = pixel % 32, y = pixel / 32;
            uint64_t key = rng_sample_key(3, pixel, 0);
            double sx, sy;
            screen_point(cases[k].window, x + rng_uniform(key, 0), y + rng_uniform(key, 1), 32, 16, &sx, &sy);
            CameraRay ray = ray_of(&scene, x, y, key);
            if (cases[k].orthographic) {
                assert_true(fabs(ray.origin.x - (1.0 + sx)) < 1e-5 && fabs(ray.origin.y - (2.0 + sy)) < 1e-5);
                assert_true(fabs(ray.origin.z - 3.0) < 1e-6);
                assert_true(ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 1.0f);
            } else {
                double n = sqrt(sx * sx + sy * sy + 1.0);
                assert_true(fabs(ray.direction.x - sx / n) < 1e-6 && fabs(ray.direction.y - sy / n) < 1e-6 &&
                            fabs(ray.direction.z - 1.0 / n) < 1e-6);
                assert_true(ray.origin.x == 1.0f && ray.origin.y == 2.0f && ray.origin.z == 3.0f);
            }
        }
        render_scene_destroy(&scene);
    }
}

/* With a thin lens every ray starts on the lens disk and passes through
 * the point where the pinhole ray of the same image point meets the plane
 * of focus (pbrt-v4's ray, for both projections); the pinhole rays are
 * those of the same camera without the lens (the lens dimensions come
 * after every other). */
static void test_thin_lens_rays(void **state)
{
    (void)state;
    const char *cameras[] = {"Camera \"perspective\" \"float fov\" 50", "Camera \"orthographic\""};
    for (int k = 0; k < 2; ++k) {
        char with_lens[512], pinhole[512];
        const char *format =
            "LookAt 0 0 0  0 0 1  0 1 0\n%s%s\nPixelFilter \"gaussian\"\nWorldBegin\nShape \"sphere\"\n";
        snprintf(with_lens, sizeof with_lens, format, cameras[k],
                 " \"float lensradius\" 0.2 \"float focaldistance\" 4");
        snprintf(pinhole, sizeof pinhole, format, cameras[k], "");
        RenderScene lens, plain;
        load_scene(with_lens, 16, 16, &lens, NULL);
        load_scene(pinhole, 16, 16, &plain, NULL);
        assert_true(render_scene_features(&lens) & FEATURE_THIN_LENS);
        assert_false(render_scene_features(&plain) & FEATURE_THIN_LENS);
        double largest = 0.0;
        for (uint32_t pixel = 0; pixel < 256; ++pixel) {
            uint64_t key = rng_sample_key(5, pixel, 1);
            CameraRay a = ray_of(&lens, pixel % 16, pixel / 16, key), b = ray_of(&plain, pixel % 16, pixel / 16, key);
            assert_true(fabs(a.origin.z) < 1e-7);
            double r = sqrt((double)a.origin.x * a.origin.x + (double)a.origin.y * a.origin.y);
            assert_true(r <= 0.2 + 1e-6);
            largest = fmax(largest, r);
            double ta = 4.0 / a.direction.z, tb = 4.0 / b.direction.z; /* to the plane z = 4 */
            assert_true(fabs((a.origin.x + ta * a.direction.x) - (b.origin.x + tb * b.direction.x)) < 1e-5);
            assert_true(fabs((a.origin.y + ta * a.direction.y) - (b.origin.y + tb * b.direction.y)) < 1e-5);
            assert_true(a.weight == b.weight);
        }
        assert_true(largest > 0.15); /* the lens is used, not a point */
        render_scene_destroy(&lens);
        render_scene_destroy(&plain);
    }
}

/* The filters with pbrt-v4's default parameters (and a wide box). */
static const PixelFilter filters[] = {
    {PIXEL_FILTER_BOX, {1.0f, 0.75f}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f},
    {PIXEL_FILTER_GAUSSIAN, {1.5f, 1.5f}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f},
    {PIXEL_FILTER_MITCHELL, {2.0f, 2.0f}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f},
    {PIXEL_FILTER_LANCZOS, {4.0f, 4.0f}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f},
    {PIXEL_FILTER_TRIANGLE, {2.0f, 1.0f}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f},
};
static const char *filter_names[] = {"box 1 x 0.75", "gaussian", "mitchell", "lanczos", "triangle 2 x 1"};

/* The integral of the filter's axis `axis` (the other at 0, the filter
 * being separable) over [a, b], in value (or |value|), by the midpoint rule. */
static double filter_integral(const PixelFilter *f, int axis, double a, double b, int magnitude)
{
    const int steps = 4000;
    double sum = 0.0, h = (b - a) / steps;
    for (int i = 0; i < steps; ++i) {
        double x = a + (i + 0.5) * h;
        double v = axis == 0 ? pixel_filter_evaluate(f, x, 0.0) : pixel_filter_evaluate(f, 0.0, x);
        sum += magnitude ? fabs(v) : v;
    }
    return sum * h;
}

/* Offsets drawn from each filter's table, weighted by their weights,
 * histogrammed along each axis: each bin's mean weight is the filter's
 * normalised integral over the bin (its share of the filter's mass), to 5
 * standard errors plus the table's discretisation (32 cells a pixel). */
static void test_filter_sampling_reproduces_weights(void **state)
{
    (void)state;
    enum { SAMPLES = 400000, BINS_PER_PIXEL = 4, MAX_BINS = 64 };
    for (size_t k = 0; k < sizeof filters / sizeof filters[0]; ++k) {
        const PixelFilter *f = &filters[k];
        RenderScene scene;
        render_scene_init(&scene);
        assert_int_equal(render_scene_set_filter(&scene, f, error, sizeof error), 0);
        const FilterData *data = &scene.constants.filter;
        assert_true(data->table_width == (uint32_t)(32 * f->radius[0]) &&
                    data->table_height == (uint32_t)(32 * f->radius[1]));
        double sum[2][MAX_BINS] = {{0}}, sum2[2][MAX_BINS] = {{0}};
        int bins[2] = {(int)(2 * BINS_PER_PIXEL * f->radius[0]), (int)(2 * BINS_PER_PIXEL * f->radius[1])};
        int negative = 0;
        for (uint64_t i = 0; i < SAMPLES; ++i) {
            uint64_t key = rng_sample_key(11, k, i);
            float d[2];
            float w = filter_sample(data, scene.distributions, rng_uniform(key, 0), rng_uniform(key, 1), &d[0], &d[1]);
            negative += w < 0.0f;
            for (int a = 0; a < 2; ++a) {
                assert_true(d[a] >= -f->radius[a] && d[a] < f->radius[a]);
                int bin = (int)floor((d[a] + f->radius[a]) * BINS_PER_PIXEL);
                sum[a][bin] += w;
                sum2[a][bin] += (double)w * w;
            }
        }
        double worst = 0.0;
        for (int a = 0; a < 2; ++a) {
            double r = f->radius[a], total = filter_integral(f, a, -r, r, 0);
            for (int b = 0; b < bins[a]; ++b) {
                double lo = -r + (double)b / BINS_PER_PIXEL,
                       expected = filter_integral(f, a, lo, lo + 1.0 / BINS_PER_PIXEL, 0) / total;
                double mean = sum[a][b] / SAMPLES, variance = sum2[a][b] / SAMPLES - mean * mean;
                double tolerance = 5.0 * sqrt(variance / SAMPLES) + 2e-3 * (1.0 / BINS_PER_PIXEL) / r;
                if (fabs(mean - expected) > tolerance)
                    fail_msg("%s: axis %d, bin [%g, %g): %.5f, expected %.5f (tolerance %.5f)", filter_names[k], a, lo,
                             lo + 1.0 / BINS_PER_PIXEL, mean, expected, tolerance);
                worst = fmax(worst, fabs(mean - expected) / tolerance);
            }
        }
        int signed_filter = f->type == PIXEL_FILTER_MITCHELL || f->type == PIXEL_FILTER_LANCZOS;
        printf("  %-16s table %ux%u, weight %.5f, negative samples %.4f, worst bin at %.2f of its tolerance\n",
               filter_names[k], data->table_width, data->table_height, (double)data->weight, (double)negative / SAMPLES,
               worst);
        assert_true(signed_filter ? (negative > 0 && data->weight > 1.0f) : (negative == 0 && data->weight == 1.0f));
        render_scene_destroy(&scene);
    }
}

/* ------------------------------------------------------------ renders */

static Material black(void)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_DIFFUSE;
    return m;
}

/* Renders emitters seen directly (max depth 0, BSDF sampling only) and
 * returns the mean image (RGB); free with render_output_free. */
static const float *render(RenderScene *scene, uint64_t samples, RenderOutput *out)
{
    scene->constants.integrator.max_depth = 0;
    scene->constants.integrator.flags = 0;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = samples;
    settings.seed = 3;
    if (renderer_run(&test_device, 1, scene, &settings, out, error, sizeof error) != 0)
        fail_msg("%s", error);
    assert_int_equal(out->rejected_total, 0);
    return (const float *)out->pass[PASS_MEAN];
}

/* Two small emitting spheres seen through a thin lens focused at 10, each
 * centred on a pixel: the one at 10 stays sharp (all its light in its
 * pixel), the one at 5 spreads into the circle of confusion, of radius
 * R |z - F| / (F z) on the image plane at distance 1. That radius is
 * measured from the image's second moment about the centroid: a uniform
 * disk of radius c has c^2 / 2, the sphere's own disk (radius a) adds
 * a^2 / 2, and pixels (a box filter) add 1/6 (Sheppard's correction:
 * 1/12 an axis). The lens moves light without making or losing it: the
 * blurred image holds the sphere's pi a^2 square pixels of radiance. */
static void test_thin_lens_focus(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { SIZE = 48, SAMPLES = 2048 };
    const float tan_half = 0.1f, lens_radius = 0.25f, focus = 10.0f, sphere_radii[2] = {0.01f, 0.05f};
    const double pixels_per_tangent = SIZE / (2.0 * tan_half);
    /* Pixel centres (12.5, 24.5) and (36.5, 24.5), at depths 10 and 5. */
    const double centres[2][2] = {{12.5, 24.5}, {36.5, 24.5}}, depths[2] = {10.0, 5.0};
    RenderScene scene;
    render_scene_init(&scene);
    Material m = black();
    int material = render_scene_add_material(&scene, &m);
    const float radiance[3] = {1, 1, 1};
    for (int k = 0; k < 2; ++k) {
        float centre[3] = {(float)((centres[k][0] - SIZE / 2.0) / pixels_per_tangent * depths[k]),
                           (float)((SIZE / 2.0 - centres[k][1]) / pixels_per_tangent * depths[k]), (float)depths[k]};
        assert_int_equal(render_scene_add_sphere(&scene, centre, sphere_radii[k], material, radiance, 0, 0), 0);
    }
    const float origin[3] = {0, 0, 0}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(origin, forward, right, up, tan_half, tan_half, SIZE, SIZE);
    camera.lens_radius = lens_radius;
    camera.focal_distance = focus;
    render_scene_set_camera(&scene, &camera);
    assert_true(render_scene_features(&scene) & FEATURE_THIN_LENS);
    RenderOutput out;
    const float *image = render(&scene, SAMPLES, &out);
    double radius[2], energy[2], peak[2], own[2];
    for (int k = 0; k < 2; ++k) {
        /* Each sphere's half of the image (columns < 24 or >= 24). */
        double sum = 0.0, sx = 0.0, sy = 0.0, moment = 0.0;
        peak[k] = 0.0;
        for (int y = 0; y < SIZE; ++y)
            for (int x = k * SIZE / 2; x < (k + 1) * SIZE / 2; ++x) {
                double v = image[3 * ((size_t)y * SIZE + (size_t)x)];
                sum += v;
                sx += v * (x + 0.5);
                sy += v * (y + 0.5);
                peak[k] = fmax(peak[k], v);
            }
        sx /= sum;
        sy /= sum;
        for (int y = 0; y < SIZE; ++y)
            for (int x = k * SIZE / 2; x < (k + 1) * SIZE / 2; ++x) {
                double v = image[3 * ((size_t)y * SIZE + (size_t)x)];
                moment += v * ((x + 0.5 - sx) * (x + 0.5 - sx) + (y + 0.5 - sy) * (y + 0.5 - sy)) / sum;
            }
        double z = depths[k], rho = sphere_radii[k];
        own[k] = rho / sqrt(z * z - rho * rho) * pixels_per_tangent;
        radius[k] = sqrt(fmax(0.0, 2.0 * (moment - 1.0 / 6.0) - own[k] * own[k]));
        energy[k] = sum;
        peak[k] /= sum;
        printf("  sphere at z = %g: centroid (%.3f, %.3f), its pixel holds %.3f of its light, blur radius %.3f "
               "pixels\n",
               z, sx, sy, peak[k], radius[k]);
        assert_true(fabs(sx - centres[k][0]) < 0.05 && fabs(sy - centres[k][1]) < 0.05);
    }
    double confusion = lens_radius * fabs(depths[1] - focus) / (focus * depths[1]) * pixels_per_tangent;
    double area = 3.14159265358979323846 * own[1] * own[1];
    printf("  circle of confusion at z = 5: %.3f pixels; the blurred sphere's light %.3f, expected %.3f\n", confusion,
           energy[1], area);
    assert_true(peak[0] > 0.99);                                 /* in focus: sharp */
    assert_true(fabs(radius[1] - confusion) < 0.02 * confusion); /* 6 pixels */
    assert_true(fabs(energy[1] - area) < 0.03 * area);
    render_output_free(&out);
    render_scene_destroy(&scene);
}

/* An orthographic camera over an emitting sphere of radius 1: every pixel
 * wholly inside its outline (parallel projection: the disk of radius 1
 * around its centre, wherever the sphere is along the view) is fully lit,
 * every pixel wholly outside is black; an off-centre screen window moves
 * the disk as pbrt's raster-to-screen transform says. */
static void test_orthographic_projection(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { SIZE = 32 };
    const float windows[2][4] = {{-4, 4, -4, 4}, {0, 4, -1, 3}};
    for (int w = 0; w < 2; ++w) {
        RenderScene scene;
        render_scene_init(&scene);
        Material m = black();
        int material = render_scene_add_material(&scene, &m);
        const float radiance[3] = {2, 2, 2}, centre[3] = {2, 1, 50};
        assert_int_equal(render_scene_add_sphere(&scene, centre, 1.0f, material, radiance, 0, 0), 0);
        const float origin[3] = {0, 0, 0}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
        RenderCamera camera = render_camera_pinhole(origin, forward, right, up, 1, 1, SIZE, SIZE);
        camera.projection = CAMERA_ORTHOGRAPHIC;
        memcpy(camera.window, windows[w], sizeof camera.window);
        render_scene_set_camera(&scene, &camera);
        RenderOutput out;
        const float *image = render(&scene, 16, &out);
        const float *win = windows[w];
        double pixel_x = (win[1] - win[0]) / SIZE, pixel_y = (win[3] - win[2]) / SIZE;
        int inside = 0, outside = 0;
        for (int y = 0; y < SIZE; ++y)
            for (int x = 0; x < SIZE; ++x) {
                /* The pixel's nearest and farthest points from the disk's centre. */
                double x0 = win[0] + x * pixel_x, x1 = x0 + pixel_x, y1 = win[3] - y * pixel_y, y0 = y1 - pixel_y;
                double nx = fmax(x0 - centre[0], fmax(0.0, centre[0] - x1)),
                       ny = fmax(y0 - centre[1], fmax(0.0, centre[1] - y1));
                double fx = fmax(fabs(x0 - centre[0]), fabs(x1 - centre[0])),
                       fy = fmax(fabs(y0 - centre[1]), fabs(y1 - centre[1]));
                float v = image[3 * ((size_t)y * SIZE + (size_t)x)];
                if (fx * fx + fy * fy < 1.0) {
                    assert_true(v == 2.0f);
                    ++inside;
                } else if (nx * nx + ny * ny > 1.0) {
                    assert_true(v == 0.0f);
                    ++outside;
                }
            }
        printf("  window [%g, %g] x [%g, %g]: %d pixels inside the outline all lit, %d outside all black\n", win[0],
               win[1], win[2], win[3], inside, outside);
        assert_true(inside >= (w == 0 ? 30 : 150));
        render_output_free(&out);
        render_scene_destroy(&scene);
    }
}

/* An emitter covering the right half of the view (x > 0 on the plane z =
 * 1, the image's middle column boundary) seen through each filter: column
 * i's mean is the filter's normalised mass beyond the edge, the integral
 * of f over dx > W / 2 - (i + 1/2), dx the sample's offset from its
 * pixel's centre. Mitchell and Lanczos overshoot: negative pixels before
 * the edge, pixels above the emitter's radiance after it. */
static void test_filter_edge_response(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    enum { WIDTH = 32, HEIGHT = 2, SAMPLES = 8192 };
    for (size_t k = 1; k < sizeof filters / sizeof filters[0]; ++k) {
        const PixelFilter *f = &filters[k];
        RenderScene scene;
        render_scene_init(&scene);
        Material m = black();
        int material = render_scene_add_material(&scene, &m);
        const float radiance[3] = {1, 1, 1};
        const float a[3] = {0, -50, 1}, b[3] = {50, -50, 1}, c[3] = {50, 50, 1}, d[3] = {0, 50, 1};
        assert_int_equal(render_scene_add_triangle(&scene, a, b, c, material, radiance, 1, 0), 0);
        assert_int_equal(render_scene_add_triangle(&scene, a, c, d, material, radiance, 1, 0), 0);
        const float origin[3] = {0, 0, 0}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
        RenderCamera camera =
            render_camera_pinhole(origin, forward, right, up, 1.0f, (float)HEIGHT / WIDTH, WIDTH, HEIGHT);
        render_scene_set_camera(&scene, &camera);
        assert_int_equal(render_scene_set_filter(&scene, f, error, sizeof error), 0);
        assert_true(render_scene_features(&scene) & FEATURE_PIXEL_FILTER);
        double weight = scene.constants.filter.weight;
        RenderOutput out;
        const float *image = render(&scene, SAMPLES, &out);
        double r = f->radius[0], total = filter_integral(f, 0, -r, r, 0), magnitude = filter_integral(f, 0, -r, r, 1);
        double lowest = 1.0, highest = 0.0;
        for (int x = 0; x < WIDTH; ++x) {
            double edge = WIDTH / 2.0 - (x + 0.5), mean = 0.0;
            for (int y = 0; y < HEIGHT; ++y)
                mean += image[3 * ((size_t)y * WIDTH + (size_t)x)] / HEIGHT;
            double expected = edge >= r ? 0.0 : edge <= -r ? 1.0 : filter_integral(f, 0, edge, r, 0) / total;
            double bright = edge >= r ? 0.0 : edge <= -r ? 1.0 : filter_integral(f, 0, edge, r, 1) / magnitude;
            double variance = weight * weight * bright - expected * expected; /* of one sample */
            double tolerance = 5.0 * sqrt(fmax(variance, 0.0) / (SAMPLES * HEIGHT)) + 2e-3;
            if (fabs(mean - expected) > tolerance)
                fail_msg("%s: column %d: %.4f, expected %.4f (tolerance %.4f)", filter_names[k], x, mean, expected,
                         tolerance);
            lowest = fmin(lowest, mean);
            highest = fmax(highest, mean);
        }
        printf("  %-16s edge response matches; columns range over [%.4f, %.4f]\n", filter_names[k], lowest, highest);
        int signed_filter = f->type == PIXEL_FILTER_MITCHELL || f->type == PIXEL_FILTER_LANCZOS;
        assert_true(signed_filter ? (lowest < 0.0 && highest > 1.0) : (lowest == 0.0 && highest == 1.0));
        render_output_free(&out);
        render_scene_destroy(&scene);
    }
}

/* Film "cropwindow": the image is the pixels [ceil(W x0), ceil(W x1)) x
 * [ceil(H y0), ceil(H y1)), each seeing what it sees in the whole image
 * ("pixelbounds" gives the same pixels in pixel units). */
static void test_crop_window(void **state)
{
    (void)state;
    static const char *const films[] = {
        "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 30 \"float cropwindow\" [ 0.75 0.25 0.1 "
        "0.6 ]\n",
        "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 30 \"integer pixelbounds\" [ 10 30 3 18 ]\n",
    };
    RenderScene full;
    load_scene("Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 30\n"
               "LookAt 1 2 3  1 2 10  0 1 0\nCamera \"perspective\" \"float fov\" 50\nPixelFilter \"box\"\n"
               "WorldBegin\nShape \"sphere\"\n",
               0, 0, &full, NULL);
    for (int f = 0; f < 2; ++f) {
        char text[512];
        snprintf(text, sizeof text,
                 "%sLookAt 1 2 3  1 2 10  0 1 0\nCamera \"perspective\" \"float fov\" 50\nPixelFilter \"box\"\n"
                 "WorldBegin\nShape \"sphere\"\n",
                 films[f]);
        RenderScene crop;
        load_scene(text, 0, 0, &crop, NULL);
        assert_int_equal(crop.constants.camera.width, 20);
        assert_int_equal(crop.constants.camera.height, 15);
        for (uint32_t y = 0; y < 15; ++y)
            for (uint32_t x = 0; x < 20; ++x) {
                CameraRay a = ray_of(&crop, x, y, 77 + x), b = ray_of(&full, x + 10, y + 3, 77 + x);
                assert_true(fabsf(a.direction.x - b.direction.x) < 1e-6f &&
                            fabsf(a.direction.y - b.direction.y) < 1e-6f &&
                            fabsf(a.direction.z - b.direction.z) < 1e-6f);
            }
        render_scene_destroy(&crop);
    }
    render_scene_destroy(&full);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pinhole_box_rays_unchanged),
        cmocka_unit_test(test_screen_window_and_orthographic_rays),
        cmocka_unit_test(test_thin_lens_rays),
        cmocka_unit_test(test_crop_window),
        cmocka_unit_test(test_filter_sampling_reproduces_weights),
        cmocka_unit_test(test_thin_lens_focus),
        cmocka_unit_test(test_orthographic_projection),
        cmocka_unit_test(test_filter_edge_response),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
