/* OpenCL C sources: embedded in the binary at build time, or read from a
 * kernels/ directory at run time (developer option: edit and rerun without
 * rebuilding). */
#ifndef HOST_CL_KERNEL_SOURCES_H
#define HOST_CL_KERNEL_SOURCES_H

#include <stddef.h>

typedef struct {
    const char *name;   /* e.g. "estimator" */
    const char *path;   /* e.g. "kernels/film/estimator.cl", relative to the repository */
    const char *source; /* includes inlined, with #line markers */
} EmbeddedKernel;

/* The embedded source of kernel file `name`, or NULL. */
const EmbeddedKernel *kernel_source_embedded(const char *name);

/* Environment variable naming a kernels/ directory to load sources from
 * instead of the embedded copies. */
#define KERNEL_DIR_ENV "GMON_KERNEL_DIR"

/* The source of kernel `name`: read from `kernel_dir` (gmonrt's
 * --kernel-dir, else $GMON_KERNEL_DIR, which its main reads) if set, at
 * its place below it (e.g. film/estimator.cl), else the embedded copy.
 * Returns a malloc'd string and
 * writes the directory to pass as -I to include_dir (the source file's own,
 * from which its includes are relative; "" when embedded), or NULL with a
 * message in `error`. */
char *kernel_source_load(const char *name, const char *kernel_dir, char *include_dir, size_t include_dir_size,
                         char *error, int error_size);

/* The directory of the kernel headers this build generated (its
 * generated/kernels: film/sorting_networks.h, tracing/CNanoVDB.h), which a
 * kernels/ directory does not hold: a program read from a directory is
 * built with -I for its film/ and tracing/ after the kernel directory's own. */
const char *kernel_source_generated_dir(void);

#endif
