/* Reading gzip-compressed scene files (.pbrt.gz, .ply.gz: pbrt-v4 reads
 * them, and public scenes ship them) through zlib, with the size limit on
 * the uncompressed data: a small file that inflates without end (a "gzip
 * bomb") stops at the limit instead of filling the memory. */
#define _POSIX_C_SOURCE 200809L /* read */

#include "scene/scene_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

int scene_read_gzip(int fd, size_t max_size, const char *limit, char **data, size_t *size, char *why, size_t why_size)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) { /* 16: a gzip header, not zlib's */
        snprintf(why, why_size, "cannot start zlib: %s", z.msg ? z.msg : "out of memory");
        return -1;
    }
    /* Up to one byte past the limit (to see it is passed), plus the NUL. */
    size_t most = max_size + 2, capacity = most < ((size_t)1 << 20) ? most : ((size_t)1 << 20), length = 0;
    char *buffer = malloc(capacity);
    unsigned char input[1 << 16];
    int failed = buffer == NULL, ended = 0; /* ended: the last member is complete */
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
        if (length + 1 == capacity) {
            if (capacity == most) {
                snprintf(why, why_size, "over the %s limit once uncompressed", limit);
                failed = 1;
                break;
            }
            size_t grown = capacity > most / 2 ? most : 2 * capacity;
            char *p = realloc(buffer, grown);
            if (!p) {
                snprintf(why, why_size, "out of memory for %zu bytes", grown);
                failed = 1;
                break;
            }
            buffer = p;
            capacity = grown;
        }
        size_t room = capacity - 1 - length;
        z.next_out = (Bytef *)buffer + length;
        z.avail_out = room > UINT32_MAX ? UINT32_MAX : (uInt)room;
        uInt before = z.avail_out;
        int status = inflate(&z, Z_NO_FLUSH);
        length += before - z.avail_out;
        if (status == Z_STREAM_END)
            ended = 1;
        else if (status != Z_OK && status != Z_BUF_ERROR) {
            snprintf(why, why_size, "corrupt gzip data: %s", z.msg ? z.msg : zError(status));
            failed = 1;
        }
    }
    inflateEnd(&z);
    if (!failed && !ended) {
        snprintf(why, why_size, "corrupt gzip data: the file ends inside the compressed stream (truncated?)");
        failed = 1;
    }
    if (!failed && length > max_size) {
        snprintf(why, why_size, "over the %s limit once uncompressed", limit);
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
