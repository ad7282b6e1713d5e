#include "io/png_image.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STORED_BLOCK_MAX 65535u /* bytes of data in one stored deflate block */

/* ------------------------------------------------------------------------
 * Checksums
 * ---------------------------------------------------------------------- */

/* CRC-32 (ISO 3309, polynomial 0xedb88320 reflected), as PNG chunks use. */
typedef struct {
    uint32_t table[256];
} Crc32Table;

static void crc32_table_init(Crc32Table *t)
{
    for (uint32_t n = 0; n < 256; ++n) {
        uint32_t c = n;
        for (int k = 0; k < 8; ++k)
            c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        t->table[n] = c;
    }
}

/* Continues a CRC: start with crc = 0. */
static uint32_t crc32_update(const Crc32Table *t, uint32_t crc, const uint8_t *data, size_t length)
{
    uint32_t c = crc ^ 0xffffffffu;
    for (size_t i = 0; i < length; ++i)
        c = t->table[(c ^ data[i]) & 0xffu] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

/* Adler-32 (RFC 1950): start with 1. */
static uint32_t adler32_update(uint32_t adler, const uint8_t *data, size_t length)
{
    const uint32_t modulus = 65521u;
    uint32_t a = adler & 0xffffu, b = adler >> 16;
    while (length > 0) {
        /* 5552 bytes is the most that cannot overflow b before the modulo. */
        size_t n = length < 5552 ? length : 5552;
        length -= n;
        while (n--) {
            a += *data++;
            b += a;
        }
        a %= modulus;
        b %= modulus;
    }
    return (b << 16) | a;
}

/* ------------------------------------------------------------------------
 * Tone mapping
 * ---------------------------------------------------------------------- */

uint8_t png_srgb_byte(float linear)
{
    double x = linear;
    if (!(x > 0.0)) /* NaN and negatives */
        return 0;
    if (x >= 1.0)
        return 255;
    double encoded = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
    return (uint8_t)(encoded * 255.0 + 0.5);
}

/* ------------------------------------------------------------------------
 * Writing
 * ---------------------------------------------------------------------- */

typedef struct {
    FILE *file;
    Crc32Table crc;
    int failed;
} PngWriter;

static void put_u32(uint8_t *out, uint32_t v)
{
    out[0] = (uint8_t)(v >> 24);
    out[1] = (uint8_t)(v >> 16);
    out[2] = (uint8_t)(v >> 8);
    out[3] = (uint8_t)v;
}

/* One chunk: length, type, data, CRC of type and data. */
static void write_chunk(PngWriter *w, const char type[4], const uint8_t *data, uint32_t length)
{
    uint8_t header[8], trailer[4];
    put_u32(header, length);
    memcpy(header + 4, type, 4);
    uint32_t crc = crc32_update(&w->crc, 0, header + 4, 4);
    crc = crc32_update(&w->crc, crc, data, length);
    put_u32(trailer, crc);
    if (w->failed)
        return;
    if (fwrite(header, 1, sizeof header, w->file) != sizeof header ||
        (length > 0 && fwrite(data, 1, length, w->file) != length) ||
        fwrite(trailer, 1, sizeof trailer, w->file) != sizeof trailer)
        w->failed = 1;
}

/* The filtered image data (filter 0 per row, then RGB bytes), produced row
 * by row on demand. */
typedef struct {
    const float *rgb;
    float exposure;
    size_t width;
    uint8_t *row; /* 1 + 3 * width bytes */
    size_t row_size;
    size_t next_row;
    size_t offset; /* bytes of `row` already handed out */
} ScanlineStream;

static void stream_fill_row(ScanlineStream *s)
{
    const float *pixel = s->rgb + s->next_row * s->width * 3;
    s->row[0] = 0; /* filter type None */
    for (size_t i = 0; i < s->width * 3; ++i)
        s->row[1 + i] = png_srgb_byte(pixel[i] * s->exposure);
    s->next_row += 1;
    s->offset = 0;
}

static void stream_read(ScanlineStream *s, uint8_t *out, size_t length)
{
    while (length > 0) {
        if (s->offset == s->row_size)
            stream_fill_row(s);
        size_t n = s->row_size - s->offset;
        n = n < length ? n : length;
        memcpy(out, s->row + s->offset, n);
        s->offset += n;
        out += n;
        length -= n;
    }
}

static ImageIoStatus fail(const char *path, char *error, size_t error_size, const char *format, ...)
{
    if (error && error_size > 0) {
        int used = snprintf(error, error_size, "%s: ", path ? path : "(no file name)");
        if (used >= 0 && (size_t)used < error_size) {
            va_list args;
            va_start(args, format);
            vsnprintf(error + used, error_size - (size_t)used, format, args);
            va_end(args);
        }
    }
    return IMAGE_IO_ERROR;
}

ImageIoStatus png_write_srgb(const char *path, int width, int height, const float *rgb, float exposure, char *error,
                             size_t error_size)
{
    if (!path || !path[0])
        return fail(path, error, error_size, "no file name given");
    if (width < 1 || height < 1)
        return fail(path, error, error_size, "image size %dx%d is empty", width, height);
    if (!rgb)
        return fail(path, error, error_size, "no pixels given");
    if (!(exposure >= 0.0f) || !isfinite(exposure))
        return fail(path, error, error_size, "exposure %g must be finite and >= 0", (double)exposure);
    size_t row_size = 1 + 3 * (size_t)width;
    if ((size_t)height > SIZE_MAX / row_size)
        return fail(path, error, error_size, "image size %dx%d is too large", width, height);
    size_t raw_size = row_size * (size_t)height;

    ScanlineStream stream = {rgb, exposure, (size_t)width, NULL, row_size, 0, row_size};
    /* One IDAT per stored block: zlib header in the first, Adler-32 in the
     * last. */
    uint8_t *idat = malloc(2 + 5 + STORED_BLOCK_MAX + 4);
    stream.row = malloc(row_size);
    PngWriter w = {NULL, {{0}}, 0};
    if (!idat || !stream.row) {
        free(idat);
        free(stream.row);
        return fail(path, error, error_size, "out of memory");
    }
    crc32_table_init(&w.crc);
    w.file = fopen(path, "wb");
    if (!w.file) {
        int cause = errno;
        free(idat);
        free(stream.row);
        return fail(path, error, error_size, "cannot create the file: %s", strerror(cause));
    }

    static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (fwrite(signature, 1, sizeof signature, w.file) != sizeof signature)
        w.failed = 1;

    uint8_t ihdr[13];
    put_u32(ihdr, (uint32_t)width);
    put_u32(ihdr + 4, (uint32_t)height);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 2;  /* colour type: RGB */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filtering */
    ihdr[12] = 0; /* no interlace */
    write_chunk(&w, "IHDR", ihdr, sizeof ihdr);

    /* sRGB chunk: the bytes are sRGB-encoded (rendering intent perceptual). */
    const uint8_t srgb_intent = 0;
    write_chunk(&w, "sRGB", &srgb_intent, 1);

    uint32_t adler = 1;
    size_t remaining = raw_size;
    int first = 1;
    while (!w.failed && remaining > 0) {
        size_t n = remaining < STORED_BLOCK_MAX ? remaining : STORED_BLOCK_MAX;
        int last = n == remaining;
        size_t at = 0;
        if (first) {
            idat[at++] = 0x78; /* CM 8 (deflate), CINFO 7 (32K window) */
            idat[at++] = 0x01; /* no dictionary, FCHECK: 0x7801 % 31 == 0 */
            first = 0;
        }
        idat[at++] = last ? 1 : 0; /* BFINAL, BTYPE 00 (stored) */
        idat[at++] = (uint8_t)(n & 0xffu);
        idat[at++] = (uint8_t)(n >> 8);
        idat[at++] = (uint8_t)(~n & 0xffu);
        idat[at++] = (uint8_t)((~n >> 8) & 0xffu);
        stream_read(&stream, idat + at, n);
        adler = adler32_update(adler, idat + at, n);
        at += n;
        remaining -= n;
        if (last) {
            put_u32(idat + at, adler);
            at += 4;
        }
        write_chunk(&w, "IDAT", idat, (uint32_t)at);
    }
    write_chunk(&w, "IEND", NULL, 0);

    int close_failed = fclose(w.file) != 0;
    free(idat);
    free(stream.row);
    if (w.failed || close_failed) {
        int cause = errno;
        remove(path);
        return fail(path, error, error_size, "cannot write the file: %s", strerror(cause));
    }
    return IMAGE_IO_OK;
}
