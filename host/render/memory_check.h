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

/* The host memory this process can still use: the smallest of the
 * GMON_HOST_MEMORY setting, the cgroup's memory.max less its memory.current,
 * RLIMIT_AS and MemAvailable from /proc/meminfo. `source` names the one
 * that decided it. UINT64_MAX when nothing limits it. */
uint64_t memory_host_available(char *source, size_t source_size);

#endif
