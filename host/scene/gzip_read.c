/* Reading gzip-compressed scene files (.pbrt.gz, .ply.gz: pbrt-v4 reads
 * them, and public scenes ship them) through zlib. The caller's size limit
 * applies to the inflated data: a small file that inflates without end (a
 * "gzip bomb") stops at the limit instead of filling the memory. */
#define _POSIX_C_SOURCE 200809L /* read */

#include "scene/scene_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

int scene_read_gzip(int fd, size_t most, char **buffer, size_t *length, char *why, size_t why_size)
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
        int full = scene_grow_read_buffer(buffer, &capacity, *length, most, why, why_size);
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
