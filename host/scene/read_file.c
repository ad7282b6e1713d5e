/* Reading a whole scene, PLY or .spd file into memory, to a size limit:
 * plain files, and gzip-compressed ones (.pbrt.gz, .ply.gz: pbrt-v4 reads
 * them, and public scenes ship them) through zlib. The limit applies to the
 * inflated data: a small file that inflates without end (a "gzip bomb")
 * stops at the limit instead of filling the memory. */
#define _POSIX_C_SOURCE 200809L /* pread */

#include "scene/read_file.h"
#include "io/regular_file.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <zlib.h>

/* "1 GiB" for the size limits in messages. */
static void format_bytes(size_t bytes, char *out, size_t size)
{
    if (bytes >= ((size_t)1 << 30) && bytes % ((size_t)1 << 30) == 0)
        snprintf(out, size, "%zu GiB", bytes >> 30);
    else
        snprintf(out, size, "%zu bytes", bytes);
}

/* When buffer[0, length) fills all but the NUL's byte of *capacity,
 * doubles it, to at most `most` bytes. Returns 1 when it is `most` already
 * (a limit passed), 0 when there is room, -1 when out of memory (the reason
 * in `why`). */
static int grow_read_buffer(char **buffer, size_t *capacity, size_t length, size_t most, char *why, size_t why_size)
{
    if (length + 1 < *capacity)
        return 0;
    if (*capacity == most)
        return 1;
    size_t grown = *capacity > most / 2 ? most : 2 * *capacity;
    char *p = realloc(*buffer, grown);
    if (!p) {
        snprintf(why, why_size, "out of memory for %zu bytes", grown);
        return -1;
    }
    *buffer = p;
    *capacity = grown;
    return 0;
}

/* Reads fd to the end, not just st_size bytes (the file may have grown),
 * into a buffer of at most `most` bytes (one past the limit, plus the NUL). */
static int read_plain(int fd, size_t file_size, size_t most, char **buffer, size_t *length, char *why, size_t why_size)
{
    size_t capacity = file_size + 2;
    *buffer = malloc(capacity);
    if (!*buffer) {
        snprintf(why, why_size, "out of memory for %zu bytes", capacity);
        return -1;
    }
    for (;;) {
        int full = grow_read_buffer(buffer, &capacity, *length, most, why, why_size);
        if (full != 0)
            return full < 0 ? -1 : 0; /* one byte past the limit: the caller sees it */
        ssize_t n = read(fd, *buffer + *length, capacity - 1 - *length);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            snprintf(why, why_size, "%s", strerror(errno));
            return -1;
        }
        if (n == 0)
            return 0;
        *length += (size_t)n;
    }
}

/* A file that starts with gzip's magic bytes (1f 8b): inflates all of fd
 * into *buffer (malloc'd, freed by the caller, room for a NUL), stopping
 * once it holds most - 1 bytes. Returns 0, or -1 with the reason in `why`
 * (corrupt data: "corrupt gzip data: <zlib's message>"). */
static int read_gzip(int fd, size_t most, char **buffer, size_t *length, char *why, size_t why_size)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) { /* 16: a gzip header, not zlib's */
        snprintf(why, why_size, "cannot start zlib: %s", z.msg ? z.msg : "out of memory");
        return -1;
    }
    size_t capacity = most < ((size_t)1 << 20) ? most : ((size_t)1 << 20);
    *buffer = malloc(capacity);
    unsigned char input[1 << 16];
    int failed = *buffer == NULL, ended = 0; /* ended: the last member is complete */
    if (failed)
        snprintf(why, why_size, "out of memory for %zu bytes", capacity);
    while (!failed) {
        if (z.avail_in == 0) {
            ssize_t n = read(fd, input, sizeof input);
            if (n < 0 && errno == EINTR)
                continue;
            if (n < 0) {
                snprintf(why, why_size, "%s", strerror(errno));
                failed = 1;
                break;
            }
            if (n == 0)
                break;
            z.next_in = input;
            z.avail_in = (uInt)n;
        }
        if (ended) { /* more after a complete member: gzip concatenates members */
            inflateReset(&z);
            ended = 0;
        }
        int full = grow_read_buffer(buffer, &capacity, *length, most, why, why_size);
        if (full != 0) {
            failed = full < 0;
            ended = full > 0; /* at the limit: the caller reports it */
            break;
        }
        size_t room = capacity - 1 - *length;
        z.next_out = (Bytef *)*buffer + *length;
        z.avail_out = room > UINT32_MAX ? UINT32_MAX : (uInt)room;
        uInt before = z.avail_out;
        int status = inflate(&z, Z_NO_FLUSH);
        *length += before - z.avail_out;
        if (status == Z_STREAM_END) {
            ended = 1;
        } else if (status != Z_OK && status != Z_BUF_ERROR) {
            snprintf(why, why_size, "corrupt gzip data: %s", z.msg ? z.msg : zError(status));
            failed = 1;
        }
    }
    inflateEnd(&z);
    if (!failed && !ended) {
        snprintf(why, why_size, "corrupt gzip data: the file ends inside the compressed stream (truncated?)");
        failed = 1;
    }
    return failed ? -1 : 0;
}

int scene_read_file(const char *path, size_t max_size, char **data, size_t *size, char *why, size_t why_size)
{
    *data = NULL;
    *size = 0;
    struct stat st;
    int fd = regular_file_open(path, &st, why, why_size);
    if (fd < 0)
        return -1;
    char limit[32];
    format_bytes(max_size, limit, sizeof limit);
    if ((uintmax_t)st.st_size > max_size) {
        snprintf(why, why_size, "%jd bytes, over the %s limit", (intmax_t)st.st_size, limit);
        close(fd);
        return -1;
    }
    unsigned char magic[2];
    int gzip = pread(fd, magic, 2, 0) == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
    char *buffer = NULL;
    size_t length = 0, most = max_size + 2;
    int failed = gzip ? read_gzip(fd, most, &buffer, &length, why, why_size)
                      : read_plain(fd, (size_t)st.st_size, most, &buffer, &length, why, why_size);
    close(fd);
    if (!failed && length > max_size) {
        snprintf(why, why_size, "over the %s limit%s", limit, gzip ? " once uncompressed" : "");
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
