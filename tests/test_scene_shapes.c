/* The tessellated shapes (disk, cylinder, bilinearmesh, loopsubdiv) against
 * closed forms and hand-derived values: area and silhouette, facing, (u, v)
 * and normals; Loop subdivision limit positions worked out from the Loop
 * masks with pbrt's weights; bad parameters as "file:line:" errors. Runs
 * under ASan and UBSan, as the parser's test. */
#define _POSIX_C_SOURCE 200809L

#include "scene/scene.h"

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

#include "scene_fixture.h"

#ifndef GMON_SOURCE_DIR
#define GMON_SOURCE_DIR "."
#endif

#define PI 3.14159265358979323846
#define WORLD "WorldBegin\n"

/* cross(v1 - v0, v2 - v0) of a triangle, in double, negated when its shape
 * is flipped: the side a one-sided light emits to, times twice the area. */
static void front(const Scene *s, size_t t, double out[3])
{
    const float *a = vertex(s, t, 0), *b = vertex(s, t, 1), *c = vertex(s, t, 2);
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
    double sign = s->shapes[s->triangles[t].shape].flip_normal ? -1.0 : 1.0;
    out[0] = sign * (e1[1] * e2[2] - e1[2] * e2[1]);
    out[1] = sign * (e1[2] * e2[0] - e1[0] * e2[2]);
    out[2] = sign * (e1[0] * e2[1] - e1[1] * e2[0]);
}

static double total_area(const Scene *s)
{
    double area = 0.0;
    for (size_t t = 0; t < s->triangle_count; ++t) {
        double n[3];
        front(s, t, n);
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return area;
}

/* The largest relative distance of the triangles' corners and edge
 * midpoints from the cylinder of `radius` around the z axis, among the
 * points farther than `inner` from it (the silhouette's error). */
static double silhouette_error(const Scene *s, double radius, double inner)
{
    double worst = 0.0;
    for (size_t t = 0; t < s->triangle_count; ++t)
        for (int a = 0; a < 3; ++a) {
            const float *p = vertex(s, t, a), *q = vertex(s, t, (a + 1) % 3);
            double points[2][2] = {{p[0], p[1]}, {0.5 * ((double)p[0] + q[0]), 0.5 * ((double)p[1] + q[1])}};
            for (int i = 0; i < 2; ++i) {
                double r = hypot(points[i][0], points[i][1]);
                if (r > inner && (i == 0 || fabs(hypot(q[0], q[1]) - hypot(p[0], p[1])) < 1e-3 * radius))
                    worst = fmax(worst, fabs(r - radius) / radius);
            }
        }
    return worst;
}

/* ---------------------------------------------------------------- disk */

static void test_disk_area_silhouette_and_uv(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Shape \"disk\" \"float radius\" 2 \"float height\" 0.5\n", &s);
    double area = total_area(&s);
    print_message("disk r = 2: %zu triangles, area %.9g, relative error %.2e, silhouette error %.2e\n",
                  s.triangle_count, area, fabs(area / (4.0 * PI) - 1.0), silhouette_error(&s, 2.0, 1.0));
    assert_near(area / (4.0 * PI), 1.0, 1e-6);
    assert_true(silhouette_error(&s, 2.0, 1.0) <= 1e-4);
    assert_int_equal(s.shape_count, 1);
    assert_null(s.normals); /* flat */
    assert_non_null(s.uvs);
    assert_true(s.shapes[0].has_uvs);
    for (size_t v = 0; v < s.vertex_count; ++v) {
        double r = hypot(s.positions[3 * v], s.positions[3 * v + 1]);
        assert_near(s.positions[3 * v + 2], 0.5, 1e-7);
        assert_near(s.uvs[2 * v + 1], 1.0 - r / 2.0, 1e-4); /* v = (radius - r) / (radius - innerradius) */
        if (r > 0.0 && s.uvs[2 * v] > 0.0 && s.uvs[2 * v] < 1.0) {
            double phi = atan2(s.positions[3 * v + 1], s.positions[3 * v]);
            assert_near(s.uvs[2 * v], (phi < 0 ? phi + 2 * PI : phi) / (2 * PI), 1e-5); /* u = phi / phimax */
        }
    }
    scene_destroy(&s);

    /* A quarter annulus under a uniform scale: (phimax / 2) (r^2 - ri^2) s^2. */
    load_ok(WORLD "Scale 3 3 3\nShape \"disk\" \"float radius\" 1 \"float innerradius\" 0.5 \"float phimax\" 90\n", &s);
    area = total_area(&s);
    double expected = 0.25 * PI * (1.0 - 0.25) * 9.0;
    print_message("quarter annulus: %zu triangles, area %.9g, relative error %.2e, silhouette error %.2e\n",
                  s.triangle_count, area, fabs(area / expected - 1.0), silhouette_error(&s, 3.0, 2.0));
    assert_near(area / expected, 1.0, 1e-6);
    assert_true(silhouette_error(&s, 3.0, 2.0) <= 1e-4);
    for (size_t v = 0; v < s.vertex_count; ++v) {
        double r = hypot(s.positions[3 * v], s.positions[3 * v + 1]);
        assert_true(r > 1.5 * (1 - 1e-4) && r < 3.0 * (1 + 1e-4));
        assert_true(s.positions[3 * v] >= -1e-6 && s.positions[3 * v + 1] >= -1e-6); /* the first quadrant */
    }
    scene_destroy(&s);
}

/* pbrt's disk faces +z: a one-sided disk light emits toward +z, and toward
 * -z after ReverseOrientation (killeroo-gold's light shines down so). */
static void test_disk_orientation(void **state)
{
    (void)state;
    static const struct {
        const char *transform;
        double z;
    } cases[] = {
        {"", 1.0},
        {"ReverseOrientation\n", -1.0},
        {"Rotate 180 1 0 0\n", -1.0},
        {"Scale 1 1 -1\n", -1.0}, /* a mirror keeps the object-space facing, mirrored */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char text[256];
        snprintf(text, sizeof text, WORLD "AreaLightSource \"diffuse\"\n%sShape \"disk\"\n", cases[i].transform);
        Scene s;
        load_ok(text, &s);
        assert_int_equal(s.area_light_count, 1);
        for (size_t t = 0; t < s.triangle_count; ++t) {
            double n[3];
            front(&s, t, n);
            assert_true(n[2] * cases[i].z > 0.0);
            assert_near(n[0], 0.0, 1e-6);
            assert_near(n[1], 0.0, 1e-6);
        }
        scene_destroy(&s);
    }
}

/* ------------------------------------------------------------ cylinder */

static void test_cylinder_area_normals_and_uv(void **state)
{
    (void)state;
    static const struct {
        const char *params;
        double radius, height, phi;
    } cases[] = {
        {"", 1.0, 2.0, 2 * PI},
        {"\"float radius\" 0.5 \"float zmin\" 1 \"float zmax\" 4", 0.5, 3.0, 2 * PI},
        {"\"float radius\" 2 \"float zmin\" 1 \"float zmax\" -1 \"float phimax\" 180", 2.0, 2.0, PI}, /* swapped */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char text[256];
        snprintf(text, sizeof text, WORLD "Shape \"cylinder\" %s\n", cases[i].params);
        Scene s;
        load_ok(text, &s);
        double area = total_area(&s), expected = cases[i].phi * cases[i].radius * cases[i].height;
        print_message("cylinder %s: %zu triangles, area relative error %.2e, silhouette error %.2e\n", cases[i].params,
                      s.triangle_count, fabs(area / expected - 1.0), silhouette_error(&s, cases[i].radius, 0.0));
        assert_near(area / expected, 1.0, 1e-6);
        assert_true(silhouette_error(&s, cases[i].radius, 0.0) <= 1e-4);
        assert_non_null(s.normals);
        for (size_t t = 0; t < s.triangle_count; ++t) {
            double n[3];
            front(&s, t, n);
            const float *p = vertex(&s, t, 0);
            assert_true(n[0] * p[0] + n[1] * p[1] > 0.0); /* outward */
            assert_near(n[2], 0.0, 1e-9);
        }
        float z_min = INFINITY, z_max = -INFINITY;
        for (size_t v = 0; v < s.vertex_count; ++v) {
            const float *p = s.positions + 3 * v, *n = s.normals + 3 * v;
            double r = hypot(p[0], p[1]);
            assert_near(n[0], p[0] / r, 1e-6); /* smooth, radial, unit */
            assert_near(n[1], p[1] / r, 1e-6);
            assert_near(n[2], 0.0, 1e-7);
            assert_true(p[1] >= -1e-6 || cases[i].phi > PI);
            z_min = fminf(z_min, p[2]);
            z_max = fmaxf(z_max, p[2]);
        }
        assert_near(z_max - z_min, cases[i].height, 1e-6);
        for (size_t v = 0; v < s.vertex_count; ++v)
            assert_near(s.uvs[2 * v + 1], (s.positions[3 * v + 2] - z_min) / cases[i].height, 1e-6);
        scene_destroy(&s);
    }
}

/* ------------------------------------------------------- bilinear patch */

static void test_bilinear_planar_patch_is_two_triangles(void **state)
{
    (void)state;
    Scene s;
    /* pbrt's corner order is p00, p10, p01, p11: this is the unit square. */
    load_ok(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  2 0 0  0 1 0  2 1 0 ]\n", &s);
    assert_int_equal(s.triangle_count, 2);
    assert_near(total_area(&s), 2.0, 1e-9);
    for (size_t t = 0; t < 2; ++t) {
        double n[3];
        front(&s, t, n);
        assert_true(n[2] > 0.0); /* cross(p10 - p00, p01 - p00) */
    }
    assert_null(s.normals);
    for (size_t v = 0; v < s.vertex_count; ++v) { /* uv: the patch's own (u, v) */
        assert_near(s.uvs[2 * v], s.positions[3 * v] / 2.0, 1e-7);
        assert_near(s.uvs[2 * v + 1], s.positions[3 * v + 1], 1e-7);
    }
    scene_destroy(&s);

    /* Two patches sharing an edge, with uv and N given: interpolated. */
    load_ok(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0  2 0 0  2 1 0 ]\n"
                  "  \"integer indices\" [ 0 1 2 3  1 4 3 5 ] \"point2 uv\" [ 0 0 1 0 0 1 1 1 2 0 2 1 ]\n"
                  "  \"normal N\" [ 0 0 1  0 0 1  0 0 1  0 0 1  0 0 1  0 0 1 ]\n",
            &s);
    assert_int_equal(s.triangle_count, 4);
    assert_near(total_area(&s), 2.0, 1e-9);
    for (size_t v = 0; v < s.vertex_count; ++v) {
        assert_near(s.uvs[2 * v], s.positions[3 * v], 1e-7);
        assert_near(s.uvs[2 * v + 1], s.positions[3 * v + 1], 1e-7);
        assert_near(s.normals[3 * v + 2], 1.0, 1e-7);
    }
    scene_destroy(&s);
}

/* The saddle z = u v over the unit square: its area by a fine midpoint
 * rule over |dp/du x dp/dv| = sqrt(1 + u^2 + v^2). */
static void test_bilinear_saddle_is_tessellated(void **state)
{
    (void)state;
    const int n = 2000;
    double expected = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double u = (i + 0.5) / n, v = (j + 0.5) / n;
            expected += sqrt(1.0 + u * u + v * v) / ((double)n * n);
        }
    Scene s;
    load_ok(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 1 ]\n", &s);
    double area = total_area(&s), worst = 0.0;
    for (size_t v = 0; v < s.vertex_count; ++v) { /* every vertex on the surface, its normal the surface's */
        const float *p = s.positions + 3 * v, *nv = s.normals + 3 * v;
        assert_near(p[2], (double)p[0] * p[1], 1e-6);
        double length = sqrt(1.0 + (double)p[0] * p[0] + (double)p[1] * p[1]);
        assert_near(nv[0], -p[1] / length, 1e-5);
        assert_near(nv[1], -p[0] / length, 1e-5);
        assert_near(nv[2], 1.0 / length, 1e-5);
    }
    for (size_t t = 0; t < s.triangle_count; ++t) { /* the surface's distance from each triangle's centre */
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int corner = 0; corner < 3; ++corner)
                c[k] += vertex(&s, t, corner)[k] / 3.0;
        worst = fmax(worst, fabs(c[2] - c[0] * c[1]));
    }
    print_message("saddle: %zu triangles, area %.7f (quadrature %.7f), relative error %.2e, largest distance %.2e\n",
                  s.triangle_count, area, expected, fabs(area / expected - 1.0), worst);
    assert_true(s.triangle_count > 2);
    assert_near(area / expected, 1.0, 1e-4);
    assert_true(worst <= 1e-4 * sqrt(3.0));
    scene_destroy(&s);
}

/* ----------------------------------------------------------- loopsubdiv */

#define TETRAHEDRON                                                                                                    \
    "\"point3 P\" [ 1 1 1  1 -1 -1  -1 1 -1  -1 -1 1 ] \"integer indices\" [ 0 1 2  0 3 1  0 2 3  1 3 2 ]"

static int find_vertex(const Scene *s, const double expected[3])
{
    for (size_t v = 0; v < s->vertex_count; ++v) {
        const float *p = s->positions + 3 * v;
        if (fabs(p[0] - expected[0]) < 1e-5 && fabs(p[1] - expected[1]) < 1e-5 && fabs(p[2] - expected[2]) < 1e-5)
            return (int)v;
    }
    fail_msg("no vertex at (%g, %g, %g)", expected[0], expected[1], expected[2]);
    return -1;
}

/* A regular tetrahedron (corners c, sum 0), wound outward. Valence 3, so
 * pbrt's beta = 3/16 and the limit weight gamma = 1 / (3 + 3 / (8 beta)) =
 * 1/5: a corner's limit is (1 - 3/5) c + 1/5 (sum of the others) = c / 5,
 * at every level. After one level, the new vertex on edge (a, b) lies at
 * 3/8 (a + b) + 1/8 (c + d) = (a + b) / 4 with valence 6 (beta 1/16, gamma
 * 1/12); its neighbours sum to (a + b) / 4, so its limit is m / 2 + (a +
 * b) / 48 = 7 (a + b) / 48. pbrt's limit normal points inward here (against
 * the winding), and the triangles face the same way. */
static void test_loop_tetrahedron_limit_positions(void **state)
{
    (void)state;
    static const double corners[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (int levels = 0; levels <= 2; ++levels) {
        char text[512];
        snprintf(text, sizeof text, WORLD "Shape \"loopsubdiv\" \"integer levels\" %d " TETRAHEDRON "\n", levels);
        Scene s;
        load_ok(text, &s);
        assert_int_equal(s.triangle_count, 4u << (2 * levels));
        assert_non_null(s.normals);
        for (int c = 0; c < 4; ++c) {
            double limit[3] = {corners[c][0] / 5, corners[c][1] / 5, corners[c][2] / 5};
            int v = find_vertex(&s, limit);
            for (int k = 0; k < 3; ++k)
                assert_near(s.normals[3 * v + k], -corners[c][k] / sqrt(3.0), 1e-5);
        }
        for (int a = 0; levels == 1 && a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) {
                double limit[3];
                for (int k = 0; k < 3; ++k)
                    limit[k] = 7.0 * (corners[a][k] + corners[b][k]) / 48.0;
                find_vertex(&s, limit);
            }
        if (levels == 1)
            assert_int_equal(s.vertex_count, 10);
        for (size_t t = 0; t < s.triangle_count; ++t) {
            double n[3], centre = 0.0;
            front(&s, t, n);
            for (int k = 0; k < 3; ++k)
                centre += n[k] * (vertex(&s, t, 0)[k] + vertex(&s, t, 1)[k] + vertex(&s, t, 2)[k]);
            assert_true(centre < 0.0); /* facing the centre, as the normals */
        }
        scene_destroy(&s);
    }
}

/* One triangle: every vertex and edge is on the boundary. Level 1 moves a
 * corner to 3/4 c + 1/8 (its two neighbours) and puts edge vertices at the
 * midpoints; the boundary limit is 3/5 p + 1/5 (its two boundary
 * neighbours): (0, 0, 0) -> (1/8, 1/8) -> 3/5 (1/8, 1/8) + 1/5 ((1/2, 0) +
 * (0, 1/2)) = (0.175, 0.175); (1, 0, 0) -> (3/4, 1/8) -> (0.65, 0.175); the
 * midpoint (1/2, 0, 0) -> 3/5 (1/2, 0) + 1/5 ((1/8, 1/8) + (3/4, 1/8)) =
 * (0.475, 0.05). */
static void test_loop_boundary_rules(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Shape \"loopsubdiv\" \"integer levels\" 1 \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] "
                  "\"integer indices\" [ 0 1 2 ]\n",
            &s);
    assert_int_equal(s.triangle_count, 4);
    static const double expected[][3] = {{0.175, 0.175, 0}, {0.65, 0.175, 0}, {0.175, 0.65, 0},
                                         {0.475, 0.05, 0},  {0.05, 0.475, 0}, {0.475, 0.475, 0}};
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; ++i) {
        int v = find_vertex(&s, expected[i]);
        assert_near(s.normals[3 * v + 2], -1.0, 1e-6); /* against the winding, as pbrt's */
    }
    for (size_t t = 0; t < s.triangle_count; ++t) {
        double n[3];
        front(&s, t, n);
        assert_true(n[2] < 0.0);
    }
    scene_destroy(&s);
}

/* killeroo-simple.pbrt (two Loop surfaces) loads when the public scenes are
 * there (../shared/scenes beside the checkout). */
static void test_killeroo_simple_loads(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/../shared/scenes/killeroos/killeroo-simple.pbrt", GMON_SOURCE_DIR);
    if (access(path, R_OK) != 0) {
        print_message("%s is not there\n", path);
        skip();
    }
    Scene s;
    if (scene_load(path, NULL, &s, error, sizeof error))
        fail_msg("%s", error);
    print_message("killeroo-simple: %zu shapes, %zu triangles, %zu vertices, %zu warnings\n", s.shape_count,
                  s.triangle_count, s.vertex_count, s.warning_count);
    assert_int_equal(s.warning_count, 0);
    assert_int_equal(s.shape_count, 5); /* the light, two walls, two killeroos */
    assert_non_null(s.normals);
    scene_destroy(&s);
}

/* ------------------------------------------------------------ bad input */

static void test_bad_parameters(void **state)
{
    (void)state;
    load_fails(WORLD "Shape \"disk\" \"float radius\" -1\n", 2, "radius -1 must be positive");
    load_fails(WORLD "Shape \"disk\" \"float radius\" 1 \"float innerradius\" 1\n", 2, "innerradius 1 must lie in");
    load_fails(WORLD "Shape \"disk\" \"float innerradius\" -0.5\n", 2, "innerradius -0.5 must lie in");
    load_fails(WORLD "Shape \"disk\" \"float phimax\" 0\n", 2, "phimax 0 must lie in (0, 360]");
    load_fails(WORLD "Shape \"cylinder\" \"float phimax\" 361\n", 2, "phimax 361 must lie in (0, 360]");
    load_fails(WORLD "Shape \"cylinder\" \"float radius\" 0\n", 2, "radius 0 must be positive");
    load_fails(WORLD "Shape \"cylinder\" \"float zmin\" 2 \"float zmax\" 2\n", 2, "no area");
    load_fails(WORLD "Shape \"cylinder\" \"float radius\" [ 1 2 ]\n", 2, "expected 1 value");
    load_fails(WORLD "Shape \"disk\" \"float zmin\" 0.5\n", 2, "unsupported parameter \"float zmin\"");
    load_fails(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 ]\n"
                     "  \"integer indices\" [ 0 1 2 3 4 ]\n",
               3, "5 vertex indices is not a multiple of 4");
    load_fails(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 ]\n", 2,
               "missing \"integer indices\"");
    load_fails(WORLD
               "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 ] \"integer indices\" [ 0 1 2 4 ]\n",
               2, "vertex index 4 (number 3) is out of range");
    load_fails(WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 ] \"point2 uv\" [ 0 0 1 0 ]\n", 2,
               "2 texture coordinates for 4 vertices");
    load_fails(WORLD "Shape \"bilinearmesh\" \"integer indices\" [ 0 1 2 3 ]\n", 2, "missing \"point3 P\"");
    static char saddles[16384]; /* 1800 curved patches of 2450 triangles each */
    int length =
        snprintf(saddles, sizeof saddles,
                 WORLD "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 1 ] \"integer indices\" [");
    for (int i = 0; i < 1800; ++i)
        length += snprintf(saddles + length, sizeof saddles - (size_t)length, " 0 1 2 3");
    snprintf(saddles + length, sizeof saddles - (size_t)length, " ]\n");
    load_fails(saddles, 2, "the curved patches make 4410000 triangles, over the limit of 4194304");
    load_fails(WORLD "Shape \"loopsubdiv\" \"integer levels\" -1 " TETRAHEDRON "\n", 2, "levels -1 must not be");
    load_fails(WORLD "Shape \"loopsubdiv\" \"integer levels\" 11 " TETRAHEDRON "\n", 2,
               "11 levels make 1.678e+07 triangles from 4, over the limit of 4194304");
    load_fails(WORLD "Shape \"loopsubdiv\" \"integer levels\" 2147483647 " TETRAHEDRON "\n", 2, "over the limit");
    load_fails(WORLD "Shape \"loopsubdiv\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n", 2, "missing \"integer indices\"");
    load_fails(WORLD "Shape \"loopsubdiv\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 1 ]\n", 2,
               "triangle 0 repeats a vertex");
    load_fails(WORLD "Shape \"loopsubdiv\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 0 0 1 1 1 1 ]\n"
                     "  \"integer indices\" [ 0 1 2  1 0 3  0 1 4 ]\n",
               2, "the edge between vertices 0 and 1 is in 3 triangles");
    load_fails(WORLD "Shape \"loopsubdiv\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 0 0 1 ]\n"
                     "  \"integer indices\" [ 0 1 2  0 1 3 ]\n",
               2, "wound in the same direction");
    /* Two fans meeting at vertex 0 (a bowtie). */
    load_fails(WORLD "Shape \"loopsubdiv\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  -1 0 0  0 -1 0 ]\n"
                     "  \"integer indices\" [ 0 1 2  0 3 4 ]\n",
               2, "the triangles around vertex 0 do not form one fan");
    load_fails(WORLD "Shape \"loopsubdiv\" \"string scheme\" \"catmull-clark\" " TETRAHEDRON "\n", 2,
               "scheme \"catmull-clark\" is not supported");
}

/* trianglemesh "uv" (or pbrt-v3's "st") reaches Scene.uvs. */
static void test_trianglemesh_uv(void **state)
{
    (void)state;
    Scene s;
    load_ok(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"point2 uv\" [ 0.5 0.25 1 0 0 1 ]\n"
                  "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n"
                  "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"point2 st\" [ 0 0 0.5 0.5 1 1 ]\n",
            &s);
    assert_non_null(s.uvs);
    assert_true(s.shapes[0].has_uvs);
    assert_false(s.shapes[1].has_uvs);
    assert_true(s.shapes[2].has_uvs);
    static const float expected[] = {0.5f, 0.25f, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0.5f, 1, 1};
    assert_memory_equal(s.uvs, expected, sizeof expected);
    scene_destroy(&s);
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"point2 uv\" [ 0 0 1 0 0 1 ]\n"
                     "  \"point2 st\" [ 0 0 1 0 0 1 ]\n",
               3, "give \"uv\" or \"st\", not both");
    load_fails(WORLD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"point2 uv\" [ 0 0 1 0 ]\n", 2,
               "2 texture coordinates for 3 vertices");
}

/* PLY texture coordinates under pbrt-v4's names: the first complete pair of
 * u v, s t, texture_u texture_v, texture_s texture_t (the last case has s t
 * before u v in the file: u v wins). */
static void test_ply_uv(void **state)
{
    (void)state;
    static const char *const properties[] = {
        "u\nproperty float v",
        "s\nproperty float t",
        "texture_u\nproperty float texture_v",
        "texture_s\nproperty float texture_t",
        "s\nproperty float t\nproperty float u\nproperty float v",
    };
    static const char *const values[] = {"", "", "", "", "9 9 "};
    char ply_path[512], text[768];
    snprintf(ply_path, sizeof ply_path, "%s", temp_path("uv.ply"));
    for (size_t i = 0; i < sizeof properties / sizeof properties[0]; ++i) {
        char ply[1024];
        snprintf(ply, sizeof ply,
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float %s\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0 %s0.5 0.25\n1 0 0 %s1 0\n0 1 0 %s0 1\n3 0 1 2\n",
                 properties[i], values[i], values[i], values[i]);
        write_text("uv.ply", ply);
        snprintf(text, sizeof text, WORLD "Shape \"plymesh\" \"string filename\" \"%s\"\n", ply_path);
        Scene s;
        load_ok(text, &s);
        assert_true(s.shapes[0].has_uvs);
        static const float expected[] = {0.5f, 0.25f, 1, 0, 0, 1};
        assert_memory_equal(s.uvs, expected, sizeof expected);
        scene_destroy(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_disk_area_silhouette_and_uv),
        cmocka_unit_test(test_disk_orientation),
        cmocka_unit_test(test_cylinder_area_normals_and_uv),
        cmocka_unit_test(test_bilinear_planar_patch_is_two_triangles),
        cmocka_unit_test(test_bilinear_saddle_is_tessellated),
        cmocka_unit_test(test_loop_tetrahedron_limit_positions),
        cmocka_unit_test(test_loop_boundary_rules),
        cmocka_unit_test(test_killeroo_simple_loads),
        cmocka_unit_test(test_bad_parameters),
        cmocka_unit_test(test_trianglemesh_uv),
        cmocka_unit_test(test_ply_uv),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
