/* The pbrt-v4 scene format's syntax and graphics state: reads each file's
 * directives (and the files they Include), keeps the transforms and the
 * graphics-state stack (AttributeBegin/End, TransformBegin/End,
 * ObjectBegin/End), and hands each directive that makes part of the scene
 * to its family's handler (directives.h; README.md here has the map). Once
 * the whole scene is read, it finishes the Scene. */
#include "scene/camera.h"
#include "scene/directives.h"
#include "scene/geometry.h"
#include "scene/instance_check.h"
#include "scene/lights.h"
#include "scene/materials.h"
#include "scene/media.h"
#include "scene/read_file.h"
#include "scene/shapes.h"
#include "scene/textures.h"

#include <cglm/cglm.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_INCLUDE_DEPTH 32

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

static int parse_file(Parser *p, const char *path, const char *from_file, int from_line);

/* --------------------------------------------------------------- transforms */

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

/* ------------------------------------------------- the graphics-state stack */

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

/* ---------------------------------------------------- objects and instances */

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

/* ---------------------------------------------------------------- the world */

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

/* -------------------------------------------- files and the directive table */

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

/* pbrt directives this reader does not implement. With allow_unsupported
 * they are skipped with their arguments (ObjectBegin/End/Instance have
 * handlers: they must skip the shapes in between). */
static const char *const unsupported_directives[] = {
    "Option",
    "ColorSpace",
    "Attribute",
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
    {"MakeNamedMedium", on_make_named_medium},
    {"MediumInterface", on_medium_interface},
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

/* --------------------------------------------------------------- scene_load */

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
    p.state.medium_inside = p.state.medium_outside = -1;
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
    scene->integrator_media = 1; /* pbrt-v4's default integrator is volpath */
    scene->camera_medium = -1;
    scene->camera.fov = 90.0f;
    scene->camera.focal_distance = 1e6f;
    scene->filter = default_pixel_filter();
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
        result = finish_media(&p);
    if (result == 0)
        result = scene_texture_finish(&p.diag, scene, files_missing(&p));

    for (size_t i = 0; i < p.named_count; ++i)
        free(p.named[i].name);
    free(p.named);
    free(p.medium_names);
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
