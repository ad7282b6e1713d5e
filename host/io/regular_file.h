/* Opening a file a scene names (the scene, its PLY, spectrum and image
 * files): without blocking, and only if it is a regular file. A FIFO
 * without a writer would block open() and read() forever; a directory or a
 * device such as /dev/zero is no file to read. Scene and image readers share
 * this, so every input is refused the same way. */
#ifndef HOST_IO_REGULAR_FILE_H
#define HOST_IO_REGULAR_FILE_H

#include <stddef.h>
#include <sys/stat.h>

/* Returns a descriptor for reading (fstat'ed into *st), or -1 with the
 * cause (strerror's, or "not a regular file ...") in why. */
int regular_file_open(const char *path, struct stat *st, char *why, size_t why_size);

/* Reads the whole regular file into a malloc'ed buffer (with a NUL byte
 * past its end, not counted in *size). Refuses files over max_size bytes.
 * Returns 0, or -1 with the cause in why. */
int regular_file_read(const char *path, size_t max_size, unsigned char **data, size_t *size, char *why,
                      size_t why_size);

#endif
