/* Reading a whole file into memory, to a size limit; gzip files inflated. */
#ifndef HOST_SCENE_READ_FILE_H
#define HOST_SCENE_READ_FILE_H

#include <stddef.h>

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

#endif
