/* 8-bit sRGB PNG previews of linear images, written with libpng
 * (compressed, with an sRGB chunk). */
#ifndef HOST_IO_PNG_IMAGE_H
#define HOST_IO_PNG_IMAGE_H

#include "io/image_io.h"

#include <stddef.h>
#include <stdint.h>

#define PNG_DEFAULT_EXPOSURE 1.0f

/* Writes a width x height RGB image (3 linear floats per pixel, row-major
 * from the top left) as an 8-bit RGB PNG. Each value is multiplied by
 * `exposure` (finite, >= 0; PNG_DEFAULT_EXPOSURE for none), clamped to
 * [0, 1] (NaN and negatives give 0), encoded with the sRGB transfer function
 * and rounded to the nearest of 0..255. On failure returns IMAGE_IO_ERROR
 * with a message in `error` (may be NULL); no partial file is left. */
ImageIoStatus png_write_srgb(const char *path, int width, int height, const float *rgb, float exposure, char *error,
                             size_t error_size);

/* The 8-bit sRGB code of one linear value, after the exposure (as above). */
uint8_t png_srgb_byte(float linear);

#endif
