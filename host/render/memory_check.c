#define _POSIX_C_SOURCE 200809L
#include "render/memory_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

/* "123", "4K", "2.5G": bytes; 0 if unparsable. */
static uint64_t parse_size(const char *text)
{
    char *end = NULL;
    double value = strtod(text, &end);
    if (end == text || value <= 0.0)
        return 0;
    double scale = 1.0;
    if (*end == 'K' || *end == 'k')
        scale = 1024.0;
    else if (*end == 'M' || *end == 'm')
        scale = 1024.0 * 1024.0;
    else if (*end == 'G' || *end == 'g')
        scale = 1024.0 * 1024.0 * 1024.0;
    else if (*end != '\0')
        return 0;
    return (uint64_t)(value * scale);
}

/* The first number in a file (e.g. a cgroup's memory.max); 0 if none or
 * "max". */
static uint64_t read_number(const char *path)
{
    FILE *f = fopen(path, "r");
    unsigned long long value = 0;
    if (f) {
        if (fscanf(f, "%llu", &value) != 1)
            value = 0;
        fclose(f);
    }
    return value;
}

/* MemAvailable from /proc/meminfo, in bytes; 0 if unknown. */
static uint64_t mem_available(void)
{
    FILE *f = fopen("/proc/meminfo", "r");
    char line[256];
    unsigned long long kib = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "MemAvailable: %llu kB", &kib) == 1)
            break;
    if (f)
        fclose(f);
    return (uint64_t)kib * 1024u;
}

/* This process's cgroup (v2) directory, from /proc/self/cgroup ("0::/path"). */
static int cgroup_directory(char *out, size_t size)
{
    FILE *f = fopen("/proc/self/cgroup", "r");
    char line[1024];
    int found = 0;
    while (f && !found && fgets(line, sizeof line, f))
        if (strncmp(line, "0::", 3) == 0) {
            line[strcspn(line, "\n")] = '\0';
            found = snprintf(out, size, "/sys/fs/cgroup%s", line + 3) < (int)size;
        }
    if (f)
        fclose(f);
    return found;
}

static void consider(uint64_t candidate, const char *name, uint64_t *best, char *source, size_t source_size)
{
    if (candidate > 0 && candidate < *best) {
        *best = candidate;
        snprintf(source, source_size, "%s", name);
    }
}

int memory_limit_from_environment(uint64_t *limit)
{
    *limit = 0;
    const char *setting = getenv(MEMORY_LIMIT_ENV);
    if (!setting || !*setting)
        return 0;
    *limit = parse_size(setting);
    if (*limit == 0) {
        fprintf(stderr, "%s=%s: expected a size in bytes, e.g. 512M or 2.5G\n", MEMORY_LIMIT_ENV, setting);
        return -1;
    }
    return 0;
}

uint64_t memory_host_available(uint64_t limit, char *source, size_t source_size)
{
    uint64_t best = UINT64_MAX;
    snprintf(source, source_size, "no limit found");
    consider(limit, MEMORY_LIMIT_ENV, &best, source, source_size);
    char directory[1024], path[1100];
    if (cgroup_directory(directory, sizeof directory)) {
        snprintf(path, sizeof path, "%s/memory.max", directory);
        uint64_t max = read_number(path);
        snprintf(path, sizeof path, "%s/memory.current", directory);
        uint64_t current = read_number(path);
        if (max > 0)
            consider(max > current ? max - current : 1, "the cgroup's memory.max", &best, source, source_size);
    }
    /* The address space limit counts what the process maps already (the
     * OpenCL runtime maps much). */
    struct rlimit address_space;
    if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY) {
        uint64_t mapped = read_number("/proc/self/statm") * 4096u;
        uint64_t left = (uint64_t)address_space.rlim_cur > mapped ? (uint64_t)address_space.rlim_cur - mapped : 1;
        consider(left, "RLIMIT_AS (ulimit -v) less the mapped memory", &best, source, source_size);
    }
    consider(mem_available(), "MemAvailable in /proc/meminfo", &best, source, source_size);
    return best;
}
