/* What the directive handlers share: reading a directive's arguments,
 * where a directive may come, named coordinate systems and paths. */
#include "scene/directives.h"

#include "scene/geometry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void directive_name(const Token *t, char *out, size_t size)
{
    size_t n = t->length < size - 1 ? t->length : size - 1;
    memcpy(out, t->text, n);
    out[n] = '\0';
}

int expect_string(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *out)
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

int out_of_memory(Parser *p, const char *file, int line)
{
    return scene_error(&p->diag, file, line, "out of memory");
}

int require_world(Parser *p, Lexer *lex, const Token *directive, int inside)
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
int read_typed_directive(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *type,
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

/* Before a shape, light or camera takes the CTM: when its start and end
 * transforms differ it moves, which gmonrt does not render. It renders the
 * start time, with one warning for the whole scene. */
int warn_if_moving(Parser *p, Lexer *lex, const Token *d)
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

/* The named coordinate system, or NULL. */
NamedTransform *find_coordinate_system(Parser *p, const char *name, size_t length)
{
    for (size_t i = 0; i < p->coordinate_system_count; ++i)
        if (strlen(p->coordinate_systems[i].name) == length && memcmp(p->coordinate_systems[i].name, name, length) == 0)
            return &p->coordinate_systems[i];
    return NULL;
}

/* Names (or renames) a coordinate system: CoordinateSystem, and pbrt-v4's
 * "camera" at Camera and "world" at WorldBegin. */
int define_coordinate_system(Parser *p, const char *name, size_t length, mat4 start, mat4 end)
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

int replace_string(Parser *p, const char *file, int line, char **target, const char *value)
{
    char *copy = scene_strndup(value, strlen(value));
    if (!copy)
        return out_of_memory(p, file, line);
    free(*target);
    *target = copy;
    return 0;
}

/* Resolves a file named in `file` as pbrt-v4 does (ResolveFilename):
 * relative to the main file's directory. When nothing is there, gmonrt also
 * tries the directory of the file naming it (pbrt-v4 would try the working
 * directory); when that fails too, the path is pbrt-v4's, for messages. */
char *resolve_path(Parser *p, const char *file, const char *name)
{
    return scene_resolve_path(file, p->main_path, name);
}

/* Whether check mode found files missing: a name the scene never defines
 * (a material, a texture) may then be defined in one of them. */
int files_missing(const Parser *p)
{
    const Scene *s = p->scene;
    if (p->diag.check)
        for (size_t i = 0; i < s->diagnostic_count; ++i)
            if (s->diagnostics[i].kind == SCENE_DIAGNOSTIC_MISSING_FILE)
                return 1;
    return 0;
}
