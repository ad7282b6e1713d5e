/* The Shape directive: spheres, triangle meshes, PLY meshes and the shapes
 * tessellate.c makes into triangle meshes, taken to world space under the
 * graphics state (transform, material, area light, orientation). */
#include "scene/shapes.h"

#include "scene/geometry.h"
#include "scene/materials.h"
#include "scene/ply.h"
#include "scene/tessellate.h"
#include "scene/textures.h"

#include <cglm/cglm.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Geometry lying farther from the origin than this many times its size
 * gets a warning: the renderer offsets rays leaving a surface by 1e-5 times
 * their distance from the origin, which is then over 1% of the scene's size. */
#define PRECISION_RATIO 1e3

/* A triangle's edges from its first vertex, in double. */
static void edges(const float *positions, const uint32_t *triangle, double e1[3], double e2[3])
{
    const float *a = positions + 3 * triangle[0], *b = positions + 3 * triangle[1], *c = positions + 3 * triangle[2];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
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
    shape->medium_inside = p->state.medium_inside;
    shape->medium_outside = p->state.medium_outside;
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

static int shape_sphere(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    float radius = 1.0f;
    if (params_get_float(params, "radius", &radius) < 0 || params_check_unused(params))
        return -1;
    if (!(radius > 0.0f))
        return scene_error(&p->diag, lex->path, d->line, "%s: radius must be positive", params->owner);
    if (!is_affine(p->state.ctm))
        return scene_error(&p->diag, lex->path, d->line, "%s: a projective transform is not supported", params->owner);
    if (det3(p->state.ctm) == 0.0)
        return scene_error(&p->diag, lex->path, d->line, "%s: the transform is singular (it flattens the sphere)",
                           params->owner);
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

/* A shape built as a triangle mesh (tessellate.c), through the mesh path. */
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

int on_shape(Parser *p, Lexer *lex, const Token *d)
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

/* Warns when the geometry lies far from the origin for its size, where
 * single precision (and the renderer's ray offsets, which grow with the
 * distance from the origin) are too coarse for it. */
int check_precision(Parser *p)
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
