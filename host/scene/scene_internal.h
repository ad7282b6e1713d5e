/* Shared by the scene reader's files: diagnostics and growing the Scene's
 * arrays. Not part of the public API. */
#ifndef HOST_SCENE_SCENE_INTERNAL_H
#define HOST_SCENE_SCENE_INTERNAL_H

#include "scene/scene.h"

#include <stdarg.h>
#include <stddef.h>

#if defined(__GNUC__)
#define SCENE_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define SCENE_PRINTF(fmt, args)
#endif

/* Where messages go: the error buffer, and the scene's warning list. */
typedef struct {
    char *error;
    size_t error_size;
    int allow_unsupported;
    int check; /* SceneLoadOptions.check: record diagnostics and go on */
    Scene *scene;
} Diagnostics;

/* Writes "file:line: message" (or "file: message" when line <= 0) to the
 * error buffer. Returns -1, for `return scene_error(...)`. */
int scene_error(Diagnostics *diag, const char *file, int line, const char *format, ...) SCENE_PRINTF(4, 5);

/* Appends "file:line: warning: message" to the scene's warnings, unless
 * the same line is there already (a file included twice). Returns 0, or -1
 * (with an error) when out of memory. */
int scene_warn(Diagnostics *diag, const char *file, int line, const char *format, ...) SCENE_PRINTF(4, 5);

/* Appends "file:line: note: message" to the scene's notes (once): what
 * gmonrt does differently from pbrt-v4 without changing the expected image. */
int scene_note(Diagnostics *diag, const char *file, int line, const char *format, ...) SCENE_PRINTF(4, 5);

/* An unsupported feature: an error; with allow_unsupported a warning that
 * ends "; <substitute>" (what is used instead); in check mode a diagnostic.
 * Returns -1 or 0 (go on with the substitute). */
int scene_unsupported(Diagnostics *diag, const char *file, int line, const char *substitute, const char *format, ...)
    SCENE_PRINTF(5, 6);

/* In check mode, records `path` as missing when nothing is there and
 * returns 1: the caller skips what needs the file (`what` names it, e.g.
 * Shape "plymesh"). Otherwise returns 0 and the caller reads the file (an
 * error if that fails); -1 when out of memory. */
int scene_missing_file(Diagnostics *diag, const char *file, int line, const char *path, const char *what);

/* Grows *array (of item_size-byte items, *capacity of them) to hold `needed`.
 * Returns 0, or -1 when out of memory or the size overflows. */
int scene_reserve(void **array, size_t *capacity, size_t needed, size_t item_size);

/* Resolves a file named in `file`: relative to main_file's directory, as pbrt-v4's
 * ResolveFilename, or when nothing is there to that file's own directory. NULL when out of memory. */
char *scene_resolve_path(const char *file, const char *main_file, const char *name);

/* Whether something is at `path` (stat, not open: opening a FIFO could block). */
int scene_file_exists(const char *path);

/* A copy of text[0, length) with a terminating NUL, or NULL. */
char *scene_strndup(const char *text, size_t length);

#endif
