/* Shared by the scene reader's directive handlers: the Parser (the scene
 * being built and the graphics state), the handlers' signature, and the
 * helpers in directives.c. parser.c reads the tokens, keeps the graphics
 * state and calls a handler per directive; the handlers of each family of
 * scene objects are in their own file (README.md here has the map). Not
 * part of the public API. */
#ifndef HOST_SCENE_DIRECTIVES_H
#define HOST_SCENE_DIRECTIVES_H

#include "scene/lexer.h"
#include "scene/params.h"
#include "scene/scene_internal.h"

#include <cglm/cglm.h>

#include <stddef.h>

/* What saved a graphics state on the stack, for the End that restores it. */
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
    int medium_inside, medium_outside; /* MediumInterface: indices into Scene.media, or -1 (vacuum) */
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

/* The reader's state while it reads one scene: the Scene being built, the
 * graphics state and its stack, what is bound once the whole scene is read
 * (named materials, instances), and the camera and film settings that
 * finish_camera and finish_film combine at the end. */
typedef struct Parser {
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
    /* Per Scene.media entry: whether MakeNamedMedium defined it, and where
     * it was first named (pbrt-v4 binds medium names at the end too). */
    struct MediumName {
        int defined;
        const char *file;
        int line;
    } * medium_names;
    size_t medium_capacity, medium_name_capacity;
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

/* A directive's handler, called with the directive's name read: reads its
 * arguments, then changes the graphics state or adds to the scene. Returns
 * 0, or -1 with the error in p->diag. */
typedef int (*Handler)(Parser *p, Lexer *lex, const Token *directive);

/* The directive's name (a word token) as a C string, for messages. */
void directive_name(const Token *t, char *out, size_t size);

/* Reads the directive's next argument, which must be a quoted string
 * (`what` names it in the error). Returns 0 or -1. */
int expect_string(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *out);

/* "file:line: out of memory". Returns -1. */
int out_of_memory(Parser *p, const char *file, int line);

/* An error unless the directive comes after WorldBegin (inside 1) or
 * before it (inside 0). Returns 0 or -1. */
int require_world(Parser *p, Lexer *lex, const Token *directive, int inside);

/* Reads a directive's type string and parameter list (free it either way);
 * its owner, for messages, is e.g. Shape "sphere". Returns 0 or -1. */
int read_typed_directive(Parser *p, Lexer *lex, const Token *directive, const char *what, Token *type,
                         ParamList *params);

/* Before a shape, light, camera or instance takes the CTM: one warning for
 * the scene when its start and end transforms differ (motion is not
 * rendered). Returns 0 or -1. */
int warn_if_moving(Parser *p, Lexer *lex, const Token *d);

/* The named coordinate system, or NULL. */
NamedTransform *find_coordinate_system(Parser *p, const char *name, size_t length);

/* Names (or renames) a coordinate system. Returns 0, or -1 when out of
 * memory. */
int define_coordinate_system(Parser *p, const char *name, size_t length, mat4 start, mat4 end);

/* Replaces *target by a copy of value. Returns 0 or -1. */
int replace_string(Parser *p, const char *file, int line, char **target, const char *value);

/* A file named in `file`, resolved as pbrt-v4 does (scene_resolve_path);
 * NULL when out of memory. */
char *resolve_path(Parser *p, const char *file, const char *name);

/* Whether check mode found files missing: a name the scene never defines
 * (a material, a texture) may then be defined in one of them. */
int files_missing(const Parser *p);

#endif
