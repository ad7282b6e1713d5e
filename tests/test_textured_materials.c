/* The material parameters pbrt-v4 takes as textures beyond reflectance,
 * roughness and the conductors' (diffusetransmission's reflectance and
 * transmittance, mix's amount, the coated materials' thickness, g, albedo
 * and a coated conductor's conductor.roughness): which texture each
 * material slot gets and the errors of the scene reader; and on a device:
 * a constant texture renders bit for bit as the constant parameter, a
 * checkerboard amount of 0 and 1 selects each material of a mix where the
 * checkerboard says, and a checkerboard transmittance transmits exactly
 * where it is not 0. */
#define _POSIX_C_SOURCE 200809L

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

static char temp_dir[64];
static char error[1024];

#define SIDE 16

static int setup(void **state)
{
    (void)state;
    strcpy(temp_dir, "/tmp/gmon-textured-materials-XXXXXX");
    return mkdtemp(temp_dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char command[128];
    snprintf(command, sizeof command, "rm -rf %s", temp_dir);
    return system(command);
}

static const char *const front_and_back = "LightSource \"point\" \"rgb I\" [ 4 4 4 ] \"point3 from\" [ 0.3 0.2 2 ]\n"
                                          "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ -0.2 0.1 -2 ]\n";

/* A scene: camera looking down -z at a 2x2 quad at z = 0 with uv 0..1,
 * `lights` (by default a point light in front and one behind it, for
 * transmission); `before` (textures, named materials) then `material`
 * shade the quad. */
static const char *lit_quad_scene(const char *name, const char *lights, const char *before, const char *material)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", temp_dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f,
            "LookAt 0 0 4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
            "Film \"rgb\" \"integer xresolution\" %d \"integer yresolution\" %d\n"
            "WorldBegin\n%s%s%s\n"
            "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
            "  \"integer indices\" [ 0 1 2  0 2 3 ] \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n",
            SIDE, SIDE, lights, before, material);
    fclose(f);
    return path;
}

static const char *quad_scene(const char *name, const char *before, const char *material)
{
    return lit_quad_scene(name, front_and_back, before, material);
}

static int convert(const char *path, RenderScene *scene)
{
    SceneSummary summary;
    error[0] = '\0';
    if (scene_convert_load(path, 0, SIDE, SIDE, 1, scene, &summary, error, sizeof error))
        return -1;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    return 0;
}

static void convert_fails(const char *before, const char *material, const char *needle)
{
    RenderScene scene;
    if (convert(quad_scene("bad.pbrt", before, material), &scene) == 0) {
        render_scene_destroy(&scene);
        fail_msg("converted, expected an error with \"%s\"", needle);
    }
    if (!strstr(error, needle) || !strstr(error, "bad.pbrt:"))
        fail_msg("error \"%s\" lacks \"%s\" or the file", error, needle);
}

/* The material the quad's shape uses (the last one converted). */
static const MaterialTextures *last_material_textures(const RenderScene *scene)
{
    assert_true(scene->material_texture_count >= scene->material_count);
    return &scene->material_textures[scene->material_count - 1];
}

static void test_slots(void **state)
{
    (void)state;
    RenderScene scene;
    const char *textures = "Texture \"f\" \"float\" \"constant\" \"float value\" 0.25\n"
                           "Texture \"s\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.4 0.3 ]\n";
    char before[1024];

    /* diffusetransmission: reflectance (spectrum program 1) and
     * transmittance (spectrum), its scale kept for them. */
    assert_int_equal(convert(quad_scene("dt.pbrt", textures,
                                        "Material \"diffusetransmission\" \"texture transmittance\" \"s\" "
                                        "\"rgb reflectance\" [ 0.2 0.2 0.2 ] \"float scale\" 0.5\n"),
                             &scene),
                     0);
    const MaterialTextures *t = last_material_textures(&scene);
    assert_true(t->transmittance >= 0);
    assert_int_equal(t->reflectance, -1);
    assert_float_equal(t->scale, 0.5f, 0.0f);
    assert_int_equal(scene.textures[t->transmittance].spectrum, 1);
    /* The constant reflectance is scaled on the host, as before. */
    assert_float_equal(scene.materials[scene.material_count - 1].reflectance[0], 0.1f, 1e-7f);
    render_scene_destroy(&scene);

    /* mix: amount. */
    snprintf(before, sizeof before,
             "%sMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
             "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n",
             textures);
    assert_int_equal(
        convert(quad_scene("mix.pbrt", before,
                           "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"texture amount\" \"f\"\n"),
                &scene),
        0);
    t = last_material_textures(&scene);
    assert_true(t->mix_amount >= 0);
    assert_int_equal(scene.textures[t->mix_amount].spectrum, 0);
    assert_int_equal(t->reflectance & t->transmittance & t->thickness & t->g & t->albedo, -1);
    assert_true(render_scene_features(&scene) & FEATURE_MIX);
    render_scene_destroy(&scene);

    /* coatedconductor: thickness, g, albedo and the conductor's roughness
     * (u and v from "conductor.roughness"; v overridden by a constant). */
    assert_int_equal(convert(quad_scene("cc.pbrt", textures,
                                        "Material \"coatedconductor\" \"texture thickness\" \"f\" \"texture g\" \"f\" "
                                        "\"texture albedo\" \"s\" \"texture conductor.roughness\" \"f\"\n"),
                             &scene),
                     0);
    t = last_material_textures(&scene);
    assert_true(t->thickness >= 0 && t->g >= 0 && t->albedo >= 0 && t->base_roughness[0] >= 0 &&
                t->base_roughness[1] >= 0);
    assert_int_equal(t->roughness[0] & t->roughness[1], -1);
    /* The constant base roughness is 0 (smooth): the texture makes it rough. */
    assert_true(render_scene_features(&scene) & FEATURE_ROUGH);
    render_scene_destroy(&scene);
    assert_int_equal(convert(quad_scene("cc2.pbrt", textures,
                                        "Material \"coatedconductor\" \"texture conductor.roughness\" \"f\" "
                                        "\"float conductor.vroughness\" 0.1\n"),
                             &scene),
                     0);
    t = last_material_textures(&scene);
    assert_true(t->base_roughness[0] >= 0);
    assert_int_equal(t->base_roughness[1], -1);
    render_scene_destroy(&scene);

    /* coateddiffuse: the same layer parameters. */
    assert_int_equal(convert(quad_scene("cd.pbrt", textures,
                                        "Material \"coateddiffuse\" \"texture thickness\" \"f\" \"texture albedo\" "
                                        "\"s\"\n"),
                             &scene),
                     0);
    t = last_material_textures(&scene);
    assert_true(t->thickness >= 0 && t->albedo >= 0);
    assert_int_equal(t->g & t->base_roughness[0], -1);
    render_scene_destroy(&scene);
}

static void test_bad_slots(void **state)
{
    (void)state;
    const char *textures = "Texture \"f\" \"float\" \"constant\" \"float value\" 0.25\n"
                           "Texture \"s\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.4 0.3 ]\n"
                           "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n";
    convert_fails(textures, "Material \"mix\" \"string materials\" [ \"a\" \"a\" ] \"texture amount\" \"s\"\n",
                  "\"s\" is a spectrum texture, \"amount\" takes a float texture");
    convert_fails(textures, "Material \"diffusetransmission\" \"texture transmittance\" \"f\"\n",
                  "\"f\" is a float texture, \"transmittance\" takes a spectrum texture");
    convert_fails(textures, "Material \"coateddiffuse\" \"texture thickness\" \"nope\"\n",
                  "no float texture named \"nope\"");
    convert_fails(textures, "Material \"coatedconductor\" \"texture albedo\" \"f\"\n",
                  "\"f\" is a float texture, \"albedo\" takes a spectrum texture");
    convert_fails(textures, "Material \"coateddiffuse\" \"texture g\" \"s\"\n",
                  "\"s\" is a spectrum texture, \"g\" takes a float texture");
    /* The constants are still checked where the textures are not. */
    convert_fails(textures,
                  "Material \"diffusetransmission\" \"texture reflectance\" \"s\" \"rgb transmittance\" [ 1 1 1 ] "
                  "\"float scale\" 1.5\n",
                  "\"scale\" must not be negative nor scatter more than it receives");
}

/* ---- on a device ---- */

/* The mean pass of the scene at `path`, SIDE x SIDE at 4 spp (malloc'd). */
static float *render_mean(const char *path)
{
    RenderScene scene;
    if (convert(path, &scene))
        fail_msg("%s", error);
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = 4;
    settings.seed = 3;
    RenderOutput out;
    if (renderer_run(&test_device, 1, &scene, &settings, &out, error, sizeof error) != 0)
        fail_msg("%s", error);
    size_t n = (size_t)out.width * out.height * 3;
    float *mean = malloc(n * sizeof *mean);
    memcpy(mean, out.pass[PASS_MEAN], n * sizeof *mean);
    render_output_free(&out);
    render_scene_destroy(&scene);
    return mean;
}

static int any_positive(const float *image)
{
    for (size_t i = 0; i < SIDE * SIDE * 3; ++i)
        if (image[i] > 0.0f)
            return 1;
    return 0;
}

/* Each case: the parameters as constant textures, and as constants. */
static void test_constant_textures_are_constants(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    static const char *const cases[][3] = {
        {"Texture \"r\" \"spectrum\" \"constant\" \"rgb value\" [ 0.3 0.35 0.4 ]\n"
         "Texture \"t\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.45 0.4 ]\n",
         "Material \"diffusetransmission\" \"texture reflectance\" \"r\" \"texture transmittance\" \"t\" "
         "\"float scale\" 0.9\n",
         "Material \"diffusetransmission\" \"rgb reflectance\" [ 0.3 0.35 0.4 ] \"rgb transmittance\" "
         "[ 0.5 0.45 0.4 ] \"float scale\" 0.9\n"},
        {"MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
         "MakeNamedMaterial \"blue\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.1 0.1 0.8 ]\n"
         "Texture \"a\" \"float\" \"constant\" \"float value\" 0.3\n",
         "Material \"mix\" \"string materials\" [ \"red\" \"blue\" ] \"texture amount\" \"a\"\n",
         "Material \"mix\" \"string materials\" [ \"red\" \"blue\" ] \"float amount\" 0.3\n"},
        {"Texture \"d\" \"float\" \"constant\" \"float value\" 0.05\n"
         "Texture \"g\" \"float\" \"constant\" \"float value\" 0.4\n"
         "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.6 0.7 ]\n",
         "Material \"coateddiffuse\" \"float roughness\" 0.2 \"texture thickness\" \"d\" \"texture g\" \"g\" "
         "\"texture albedo\" \"a\"\n",
         "Material \"coateddiffuse\" \"float roughness\" 0.2 \"float thickness\" 0.05 \"float g\" 0.4 "
         "\"rgb albedo\" [ 0.5 0.6 0.7 ]\n"},
        {"Texture \"d\" \"float\" \"constant\" \"float value\" 0.05\n"
         "Texture \"g\" \"float\" \"constant\" \"float value\" -0.3\n"
         "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 0.4 0.5 0.6 ]\n"
         "Texture \"r\" \"float\" \"constant\" \"float value\" 0.2\n",
         "Material \"coatedconductor\" \"float interface.roughness\" 0.1 \"texture conductor.roughness\" \"r\" "
         "\"texture thickness\" \"d\" \"texture g\" \"g\" \"texture albedo\" \"a\"\n",
         "Material \"coatedconductor\" \"float interface.roughness\" 0.1 \"float conductor.roughness\" 0.2 "
         "\"float thickness\" 0.05 \"float g\" -0.3 \"rgb albedo\" [ 0.4 0.5 0.6 ]\n"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        float *textured = render_mean(quad_scene("textured.pbrt", cases[i][0], cases[i][1]));
        float *constant = render_mean(quad_scene("constant.pbrt", cases[i][0], cases[i][2]));
        assert_true(any_positive(constant));
        if (memcmp(textured, constant, SIDE * SIDE * 3 * sizeof(float)) != 0)
            fail_msg("case %zu: %s renders differently from %s", i, cases[i][1], cases[i][2]);
        free(textured);
        free(constant);
    }
}

/* Pixels well inside each square of a 2 x 2 checkerboard of the quad
 * (uscale = vscale = 2). The camera's x runs along world -x (pbrt's LookAt
 * is left-handed): the left column sees u > 0.5, and the top row v > 0.5.
 * pbrt-v4's checkerboard is tex1 where floor(2u) + floor(2v) is even. */
static const int square_pixels[4][2] = {{4, 4}, {11, 4}, {4, 11}, {11, 11}};
static const int square_is_tex1[4] = {1, 0, 0, 1};

static const float *pixel(const float *image, const int xy[2])
{
    return image + 3 * (xy[1] * SIDE + xy[0]);
}

static void test_checkerboard_amount_selects_each_material(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* Amount 0 (tex1: the first material, red) and 1 (tex2: blue), against
     * a diffuse whose checkerboard reflectance has the same two colours. */
    float *mixed = render_mean(
        quad_scene("mix.pbrt",
                   "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
                   "MakeNamedMaterial \"blue\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.1 0.1 0.8 ]\n"
                   "Texture \"c\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 "
                   "\"float tex1\" 0 \"float tex2\" 1\n",
                   "Material \"mix\" \"string materials\" [ \"red\" \"blue\" ] \"texture amount\" \"c\"\n"));
    float *reference =
        render_mean(quad_scene("reference.pbrt",
                               "Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 "
                               "\"rgb tex1\" [ 0.8 0.1 0.1 ] \"rgb tex2\" [ 0.1 0.1 0.8 ]\n",
                               "Material \"diffuse\" \"texture reflectance\" \"c\"\n"));
    for (int i = 0; i < 4; ++i) {
        const float *m = pixel(mixed, square_pixels[i]), *r = pixel(reference, square_pixels[i]);
        int red = m[0] > m[2];
        printf("  pixel (%d, %d): %s (%g %g %g)\n", square_pixels[i][0], square_pixels[i][1], red ? "red" : "blue",
               (double)m[0], (double)m[1], (double)m[2]);
        assert_true(m[0] > 0.0f && m[2] > 0.0f);
        assert_int_equal(red, square_is_tex1[i]);
        assert_memory_equal(m, r, 3 * sizeof(float));
    }
    free(mixed);
    free(reference);
}

/* A Lambertian transmitter of transmittance T lit from behind by a point
 * light of intensity I at `light`: radiance T / pi * I cos / d^2 at the
 * quad's point seen through image position (px, py) in pixels (40 degrees
 * of field, camera at z = 4, image x along world -x). */
static double transmitted_radiance(double transmittance, double intensity, const double light[3], double px, double py)
{
    double half = 4.0 * tan(20.0 * 3.14159265358979323846 / 180.0);
    double x = -(2.0 * px / SIDE - 1.0) * half, y = (1.0 - 2.0 * py / SIDE) * half;
    double d[3] = {light[0] - x, light[1] - y, light[2]};
    double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    return transmittance / 3.14159265358979323846 * intensity * (fabs(d[2]) / sqrt(d2)) / d2;
}

static void test_checkerboard_transmittance(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    /* A light behind the quad, seen through the squares of transmittance
     * 0.8; those of 0 are black. */
    const char *behind = "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ -0.2 0.1 -2 ]\n";
    float *textured = render_mean(lit_quad_scene(
        "transmits.pbrt", behind,
        "Texture \"t\" \"spectrum\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 "
        "\"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0 0 0 ]\n",
        "Material \"diffusetransmission\" \"rgb reflectance\" [ 0 0 0 ] \"texture transmittance\" \"t\"\n"));
    float *constant = render_mean(lit_quad_scene(
        "constant.pbrt", behind, "",
        "Material \"diffusetransmission\" \"rgb reflectance\" [ 0 0 0 ] \"rgb transmittance\" [ 0.8 0.8 0.8 ]\n"));
    for (int i = 0; i < 4; ++i) {
        const float *t = pixel(textured, square_pixels[i]), *c = pixel(constant, square_pixels[i]);
        printf("  pixel (%d, %d): %g %g %g (constant %g)\n", square_pixels[i][0], square_pixels[i][1], (double)t[0],
               (double)t[1], (double)t[2], (double)c[0]);
        if (square_is_tex1[i]) {
            /* The mean of 4 samples over the pixel lies within the range
             * the radiance spans over it (a 16 x 16 grid, and 0.5% for
             * the grid's and the filter's reach). */
            static const double light[3] = {-0.2, 0.1, -2.0};
            double low = INFINITY, high = 0.0;
            for (int g = 0; g < 256; ++g) {
                double r = transmitted_radiance(0.8, 3.0, light, square_pixels[i][0] + (g % 16 + 0.5) / 16.0,
                                                square_pixels[i][1] + (g / 16 + 0.5) / 16.0);
                low = fmin(low, r);
                high = fmax(high, r);
            }
            printf("    expected %g..%g\n", low, high);
            assert_true(t[0] > 0.995 * low && t[0] < 1.005 * high);
            assert_memory_equal(t, c, 3 * sizeof(float));
        } else {
            assert_true(t[0] == 0.0f && t[1] == 0.0f && t[2] == 0.0f);
        }
    }
    free(textured);
    free(constant);
}

int main(void)
{
    const struct CMUnitTest host[] = {
        cmocka_unit_test(test_slots),
        cmocka_unit_test(test_bad_slots),
    };
    const struct CMUnitTest device[] = {
        cmocka_unit_test(test_constant_textures_are_constants),
        cmocka_unit_test(test_checkerboard_amount_selects_each_material),
        cmocka_unit_test(test_checkerboard_transmittance),
    };
    if (setup(NULL))
        return 1;
    int failed = cmocka_run_group_tests_name("host", host, NULL, NULL);
    int status = test_device_setup(NULL);
    if (status == 0)
        failed += cmocka_run_group_tests_name("device", device, NULL, NULL);
    test_device_teardown(NULL);
    teardown(NULL);
    return failed || status;
}
