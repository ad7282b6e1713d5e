#include "cl/kernel_sources.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *read_text_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = NULL;
    if (fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        if (size >= 0 && fseek(f, 0, SEEK_SET) == 0 && (text = malloc((size_t)size + 1))) {
            if (fread(text, 1, (size_t)size, f) != (size_t)size) {
                free(text);
                text = NULL;
            } else {
                text[size] = '\0';
            }
        }
    }
    fclose(f);
    return text;
}

char *kernel_source_load(const char *name, const char *kernel_dir, char *include_dir, size_t include_dir_size,
                         char *error, int error_size)
{
    const EmbeddedKernel *embedded = kernel_source_embedded(name);
    if (!embedded) {
        snprintf(error, (size_t)error_size, "no kernel source named '%s'", name);
        return NULL;
    }
    include_dir[0] = '\0';
    if (!kernel_dir || !*kernel_dir) {
        char *copy = malloc(strlen(embedded->source) + 1);
        if (copy)
            strcpy(copy, embedded->source);
        else
            snprintf(error, (size_t)error_size, "out of memory");
        return copy;
    }
    /* embedded->path is "kernels/<folder>/<file>": the same place below kernel_dir. */
    const char *file = strchr(embedded->path, '/');
    file = file ? file + 1 : embedded->path;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", kernel_dir, file);
    char *text = read_text_file(path);
    if (!text) {
        snprintf(error, (size_t)error_size, "cannot read kernel source %s (--kernel-dir or %s)", path, KERNEL_DIR_ENV);
        return NULL;
    }
    snprintf(include_dir, include_dir_size, "%s", path);
    char *slash = strrchr(include_dir, '/');
    if (slash)
        *slash = '\0';
    return text;
}

const char *kernel_source_generated_dir(void)
{
    return GMON_GENERATED_KERNEL_DIR;
}
