#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "fuzz_input.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_NAMES 8

static char directory[4096];
static char *paths[MAX_NAMES];
static int path_count;

static void remove_inputs(void)
{
    for (int i = 0; i < path_count; ++i) {
        remove(paths[i]);
        free(paths[i]);
    }
    if (directory[0])
        rmdir(directory);
}

const char *fuzz_input_path(const char *name)
{
    if (!directory[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(directory, sizeof directory, "%s/gmon-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(directory)) {
            perror("fuzz: cannot create a temporary directory");
            abort();
        }
        atexit(remove_inputs);
    }
    if (path_count == MAX_NAMES)
        abort();
    size_t size = strlen(directory) + 1 + strlen(name) + 1;
    char *path = malloc(size);
    if (!path)
        abort();
    snprintf(path, size, "%s/%s", directory, name);
    paths[path_count++] = path;
    return path;
}

void fuzz_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f || (size > 0 && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror(path);
        abort();
    }
}

uint8_t fuzz_touch(const void *data, size_t size)
{
    const volatile uint8_t *bytes = data;
    uint8_t sum = 0;
    for (size_t i = 0; i < size; ++i)
        sum ^= bytes[i];
    return sum;
}
