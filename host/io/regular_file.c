#define _POSIX_C_SOURCE 200809L /* O_CLOEXEC, pread */

#include "io/regular_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int regular_file_open(const char *path, struct stat *st, char *why, size_t why_size)
{
    /* O_NONBLOCK: opening a FIFO without a writer would wait for one. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        return -1;
    }
    if (fstat(fd, st) != 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st->st_mode)) {
        snprintf(why, why_size, "not a regular file (a directory, device or FIFO)");
        close(fd);
        return -1;
    }
    return fd;
}

int regular_file_read(const char *path, size_t max_size, unsigned char **data, size_t *size, char *why, size_t why_size)
{
    *data = NULL;
    *size = 0;
    struct stat st;
    int fd = regular_file_open(path, &st, why, why_size);
    if (fd < 0)
        return -1;
    if ((uintmax_t)st.st_size > max_size) {
        snprintf(why, why_size, "%jd bytes, over the limit of %zu", (intmax_t)st.st_size, max_size);
        close(fd);
        return -1;
    }
    size_t expected = (size_t)st.st_size, length = 0;
    /* One byte more than fstat said, to see a file that grew while read. */
    unsigned char *buffer = malloc(expected + 2);
    if (!buffer) {
        snprintf(why, why_size, "out of memory for %zu bytes", expected + 2);
        close(fd);
        return -1;
    }
    int failed = 0;
    for (;;) {
        ssize_t n = read(fd, buffer + length, expected + 1 - length);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            snprintf(why, why_size, "%s", strerror(errno));
            failed = 1;
            break;
        }
        if (n == 0 || (length += (size_t)n) > expected)
            break;
    }
    close(fd);
    if (!failed && length != expected) {
        snprintf(why, why_size, "changed size while being read (%zu bytes, then %s)", expected,
                 length > expected ? "more" : "fewer");
        failed = 1;
    }
    if (failed) {
        free(buffer);
        return -1;
    }
    buffer[length] = '\0';
    *data = buffer;
    *size = length;
    return 0;
}
