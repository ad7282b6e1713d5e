/* The Texture directive and texture-valued parameters (SceneTexture). */
#ifndef HOST_SCENE_TEXTURES_H
#define HOST_SCENE_TEXTURES_H

#include "scene/params.h"
#include "scene/scene_internal.h"

/* The scene reader's parser state (directives.h). */
typedef struct Parser Parser;

/* The most textures one texture may reach through its inputs, itself
 * included (the kernels' TEXTURE_MAX_PROGRAM). */
#define SCENE_TEXTURE_MAX_NODES 16

/* Texture "name" "float|spectrum" "class" params, at `line` of params->file,
 * with the CTM world_from_texture (column-major, [column][row]). Adds it
 * to scene->textures (*capacity of them). Returns 0 or -1. */
int scene_texture_parse(Diagnostics *diag, Scene *scene, size_t *capacity, const char *name, const char *type,
                        const char *texture_class, ParamList *params, float world_from_texture[4][4], int line);

/* A material's or a shape's parameter that may name a texture ("texture
 * name" "tex"): when it does, *texture is its index (a float or, with
 * is_spectrum, a spectrum texture) and the parameter is consumed. pbrt-v4
 * binds these once the whole scene is read, so a name no Texture has
 * defined yet gets a placeholder (SceneTexture.placeholder) that its
 * Texture directive fills in later. Returns 1 taken, 0 not a texture
 * (read the constant), -1 error. */
int scene_texture_param_late(Diagnostics *diag, Scene *scene, size_t *capacity, ParamList *params, const char *name,
                             int is_spectrum, int *texture);

/* Once the whole scene is read: a placeholder no Texture filled in is an
 * error at its first use (in check mode with files missing, where the
 * Texture may be in one of them, it stays a constant). Returns 0 or -1. */
int scene_texture_finish(Diagnostics *diag, Scene *scene, int files_missing);

/* A material's "string normalmap": an image texture of tangent-space
 * normals added to the scene, *texture its index; 0 when absent, -1 error. */
int scene_texture_normal_map(Diagnostics *diag, Scene *scene, size_t *capacity, ParamList *params, int line,
                             int *texture);

/* The Texture directive's handler, for parser.c's table. */
int on_texture(Parser *p, Lexer *lex, const Token *d);

#endif
