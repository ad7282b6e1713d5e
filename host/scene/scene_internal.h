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

/* Size limits for what scene_read_file reads: pbrt scenes come with PLY
 * files of several GB, but no sane scene text is larger than this. */
#define SCENE_MAX_TEXT_BYTES ((size_t)1 << 30)
#define SCENE_MAX_PLY_BYTES ((size_t)4 << 30)

/* Reads the whole of `path` into *data (NUL-terminated, *size bytes before
 * the NUL). Only a regular file of at most max_size bytes is read (a device
 * such as /dev/zero would be read forever, a FIFO could block); a gzip file
 * is inflated, to at most max_size bytes. Returns 0,
 * or -1 with the reason (without the path) in `why`. */
int scene_read_file(const char *path, size_t max_size, char **data, size_t *size, char *why, size_t why_size);

/* For the file readers: when buffer[0, length) fills all but the NUL's
 * byte of *capacity, doubles it, to at most `most` bytes. Returns 1 when it
 * is `most` already (a limit passed), 0 when there is room, -1 when out of
 * memory (the reason in `why`). */
int scene_grow_read_buffer(char **buffer, size_t *capacity, size_t length, size_t most, char *why, size_t why_size);

/* For scene_read_file, a file that starts with gzip's magic bytes (1f 8b):
 * inflates all of fd into *buffer (malloc'd, freed by the caller, room for
 * a NUL), stopping once it holds most - 1 bytes. Returns 0, or -1 with the
 * reason in `why` (corrupt data: "corrupt gzip data: <zlib's message>"). */
int scene_read_gzip(int fd, size_t most, char **buffer, size_t *length, char *why, size_t why_size);

/* Resolves a file named in `file`: relative to main_file's directory, as pbrt-v4's
 * ResolveFilename, or when nothing is there to that file's own directory. NULL when out of memory. */
char *scene_resolve_path(const char *file, const char *main_file, const char *name);

/* Whether something is at `path` (stat, not open: opening a FIFO could block). */
int scene_file_exists(const char *path);

/* A copy of text[0, length) with a terminating NUL, or NULL. */
char *scene_strndup(const char *text, size_t length);

#endif
