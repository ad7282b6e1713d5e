/* Disks, cylinders, bilinear patches and Loop subdivision surfaces as
 * triangle meshes in object space, with pbrt-v4's parameters, defaults,
 * (u, v) and facing. */
#include "scene/tessellate.h"

#include "scene/loop_subdiv.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The widest angle one segment of a disk or cylinder spans. The ring's
 * radius is scaled so the triangles have the exact area (below); the
 * polygon then lies within MAX_SEGMENT_ANGLE^2 / 12 = 7.5e-5 of the radius
 * from the true circle: 210 segments around a full circle. */
#define MAX_SEGMENT_ANGLE 0.03

/* A non-planar bilinear patch is cut into an n x n grid of sub-patches, each
 * two triangles, with n the smallest that keeps the surface within
 * PATCH_TOLERANCE of the patch's size (its longer diagonal) of the
 * triangles, at most MAX_PATCH_SEGMENTS. */
#define PATCH_TOLERANCE 1e-4
#define MAX_PATCH_SEGMENTS 64

/* Levels pbrt-v4 subdivides a "loopsubdiv" by when the scene says nothing. */
#define LOOP_DEFAULT_LEVELS 3

static int shape_fail(ParamList *params, int line, const char *format, ...) SCENE_PRINTF(3, 4);

static int shape_fail(ParamList *params, int line, const char *format, ...)
{
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return scene_error(params->diag, params->file, line, "%s: %s", params->owner, message);
}

static int mesh_alloc(ShapeMesh *mesh, size_t vertices, size_t triangles, int with_normals)
{
    memset(mesh, 0, sizeof *mesh);
    mesh->vertex_count = vertices;
    mesh->index_count = 3 * triangles;
    mesh->positions = calloc(3 * vertices + 1, sizeof *mesh->positions);
    mesh->normals = with_normals ? calloc(3 * vertices + 1, sizeof *mesh->normals) : NULL;
    mesh->uvs = calloc(2 * vertices + 1, sizeof *mesh->uvs);
    mesh->indices = calloc(3 * triangles + 1, sizeof *mesh->indices);
    if (mesh->positions && mesh->uvs && mesh->indices && (mesh->normals || !with_normals))
        return 0;
    shape_mesh_free(mesh);
    return -1;
}

static void set_vertex(ShapeMesh *mesh, size_t v, const double p[3], double u, double uv_v)
{
    for (int k = 0; k < 3; ++k)
        mesh->positions[3 * v + (size_t)k] = (float)p[k];
    mesh->uvs[2 * v] = (float)u;
    mesh->uvs[2 * v + 1] = (float)uv_v;
}

static void set_triangle(ShapeMesh *mesh, size_t t, size_t a, size_t b, size_t c)
{
    mesh->indices[3 * t] = (uint32_t)a;
    mesh->indices[3 * t + 1] = (uint32_t)b;
    mesh->indices[3 * t + 2] = (uint32_t)c;
}

/* "phimax" in degrees, (0, 360], as radians. */
static int read_phi_max(ParamList *params, int line, double *phi_max)
{
    float degrees = 360.0f;
    if (params_get_float(params, "phimax", &degrees) < 0)
        return -1;
    if (!(degrees > 0.0f && degrees <= 360.0f))
        return shape_fail(params, line, "phimax %g must lie in (0, 360] degrees", (double)degrees);
    *phi_max = degrees * (PI / 180.0);
    return 0;
}

static size_t segment_count(double phi_max)
{
    return (size_t)ceil(phi_max / MAX_SEGMENT_ANGLE);
}

/* pbrt's disk: in the plane z = height between innerradius and radius, the
 * front +z; u = phi / phimax, v = (radius - r) / (radius - innerradius). */
static int build_disk(ParamList *params, int line, ShapeMesh *mesh)
{
    float height = 0.0f, radius = 1.0f, inner = 0.0f;
    double phi_max;
    if (params_get_float(params, "height", &height) < 0 || params_get_float(params, "radius", &radius) < 0 ||
        params_get_float(params, "innerradius", &inner) < 0 || read_phi_max(params, line, &phi_max))
        return -1;
    if (!(radius > 0.0f))
        return shape_fail(params, line, "radius %g must be positive", (double)radius);
    if (!(inner >= 0.0f && inner < radius))
        return shape_fail(params, line, "innerradius %g must lie in [0, radius %g)", (double)inner, (double)radius);
    size_t n = segment_count(phi_max);
    /* A wedge's triangles span (r^2 - ri^2) sin(step) / 2 instead of its
     * area (r^2 - ri^2) step / 2: scaling both radii restores it. */
    double step = phi_max / (double)n, scale = sqrt(step / sin(step));
    int annulus = inner > 0.0f;
    if (mesh_alloc(mesh, 2 * (n + 1), annulus ? 2 * n : n, 0))
        return shape_fail(params, line, "out of memory");
    mesh->one_part = 1;
    for (size_t k = 0; k <= n; ++k) {
        double phi = (double)k * step, c = cos(phi), s = sin(phi);
        double outer[3] = {scale * radius * c, scale * radius * s, height};
        double in[3] = {scale * inner * c, scale * inner * s, height};
        set_vertex(mesh, 2 * k, in, (double)k / (double)n, 1.0);
        set_vertex(mesh, 2 * k + 1, outer, (double)k / (double)n, 0.0);
    }
    for (size_t k = 0, t = 0; k < n; ++k) {
        set_triangle(mesh, t++, 2 * k, 2 * k + 1, 2 * k + 3);
        if (annulus)
            set_triangle(mesh, t++, 2 * k, 2 * k + 3, 2 * k + 2);
    }
    return 0;
}

/* pbrt's cylinder: around the z axis from zmin to zmax, the front outward,
 * smooth radial normals; u = phi / phimax, v = (z - zmin) / (zmax - zmin). */
static int build_cylinder(ParamList *params, int line, ShapeMesh *mesh)
{
    float radius = 1.0f, z_min = -1.0f, z_max = 1.0f;
    double phi_max;
    if (params_get_float(params, "radius", &radius) < 0 || params_get_float(params, "zmin", &z_min) < 0 ||
        params_get_float(params, "zmax", &z_max) < 0 || read_phi_max(params, line, &phi_max))
        return -1;
    if (!(radius > 0.0f))
        return shape_fail(params, line, "radius %g must be positive", (double)radius);
    if (z_min == z_max)
        return shape_fail(params, line, "zmin and zmax are both %g: the cylinder has no area", (double)z_min);
    if (z_min > z_max) { /* pbrt-v4 swaps them */
        float t = z_min;
        z_min = z_max;
        z_max = t;
    }
    size_t n = segment_count(phi_max);
    /* A chord is 2 r sin(step / 2) long instead of the arc's r step. */
    double step = phi_max / (double)n, scale = (0.5 * step) / sin(0.5 * step);
    if (mesh_alloc(mesh, 2 * (n + 1), 2 * n, 1))
        return shape_fail(params, line, "out of memory");
    mesh->one_part = 1;
    for (size_t k = 0; k <= n; ++k) {
        double phi = (double)k * step, c = cos(phi), s = sin(phi);
        double bottom[3] = {scale * radius * c, scale * radius * s, z_min};
        double top[3] = {bottom[0], bottom[1], z_max};
        set_vertex(mesh, 2 * k, bottom, (double)k / (double)n, 0.0);
        set_vertex(mesh, 2 * k + 1, top, (double)k / (double)n, 1.0);
        for (size_t v = 2 * k; v <= 2 * k + 1; ++v) {
            mesh->normals[3 * v] = (float)c;
            mesh->normals[3 * v + 1] = (float)s;
        }
    }
    for (size_t k = 0; k < n; ++k) {
        set_triangle(mesh, 2 * k, 2 * k, 2 * k + 2, 2 * k + 3);
        set_triangle(mesh, 2 * k + 1, 2 * k, 2 * k + 3, 2 * k + 1);
    }
    return 0;
}

int shape_read_indices(ParamList *params, const Param *indices, size_t vertex_count, size_t per_item, uint32_t *out)
{
    if (indices->count % per_item != 0)
        return params_error(params, indices, "%zu vertex indices is not a multiple of %zu", indices->count, per_item);
    for (size_t i = 0; i < indices->count; ++i) {
        double v = indices->numbers[i];
        if (v < 0.0)
            return params_error(params, indices, "negative vertex index %.0f (number %zu)", v, i);
        if (v >= (double)vertex_count)
            return params_error(params, indices, "vertex index %.0f (number %zu) is out of range: %zu vertices", v, i,
                                vertex_count);
        out[i] = (uint32_t)v;
    }
    return 0;
}

int shape_read_uv(ParamList *params, size_t vertex_count, const Param **uv)
{
    const Param *st = NULL;
    *uv = NULL;
    int has_uv = params_get_array(params, "uv", PARAM_POINT2, uv);
    int has_st = params_get_array(params, "st", PARAM_POINT2, &st);
    if (has_uv < 0 || has_st < 0)
        return -1;
    if (has_uv && has_st)
        return params_error(params, st, "give \"uv\" or \"st\", not both");
    if (has_st)
        *uv = st;
    if (*uv && (*uv)->count != 2 * vertex_count)
        return params_error(params, *uv, "%zu texture coordinates for %zu vertices", (*uv)->count / 2, vertex_count);
    return *uv != NULL;
}

/* The bilinear interpolation of 4 corner values (p00, p10, p01, p11) of
 * `components` numbers each, at (u, v). */
static void bilinear(double corner[4][3], int components, double u, double v, double *out)
{
    for (int k = 0; k < components; ++k)
        out[k] = (1.0 - u) * ((1.0 - v) * corner[0][k] + v * corner[2][k]) +
                 u * ((1.0 - v) * corner[1][k] + v * corner[3][k]);
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double length(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Grid segments for a patch (p00, p10, p01, p11). The surface's centre lies
 * |twist . n| / 4 off the two triangles (twist = p00 - p10 - p01 + p11, n
 * the unit normal of the mean plane, across its diagonals); an n x n grid
 * divides that by n^2. A planar patch gets 1: two exact triangles. */
static size_t patch_segments(double p[4][3])
{
    double twist[3], d1[3], d2[3], normal[3];
    for (int k = 0; k < 3; ++k) {
        twist[k] = p[0][k] - p[1][k] - p[2][k] + p[3][k];
        d1[k] = p[3][k] - p[0][k];
        d2[k] = p[2][k] - p[1][k];
    }
    cross(d1, d2, normal);
    double size = fmax(length(d1), length(d2)), area = length(normal);
    if (!(size > 0.0) || !(area > 0.0))
        return 1;
    double offset = fabs(twist[0] * normal[0] + twist[1] * normal[1] + twist[2] * normal[2]) / area / 4.0;
    double n = ceil(sqrt(offset / (PATCH_TOLERANCE * size)));
    return n < 1.0 ? 1 : n > MAX_PATCH_SEGMENTS ? MAX_PATCH_SEGMENTS : (size_t)n;
}

/* pbrt's bilinear patch mesh: 4 indices per patch in the order p00, p10,
 * p01, p11; p(u, v) = lerp(u, lerp(v, p00, p01), lerp(v, p10, p11)), the
 * front cross(dp/du, dp/dv); uv the patch's (u, v) unless given. */
static int build_bilinear_mesh(ParamList *params, int line, ShapeMesh *mesh)
{
    const Param *P = NULL, *indices = NULL, *N = NULL, *uv = NULL;
    memset(mesh, 0, sizeof *mesh); /* freed on every error below */
    if (params_get_array(params, "P", PARAM_POINT3, &P) < 0 ||
        params_get_array(params, "indices", PARAM_INTEGER, &indices) < 0 ||
        params_get_array(params, "N", PARAM_NORMAL3, &N) < 0)
        return -1;
    params_ignore(params, "faceIndices"); /* per-patch ids, only for Ptex textures */
    /* An image pbrt samples an emitting patch's points by: only how it
     * samples, not what the image converges to. */
    params_ignore(params, "emissionfilename");
    if (!P)
        return shape_fail(params, line, "missing \"point3 P\"");
    size_t vertex_count = P->count / 3;
    if (shape_read_uv(params, vertex_count, &uv) < 0)
        return -1;
    if (!indices && vertex_count != 4)
        return shape_fail(params, line, "missing \"integer indices\" (needed unless P holds exactly one patch)");
    if (N && N->count != P->count)
        return params_error(params, N, "%zu normals for %zu vertices", N->count / 3, vertex_count);
    size_t index_count = indices ? indices->count : 4, patches = index_count / 4;
    if (index_count == 0)
        return shape_fail(params, line, "the mesh has no patches");
    uint32_t *corners = malloc(index_count * sizeof *corners + 1);
    size_t *segments = malloc(patches * sizeof *segments + 1);
    if (!corners || !segments) {
        free(corners);
        free(segments);
        return shape_fail(params, line, "out of memory");
    }
    int result = 0;
    if (indices)
        result = shape_read_indices(params, indices, vertex_count, 4, corners);
    else
        for (uint32_t i = 0; i < 4; ++i)
            corners[i] = i;
    size_t vertices = 0, triangles = 0;
    int smooth = N != NULL;
    for (size_t patch = 0; result == 0 && patch < patches; ++patch) {
        double p[4][3];
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k)
                p[c][k] = P->numbers[3 * (size_t)corners[4 * patch + (size_t)c] + (size_t)k];
        segments[patch] = patch_segments(p);
        smooth |= segments[patch] > 1;
        vertices += (segments[patch] + 1) * (segments[patch] + 1);
        triangles += 2 * segments[patch] * segments[patch];
    }
    if (result == 0 && triangles > SHAPE_MAX_TRIANGLES)
        result = shape_fail(params, line, "the curved patches make %zu triangles, over the limit of %zu", triangles,
                            SHAPE_MAX_TRIANGLES);
    if (result == 0 && mesh_alloc(mesh, vertices, triangles, smooth))
        result = shape_fail(params, line, "out of memory");
    if (result == 0 && !(mesh->parts = malloc(triangles * sizeof *mesh->parts + 1)))
        result = shape_fail(params, line, "out of memory");
    size_t first = 0, t = 0;
    for (size_t patch = 0; result == 0 && patch < patches; ++patch) {
        double p[4][3], n[4][3] = {{0}}, st[4][3] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
        for (int c = 0; c < 4; ++c) {
            size_t v = corners[4 * patch + (size_t)c];
            for (int k = 0; k < 3; ++k) {
                p[c][k] = P->numbers[3 * v + (size_t)k];
                n[c][k] = N ? N->numbers[3 * v + (size_t)k] : 0.0;
            }
            for (int k = 0; uv && k < 2; ++k)
                st[c][k] = uv->numbers[2 * v + (size_t)k];
        }
        size_t s = segments[patch];
        for (size_t j = 0; j <= s; ++j)
            for (size_t i = 0; i <= s; ++i) {
                double u = (double)i / (double)s, v = (double)j / (double)s, point[3], coords[2], normal[3];
                size_t index = first + j * (s + 1) + i;
                bilinear(p, 3, u, v, point);
                bilinear(st, 2, u, v, coords);
                set_vertex(mesh, index, point, coords[0], coords[1]);
                if (N) {
                    bilinear(n, 3, u, v, normal);
                } else if (s > 1) { /* the surface's own: dp/du x dp/dv */
                    double du[3], dv[3];
                    for (int k = 0; k < 3; ++k) {
                        du[k] = (1.0 - v) * (p[1][k] - p[0][k]) + v * (p[3][k] - p[2][k]);
                        dv[k] = (1.0 - u) * (p[2][k] - p[0][k]) + u * (p[3][k] - p[1][k]);
                    }
                    cross(du, dv, normal);
                }
                for (int k = 0; mesh->normals && (N || s > 1) && k < 3; ++k)
                    mesh->normals[3 * index + (size_t)k] = (float)normal[k];
            }
        for (size_t j = 0; j < s; ++j)
            for (size_t i = 0; i < s; ++i) {
                size_t a = first + j * (s + 1) + i, b = a + 1, c = a + s + 2, d = a + s + 1;
                mesh->parts[t] = mesh->parts[t + 1] = (uint32_t)patch;
                set_triangle(mesh, t++, a, b, c);
                set_triangle(mesh, t++, a, c, d);
            }
        first += (s + 1) * (s + 1);
    }
    free(corners);
    free(segments);
    if (result)
        shape_mesh_free(mesh);
    return result;
}

static int build_loop_subdiv(ParamList *params, int line, ShapeMesh *mesh)
{
    const Param *P = NULL, *indices = NULL;
    int levels = LOOP_DEFAULT_LEVELS;
    if (params_get_array(params, "P", PARAM_POINT3, &P) < 0 ||
        params_get_array(params, "indices", PARAM_INTEGER, &indices) < 0 ||
        params_get_int(params, "levels", &levels) < 0)
        return -1;
    const char *scheme = "loop";
    if (params_get_string(params, "scheme", &scheme) < 0)
        return -1;
    if (strcmp(scheme, "loop") != 0)
        return shape_fail(params, line, "scheme \"%s\" is not supported (only \"loop\", as in pbrt-v4)", scheme);
    if (!P)
        return shape_fail(params, line, "missing \"point3 P\"");
    if (!indices)
        return shape_fail(params, line, "missing \"integer indices\"");
    if (levels < 0)
        return shape_fail(params, line, "levels %d must not be negative", levels);
    size_t vertex_count = P->count / 3;
    if (indices->count == 0)
        return shape_fail(params, line, "the mesh has no triangles");
    float *positions = malloc(P->count * sizeof *positions + 1);
    uint32_t *index = malloc(indices->count * sizeof *index + 1);
    int result = positions && index ? 0 : shape_fail(params, line, "out of memory");
    if (result == 0)
        result = shape_read_indices(params, indices, vertex_count, 3, index);
    for (size_t i = 0; result == 0 && i < P->count; ++i)
        positions[i] = (float)P->numbers[i];
    char why[256];
    if (result == 0 &&
        loop_subdivide(positions, vertex_count, index, indices->count / 3, levels, mesh, why, sizeof why))
        result = shape_fail(params, line, "%s", why);
    free(positions);
    free(index);
    return result;
}

static const struct {
    const char *name;
    ShapeBuilder build;
} builders[] = {
    {"disk", build_disk},
    {"cylinder", build_cylinder},
    {"bilinearmesh", build_bilinear_mesh},
    {"loopsubdiv", build_loop_subdiv},
};

ShapeBuilder shape_builder(const char *name)
{
    for (size_t i = 0; i < sizeof builders / sizeof builders[0]; ++i)
        if (strcmp(builders[i].name, name) == 0)
            return builders[i].build;
    return NULL;
}
