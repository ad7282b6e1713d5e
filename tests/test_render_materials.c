/* The materials of the path tracer kernel in a constant environment of
 * radiance 1, seen on a large square (both of its sides lit, so the light a
 * surface transmits arrives too), one bounce: a pixel's value is the
 * material's albedo toward the camera. Closed forms where there is one
 * (diffuse transmission: R + T; a thin dielectric: 1), and next-event
 * estimation with MIS against BSDF sampling alone for every material with
 * lobes that are not deltas: the two image means must agree within 5
 * standard errors of their difference. A mix of amount 0 or 1 renders bit
 * for bit as its component. */
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

static Material material_of(uint32_t type, float alpha)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = type;
    m.alpha_x = m.alpha_y = alpha;
    m.eta = 1.5f;
    for (int c = 0; c < 3; ++c) {
        m.reflectance[c] = 0.3f + 0.2f * (float)c;
        m.transmittance[c] = 0.4f - 0.1f * (float)c;
        m.conductor_eta[c] = 0.2f + 0.3f * (float)c;
        m.conductor_k[c] = 3.0f - 0.5f * (float)c;
    }
    m.base_alpha_x = m.base_alpha_y = 0.2f;
    m.thickness = 0.01f;
    m.max_depth = 10;
    m.sample_count = 1;
    return m;
}

/* The square [-50, 50]^2 at z = 0 of materials[used] (the others are there
 * for a mix to refer to), seen obliquely from above through a narrow view,
 * in the environment. */
static void square_scene(RenderScene *scene, const Material *materials, int count, int used)
{
    render_scene_init(scene);
    for (int i = 0; i < count; ++i)
        assert_int_equal(render_scene_add_material(scene, &materials[i]), i);
    const float a[3] = {-50, -50, 0}, b[3] = {50, -50, 0}, c[3] = {50, 50, 0}, d[3] = {-50, 50, 0};
    assert_int_equal(render_scene_add_triangle(scene, a, b, c, used, NULL, 0, 0), 0);
    assert_int_equal(render_scene_add_triangle(scene, a, c, d, used, NULL, 0, 0), 0);
    const float sky[3] = {1.0f, 1.0f, 1.0f};
    assert_int_equal(render_scene_add_infinite_light(scene, sky), 0);
    const float position[3] = {0, -1.2f, 1}, forward[3] = {0, 0.768221f, -0.640184f}, right[3] = {1, 0, 0},
                up[3] = {0, 0.640184f, 0.768221f};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 0.2f, 0.2f, 16, 16);
    render_scene_set_camera(scene, &camera);
}

typedef struct {
    double mean[3], standard_error[3];
    float *image; /* the mean pass, malloc'd */
} Rendered;

static Rendered render_using(const Material *materials, int count, int used, int nee, unsigned spp)
{
    RenderScene scene;
    square_scene(&scene, materials, count, used);
    char error[256];
    scene.constants.integrator.max_depth = 1;
    scene.constants.integrator.flags = nee ? RENDER_NEE : 0u;
    assert_int_equal(render_scene_finalize(&scene, error, sizeof error), 0);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = spp;
    settings.seed = 5;
    RenderOutput out;
    if (renderer_run(&test_device, 1, &scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s", error);
    assert_int_equal(out.rejected_total, 0);
    Rendered r;
    size_t pixels = (size_t)out.width * out.height;
    r.image = malloc(pixels * 3 * sizeof *r.image);
    memcpy(r.image, out.pass[PASS_MEAN], pixels * 3 * sizeof *r.image);
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0, sum2 = 0.0;
        for (size_t p = 0; p < pixels; ++p) {
            double v = r.image[3 * p + (size_t)c];
            sum += v;
            sum2 += v * v;
        }
        r.mean[c] = sum / (double)pixels;
        double variance = sum2 / (double)pixels - r.mean[c] * r.mean[c];
        r.standard_error[c] = sqrt(variance > 0.0 ? variance / (double)pixels : 0.0);
    }
    render_output_free(&out);
    render_scene_destroy(&scene);
    return r;
}

static Rendered render(const Material *materials, int count, int nee, unsigned spp)
{
    return render_using(materials, count, 0, nee, spp);
}

static void check_closed_form(const Material *m, const double expected[3], const char *name)
{
    for (int nee = 0; nee <= 1; ++nee) {
        Rendered r = render(m, 1, nee, 64);
        for (int c = 0; c < 3; ++c) {
            printf("  %-36s %s channel %d: mean %.5f expected %.5f (standard error %.5f)\n", name,
                   nee ? "NEE+MIS" : "BSDF   ", c, r.mean[c], expected[c], r.standard_error[c]);
            assert_true(fabs(r.mean[c] - expected[c]) <= 5.0 * r.standard_error[c] + 1e-4);
        }
        free(r.image);
    }
}

static void check_nee_agrees(const Material *materials, int count, const char *name)
{
    Rendered with = render(materials, count, 1, 256), without = render(materials, count, 0, 256);
    for (int c = 0; c < 3; ++c) {
        double se = sqrt(with.standard_error[c] * with.standard_error[c] +
                         without.standard_error[c] * without.standard_error[c]);
        printf("  %-36s channel %d: NEE+MIS %.5f BSDF only %.5f (standard error of the difference %.5f)\n", name, c,
               with.mean[c], without.mean[c], se);
        assert_true(with.mean[c] > 0.01);
        assert_true(fabs(with.mean[c] - without.mean[c]) <= 5.0 * se + 1e-4);
    }
    free(with.image);
    free(without.image);
}

static void test_diffuse_transmission(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    Material m = material_of(MAT_DIFFUSE_TRANSMISSION, 0.0f);
    double expected[3];
    for (int c = 0; c < 3; ++c)
        expected[c] = (double)m.reflectance[c] + (double)m.transmittance[c];
    check_closed_form(&m, expected, "diffuse transmission");
    check_nee_agrees(&m, 1, "diffuse transmission");
}

static void test_thin_dielectric(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    Material m = material_of(MAT_THIN_DIELECTRIC, 0.0f);
    const double expected[3] = {1.0, 1.0, 1.0}; /* it reflects or transmits everything */
    check_closed_form(&m, expected, "thin dielectric");
}

static void test_layered(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    Material smooth_diffuse = material_of(MAT_COATED_DIFFUSE, 0.0f);
    check_nee_agrees(&smooth_diffuse, 1, "smooth coated diffuse");
    Material rough_diffuse = material_of(MAT_COATED_DIFFUSE, 0.3f);
    check_nee_agrees(&rough_diffuse, 1, "rough coated diffuse");
    Material conductor = material_of(MAT_COATED_CONDUCTOR, 0.2f);
    check_nee_agrees(&conductor, 1, "rough coated conductor");
    Material smooth_conductor = material_of(MAT_COATED_CONDUCTOR, 0.0f);
    check_nee_agrees(&smooth_conductor, 1, "smooth coat over rough conductor");
    Material medium = material_of(MAT_COATED_CONDUCTOR, 0.2f);
    medium.albedo[0] = medium.albedo[1] = medium.albedo[2] = 0.7f;
    medium.g = 0.4f;
    medium.thickness = 0.2f;
    check_nee_agrees(&medium, 1, "coated conductor with a medium");
}

/* Mixes: of amount 0.4 between a diffuse and a rough conductor, whose
 * albedos it mixes; of amount 0 and 1, each the image of the square made of
 * the component bit for bit (in the same scene, so with the same kernel:
 * kernels built for other feature sets may round a last bit differently). */
static void test_mix(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    Material materials[3] = {material_of(MAT_MIX, 0.0f), material_of(MAT_DIFFUSE, 0.0f),
                             material_of(MAT_CONDUCTOR, 0.25f)};
    materials[0].mix_materials[0] = 1;
    materials[0].mix_materials[1] = 2;
    materials[0].mix_amount = 0.4f;
    check_nee_agrees(materials, 3, "mix of diffuse and conductor");
    Rendered parts[2];
    for (int i = 0; i < 2; ++i)
        parts[i] = render_using(materials, 3, 1 + i, 1, 64);
    Rendered mixed = render(materials, 3, 1, 64);
    for (int c = 0; c < 3; ++c) {
        double expected = 0.6 * parts[0].mean[c] + 0.4 * parts[1].mean[c];
        double se = sqrt(mixed.standard_error[c] * mixed.standard_error[c] +
                         0.36 * parts[0].standard_error[c] * parts[0].standard_error[c] +
                         0.16 * parts[1].standard_error[c] * parts[1].standard_error[c]);
        printf("  mix 0.4 channel %d: %.5f, of its parts %.5f (standard error %.5f)\n", c, mixed.mean[c], expected, se);
        assert_true(fabs(mixed.mean[c] - expected) <= 5.0 * se + 1e-4);
    }
    free(mixed.image);
    for (int i = 0; i < 2; ++i) {
        materials[0].mix_amount = (float)i;
        Rendered r = render(materials, 3, 1, 64);
        assert_memory_equal(r.image, parts[i].image, 16 * 16 * 3 * sizeof(float));
        free(r.image);
        free(parts[i].image);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_diffuse_transmission),
        cmocka_unit_test(test_thin_dielectric),
        cmocka_unit_test(test_layered),
        cmocka_unit_test(test_mix),
    };
    return cmocka_run_group_tests(tests, test_device_setup, test_device_teardown);
}
