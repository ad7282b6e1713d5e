/* The BVH: its nearest hit equals a brute-force search over every
 * primitive, for triangles and spheres, and any-hit agrees on occlusion. */
#include "intersect.h"
#include "render/bvh.h"
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
        Hit hit, nearest = {INFINITY, -1, 0, 0};
        for (int i = 0; i < bvh.primitive_count; ++i) {
            Hit h;
            if (intersect_primitive(&ray, &bvh.primitives[i], 1e-4f, nearest.t, &h)) {
                nearest = h;
                nearest.primitive = i;
            }
        }
        int found = bvh_intersect(bvh.nodes, bvh.primitives, &ray, 1e-4f, INFINITY, 0, &hit);
        assert_int_equal(found, nearest.primitive >= 0);
        if (found) {
            ++hits;
            assert_true(hit.t == nearest.t);
            Hit any;
            assert_true(bvh_intersect(bvh.nodes, bvh.primitives, &ray, 1e-4f, INFINITY, 1, &any));
            assert_true(any.t >= hit.t);
            /* A shadow ray stopping short of the nearest hit is blocked
             * exactly when brute force finds something before its end. */
            float end = hit.t * 0.5f;
            int blocked = 0;
            for (int i = 0; i < bvh.primitive_count && !blocked; ++i) {
                Hit h;
                blocked = intersect_primitive(&ray, &bvh.primitives[i], 1e-4f, end, &h);
            }
            assert_int_equal(bvh_intersect(bvh.nodes, bvh.primitives, &ray, 1e-4f, end, 1, &any), blocked);
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
    assert_false(bvh_intersect(bvh.nodes, bvh.primitives, &ray, 0.0f, INFINITY, 0, &hit));
    bvh_destroy(&bvh);
}

static void test_identical_primitives_stay_shallow(void **state)
{
    (void)state;
    /* Many copies of one triangle cannot be split by centroid. */
    Primitive p[100];
    for (int i = 0; i < 100; ++i)
        p[i] = (Primitive){{0, 0, 0}, PRIM_TRIANGLE, {1, 0, 0}, 0, {0, 1, 0}, -1};
    Bvh bvh;
    char error[256];
    assert_int_equal(bvh_build(p, 100, &bvh, error, sizeof error), 0);
    assert_true(bvh.largest_leaf > BVH_WIDTH); /* too many for a packet: tested one by one */
    Ray ray = {{0.2f, 0.2f, -1}, {0, 0, 1}};
    Hit hit;
    assert_true(bvh_intersect(bvh.nodes, bvh.primitives, &ray, 0.0f, INFINITY, 0, &hit));
    assert_true(fabsf(hit.t - 1.0f) < 1e-6f);
    bvh_destroy(&bvh);
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
        assert_true(bvh_intersect(bvh.nodes, bvh.primitives, &ray, 0.0f, INFINITY, 0, &hit));
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_brute_force),
        cmocka_unit_test(test_empty_scene),
        cmocka_unit_test(test_identical_primitives_stay_shallow),
        cmocka_unit_test(test_coordinates_near_the_float_limit),
        cmocka_unit_test(test_non_finite_primitive_is_an_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
