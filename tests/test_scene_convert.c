/* From scene file to the kernels' scene, without a device: the repository's
 * scenes convert to finite primitives, emitters and light-picking
 * probabilities with a BVH; emitters whose radiance or area would overflow
 * a float are file:line errors; geometry at the limits the scene reader
 * allows still converts to finite values. Runs under clang's UBSan too
 * (the clang_ubsan test). */
#define _POSIX_C_SOURCE 200809L

#include "render/scene_convert.h"

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

static char temp_dir[64];
static char error[1024];

static int setup(void **state)
{
    (void)state;
    strcpy(temp_dir, "/tmp/gmon-convert-XXXXXX");
    return mkdtemp(temp_dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    return rmdir(temp_dir);
}

/* Writes temp_dir/name (removed by convert_text). */
static const char *write_scene(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", temp_dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    fclose(f);
    return path;
}

/* Loads and finalizes `path` at 16 x 16; returns scene_convert_load's
 * result (the scene is left empty on failure). */
static int convert(const char *path, RenderScene *scene)
{
    SceneSummary summary;
    error[0] = '\0';
    if (scene_convert_load(path, 0, 16, 16, 1, scene, &summary, error, sizeof error))
        return -1;
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
    return 0;
}

/* Every number the kernels read is finite, and the lights are picked with
 * probabilities that add up to 1. */
static void assert_finite(const RenderScene *scene)
{
    const CameraData *p = &scene->constants.camera;
    for (int k = 0; k < 3; ++k)
        assert_true(isfinite(p->position[k]) && isfinite(p->forward[k]) && isfinite(p->right[k]) && isfinite(p->up[k]));
    for (int i = 0; i < scene->bvh.primitive_count; ++i) {
        const Primitive *prim = &scene->bvh.primitives[i];
        for (int k = 0; k < 3; ++k)
            assert_true(isfinite(prim->a[k]) && isfinite(prim->b[k]) && isfinite(prim->c[k]));
    }
    double total = 0.0;
    for (int i = 0; i < scene->light_count; ++i) {
        const Light *e = &scene->lights[i];
        assert_true(e->type != LIGHT_AREA || (isfinite(e->area) && e->area > 0.0f));
        for (int k = 0; k < 3; ++k)
            assert_true(isfinite(e->radiance[k]));
        assert_true(isfinite(e->pick_probability));
        total += e->pick_probability;
    }
    if (scene->light_count > 0)
        assert_true(fabs(total - 1.0) < 1e-5);
}

static void test_repository_scenes(void **state)
{
    (void)state;
    static const char *const names[] = {"scenes/cornell-diffuse.pbrt", "scenes/cornell-glass.pbrt",
                                        "scenes/narrow-gap.pbrt", "scenes/furnace.pbrt", "tests/data/scenes/main.pbrt"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", GMON_SOURCE_DIR, names[i]);
        RenderScene scene;
        if (convert(path, &scene))
            fail_msg("%s", error);
        assert_true(scene.primitive_count > 0);
        assert_finite(&scene);
        /* pbrt-v4's default film is the identity: no film code compiled. */
        assert_int_equal(render_scene_features(&scene) & FEATURE_FILM_MATRIX, 0);
        render_scene_destroy(&scene);
    }
}

#define CAMERA "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"

/* An infinite radiance or emitter area made an all-black image; so did a
 * "power" spread over an area so small (or large) that the radiance left
 * single precision. */
static void test_overflowing_emitters_are_errors(void **state)
{
    (void)state;
    static const struct {
        const char *text, *needle;
    } cases[] = {
        {CAMERA "AreaLightSource \"diffuse\" \"rgb L\" [ 3e38 3e38 3e38 ] \"float scale\" 10\nShape \"sphere\"\n",
         ":4: AreaLightSource: the radiance L * scale, 3e+39, overflows single precision"},
        {CAMERA "AreaLightSource \"diffuse\"\nShape \"sphere\" \"float radius\" 1e20\n",
         ":5: Shape \"sphere\": the sphere (centre (0, 0, 0), radius 1e+20 in world space) reaches beyond 1e+18"},
        {CAMERA "LightSource \"infinite\" \"rgb L\" [ 3e38 3e38 3e38 ] \"float scale\" 10\n",
         ":4: LightSource \"infinite\": the radiance L * scale, 3e+39, overflows single precision"},
        {CAMERA "AreaLightSource \"diffuse\" \"float power\" 10\nShape \"sphere\" \"float radius\" 1e-20\n",
         ":4: AreaLightSource \"power\" 10 over its shape's area 1.25664e-39 gives a radiance of 2.53303e+39, which "
         "overflows single precision"},
        {CAMERA "AreaLightSource \"diffuse\" \"float power\" 1e-30\n"
                "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  3e9 0 0  0 3e9 0 ] \"integer indices\" [ 0 1 2 ]\n",
         ":4: AreaLightSource \"power\" 1e-30 over its shape's area 4.5e+18 gives a radiance of 7.07355e-50, which "
         "underflows single precision"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const char *path = write_scene("emitter.pbrt", cases[i].text);
        RenderScene scene;
        int result = convert(path, &scene);
        remove(path);
        if (result == 0)
            fail_msg("case %zu converted; expected \"%s\"", i, cases[i].needle);
        if (strncmp(error, path, strlen(path)) != 0 || !strstr(error, cases[i].needle))
            fail_msg("error \"%s\"; expected \"%s\" and \"%s\"", error, path, cases[i].needle);
        assert_int_equal(scene.primitive_count, 0);
    }
}

/* Just inside the reader's limits, every converted number stays finite. */
static void test_geometry_at_the_limits_converts(void **state)
{
    (void)state;
    const char *path =
        write_scene("limits.pbrt", CAMERA
                    "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 3e38 1 1 ]\n"
                    "  Translate 5e17 0 0\n  Shape \"sphere\" \"float radius\" 4.9e17\nAttributeEnd\n"
                    "AreaLightSource \"diffuse\"\n"
                    "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  3e9 0 0  0 3e9 0 ] \"integer indices\" [ 0 1 2 ]\n");
    RenderScene scene;
    int result = convert(path, &scene);
    remove(path);
    if (result)
        fail_msg("%s", error);
    assert_int_equal(scene.primitive_count, 2);
    assert_int_equal(scene.light_count, 2);
    assert_finite(&scene);
    render_scene_destroy(&scene);
}

/* "power" P on an area light: radiance P / (pi * sides * the area of each
 * of pbrt-v4's shapes, which each get their own light): a triangle of a
 * trianglemesh (a 2 x 2 quad of two: 2 each, so the quad emits 2 P), a
 * bilinear patch (the same quad as one patch: 4), a sphere (radius 0.5:
 * pi), a disk (radius 1: pi, over all its triangles). */
static void test_area_light_power(void **state)
{
    (void)state;
    const char *path = write_scene(
        "power.pbrt", CAMERA "AttributeBegin\n  AreaLightSource \"diffuse\" \"float power\" 100 \"float scale\" 2\n"
                             "  Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
                             "    \"integer indices\" [ 0 1 2  0 2 3 ]\n"
                             "  Shape \"bilinearmesh\" \"point3 P\" [ -1 -1 1  1 -1 1  -1 1 1  1 1 1 ]\nAttributeEnd\n"
                             "AreaLightSource \"diffuse\" \"float power\" 100 \"bool twosided\" true\n"
                             "Shape \"sphere\" \"float radius\" 0.5\n"
                             "Translate 0 0 2\nShape \"disk\"\n");
    RenderScene scene;
    int result = convert(path, &scene);
    remove(path);
    if (result)
        fail_msg("%s", error);
    const double pi = 3.14159265358979323846;
    const double expected[] = {2.0 * 100.0 / (pi * 2.0), 2.0 * 100.0 / (pi * 2.0), 2.0 * 100.0 / (pi * 4.0),
                               2.0 * 100.0 / (pi * 4.0), 100.0 / (pi * 2.0 * pi)};
    assert_true(scene.light_count > 5); /* the disk's triangles after the sphere */
    for (int i = 0; i < scene.light_count; ++i) {
        double e = i < 5 ? expected[i] : 100.0 / (pi * 2.0 * pi);
        if (!(fabs(scene.lights[i].radiance[1] - e) < 1e-5 * e))
            fail_msg("light %d: radiance %g, expected %g", i, (double)scene.lights[i].radiance[1], e);
    }
    render_scene_destroy(&scene);
}

/* A PLY file's faces are pbrt-v4's shapes: a quad (two triangles here) is
 * one light of its own area, 4, a triangle beside it another, of area 2. */
static void test_area_light_power_on_ply_faces(void **state)
{
    (void)state;
    const char *ply = write_scene("faces.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                                               "property float y\nproperty float z\nelement face 2\n"
                                               "property list uchar int vertex_indices\nend_header\n"
                                               "-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n-3 0 0\n4 0 1 2 3\n3 0 3 4\n");
    char ply_path[256];
    snprintf(ply_path, sizeof ply_path, "%s", ply);
    const char *path = write_scene("ply-power.pbrt", CAMERA "AreaLightSource \"diffuse\" \"float power\" 100\n"
                                                            "Shape \"plymesh\" \"string filename\" \"faces.ply\"\n");
    RenderScene scene;
    int result = convert(path, &scene);
    remove(path);
    remove(ply_path);
    if (result)
        fail_msg("%s", error);
    const double pi = 3.14159265358979323846;
    const double expected[3] = {100.0 / (pi * 4.0), 100.0 / (pi * 4.0), 100.0 / (pi * 2.0)};
    assert_int_equal(scene.light_count, 3);
    for (int i = 0; i < 3; ++i)
        if (!(fabs(scene.lights[i].radiance[1] - expected[i]) < 1e-5 * expected[i]))
            fail_msg("light %d: radiance %g, expected %g", i, (double)scene.lights[i].radiance[1], expected[i]);
    render_scene_destroy(&scene);
}

/* An "interface" shape is a medium's boundary, which changes nothing
 * without media: the converted scene is the scene without it, bit for bit. */
static void test_interface_changes_nothing(void **state)
{
    (void)state;
    const char *body = "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\nShape \"sphere\" \"float radius\" 0.5\n";
    char with_text[1024], without_text[1024];
    snprintf(without_text, sizeof without_text, CAMERA "%s", body);
    snprintf(with_text, sizeof with_text,
             CAMERA
             "%sAttributeBegin\n  Material \"interface\"\n  Shape \"sphere\" \"float radius\" 2\n"
             "  Shape \"trianglemesh\" \"point3 P\" [ -1 -1 -1  1 -1 -1  1 1 -1 ] \"integer indices\" [ 0 1 2 ]\n"
             "AttributeEnd\n",
             body);
    RenderScene with, without;
    const char *path = write_scene("interface.pbrt", with_text);
    int result = convert(path, &with);
    remove(path);
    if (result)
        fail_msg("%s", error);
    path = write_scene("plain.pbrt", without_text);
    result = convert(path, &without);
    remove(path);
    if (result)
        fail_msg("%s", error);
    assert_int_equal(with.primitive_count, 1);
    RenderSceneArrays a = render_scene_arrays(&with), b = render_scene_arrays(&without);
    /* The material array also holds the unused interface (after the others). */
    assert_int_equal(a.materials_count, b.materials_count + 1);
    a.materials_count = b.materials_count;
#define SAME_ARRAY(name, type)                                                                                         \
    assert_int_equal(a.name##_count, b.name##_count);                                                                  \
    if (a.name##_count > 0)                                                                                            \
        assert_memory_equal(a.name, b.name, a.name##_count * sizeof(type));
    GMON_SCENE_ARRAYS(SAME_ARRAY)
#undef SAME_ARRAY
    assert_memory_equal(&with.constants, &without.constants, sizeof with.constants);
    assert_true(render_scene_features(&with) == render_scene_features(&without));
    render_scene_destroy(&with);
    render_scene_destroy(&without);
}

/* The new materials reach the kernel's Material: types, a mix's
 * components by index, a coated conductor's two roughnesses. */
static void test_materials_convert(void **state)
{
    (void)state;
    const char *path = write_scene("materials.pbrt", CAMERA
                                   "MakeNamedMaterial \"a\" \"string type\" \"diffusetransmission\"\n"
                                   "MakeNamedMaterial \"b\" \"string type\" \"thindielectric\"\n"
                                   "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 0.25\n"
                                   "Shape \"sphere\"\n"
                                   "Material \"coatedconductor\" \"float interface.roughness\" 0.09 "
                                   "\"float conductor.roughness\" 0.16 \"rgb albedo\" [ 0.5 0.5 0.5 ]\n"
                                   "Shape \"sphere\" \"float radius\" 0.1\n"
                                   "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\n");
    RenderScene scene;
    int result = convert(path, &scene);
    remove(path);
    if (result)
        fail_msg("%s", error);
    assert_int_equal(scene.material_count, 4);
    const Material *mix = &scene.materials[2], *coated = &scene.materials[3];
    assert_int_equal(mix->type, MAT_MIX);
    assert_int_equal(scene.materials[mix->mix_materials[0]].type, MAT_DIFFUSE_TRANSMISSION);
    assert_int_equal(scene.materials[mix->mix_materials[1]].type, MAT_THIN_DIELECTRIC);
    assert_true(mix->mix_amount == 0.25f);
    assert_int_equal(coated->type, MAT_COATED_CONDUCTOR);
    assert_true(fabsf(coated->alpha_x - 0.3f) < 1e-6f && fabsf(coated->base_alpha_y - 0.4f) < 1e-6f);
    assert_true(coated->albedo[1] == 0.5f && coated->thickness == 0.01f && coated->sample_count == 1);
    uint64_t features = render_scene_features(&scene);
    uint64_t expected = FEATURE_DIFFUSE_TRANSMISSION | FEATURE_THIN_DIELECTRIC | FEATURE_MIX |
                        FEATURE_COATED_CONDUCTOR | FEATURE_LAYERED | FEATURE_ROUGH;
    assert_true((features & expected) == expected);
    assert_true((features & (FEATURE_COATED_DIFFUSE | FEATURE_DIELECTRIC | FEATURE_CONDUCTOR)) == 0);
    render_scene_destroy(&scene);
}

/* Integrator "rrthreshold" reaches the kernel's IntegratorData, at most 1
 * (above 1 pbrt-v4's roulette never terminates a path); 1 by default. */
static void test_roulette_threshold_converts(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        float expected;
    } cases[] = {{"", 1.0f},
                 {"Integrator \"volpath\" \"float rrthreshold\" 0\n", 0.0f},
                 {"Integrator \"path\" \"float rrthreshold\" 0.5\n", 0.5f},
                 {"Integrator \"path\" \"float rrthreshold\" 3\n", 1.0f}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char text[512];
        snprintf(text, sizeof text, "%s" CAMERA "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\nShape \"sphere\"\n",
                 cases[i].text);
        const char *path = write_scene("roulette.pbrt", text);
        RenderScene scene;
        int result = convert(path, &scene);
        remove(path);
        if (result)
            fail_msg("%s", error);
        assert_true(scene.constants.integrator.rr_threshold == cases[i].expected);
        render_scene_destroy(&scene);
    }
}

/* An instance the conversion refuses (the scene reader refuses it first:
 * here its transform is made singular after reading) is reported as what
 * it is, not as running out of memory. */
static void test_instance_error_is_not_out_of_memory(void **state)
{
    (void)state;
    const char *path = write_scene("instance.pbrt", "WorldBegin\nObjectBegin \"a\"\nShape \"sphere\"\nObjectEnd\n"
                                                    "ObjectInstance \"a\"\n");
    Scene scene;
    assert_int_equal(scene_load(path, NULL, &scene, error, sizeof error), 0);
    assert_int_equal(scene.instance_count, 1);
    memset(scene.instances[0].world_from_object, 0, sizeof scene.instances[0].world_from_object);
    RenderScene converted;
    SceneSummary summary;
    assert_int_equal(scene_convert(&scene, path, 16, 16, 1, &converted, &summary, error, sizeof error), -1);
    assert_non_null(strstr(error, "ObjectInstance \"a\": the instance's transform is singular"));
    assert_null(strstr(error, "out of memory"));
    scene_destroy(&scene);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_repository_scenes),
        cmocka_unit_test(test_overflowing_emitters_are_errors),
        cmocka_unit_test(test_area_light_power),
        cmocka_unit_test(test_geometry_at_the_limits_converts),
        cmocka_unit_test(test_interface_changes_nothing),
        cmocka_unit_test(test_materials_convert),
        cmocka_unit_test(test_roulette_threshold_converts),
        cmocka_unit_test(test_area_light_power_on_ply_faces),
        cmocka_unit_test(test_instance_error_is_not_out_of_memory),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
