/* Each format's header is read as stb_image (v2.27, Debian's libstb) reads
 * it, so that what passes here is what stb decodes; where stb would read
 * past the end of the data (and fill with zeros, or leave texels unset),
 * the data's size or structure is checked first. PNG stays with stb rather
 * than libpng: its chunks, CRCs and zlib stream are checked here with zlib,
 * which keeps one decoder (and one set of conversions) for every 8-bit
 * format. */
#include "io/image_probe.h"

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

typedef struct {
    const unsigned char *data;
    size_t size;
    ImageHeader *header;
    char *why;
    size_t why_size;
} Probe;

static const char *const format_names[] = {"OpenEXR", "PFM", "PNG", "JPEG", "BMP", "GIF",
                                           "PSD",     "PIC", "PNM", "HDR",  "TGA"};

const char *image_format_name(ImageFormat format)
{
    return format_names[format];
}

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static ImageIoStatus
refuse(Probe *p, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(p->why, p->why_size, format, args);
    va_end(args);
    return IMAGE_IO_ERROR;
}

static uint32_t le16(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8;
}

static uint32_t le32(const unsigned char *b)
{
    return le16(b) | le16(b + 2) << 16;
}

static uint32_t be16(const unsigned char *b)
{
    return (uint32_t)b[0] << 8 | b[1];
}

static uint32_t be32(const unsigned char *b)
{
    return be16(b) << 16 | be16(b + 2);
}

static int starts_with(const Probe *p, const char *magic, size_t length)
{
    return p->size >= length && memcmp(p->data, magic, length) == 0;
}

/* The size from the header: not empty, and at most IMAGE_MAX_TEXELS. */
static ImageIoStatus set_size(Probe *p, uint64_t width, uint64_t height)
{
    const char *name = image_format_name(p->header->format);
    if (width == 0 || height == 0)
        return refuse(p, "the %s header gives an empty image (%" PRIu64 "x%" PRIu64 ")", name, width, height);
    /* Each side first, so that the product cannot wrap. */
    if (width > IMAGE_MAX_TEXELS || height > IMAGE_MAX_TEXELS || width * height > IMAGE_MAX_TEXELS)
        return refuse(
            p, "the %s header claims %" PRIu64 "x%" PRIu64 " texels, over the limit of %" PRIu64 " (16384x16384)", name,
            width, height, IMAGE_MAX_TEXELS);
    p->header->width = (uint32_t)width;
    p->header->height = (uint32_t)height;
    return IMAGE_IO_OK;
}

/* A file shorter than its header and pixels: stb would decode zeros (or
 * leave texels unset) for what is missing. */
static ImageIoStatus need_bytes(Probe *p, uint64_t need)
{
    if (need <= p->size)
        return IMAGE_IO_OK;
    return refuse(p, "truncated: the %ux%u %s needs %" PRIu64 " bytes, the file has %zu", p->header->width,
                  p->header->height, image_format_name(p->header->format), need, p->size);
}

static ImageIoStatus cut_short(Probe *p, const char *what)
{
    return refuse(p, "truncated: the %s file ends inside its %s", image_format_name(p->header->format), what);
}

/* --- TGA: an 18-byte header, no magic (stbi__tga_test's conditions). --- */

static int is_tga(const Probe *p)
{
    if (p->size < 18)
        return 0;
    const unsigned char *d = p->data;
    int mapped = d[1], type = d[2], bits = d[16];
    if (mapped > 1)
        return 0;
    if (mapped) {
        if ((type != 1 && type != 9) || (d[7] != 8 && d[7] != 15 && d[7] != 16 && d[7] != 24 && d[7] != 32))
            return 0;
        if (bits != 8 && bits != 16)
            return 0;
    } else if (type != 2 && type != 3 && type != 10 && type != 11) {
        return 0;
    }
    return le16(d + 12) >= 1 && le16(d + 14) >= 1 &&
           (bits == 8 || bits == 15 || bits == 16 || bits == 24 || bits == 32);
}

static ImageIoStatus probe_tga(Probe *p)
{
    const unsigned char *d = p->data;
    uint32_t width = le16(d + 12), height = le16(d + 14), pixel = (d[16] + 7u) / 8u;
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    uint64_t at = 18 + (uint64_t)d[0];
    if (d[1]) {
        if (le16(d + 5) == 0)
            return refuse(p, "the TGA colour map has no entries");
        /* stb skips "first entry index" bytes before the map. */
        at += le16(d + 3) + (uint64_t)le16(d + 5) * ((d[7] + 7u) / 8u);
    }
    uint64_t left = (uint64_t)width * height;
    if (d[2] < 8)
        return need_bytes(p, at + left * pixel);
    /* Run-length packets, walked as stb reads them: a header byte, then one
     * pixel repeated or `count` literal ones (no more than are left). */
    while (left > 0) {
        if (at >= p->size)
            return cut_short(p, "run-length pixel data");
        unsigned command = p->data[at++];
        uint64_t count = 1 + (command & 127u);
        if (count > left)
            count = left;
        at += command & 128u ? pixel : count * pixel;
        left -= count;
    }
    return at <= p->size ? IMAGE_IO_OK : cut_short(p, "run-length pixel data");
}

/* --- BMP (stbi__bmp_parse_header, stbi__bmp_load). --- */

static ImageIoStatus probe_bmp(Probe *p)
{
    const unsigned char *d = p->data;
    if (p->size < 18)
        return cut_short(p, "header");
    uint32_t header_size = le32(d + 14);
    if (header_size != 12 && header_size != 40 && header_size != 56 && header_size != 108 && header_size != 124)
        return refuse(p, "BMP header size %" PRIu32 " is none of 12, 40, 56, 108, 124", header_size);
    if (p->size < 14 + (size_t)header_size)
        return cut_short(p, "header");
    int64_t width, height;
    uint32_t planes, bits, compression = 0;
    if (header_size == 12) {
        width = le16(d + 18);
        height = le16(d + 20);
        planes = le16(d + 22);
        bits = le16(d + 24);
    } else {
        width = (int32_t)le32(d + 18);
        height = (int32_t)le32(d + 22);
        planes = le16(d + 26);
        bits = le16(d + 28);
        compression = le32(d + 30);
    }
    if (planes != 1)
        return refuse(p, "BMP with %" PRIu32 " planes (1 expected)", planes);
    if (bits != 1 && bits != 4 && bits != 8 && bits != 16 && bits != 24 && bits != 32)
        return refuse(p, "BMP with %" PRIu32 " bits per pixel (1, 4, 8, 16, 24 or 32 are read)", bits);
    if (compression == 1 || compression == 2)
        return refuse(p, "run-length compressed BMPs are not supported");
    if (compression > 3 || (compression == 3 && bits != 16 && bits != 32))
        return refuse(p, "BMP compression %" PRIu32 " is not supported for %" PRIu32 " bits per pixel", compression,
                      bits);
    if (width <= 0 || height == 0 || height == INT32_MIN)
        return refuse(p, "the BMP header gives an empty or negative size (%" PRId64 "x%" PRId64 ")", width, height);
    if (height < 0)
        height = -height; /* rows stored from the top */
    if (set_size(p, (uint64_t)width, (uint64_t)height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    /* stb reads the three masks after a 40- or 56-byte header. */
    int64_t header_end =
        14 + (int64_t)header_size + ((header_size == 40 || header_size == 56) && compression == 3 ? 12 : 0);
    int64_t offset = (int32_t)le32(d + 10), palette = 0;
    if (bits < 16) {
        /* stb's count (for a 12-byte header it leaves out 4 entries). */
        palette = header_size == 12 ? (offset - 14 - 24) / 3 : (offset - header_end) / 4;
        if (palette <= 0 || palette > 256)
            return refuse(
                p, "the BMP's pixel data offset %" PRId64 " leaves room for %" PRId64 " palette colours (1 to 256)",
                offset, palette < 0 ? 0 : palette);
    } else if (offset != header_end) {
        return refuse(p, "the BMP's pixel data offset %" PRId64 " does not follow its header (%" PRId64 ")", offset,
                      header_end);
    }
    uint64_t row = ((uint64_t)width * bits + 31) / 32 * 4;
    if (need_bytes(p, (uint64_t)offset + row * (uint64_t)height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    /* stb looks colours up in a palette array of which only the file's
     * entries are set: an index past them would read stack garbage. */
    for (int64_t y = 0; y < height && bits < 16; ++y) {
        const unsigned char *line = d + offset + (uint64_t)y * row;
        for (int64_t x = 0; x < width; ++x) {
            unsigned index = bits == 8   ? line[x]
                             : bits == 4 ? (line[x / 2] >> (x % 2 ? 0 : 4)) & 15u
                                         : (line[x / 8] >> (7 - x % 8)) & 1u;
            if (index >= palette)
                return refuse(p, "BMP pixel (%" PRId64 ", %" PRId64 ") is colour %u of a %" PRId64 "-colour palette", x,
                              y, index, palette);
        }
    }
    return IMAGE_IO_OK;
}

/* --- Radiance HDR (stbi__hdr_load): text header lines, then flat or
 * run-length scanlines. --- */

/* The line at *at (without its '\n'), or -1 at the end of the file. */
static int hdr_line(Probe *p, size_t *at, const char **line, size_t *length)
{
    if (*at >= p->size)
        return -1;
    const unsigned char *start = p->data + *at, *end = memchr(start, '\n', p->size - *at);
    if (!end)
        return -1;
    *line = (const char *)start;
    *length = (size_t)(end - start);
    *at += *length + 1;
    return 0;
}

static int hdr_number(const char **s, const char *end, uint64_t *value)
{
    if (*s == end || **s < '0' || **s > '9')
        return -1;
    *value = 0;
    for (; *s < end && **s >= '0' && **s <= '9'; ++*s)
        if ((*value = *value * 10 + (uint64_t)(**s - '0')) > 0x7fffffff)
            return -1;
    return 0;
}

static ImageIoStatus probe_hdr(Probe *p)
{
    size_t at = 0, length;
    const char *line;
    int format_found = 0;
    hdr_line(p, &at, &line, &length); /* "#?RADIANCE" or "#?RGBE", as detected */
    for (;;) {
        if (hdr_line(p, &at, &line, &length) != 0)
            return cut_short(p, "header");
        if (length == 0)
            break;
        if (length == 22 && memcmp(line, "FORMAT=32-bit_rle_rgbe", 22) == 0)
            format_found = 1;
    }
    if (!format_found)
        return refuse(p, "the HDR header has no FORMAT=32-bit_rle_rgbe line");
    if (hdr_line(p, &at, &line, &length) != 0)
        return cut_short(p, "header");
    const char *s = line, *end = line + length;
    uint64_t width = 0, height = 0;
    int ok = length > 3 && memcmp(s, "-Y ", 3) == 0;
    s += 3;
    ok = ok && hdr_number(&s, end, &height) == 0;
    while (ok && s < end && *s == ' ')
        ++s;
    ok = ok && end - s > 3 && memcmp(s, "+X ", 3) == 0;
    s += 3;
    ok = ok && hdr_number(&s, end, &width) == 0;
    if (!ok)
        return refuse(p, "the HDR resolution line is not \"-Y height +X width\" (the only layout read)");
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    const unsigned char *d = p->data;
    /* Flat RGBE texels unless every scanline starts 2, 2, width (stb
     * decides from the first one). */
    if (width < 8 || width >= 32768 || at + 4 > p->size || d[at] != 2 || d[at + 1] != 2 || (d[at + 2] & 0x80))
        return need_bytes(p, at + 4 * width * height);
    for (uint64_t y = 0; y < height; ++y) {
        if (at + 4 > p->size)
            return cut_short(p, "run-length scanlines");
        if (d[at] != 2 || d[at + 1] != 2 || be16(d + at + 2) != width)
            return refuse(p, "HDR scanline %" PRIu64 " does not start 2, 2, %" PRIu64, y, width);
        at += 4;
        for (int component = 0; component < 4; ++component) {
            for (uint64_t x = 0; x < width;) {
                if (at >= p->size)
                    return cut_short(p, "run-length scanlines");
                unsigned count = d[at++];
                int run = count > 128;
                count = run ? count - 128 : count;
                /* A count of 0 would make stb loop for ever. */
                if (count == 0 || count > width - x)
                    return refuse(p, "bad run-length data in HDR scanline %" PRIu64, y);
                at += run ? 1 : count;
                x += count;
            }
        }
    }
    return at <= p->size ? IMAGE_IO_OK : cut_short(p, "run-length scanlines");
}

/* --- PNG: chunks with their CRCs, then the zlib stream inflated to the
 * size the header calls for. --- */

typedef struct {
    uint32_t width, height;
    int depth, color_type, interlaced, palette_entries;
    uint64_t raw_size; /* the filtered rows, all passes */
} PngInfo;

static uint64_t png_row_bytes(const PngInfo *png, uint64_t width)
{
    static const int channels[7] = {1, 0, 3, 1, 2, 0, 4};
    return (width * (uint64_t)channels[png->color_type] * (uint64_t)png->depth + 7) / 8;
}

/* Adam7's passes (x0, y0, dx, dy); one pass of the whole image if not
 * interlaced. */
static const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};

static void png_pass_size(const PngInfo *png, int pass, uint64_t *width, uint64_t *height)
{
    if (!png->interlaced) {
        *width = png->width;
        *height = png->height;
        return;
    }
    const int *a = adam7[pass];
    *width = png->width > (uint32_t)a[0] ? (png->width - a[0] + a[2] - 1) / a[2] : 0;
    *height = png->height > (uint32_t)a[1] ? (png->height - a[1] + a[3] - 1) / a[3] : 0;
}

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* stb expands palette indices through a 256-entry table of which only the
 * PLTE's entries are set: an index past them would read stack garbage. So
 * the rows of a palette image are unfiltered here and every index checked. */
static ImageIoStatus png_check_indices(Probe *p, const PngInfo *png, unsigned char *raw)
{
    int passes = png->interlaced ? 7 : 1;
    for (int pass = 0; pass < passes; ++pass) {
        uint64_t width, height;
        png_pass_size(png, pass, &width, &height);
        if (width == 0 || height == 0)
            continue;
        uint64_t row = png_row_bytes(png, width);
        unsigned char *previous = NULL;
        for (uint64_t y = 0; y < height; ++y, raw += row + 1) {
            int filter = raw[0];
            unsigned char *line = raw + 1;
            if (filter > 4)
                return refuse(p, "PNG row %" PRIu64 " has filter type %d (0 to 4)", y, filter);
            for (uint64_t i = 0; i < row; ++i) {
                int left = i > 0 ? line[i - 1] : 0, up = previous ? previous[i] : 0;
                int up_left = i > 0 && previous ? previous[i - 1] : 0;
                int predictor = filter == 1   ? left
                                : filter == 2 ? up
                                : filter == 3 ? (left + up) / 2
                                : filter == 4 ? paeth(left, up, up_left)
                                              : 0;
                line[i] = (unsigned char)(line[i] + predictor);
            }
            for (uint64_t x = 0; x < width; ++x) {
                int shift = 8 - png->depth - (int)(x * png->depth % 8);
                int index = (line[x * png->depth / 8] >> shift) & ((1 << png->depth) - 1);
                if (index >= png->palette_entries)
                    return refuse(p, "PNG texel uses colour %d of a %d-colour palette", index, png->palette_entries);
            }
            previous = line;
        }
    }
    return IMAGE_IO_OK;
}

/* Inflates the IDAT chunks (each given as offset and length) with zlib:
 * the stream must end, check (Adler-32) and hold the header's rows. */
static ImageIoStatus png_inflate(Probe *p, const PngInfo *png, const size_t (*idat)[2], size_t idat_count)
{
    int palette = png->color_type == 3;
    /* A palette image is kept (at most a byte a texel plus a byte a row)
     * for its index check; any other is inflated into a scratch buffer. */
    size_t keep = palette ? (size_t)png->raw_size : 0, scratch_size = 1 << 16;
    unsigned char *out = malloc(palette ? keep + 1 : scratch_size);
    if (!out)
        return refuse(p, "out of memory for %zu bytes of PNG rows", palette ? keep : scratch_size);
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit(&z) != Z_OK) {
        free(out);
        return refuse(p, "cannot start zlib");
    }
    uint64_t total = 0;
    int result = Z_OK;
    for (size_t i = 0; i < idat_count && result == Z_OK; ++i) {
        z.next_in = (unsigned char *)(p->data + idat[i][0]);
        z.avail_in = (uInt)idat[i][1];
        while (result == Z_OK && z.avail_in > 0) {
            size_t written = palette ? (size_t)total : 0;
            size_t room = palette ? keep + 1 - written : scratch_size;
            if (room == 0)
                break; /* more rows than the header's: stb ignores them */
            z.next_out = out + written;
            z.avail_out = (uInt)(room < (1u << 30) ? room : (1u << 30));
            uInt before = z.avail_out;
            result = inflate(&z, Z_NO_FLUSH);
            total += before - z.avail_out;
            if (result == Z_BUF_ERROR)
                result = Z_OK; /* no progress: needs more input */
        }
    }
    char zlib_message[128];
    snprintf(zlib_message, sizeof zlib_message, "%s", z.msg ? z.msg : "");
    inflateEnd(&z);
    ImageIoStatus status = IMAGE_IO_OK;
    if (result != Z_OK && result != Z_STREAM_END)
        status = refuse(p, "corrupt PNG image data (zlib: %s)", zlib_message[0] ? zlib_message : "error");
    else if (total < png->raw_size)
        status =
            refuse(p, "truncated: the PNG's image data holds %" PRIu64 " of the %" PRIu64 " bytes of its %ux%u rows",
                   total, png->raw_size, png->width, png->height);
    else if (result != Z_STREAM_END && !palette)
        status = cut_short(p, "compressed image data");
    if (status == IMAGE_IO_OK && palette)
        status = png_check_indices(p, png, out);
    free(out);
    return status;
}

static ImageIoStatus probe_png(Probe *p)
{
    const unsigned char *d = p->data;
    size_t at = 8, idat_count = 0, idat_capacity = 0;
    size_t(*idat)[2] = NULL;
    PngInfo png;
    memset(&png, 0, sizeof png);
    int seen_header = 0, seen_end = 0;
    ImageIoStatus status = IMAGE_IO_OK;
    for (int chunk = 0; status == IMAGE_IO_OK && !seen_end; ++chunk) {
        if (p->size - at < 12) {
            status = cut_short(p, seen_header ? "chunks (no IEND chunk)" : "header");
            break;
        }
        uint32_t length = be32(d + at);
        const unsigned char *type = d + at + 4;
        int letters = 1;
        for (int i = 0; i < 4; ++i)
            letters &= (type[i] | 0x20) >= 'a' && (type[i] | 0x20) <= 'z';
        if (!letters) {
            status = refuse(p, "PNG chunk %d's type is not four letters (corrupt file)", chunk);
            break;
        }
        if (length > 0x7fffffffu || length > p->size - at - 12) {
            status = cut_short(p, "chunks");
            break;
        }
        char name[5] = {(char)type[0], (char)type[1], (char)type[2], (char)type[3], 0};
        const unsigned char *body = d + at + 8;
        int critical = !(type[0] & 0x20);
        /* Ancillary chunks may be damaged (libpng warns and goes on). */
        if (critical && crc32(crc32(0L, Z_NULL, 0), type, length + 4) != be32(body + length)) {
            status = refuse(p, "PNG chunk %s fails its CRC (corrupt file)", name);
            break;
        }
        if (chunk == 0 && strcmp(name, "IHDR") != 0) {
            status = refuse(p, "the PNG does not start with an IHDR chunk (Apple's CgBI PNGs are not read)");
            break;
        }
        if (strcmp(name, "IHDR") == 0) {
            if (chunk != 0 || length != 13) {
                status = refuse(p, "PNG IHDR chunk misplaced or not 13 bytes");
                break;
            }
            png.width = be32(body);
            png.height = be32(body + 4);
            png.depth = body[8];
            png.color_type = body[9];
            png.interlaced = body[12];
            int depth = png.depth, type_ok = 0;
            switch (png.color_type) {
            case 0:
                type_ok = depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16;
                break;
            case 3:
                type_ok = depth == 1 || depth == 2 || depth == 4 || depth == 8;
                break;
            case 2:
            case 4:
            case 6:
                type_ok = depth == 8 || depth == 16;
                break;
            }
            if (!type_ok || body[10] != 0 || body[11] != 0 || body[12] > 1) {
                status = refuse(p, "PNG IHDR has colour type %d, bit depth %d, methods %d %d %d (not valid PNG)",
                                png.color_type, depth, body[10], body[11], body[12]);
                break;
            }
            if (png.width > 0x7fffffffu || png.height > 0x7fffffffu) {
                status = refuse(p, "PNG size %" PRIu32 "x%" PRIu32 " is over 2^31 - 1 a side", png.width, png.height);
                break;
            }
            status = set_size(p, png.width, png.height);
            seen_header = 1;
        } else if (strcmp(name, "PLTE") == 0) {
            if (length % 3 != 0 || length == 0 || length > 768) {
                status = refuse(p, "PNG PLTE chunk of %" PRIu32 " bytes (3 to 768, a multiple of 3)", length);
                break;
            }
            png.palette_entries = (int)(length / 3);
        } else if (strcmp(name, "IDAT") == 0 && length > 0) {
            if (idat_count == idat_capacity) {
                size_t grown = idat_capacity ? 2 * idat_capacity : 16;
                void *more = realloc(idat, grown * sizeof *idat);
                if (!more) {
                    status = refuse(p, "out of memory for the PNG's chunk list");
                    break;
                }
                idat = more;
                idat_capacity = grown;
            }
            idat[idat_count][0] = (size_t)(body - d);
            idat[idat_count][1] = length;
            ++idat_count;
        } else if (strcmp(name, "IEND") == 0) {
            seen_end = 1;
        }
        at += 12 + (size_t)length;
    }
    if (status == IMAGE_IO_OK && png.color_type == 3 && png.palette_entries == 0)
        status = refuse(p, "palette PNG without a PLTE chunk");
    if (status == IMAGE_IO_OK && idat_count == 0)
        status = refuse(p, "PNG without image data (no IDAT chunk)");
    if (status == IMAGE_IO_OK) {
        for (int pass = 0; pass < (png.interlaced ? 7 : 1); ++pass) {
            uint64_t width, height;
            png_pass_size(&png, pass, &width, &height);
            if (width > 0 && height > 0)
                png.raw_size += height * (1 + png_row_bytes(&png, width));
        }
        status = png_inflate(p, &png, (const size_t(*)[2])idat, idat_count);
    }
    free(idat);
    return status;
}

/* --- JPEG: the marker segments, the frame header (SOF0, 1 or 2, which stb
 * decodes) and an end-of-image marker after the scans. --- */

static ImageIoStatus probe_jpeg(Probe *p)
{
    const unsigned char *d = p->data;
    size_t at = 2;
    uint64_t blocks = 0;
    int seen_frame = 0;
    for (;;) {
        if (at + 2 > p->size)
            return cut_short(p, seen_frame ? "scans (no end-of-image marker)" : "header");
        if (d[at] != 0xff)
            return refuse(p, "corrupt JPEG: no marker at byte %zu", at);
        int marker = d[at + 1];
        at += 2;
        if (marker == 0xff) {
            --at; /* fill byte */
            continue;
        }
        if (marker == 0xd9) {
            if (!seen_frame)
                return refuse(p, "the JPEG ends before its frame header");
            break;
        }
        if ((marker >= 0xd0 && marker <= 0xd7) || marker == 0x01)
            continue; /* no length */
        if (at + 2 > p->size)
            return cut_short(p, "header");
        size_t length = be16(d + at);
        if (length < 2 || length > p->size - at)
            return cut_short(p, "header");
        const unsigned char *body = d + at + 2;
        if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc) {
            if (marker > 0xc2)
                return refuse(p, "JPEG with frame type SOF%d (only baseline and progressive are read)", marker - 0xc0);
            if (seen_frame)
                return refuse(p, "JPEG with two frame headers");
            if (length < 8)
                return cut_short(p, "frame header");
            int components = body[5];
            if (body[0] != 8)
                return refuse(p, "JPEG with %d-bit samples (8-bit are read)", body[0]);
            if (components != 1 && components != 3 && components != 4)
                return refuse(p, "JPEG with %d components (1, 3 or 4 are read)", components);
            if (length < 8 + 3 * (size_t)components)
                return cut_short(p, "frame header");
            uint32_t height = be16(body + 1), width = be16(body + 3);
            if (height == 0)
                return refuse(p, "JPEG whose height is given after the scan (DNL) is not read");
            if (set_size(p, width, height) != IMAGE_IO_OK)
                return IMAGE_IO_ERROR;
            int h_max = 1, v_max = 1;
            for (int c = 0; c < components; ++c) {
                int h = body[7 + 3 * c] >> 4, v = body[7 + 3 * c] & 15;
                if (h < 1 || h > 4 || v < 1 || v > 4)
                    return refuse(p, "JPEG component %d has sampling factors %dx%d (1 to 4)", c, h, v);
                h_max = h > h_max ? h : h_max;
                v_max = v > v_max ? v : v_max;
            }
            for (int c = 0; c < components; ++c) {
                uint64_t h = body[7 + 3 * c] >> 4, v = body[7 + 3 * c] & 15;
                uint64_t w_c = (width * h + h_max - 1) / h_max, h_c = (height * v + v_max - 1) / v_max;
                blocks += ((w_c + 7) / 8) * ((h_c + 7) / 8);
            }
            /* Every 8x8 block of every component takes at least one bit of
             * entropy-coded data (its DC coefficient's code). */
            if (blocks / 8 > p->size)
                return refuse(
                    p, "truncated: the %ux%u JPEG needs at least %" PRIu64 " bytes of coded blocks, the file has %zu",
                    width, height, blocks / 8, p->size);
            seen_frame = 1;
        }
        at += length;
        if (marker == 0xda) {
            if (!seen_frame)
                return refuse(p, "JPEG scan before its frame header");
            /* The entropy-coded data: up to the next marker that is neither
             * a stuffed 0xff 0x00 nor a restart marker. */
            while (at + 1 < p->size &&
                   !(d[at] == 0xff && d[at + 1] != 0x00 && d[at + 1] != 0xff && (d[at + 1] < 0xd0 || d[at + 1] > 0xd7)))
                ++at;
            if (at + 1 >= p->size)
                return cut_short(p, "scans (no end-of-image marker)");
        }
    }
    return IMAGE_IO_OK;
}

/* --- GIF: the logical screen (stb's output size) and every block up to
 * the trailer. --- */

static ImageIoStatus gif_sub_blocks(Probe *p, size_t *at, uint64_t *bytes)
{
    for (;;) {
        if (*at >= p->size)
            return cut_short(p, "data blocks (no trailer)");
        size_t length = p->data[(*at)++];
        if (length == 0)
            return IMAGE_IO_OK;
        if (length > p->size - *at)
            return cut_short(p, "data blocks (no trailer)");
        *at += length;
        *bytes += length;
    }
}

static ImageIoStatus probe_gif(Probe *p)
{
    const unsigned char *d = p->data;
    if (p->size < 13)
        return cut_short(p, "header");
    uint32_t width = le16(d + 6), height = le16(d + 8);
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    size_t at = 13;
    if (d[10] & 0x80)
        at += 3u << ((d[10] & 7) + 1);
    int images = 0;
    uint64_t coded = 0;
    for (;;) {
        if (at >= p->size)
            return cut_short(p, "blocks (no trailer)");
        int block = d[at++];
        if (block == 0x3b)
            break;
        if (block == 0x21) {
            ++at; /* the extension's label */
            uint64_t ignored = 0;
            if (gif_sub_blocks(p, &at, &ignored) != IMAGE_IO_OK)
                return IMAGE_IO_ERROR;
        } else if (block == 0x2c) {
            if (at + 10 > p->size)
                return cut_short(p, "image descriptor");
            uint32_t x = le16(d + at), y = le16(d + at + 2), w = le16(d + at + 4), h = le16(d + at + 6);
            if ((uint64_t)x + w > width || (uint64_t)y + h > height)
                return refuse(p,
                              "GIF image %d (%" PRIu32 "x%" PRIu32 " at %" PRIu32 ", %" PRIu32
                              ") lies outside its %" PRIu32 "x%" PRIu32 " screen",
                              images, w, h, x, y, width, height);
            int flags = d[at + 8];
            at += 9;
            if (flags & 0x80)
                at += 3u << ((flags & 7) + 1);
            ++at;               /* LZW minimum code size */
            uint64_t bytes = 0; /* stb decodes the first image only */
            if (gif_sub_blocks(p, &at, &bytes) != IMAGE_IO_OK)
                return IMAGE_IO_ERROR;
            coded = images == 0 ? bytes : coded;
            ++images;
        } else {
            return refuse(p, "corrupt GIF: block type 0x%02x at byte %zu", block, at - 1);
        }
    }
    if (images == 0)
        return refuse(p, "GIF without an image");
    /* An LZW code of at most 12 bits stands for at most 4096 texels. */
    if (coded * 8 / 12 * 4096 < (uint64_t)width * height)
        return refuse(p, "truncated: %" PRIu64 " bytes of LZW data cannot fill a %ux%u GIF screen", coded, width,
                      height);
    return IMAGE_IO_OK;
}

/* --- PSD (stbi__psd_load): RGB, 8 or 16 bits, raw or PackBits. --- */

static ImageIoStatus probe_psd(Probe *p)
{
    const unsigned char *d = p->data;
    if (p->size < 26)
        return cut_short(p, "header");
    uint32_t channels = be16(d + 12), height = be32(d + 14), width = be32(d + 18), depth = be16(d + 22);
    if (be16(d + 4) != 1)
        return refuse(p, "PSD version %" PRIu32 " (1 is read)", be16(d + 4));
    if (channels < 3 || channels > 16)
        return refuse(p, "PSD with %" PRIu32 " channels (3 to 16)", channels);
    if (depth != 8 && depth != 16)
        return refuse(p, "PSD with %" PRIu32 "-bit channels (8 or 16 are read)", depth);
    if (be16(d + 24) != 3)
        return refuse(p, "PSD colour mode %" PRIu32 " (only RGB, 3, is read)", be16(d + 24));
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    size_t at = 26;
    for (int section = 0; section < 3; ++section) {
        if (p->size - at < 4 || be32(d + at) > p->size - at - 4)
            return cut_short(p, "header sections");
        at += 4 + (size_t)be32(d + at);
    }
    if (p->size - at < 2)
        return cut_short(p, "header sections");
    uint32_t compression = be16(d + at);
    at += 2;
    uint64_t pixels = (uint64_t)width * height, read = channels < 4 ? channels : 4;
    if (compression > 1)
        return refuse(p, "PSD compression %" PRIu32 " (raw or PackBits are read)", compression);
    if (compression == 0)
        return need_bytes(p, at + read * pixels * (depth / 8));
    if (depth == 16)
        return refuse(p, "16-bit PackBits PSDs are not read");
    /* stb skips the row byte counts and decodes the first four channels'
     * PackBits runs of width * height bytes each. */
    uint64_t next = at + (uint64_t)height * channels * 2;
    for (uint64_t channel = 0; channel < read; ++channel) {
        for (uint64_t count = 0; count < pixels;) {
            if (next >= p->size)
                return cut_short(p, "PackBits data");
            unsigned length = d[next++];
            if (length == 128)
                continue;
            uint64_t n = length < 128 ? length + 1u : 257u - length;
            if (n > pixels - count)
                return refuse(p, "corrupt PSD PackBits data in channel %" PRIu64, channel);
            next += length < 128 ? n : 1;
            count += n;
        }
    }
    return next <= p->size ? IMAGE_IO_OK : cut_short(p, "PackBits data");
}

/* --- Softimage PIC (stbi__pic_load): stb checks the end of the data
 * itself, but allocates the image first; a file too short for any data of
 * that size is refused here. --- */

static ImageIoStatus probe_pic(Probe *p)
{
    const unsigned char *d = p->data;
    if (p->size < 104)
        return cut_short(p, "header");
    uint32_t width = be16(d + 92), height = be16(d + 94);
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    size_t at = 104;
    uint64_t row_minimum = 0;
    int chained = 1, covered = 0;
    for (int packet = 0; chained; ++packet) {
        if (packet == 10)
            return refuse(p, "PIC with more than 10 channel packets");
        if (at + 4 > p->size)
            return cut_short(p, "channel packets");
        chained = d[at];
        int size = d[at + 1], type = d[at + 2], mask = d[at + 3];
        at += 4;
        int bytes = !!(mask & 0x80) + !!(mask & 0x40) + !!(mask & 0x20) + !!(mask & 0x10);
        if (size != 8)
            return refuse(p, "PIC packet of %d bits (8 are read)", size);
        if (type > 2)
            return refuse(p, "PIC packet with compression %d (0, 1 or 2)", type);
        if (bytes == 0)
            return refuse(p, "PIC packet %d holds no channel", packet);
        covered |= mask;
        /* The fewest bytes a row of this packet can take: raw texels, runs
         * of at most 255, or mixed runs of at most 65535. */
        row_minimum += type == 0   ? (uint64_t)width * bytes
                       : type == 1 ? (width + 254) / 255 * (uint64_t)(1 + bytes)
                                   : (width + 65534) / 65535 * (uint64_t)(3 + bytes);
    }
    if ((covered & 0xe0) != 0xe0)
        return refuse(p, "PIC packets leave some of R, G, B without data");
    return need_bytes(p, at + row_minimum * height);
}

/* --- PNM: binary P5 (grey) and P6 (RGB), as stbi__pnm_info reads the
 * header: a 255 or 65535 maximum (stb does not rescale others). --- */

static int pnm_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

static ImageIoStatus probe_pnm(Probe *p)
{
    const unsigned char *d = p->data;
    size_t at = 2;
    uint64_t values[3];
    /* stb reads one byte ahead: `c` is the byte after the last one used. */
    int c = at < p->size ? d[at++] : -1;
    for (int i = 0; i < 3; ++i) {
        for (;;) {
            while (c >= 0 && pnm_space(c))
                c = at < p->size ? d[at++] : -1;
            if (c != '#')
                break;
            while (c >= 0 && c != '\n' && c != '\r')
                c = at < p->size ? d[at++] : -1;
        }
        if (c < '0' || c > '9')
            return c < 0 ? cut_short(p, "header") : refuse(p, "PNM header field %d is not a number", i + 1);
        values[i] = 0;
        while (c >= '0' && c <= '9') {
            values[i] = values[i] * 10 + (uint64_t)(c - '0');
            if (values[i] > 0x7fffffff)
                return refuse(p, "PNM header number out of range");
            c = at < p->size ? d[at++] : -1;
        }
        if (c < 0)
            return cut_short(p, "header");
    }
    if (values[2] != 255 && values[2] != 65535)
        return refuse(p, "PNM maximum value %" PRIu64 " (255 or 65535 are read)", values[2]);
    if (set_size(p, values[0], values[1]) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    uint64_t channels = d[1] == '6' ? 3 : 1, bytes = values[2] > 255 ? 2 : 1;
    return need_bytes(p, at + values[0] * values[1] * channels * bytes);
}

/* --- PFM (read in image_read.c): "PF" or "Pf", width, height, scale,
 * one whitespace byte, then the rows of 32-bit floats. --- */

static int pfm_token(Probe *p, size_t *at, char *token, size_t token_size)
{
    while (*at < p->size && pnm_space(p->data[*at]))
        ++*at;
    size_t n = 0;
    while (*at < p->size && !pnm_space(p->data[*at]) && n + 1 < token_size)
        token[n++] = (char)p->data[(*at)++];
    token[n] = '\0';
    return n > 0 && *at < p->size && pnm_space(p->data[*at]) ? 0 : -1;
}

static ImageIoStatus probe_pfm(Probe *p)
{
    size_t at = 2;
    char width_text[24], height_text[24], scale_text[64];
    char *end_width, *end_height, *end_scale;
    int ok = pfm_token(p, &at, width_text, sizeof width_text) == 0 &&
             pfm_token(p, &at, height_text, sizeof height_text) == 0 &&
             pfm_token(p, &at, scale_text, sizeof scale_text) == 0;
    unsigned long long width = ok ? strtoull(width_text, &end_width, 10) : 0;
    unsigned long long height = ok ? strtoull(height_text, &end_height, 10) : 0;
    double scale = ok ? strtod(scale_text, &end_scale) : 0.0;
    if (!ok || *end_width || *end_height || *end_scale || width_text[0] == '-' || height_text[0] == '-' ||
        scale == 0.0 || !isfinite(scale))
        return refuse(p, "not a PFM file (header \"PF|Pf width height scale\")");
    if (set_size(p, width, height) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    ++at; /* the single whitespace byte */
    p->header->pfm_channels = p->data[1] == 'F' ? 3 : 1;
    p->header->pfm_scale = scale;
    p->header->pfm_data = at;
    return need_bytes(p, at + (uint64_t)width * height * p->header->pfm_channels * 4);
}

ImageIoStatus image_probe(const unsigned char *data, size_t size, ImageHeader *header, char *why, size_t why_size)
{
    memset(header, 0, sizeof *header);
    Probe probe = {data, size, header, why, why_size}, *p = &probe;
    static const unsigned char png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01}, pic_magic[4] = {0x53, 0x80, 0xf6, 0x34};
    if (starts_with(p, (const char *)exr_magic, 4)) {
        header->format = IMAGE_FORMAT_EXR;
        return IMAGE_IO_OK;
    }
    if (size > 2 && data[0] == 'P' && (data[1] == 'F' || data[1] == 'f') && pnm_space(data[2])) {
        header->format = IMAGE_FORMAT_PFM;
        return probe_pfm(p);
    }
    if (starts_with(p, (const char *)png_magic, 8)) {
        header->format = IMAGE_FORMAT_PNG;
        return probe_png(p);
    }
    if (starts_with(p, "BM", 2)) {
        header->format = IMAGE_FORMAT_BMP;
        return probe_bmp(p);
    }
    if (starts_with(p, "GIF87a", 6) || starts_with(p, "GIF89a", 6)) {
        header->format = IMAGE_FORMAT_GIF;
        return probe_gif(p);
    }
    if (starts_with(p, "8BPS", 4)) {
        header->format = IMAGE_FORMAT_PSD;
        return probe_psd(p);
    }
    if (starts_with(p, (const char *)pic_magic, 4) && size >= 92 && memcmp(data + 88, "PICT", 4) == 0) {
        header->format = IMAGE_FORMAT_PIC;
        return probe_pic(p);
    }
    if (size >= 2 && data[0] == 0xff && data[1] == 0xd8) {
        header->format = IMAGE_FORMAT_JPEG;
        return probe_jpeg(p);
    }
    if (size >= 2 && data[0] == 'P' && (data[1] == '5' || data[1] == '6')) {
        header->format = IMAGE_FORMAT_PNM;
        return probe_pnm(p);
    }
    if (starts_with(p, "#?RADIANCE\n", 11) || starts_with(p, "#?RGBE\n", 7)) {
        header->format = IMAGE_FORMAT_HDR;
        return probe_hdr(p);
    }
    if (is_tga(p)) {
        header->format = IMAGE_FORMAT_TGA;
        return probe_tga(p);
    }
    return refuse(p, size == 0
                         ? "empty file, not an image"
                         : "not an image gmonrt reads (PNG, JPEG, TGA, BMP, GIF, PSD, PIC, PNM, HDR, EXR or PFM)");
}

void image_printable(const char *text, char *out, size_t out_size)
{
    size_t n = 0;
    for (const unsigned char *s = (const unsigned char *)text; *s && n + 1 < out_size; ++s) {
        if (*s >= 0x20 && *s < 0x7f) {
            out[n++] = (char)*s;
        } else if (n + 5 < out_size) {
            snprintf(out + n, out_size - n, "\\x%02x", *s);
            n += 4;
        } else {
            break;
        }
    }
    if (out_size > 0)
        out[n] = '\0';
}
