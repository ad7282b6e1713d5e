/* Cameras and pixel filters. On the host (kernels/camera.h compiled as C):
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

static CameraRay ray_of(const RenderScene *scene, uint32_t x, uint32_t y, uint64_t key)
{
    return camera_ray(&scene->constants.camera, &scene->constants.filter, scene->distributions, x, y, key);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pinhole_box_rays_unchanged),
        cmocka_unit_test(test_screen_window_and_orthographic_rays),
        cmocka_unit_test(test_thin_lens_rays),
        cmocka_unit_test(test_filter_sampling_reproduces_weights),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
