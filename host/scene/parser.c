/* The pbrt-v4 directives: a graphics-state stack (transform, material, area
 * light, orientation) and one handler per directive, which fill a Scene in
 * world space. See README.md in this directory for the supported subset. */
#define _POSIX_C_SOURCE 200809L /* stat */

#include "scene/instance_check.h"
#include "scene/lexer.h"
#include "scene/params.h"
#include "scene/ply.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "scene/shapes.h"
#include "scene/spectrum.h"
#include "scene/textures.h"

#include <cglm/cglm.h>

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_INCLUDE_DEPTH 32

/* Geometry lying farther from the origin than this many times its size
 * gets a warning: the renderer offsets rays leaving a surface by 1e-5 times
 * their distance from the origin, which is then over 1% of the scene's size. */
#define PRECISION_RATIO 1e3

typedef enum { PUSHED_ATTRIBUTES, PUSHED_TRANSFORM, PUSHED_OBJECT } PushKind;

/* Which of the two transforms (at the shutter's start and end time) the
 * transform directives change: ActiveTransform StartTime, EndTime or All. */
enum { ACTIVE_START = 1, ACTIVE_END = 2, ACTIVE_ALL = 3 };

typedef struct {
    mat4 ctm;     /* object to world (camera before WorldBegin), at the start time: what is rendered */
    mat4 ctm_end; /* the same at the end time (pbrt-v4 animates between them); only compared with ctm */
    int active_transforms;
    int material; /* index into the scene's materials; -1: pbrt's default */
    int has_area_light;
    float area_radiance[3];
    int area_two_sided;
    float area_power;      /* "power", or -1 */
    char area_origin[256]; /* "file:line" of the AreaLightSource */
    int reverse_orientation;
    /* Where this state was pushed (kept on the stack only). */
    PushKind kind;
    const char *file;
    int line;
} GraphicsState;

/* A material name and its slot in Scene.materials. pbrt-v4 binds names
 * once the whole scene is read, so a NamedMaterial before its
 * MakeNamedMaterial gets a slot (not yet `defined`; file and line: that
 * first use) that the definition fills in later. */
typedef struct {
    char *name;
    int material;
    int defined;
    const char *file;
    int line;
} NamedMaterial;

/* CoordinateSystem "name", and pbrt-v4's own "camera" and "world". */
typedef struct {
    char *name;
    mat4 start, end;
} NamedTransform;

typedef struct {
    Scene *scene;
    Diagnostics diag;
    GraphicsState state;
    GraphicsState *stack;
    size_t depth, stack_capacity;
    int in_world;
    int object; /* the object being defined (Scene.objects), or -1 */
    const char *object_file;
    int object_line;
    size_t object_capacity, instance_capacity, pending_capacity;
    /* ObjectInstance names, resolved once the whole scene is read (pbrt-v4
     * lets an instance come before its object's definition). */
    struct PendingInstance {
        char *name;
        const char *file;
        int line;
    } * pending;
    int include_depth;
    NamedMaterial *named;
    size_t named_count, named_capacity;
    NamedTransform *coordinate_systems;
    size_t coordinate_system_count, coordinate_system_capacity;
    int motion_warned; /* one warning for all animated transforms */
    int default_material;
    size_t material_capacity, texture_capacity, shape_capacity, area_light_capacity, light_capacity, vertex_capacity,
        triangle_capacity, sphere_capacity;
    char **paths; /* every file read, alive until scene_load returns (messages point at them) */
    size_t path_count, path_capacity;
    const char *main_path;
    mat4 camera_from_world, world_from_camera;
    const char *camera_file;
    int camera_line;
    /* The film's sensor settings and the camera's shutter, combined into
     * the film matrix at the end (Film may come before or after Camera). */
    float film_iso, film_scale, film_white_balance, shutter_open, shutter_close;
    char film_sensor[64];
} Parser;

typedef int (*Handler)(Parser *p, Lexer *lex, const Token *directive);

/* ---------------------------------------------------------------- helpers */

static void directive_name(const Token *t, char *out, size_t size)
{
    size_t n = t->length < size - 1 ? t->length : size - 1;
    memcpy(out, t->text, n);
    out[n] = '\0';
}

static int expect_string(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *out)
{
    if (lexer_next(lex, out))
        return -1;
    if (out->kind == TOKEN_STRING)
        return 0;
    char name[32], shown[64];
    directive_name(directive, name, sizeof name);
    token_describe(out, shown, sizeof shown);
    return scene_error(&p->diag, lex->path, out->line, "%s: expected %s as a quoted string, got %s", name, what, shown);
}

/* Reads `count` numbers; with `brackets`, optionally enclosed in [ ]. */
static int read_numbers(Parser *p, Lexer *lex, const Token *directive, int count, int brackets, double *out)
{
    char name[32], shown[64];
    directive_name(directive, name, sizeof name);
    Token t;
    if (lexer_peek(lex, &t))
        return -1;
    int bracketed = brackets && t.kind == TOKEN_OPEN;
    if (bracketed)
        lexer_next(lex, &t);
    for (int i = 0; i < count; ++i) {
        if (lexer_next(lex, &t))
            return -1;
        if (token_number(&t, &out[i]) || fabs(out[i]) > FLT_MAX) {
            token_describe(&t, shown, sizeof shown);
            return scene_error(&p->diag, lex->path, t.line, "%s: expected %d numbers, got %s as number %d", name, count,
                               shown, i + 1);
        }
    }
    if (bracketed) {
        if (lexer_next(lex, &t))
            return -1;
        if (t.kind != TOKEN_CLOSE) {
            token_describe(&t, shown, sizeof shown);
            return scene_error(&p->diag, lex->path, t.line, "%s: expected ']' after %d numbers, got %s", name, count,
                               shown);
        }
    }
    return 0;
}

static int out_of_memory(Parser *p, const char *file, int line)
{
    return scene_error(&p->diag, file, line, "out of memory");
}

static int require_world(Parser *p, Lexer *lex, const Token *directive, int inside)
{
    if (p->in_world == inside)
        return 0;
    char name[32];
    directive_name(directive, name, sizeof name);
    return scene_error(&p->diag, lex->path, directive->line, "%s must come %s WorldBegin", name,
                       inside ? "after" : "before");
}

/* Reads a directive's type string and parameter list; `owner` receives e.g.
 * Shape "sphere" for messages. */
static int read_typed_directive(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *type,
                                ParamList *params)
{
    memset(params, 0, sizeof *params);
    if (expect_string(p, lex, directive, what, type))
        return -1;
    char name[32], shown[64], owner[100];
    directive_name(directive, name, sizeof name);
    token_describe(type, shown, sizeof shown);
    snprintf(owner, sizeof owner, "%s %s", name, shown);
    int result = params_parse(lex, owner, params);
    params->main_file = p->main_path; /* after params_parse, which clears the list */
    return result;
}

static void transform_point(mat4 m, const float in[3], float out[3])
{
    double x = in[0], y = in[1], z = in[2];
    double r[4];
    for (int row = 0; row < 4; ++row)
        r[row] = m[0][row] * x + m[1][row] * y + m[2][row] * z + m[3][row];
    double w = r[3];
    for (int k = 0; k < 3; ++k)
        out[k] = (float)(w == 1.0 ? r[k] : r[k] / w);
}

static double det3(mat4 m)
{
    return (double)m[0][0] * ((double)m[1][1] * m[2][2] - (double)m[2][1] * m[1][2]) -
           (double)m[1][0] * ((double)m[0][1] * m[2][2] - (double)m[2][1] * m[0][2]) +
           (double)m[2][0] * ((double)m[0][1] * m[1][2] - (double)m[1][1] * m[0][2]);
}

static void cross_d(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot_d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Scales v to unit length; returns its length before. */
static double normalize_d(double v[3])
{
    double length = sqrt(dot_d(v, v));
    for (int k = 0; length > 0.0 && k < 3; ++k)
        v[k] /= length;
    return length;
}

/* A triangle's edges from its first vertex, in double. */
static void edges(const float *positions, const uint32_t *triangle, double e1[3], double e2[3])
{
    const float *a = positions + 3 * triangle[0], *b = positions + 3 * triangle[1], *c = positions + 3 * triangle[2];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
}

/* Whether m's linear part is a rotation (or reflection) times a uniform
 * scale; *scale receives that scale (the columns' mean length). */
static int is_similarity(mat4 m, double *scale)
{
    double length[3], largest = 0.0;
    for (int c = 0; c < 3; ++c) {
        length[c] = sqrt((double)m[c][0] * m[c][0] + (double)m[c][1] * m[c][1] + (double)m[c][2] * m[c][2]);
        largest = fmax(largest, length[c]);
    }
    *scale = (length[0] + length[1] + length[2]) / 3.0;
    if (largest == 0.0)
        return 0;
    const double tolerance = 1e-4;
    for (int a = 0; a < 3; ++a) {
        int b = (a + 1) % 3;
        double dot = (double)m[a][0] * m[b][0] + (double)m[a][1] * m[b][1] + (double)m[a][2] * m[b][2];
        if (fabs(length[a] - length[b]) > tolerance * largest || fabs(dot) > tolerance * largest * largest)
            return 0;
    }
    return 1;
}

static int is_affine(mat4 m)
{
    return m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
}

/* The inverse of m by Gauss-Jordan elimination in double (a float inverse
 * loses a camera's tiny Scale to underflow). Returns -1 when m is singular
 * or its inverse does not fit a float. */
static int invert_in_double(mat4 m, mat4 inverse)
{
    double a[4][8]; /* [row][column]: m, then the identity */
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            a[r][c] = m[c][r];
            a[r][c + 4] = r == c ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (fabs(a[r][c]) > fabs(a[pivot][c]))
                pivot = r;
        if (a[pivot][c] == 0.0)
            return -1;
        for (int k = 0; k < 8; ++k) {
            double t = a[c][k];
            a[c][k] = a[pivot][k];
            a[pivot][k] = t;
        }
        double scale = 1.0 / a[c][c];
        for (int k = 0; k < 8; ++k)
            a[c][k] *= scale;
        for (int r = 0; r < 4; ++r) {
            double f = a[r][c];
            for (int k = 0; r != c && k < 8; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            if (!(fabs(a[r][c + 4]) <= FLT_MAX))
                return -1;
            inverse[c][r] = (float)a[r][c + 4];
        }
    return 0;
}

/* Whether every coordinate of a world-space point is within the renderer's
 * range (false for NaN). */
static int within_range(const float point[3])
{
    return fabsf(point[0]) <= SCENE_MAX_COORDINATE && fabsf(point[1]) <= SCENE_MAX_COORDINATE &&
           fabsf(point[2]) <= SCENE_MAX_COORDINATE;
}

/* ------------------------------------------------------- scene building */

static int add_material(Parser *p, const SceneMaterial *m)
{
    Scene *s = p->scene;
    if (scene_reserve((void **)&s->materials, &p->material_capacity, s->material_count + 1, sizeof *s->materials))
        return -1;
    s->materials[s->material_count] = *m;
    return (int)s->material_count++;
}

static void default_material(SceneMaterial *m)
{
    memset(m, 0, sizeof *m);
    m->type = SCENE_MATERIAL_DIFFUSE;
    for (int i = 0; i < SCENE_SLOT_COUNT; ++i)
        m->textures[i] = -1;
    m->reflectance[0] = m->reflectance[1] = m->reflectance[2] = 0.5f;
    m->eta = 1.5f;
    m->remap_roughness = 1;
    m->mix_amount = 0.5f;
    m->scale = 1.0f;
    m->thickness = 0.01f;
    m->max_depth = 10;
    m->sample_count = 1;
}

/* The current material's index, creating pbrt's default (diffuse 0.5) once. */
static int current_material(Parser *p)
{
    if (p->state.material >= 0)
        return p->state.material;
    if (p->default_material < 0) {
        SceneMaterial m;
        default_material(&m);
        p->default_material = add_material(p, &m);
    }
    return p->default_material;
}

/* Appends a shape record (with its area light) for the current state. */
static int add_shape(Parser *p, SceneShapeKind kind, int flip_normal, size_t first, size_t count)
{
    Scene *s = p->scene;
    int material = current_material(p);
    if (material < 0)
        return -1;
    if (scene_reserve((void **)&s->shapes, &p->shape_capacity, s->shape_count + 1, sizeof *s->shapes))
        return -1;
    SceneShape *shape = &s->shapes[s->shape_count];
    shape->kind = kind;
    shape->material = material;
    shape->area_light = -1;
    shape->flip_normal = flip_normal;
    shape->has_uvs = 0;
    shape->first = first;
    shape->count = count;
    shape->object = p->object;
    shape->alpha = 1.0f;
    shape->alpha_texture = -1;
    if (p->state.has_area_light && p->object < 0) {
        if (scene_reserve((void **)&s->area_lights, &p->area_light_capacity, s->area_light_count + 1,
                          sizeof *s->area_lights))
            return -1;
        SceneAreaLight *light = &s->area_lights[s->area_light_count];
        memcpy(light->radiance, p->state.area_radiance, sizeof light->radiance);
        light->two_sided = p->state.area_two_sided;
        light->power = p->state.area_power;
        light->shape = (int)s->shape_count;
        light->origin = NULL;
        if (light->power > 0.0f && !(light->origin = scene_strndup(p->state.area_origin, strlen(p->state.area_origin))))
            return -1;
        shape->area_light = (int)s->area_light_count++;
    }
    s->shape_count++;
    return 0;
}

/* Grows an optional per-vertex attribute (NULL until some mesh has one) to
 * the positions' capacity. */
static int reserve_attribute(float **array, size_t old_capacity, size_t capacity, size_t components, int wanted)
{
    if (*array && capacity != old_capacity) {
        float *grown = realloc(*array, capacity * components * sizeof *grown);
        if (!grown)
            return -1;
        *array = grown;
    }
    if (wanted && !*array) {
        *array = calloc(capacity * components, sizeof **array);
        if (!*array)
            return -1;
    }
    return 0;
}

/* Grows positions (and normals and uvs, once any mesh has them) to `needed` vertices. */
static int reserve_vertices(Parser *p, size_t needed, int want_normals, int want_uvs)
{
    Scene *s = p->scene;
    size_t old_capacity = p->vertex_capacity;
    if (scene_reserve((void **)&s->positions, &p->vertex_capacity, needed, 3 * sizeof *s->positions))
        return -1;
    if (reserve_attribute(&s->normals, old_capacity, p->vertex_capacity, 3, want_normals) ||
        reserve_attribute(&s->uvs, old_capacity, p->vertex_capacity, 2, want_uvs))
        return -1;
    return 0;
}

/* Adds a mesh given in object space under the current transform: checks it,
 * transforms it to world space and drops zero-area triangles (counted in a
 * warning). normals and uvs may be NULL. `owner` names the shape in messages. */
static int add_mesh(Parser *p, const char *file, int line, const char *owner, const float *positions,
                    size_t vertex_count, const uint32_t *indices, size_t index_count, const float *normals,
                    const float *uvs, const uint32_t *parts, int one_part)
{
    Scene *s = p->scene;
    if (vertex_count == 0)
        return scene_error(&p->diag, file, line, "%s: the mesh has no vertices", owner);
    if (index_count == 0)
        return scene_error(&p->diag, file, line, "%s: the mesh has no triangles", owner);
    if (index_count % 3 != 0)
        return scene_error(&p->diag, file, line, "%s: %zu vertex indices is not a multiple of 3", owner, index_count);
    for (size_t i = 0; i < index_count; ++i)
        if (indices[i] >= vertex_count)
            return scene_error(&p->diag, file, line, "%s: vertex index %u (number %zu) is out of range: %zu vertices",
                               owner, indices[i], i, vertex_count);
    for (size_t i = 0; i < 3 * vertex_count; ++i)
        if (!isfinite(positions[i]))
            return scene_error(&p->diag, file, line, "%s: vertex %zu has a non-finite position", owner, i / 3);
    for (size_t i = 0; uvs && i < 2 * vertex_count; ++i)
        if (!isfinite(uvs[i]))
            return scene_error(&p->diag, file, line, "%s: vertex %zu has a non-finite texture coordinate", owner,
                               i / 2);
    if (vertex_count > UINT32_MAX - s->vertex_count || s->shape_count >= UINT32_MAX - index_count / 3)
        return scene_error(&p->diag, file, line, "%s: too many vertices in the scene", owner);

    size_t base = s->vertex_count;
    if (reserve_vertices(p, base + vertex_count, normals != NULL, uvs != NULL))
        return out_of_memory(p, file, line);
    float *world = s->positions + 3 * base;
    int invertible = det3(p->state.ctm) != 0.0; /* else the triangles have no area either */
    float farthest = 0.0f;                      /* the largest world-space coordinate magnitude */
    for (size_t v = 0; v < vertex_count; ++v) {
        float *w = world + 3 * v;
        transform_point(p->state.ctm, positions + 3 * v, w);
        if (!within_range(w))
            return scene_error(&p->diag, file, line,
                               "%s: vertex %zu is at (%g, %g, %g) in world space, beyond %g from the origin (the "
                               "renderer squares distances in single precision)",
                               owner, v, (double)w[0], (double)w[1], (double)w[2], SCENE_MAX_COORDINATE);
        farthest = fmaxf(farthest, fmaxf(fabsf(w[0]), fmaxf(fabsf(w[1]), fabsf(w[2]))));
    }
    if (s->uvs) {
        float *out = s->uvs + 2 * base;
        for (size_t i = 0; i < 2 * vertex_count; ++i)
            out[i] = uvs ? uvs[i] : 0.0f;
    }
    if (s->normals) {
        float *out = s->normals + 3 * base;
        memset(out, 0, 3 * vertex_count * sizeof *out);
        mat4 inverse;
        glm_mat4_inv(p->state.ctm, inverse);
        /* Normals transform by the inverse transpose: n'_r = sum_c inverse[r][c] n_c. */
        for (size_t v = 0; normals && invertible && v < vertex_count; ++v) {
            const float *n = normals + 3 * v;
            double t[3], length = 0.0;
            for (int r = 0; r < 3; ++r) {
                t[r] = (double)inverse[r][0] * n[0] + (double)inverse[r][1] * n[1] + (double)inverse[r][2] * n[2];
                length += t[r] * t[r];
            }
            length = sqrt(length);
            if (!(length > 0.0) || !isfinite(length))
                continue; /* a zero (or broken) normal stays zero: none */
            double sign = p->state.reverse_orientation ? -1.0 : 1.0;
            for (int r = 0; r < 3; ++r)
                out[3 * v + (size_t)r] = (float)(sign * t[r] / length);
        }
    }

    size_t triangles = index_count / 3, kept = 0, rounded_away = 0, first = s->triangle_count;
    if (scene_reserve((void **)&s->triangles, &p->triangle_capacity, first + triangles, sizeof *s->triangles))
        return out_of_memory(p, file, line);
    /* pbrt-v4 makes an area light for each of the mesh's shapes (a triangle,
     * a patch), with "power" each one's: such a mesh becomes a shape a part,
     * kept_parts the part of each kept triangle. */
    int split = p->state.has_area_light && p->object < 0 && p->state.area_power > 0.0f && !one_part;
    uint32_t *kept_parts = split ? malloc(triangles * sizeof *kept_parts + 1) : NULL;
    if (split && !kept_parts)
        return out_of_memory(p, file, line);
    for (size_t t = 0; t < triangles; ++t) {
        const uint32_t *tri = indices + 3 * t;
        double e1[3], e2[3], normal[3];
        edges(world, tri, e1, e2);
        cross_d(e1, e2, normal);
        if (normal[0] == 0.0 && normal[1] == 0.0 && normal[2] == 0.0) {
            /* Zero area: harmless to drop, and it has no normal. When it had
             * area before an invertible transform, rounding took it. */
            edges(positions, tri, e1, e2);
            cross_d(e1, e2, normal);
            rounded_away += invertible && (normal[0] != 0.0 || normal[1] != 0.0 || normal[2] != 0.0);
            continue;
        }
        double product = sqrt(dot_d(e1, e1)) * sqrt(dot_d(e2, e2));
        if (product > SCENE_MAX_EDGE_PRODUCT) {
            free(kept_parts);
            return scene_error(&p->diag, file, line,
                               "%s: triangle %zu is too large for single precision: its edges from its first vertex "
                               "are %g and %g long, a product over %g",
                               owner, t, sqrt(dot_d(e1, e1)), sqrt(dot_d(e2, e2)), SCENE_MAX_EDGE_PRODUCT);
        }
        if (split)
            kept_parts[kept] = parts ? parts[t] : (uint32_t)t;
        SceneTriangle *out = &s->triangles[first + kept++];
        for (int k = 0; k < 3; ++k)
            out->vertex[k] = (uint32_t)(base + tri[k]);
        out->shape = (uint32_t)s->shape_count;
    }
    if (kept < triangles) {
        char why[256] = "";
        if (rounded_away > 0)
            snprintf(why, sizeof why,
                     "; %zu of them lost their area to single-precision rounding in world space (at coordinates "
                     "up to %g floats are %g apart): move the shape nearer the origin",
                     rounded_away, (double)farthest, (double)(nextafterf(farthest, INFINITY) - farthest));
        if (scene_warn(&p->diag, file, line, "%s: skipped %zu degenerate (zero-area) triangle%s of %zu%s", owner,
                       triangles - kept, triangles - kept == 1 ? "" : "s", triangles, why)) {
            free(kept_parts);
            return -1;
        }
    }
    if (kept == 0) {
        free(kept_parts);
        return 0; /* nothing left to draw: no vertices, no shape */
    }
    s->vertex_count += vertex_count;
    s->triangle_count += kept;
    int flip = p->state.reverse_orientation ^ (det3(p->state.ctm) < 0.0);
    size_t start = 0;
    for (size_t i = 1; i <= kept; ++i) {
        if (i < kept && (!split || kept_parts[i] == kept_parts[start]))
            continue;
        for (size_t j = start; j < i; ++j)
            s->triangles[first + j].shape = (uint32_t)s->shape_count;
        if (add_shape(p, SCENE_SHAPE_TRIANGLES, flip, first + start, i - start)) {
            free(kept_parts);
            return out_of_memory(p, file, line);
        }
        s->shapes[s->shape_count - 1].has_uvs = uvs != NULL;
        start = i;
    }
    free(kept_parts);
    return 0;
}

/* ------------------------------------------------------------ materials */

/* A material parameter that may be a texture: 1 when it is one (its
 * index in m->textures[slot]), 0 when not (read the constant), -1 error. */
static int read_slot(Parser *p, ParamList *params, SceneMaterial *m, SceneMaterialSlot slot, const char *name,
                     int is_spectrum)
{
    return scene_texture_param_late(&p->diag, p->scene, &p->texture_capacity, params, name, is_spectrum,
                                    &m->textures[slot]);
}

/* A spectrum parameter given by a texture or a constant. Returns 0 or -1. */
static int read_spectrum_slot(Parser *p, ParamList *params, SceneMaterial *m, SceneMaterialSlot slot, const char *name,
                              SpectrumKind kind, float rgb[3], int *given)
{
    int taken = read_slot(p, params, m, slot, name, 1);
    if (taken == 0)
        taken = params_get_spectrum(params, name, kind, rgb);
    if (given)
        *given = taken > 0;
    return taken < 0 ? -1 : 0;
}

/* Every material's bump and normal maps. Returns 0 or -1. */
static int read_bump(Parser *p, ParamList *params, SceneMaterial *m, int line)
{
    if (read_slot(p, params, m, SCENE_SLOT_DISPLACEMENT, "displacement", 0) < 0)
        return -1;
    params_ignore(params, "displacement"); /* a constant displacement changes nothing */
    return scene_texture_normal_map(&p->diag, p->scene, &p->texture_capacity, params, line,
                                    &m->textures[SCENE_SLOT_NORMAL_MAP]) < 0
               ? -1
               : 0;
}

/* "<prefix>roughness" or "<prefix>uroughness"/"<prefix>vroughness"
 * (pbrt-v4's names, prefix "" or "interface." / "conductor."; pbrt-v4
 * prefers u and v), each a constant or a float texture (m->textures' slots
 * `slot_u` and the one after it, for v). */
static int read_roughness(Parser *p, ParamList *params, SceneMaterial *m, const char *prefix, float roughness[2],
                          SceneMaterialSlot slot_u_index, int line)
{
    SceneMaterialSlot slot_v_index = (SceneMaterialSlot)(slot_u_index + 1);
    char names[3][64];
    snprintf(names[0], sizeof names[0], "%sroughness", prefix);
    snprintf(names[1], sizeof names[1], "%suroughness", prefix);
    snprintf(names[2], sizeof names[2], "%svroughness", prefix);
    int *slot_u = &m->textures[slot_u_index], *slot_v = &m->textures[slot_v_index];
    if (read_slot(p, params, m, slot_u_index, names[0], 0) < 0)
        return -1;
    *slot_v = *slot_u;
    if (read_slot(p, params, m, slot_u_index, names[1], 0) < 0 ||
        read_slot(p, params, m, slot_v_index, names[2], 0) < 0)
        return -1;
    float r = 0.0f;
    if (params_get_float(params, names[0], &r) < 0)
        return -1;
    roughness[0] = roughness[1] = r;
    int constant_u = params_get_float(params, names[1], &roughness[0]);
    int constant_v = params_get_float(params, names[2], &roughness[1]);
    if (constant_u < 0 || constant_v < 0)
        return -1;
    if (constant_u > 0)
        *slot_u = -1;
    if (constant_v > 0)
        *slot_v = -1;
    if (roughness[0] < 0.0f || roughness[1] < 0.0f)
        return scene_error(&p->diag, params->file, line, "%s: roughness must not be negative", params->owner);
    return 0;
}

static int read_eta(ParamList *params, const char *name, float *eta, int line, Parser *p)
{
    if (params_get_eta(params, name, eta) < 0)
        return -1;
    if (!(*eta > 0.0f))
        return scene_error(&p->diag, params->file, line, "%s: eta must be positive", params->owner);
    return 0;
}

/* A conductor's "<prefix>eta" and "<prefix>k", or "reflectance" instead;
 * each may be a spectrum texture. */
static int read_conductor(Parser *p, ParamList *params, const char *prefix, SceneMaterial *m, int line)
{
    char eta_name[64], k_name[64];
    snprintf(eta_name, sizeof eta_name, "%seta", prefix);
    snprintf(k_name, sizeof k_name, "%sk", prefix);
    int eta_texture = read_slot(p, params, m, SCENE_SLOT_CONDUCTOR_ETA, eta_name, 1);
    int k_texture = read_slot(p, params, m, SCENE_SLOT_CONDUCTOR_K, k_name, 1);
    float reflectance[3];
    int has_reflectance = 0;
    if (eta_texture < 0 || k_texture < 0 ||
        read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, reflectance,
                           &has_reflectance))
        return -1;
    int has_eta_k = params_get_conductor(params, prefix, m->conductor_eta, m->conductor_k);
    if (has_eta_k < 0)
        return -1;
    has_eta_k |= eta_texture | k_texture;
    if (has_reflectance && has_eta_k)
        return scene_error(&p->diag, params->file, line, "%s: give either \"reflectance\" or \"%seta\" and \"%sk\"",
                           params->owner, prefix, prefix);
    m->use_reflectance = has_reflectance;
    if (has_reflectance)
        memcpy(m->reflectance, reflectance, sizeof reflectance);
    return 0;
}

/* The layered BSDF's parameters of the coated materials (pbrt-v4's
 * defaults: thickness 0.01, no medium, g 0, maxdepth 10, nsamples 1);
 * thickness, g and albedo may be textures. */
static int read_layers(ParamList *params, SceneMaterial *m, int line, Parser *p)
{
    if (read_slot(p, params, m, SCENE_SLOT_THICKNESS, "thickness", 0) < 0 ||
        read_slot(p, params, m, SCENE_SLOT_G, "g", 0) < 0 ||
        read_spectrum_slot(p, params, m, SCENE_SLOT_ALBEDO, "albedo", SPECTRUM_ALBEDO, m->albedo, NULL) ||
        params_get_float(params, "thickness", &m->thickness) < 0 || params_get_float(params, "g", &m->g) < 0 ||
        params_get_int(params, "maxdepth", &m->max_depth) < 0 ||
        params_get_int(params, "nsamples", &m->sample_count) < 0 ||
        params_get_bool(params, "remaproughness", &m->remap_roughness) < 0)
        return -1;
    if (!(m->thickness > 0.0f) || !(m->g > -1.0f && m->g < 1.0f) || m->max_depth < 1 || m->sample_count < 1 ||
        m->sample_count > 1024 || m->max_depth > 1024)
        return scene_error(&p->diag, params->file, line,
                           "%s: needs thickness > 0, -1 < g < 1, 1 <= maxdepth <= 1024 and 1 <= nsamples <= 1024",
                           params->owner);
    return 0;
}

/* How many mixes deep material `index` is (0: not a mix). Components come
 * before their mix, and their nesting is bounded when they are read. */
static int mix_nesting(const Scene *scene, int index)
{
    const SceneMaterial *m = &scene->materials[index];
    if (m->type != SCENE_MATERIAL_MIX)
        return 0;
    int a = mix_nesting(scene, m->mix_materials[0]), b = mix_nesting(scene, m->mix_materials[1]);
    return 1 + (a > b ? a : b);
}

/* "string materials" [ "a" "b" ]: two named materials defined before. */
static int read_mix(Parser *p, ParamList *params, int line, SceneMaterial *m)
{
    const Param *names = NULL;
    int found = params_get_array(params, "materials", PARAM_STRING, &names);
    if (found < 0)
        return -1;
    if (found == 0 || names->count != 2)
        return scene_error(&p->diag, params->file, line, "%s: needs \"string materials\" with two material names",
                           params->owner);
    for (int i = 0; i < 2; ++i) {
        m->mix_materials[i] = -1;
        for (size_t j = 0; j < p->named_count && m->mix_materials[i] < 0; ++j)
            if (p->named[j].defined && strcmp(p->named[j].name, names->strings[i]) == 0)
                m->mix_materials[i] = p->named[j].material;
        if (m->mix_materials[i] < 0)
            return scene_error(&p->diag, params->file, line, "%s: no material named \"%s\"", params->owner,
                               names->strings[i]);
        const SceneMaterial *component = &p->scene->materials[m->mix_materials[i]];
        if (component->type == SCENE_MATERIAL_INTERFACE)
            return scene_error(&p->diag, params->file, line, "%s: \"%s\" is an \"interface\", which a mix cannot hold",
                               params->owner, names->strings[i]);
        if (mix_nesting(p->scene, m->mix_materials[i]) >= SCENE_MIX_MAX_NESTING)
            return scene_error(&p->diag, params->file, line, "%s: mixes nested deeper than %d", params->owner,
                               SCENE_MIX_MAX_NESTING);
    }
    if (read_slot(p, params, m, SCENE_SLOT_MIX_AMOUNT, "amount", 0) < 0 ||
        params_get_float(params, "amount", &m->mix_amount) < 0)
        return -1;
    return 0;
}

/* Fills *m from a material type and its parameters. An unknown type is
 * unsupported; allow_unsupported substitutes grey diffuse, or for hair,
 * measured and subsurface a diffuse of their reflectance. */
static int parse_material(Parser *p, const char *type, ParamList *params, int line, SceneMaterial *m)
{
    default_material(m);
    if (read_bump(p, params, m, line))
        return -1;
    if (strcmp(type, "diffuse") == 0) {
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL))
            return -1;
    } else if (strcmp(type, "dielectric") == 0 || strcmp(type, "thindielectric") == 0) {
        m->type = type[0] == 't' ? SCENE_MATERIAL_THIN_DIELECTRIC : SCENE_MATERIAL_DIELECTRIC;
        if (read_slot(p, params, m, SCENE_SLOT_ETA, "eta", 0) < 0 || read_eta(params, "eta", &m->eta, line, p))
            return -1;
        if (m->type == SCENE_MATERIAL_DIELECTRIC &&
            (read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
             params_get_bool(params, "remaproughness", &m->remap_roughness) < 0))
            return -1;
    } else if (strcmp(type, "conductor") == 0) {
        m->type = SCENE_MATERIAL_CONDUCTOR;
        memset(m->reflectance, 0, sizeof m->reflectance);
        if (read_conductor(p, params, "", m, line) ||
            read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            params_get_bool(params, "remaproughness", &m->remap_roughness) < 0)
            return -1;
    } else if (strcmp(type, "coateddiffuse") == 0) {
        m->type = SCENE_MATERIAL_COATED_DIFFUSE;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL) ||
            read_eta(params, "eta", &m->eta, line, p) ||
            read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            read_layers(params, m, line, p))
            return -1;
    } else if (strcmp(type, "coatedconductor") == 0) {
        m->type = SCENE_MATERIAL_COATED_CONDUCTOR;
        memset(m->reflectance, 0, sizeof m->reflectance);
        if (read_eta(params, "interface.eta", &m->eta, line, p) ||
            read_roughness(p, params, m, "interface.", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            read_conductor(p, params, "conductor.", m, line) ||
            read_roughness(p, params, m, "conductor.", m->base_roughness, SCENE_SLOT_BASE_ROUGHNESS_U, line) ||
            read_layers(params, m, line, p))
            return -1;
    } else if (strcmp(type, "diffusetransmission") == 0) {
        m->type = SCENE_MATERIAL_DIFFUSE_TRANSMISSION;
        float scale = 1.0f;
        m->reflectance[0] = m->reflectance[1] = m->reflectance[2] = 0.25f;
        m->transmittance[0] = m->transmittance[1] = m->transmittance[2] = 0.25f;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL) ||
            read_spectrum_slot(p, params, m, SCENE_SLOT_TRANSMITTANCE, "transmittance", SPECTRUM_ALBEDO,
                               m->transmittance, NULL) ||
            params_get_float(params, "scale", &scale) < 0)
            return -1;
        /* Constants only: the kernel clamps each textured one, scaled, to
         * [0, 1] (as pbrt-v4 does every one). */
        int reflects = m->textures[SCENE_SLOT_REFLECTANCE] < 0, transmits = m->textures[SCENE_SLOT_TRANSMITTANCE] < 0;
        float most = 0.0f;
        for (int c = 0; c < 3; ++c)
            most = fmaxf(most, (reflects ? m->reflectance[c] : 0.0f) + (transmits ? m->transmittance[c] : 0.0f));
        if (!(scale >= 0.0f) || scale * most > 1.0f)
            return scene_error(&p->diag, params->file, line,
                               "%s: \"scale\" must not be negative nor scatter more than it receives", params->owner);
        m->scale = scale;
        for (int c = 0; c < 3; ++c) {
            m->reflectance[c] *= scale;
            m->transmittance[c] *= scale;
        }
    } else if (strcmp(type, "mix") == 0) {
        m->type = SCENE_MATERIAL_MIX;
        if (read_mix(p, params, line, m))
            return -1;
    } else if (strcmp(type, "interface") == 0 || type[0] == '\0' || strcmp(type, "none") == 0) {
        m->type = SCENE_MATERIAL_INTERFACE; /* pbrt-v4 takes "" and "none" as no material, as "interface" */
    } else if (strcmp(type, "hair") == 0 || strcmp(type, "measured") == 0 || strcmp(type, "subsurface") == 0) {
        if (scene_unsupported(&p->diag, params->file, line, "a diffuse of its \"reflectance\" (default 0.5) is used",
                              "Material \"%s\" is not supported", type))
            return -1;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL))
            return -1;
        return 0; /* its other parameters mean nothing to the substitute */
    } else {
        return scene_unsupported(&p->diag, params->file, line, "grey diffuse (reflectance 0.5) is used instead",
                                 "Material \"%s\" is not supported (diffuse, dielectric, thindielectric, conductor, "
                                 "coateddiffuse, coatedconductor, diffusetransmission, mix, interface)",
                                 type);
    }
    return params_check_unused(params);
}

/* ----------------------------------------------------------- directives */

static int parse_file(Parser *p, const char *path, const char *from_file, int from_line);

static int same_matrix(mat4 a, mat4 b)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (a[c][r] != b[c][r])
                return 0;
    return 1;
}

/* After a transform directive: products of finite numbers can overflow. */
static int check_transform(Parser *p, Lexer *lex, const Token *d)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!isfinite(p->state.ctm[c][r]) || !isfinite(p->state.ctm_end[c][r])) {
                char name[32];
                directive_name(d, name, sizeof name);
                return scene_error(&p->diag, lex->path, d->line,
                                   "%s: the transform overflows single precision (an entry is not finite)", name);
            }
    return 0;
}

/* Before a shape, light or camera takes the CTM: when its start and end
 * transforms differ it moves, which gmonrt does not render. It renders the
 * start time, with one warning for the whole scene. */
static int warn_if_moving(Parser *p, Lexer *lex, const Token *d)
{
    if (p->motion_warned || same_matrix(p->state.ctm, p->state.ctm_end))
        return 0;
    p->motion_warned = 1;
    char name[32];
    directive_name(d, name, sizeof name);
    return scene_warn(&p->diag, lex->path, d->line,
                      "%s: its transforms at the start and end times differ (ActiveTransform): motion is not "
                      "rendered, the scene is rendered at the start time",
                      name);
}

/* The transforms a transform directive changes (ActiveTransform); returns
 * how many of out[0..1] it filled. */
static int active_transforms(Parser *p, mat4 *out[2])
{
    int n = 0;
    if (p->state.active_transforms & ACTIVE_START)
        out[n++] = &p->state.ctm;
    if (p->state.active_transforms & ACTIVE_END)
        out[n++] = &p->state.ctm_end;
    return n;
}

static int apply_transform(Parser *p, Lexer *lex, const Token *d, mat4 m)
{
    mat4 *active[2];
    for (int i = active_transforms(p, active) - 1; i >= 0; --i)
        glm_mat4_mul(*active[i], m, *active[i]);
    return check_transform(p, lex, d);
}

/* Sets the active transforms to m. */
static int set_transform(Parser *p, Lexer *lex, const Token *d, mat4 m)
{
    mat4 *active[2];
    for (int i = active_transforms(p, active) - 1; i >= 0; --i)
        glm_mat4_copy(m, *active[i]);
    return check_transform(p, lex, d);
}

/* In double: a float difference of far points overflows, and squaring a
 * float direction of 1e20 overflows too. */
static int on_look_at(Parser *p, Lexer *lex, const Token *d)
{
    double v[9];
    if (read_numbers(p, lex, d, 9, 0, v))
        return -1;
    double eye[3] = {(float)v[0], (float)v[1], (float)v[2]}, up[3] = {(float)v[6], (float)v[7], (float)v[8]};
    double dir[3] = {(double)(float)v[3] - eye[0], (double)(float)v[4] - eye[1], (double)(float)v[5] - eye[2]};
    double right[3], new_up[3];
    if (normalize_d(dir) == 0.0)
        return scene_error(&p->diag, lex->path, d->line, "LookAt: the eye and the look-at point are the same");
    normalize_d(up);
    cross_d(up, dir, right); /* left-handed: +x = up x forward */
    if (normalize_d(right) < 1e-6)
        return scene_error(&p->diag, lex->path, d->line, "LookAt: the up vector is parallel to the view direction");
    cross_d(dir, right, new_up);
    /* camera_from_world is the inverse of [right up dir eye]: rows right,
     * up, dir and the translation -R^T eye. */
    mat4 m = GLM_MAT4_IDENTITY_INIT;
    for (int c = 0; c < 3; ++c) {
        m[c][0] = (float)right[c];
        m[c][1] = (float)new_up[c];
        m[c][2] = (float)dir[c];
    }
    m[3][0] = (float)-dot_d(right, eye);
    m[3][1] = (float)-dot_d(new_up, eye);
    m[3][2] = (float)-dot_d(dir, eye);
    return apply_transform(p, lex, d, m);
}

static int on_translate(Parser *p, Lexer *lex, const Token *d)
{
    double v[3];
    if (read_numbers(p, lex, d, 3, 0, v))
        return -1;
    vec3 t = {(float)v[0], (float)v[1], (float)v[2]};
    mat4 *active[2];
    for (int i = active_transforms(p, active) - 1; i >= 0; --i)
        glm_translate(*active[i], t);
    return check_transform(p, lex, d);
}

static int on_scale(Parser *p, Lexer *lex, const Token *d)
{
    double v[3];
    if (read_numbers(p, lex, d, 3, 0, v))
        return -1;
    vec3 s = {(float)v[0], (float)v[1], (float)v[2]};
    mat4 *active[2];
    for (int i = active_transforms(p, active) - 1; i >= 0; --i)
        glm_scale(*active[i], s);
    return check_transform(p, lex, d);
}

static int on_rotate(Parser *p, Lexer *lex, const Token *d)
{
    double v[4];
    if (read_numbers(p, lex, d, 4, 0, v))
        return -1;
    vec3 axis = {(float)v[1], (float)v[2], (float)v[3]};
    if (glm_vec3_norm(axis) == 0.0f)
        return scene_error(&p->diag, lex->path, d->line, "Rotate: the axis is zero");
    mat4 *active[2];
    for (int i = active_transforms(p, active) - 1; i >= 0; --i)
        glm_rotate(*active[i], (float)(v[0] * 3.14159265358979323846 / 180.0), axis);
    return check_transform(p, lex, d);
}

/* Transform and ConcatTransform list the matrix column by column (pbrt
 * stores it transposed), which is cglm's memory order. */
static int read_matrix(Parser *p, Lexer *lex, const Token *d, mat4 m)
{
    double v[16];
    if (read_numbers(p, lex, d, 16, 1, v))
        return -1;
    for (int i = 0; i < 16; ++i)
        m[i / 4][i % 4] = (float)v[i];
    return 0;
}

static int on_transform(Parser *p, Lexer *lex, const Token *d)
{
    mat4 m;
    if (read_matrix(p, lex, d, m))
        return -1;
    return set_transform(p, lex, d, m);
}

static int on_concat_transform(Parser *p, Lexer *lex, const Token *d)
{
    mat4 m;
    if (read_matrix(p, lex, d, m))
        return -1;
    return apply_transform(p, lex, d, m);
}

static int on_identity(Parser *p, Lexer *lex, const Token *d)
{
    mat4 identity = GLM_MAT4_IDENTITY_INIT;
    return set_transform(p, lex, d, identity);
}

/* The named coordinate system, or NULL. */
static NamedTransform *find_coordinate_system(Parser *p, const char *name, size_t length)
{
    for (size_t i = 0; i < p->coordinate_system_count; ++i)
        if (strlen(p->coordinate_systems[i].name) == length && memcmp(p->coordinate_systems[i].name, name, length) == 0)
            return &p->coordinate_systems[i];
    return NULL;
}

/* Names (or renames) a coordinate system: CoordinateSystem, and pbrt-v4's
 * "camera" at Camera and "world" at WorldBegin. */
static int define_coordinate_system(Parser *p, const char *name, size_t length, mat4 start, mat4 end)
{
    NamedTransform *named = find_coordinate_system(p, name, length);
    if (!named) {
        char *copy = scene_strndup(name, length);
        if (!copy || scene_reserve((void **)&p->coordinate_systems, &p->coordinate_system_capacity,
                                   p->coordinate_system_count + 1, sizeof *p->coordinate_systems)) {
            free(copy);
            return -1;
        }
        named = &p->coordinate_systems[p->coordinate_system_count++];
        named->name = copy;
    }
    glm_mat4_copy(start, named->start);
    glm_mat4_copy(end, named->end);
    return 0;
}

static int on_coordinate_system(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (expect_string(p, lex, d, "the coordinate system's name", &name))
        return -1;
    if (define_coordinate_system(p, name.text, name.length, p->state.ctm, p->state.ctm_end))
        return out_of_memory(p, lex->path, d->line);
    return 0;
}

/* pbrt-v4: the CTM becomes the named one (both times, whatever is active);
 * an unknown name is a warning and leaves the CTM as it was. */
static int on_coord_sys_transform(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (expect_string(p, lex, d, "the coordinate system's name", &name))
        return -1;
    const NamedTransform *named = find_coordinate_system(p, name.text, name.length);
    if (!named) {
        char shown[64];
        token_describe(&name, shown, sizeof shown);
        return scene_warn(&p->diag, lex->path, d->line,
                          "CoordSysTransform: no coordinate system named %s (pbrt-v4 defines \"camera\" at Camera "
                          "and \"world\" at WorldBegin); the transform is unchanged",
                          shown);
    }
    glm_mat4_copy((vec4 *)named->start, p->state.ctm);
    glm_mat4_copy((vec4 *)named->end, p->state.ctm_end);
    return check_transform(p, lex, d);
}

static int on_active_transform(Parser *p, Lexer *lex, const Token *d)
{
    (void)d;
    Token which;
    if (lexer_next(lex, &which))
        return -1;
    if (token_is(&which, "All"))
        p->state.active_transforms = ACTIVE_ALL;
    else if (token_is(&which, "StartTime"))
        p->state.active_transforms = ACTIVE_START;
    else if (token_is(&which, "EndTime"))
        p->state.active_transforms = ACTIVE_END;
    else {
        char shown[64];
        token_describe(&which, shown, sizeof shown);
        return scene_error(&p->diag, lex->path, which.line,
                           "ActiveTransform: expected All, StartTime or EndTime, got %s", shown);
    }
    return 0;
}

/* The shutter times the two transforms belong to: only the start is rendered. */
static int on_transform_times(Parser *p, Lexer *lex, const Token *d)
{
    double times[2];
    return read_numbers(p, lex, d, 2, 0, times) || require_world(p, lex, d, 0) ? -1 : 0;
}

static int on_reverse_orientation(Parser *p, Lexer *lex, const Token *d)
{
    (void)lex, (void)d;
    p->state.reverse_orientation = !p->state.reverse_orientation;
    return 0;
}

static int push_state(Parser *p, Lexer *lex, const Token *d, PushKind kind)
{
    if (scene_reserve((void **)&p->stack, &p->stack_capacity, p->depth + 1, sizeof *p->stack))
        return out_of_memory(p, lex->path, d->line);
    GraphicsState *saved = &p->stack[p->depth++];
    *saved = p->state;
    saved->kind = kind;
    saved->file = lex->path;
    saved->line = d->line;
    return 0;
}

static const char *push_name(PushKind kind)
{
    return kind == PUSHED_ATTRIBUTES ? "AttributeBegin" : kind == PUSHED_TRANSFORM ? "TransformBegin" : "ObjectBegin";
}

static int pop_state(Parser *p, Lexer *lex, const Token *d, PushKind kind)
{
    char name[32];
    directive_name(d, name, sizeof name);
    if (p->depth == 0)
        return scene_error(&p->diag, lex->path, d->line, "%s without a matching %s", name, push_name(kind));
    GraphicsState *saved = &p->stack[p->depth - 1];
    if (saved->kind != kind)
        return scene_error(&p->diag, lex->path, d->line, "%s closes the %s at %s:%d", name, push_name(saved->kind),
                           saved->file, saved->line);
    p->depth--;
    if (kind == PUSHED_TRANSFORM) {
        glm_mat4_copy(saved->ctm, p->state.ctm);
        glm_mat4_copy(saved->ctm_end, p->state.ctm_end);
        p->state.active_transforms = saved->active_transforms;
    } else
        p->state = *saved;
    return 0;
}

static int on_attribute_begin(Parser *p, Lexer *lex, const Token *d)
{
    return push_state(p, lex, d, PUSHED_ATTRIBUTES);
}

static int on_attribute_end(Parser *p, Lexer *lex, const Token *d)
{
    return pop_state(p, lex, d, PUSHED_ATTRIBUTES);
}

static int on_transform_begin(Parser *p, Lexer *lex, const Token *d)
{
    return push_state(p, lex, d, PUSHED_TRANSFORM);
}

static int on_transform_end(Parser *p, Lexer *lex, const Token *d)
{
    return pop_state(p, lex, d, PUSHED_TRANSFORM);
}

static int on_object_begin(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (require_world(p, lex, d, 1) || expect_string(p, lex, d, "the object's name", &name))
        return -1;
    if (p->object >= 0)
        return scene_error(&p->diag, lex->path, d->line,
                           "ObjectBegin inside the ObjectBegin at %s:%d (pbrt-v4 does "
                           "not nest object definitions)",
                           p->object_file, p->object_line);
    Scene *s = p->scene;
    for (size_t i = 0; i < s->object_count; ++i)
        if (strlen(s->objects[i].name) == name.length && memcmp(s->objects[i].name, name.text, name.length) == 0)
            return scene_error(&p->diag, lex->path, d->line,
                               "ObjectBegin \"%s\": an object of that name is defined "
                               "already (pbrt-v4 does not redefine objects)",
                               s->objects[i].name);
    if (scene_reserve((void **)&s->objects, &p->object_capacity, s->object_count + 1, sizeof *s->objects))
        return out_of_memory(p, lex->path, d->line);
    SceneObject *object = &s->objects[s->object_count];
    object->name = scene_strndup(name.text, name.length);
    if (!object->name)
        return out_of_memory(p, lex->path, d->line);
    object->first_shape = s->shape_count;
    object->shape_count = 0;
    p->object = (int)s->object_count++;
    p->object_file = lex->path;
    p->object_line = d->line;
    return push_state(p, lex, d, PUSHED_OBJECT);
}

static int on_object_end(Parser *p, Lexer *lex, const Token *d)
{
    if (pop_state(p, lex, d, PUSHED_OBJECT))
        return -1;
    SceneObject *object = &p->scene->objects[p->object];
    object->shape_count = p->scene->shape_count - object->first_shape;
    p->object = -1;
    return 0;
}

static int on_object_instance(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (require_world(p, lex, d, 1) || expect_string(p, lex, d, "the object's name", &name) ||
        warn_if_moving(p, lex, d))
        return -1;
    if (p->object >= 0)
        return scene_error(&p->diag, lex->path, d->line,
                           "ObjectInstance inside the ObjectBegin at %s:%d (pbrt-v4 does not nest instances)",
                           p->object_file, p->object_line);
    Scene *s = p->scene;
    if (scene_reserve((void **)&s->instances, &p->instance_capacity, s->instance_count + 1, sizeof *s->instances) ||
        scene_reserve((void **)&p->pending, &p->pending_capacity, s->instance_count + 1, sizeof *p->pending))
        return out_of_memory(p, lex->path, d->line);
    struct PendingInstance *pending = &p->pending[s->instance_count];
    pending->name = scene_strndup(name.text, name.length);
    pending->file = lex->path;
    pending->line = d->line;
    if (!pending->name)
        return out_of_memory(p, lex->path, d->line);
    SceneInstance *instance = &s->instances[s->instance_count++];
    instance->object = -1;
    memcpy(instance->world_from_object, p->state.ctm, sizeof instance->world_from_object);
    return 0;
}

typedef struct {
    const char *name;
    int object;
} NamedObject;

static int compare_named_objects(const void *x, const void *y)
{
    return strcmp(((const NamedObject *)x)->name, ((const NamedObject *)y)->name);
}

/* Gives each ObjectInstance its object; an unknown name is an error, as
 * in pbrt-v4. */
static int finish_instances(Parser *p)
{
    Scene *s = p->scene;
    if (s->instance_count == 0)
        return 0;
    NamedObject *by_name = malloc((s->object_count + 1) * sizeof *by_name);
    if (!by_name)
        return scene_error(&p->diag, p->main_path, 0, "out of memory");
    for (size_t i = 0; i < s->object_count; ++i)
        by_name[i] = (NamedObject){s->objects[i].name, (int)i};
    qsort(by_name, s->object_count, sizeof *by_name, compare_named_objects);
    int result = 0;
    InstanceCheck check = {0};
    for (size_t i = 0; i < s->instance_count && result == 0; ++i) {
        NamedObject key = {p->pending[i].name, -1};
        const NamedObject *found = bsearch(&key, by_name, s->object_count, sizeof *by_name, compare_named_objects);
        if (found)
            s->instances[i].object = found->object;
        else
            result = scene_error(&p->diag, p->pending[i].file, p->pending[i].line,
                                 "ObjectInstance: no object \"%s\" is defined (ObjectBegin)", p->pending[i].name);
        if (found)
            result = scene_check_instance(&p->diag, &check, i, p->pending[i].file, p->pending[i].line);
    }
    instance_check_free(&check);
    free(by_name);
    return result;
}

static int on_world_begin(Parser *p, Lexer *lex, const Token *d)
{
    if (p->in_world)
        return scene_error(&p->diag, lex->path, d->line, "WorldBegin given twice");
    if (p->depth > 0)
        return scene_error(&p->diag, lex->path, d->line, "WorldBegin inside the %s at %s:%d",
                           push_name(p->stack[p->depth - 1].kind), p->stack[p->depth - 1].file,
                           p->stack[p->depth - 1].line);
    p->in_world = 1;
    glm_mat4_identity(p->state.ctm);
    glm_mat4_identity(p->state.ctm_end);
    p->state.active_transforms = ACTIVE_ALL;
    if (define_coordinate_system(p, "world", 5, p->state.ctm, p->state.ctm_end))
        return out_of_memory(p, lex->path, d->line);
    return 0;
}

static int on_world_end(Parser *p, Lexer *lex, const Token *d)
{
    (void)p, (void)lex, (void)d; /* pbrt-v3's; pbrt-v4 ends the world at the end of the file */
    return 0;
}

/* Camera "screenwindow": x_min x_max y_min y_max, each pair apart. */
static int read_screen_window(ParamList *params, SceneCamera *camera)
{
    const Param *window = NULL;
    int found = params_get_array(params, "screenwindow", PARAM_FLOAT, &window);
    if (found <= 0)
        return found;
    if (window->count != 4)
        return params_error(params, window, "expected 4 values (x_min x_max y_min y_max), got %zu", window->count);
    if (window->numbers[0] == window->numbers[1] || window->numbers[2] == window->numbers[3])
        return params_error(params, window, "the window is empty (x_min = x_max or y_min = y_max)");
    for (int i = 0; i < 4; ++i)
        camera->screen_window[i] = (float)window->numbers[i];
    camera->has_screen_window = 1;
    return 0;
}

static int on_camera(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the camera type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0)
        result = warn_if_moving(p, lex, d);
    int orthographic = result == 0 && token_is(&type, "orthographic");
    if (result == 0 && !orthographic && !token_is(&type, "perspective")) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line,
                                   "a \"perspective\" camera (fov 90) is used, and its parameters other than the "
                                   "shutter times are ignored",
                                   "Camera %s is not supported (only \"perspective\" and \"orthographic\")", shown);
        /* realistic's lens, spherical's mapping: nothing a perspective camera has */
        for (size_t i = 0; result == 0 && i < params.count; ++i)
            if (strcmp(params.items[i].name, "shutteropen") != 0 && strcmp(params.items[i].name, "shutterclose") != 0)
                params_ignore(&params, params.items[i].name);
    }
    const char *kind = orthographic ? "orthographic" : "perspective";
    SceneCamera camera; /* a Camera given twice replaces the first */
    memset(&camera, 0, sizeof camera);
    camera.projection = orthographic ? SCENE_CAMERA_ORTHOGRAPHIC : SCENE_CAMERA_PERSPECTIVE;
    /* pbrt-v4's defaults; frame NAN: not given (the film's aspect ratio). */
    float fov = 90.0f, lens_radius = 0.0f, focal_distance = 1e6f, frame = NAN;
    if (result == 0 &&
        ((!orthographic && params_get_float(&params, "fov", &fov) < 0) ||
         params_get_float(&params, "lensradius", &lens_radius) < 0 ||
         params_get_float(&params, "focaldistance", &focal_distance) < 0 ||
         params_get_float(&params, "frameaspectratio", &frame) < 0 || read_screen_window(&params, &camera) < 0 ||
         params_get_float(&params, "shutteropen", &p->shutter_open) < 0 ||
         params_get_float(&params, "shutterclose", &p->shutter_close) < 0))
        result = -1;
    if (result == 0 && !(fov > 0.0f && fov < 180.0f))
        result =
            scene_error(&p->diag, lex->path, d->line, "Camera \"perspective\": fov %g is not in (0, 180)", (double)fov);
    if (result == 0 && lens_radius < 0.0f)
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": lensradius %g is negative", kind,
                             (double)lens_radius);
    if (result == 0 && !(focal_distance > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": focaldistance %g is not positive", kind,
                             (double)focal_distance);
    if (result == 0 && !isnan(frame) && !(frame > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": frameaspectratio %g is not positive", kind,
                             (double)frame);
    if (result == 0)
        result = params_check_unused(&params);
    mat4 world_from_camera;
    if (result == 0 && (det3(p->state.ctm) == 0.0 || invert_in_double(p->state.ctm, world_from_camera)))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Camera: the camera transform is singular (or its inverse overflows single precision)");
    const float origin[3] = {0.0f, 0.0f, 0.0f};
    float position[3];
    if (result == 0)
        transform_point(world_from_camera, origin, position);
    if (result == 0 && !within_range(position))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Camera: the camera is at (%g, %g, %g), beyond %g from the origin (the renderer squares "
                             "distances in single precision)",
                             (double)position[0], (double)position[1], (double)position[2], SCENE_MAX_COORDINATE);
    if (result == 0) {
        glm_mat4_copy(p->state.ctm, p->camera_from_world);
        glm_mat4_copy(world_from_camera, p->world_from_camera);
        /* pbrt-v4's "camera" space; a moving camera is rendered at the start time. */
        if (define_coordinate_system(p, "camera", 6, world_from_camera, world_from_camera))
            result = out_of_memory(p, lex->path, d->line);
        camera.fov = fov;
        camera.lens_radius = lens_radius; /* camera space until finish_camera */
        camera.focal_distance = focal_distance;
        camera.frame_aspect_ratio = isnan(frame) ? 0.0f : frame;
        p->scene->camera = camera;
        p->camera_file = lex->path;
        p->camera_line = d->line;
    }
    params_free(&params);
    return result;
}

static int replace_string(Parser *p, const char *file, int line, char **target, const char *value)
{
    char *copy = scene_strndup(value, strlen(value));
    if (!copy)
        return out_of_memory(p, file, line);
    free(*target);
    *target = copy;
    return 0;
}

/* pbrt-v4's "cropwindow" (fractions x0 x1 y0 y1 of the image, clamped to
 * [0, 1], either order) or "pixelbounds" (pixels x0 x1 y0 y1, clamped to
 * the image; the crop window wins when both are given), as a crop window. */
static int read_film_crop(Parser *p, Lexer *lex, const Token *d, ParamList *params, int width, int height,
                          float crop[4])
{
    const Param *window = NULL, *bounds = NULL;
    int has_window = params_get_array(params, "cropwindow", PARAM_FLOAT, &window);
    int has_bounds = params_get_array(params, "pixelbounds", PARAM_INTEGER, &bounds);
    if (has_window < 0 || has_bounds < 0)
        return -1;
    if (has_window && window->count != 4)
        return params_error(params, window, "expected 4 values (x0 x1 y0 y1), got %zu", window->count);
    if (has_bounds && bounds->count != 4)
        return params_error(params, bounds, "expected 4 values (x0 x1 y0 y1), got %zu", bounds->count);
    const int size[2] = {width, height};
    for (int axis = 0; axis < 2; ++axis) {
        double a = 0.0, b = 1.0;
        if (has_window) {
            a = fmin(window->numbers[2 * axis], window->numbers[2 * axis + 1]);
            b = fmax(window->numbers[2 * axis], window->numbers[2 * axis + 1]);
        } else if (has_bounds) {
            a = bounds->numbers[2 * axis] / size[axis];
            b = bounds->numbers[2 * axis + 1] / size[axis];
        }
        crop[2 * axis] = (float)fmin(fmax(a, 0.0), 1.0);
        crop[2 * axis + 1] = (float)fmin(fmax(b, 0.0), 1.0);
        float lo = (float)size[axis] * crop[2 * axis], hi = (float)size[axis] * crop[2 * axis + 1];
        if (ceilf(lo) >= ceilf(hi)) /* in single precision, as pbrt-v4 */
            return scene_error(&p->diag, lex->path, d->line, "Film: the %s leaves no pixel",
                               has_window ? "crop window" : "pixel bounds");
    }
    return 0;
}

static int on_film(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    Scene *s = p->scene;
    int result = read_typed_directive(p, lex, d, "the film type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0 && token_is(&type, "gbuffer")) {
        /* pbrt-v4's gbuffer film adds geometry channels to the same RGB. */
        result =
            scene_warn(&p->diag, lex->path, d->line, "Film \"gbuffer\": rendered as \"rgb\" (no geometry channels)");
        params_ignore(&params, "coordinatesystem");
    } else if (result == 0 && !token_is(&type, "rgb")) {
        result = scene_unsupported(&p->diag, lex->path, d->line, "an \"rgb\" film is used",
                                   "Film: only \"rgb\" and \"gbuffer\" are supported");
    }
    int width = (int)s->width, height = (int)s->height, save_fp16 = s->save_fp16;
    const char *filename = NULL, *sensor = "cie1931";
    float iso = 100.0f, scale = 1.0f, white_balance = 0.0f, max_component = INFINITY, diagonal = s->film_diagonal;
    if (result == 0 &&
        (params_get_int(&params, "xresolution", &width) < 0 || params_get_int(&params, "yresolution", &height) < 0 ||
         params_get_string(&params, "filename", &filename) < 0 || params_get_float(&params, "iso", &iso) < 0 ||
         params_get_float(&params, "scale", &scale) < 0 ||
         params_get_float(&params, "whitebalance", &white_balance) < 0 ||
         params_get_string(&params, "sensor", &sensor) < 0 ||
         params_get_float(&params, "maxcomponentvalue", &max_component) < 0 ||
         params_get_float(&params, "diagonal", &diagonal) < 0 || params_get_bool(&params, "savefp16", &save_fp16) < 0))
        result = -1;
    if (result == 0 && (width < 1 || height < 1 || width > 65536 || height > 65536))
        result = scene_error(&p->diag, lex->path, d->line, "Film: resolution %d x %d is out of range", width, height);
    if (result == 0 && !(iso > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: iso %g must be positive", (double)iso);
    if (result == 0 && !(scale > 0.0f && scale < INFINITY))
        result = scene_error(&p->diag, lex->path, d->line, "Film: scale %g must be positive and finite", (double)scale);
    if (result == 0 && (white_balance < 0.0f || white_balance > 1e5f))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Film: whitebalance %g K is not 0 (none) or a temperature up to 100000 K",
                             (double)white_balance);
    if (result == 0 && !(max_component > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: maxcomponentvalue %g must be positive",
                             (double)max_component);
    if (result == 0 && !(diagonal > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: diagonal %g must be positive", (double)diagonal);
    if (result == 0 && (!spectrum_sensor_known(sensor) || strlen(sensor) >= sizeof p->film_sensor)) {
        char known[1024];
        spectrum_sensor_list(known, sizeof known);
        result = scene_error(&p->diag, lex->path, d->line, "Film: unknown sensor \"%s\" (%s)", sensor, known);
    }
    float crop[4] = {0.0f, 1.0f, 0.0f, 1.0f};
    if (result == 0)
        result = read_film_crop(p, lex, d, &params, width, height, crop);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0 && filename)
        result = replace_string(p, lex->path, d->line, &s->film_filename, filename);
    if (result == 0) {
        memcpy(s->crop_window, crop, sizeof crop);
        s->width = (unsigned)width;
        s->height = (unsigned)height;
        s->max_component_value = max_component;
        s->save_fp16 = save_fp16;
        s->film_diagonal = diagonal;
        p->film_iso = iso;
        p->film_scale = scale;
        p->film_white_balance = white_balance;
        snprintf(p->film_sensor, sizeof p->film_sensor, "%s", sensor);
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's imaging ratio takes the exposure from the camera's shutter;
 * the film's "scale" multiplies it (the scale of pbrt-v3's image film,
 * which the scenes that set it carried over). */
static int finish_film(Parser *p)
{
    double exposure = (double)p->shutter_close - (double)p->shutter_open;
    if (!(exposure > 0.0))
        return scene_error(&p->diag, p->camera_file ? p->camera_file : p->main_path, p->camera_line,
                           "Camera: shutterclose %g must be after shutteropen %g (the film's exposure time)",
                           (double)p->shutter_close, (double)p->shutter_open);
    /* on_film accepted only known sensors */
    return spectrum_film_from_radiance(p->film_sensor, exposure * p->film_iso / 100.0 * p->film_scale,
                                       p->film_white_balance, p->scene->film_from_radiance);
}

static int on_sampler(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the sampler type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    int spp = (int)p->scene->spp;
    if (result == 0 && params_get_int(&params, "pixelsamples", &spp) < 0)
        result = -1;
    if (result == 0 && spp < 1)
        result = scene_error(&p->diag, lex->path, d->line, "Sampler: pixelsamples must be at least 1");
    if (result == 0) {
        /* Any sampler is accepted: its name picks one of the renderer's
         * (sampler_for_scene), whose other parameters (seed, jitter, ...)
         * do not apply. */
        char *name = scene_strndup(type.text, type.length);
        if (!name)
            result = out_of_memory(p, lex->path, d->line);
        else {
            free(p->scene->sampler);
            p->scene->sampler = name;
            p->scene->spp = (unsigned)spp;
        }
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's integrators whose expected image is the path tracer's (for a
 * scene without participating media, which gmonrt does not support), and
 * their parameters that only change how fast they converge. */
static const struct {
    const char *name;
    const char *tuning[6];
} same_image_integrators[] = {
    {"path", {NULL}},
    {"volpath", {NULL}},
    {"simplevolpath", {NULL}},
    {"bdpt", {NULL}},
    {"mlt", {"bootstrapsamples", "chains", "mutationsperpixel", "largestepprobability", "sigma", NULL}},
    {"sppm", {"photonsperiteration", "radius", "seed", NULL}},
    {"simplepath", {"samplelights", "samplebsdf", NULL}},
    {"lightpath", {NULL}},
    {"randomwalk", {NULL}},
};

/* Which integrator renders the scene: the path tracer, with a note where
 * pbrt-v4 would use another one with the same expected image, else an
 * unsupported feature (ambientocclusion, aov, ...: their images differ). */
static int choose_integrator(Parser *p, Lexer *lex, const Token *d, const Token *type, ParamList *params)
{
    char shown[64];
    token_describe(type, shown, sizeof shown);
    for (size_t i = 0; i < sizeof same_image_integrators / sizeof same_image_integrators[0]; ++i) {
        if (!token_is(type, same_image_integrators[i].name))
            continue;
        for (const char *const *tuning = same_image_integrators[i].tuning; *tuning; ++tuning)
            params_ignore(params, *tuning);
        int visualize_strategies = 0, visualize_weights = 0; /* bdpt's images of single strategies */
        if (strcmp(same_image_integrators[i].name, "bdpt") == 0 &&
            (params_get_bool(params, "visualizestrategies", &visualize_strategies) < 0 ||
             params_get_bool(params, "visualizeweights", &visualize_weights) < 0))
            return -1;
        if (visualize_strategies || visualize_weights)
            return scene_unsupported(&p->diag, lex->path, d->line, "the path tracer's image is rendered",
                                     "Integrator %s: \"visualizestrategies\" and \"visualizeweights\" are "
                                     "not supported",
                                     shown);
        if (token_is(type, "path"))
            return 0;
        const char *media = strstr(same_image_integrators[i].name, "vol")
                                ? " without participating media (which gmonrt does not support)"
                                : "";
        return scene_note(&p->diag, lex->path, d->line,
                          "Integrator %s is rendered by the path tracer (\"path\"): the expected image is the same%s",
                          shown, media);
    }
    return scene_unsupported(&p->diag, lex->path, d->line, "\"path\" is used",
                             "Integrator %s is not supported: its image differs from the path tracer's "
                             "(path, volpath, simplevolpath, bdpt, mlt, sppm, simplepath, lightpath, randomwalk are)",
                             shown);
}

/* Integrator "lightsampler": pbrt-v4's bvh (its default), exhaustive,
 * power or uniform. bvh is gmonrt's light tree, exhaustive too (the same
 * chances from each light's own bounds, which the tree's walk
 * approximates): the expected image is the same. */
static int read_light_sampler(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    const char *light_sampler = NULL;
    int found = params_get_string(params, "lightsampler", &light_sampler);
    if (found <= 0)
        return found; /* absent, or an error */
    if (strcmp(light_sampler, "bvh") != 0 && strcmp(light_sampler, "exhaustive") != 0 &&
        strcmp(light_sampler, "power") != 0 && strcmp(light_sampler, "uniform") != 0)
        return scene_error(&p->diag, lex->path, d->line,
                           "Integrator: \"lightsampler\" \"%s\" is not bvh, exhaustive, power or uniform",
                           light_sampler);
    if (replace_string(p, lex->path, d->line, &p->scene->light_sampler, light_sampler))
        return -1;
    if (strcmp(light_sampler, "exhaustive") != 0)
        return 0;
    return scene_note(&p->diag, lex->path, d->line,
                      "Integrator: \"lightsampler\" \"exhaustive\" is rendered with gmonrt's light tree (bvh): "
                      "the expected image is the same");
}

static int on_integrator(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the integrator type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0)
        result = choose_integrator(p, lex, d, &type, &params);
    int max_depth = p->scene->max_depth, regularize = 0;
    float rr_threshold = p->scene->rr_threshold;
    /* pbrt-v4's path and volpath integrators take "rrthreshold". */
    int has_roulette_threshold = token_is(&type, "path") || token_is(&type, "volpath");
    if (result == 0 && (params_get_int(&params, "maxdepth", &max_depth) < 0 ||
                        params_get_bool(&params, "regularize", &regularize) < 0 ||
                        (has_roulette_threshold && params_get_float(&params, "rrthreshold", &rr_threshold) < 0)))
        result = -1;
    if (result == 0)
        result = read_light_sampler(p, lex, d, &params);
    if (result == 0 && max_depth < 0)
        result = scene_error(&p->diag, lex->path, d->line, "Integrator: maxdepth must not be negative");
    if (result == 0 && !(rr_threshold >= 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Integrator: rrthreshold %g must not be negative",
                             (double)rr_threshold);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0) {
        p->scene->max_depth = max_depth;
        p->scene->regularize = regularize;
        p->scene->rr_threshold = rr_threshold;
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's Accelerator: "bvh" (its default) or "kdtree", and their build
 * parameters. They change how fast rays are traced, not the image: gmonrt
 * builds its own BVH and notes that. */
static const struct {
    const char *name;
    const char *tuning[6];
} accelerators[] = {
    {"bvh", {"maxnodeprims", "splitmethod", NULL}},
    {"kdtree", {"intersectcost", "traversalcost", "emptybonus", "maxprims", "maxdepth"}},
};

static int on_accelerator(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the accelerator type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    size_t kind = 0;
    while (result == 0 && kind < sizeof accelerators / sizeof accelerators[0] &&
           !token_is(&type, accelerators[kind].name))
        ++kind;
    char shown[64];
    token_describe(&type, shown, sizeof shown);
    if (result == 0 && kind == sizeof accelerators / sizeof accelerators[0])
        result =
            scene_error(&p->diag, lex->path, d->line, "Accelerator %s is not pbrt-v4's \"bvh\" or \"kdtree\"", shown);
    if (result == 0)
        for (const char *const *tuning = accelerators[kind].tuning; *tuning; ++tuning)
            params_ignore(&params, *tuning);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0)
        result = scene_note(&p->diag, lex->path, d->line,
                            "Accelerator %s: gmonrt builds its own BVH (the accelerator changes the speed, not the "
                            "image)",
                            shown);
    params_free(&params);
    return result;
}

/* A filter parameter that must be positive (at most `largest`). */
static int get_filter_parameter(Parser *p, Lexer *lex, const Token *d, ParamList *params, const char *name,
                                float largest, float *value)
{
    if (params_get_float(params, name, value) < 0)
        return -1;
    if (!(*value > 0.0f && *value <= largest))
        return scene_error(&p->diag, lex->path, d->line, "%s: %s %g is not in (0, %g]", params->owner, name,
                           (double)*value, (double)largest);
    return 0;
}

/* pbrt-v4's filters and their default radii; "lanczos" is accepted for
 * pbrt-v4's "sinc" (its class is LanczosSincFilter). */
static const struct {
    const char *name;
    SceneFilterType type;
    float radius;
} FILTERS[] = {
    {"box", SCENE_FILTER_BOX, 0.5f},           {"gaussian", SCENE_FILTER_GAUSSIAN, 1.5f},
    {"mitchell", SCENE_FILTER_MITCHELL, 2.0f}, {"sinc", SCENE_FILTER_LANCZOS, 4.0f},
    {"lanczos", SCENE_FILTER_LANCZOS, 4.0f},   {"triangle", SCENE_FILTER_TRIANGLE, 2.0f},
};
#define FILTER_KINDS (sizeof FILTERS / sizeof FILTERS[0])
#define DEFAULT_FILTER 1 /* gaussian: pbrt-v4's filter when a scene names none */

/* FILTERS[kind] with pbrt-v4's default parameters. */
static SceneFilter default_filter(size_t kind)
{
    SceneFilter f = {
        FILTERS[kind].type, {FILTERS[kind].radius, FILTERS[kind].radius}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f};
    return f;
}

static int on_pixel_filter(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the filter type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    size_t kind = 0;
    while (result == 0 && kind < FILTER_KINDS && !token_is(&type, FILTERS[kind].name))
        ++kind;
    if (result == 0 && kind == FILTER_KINDS) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_error(&p->diag, lex->path, d->line,
                             "PixelFilter %s is not supported (only \"box\", \"gaussian\", \"mitchell\", "
                             "\"sinc\" or \"lanczos\", \"triangle\")",
                             shown);
    }
    SceneFilter filter = default_filter(DEFAULT_FILTER);
    if (result == 0) {
        filter = default_filter(kind);
        const float unbounded = FLT_MAX;
        result = get_filter_parameter(p, lex, d, &params, "xradius", SCENE_MAX_FILTER_RADIUS, &filter.radius[0]);
        if (result == 0)
            result = get_filter_parameter(p, lex, d, &params, "yradius", SCENE_MAX_FILTER_RADIUS, &filter.radius[1]);
        if (result == 0 && filter.type == SCENE_FILTER_GAUSSIAN)
            result = get_filter_parameter(p, lex, d, &params, "sigma", unbounded, &filter.sigma);
        if (result == 0 && filter.type == SCENE_FILTER_LANCZOS)
            result = get_filter_parameter(p, lex, d, &params, "tau", unbounded, &filter.tau);
        if (result == 0 && filter.type == SCENE_FILTER_MITCHELL &&
            (params_get_float(&params, "B", &filter.b) < 0 || params_get_float(&params, "C", &filter.c) < 0))
            result = -1;
    }
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0)
        p->scene->filter = filter;
    params_free(&params);
    return result;
}

static int on_material(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the material type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    char *type_name = result == 0 ? scene_strndup(type.text, type.length) : NULL;
    if (result == 0 && !type_name)
        result = out_of_memory(p, lex->path, d->line);
    SceneMaterial m;
    if (result == 0)
        result = parse_material(p, type_name, &params, d->line, &m);
    if (result == 0) {
        p->state.material = add_material(p, &m);
        if (p->state.material < 0)
            result = out_of_memory(p, lex->path, d->line);
    }
    free(type_name);
    params_free(&params);
    return result;
}

static int on_make_named_material(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the material's name", &name, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    char *name_copy = result == 0 ? scene_strndup(name.text, name.length) : NULL;
    if (result == 0 && !name_copy)
        result = out_of_memory(p, lex->path, d->line);
    NamedMaterial *used_before = NULL; /* by a NamedMaterial before this definition */
    for (size_t i = 0; result == 0 && i < p->named_count; ++i)
        if (strcmp(p->named[i].name, name_copy) == 0) {
            if (p->named[i].defined)
                result =
                    scene_error(&p->diag, lex->path, d->line, "MakeNamedMaterial: \"%s\" is defined twice", name_copy);
            else
                used_before = &p->named[i];
        }
    const char *type = NULL;
    if (result == 0 && params_get_string(&params, "type", &type) < 0)
        result = -1;
    if (result == 0 && !type)
        result =
            scene_error(&p->diag, lex->path, d->line, "MakeNamedMaterial \"%s\": missing \"string type\"", name_copy);
    SceneMaterial m;
    if (result == 0)
        result = parse_material(p, type, &params, d->line, &m);
    if (result == 0 && used_before) {
        p->scene->materials[used_before->material] = m;
        used_before->defined = 1;
    } else if (result == 0) {
        int index = add_material(p, &m);
        if (index < 0 || scene_reserve((void **)&p->named, &p->named_capacity, p->named_count + 1, sizeof *p->named))
            result = out_of_memory(p, lex->path, d->line);
        else {
            p->named[p->named_count++] = (NamedMaterial){name_copy, index, 1, lex->path, d->line};
            name_copy = NULL;
        }
    }
    free(name_copy);
    params_free(&params);
    return result;
}

static int on_named_material(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (require_world(p, lex, d, 1) || expect_string(p, lex, d, "the material's name", &name))
        return -1;
    for (size_t i = 0; i < p->named_count; ++i)
        if (token_is(&name, p->named[i].name)) {
            p->state.material = p->named[i].material;
            return 0;
        }
    /* Not defined yet: a slot for the definition to come (finish_named_materials). */
    SceneMaterial placeholder;
    default_material(&placeholder);
    char *name_copy = scene_strndup(name.text, name.length);
    int index = name_copy ? add_material(p, &placeholder) : -1;
    if (index < 0 || scene_reserve((void **)&p->named, &p->named_capacity, p->named_count + 1, sizeof *p->named)) {
        free(name_copy);
        return out_of_memory(p, lex->path, d->line);
    }
    p->named[p->named_count++] = (NamedMaterial){name_copy, index, 0, lex->path, d->line};
    p->state.material = index;
    return 0;
}

/* Whether check mode found files missing: a name the scene never defines
 * (a material, a texture) may then be defined in one of them. */
static int files_missing(const Parser *p)
{
    const Scene *s = p->scene;
    if (p->diag.check)
        for (size_t i = 0; i < s->diagnostic_count; ++i)
            if (s->diagnostics[i].kind == SCENE_DIAGNOSTIC_MISSING_FILE)
                return 1;
    return 0;
}

/* A NamedMaterial whose name the whole scene never defines is an error at
 * its line, as in pbrt-v4; in check mode with files missing the name may
 * be defined in one of them, so it is not. */
static int finish_named_materials(Parser *p)
{
    if (files_missing(p))
        return 0;
    for (size_t i = 0; i < p->named_count; ++i)
        if (!p->named[i].defined)
            return scene_error(&p->diag, p->named[i].file, p->named[i].line,
                               "NamedMaterial: no material named \"%s\" is defined (MakeNamedMaterial) in the scene",
                               p->named[i].name);
    return 0;
}

/* A light's radiance (L * scale, in double) must fit a float. */
static int check_radiance(Parser *p, Lexer *lex, const Token *d, const char *light, const double radiance[3])
{
    for (int k = 0; k < 3; ++k)
        if (radiance[k] > FLT_MAX)
            return scene_error(&p->diag, lex->path, d->line,
                               "%s: the radiance L * scale, %g, overflows single precision (at most %g)", light,
                               radiance[k], (double)FLT_MAX);
    return 0;
}

static int on_area_light_source(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the area light type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    if (result == 0 && !token_is(&type, "diffuse")) {
        p->state.has_area_light = 0;
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line, "the shapes do not emit",
                                   "AreaLightSource %s is not supported (only \"diffuse\")", shown);
        params_free(&params);
        return result;
    }
    float L[3] = {1.0f, 1.0f, 1.0f}, scale = 1.0f, power = -1.0f;
    int two_sided = 0;
    if (result == 0 &&
        (params_get_spectrum(&params, "L", SPECTRUM_ILLUMINANT, L) < 0 ||
         params_get_float(&params, "scale", &scale) < 0 || params_get_bool(&params, "twosided", &two_sided) < 0 ||
         params_get_float(&params, "power", &power) < 0))
        result = -1;
    if (result == 0 && scale < 0.0f)
        result = scene_error(&p->diag, lex->path, d->line, "AreaLightSource: scale must not be negative");
    if (result == 0 && !(power == -1.0f || power > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "AreaLightSource: power must be positive");
    if (result == 0)
        result = params_check_unused(&params);
    double radiance[3] = {(double)L[0] * scale, (double)L[1] * scale, (double)L[2] * scale};
    if (result == 0)
        result = check_radiance(p, lex, d, "AreaLightSource", radiance);
    if (result == 0) {
        p->state.has_area_light = 1;
        for (int k = 0; k < 3; ++k)
            p->state.area_radiance[k] = (float)radiance[k];
        p->state.area_two_sided = two_sided;
        p->state.area_power = power;
        snprintf(p->state.area_origin, sizeof p->state.area_origin, "%s:%d", lex->path, d->line);
    }
    params_free(&params);
    return result;
}

static char *resolve_path(Parser *p, const char *file, const char *name);

/* A direction through the CTM's linear part, in double. */
static void transform_vector_d(mat4 m, const double v[3], double out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = m[0][k] * v[0] + m[1][k] * v[1] + m[2][k] * v[2];
}

/* Reads the light's point parameter `name` (default `fallback`). */
static int light_point(ParamList *params, const char *name, const float fallback[3], double out[3])
{
    const Param *param = NULL;
    int found = params_get_array(params, name, PARAM_POINT3, &param);
    if (found < 0)
        return -1;
    if (found && param->count != 3)
        return params_error(params, param, "expected one point (3 values), got %zu values", param->count);
    for (int k = 0; k < 3; ++k)
        out[k] = found ? param->numbers[k] : fallback[k];
    return 0;
}

/* pbrt-v4's LightSource directive: point, spot, distant, infinite
 * (uniform, or an equal-area image). Each light's spectrum is scaled by
 * "scale", and "power" (point, spot) or "illuminance" (distant, infinite)
 * replace that scale by one that gives the light this power (W... in
 * pbrt's photometric units) or this illuminance on a surface facing it. */
static int on_light_source(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the light type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    if (result == 0)
        result = warn_if_moving(p, lex, d);
    const int is_point = token_is(&type, "point"), is_spot = token_is(&type, "spot");
    const int is_distant = token_is(&type, "distant"), is_infinite = token_is(&type, "infinite");
    const int is_goniometric = token_is(&type, "goniometric"), is_projection = token_is(&type, "projection");
    const int is_imaged = is_goniometric || is_projection; /* point lights shaped by an image */
    if (result == 0 && !is_point && !is_spot && !is_distant && !is_infinite && !is_imaged) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line, "skipped",
                                   "LightSource %s is not supported (point, spot, distant, infinite, goniometric, "
                                   "projection)",
                                   shown);
        params_free(&params);
        return result;
    }
    if (result) {
        params_free(&params);
        return result;
    }
    SceneLight light;
    memset(&light, 0, sizeof light);
    light.illuminance = -1.0f;
    light.power = -1.0f;
    light.fov = 90.0f;
    float L[3] = {1.0f, 1.0f, 1.0f}, scale = 1.0f, power = -1.0f, illuminance = -1.0f;
    const char *filename = NULL;
    int has_L = 0;
    const double pi = 3.14159265358979323846;
    mat4 *ctm = &p->state.ctm;
    result = params_get_float(&params, "scale", &scale) < 0;
    if (!result && (is_point || is_spot || is_goniometric))
        result = params_get_spectrum(&params, "I", SPECTRUM_ILLUMINANT, L) < 0;
    if (!result && (is_point || is_spot || is_imaged))
        result = params_get_float(&params, "power", &power) < 0;
    if (!result && is_imaged)
        result = params_get_string(&params, "filename", &filename) < 0;
    if (!result && is_projection) {
        result = params_get_float(&params, "fov", &light.fov) < 0;
        if (!result && !filename)
            result = scene_error(&p->diag, lex->path, d->line, "%s: missing \"string filename\"", params.owner);
        if (!result && !(light.fov > 0.0f && light.fov < 180.0f))
            result = scene_error(&p->diag, lex->path, d->line, "%s: fov must be in (0, 180), got %g", params.owner,
                                 (double)light.fov);
    }
    if (!result && (is_distant || is_infinite))
        result = (has_L = params_get_spectrum(&params, "L", SPECTRUM_ILLUMINANT, L)) < 0 ||
                 params_get_float(&params, "illuminance", &illuminance) < 0;
    if (!result && is_infinite) {
        /* A portal only helps pbrt sample the image: the light is the same. */
        params_ignore(&params, "portal");
        result = params_get_string(&params, "filename", &filename) < 0;
        if (!result && filename && !filename[0])
            filename = NULL;
        if (!result && filename && has_L)
            result = scene_error(&p->diag, lex->path, d->line,
                                 "LightSource \"infinite\": both \"L\" and \"filename\" given (pbrt-v4 refuses this)");
    }
    if (!result && (scale < 0.0f || !(power == -1.0f || power > 0.0f) || !(illuminance == -1.0f || illuminance > 0.0f)))
        result = scene_error(&p->diag, lex->path, d->line,
                             "%s: scale must not be negative, power and illuminance must be positive", params.owner);
    double from[3], to[3];
    static const float origin[3] = {0.0f, 0.0f, 0.0f}, ahead[3] = {0.0f, 0.0f, 1.0f};
    if (!result && !is_infinite && !is_imaged)
        result = light_point(&params, "from", origin, from) || light_point(&params, "to", ahead, to);
    for (int c = 0; c < 3 && is_imaged; ++c)
        from[c] = 0.0; /* at the CTM's origin */
    if (!result && is_spot) {
        float cone = 30.0f, delta = 5.0f;
        result = params_get_float(&params, "coneangle", &cone) < 0 ||
                 params_get_float(&params, "conedeltaangle", &delta) < 0;
        if (!result && !(cone > 0.0f && cone <= 180.0f && delta >= 0.0f && delta <= cone))
            result = scene_error(&p->diag, lex->path, d->line,
                                 "LightSource \"spot\": coneangle must be in (0, 180] and conedeltaangle in [0, "
                                 "coneangle] (got %g and %g)",
                                 (double)cone, (double)delta);
        light.cos_total_width = (float)cos(cone * pi / 180.0);
        light.cos_falloff_start = (float)cos((cone - delta) * pi / 180.0);
    }
    if (!result)
        result = params_check_unused(&params);
    double k = scale;
    if (!result && is_point) {
        light.type = SCENE_LIGHT_POINT;
        if (power > 0.0f)
            k *= power / (4.0 * pi);
    } else if (!result && is_spot) {
        light.type = SCENE_LIGHT_SPOT;
        if (power > 0.0f)
            k *= power / (2.0 * pi *
                          ((1.0 - light.cos_falloff_start) + (light.cos_falloff_start - light.cos_total_width) / 2.0));
    } else if (!result && is_distant) {
        light.type = SCENE_LIGHT_DISTANT;
        if (illuminance > 0.0f)
            k *= illuminance;
    } else if (!result && is_goniometric && !filename) {
        light.type = SCENE_LIGHT_POINT; /* pbrt-v4 warns and renders it without an image */
        result =
            scene_warn(&p->diag, lex->path, d->line, "%s: no \"filename\": an isotropic point light", params.owner);
        if (power > 0.0f)
            k *= power / (4.0 * pi);
    } else if (!result && is_imaged) {
        light.type = is_goniometric ? SCENE_LIGHT_GONIOMETRIC : SCENE_LIGHT_PROJECTION;
        light.power = power; /* needs the image: scene_convert applies it */
    } else if (!result) {
        light.type = filename ? SCENE_LIGHT_IMAGE : SCENE_LIGHT_INFINITE;
        if (filename)
            light.illuminance = illuminance;
        else if (illuminance > 0.0f)
            k *= illuminance / pi; /* a uniform sky of radiance L gives pi L */
    }
    double radiance[3];
    for (int c = 0; c < 3; ++c)
        radiance[c] = (light.type == SCENE_LIGHT_IMAGE || is_projection ? 1.0 : (double)L[c]) * k;
    if (!result)
        result = check_radiance(p, lex, d, params.owner, radiance);
    for (int c = 0; c < 3; ++c)
        light.radiance[c] = (float)radiance[c];

    if (!result && (is_point || is_spot || is_imaged)) {
        float from_f[3] = {(float)from[0], (float)from[1], (float)from[2]};
        transform_point(*ctm, from_f, light.position);
        if (!within_range(light.position))
            result = scene_error(&p->diag, lex->path, d->line, "%s: the light lies beyond %g of the origin",
                                 params.owner, SCENE_MAX_COORDINATE);
    }
    if (!result && (is_spot || is_distant)) {
        /* spot: it shines along to - from; distant: the light is along from - to */
        double v[3], w[3];
        for (int c = 0; c < 3; ++c)
            v[c] = is_spot ? to[c] - from[c] : from[c] - to[c];
        transform_vector_d(*ctm, v, w);
        if (normalize_d(w) == 0.0 || !isfinite(w[0] + w[1] + w[2]))
            result =
                scene_error(&p->diag, lex->path, d->line, "%s: \"from\" and \"to\" give no direction", params.owner);
        for (int c = 0; c < 3; ++c)
            light.direction[c] = (float)w[c];
    }
    if (!result && (light.type == SCENE_LIGHT_IMAGE || is_imaged) && filename) {
        /* Light space is object space: the rows of the CTM's inverse
         * rotation (its transpose, for a rotation times a uniform scale);
         * pbrt-v4 swaps a goniometric light's y and z, and flips a
         * projection light's y (its image's rows run down). */
        double s;
        if (!is_similarity(*ctm, &s) || !(s > 0.0))
            result = scene_unsupported(&p->diag, lex->path, d->line, "its non-uniform scale or shear is ignored",
                                       "%s: the transform is not a rotation and uniform scale", params.owner);
        for (int r = 0; r < 3; ++r) {
            int column = is_goniometric && r > 0 ? 3 - r : r;
            double sign = is_projection && r == 1 ? -1.0 : 1.0;
            double row[3] = {(*ctm)[column][0], (*ctm)[column][1], (*ctm)[column][2]}; /* a column of the CTM */
            normalize_d(row);
            for (int c = 0; c < 3; ++c)
                light.light_from_world[r][c] = (float)(sign * row[c]);
        }
        if (!result) {
            light.filename = resolve_path(p, lex->path, filename);
            int missing =
                light.filename ? scene_missing_file(&p->diag, lex->path, d->line, light.filename, params.owner) : -1;
            if (missing < 0)
                result = out_of_memory(p, lex->path, d->line);
            else if (missing) { /* check mode: listed, and the light skipped */
                free(light.filename);
                params_free(&params);
                return 0;
            } else if (!scene_file_exists(light.filename))
                result =
                    scene_error(&p->diag, lex->path, d->line, "%s: cannot find \"%s\"", params.owner, light.filename);
        }
    }
    if (!result) {
        char where[1024];
        snprintf(where, sizeof where, "%s:%d", lex->path, d->line);
        light.origin = scene_strndup(where, strlen(where));
        Scene *sc = p->scene;
        if (!light.origin ||
            scene_reserve((void **)&sc->lights, &p->light_capacity, sc->light_count + 1, sizeof *sc->lights))
            result = out_of_memory(p, lex->path, d->line);
        else
            sc->lights[sc->light_count++] = light;
    }
    if (result) {
        free(light.filename);
        free(light.origin);
    }
    params_free(&params);
    return result ? -1 : 0; /* the getters' checks above give 1 */
}

static int shape_sphere(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    float radius = 1.0f;
    if (params_get_float(params, "radius", &radius) < 0 || params_check_unused(params))
        return -1;
    if (!(radius > 0.0f))
        return scene_error(&p->diag, lex->path, d->line, "%s: radius must be positive", params->owner);
    if (!is_affine(p->state.ctm))
        return scene_error(&p->diag, lex->path, d->line, "%s: a projective transform is not supported", params->owner);
    double scale;
    if (!is_similarity(p->state.ctm, &scale)) {
        if (scene_unsupported(&p->diag, lex->path, d->line,
                              "the radius is scaled by the cube root of the volume change",
                              "%s: a non-uniform scale (or shear) would make an ellipsoid", params->owner))
            return -1;
        scale = cbrt(fabs(det3(p->state.ctm)));
    }
    Scene *s = p->scene;
    SceneSphere sphere;
    const float origin[3] = {0.0f, 0.0f, 0.0f};
    transform_point(p->state.ctm, origin, sphere.center);
    sphere.radius = (float)(radius * scale);
    if (!isfinite(sphere.center[0]) || !isfinite(sphere.center[1]) || !isfinite(sphere.center[2]) ||
        !(sphere.radius > 0.0f) || !isfinite(sphere.radius))
        return scene_error(&p->diag, lex->path, d->line, "%s: the transformed sphere is degenerate or not finite",
                           params->owner);
    const float reach[3] = {fabsf(sphere.center[0]) + sphere.radius, fabsf(sphere.center[1]) + sphere.radius,
                            fabsf(sphere.center[2]) + sphere.radius};
    if (!within_range(reach))
        return scene_error(&p->diag, lex->path, d->line,
                           "%s: the sphere (centre (%g, %g, %g), radius %g in world space) reaches beyond %g from "
                           "the origin (the renderer squares distances in single precision)",
                           params->owner, (double)sphere.center[0], (double)sphere.center[1], (double)sphere.center[2],
                           (double)sphere.radius, SCENE_MAX_COORDINATE);
    if (scene_reserve((void **)&s->spheres, &p->sphere_capacity, s->sphere_count + 1, sizeof *s->spheres))
        return out_of_memory(p, lex->path, d->line);
    sphere.shape = (uint32_t)s->shape_count;
    s->spheres[s->sphere_count] = sphere;
    /* pbrt keeps a sphere's outward normal under mirroring transforms. */
    if (add_shape(p, SCENE_SHAPE_SPHERE, p->state.reverse_orientation, s->sphere_count, 1))
        return out_of_memory(p, lex->path, d->line);
    s->sphere_count++;
    return 0;
}

static int shape_triangle_mesh(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    const Param *P = NULL, *indices = NULL, *N = NULL, *uv = NULL;
    if (params_get_array(params, "P", PARAM_POINT3, &P) < 0 ||
        params_get_array(params, "indices", PARAM_INTEGER, &indices) < 0 ||
        params_get_array(params, "N", PARAM_NORMAL3, &N) < 0)
        return -1;
    size_t vertex_count = P ? P->count / 3 : 0;
    if (shape_read_uv(params, vertex_count, &uv) < 0 || params_check_unused(params))
        return -1;
    if (!P)
        return scene_error(&p->diag, lex->path, d->line, "%s: missing \"point3 P\"", params->owner);
    if (!indices && vertex_count != 3)
        return scene_error(&p->diag, lex->path, d->line,
                           "%s: missing \"integer indices\" (needed unless P holds "
                           "exactly one triangle)",
                           params->owner);
    if (N && N->count != P->count)
        return params_error(params, N, "%zu normals for %zu vertices", N->count / 3, vertex_count);
    size_t index_count = indices ? indices->count : 3;
    float *positions = malloc(3 * vertex_count * sizeof *positions + 1);
    float *normals = N ? malloc(3 * vertex_count * sizeof *normals + 1) : NULL;
    float *uvs = uv ? malloc(2 * vertex_count * sizeof *uvs + 1) : NULL;
    uint32_t *index = malloc(index_count * sizeof *index + 1);
    int result = 0;
    if (!positions || !index || (N && !normals) || (uv && !uvs))
        result = out_of_memory(p, lex->path, d->line);
    for (size_t i = 0; result == 0 && i < 3 * vertex_count; ++i) {
        positions[i] = (float)P->numbers[i];
        if (normals)
            normals[i] = (float)N->numbers[i];
    }
    for (size_t i = 0; result == 0 && uvs && i < 2 * vertex_count; ++i)
        uvs[i] = (float)uv->numbers[i];
    if (result == 0 && indices)
        result = shape_read_indices(params, indices, vertex_count, 3, index);
    for (uint32_t i = 0; result == 0 && !indices && i < 3; ++i)
        index[i] = i;
    if (result == 0)
        result = add_mesh(p, lex->path, d->line, params->owner, positions, vertex_count, index, index_count, normals,
                          uvs, NULL, 0);
    free(positions);
    free(normals);
    free(uvs);
    free(index);
    return result;
}

/* Resolves a file named in `file` as pbrt-v4 does (ResolveFilename):
 * relative to the main file's directory. When nothing is there, gmonrt also
 * tries the directory of the file naming it (pbrt-v4 would try the working
 * directory); when that fails too, the path is pbrt-v4's, for messages. */
static char *resolve_path(Parser *p, const char *file, const char *name)
{
    return scene_resolve_path(file, p->main_path, name);
}

static int shape_ply_mesh(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    const char *filename = NULL;
    if (params_get_string(params, "filename", &filename) < 0 || params_check_unused(params))
        return -1;
    if (!filename)
        return scene_error(&p->diag, lex->path, d->line, "%s: missing \"string filename\"", params->owner);
    char *path = resolve_path(p, lex->path, filename);
    if (!path)
        return out_of_memory(p, lex->path, d->line);
    int missing = scene_missing_file(&p->diag, lex->path, d->line, path, params->owner);
    if (missing) {
        free(path);
        return missing < 0 ? -1 : 0; /* check mode: the shape is skipped */
    }
    PlyMesh mesh;
    char message[256], owner[1024]; /* messages name the PLY file, their vertex and face numbers its elements' */
    snprintf(owner, sizeof owner, "%s: \"%s\"", params->owner, path);
    int result = ply_read(path, &mesh, message, sizeof message);
    if (result)
        result = scene_error(&p->diag, lex->path, d->line, "%s: %s", owner, message);
    else
        result = add_mesh(p, lex->path, d->line, owner, mesh.positions, mesh.vertex_count, mesh.indices,
                          mesh.index_count, mesh.normals, mesh.uvs, mesh.parts, 0);
    shape_mesh_free(&mesh);
    free(path);
    return result;
}

/* A shape built as a triangle mesh (shapes.c), through the mesh path. */
static int shape_tessellated(Parser *p, Lexer *lex, const Token *d, ParamList *params, ShapeBuilder build)
{
    ShapeMesh mesh = {0};
    if (build(params, d->line, &mesh))
        return -1;
    int result = params_check_unused(params);
    if (result == 0)
        result = add_mesh(p, lex->path, d->line, params->owner, mesh.positions, mesh.vertex_count, mesh.indices,
                          mesh.index_count, mesh.normals, mesh.uvs, mesh.parts, mesh.one_part);
    shape_mesh_free(&mesh);
    return result;
}

/* A shape's "float alpha" (pbrt-v4's cut-out; default 1, opaque) or
 * "texture alpha" (a float texture, *texture its index; else -1). */
static int shape_alpha(Parser *p, ParamList *params, float *alpha, int *texture)
{
    for (size_t i = 0; i < params->count; ++i) {
        Param *param = &params->items[i];
        if (strcmp(param->name, "alpha") != 0)
            continue;
        if (param->type == PARAM_TEXTURE)
            return scene_texture_param_late(&p->diag, p->scene, &p->texture_capacity, params, "alpha", 0, texture) < 0
                       ? -1
                       : 0;
        if (params_get_float(params, "alpha", alpha) < 0)
            return -1;
        if (!isfinite(*alpha))
            return params_error(params, param, "must be finite");
    }
    return 0;
}

static int on_shape(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the shape type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    ShapeBuilder builder = NULL;
    if (result == 0) {
        char name[32];
        directive_name(&type, name, sizeof name);
        builder = shape_builder(name);
    }
    if (result == 0)
        result = warn_if_moving(p, lex, d);
    size_t shapes_before = p->scene->shape_count;
    float alpha = 1.0f;
    int alpha_texture = -1;
    if (result == 0)
        result = shape_alpha(p, &params, &alpha, &alpha_texture);
    if (result == 0 && p->object >= 0 && p->state.has_area_light)
        result = scene_warn(&p->diag, lex->path, d->line,
                            "%s: an area light inside ObjectBegin is ignored (the shape does not emit), as pbrt-v4 "
                            "ignores area lights in object instances",
                            params.owner);
    if (result == 0 && p->state.has_area_light && p->state.material >= 0 &&
        p->scene->materials[p->state.material].type == SCENE_MATERIAL_INTERFACE)
        result =
            scene_unsupported(&p->diag, lex->path, d->line, "it is left out, as every \"interface\" shape",
                              "%s: an area light on a shape of Material \"interface\" is not supported", params.owner);
    if (result == 0) {
        if (token_is(&type, "sphere"))
            result = shape_sphere(p, lex, d, &params);
        else if (token_is(&type, "trianglemesh"))
            result = shape_triangle_mesh(p, lex, d, &params);
        else if (token_is(&type, "plymesh"))
            result = shape_ply_mesh(p, lex, d, &params);
        else if (builder)
            result = shape_tessellated(p, lex, d, &params, builder);
        else
            result = scene_unsupported(&p->diag, lex->path, d->line, "skipped",
                                       "%s is not supported (sphere, trianglemesh, plymesh, disk, cylinder, "
                                       "bilinearmesh, loopsubdiv)",
                                       params.owner);
    }
    for (size_t i = shapes_before; result == 0 && i < p->scene->shape_count; ++i) {
        p->scene->shapes[i].alpha = alpha;
        p->scene->shapes[i].alpha_texture = alpha_texture;
    }
    params_free(&params);
    return result;
}

/* Skips parameters and values up to the next directive (a bare word that is
 * not a number or a bool), or to the end of the file. */
static int skip_to_next_directive(Lexer *lex)
{
    for (;;) {
        Token t;
        double number;
        if (lexer_peek(lex, &t))
            return -1;
        if (t.kind == TOKEN_END)
            return 0;
        int is_value =
            t.kind != TOKEN_WORD || token_number(&t, &number) == 0 || token_is(&t, "true") || token_is(&t, "false");
        if (!is_value)
            return 0; /* the next directive */
        lexer_next(lex, &t);
    }
}

static int on_include(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (expect_string(p, lex, d, "the file name", &name))
        return -1;
    char *relative = scene_strndup(name.text, name.length);
    char *path = relative ? resolve_path(p, lex->path, relative) : NULL;
    free(relative);
    if (!path)
        return out_of_memory(p, lex->path, d->line);
    char name_shown[32];
    directive_name(d, name_shown, sizeof name_shown);
    int result = scene_missing_file(&p->diag, lex->path, d->line, path, name_shown);
    if (result == 0)
        result = parse_file(p, path, lex->path, d->line);
    else if (result == 1)
        /* A directive begun in the missing file may go on after the Include
         * (as smoke-plume's density grid, whose sigma_a and sigma_s follow):
         * check skips those parameters rather than stopping at them. */
        result = skip_to_next_directive(lex);
    free(path);
    return result < 0 ? -1 : 0;
}

/* Texture "name" "float|spectrum" "class" params (host/scene/textures.c). */
static int on_texture(Parser *p, Lexer *lex, const Token *d)
{
    Token name, type, texture_class;
    ParamList params;
    if (expect_string(p, lex, d, "the texture's name", &name) || expect_string(p, lex, d, "the texture's type", &type))
        return -1;
    int result = read_typed_directive(p, lex, d, "the texture class", &texture_class, &params);
    char *name_text = NULL, *type_text = NULL, *class_text = NULL;
    if (result == 0) {
        name_text = scene_strndup(name.text, name.length);
        type_text = scene_strndup(type.text, type.length);
        class_text = scene_strndup(texture_class.text, texture_class.length);
    }
    if (result == 0 && (!name_text || !type_text || !class_text))
        result = out_of_memory(p, lex->path, d->line);
    if (result == 0) {
        snprintf(params.owner, sizeof params.owner, "Texture \"%.40s\"", name_text);
        result = scene_texture_parse(&p->diag, p->scene, &p->texture_capacity, name_text, type_text, class_text,
                                     &params, p->state.ctm, d->line);
    }
    free(name_text);
    free(type_text);
    free(class_text);
    params_free(&params);
    return result < 0 ? -1 : 0;
}

/* pbrt directives this reader does not implement. With allow_unsupported
 * they are skipped with their arguments (ObjectBegin/End/Instance have
 * handlers: they must skip the shapes in between). */
static const char *const unsupported_directives[] = {
    "MakeNamedMedium", "MediumInterface", "Option", "ColorSpace", "Attribute",
};

static int skip_directive(Parser *p, Lexer *lex, const Token *d)
{
    char name[32];
    directive_name(d, name, sizeof name);
    if (scene_unsupported(&p->diag, lex->path, d->line, "skipped", "%s is not supported", name))
        return -1;
    return skip_to_next_directive(lex);
}

static const struct {
    const char *name;
    Handler handler;
} directives[] = {
    {"LookAt", on_look_at},
    {"Translate", on_translate},
    {"Scale", on_scale},
    {"Rotate", on_rotate},
    {"Transform", on_transform},
    {"ConcatTransform", on_concat_transform},
    {"Identity", on_identity},
    {"CoordinateSystem", on_coordinate_system},
    {"CoordSysTransform", on_coord_sys_transform},
    {"ActiveTransform", on_active_transform},
    {"TransformTimes", on_transform_times},
    {"Texture", on_texture},
    {"ReverseOrientation", on_reverse_orientation},
    {"AttributeBegin", on_attribute_begin},
    {"AttributeEnd", on_attribute_end},
    {"TransformBegin", on_transform_begin},
    {"TransformEnd", on_transform_end},
    {"ObjectBegin", on_object_begin},
    {"ObjectEnd", on_object_end},
    {"ObjectInstance", on_object_instance},
    {"WorldBegin", on_world_begin},
    {"WorldEnd", on_world_end},
    {"Camera", on_camera},
    {"Film", on_film},
    {"Sampler", on_sampler},
    {"Integrator", on_integrator},
    {"Accelerator", on_accelerator},
    {"PixelFilter", on_pixel_filter},
    {"Material", on_material},
    {"MakeNamedMaterial", on_make_named_material},
    {"NamedMaterial", on_named_material},
    {"AreaLightSource", on_area_light_source},
    {"LightSource", on_light_source},
    {"Shape", on_shape},
    {"Include", on_include},
    {"Import", on_include},
};

static int parse_directives(Parser *p, Lexer *lex)
{
    for (;;) {
        Token t;
        if (lexer_next(lex, &t))
            return -1;
        if (t.kind == TOKEN_END)
            return 0;
        char shown[64];
        token_describe(&t, shown, sizeof shown);
        if (t.kind != TOKEN_WORD)
            return scene_error(&p->diag, lex->path, t.line, "expected a directive, got %s", shown);
        Handler handler = NULL;
        for (size_t i = 0; !handler && i < sizeof directives / sizeof directives[0]; ++i)
            if (token_is(&t, directives[i].name))
                handler = directives[i].handler;
        for (size_t i = 0; !handler && i < sizeof unsupported_directives / sizeof unsupported_directives[0]; ++i)
            if (token_is(&t, unsupported_directives[i]))
                handler = skip_directive;
        if (!handler)
            return scene_error(&p->diag, lex->path, t.line, "unknown directive %s", shown);
        if (handler(p, lex, &t))
            return -1;
    }
}

static const char *keep_path(Parser *p, const char *path)
{
    char *copy = scene_strndup(path, strlen(path));
    if (!copy || scene_reserve((void **)&p->paths, &p->path_capacity, p->path_count + 1, sizeof *p->paths)) {
        free(copy);
        return NULL;
    }
    p->paths[p->path_count++] = copy;
    return copy;
}

static int parse_file(Parser *p, const char *path, const char *from_file, int from_line)
{
    if (p->include_depth >= MAX_INCLUDE_DEPTH)
        return scene_error(&p->diag, from_file, from_line, "Include: files nested more than %d deep (a cycle?)",
                           MAX_INCLUDE_DEPTH);
    char *data = NULL, why[128];
    size_t size = 0;
    if (scene_read_file(path, SCENE_MAX_TEXT_BYTES, &data, &size, why, sizeof why))
        return from_file ? scene_error(&p->diag, from_file, from_line, "cannot read \"%s\": %s", path, why)
                         : scene_error(&p->diag, path, 0, "cannot read: %s", why);
    const char *kept = keep_path(p, path);
    if (!kept) {
        free(data);
        return out_of_memory(p, from_file ? from_file : path, from_line);
    }
    if (!p->main_path)
        p->main_path = kept;
    Lexer lex;
    lexer_init(&lex, kept, data, size, &p->diag);
    p->include_depth++;
    int result = parse_directives(p, &lex);
    p->include_depth--;
    if (result == 0 && p->include_depth == 0) {
        /* The end of the main file: everything opened must be closed. */
        if (p->depth > 0)
            result =
                scene_error(&p->diag, p->stack[p->depth - 1].file, p->stack[p->depth - 1].line,
                            "%s without a matching end (end of file reached)", push_name(p->stack[p->depth - 1].kind));
        else if (!p->in_world)
            result = scene_error(&p->diag, kept, lex.line, "end of file before WorldBegin (truncated file?)");
    }
    lexer_destroy(&lex);
    return result;
}

/* Turns the camera transform and film size into the camera's basis. */
static int finish_camera(Parser *p)
{
    Scene *s = p->scene;
    SceneCamera *camera = &s->camera;
    int affine = is_affine(p->camera_from_world);
    memcpy(camera->world_from_camera, p->world_from_camera, sizeof camera->world_from_camera);
    const float origin[3] = {0, 0, 0};
    transform_point(p->world_from_camera, origin, camera->position);
    float *axes[3] = {camera->right, camera->up, camera->forward};
    for (int a = 0; a < 3; ++a) { /* in double: squaring a 1e20 column overflows a float */
        double v[3] = {p->world_from_camera[a][0], p->world_from_camera[a][1], p->world_from_camera[a][2]};
        normalize_d(v);
        for (int k = 0; k < 3; ++k)
            axes[a][k] = (float)v[k];
    }
    double scale;
    const char *file = p->camera_file ? p->camera_file : p->main_path;
    int similarity = is_similarity(p->world_from_camera, &scale);
    if (!affine || !similarity) {
        if (scene_warn(&p->diag, file, p->camera_line,
                       "Camera: the camera transform is not a rotation with a uniform scale; its axes are "
                       "normalized"))
            return -1;
    }
    scene_camera_tan_half_fov(camera->fov, s->width, s->height, camera->tan_half_fov);
    /* pbrt keeps the camera transform's scale: camera-space lengths (the
     * lens, an orthographic window) scale with it. */
    double lens_radius = camera->lens_radius * scale, focal_distance = camera->focal_distance * scale;
    if (lens_radius > 0.0 && !(lens_radius <= FLT_MAX && focal_distance <= FLT_MAX && focal_distance >= FLT_MIN))
        return scene_error(&p->diag, file, p->camera_line,
                           "Camera: lensradius or focaldistance times the camera transform's scale %g is out of "
                           "single precision's range",
                           scale);
    camera->scale = (float)fmin(scale, FLT_MAX);
    camera->lens_radius = (float)lens_radius;
    camera->focal_distance = (float)fmin(focal_distance, FLT_MAX); /* unused without a lens */
    return 0;
}

/* Warns when the geometry lies far from the origin for its size, where
 * single precision (and the renderer's ray offsets, which grow with the
 * distance from the origin) are too coarse for it. */
static int check_precision(Parser *p)
{
    const Scene *s = p->scene;
    float lower[3] = {INFINITY, INFINITY, INFINITY}, upper[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < s->triangle_count; ++i)
        for (int corner = 0; corner < 3; ++corner)
            for (int k = 0; k < 3; ++k) {
                float x = s->positions[3 * (size_t)s->triangles[i].vertex[corner] + (size_t)k];
                lower[k] = fminf(lower[k], x);
                upper[k] = fmaxf(upper[k], x);
            }
    for (size_t i = 0; i < s->sphere_count; ++i)
        for (int k = 0; k < 3; ++k) {
            lower[k] = fminf(lower[k], s->spheres[i].center[k] - s->spheres[i].radius);
            upper[k] = fmaxf(upper[k], s->spheres[i].center[k] + s->spheres[i].radius);
        }
    double size = 0.0, distance = 0.0;
    for (int k = 0; k < 3; ++k) {
        size = fmax(size, (double)upper[k] - lower[k]);
        distance = fmax(distance, fmax(fabs(lower[k]), fabs(upper[k])));
    }
    if (s->triangle_count + s->sphere_count == 0 || distance <= PRECISION_RATIO * size)
        return 0;
    return scene_warn(&p->diag, p->main_path, 0,
                      "the geometry lies up to %g from the origin but spans only %g: single precision is coarse "
                      "there, and rays leaving a surface are offset by 1e-5 of their distance from the origin (up to "
                      "%g, over 1%% of the scene's size), so shadows and surfaces may be wrong; move the scene nearer "
                      "the origin",
                      distance, size, 1e-5 * distance);
}

int scene_load(const char *path, const SceneLoadOptions *options, Scene *scene, char *error, size_t error_size)
{
    memset(scene, 0, sizeof *scene);
    if (error && error_size > 0)
        error[0] = '\0';
    Parser p;
    memset(&p, 0, sizeof p);
    p.scene = scene;
    p.diag.error = error;
    p.diag.error_size = error_size;
    p.diag.allow_unsupported = options ? options->allow_unsupported : 0;
    p.diag.check = options ? options->check : 0;
    p.diag.scene = scene;
    p.default_material = -1;
    p.object = -1;
    p.state.material = -1;
    glm_mat4_identity(p.state.ctm);
    glm_mat4_identity(p.state.ctm_end);
    p.state.active_transforms = ACTIVE_ALL;
    glm_mat4_identity(p.camera_from_world);
    glm_mat4_identity(p.world_from_camera);

    /* pbrt-v4's defaults for what the file does not say. */
    scene->width = 1280;
    scene->crop_window[1] = scene->crop_window[3] = 1.0f;
    scene->height = 720;
    scene->spp = 16;
    scene->max_depth = 5;
    scene->rr_threshold = 1.0f;
    scene->camera.fov = 90.0f;
    scene->camera.focal_distance = 1e6f;
    scene->filter = default_filter(DEFAULT_FILTER);
    scene->film_filename = scene_strndup("pbrt.exr", 8);
    scene->max_component_value = INFINITY;
    scene->save_fp16 = 1;
    scene->film_diagonal = 35.0f;
    p.film_iso = 100.0f;
    p.film_scale = 1.0f;
    strcpy(p.film_sensor, "cie1931");
    p.shutter_close = 1.0f;
    scene->sampler = scene_strndup("zsobol", 6);
    scene->light_sampler = scene_strndup("bvh", 3);
    int result = scene->film_filename && scene->sampler && scene->light_sampler
                     ? 0
                     : scene_error(&p.diag, path, 0, "out of memory");

    if (result == 0)
        result = parse_file(&p, path, NULL, 0);
    if (result == 0)
        result = finish_camera(&p);
    if (result == 0)
        result = finish_film(&p);
    if (result == 0)
        result = check_precision(&p);
    if (result == 0)
        result = finish_instances(&p);
    if (result == 0)
        result = finish_named_materials(&p);
    if (result == 0)
        result = scene_texture_finish(&p.diag, scene, files_missing(&p));

    for (size_t i = 0; i < p.named_count; ++i)
        free(p.named[i].name);
    free(p.named);
    for (size_t i = 0; i < p.coordinate_system_count; ++i)
        free(p.coordinate_systems[i].name);
    free(p.coordinate_systems);
    free(p.stack);
    for (size_t i = 0; i < scene->instance_count && p.pending; ++i)
        free(p.pending[i].name);
    free(p.pending);
    for (size_t i = 0; i < p.path_count; ++i)
        free(p.paths[i]);
    free(p.paths);
    if (result) {
        /* Check mode reports what it found before the error as well. */
        Scene kept;
        memset(&kept, 0, sizeof kept);
        if (p.diag.check) {
            kept.warnings = scene->warnings;
            kept.warning_count = scene->warning_count;
            kept.notes = scene->notes;
            kept.note_count = scene->note_count;
            kept.diagnostics = scene->diagnostics;
            kept.diagnostic_count = scene->diagnostic_count;
            scene->warnings = scene->notes = NULL;
            scene->diagnostics = NULL;
            scene->warning_count = scene->note_count = scene->diagnostic_count = 0;
        }
        scene_destroy(scene);
        *scene = kept;
    }
    return result;
}
