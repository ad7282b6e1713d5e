/* The integrators with light subpaths (kernels/tracing/bdpt.cl): the light
 * tracer ("lightpath") against the path tracer, which estimates the same
 * image by independent means (camera paths), and the splats' exactness:
 * the same sums bit for bit whatever the passes and slices. */
#include "cl/cl_device.h"
#include "render/caustic_check.h"
#include "render/render_scene.h"
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

/* Renders scenes/<name> at width x height with the integrator `flags`. */
static void render_scene_file(const char *name, unsigned width, unsigned height, uint32_t flags,
                              const RenderSettings *settings, RenderOutput *out)
{
    char path[1024], error[2048];
    snprintf(path, sizeof path, "%s/scenes/%s", GMON_SOURCE_DIR, name);
    RenderScene scene;
    SceneSummary summary;
    assert_int_equal(scene_convert_load(path, 0, width, height, 1, &scene, &summary, error, sizeof error), 0);
    scene.constants.integrator.flags = flags;
    assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
    RenderStatus status = renderer_run(&test_device, 1, &scene, settings, out, error, sizeof error);
    if (status != RENDER_OK)
        fail_msg("%s: %s", name, error);
    render_scene_destroy(&scene);
}

/* Compares two renders' mean images over a grid of tiles x tiles regions
 * (each region's mean of the three channels): every region within
 * `tolerance` (relative) of the reference. */
static void assert_tiles_agree(const RenderOutput *test, const RenderOutput *reference, int tiles, double tolerance,
                               const char *what)
{
    const float *a = test->pass[PASS_MEAN], *b = reference->pass[PASS_MEAN];
    unsigned width = test->width, height = test->height;
    double worst = 0.0, total_a = 0.0, total_b = 0.0;
    for (int ty = 0; ty < tiles; ++ty)
        for (int tx = 0; tx < tiles; ++tx) {
            double sum_a = 0.0, sum_b = 0.0;
            for (unsigned y = ty * height / tiles; y < (ty + 1) * height / tiles; ++y)
                for (unsigned x = tx * width / tiles; x < (tx + 1) * width / tiles; ++x)
                    for (int c = 0; c < 3; ++c) {
                        sum_a += a[3 * ((size_t)y * width + x) + c];
                        sum_b += b[3 * ((size_t)y * width + x) + c];
                    }
            double error = fabs(sum_a - sum_b) / sum_b;
            worst = error > worst ? error : worst;
            total_a += sum_a;
            total_b += sum_b;
            if (error > tolerance)
                printf("  %s: tile (%d, %d): %.5f vs %.5f, %.2f%% off\n", what, tx, ty, sum_a, sum_b, 100.0 * error);
        }
    printf("  %s: image means %.5f vs %.5f (%.2f%%), worst of %dx%d tiles %.2f%% off\n", what,
           total_a / (3.0 * width * height), total_b / (3.0 * width * height), 100.0 * (total_a - total_b) / total_b,
           tiles, tiles, 100.0 * worst);
    assert_true(worst <= tolerance);
}

/* The light tracer and the path tracer estimate the same image: every
 * 4x4 region of the diffuse Cornell box within 2%. Covers the light's own
 * point seen by the camera, the connections of every bounce and the
 * gaussian filter's splats over neighbouring pixels. */
static void test_lightpath_matches_path_tracer(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.passes = PASS_BIT(PASS_MEAN);
    s.sample_count = 512;
    s.seed = 3;
    RenderOutput path, light;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE, &s, &path);
    s.seed = 4;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE | RENDER_LIGHTPATH, &s, &light);
    assert_string_equal(light.integrator, "lightpath");
    assert_int_equal(light.rejected_total, 0);
    assert_tiles_agree(&light, &path, 4, 0.02, "lightpath vs path");
    render_output_free(&path);
    render_output_free(&light);
}

/* Bidirectional path tracing (every strategy s, t by its MIS weight) and
 * the path tracer estimate the same image: every 4x4 region of the
 * diffuse Cornell box within 2%. */
static void test_bdpt_matches_path_tracer(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.passes = PASS_BIT(PASS_MEAN);
    s.sample_count = 256;
    s.seed = 5;
    RenderOutput path, bdpt;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE, &s, &path);
    s.seed = 6;
    render_scene_file("cornell-diffuse.pbrt", 32, 32, RENDER_NEE | RENDER_BDPT, &s, &bdpt);
    assert_string_equal(bdpt.integrator, "bdpt");
    assert_int_equal(bdpt.rejected_total, 0);
    assert_tiles_agree(&bdpt, &path, 4, 0.02, "bdpt vs path");
    render_output_free(&path);
    render_output_free(&bdpt);
}

static void assert_same_sums(const RenderOutput *a, const RenderOutput *b)
{
    const size_t pixels = (size_t)a->width * a->height;
    assert_int_equal(a->set_count, b->set_count);
    assert_memory_equal(a->accumulators, b->accumulators,
                        accumulator_planes((uint32_t)a->set_count) * pixels * sizeof(uint64_t));
    assert_memory_equal(a->rejected, b->rejected, REJECTED_PLANES * pixels * sizeof(uint32_t));
    assert_memory_equal(a->pass[PASS_GMON], b->pass[PASS_GMON], pixels * 3 * sizeof(float));
}

/* Splats land in their sample's set of the pixel they reach, whatever
 * launched them: one pass of all samples, many short passes, the pixels
 * cut into slices, and launches whose records overflow run again in
 * halves give the same set sums bit for bit (no record lost or doubled),
 * with the light tracer and with bdpt. */
static void test_splat_sums_do_not_depend_on_passes_or_slices(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t integrators[] = {RENDER_LIGHTPATH, RENDER_BDPT};
    for (int i = 0; i < 2; ++i) {
        uint32_t flags = RENDER_NEE | integrators[i];
        RenderSettings s;
        render_settings_default(&s);
        s.estimator.set_count = 5;
        s.estimator.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_GMON);
        s.sample_count = 12;
        s.seed = 9;
        s.seconds_per_pass = 100.0; /* after the first pass of 1 sample, the other 11 in one */
        RenderOutput few, many, sliced;
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &few);
        s.seconds_per_pass = 1e-6; /* one sample a pass */
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &many);
        s.slice_bytes = 16 * 1024; /* 24x20 pixels' sums at M = 5 are 119 KiB */
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &sliced);
        assert_true(sliced.devices[0].slices > 1);
        /* Launches whose records pass 200 run again in halves, down to one
         * pixel's samples in halves. */
        s.slice_bytes = 0;
        s.seconds_per_pass = 100.0;
        s.splat_records = 200;
        RenderOutput split;
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &split);
        assert_same_sums(&few, &many);
        assert_same_sums(&few, &sliced);
        assert_same_sums(&few, &split);
        printf("  %s: 1 + 11 samples, 12 passes of 1, %d slices, launches cut to 200 records: the same sums\n",
               few.integrator, sliced.devices[0].slices);
        render_output_free(&few);
        render_output_free(&many);
        render_output_free(&sliced);
        render_output_free(&split);
    }
}

/* Fresnel reflectance of a conductor of complex index eta + i k at
 * incidence cosine c (the textbook formula, independent of bsdf.h). */
static double conductor_fresnel_reference(double c, double eta, double k)
{
    double s2 = 1.0 - c * c, t = eta * eta - k * k - s2;
    double a2b2 = sqrt(t * t + 4.0 * eta * eta * k * k), a = sqrt(0.5 * (a2b2 + t));
    double rs = (a2b2 - 2.0 * a * c + c * c) / (a2b2 + 2.0 * a * c + c * c);
    double rp = rs * (c * c * a2b2 - 2.0 * a * c * s2 + s2 * s2) / (c * c * a2b2 + 2.0 * a * c * s2 + s2 * s2);
    return 0.5 * (rs + rp);
}

/* A point light of `intensity` at height 1 over a diffuse floor (albedo
 * rho) at height 0, with a smooth conductor (eta + i k) mirror facing down
 * at height 2 if with_mirror, seen from (0, 1.8, 0) looking down at
 * size x size pixels. */
static void mirror_scene(RenderScene *scene, double intensity, double rho, double eta, double k, unsigned size,
                         int with_mirror)
{
    render_scene_init(scene);
    Material floor, mirror;
    memset(&floor, 0, sizeof floor);
    floor.type = MAT_DIFFUSE;
    floor.reflectance[0] = floor.reflectance[1] = floor.reflectance[2] = (float)rho;
    memset(&mirror, 0, sizeof mirror);
    mirror.type = MAT_CONDUCTOR;
    for (int c = 0; c < 3; ++c) {
        mirror.conductor_eta[c] = (float)eta;
        mirror.conductor_k[c] = (float)k;
    }
    int floor_material = render_scene_add_material(scene, &floor);
    int mirror_material = render_scene_add_material(scene, &mirror);
    const float a[3] = {-20, 0, -20}, b[3] = {20, 0, -20}, c[3] = {20, 0, 20}, d[3] = {-20, 0, 20};
    const float ma[3] = {-20, 2, -20}, mb[3] = {20, 2, -20}, mc[3] = {20, 2, 20}, md[3] = {-20, 2, 20};
    /* The floor faces up, the mirror down (each by its winding). */
    assert_int_equal(render_scene_add_triangle(scene, a, c, b, floor_material, NULL, 0, 0), 0);
    assert_int_equal(render_scene_add_triangle(scene, a, d, c, floor_material, NULL, 0, 0), 0);
    if (with_mirror) {
        assert_int_equal(render_scene_add_triangle(scene, ma, mb, mc, mirror_material, NULL, 0, 0), 0);
        assert_int_equal(render_scene_add_triangle(scene, ma, mc, md, mirror_material, NULL, 0, 0), 0);
    }
    Light light;
    memset(&light, 0, sizeof light);
    light.type = LIGHT_POINT;
    light.position[1] = 1.0f;
    light.radiance[0] = light.radiance[1] = light.radiance[2] = (float)intensity;
    assert_true(render_scene_add_light(scene, &light) >= 0);
    const float position[3] = {0, 1.8f, 0}, forward[3] = {0, -1, 0}, right[3] = {1, 0, 0}, up[3] = {0, 0, 1};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 0.5f, 0.5f, size, size);
    render_scene_set_camera(scene, &camera);
}

/* A point light at height 1 over a diffuse floor (albedo rho), under a
 * smooth conductor mirror facing down at height 2, seen from above by a
 * camera under the mirror: at floor point x the irradiance is the light's
 * I cos / d^2 plus the caustic of its mirror image at height 3, F I cos /
 * d'^2, and the floor's radiance rho / pi times that (maxdepth 2 leaves
 * out the light going back and forth). bdpt matches the closed form in
 * every 4x4 region within 2%; the path tracer, which cannot sample a point
 * light through a mirror, gets the direct term alone. */
static void test_bdpt_caustic_through_mirror(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const double intensity = 10.0, rho = 0.5, eta = 0.2, k = 3.0;
    const unsigned size = 24;
    double expected[24 * 24], direct_only[24 * 24];
    RenderOutput out[2];
    for (int pass = 0; pass < 2; ++pass) {
        RenderScene scene;
        mirror_scene(&scene, intensity, rho, eta, k, size, 1);
        scene.constants.integrator.max_depth = 2;
        scene.constants.integrator.flags = RENDER_NEE | (pass ? RENDER_BDPT : 0u);
        char error[256];
        assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
        if (pass == 0) {
            /* The closed form, averaged over 4x4 points of each pixel (the box filter). */
            const CameraData *cd = &scene.constants.camera;
            for (unsigned y = 0; y < size; ++y)
                for (unsigned x = 0; x < size; ++x) {
                    double total = 0.0, direct = 0.0;
                    for (int j = 0; j < 16; ++j) {
                        double px = x + (j % 4 + 0.5) / 4.0, py = y + (j / 4 + 0.5) / 4.0;
                        double sx = 2.0 * px / size - 1.0, sy = 1.0 - 2.0 * py / size, dir[3];
                        for (int i = 0; i < 3; ++i)
                            dir[i] = cd->forward[i] + sx * cd->right[i] + sy * cd->up[i];
                        double t = -cd->position[1] / dir[1];
                        double hx = cd->position[0] + t * dir[0], hz = cd->position[2] + t * dir[2];
                        double r2 = hx * hx + hz * hz;
                        double d1 = sqrt(r2 + 1.0), d2 = sqrt(r2 + 9.0);
                        double e1 = intensity / (d1 * d1) / d1;
                        double e2 = conductor_fresnel_reference(3.0 / d2, eta, k) * intensity / (d2 * d2) * 3.0 / d2;
                        total += rho / 3.14159265358979323846 * (e1 + e2) / 16.0;
                        direct += rho / 3.14159265358979323846 * e1 / 16.0;
                    }
                    expected[y * size + x] = total;
                    direct_only[y * size + x] = direct;
                }
        }
        RenderSettings s;
        render_settings_default(&s);
        s.estimator.passes = PASS_BIT(PASS_MEAN);
        s.sample_count = pass ? 1024 : 64;
        s.seed = 21;
        RenderStatus status = renderer_run(&test_device, 1, &scene, &s, &out[pass], error, sizeof error);
        if (status != RENDER_OK)
            fail_msg("%s", error);
        render_scene_destroy(&scene);
    }
    double worst[2] = {0.0, 0.0}, worst_direct = 0.0;
    for (int ty = 0; ty < 4; ++ty)
        for (int tx = 0; tx < 4; ++tx) {
            double sums[2] = {0.0, 0.0}, closed = 0.0, direct = 0.0;
            for (unsigned y = ty * size / 4; y < (ty + 1) * size / 4; ++y)
                for (unsigned x = tx * size / 4; x < (tx + 1) * size / 4; ++x) {
                    for (int pass = 0; pass < 2; ++pass)
                        for (int c = 0; c < 3; ++c)
                            sums[pass] += ((const float *)out[pass].pass[PASS_MEAN])[3 * (y * size + x) + c] / 3.0;
                    closed += expected[y * size + x];
                    direct += direct_only[y * size + x];
                }
            worst[1] = fmax(worst[1], fabs(sums[1] - closed) / closed);
            worst[0] = fmax(worst[0], fabs(sums[0] - closed) / closed);
            worst_direct = fmax(worst_direct, fabs(sums[0] - direct) / direct);
        }
    printf("  caustic through a mirror: bdpt within %.2f%% of the closed form in every 4x4 region; the path tracer "
           "%.1f%% off it (%.2f%% off the direct light alone)\n",
           100.0 * worst[1], 100.0 * worst[0], 100.0 * worst_direct);
    assert_true(worst[1] <= 0.02);
    assert_true(worst_direct <= 0.02); /* the path tracer: no caustic at all */
    render_output_free(&out[0]);
    render_output_free(&out[1]);
}

/* The warning for what the path tracer cannot sample: the point light
 * under the mirror sends 47.7% of its power to it (4 asin(400 / 401) of
 * 4 pi sr) and is named; without the
 * mirror, or rendered by bdpt, nothing is. */
static void test_caustic_check_names_lights_behind_specular_surfaces(void **state)
{
    (void)state;
    char message[1024], error[256];
    for (int with_mirror = 0; with_mirror < 2; ++with_mirror)
        for (int bdpt = 0; bdpt < 2; ++bdpt) {
            RenderScene scene;
            mirror_scene(&scene, 10.0, 0.5, 0.2, 3.0, 8, with_mirror);
            scene.constants.integrator.flags = RENDER_NEE | (bdpt ? RENDER_BDPT : 0u);
            assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
            int found = caustic_check(&scene, message, sizeof message);
            printf("  %s, %s: %d light(s)%s%s\n", with_mirror ? "mirror" : "no mirror", bdpt ? "bdpt" : "path", found,
                   found ? ": " : "", message);
            assert_int_equal(found, with_mirror && !bdpt);
            if (found)
                assert_non_null(
                    strstr(message, "the point light at (0, 1, 0) sends 4")); /* 47.7%: the mirror's solid angle */
            render_scene_destroy(&scene);
        }
}

/* Renders scenes/<name> expecting renderer_run to refuse it; returns the
 * error. */
static void render_refused(const char *name, uint32_t flags, const RenderSettings *settings, char *error,
                           size_t error_size)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", GMON_SOURCE_DIR, name);
    RenderScene scene;
    SceneSummary summary;
    assert_int_equal(scene_convert_load(path, 0, 8, 8, 1, &scene, &summary, error, error_size), 0);
    scene.constants.integrator.flags = flags;
    assert_int_equal(render_scene_finalize(&scene, error, error_size), 0);
    RenderOutput out;
    assert_int_not_equal(renderer_run(&test_device, 1, &scene, settings, &out, error, error_size), RENDER_OK);
    render_scene_destroy(&scene);
}

/* clamp and zirr see each splat as a sample of value its RGB (weight 1):
 * clamp at V = infinity is the mean bit for bit, a low V clamps the image
 * below it; zirr's cascades split each value, so its image keeps at most
 * the mean's light (as test_sample_passes' zirr render checks). Their images do not
 * depend on how passes batch samples (the splats' sums are exact). The
 * moment-based estimators and clamp-sum are refused with splats. */
static void test_splats_in_per_sample_estimators(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t integrators[] = {RENDER_LIGHTPATH, RENDER_BDPT};
    for (int i = 0; i < 2; ++i) {
        const uint32_t flags = RENDER_NEE | integrators[i];
        RenderSettings s;
        render_settings_default(&s);
        s.estimator.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_ZIRR);
        s.estimator.params.clamp_level_count = 2;
        s.estimator.params.clamp_levels[0] = INFINITY;
        s.estimator.params.clamp_levels[1] = 0.05f;
        s.sample_count = 12;
        s.seed = 4;
        s.seconds_per_pass = 100.0;
        RenderOutput one, many;
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &one);
        s.seconds_per_pass = 1e-6; /* one sample a pass */
        render_scene_file("cornell-diffuse.pbrt", 24, 20, flags, &s, &many);
        const size_t values = (size_t)one.width * one.height * 3;
        const float *mean = one.pass[PASS_MEAN], *clamp = one.pass[PASS_CLAMP], *zirr = one.pass[PASS_ZIRR];
        assert_non_null(clamp);
        assert_non_null(zirr);
        assert_memory_equal(mean, clamp, values * sizeof(float));
        int below = 0;
        double total = 0.0, plain = 0.0;
        for (size_t k = 0; k < values; ++k) {
            assert_true(clamp[values + k] <= mean[k]);
            below += clamp[values + k] < mean[k];
            assert_true(isfinite(zirr[k]) && zirr[k] >= 0.0f);
            total += zirr[k];
            plain += mean[k];
        }
        assert_true(below > 0);
        /* zirr's cascades split each value (splats too): trusting some less
         * than all, it keeps at most the mean's light. */
        assert_true(total <= plain * 1.0001 && total > 0.15 * plain);
        assert_memory_equal(one.pass[PASS_CLAMP], many.pass[PASS_CLAMP], 2 * values * sizeof(float));
        assert_memory_equal(one.pass[PASS_ZIRR], many.pass[PASS_ZIRR], values * sizeof(float));
        printf("  %s: clamp at infinity is the mean, at 0.05 below it in %d of %zu values; zirr's light %.3f of "
               "the mean's; the same over 12 passes\n",
               one.integrator, below, values, total / plain);
        render_output_free(&one);
        render_output_free(&many);
        const uint32_t refused[] = {PASS_ABMM, PASS_GABMM, PASS_MEAN_OR_MON, PASS_CLAMP_SUM};
        for (size_t r = 0; r < sizeof refused / sizeof refused[0]; ++r) {
            render_settings_default(&s);
            s.estimator.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(refused[r]);
            s.sample_count = 2;
            char error[2048];
            render_refused("cornell-diffuse.pbrt", flags, &s, error, sizeof error);
            assert_non_null(strstr(error, "not samples of the pixel"));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lightpath_matches_path_tracer),
        cmocka_unit_test(test_bdpt_matches_path_tracer),
        cmocka_unit_test(test_bdpt_caustic_through_mirror),
        cmocka_unit_test(test_caustic_check_names_lights_behind_specular_surfaces),
        cmocka_unit_test(test_splat_sums_do_not_depend_on_passes_or_slices),
        cmocka_unit_test(test_splats_in_per_sample_estimators),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
