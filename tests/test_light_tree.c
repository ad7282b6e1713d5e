/* The light tree (kernels/tracing/light_tree.h, host/render/light_tree_build.c)
 * and the light samplers' chances (lights.h pick_light_at, light_pick_pmf),
 * on the host: chances that sum to 1 over the lights at any shading point;
 * a walk down the tree picks each light as often as light_pick_pmf says,
 * and reports that very chance; the bounds are conservative (a light whose
 * chance is 0 cannot light the point); merged direction cones hold both. */
#include "lights.h"
#include "render/light_tree_build.h"
#include "render/render_scene.h"

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

static uint64_t rng_state = 0x853c49e6748fea9bull;

static double uniform(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) * 0x1.0p-53;
}

static void random_unit(double w[3])
{
    double z = 1.0 - 2.0 * uniform(), phi = 2.0 * PI * uniform(), r = sqrt(fmax(0.0, 1.0 - z * z));
    w[0] = r * cos(phi);
    w[1] = r * sin(phi);
    w[2] = z;
}

/* The kernel's view of a finalized scene. */
static Scene kernel_view(const RenderScene *rs)
{
    Scene s;
    RenderSceneArrays a = render_scene_arrays(rs);
    s.constants = &rs->constants;
#define ASSIGN(name, type) s.name = a.name;
    GMON_SCENE_ARRAYS(ASSIGN)
#undef ASSIGN
    return s;
}

/* A Veach-like row of sphere lights of equal power and a range of sizes,
 * one- and two-sided triangles facing random ways, a point, a spot, a
 * distant light and a uniform infinite one: every kind the tree holds and
 * the unbounded ones beside it. */
static void mixed_scene(RenderScene *scene, uint32_t light_sampler)
{
    render_scene_init(scene);
    Material m;
    memset(&m, 0, sizeof m);
    m.type = MAT_DIFFUSE;
    int material = render_scene_add_material(scene, &m);
    for (int i = 0; i < 5; ++i) {
        float centre[3] = {-4.0f + 2.0f * i, 1.0f, 0.0f}, radius = 0.05f + 0.2f * i;
        float radiance = 1.0f / (radius * radius), emission[3] = {radiance, radiance, radiance};
        assert_int_equal(render_scene_add_sphere(scene, centre, radius, material, emission, 0, 0), 0);
    }
    for (int i = 0; i < 24; ++i) {
        double centre[3] = {6.0 * uniform() - 3.0, 6.0 * uniform() - 3.0, 6.0 * uniform() - 3.0}, e1[3], e2[3];
        random_unit(e1);
        random_unit(e2);
        float a[3], b[3], c[3], emission[3] = {1.0f + (float)i, 2.0f, 0.5f};
        for (int k = 0; k < 3; ++k) {
            a[k] = (float)centre[k];
            b[k] = (float)(centre[k] + 0.5 * e1[k]);
            c[k] = (float)(centre[k] + 0.5 * e2[k]);
        }
        assert_int_equal(render_scene_add_triangle(scene, a, b, c, material, emission, i % 3 == 0, i % 2), 0);
    }
    Light point, spot, distant, sky;
    memset(&point, 0, sizeof point);
    point.type = LIGHT_POINT;
    point.primitive = -1;
    point.position[1] = 3.0f;
    point.radiance[0] = point.radiance[1] = point.radiance[2] = 5.0f;
    spot = point;
    spot.type = LIGHT_SPOT;
    spot.position[0] = 2.0f;
    spot.direction[1] = -1.0f;
    spot.cos_falloff_start = 0.95f;
    spot.cos_total_width = 0.9f;
    distant = point;
    distant.type = LIGHT_DISTANT;
    distant.direction[2] = 1.0f;
    sky = point;
    sky.type = LIGHT_UNIFORM_INFINITE;
    assert_int_equal(render_scene_add_light(scene, &point), 0);
    assert_int_equal(render_scene_add_light(scene, &spot), 0);
    assert_int_equal(render_scene_add_light(scene, &distant), 0);
    assert_int_equal(render_scene_add_light(scene, &sky), 0);
    const float position[3] = {0, 0, 10}, forward[3] = {0, 0, -1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera camera = render_camera_pinhole(position, forward, right, up, 0.5f, 0.5f, 4, 4);
    render_scene_set_camera(scene, &camera);
    scene->constants.integrator.light_sampler = light_sampler;
    char error[256];
    assert_int_equal(render_scene_finalize(scene, error, sizeof error), 0);
}

static void random_point(Vec3 *p, Vec3 *n, int with_normal)
{
    *p = vec3((float)(8.0 * uniform() - 4.0), (float)(8.0 * uniform() - 4.0), (float)(8.0 * uniform() - 4.0));
    double w[3];
    random_unit(w);
    *n = with_normal ? vec3((float)w[0], (float)w[1], (float)w[2]) : vec3(0.0f, 0.0f, 0.0f);
}

/* Over all lights the chances sum to 1 for the fixed-chance samplers. With
 * the tree they sum to at most 1: a walk may reach a subtree none of whose
 * lights may light the point (its merged bounds are looser than theirs)
 * and pick nothing, as pbrt-v4's does; the unbounded lights come first,
 * with the tree's share split as pbrt-v4's bvh sampler splits it. */
static void test_chances_sum_to_one(void **state)
{
    (void)state;
    for (uint32_t sampler = 0; sampler < LIGHT_SAMPLER_COUNT; ++sampler) {
        RenderScene rs;
        mixed_scene(&rs, sampler);
        Scene s = kernel_view(&rs);
        assert_int_equal(rs.constants.integrator.unbounded_lights, 2);
        assert_int_equal(rs.lights[0].type, LIGHT_UNIFORM_INFINITE);
        assert_int_equal(rs.lights[1].type, LIGHT_DISTANT);
        assert_int_equal(rs.light_node_count, 2 * (rs.light_count - 2) - 1);
        double worst = 0.0, lost = 0.0;
        for (int trial = 0; trial < 2000; ++trial) {
            Vec3 p, n;
            random_point(&p, &n, trial % 4 != 0);
            double total = 0.0;
            for (int i = 0; i < rs.light_count; ++i) {
                double pmf = light_pick_pmf(&s, s.lights + i, p, n);
                assert_true(pmf >= 0.0 && pmf <= 1.0);
                total += pmf;
            }
            if (sampler == LIGHT_SAMPLER_TREE) {
                assert_true(total <= 1.0 + 2e-5);
                lost = fmax(lost, 1.0 - total);
            } else {
                worst = fmax(worst, fabs(total - 1.0));
            }
        }
        if (sampler == LIGHT_SAMPLER_TREE) {
            printf("  bvh: chances over %d lights sum to at most 1 (the most a walk may find nothing: %.3g)\n",
                   rs.light_count, lost);
            assert_true(fabs(rs.lights[0].pick_probability - 1.0 / 3.0) < 1e-7);
        } else {
            printf("  %s: chances over %d lights sum to 1 within %.2g\n", light_sampler_name(sampler), rs.light_count,
                   worst);
            assert_true(worst < 2e-5);
        }
        render_scene_destroy(&rs);
    }
}

/* 2^18 evenly spaced u: each light is picked as often as its chance, the
 * chance pick_light_at reports is light_pick_pmf's for that light, bit for
 * bit, and a walk finds nothing as often as the chances fall short of 1. */
static void test_picks_follow_the_chances(void **state)
{
    (void)state;
    RenderScene rs;
    mixed_scene(&rs, LIGHT_SAMPLER_TREE);
    Scene s = kernel_view(&rs);
    enum { DRAWS = 1 << 18 };
    int *counts = calloc((size_t)rs.light_count, sizeof *counts);
    assert_non_null(counts);
    double worst = 0.0;
    for (int trial = 0; trial < 8; ++trial) {
        Vec3 p, n;
        random_point(&p, &n, trial != 0);
        memset(counts, 0, (size_t)rs.light_count * sizeof *counts);
        int none = 0;
        for (int k = 0; k < DRAWS; ++k) {
            float u = (float)((k + 0.5) / DRAWS), pmf = -1.0f;
            int i = pick_light_at(&s, p, n, u, &pmf);
            if (i < 0) {
                ++none;
                continue;
            }
            assert_true(i < rs.light_count);
            assert_true(pmf == light_pick_pmf(&s, s.lights + i, p, n));
            ++counts[i];
        }
        double total = 0.0;
        for (int i = 0; i < rs.light_count; ++i) {
            double expected = light_pick_pmf(&s, s.lights + i, p, n);
            total += expected;
            worst = fmax(worst, fabs(counts[i] / (double)DRAWS - expected));
        }
        worst = fmax(worst, fabs(none / (double)DRAWS - (1.0 - total)));
    }
    printf("  picked frequencies vs chances, worst difference %.2g\n", worst);
    assert_true(worst < 2e-4);
    free(counts);
    render_scene_destroy(&rs);
}

/* A bounded light with no chance at a point cannot light it: a one-sided
 * triangle then has the point behind its plane, a spot has it outside its
 * cone. Spheres and points have a chance everywhere. */
static void test_bounds_are_conservative(void **state)
{
    (void)state;
    RenderScene rs;
    mixed_scene(&rs, LIGHT_SAMPLER_TREE);
    Scene s = kernel_view(&rs);
    int zero = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        Vec3 p, n;
        random_point(&p, &n, 0);
        for (int i = 2; i < rs.light_count; ++i) {
            const Light *light = &rs.lights[i];
            if (light_pick_pmf(&s, s.lights + i, p, n) > 0.0f)
                continue;
            ++zero;
            if (light->type == LIGHT_AREA) {
                const Primitive *prim = &rs.bvh.primitives[light->primitive];
                assert_int_equal(prim->kind & PRIM_SPHERE, 0);
                assert_int_equal(light->two_sided, 0);
                Vec3 a = vec3_from(prim->a), b = vec3_from(prim->b), c = vec3_from(prim->c);
                Vec3 normal = v_normalize(v_cross(b, c));
                if (prim->kind & PRIM_FLIP_NORMAL)
                    normal = v_scale(normal, -1.0f);
                assert_true(v_dot(normal, v_sub(p, a)) <= 1e-5f);
            } else {
                assert_int_equal(light->type, LIGHT_SPOT);
                Vec3 to_p = v_normalize(v_sub(p, vec3_from(light->position)));
                assert_true(v_dot(to_p, vec3_from(light->direction)) <= light->cos_total_width + 1e-5f);
            }
        }
    }
    printf("  %d (point, light) pairs with no chance, each unable to light the point\n", zero);
    assert_true(zero > 1000);
    render_scene_destroy(&rs);
}

/* Merged cones hold both: directions within either cone are within the
 * union's. */
static void test_cone_union_holds_both(void **state)
{
    (void)state;
    int checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        LightBounds a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        random_unit(a.axis);
        random_unit(b.axis);
        a.theta_o = PI * uniform() * uniform();
        b.theta_o = PI * uniform() * uniform();
        a.theta_e = b.theta_e = PI / 2.0;
        LightBounds u = light_bounds_union(&a, &b);
        for (int k = 0; k < 20; ++k) {
            const LightBounds *from = k % 2 ? &a : &b;
            double w[3];
            random_unit(w);
            double cos_w = w[0] * from->axis[0] + w[1] * from->axis[1] + w[2] * from->axis[2];
            if (acos(fmax(-1.0, fmin(1.0, cos_w))) > from->theta_o)
                continue;
            double cos_u = w[0] * u.axis[0] + w[1] * u.axis[1] + w[2] * u.axis[2];
            assert_true(acos(fmax(-1.0, fmin(1.0, cos_u))) <= u.theta_o + 1e-9);
            ++checked;
        }
    }
    printf("  %d directions of the merged cones held by their union\n", checked);
    assert_true(checked > 5000);
}

/* The build splits by orientation cost (power x box area x cone), not at
 * the median: Veach's row of four small lights and a far one 200 times as
 * powerful puts the far one alone under the root, so that the close
 * lights' subtree is not weighed with the far one's box. */
static void test_split_isolates_the_far_light(void **state)
{
    (void)state;
    LightBounds bounds[5];
    const double x[5] = {-3.75, -1.25, 1.25, 3.75, 10.0}, radius[5] = {0.03, 0.1, 0.3, 0.9, 0.5};
    for (int i = 0; i < 5; ++i) {
        Light light;
        memset(&light, 0, sizeof light);
        light.type = LIGHT_POINT;
        light.position[0] = (float)x[i];
        light.position[1] = i == 4 ? 10.0f : 0.0f;
        light.position[2] = i == 4 ? 4.0f : 0.0f;
        bounds[i] = light_bounds(&light, NULL, i == 4 ? 200.0 : 1.0);
        for (int k = 0; k < 3; ++k) {
            bounds[i].lower[k] -= radius[i];
            bounds[i].upper[k] += radius[i];
        }
    }
    LightNode *nodes;
    uint64_t *trails;
    int node_count;
    assert_int_equal(light_tree_build(bounds, 5, 0, &nodes, &node_count, &trails), 0);
    assert_int_equal(node_count, 9);
    printf("  the far light's trail: 0x%llx\n", (unsigned long long)trails[4]);
    assert_true(trails[4] == 2u || trails[4] == 3u); /* depth 1, either side */
    free(nodes);
    free(trails);
}

/* The MIS weight light_pick_pmf's chances feed: a^2 / (a^2 + b^2), also
 * for densities whose squares overflow single precision (a tiny light far
 * away has a cone density past 1e19). */
static void test_power_heuristic(void **state)
{
    (void)state;
    assert_true(fabsf(power_heuristic(3.0f, 4.0f) - 9.0f / 25.0f) < 1e-7f);
    assert_true(fabsf(power_heuristic(4.0f, 3.0f) - 16.0f / 25.0f) < 1e-7f);
    assert_true(power_heuristic(1e30f, 1e30f) == 0.5f);
    assert_true(fabsf(power_heuristic(3e25f, 4e25f) - 9.0f / 25.0f) < 1e-7f);
    assert_true(power_heuristic(1e30f, 0.0f) == 1.0f);
    assert_true(power_heuristic(0.0f, 1e30f) == 0.0f);
    assert_true(power_heuristic(0.0f, 0.0f) == 0.0f);
}

/* The light sampler names, as pbrt-v4's "lightsampler" and --light-sampler
 * spell them. */
static void test_names(void **state)
{
    (void)state;
    assert_int_equal(light_sampler_from_name("bvh"), LIGHT_SAMPLER_TREE);
    assert_int_equal(light_sampler_from_name("exhaustive"), LIGHT_SAMPLER_TREE);
    assert_int_equal(light_sampler_from_name("power"), LIGHT_SAMPLER_POWER);
    assert_int_equal(light_sampler_from_name("uniform"), LIGHT_SAMPLER_UNIFORM);
    assert_int_equal(light_sampler_from_name("spatial"), -1);
    assert_string_equal(light_sampler_name(LIGHT_SAMPLER_TREE), "bvh");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chances_sum_to_one),
        cmocka_unit_test(test_picks_follow_the_chances),
        cmocka_unit_test(test_bounds_are_conservative),
        cmocka_unit_test(test_cone_union_holds_both),
        cmocka_unit_test(test_split_isolates_the_far_light),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_power_heuristic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
