/* pbrt-v4's Texture directive: its classes' parameters and defaults, the
 * 2D mappings, and texture-valued parameters of materials and textures.
 * Images are read by the renderer's conversion (host/render). */
#include "scene/textures.h"

#include "scene/directives.h"

#include "scene/spectrum.h"

#include <cglm/cglm.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The latest texture of that name and kind, or -1; a placeholder
 * (scene_texture_param_late) counts only with `placeholders`. */
static int find_texture_or_placeholder(const Scene *scene, const char *name, int is_spectrum, int placeholders)
{
    for (size_t i = scene->texture_count; i-- > 0;)
        if (scene->textures[i].is_spectrum == is_spectrum && strcmp(scene->textures[i].name, name) == 0 &&
            (placeholders || !scene->textures[i].placeholder))
            return (int)i;
    return -1;
}

/* The latest Texture directive of that name and kind, or -1. */
static int find_texture(const Scene *scene, const char *name, int is_spectrum)
{
    return find_texture_or_placeholder(scene, name, is_spectrum, 0);
}

static int add_texture(Scene *scene, size_t *capacity, SceneTexture *t);
static void free_texture(SceneTexture *t);

/* The nodes a texture's program has: itself and its inputs' (repeated). */
static int program_nodes(const Scene *scene, int texture)
{
    int nodes = 1;
    for (int i = 0; i < 3; ++i)
        if (scene->textures[texture].input[i].texture >= 0)
            nodes += program_nodes(scene, scene->textures[texture].input[i].texture);
    return nodes;
}

/* The error for a parameter of `owner` naming no texture of its kind. */
static int undefined_texture(Diagnostics *diag, const Scene *scene, const char *file, int line, const char *owner,
                             const char *parameter, const char *texture_name, int is_spectrum)
{
    const char *kind = is_spectrum ? "spectrum" : "float";
    if (find_texture(scene, texture_name, !is_spectrum) >= 0)
        return scene_error(diag, file, line,
                           "%s: parameter \"texture %s\": \"%s\" is a %s texture, \"%s\" takes a %s texture", owner,
                           parameter, texture_name, is_spectrum ? "float" : "spectrum", parameter, kind);
    return scene_error(diag, file, line, "%s: parameter \"texture %s\": no %s texture named \"%s\"", owner, parameter,
                       kind, texture_name);
}

/* The texture parameter `name`, consumed: 1 with its texture's name and
 * its line, 0 when it is not a texture, -1 on error. */
static int take_texture_name(ParamList *params, const char *name, const char **texture_name, int *line)
{
    *line = 0;
    for (size_t i = 0; i < params->count; ++i)
        if (params->items[i].name && strcmp(params->items[i].name, name) == 0)
            *line = params->items[i].line;
    *texture_name = NULL;
    return params_take_texture(params, name, texture_name);
}

/* A texture's input naming a texture: bound as read, as pbrt-v4 creates
 * textures in order. Returns 1 taken, 0 not a texture, -1 error. */
static int texture_input_param(Diagnostics *diag, const Scene *scene, ParamList *params, const char *name,
                               int is_spectrum, int *texture)
{
    const char *texture_name;
    int line, taken = take_texture_name(params, name, &texture_name, &line);
    if (taken <= 0)
        return taken;
    *texture = find_texture(scene, texture_name, is_spectrum);
    if (*texture >= 0)
        return 1;
    return undefined_texture(diag, scene, params->file, line, params->owner, name, texture_name, is_spectrum);
}

int scene_texture_param_late(Diagnostics *diag, Scene *scene, size_t *capacity, ParamList *params, const char *name,
                             int is_spectrum, int *texture)
{
    const char *texture_name;
    int line, taken = take_texture_name(params, name, &texture_name, &line);
    if (taken <= 0)
        return taken;
    *texture = find_texture_or_placeholder(scene, texture_name, is_spectrum, 1);
    if (*texture >= 0)
        return 1;
    SceneTexture t;
    memset(&t, 0, sizeof t);
    for (int i = 0; i < 3; ++i)
        t.input[i].texture = -1;
    t.is_spectrum = is_spectrum;
    t.texture_class = SCENE_TEXTURE_CONSTANT; /* 0.5, should check mode leave it unfilled */
    t.input[0].value[0] = t.input[0].value[1] = t.input[0].value[2] = 0.5f;
    t.placeholder = 1;
    t.use_file = params->file;
    t.use_line = line;
    t.name = scene_strndup(texture_name, strlen(texture_name));
    t.origin = scene_strndup(params->owner, strlen(params->owner));
    t.use_parameter = scene_strndup(name, strlen(name));
    if (!t.name || !t.origin || !t.use_parameter || add_texture(scene, capacity, &t)) {
        free_texture(&t);
        return scene_error(diag, params->file, line, "out of memory");
    }
    *texture = (int)scene->texture_count - 1;
    return 1;
}

int scene_texture_finish(Diagnostics *diag, Scene *scene, int files_missing)
{
    for (size_t i = 0; i < scene->texture_count; ++i) {
        SceneTexture *t = &scene->textures[i];
        if (!t->placeholder)
            continue;
        if (!files_missing)
            return undefined_texture(diag, scene, t->use_file, t->use_line, t->origin, t->use_parameter, t->name,
                                     t->is_spectrum);
        t->use_file = NULL; /* its file's name does not outlive the parse */
    }
    return 0;
}

/* An input of a texture: a texture, or a constant (float, or a spectrum
 * reduced to RGB), else `fallback`. Returns 0 or -1. */
static int read_input(Diagnostics *diag, const Scene *scene, ParamList *params, const char *name, int is_spectrum,
                      float fallback, SceneTextureInput *input)
{
    input->texture = -1;
    input->value[0] = input->value[1] = input->value[2] = fallback;
    int taken = texture_input_param(diag, scene, params, name, is_spectrum, &input->texture);
    if (taken != 0)
        return taken < 0 ? -1 : 0;
    if (!is_spectrum) {
        float v = fallback;
        if (params_get_float(params, name, &v) < 0)
            return -1;
        input->value[0] = input->value[1] = input->value[2] = v;
        return 0;
    }
    return params_get_spectrum(params, name, SPECTRUM_UNBOUNDED, input->value) < 0 ? -1 : 0;
}

/* pbrt-v4's TextureMapping2D parameters. Returns 0 or -1. */
static int read_mapping(Diagnostics *diag, ParamList *params, int line, mat4 texture_from_world, SceneTexture *t)
{
    const char *mapping = "uv";
    t->map_scale[0] = t->map_scale[1] = 1.0f;
    if (params_get_string(params, "mapping", &mapping) < 0 ||
        params_get_float(params, "uscale", &t->map_scale[0]) < 0 ||
        params_get_float(params, "vscale", &t->map_scale[1]) < 0 ||
        params_get_float(params, "udelta", &t->map_delta[0]) < 0 ||
        params_get_float(params, "vdelta", &t->map_delta[1]) < 0)
        return -1;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            t->texture_from_world[r][c] = texture_from_world[c][r];
    if (strcmp(mapping, "uv") == 0) {
        t->mapping = SCENE_MAPPING_UV;
    } else if (strcmp(mapping, "spherical") == 0) {
        t->mapping = SCENE_MAPPING_SPHERICAL;
    } else if (strcmp(mapping, "cylindrical") == 0) {
        t->mapping = SCENE_MAPPING_CYLINDRICAL;
    } else if (strcmp(mapping, "planar") == 0) {
        t->mapping = SCENE_MAPPING_PLANAR;
        float v[2][3] = {{1, 0, 0}, {0, 1, 0}};
        static const char *const names[2] = {"v1", "v2"};
        for (int i = 0; i < 2; ++i) {
            const Param *p = NULL;
            int found = params_get_array(params, names[i], PARAM_VECTOR3, &p);
            if (found < 0)
                return -1;
            if (found && p->count != 3)
                return params_error(params, p, "expected 3 values, got %zu", p->count);
            for (int k = 0; found && k < 3; ++k)
                v[i][k] = (float)p->numbers[k];
        }
        /* s = udelta + v1 . (texture_from_world p): fold v1 and v2 into the rows. */
        for (int i = 0; i < 2; ++i)
            for (int c = 0; c < 4; ++c)
                t->texture_from_world[i][c] = v[i][0] * texture_from_world[c][0] + v[i][1] * texture_from_world[c][1] +
                                              v[i][2] * texture_from_world[c][2];
    } else {
        return scene_error(diag, params->file, line,
                           "%s: unknown \"mapping\" \"%s\" (uv, spherical, cylindrical, planar)", params->owner,
                           mapping);
    }
    return 0;
}

/* imagemap's parameters. Returns 0 or -1. */
static int read_image(Diagnostics *diag, ParamList *params, int line, SceneTexture *t, int *skipped)
{
    const char *filename = NULL, *filter = "bilinear", *wrap = "repeat", *encoding = NULL;
    float anisotropy = 8.0f;
    t->scale = 1.0f;
    if (params_get_string(params, "filename", &filename) < 0 || params_get_string(params, "filter", &filter) < 0 ||
        params_get_string(params, "wrap", &wrap) < 0 || params_get_string(params, "encoding", &encoding) < 0 ||
        params_get_float(params, "scale", &t->scale) < 0 || params_get_bool(params, "invert", &t->invert) < 0 ||
        params_get_float(params, "maxanisotropy", &anisotropy) < 0)
        return -1;
    if (!filename || !*filename)
        return scene_error(diag, params->file, line, "%s: missing \"string filename\"", params->owner);
    t->filename = scene_resolve_path(params->file, params->main_file, filename);
    if (!t->filename)
        return scene_error(diag, params->file, line, "out of memory");
    int missing = scene_missing_file(diag, params->file, line, t->filename, params->owner);
    if (missing < 0)
        return -1;
    *skipped = missing;
    if (strcmp(filter, "point") == 0)
        t->filter = SCENE_TEXTURE_FILTER_POINT;
    else if (strcmp(filter, "bilinear") == 0)
        t->filter = SCENE_TEXTURE_FILTER_BILINEAR;
    else if (strcmp(filter, "trilinear") == 0 || strcasecmp(filter, "ewa") == 0)
        t->filter = SCENE_TEXTURE_FILTER_TRILINEAR; /* ewa: trilinear, isotropic */
    else
        return scene_error(diag, params->file, line, "%s: unknown \"filter\" \"%s\" (point, bilinear, trilinear, ewa)",
                           params->owner, filter);
    if (strcmp(wrap, "repeat") == 0)
        t->wrap = SCENE_WRAP_REPEAT;
    else if (strcmp(wrap, "black") == 0)
        t->wrap = SCENE_WRAP_BLACK;
    else if (strcmp(wrap, "clamp") == 0)
        t->wrap = SCENE_WRAP_CLAMP;
    else if (strcmp(wrap, "octahedralsphere") == 0)
        t->wrap = SCENE_WRAP_OCTAHEDRAL_SPHERE;
    else
        return scene_error(diag, params->file, line,
                           "%s: unknown \"wrap\" \"%s\" (repeat, black, clamp, octahedralsphere)", params->owner, wrap);
    /* pbrt-v4: 8-bit PNGs are sRGB unless said otherwise, other files linear. */
    size_t n = strlen(t->filename);
    if (!encoding)
        encoding = n > 4 && strcasecmp(t->filename + n - 4, ".png") == 0 ? "sRGB" : "linear";
    t->gamma = 1.0f;
    if (strcmp(encoding, "sRGB") == 0) {
        t->encoding = SCENE_ENCODING_SRGB;
    } else if (strcmp(encoding, "linear") == 0) {
        t->encoding = SCENE_ENCODING_LINEAR;
    } else if (strncmp(encoding, "gamma ", 6) == 0) {
        char *end = NULL;
        t->encoding = SCENE_ENCODING_GAMMA;
        t->gamma = strtof(encoding + 6, &end);
        if (!end || *end || !(t->gamma > 0.0f) || !isfinite(t->gamma))
            return scene_error(diag, params->file, line, "%s: \"encoding\" \"%s\": expected a positive gamma",
                               params->owner, encoding);
    } else {
        return scene_error(diag, params->file, line, "%s: unknown \"encoding\" \"%s\" (sRGB, linear, \"gamma g\")",
                           params->owner, encoding);
    }
    return 0;
}

static int add_texture(Scene *scene, size_t *capacity, SceneTexture *t)
{
    if (scene_reserve((void **)&scene->textures, capacity, scene->texture_count + 1, sizeof *scene->textures))
        return -1;
    scene->textures[scene->texture_count++] = *t;
    return 0;
}

static void free_texture(SceneTexture *t)
{
    free(t->name);
    free(t->filename);
    free(t->origin);
    free(t->use_parameter);
}

/* The texture's fields from its class's parameters. Returns 0 or -1. */
static int read_class(Diagnostics *diag, const Scene *scene, const char *texture_class, ParamList *params, int line,
                      mat4 texture_from_world, SceneTexture *t, int *skipped)
{
    int spectrum = t->is_spectrum;
    if (strcmp(texture_class, "constant") == 0) {
        t->texture_class = SCENE_TEXTURE_CONSTANT;
        return read_input(diag, scene, params, "value", spectrum, 1.0f, &t->input[0]);
    }
    if (strcmp(texture_class, "scale") == 0) {
        t->texture_class = SCENE_TEXTURE_SCALE;
        return read_input(diag, scene, params, "tex", spectrum, 1.0f, &t->input[0]) ||
               read_input(diag, scene, params, "scale", 0, 1.0f, &t->input[2]);
    }
    if (strcmp(texture_class, "mix") == 0 || strcmp(texture_class, "directionmix") == 0) {
        int direction = texture_class[0] == 'd';
        t->texture_class = direction ? SCENE_TEXTURE_DIRECTION_MIX : SCENE_TEXTURE_MIX;
        if (read_input(diag, scene, params, "tex1", spectrum, 0.0f, &t->input[0]) ||
            read_input(diag, scene, params, "tex2", spectrum, 1.0f, &t->input[1]))
            return -1;
        if (!direction)
            return read_input(diag, scene, params, "amount", 0, 0.5f, &t->input[2]);
        const Param *p = NULL;
        int found = params_get_array(params, "dir", PARAM_VECTOR3, &p);
        if (found < 0)
            return -1;
        if (found && p->count != 3)
            return params_error(params, p, "expected 3 values, got %zu", p->count);
        double d[3] = {0, 1, 0}, w[3], length = 0.0;
        for (int k = 0; found && k < 3; ++k)
            d[k] = p->numbers[k];
        mat4 world_from_texture;
        glm_mat4_inv(texture_from_world, world_from_texture);
        for (int k = 0; k < 3; ++k) {
            w[k] = world_from_texture[0][k] * d[0] + world_from_texture[1][k] * d[1] + world_from_texture[2][k] * d[2];
            length += w[k] * w[k];
        }
        if (!(length > 0.0) || !isfinite(length))
            return scene_error(diag, params->file, line, "%s: \"dir\" must be a non-zero vector", params->owner);
        for (int k = 0; k < 3; ++k)
            t->direction[k] = (float)(w[k] / sqrt(length));
        return 0;
    }
    if (strcmp(texture_class, "checkerboard") == 0) {
        t->texture_class = SCENE_TEXTURE_CHECKERBOARD;
        int dimension = 2;
        if (read_input(diag, scene, params, "tex1", spectrum, 1.0f, &t->input[0]) ||
            read_input(diag, scene, params, "tex2", spectrum, 0.0f, &t->input[1]) ||
            params_get_int(params, "dimension", &dimension) < 0)
            return -1;
        if (dimension != 2 && dimension != 3)
            return scene_error(diag, params->file, line, "%s: \"dimension\" must be 2 or 3, not %d", params->owner,
                               dimension);
        if (read_mapping(diag, params, line, texture_from_world, t))
            return -1;
        if (dimension == 3)
            t->mapping = SCENE_MAPPING_3D;
        return 0;
    }
    if (strcmp(texture_class, "bilerp") == 0) {
        t->texture_class = SCENE_TEXTURE_BILERP;
        static const char *const names[4] = {"v00", "v01", "v10", "v11"};
        for (int i = 0; i < 4; ++i) {
            SceneTextureInput v;
            if (read_input(diag, scene, params, names[i], spectrum, (float)(i & 1), &v))
                return -1;
            if (v.texture >= 0)
                return scene_error(diag, params->file, line, "%s: \"%s\" must be a constant", params->owner, names[i]);
            memcpy(t->bilerp[i], v.value, sizeof t->bilerp[i]);
        }
        return read_mapping(diag, params, line, texture_from_world, t);
    }
    if (strcmp(texture_class, "imagemap") == 0) {
        t->texture_class = SCENE_TEXTURE_IMAGE;
        return read_image(diag, params, line, t, skipped) || read_mapping(diag, params, line, texture_from_world, t);
    }
    if (strcmp(texture_class, "dots") == 0) {
        t->texture_class = SCENE_TEXTURE_DOTS;
        return read_input(diag, scene, params, "inside", spectrum, 1.0f, &t->input[0]) ||
               read_input(diag, scene, params, "outside", spectrum, 0.0f, &t->input[1]) ||
               read_mapping(diag, params, line, texture_from_world, t);
    }
    static const struct {
        const char *name;
        SceneTextureClass texture_class;
        int is_spectrum; /* pbrt-v4 has these of one type only */
    } noise[] = {{"fbm", SCENE_TEXTURE_FBM, 0},
                 {"wrinkled", SCENE_TEXTURE_WRINKLED, 0},
                 {"windy", SCENE_TEXTURE_WINDY, 0},
                 {"marble", SCENE_TEXTURE_MARBLE, 1}};
    for (size_t i = 0; i < sizeof noise / sizeof noise[0]; ++i) {
        if (strcmp(texture_class, noise[i].name) != 0)
            continue;
        if (spectrum != noise[i].is_spectrum)
            return scene_error(diag, params->file, line, "%s: \"%s\" is a %s texture in pbrt-v4, not a %s one",
                               params->owner, texture_class, noise[i].is_spectrum ? "spectrum" : "float",
                               spectrum ? "spectrum" : "float");
        t->texture_class = noise[i].texture_class;
        t->mapping = SCENE_MAPPING_3D;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c)
                t->texture_from_world[r][c] = texture_from_world[c][r];
        t->octaves = 8;
        t->omega = 0.5f;
        t->scale = 1.0f;
        t->variation = 0.2f;
        if (t->texture_class == SCENE_TEXTURE_WINDY)
            return 0;
        if (params_get_int(params, "octaves", &t->octaves) < 0 ||
            params_get_float(params, "roughness", &t->omega) < 0 ||
            (t->texture_class == SCENE_TEXTURE_MARBLE && (params_get_float(params, "scale", &t->scale) < 0 ||
                                                          params_get_float(params, "variation", &t->variation) < 0)))
            return -1;
        if (t->octaves < 0 || t->octaves > 64)
            return scene_error(diag, params->file, line, "%s: \"octaves\" %d: expected 0 to 64", params->owner,
                               t->octaves);
        if (!isfinite(t->omega) || !isfinite(t->scale) || !isfinite(t->variation))
            return scene_error(diag, params->file, line,
                               "%s: \"roughness\", \"scale\" and \"variation\" must be finite", params->owner);
        return 0;
    }
    /* ptex, ...: a constant stands in. */
    t->texture_class = SCENE_TEXTURE_CONSTANT;
    t->input[0].value[0] = t->input[0].value[1] = t->input[0].value[2] = 0.5f;
    if (scene_unsupported(diag, params->file, line, "a constant 0.5 is used instead",
                          "%s: texture class \"%s\" is not supported (constant, scale, mix, directionmix, "
                          "checkerboard, bilerp, imagemap, dots, fbm, wrinkled, windy, marble)",
                          params->owner, texture_class))
        return -1;
    for (size_t i = 0; i < params->count; ++i)
        params->items[i].used = 1;
    return 0;
}

int scene_texture_parse(Diagnostics *diag, Scene *scene, size_t *capacity, const char *name, const char *type,
                        const char *texture_class, ParamList *params, float world_from_texture[4][4], int line)
{
    SceneTexture t;
    memset(&t, 0, sizeof t);
    for (int i = 0; i < 3; ++i)
        t.input[i].texture = -1;
    if (strcmp(type, "spectrum") == 0 || strcmp(type, "color") == 0)
        t.is_spectrum = 1;
    else if (strcmp(type, "float") != 0)
        return scene_error(diag, params->file, line, "%s: texture type \"%s\" must be \"float\" or \"spectrum\"",
                           params->owner, type);
    mat4 texture_from_world;
    mat4 world; /* cglm's alignment */
    memcpy(world, world_from_texture, sizeof world);
    glm_mat4_inv(world, texture_from_world);
    char origin[1024];
    snprintf(origin, sizeof origin, "%s:%d", params->file, line);
    t.name = scene_strndup(name, strlen(name));
    t.origin = scene_strndup(origin, strlen(origin));
    if (!t.name || !t.origin) {
        free_texture(&t);
        return scene_error(diag, params->file, line, "out of memory");
    }
    int skipped = 0;
    if (read_class(diag, scene, texture_class, params, line, texture_from_world, &t, &skipped) ||
        params_check_unused(params)) {
        free_texture(&t);
        return -1;
    }
    if (skipped) { /* check mode: the image is missing; a constant stands in */
        t.texture_class = SCENE_TEXTURE_CONSTANT;
        t.input[0].value[0] = t.input[0].value[1] = t.input[0].value[2] = 0.5f;
    }
    if (find_texture(scene, name, t.is_spectrum) >= 0 &&
        scene_warn(diag, params->file, line, "%s: redefines the %s texture \"%s\"; later uses get this one",
                   params->owner, type, name)) {
        free_texture(&t);
        return -1;
    }
    int index = find_texture_or_placeholder(scene, name, t.is_spectrum, 1);
    if (index >= 0 && scene->textures[index].placeholder) { /* named by a material or shape before */
        free_texture(&scene->textures[index]);
        scene->textures[index] = t;
    } else if (add_texture(scene, capacity, &t)) {
        free_texture(&t);
        return scene_error(diag, params->file, line, "out of memory");
    } else {
        index = (int)scene->texture_count - 1;
    }
    if (program_nodes(scene, index) > SCENE_TEXTURE_MAX_NODES)
        return scene_error(diag, params->file, line, "%s: reaches more than %d textures through its inputs",
                           params->owner, SCENE_TEXTURE_MAX_NODES);
    return 0;
}

int scene_texture_normal_map(Diagnostics *diag, Scene *scene, size_t *capacity, ParamList *params, int line,
                             int *texture)
{
    const char *filename = NULL;
    int found = params_get_string(params, "normalmap", &filename);
    if (found <= 0)
        return found;
    SceneTexture t;
    memset(&t, 0, sizeof t);
    for (int i = 0; i < 3; ++i)
        t.input[i].texture = -1;
    char origin[1024];
    snprintf(origin, sizeof origin, "%s:%d", params->file, line);
    t.name = scene_strndup("", 0); /* no Texture name refers to it */
    t.origin = scene_strndup(origin, strlen(origin));
    t.filename = scene_resolve_path(params->file, params->main_file, filename);
    if (!t.name || !t.origin || !t.filename) {
        free_texture(&t);
        return scene_error(diag, params->file, line, "out of memory");
    }
    int missing = scene_missing_file(diag, params->file, line, t.filename, params->owner);
    if (missing) {
        free_texture(&t);
        return missing < 0 ? -1 : 0;
    }
    /* As pbrt-v4 reads a normal map: linear, bilinear, repeating, (u, v) as is. */
    t.is_spectrum = 1;
    t.texture_class = SCENE_TEXTURE_IMAGE;
    t.mapping = SCENE_MAPPING_UV;
    t.map_scale[0] = t.map_scale[1] = 1.0f;
    t.filter = SCENE_TEXTURE_FILTER_BILINEAR;
    t.wrap = SCENE_WRAP_REPEAT;
    t.encoding = SCENE_ENCODING_LINEAR;
    t.gamma = 1.0f;
    t.scale = 1.0f;
    t.single_level = 1;
    if (add_texture(scene, capacity, &t)) {
        free_texture(&t);
        return scene_error(diag, params->file, line, "out of memory");
    }
    *texture = (int)scene->texture_count - 1;
    return 1;
}

/* Texture "name" "float|spectrum" "class" params: copies the strings for
 * scene_texture_parse. */
int on_texture(Parser *p, Lexer *lex, const Token *d)
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
