/* The checks every image file passes before it is decoded, whatever it is
 * used as (a texture or a light's image): which format it is, its size
 * against a texel limit, and that the file holds all the data its header
 * promises. stb_image, which decodes most formats, allocates the image
 * from the header before reading the data and fills what a short file lacks
 * with zeros (or leaves it unset), so the headers are parsed here and the
 * data's structure walked (run-length packets, PNG chunks and zlib stream,
 * JPEG markers, GIF blocks) before stb sees the bytes. */
#ifndef HOST_IO_IMAGE_PROBE_H
#define HOST_IO_IMAGE_PROBE_H

#include "io/image_io.h"

#include <stddef.h>
#include <stdint.h>

/* 16384 x 16384: larger than the environment maps and textures of the
 * public pbrt-v4 scenes, small enough that a header claiming more is
 * refused before gigabytes are allocated for it. */
#define IMAGE_MAX_TEXELS ((uint64_t)1 << 28)

typedef enum {
    IMAGE_FORMAT_EXR,
    IMAGE_FORMAT_PFM,
    IMAGE_FORMAT_PNG,
    IMAGE_FORMAT_JPEG,
    IMAGE_FORMAT_BMP,
    IMAGE_FORMAT_GIF,
    IMAGE_FORMAT_PSD,
    IMAGE_FORMAT_PIC,
    IMAGE_FORMAT_PNM,
    IMAGE_FORMAT_HDR,
    IMAGE_FORMAT_TGA,
} ImageFormat;

typedef struct {
    ImageFormat format;
    uint32_t width, height; /* 0 for EXR: its reader checks its own header */
    /* PFM: "PF" (3) or "Pf" (1) channels, the scale (negative: little
     * endian) and where the rows start. */
    int pfm_channels;
    double pfm_scale;
    size_t pfm_data;
} ImageHeader;

/* The format's name as messages give it ("PNG", ...). */
const char *image_format_name(ImageFormat format);

/* Checks the `size` bytes of an image file (format detected from its first
 * bytes). Returns IMAGE_IO_OK and fills header, or IMAGE_IO_ERROR with the
 * cause, printable and without the file's name, in why. An EXR is only
 * recognised: exr_image_read checks it. */
ImageIoStatus image_probe(const unsigned char *data, size_t size, ImageHeader *header, char *why, size_t why_size);

/* Copies `text` into out, each byte outside printable ASCII written as
 * \xNN, so that a message quoting a file's bytes cannot drive a terminal. */
void image_printable(const char *text, char *out, size_t out_size);

#endif
