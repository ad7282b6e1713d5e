/* The BVH: its nearest hit equals a brute-force search over every
 * primitive, for triangles and spheres, and any-hit agrees on occlusion;
 * the traversal stays within the stack the builder says the tree needs. */

/* The highest the traversal stack has been since it was last reset. */
static int stack_high_water;
#define BVH_STACK_PUSHED(height) (stack_high_water = (height) > stack_high_water ? (height) : stack_high_water)

#include "intersect.h"
#include "render/bvh.h"
#include "render/render_scene.h"
#include "sample_streams.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static float uniform(TestRng *rng, float lo, float hi)
{
    return lo + (hi - lo) * (float)test_rng_uniform(rng);
}

/* Every sphere_every-th primitive a sphere (none if 0), the rest triangles. */
static Primitive *random_scene(int count, int sphere_every, TestRng *rng)
{
    Primitive *p = calloc((size_t)count, sizeof *p);
    for (int i = 0; i < count; ++i) {
        float centre[3] = {uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10)};
        p[i].material = i % 3;
        p[i].light = -1;
        if (sphere_every && i % sphere_every == 0) {
            p[i].kind = PRIM_SPHERE;
            memcpy(p[i].a, centre, sizeof centre);
            p[i].b[0] = uniform(rng, 0.05f, 0.6f);
        } else {
            p[i].kind = PRIM_TRIANGLE;
            for (int k = 0; k < 3; ++k) { /* a vertex and two edges */
                p[i].a[k] = centre[k] + uniform(rng, -1, 1);
                p[i].b[k] = uniform(rng, -1, 1);
                p[i].c[k] = uniform(rng, -1, 1);
            }
        }
    }
    return p;
}

static Ray random_ray(TestRng *rng)
{
    Ray r;
    float length = 0.0f;
    for (int k = 0; k < 3; ++k) {
        r.origin[k] = uniform(rng, -14, 14);
        r.direction[k] = (float)test_rng_gaussian(rng);
        length += r.direction[k] * r.direction[k];
    }
    for (int k = 0; k < 3; ++k)
        r.direction[k] /= sqrtf(length);
    if (test_rng_next(rng) % 10 == 0) /* axis-aligned rays exercise 1/0 = inf */
        r.direction[0] = r.direction[1] = 0.0f, r.direction[2] = 1.0f;
    return r;
}

static void check_against_brute_force(int count, int sphere_every, int ray_count, int min_hits, uint64_t seed)
{
    TestRng rng = test_rng(seed);
    Primitive *primitives = random_scene(count, sphere_every, &rng);
    Bvh bvh;
    char error[256];
    assert_int_equal(bvh_build(primitives, count, &bvh, error, sizeof error), 0);
    assert_int_equal(bvh.primitive_count, count);
    assert_true(bvh.depth < BVH_MAX_DEPTH);
    int hits = 0;
    for (int r = 0; r < ray_count; ++r) {
        Ray ray = random_ray(&rng);
        if (r % 2 == 0) { /* aim half the rays at a primitive so many hit */
            const Primitive *target = &bvh.primitives[test_rng_next(&rng) % (uint64_t)count];
            float length = 0.0f;
            for (int k = 0; k < 3; ++k) {
                ray.direction[k] = target->a[k] + uniform(&rng, -0.3f, 0.3f) - ray.origin[k];
                length += ray.direction[k] * ray.direction[k];
            }
            for (int k = 0; k < 3; ++k)
                ray.direction[k] /= sqrtf(length);
        }
        Hit hit, nearest = {INFINITY, -1, 0, 0, -1};
        for (int i = 0; i < bvh.primitive_count; ++i) {
            Hit h;
            if (intersect_primitive(&ray, &bvh.primitives[i], 1e-4f, nearest.t, &h)) {
                nearest = h;
                nearest.primitive = i;
            }
        }
        int found = bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 1e-4f, INFINITY,
                                  0, &hit);
        assert_int_equal(found, nearest.primitive >= 0);
        if (found) {
            ++hits;
            assert_true(hit.t == nearest.t);
            Hit any;
            assert_true(bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 1e-4f,
                                      INFINITY, 1, &any));
            assert_true(any.t >= hit.t);
            /* A shadow ray stopping short of the nearest hit is blocked
             * exactly when brute force finds something before its end. */
            float end = hit.t * 0.5f;
            int blocked = 0;
            for (int i = 0; i < bvh.primitive_count && !blocked; ++i) {
                Hit h;
                blocked = intersect_primitive(&ray, &bvh.primitives[i], 1e-4f, end, &h);
            }
            assert_int_equal(
                bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 1e-4f, end, 1, &any),
                blocked);
        }
    }
    printf("  %d primitives: %d nodes, depth %d, largest leaf %d, %d/%d rays hit\n", count, bvh.node_count, bvh.depth,
           bvh.largest_leaf, hits, ray_count);
    assert_true(hits >= min_hits);
    bvh_destroy(&bvh);
    free(primitives);
}

static void test_matches_brute_force(void **state)
{
    (void)state;
    check_against_brute_force(1, 7, 2000, 100, 1);
    check_against_brute_force(17, 7, 2000, 150, 2);
    check_against_brute_force(3000, 7, 4000, 1000, 3);
    /* Triangles only: every leaf is a triangle packet. */
    check_against_brute_force(17, 0, 2000, 150, 4);
    check_against_brute_force(3000, 0, 4000, 1000, 5);
}

static void test_empty_scene(void **state)
{
    (void)state;
    Bvh bvh;
    char error[256];
    assert_int_equal(bvh_build(NULL, 0, &bvh, error, sizeof error), 0);
    Ray ray = {{0, 0, 0}, {0, 0, 1}};
    Hit hit;
    assert_false(
        bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 0.0f, INFINITY, 0, &hit));
    bvh_destroy(&bvh);
}

static void test_identical_primitives_stay_shallow(void **state)
{
    (void)state;
    /* Many copies of one triangle cannot be split by centroid: they are
     * split by order, into leaves of one packet, and a ray meeting them all
     * stays within the stack the tree needs. */
    enum { COUNT = 20000 };
    Primitive *p = malloc(COUNT * sizeof *p);
    for (int i = 0; i < COUNT; ++i)
        p[i] = (Primitive){{0, 0, 0}, PRIM_TRIANGLE, {1, 0, 0}, 0, {0, 1, 0}, -1};
    Bvh bvh;
    char error[256];
    assert_int_equal(bvh_build(p, COUNT, &bvh, error, sizeof error), 0);
    printf("  %d identical triangles: depth %d, largest leaf %d, %d stack entries\n", COUNT, bvh.depth,
           bvh.largest_leaf, bvh.stack_need);
    assert_true(bvh.largest_leaf <= BVH_WIDTH);
    assert_true(bvh.depth <= 20);
    Ray ray = {{0.2f, 0.2f, -1}, {0, 0, 1}};
    Hit hit;
    stack_high_water = 0;
    assert_true(
        bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 0.0f, INFINITY, 0, &hit));
    assert_true(fabsf(hit.t - 1.0f) < 1e-6f);
    assert_true(stack_high_water > BVH_WIDTH);
    assert_true(stack_high_water <= bvh.stack_need);
    bvh_destroy(&bvh);
    free(p);
}

/* Centroids near the float limit: their span overflows a float to inf, and
 * binning them in float converted NaN to int (undefined behaviour, which
 * the clang_ubsan test sees). Nearest hits still match brute force. */
static void test_coordinates_near_the_float_limit(void **state)
{
    (void)state;
    enum { COUNT = 40 };
    const float width = 1e33f; /* wide enough to be more than a float step at 3e38 */
    Primitive p[COUNT];
    for (int i = 0; i < COUNT; ++i) {
        float x = (float)(i - COUNT / 2) * 1.7e37f; /* -3.4e38 to 3.2e38 */
        p[i] = (Primitive){{x, 0, 5}, PRIM_TRIANGLE, {width, 0, 0}, i, {0, 1, 0}, -1};
    }
    Bvh bvh;
    char error[256];
    assert_int_equal(bvh_build(p, COUNT, &bvh, error, sizeof error), 0);
    for (int i = 0; i < COUNT; ++i) {
        Ray ray = {{p[i].a[0] + 0.25f * width, 0.25f, 0}, {0, 0, 1}};
        Hit hit;
        assert_true(bvh_intersect(&(Geometry){.nodes = bvh.nodes, .primitives = bvh.primitives}, &ray, 0.0f, INFINITY,
                                  0, &hit));
        assert_int_equal(bvh.primitives[hit.primitive].material, i);
        assert_true(hit.t == 5.0f);
    }
    bvh_destroy(&bvh);
}

/* A primitive with an infinite or NaN bound is an error, not a tree. */
static void test_non_finite_primitive_is_an_error(void **state)
{
    (void)state;
    Primitive p[3];
    for (int i = 0; i < 3; ++i)
        p[i] = (Primitive){{(float)i, 0, 0}, PRIM_TRIANGLE, {1, 0, 0}, 0, {0, 1, 0}, -1};
    const float bad[2] = {INFINITY, NAN};
    for (int b = 0; b < 2; ++b) {
        p[1].c[2] = bad[b];
        Bvh bvh;
        char error[256] = "";
        assert_int_equal(bvh_build(p, 3, &bvh, error, sizeof error), -1);
        assert_non_null(strstr(error, "primitive 1 has non-finite bounds"));
        assert_null(bvh.nodes);
    }
}

/* An object of random triangles (input order: its primitive j is input
 * j) drawn by instances with the given transforms, and the flattened
 * scene: each instance's triangles transformed in double and rounded
 * (instance k's triangle j is input k * n + j). */
static void instanced_and_flat(const Primitive *object, int n, const double (*transforms)[3][4], int instances,
                               RenderScene *instanced, RenderScene *flat)
{
    char error[256];
    render_scene_init(instanced);
    render_scene_init(flat);
    Material m = {0};
    assert_int_equal(render_scene_add_material(instanced, &m), 0);
    assert_int_equal(render_scene_add_material(flat, &m), 0);
    assert_int_equal(render_scene_begin_object(instanced), 0);
    for (int j = 0; j < n; ++j) {
        float v[3][3];
        for (int k = 0; k < 3; ++k) {
            v[0][k] = object[j].a[k];
            v[1][k] = object[j].a[k] + object[j].b[k];
            v[2][k] = object[j].a[k] + object[j].c[k];
        }
        assert_int_equal(render_scene_add_triangle(instanced, v[0], v[1], v[2], 0, NULL, 0, 0), 0);
    }
    render_scene_end_object(instanced);
    for (int i = 0; i < instances; ++i) {
        assert_int_equal(render_scene_add_instance(instanced, 0, transforms[i], error, sizeof error), 0);
        for (int j = 0; j < n; ++j) {
            const Primitive *o = &instanced->primitives[j];
            float v[3][3];
            for (int corner = 0; corner < 3; ++corner)
                for (int r = 0; r < 3; ++r) {
                    double p[3];
                    for (int k = 0; k < 3; ++k)
                        p[k] = o->a[k] + (corner == 1 ? o->b[k] : corner == 2 ? o->c[k] : 0.0f);
                    const double *row = transforms[i][r];
                    v[corner][r] = (float)(row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3]);
                }
            assert_int_equal(render_scene_add_triangle(flat, v[0], v[1], v[2], 0, NULL, 0, 0), 0);
        }
    }
    assert_int_equal(render_scene_finalize(instanced, error, sizeof error), 0);
    assert_int_equal(render_scene_finalize(flat, error, sizeof error), 0);
    assert_int_equal(instanced->instance_count, instances);
}

static int trace(const RenderScene *scene, const Ray *ray, int any_hit, float t_max, Hit *hit)
{
    Geometry g = {.nodes = scene->bvh.nodes,
                  .primitives = scene->bvh.primitives,
                  .instances = scene->instances,
                  .alphas = scene->alphas};
    return bvh_intersect(&g, ray, 0.0f, t_max, any_hit, hit);
}

/* Rays hit an instanced object where they hit it flattened. For the
 * transforms float arithmetic does exactly (power-of-two scales, per axis
 * too, mirrors, a quarter turn about z: the ray's object-space twin then
 * rounds as the flattened triangles do) the hits agree bit for bit; for
 * any rotation and translation, up to rounding. */
static void check_instances(const double (*transforms)[3][4], int instances, int exact, uint64_t seed)
{
    TestRng rng = test_rng(seed);
    enum { N = 300, RAYS = 4000 };
    Primitive *object = random_scene(N, 0, &rng);
    RenderScene instanced, flat;
    instanced_and_flat(object, N, transforms, instances, &instanced, &flat);
    int hits = 0, same = 0;
    stack_high_water = 0;
    for (int r = 0; r < RAYS; ++r) {
        Ray ray = random_ray(&rng);
        Hit a, b;
        int found = trace(&instanced, &ray, 0, INFINITY, &a);
        assert_true(stack_high_water <= instanced.bvh.stack_need);
        int flat_found = trace(&flat, &ray, 0, INFINITY, &b);
        if (exact)
            assert_int_equal(found, flat_found);
        if (!found || !flat_found)
            continue;
        hits++;
        int flat_index = flat.bvh.order[b.primitive];
        int agree = a.instance * N + instanced.bvh.order[a.primitive] == flat_index;
        same += agree;
        if (exact) {
            assert_true(agree);
            assert_memory_equal(&a.t, &b.t, sizeof a.t);
            assert_memory_equal(&a.u, &b.u, sizeof a.u);
            assert_memory_equal(&a.v, &b.v, sizeof a.v);
        } else if (agree) {
            assert_true(fabsf(a.t - b.t) <= 1e-4f * (1.0f + b.t));
        }
        Hit any; /* shadow rays: blocked before the hit as flattened, and by the hit */
        float before = a.t * (1.0f - 1e-4f);
        if (exact)
            assert_int_equal(trace(&instanced, &ray, 1, before, &any), trace(&flat, &ray, 1, before, &b));
        assert_true(trace(&instanced, &ray, 1, INFINITY, &any));
    }
    printf("  %d instances, %s transforms: %d of %d rays hit, %d on the same triangle as flattened\n", instances,
           exact ? "exact" : "general", hits, RAYS, same);
    assert_true(hits > RAYS / 10);
    assert_true(same >= hits - hits / 100);
    render_scene_destroy(&instanced);
    render_scene_destroy(&flat);
    free(object);
}

static void test_instances_hit_as_flattened(void **state)
{
    (void)state;
    const double exact[][3][4] = {
        {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},      {{2, 0, 0, 0}, {0, 2, 0, 0}, {0, 0, 2, 0}},
        {{0.5, 0, 0, 0}, {0, 0.25, 0, 0}, {0, 0, 4, 0}}, {{-1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0.5, 0}},
        {{0, -1, 0, 0}, {1, 0, 0, 0}, {0, 0, 1, 0}},
    };
    check_instances(exact, 5, 1, 21);
    double general[4][3][4];
    for (int i = 0; i < 4; ++i) { /* rotations about (1, 1, 1) / sqrt(3), scales, translations */
        double angle = 0.7 + 1.3 * i, c = cos(angle), s = sin(angle), t = 1.0 - c, x = 1.0 / sqrt(3.0);
        double scale = 0.5 + 0.75 * i, axis[3] = {x, x, x};
        for (int r = 0; r < 3; ++r) {
            for (int k = 0; k < 3; ++k) {
                double cross = r == k ? 0.0 : ((k == (r + 1) % 3) ? -axis[3 - r - k] : axis[3 - r - k]);
                general[i][r][k] = scale * (t * axis[r] * axis[k] + (r == k ? c : s * cross));
            }
            general[i][r][3] = 3.0 * i - 4.0 + r;
        }
    }
    check_instances((const double(*)[3][4])general, 4, 0, 22);
}

/* Leaves that hold instances (several a leaf) push them on the traversal
 * stack: many small instances stay within it and hit as flattened. */
static void test_many_instances(void **state)
{
    (void)state;
    static double transforms[512][3][4];
    for (int i = 0; i < 512; ++i) {
        memset(transforms[i], 0, sizeof transforms[i]);
        for (int r = 0; r < 3; ++r)
            transforms[i][r][r] = 0.125;
        transforms[i][0][3] = 2.0 * (i % 8) - 7.0;
        transforms[i][1][3] = 2.0 * (i / 8 % 8) - 7.0;
        transforms[i][2][3] = 2.0 * (i / 64) - 7.0;
    }
    check_instances((const double(*)[3][4])transforms, 512, 0, 23);
}

/* Instances whose boxes share a centroid (identical ones, copies scaled
 * about one point) cannot be split by centroid: the top level splits them
 * by order, so that a leaf's instances, all pushed when it is met, stay
 * few. Rays meeting all of them hit as flattened, within the stack the
 * tree needs (the kernels get that size: it overflowed a fixed 128). */
static void check_coincident_instances(const double (*transforms)[3][4], int instances, int exact, uint64_t seed)
{
    TestRng rng = test_rng(seed);
    enum { N = 4, RAYS = 100 };
    Primitive *object = random_scene(N, 0, &rng);
    RenderScene instanced, flat;
    instanced_and_flat(object, N, transforms, instances, &instanced, &flat);
    assert_true(instanced.bvh.largest_leaf <= BVH_WIDTH);
    int hits = 0, high_water = 0;
    for (int r = 0; r < RAYS; ++r) {
        /* At a point of a random instance's triangle, through the others. */
        const Primitive *t = &object[r % N];
        double scale = transforms[r * 7919 % instances][0][0]; /* uniform, about the origin */
        Ray ray = {{uniform(&rng, -20, 20), uniform(&rng, -20, 20), -20}, {0, 0, 0}};
        for (int k = 0; k < 3; ++k)
            ray.direction[k] = (float)(scale * (t->a[k] + 0.3f * t->b[k] + 0.3f * t->c[k])) - ray.origin[k];
        Hit a, b;
        stack_high_water = 0;
        int found = trace(&instanced, &ray, 0, INFINITY, &a);
        high_water = stack_high_water > high_water ? stack_high_water : high_water;
        assert_true(stack_high_water <= instanced.bvh.stack_need);
        assert_int_equal(found, trace(&flat, &ray, 0, INFINITY, &b));
        if (!found)
            continue;
        hits++;
        if (exact)
            assert_memory_equal(&a.t, &b.t, sizeof a.t);
        else
            assert_true(fabsf(a.t - b.t) <= 1e-4f * (1.0f + b.t));
    }
    printf("  %d coincident instances: %d of %d rays hit, stack up to %d of the %d entries the tree needs\n", instances,
           hits, RAYS, high_water, instanced.bvh.stack_need);
    assert_true(hits > RAYS / 10);
    assert_true(high_water > BVH_WIDTH);
    render_scene_destroy(&instanced);
    render_scene_destroy(&flat);
    free(object);
}

static void test_coincident_instances(void **state)
{
    (void)state;
    enum { COUNT = 3000 };
    double(*transforms)[3][4] = calloc(COUNT, sizeof *transforms);
    for (int i = 0; i < COUNT; ++i)
        for (int r = 0; r < 3; ++r)
            transforms[i][r][r] = 1.0;
    check_coincident_instances((const double(*)[3][4])transforms, COUNT, 1, 24);
    for (int i = 0; i < COUNT; ++i)
        for (int r = 0; r < 3; ++r)
            transforms[i][r][r] = 0.1 + 2.0 * i / COUNT; /* scaled about the origin */
    check_coincident_instances((const double(*)[3][4])transforms, COUNT, 0, 25);
    free(transforms);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_brute_force),
        cmocka_unit_test(test_empty_scene),
        cmocka_unit_test(test_identical_primitives_stay_shallow),
        cmocka_unit_test(test_coordinates_near_the_float_limit),
        cmocka_unit_test(test_non_finite_primitive_is_an_error),
        cmocka_unit_test(test_instances_hit_as_flattened),
        cmocka_unit_test(test_many_instances),
        cmocka_unit_test(test_coincident_instances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
