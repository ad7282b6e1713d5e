/* How much memory a render may use: checked before it allocates, so that a
 * render too large for the machine stops with a message instead of being
 * killed by the kernel's out-of-memory handler. */
#ifndef HOST_RENDER_MEMORY_CHECK_H
#define HOST_RENDER_MEMORY_CHECK_H

#include <stddef.h>
#include <stdint.h>

/* Environment variable: host memory to assume available, in bytes (a
 * number with an optional K, M or G suffix, powers of 1024); for tests and
 * for users who want a tighter budget than the machine's. */
#define MEMORY_LIMIT_ENV "GMON_HOST_MEMORY"

/* MEMORY_LIMIT_ENV's value in bytes, for main programs to read once and
 * pass down: 0 when unset or empty; -1 (reported) when it is no size. */
int memory_limit_from_environment(uint64_t *limit);

/* The host memory this process can still use: the smallest of `limit`
 * (the MEMORY_LIMIT_ENV setting; 0: none), the cgroup's memory.max less its
 * memory.current, RLIMIT_AS and MemAvailable from /proc/meminfo. `source`
 * names the one that decided it. UINT64_MAX when nothing limits it. */
uint64_t memory_host_available(uint64_t limit, char *source, size_t source_size);

#endif
