/* Reads an image as linear RGB floats, for lights (and textures): OpenEXR
 * (its HALF or FLOAT R, G, B channels, or its first such layer), PFM,
 * and through stb_image PNG, TGA, JPEG, BMP, GIF, PSD, PIC, PNM (8- or
 * 16-bit, decoded from sRGB as pbrt-v4 decodes them) and Radiance HDR
 * (linear). Grey images are replicated to RGB, alpha is dropped. Rows
 * from the top. Both readers check the file first (image_probe.h): the
 * same file gives the same image or the same error whatever it is used
 * as. */
#ifndef HOST_IO_IMAGE_READ_H
#define HOST_IO_IMAGE_READ_H

#include "io/image_io.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint32_t width, height;
    float *rgb; /* width * height * 3, owned (free()) */
} RgbImage;

/* Returns IMAGE_IO_OK, or IMAGE_IO_ERROR with "path: cause" in error. */
ImageIoStatus image_read_rgb(const char *path, RgbImage *image, char *error, size_t error_size);

void rgb_image_free(RgbImage *image);

/* An image for a texture, in the form it is stored: 8-bit files (PNG,
 * TGA, JPEG, BMP) as their bytes, undecoded; 16-bit ones as floats v /
 * 65535, undecoded (needs_decoding); EXR, PFM and HDR as linear floats.
 * channels is 1 (grey, grey + alpha) or 3 (alpha dropped). */
typedef struct {
    uint32_t width, height, channels;
    uint8_t *bytes;
    float *floats;
    int needs_decoding;
} TextureImage;

/* Returns IMAGE_IO_OK, or IMAGE_IO_ERROR with "path: cause" in error. */
ImageIoStatus image_read_texture(const char *path, TextureImage *image, char *error, size_t error_size);

void texture_image_free(TextureImage *image);

#endif
