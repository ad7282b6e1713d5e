#include "io/png_image.h"

#include <png.h>

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    /* libpng takes the row stride as a png_int_32. */
    if (width > INT32_MAX / 3 || (size_t)height > SIZE_MAX / (3 * (size_t)width))
        return fail(path, error, error_size, "image size %dx%d is too large", width, height);
    size_t value_count = 3 * (size_t)width * (size_t)height;

    uint8_t *codes = malloc(value_count);
    if (!codes)
        return fail(path, error, error_size, "out of memory");
    for (size_t i = 0; i < value_count; ++i)
        codes[i] = png_srgb_byte(rgb[i] * exposure);

    FILE *file = fopen(path, "wb");
    if (!file) {
        int cause = errno;
        free(codes);
        return fail(path, error, error_size, "cannot create the file: %s", strerror(cause));
    }
    /* libpng's simplified API: its errors come back in image.message, not
     * through a longjmp out of this function. 8-bit RGB data gets an sRGB
     * chunk, adaptive row filters and zlib's default compression. */
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_RGB;
    int written = png_image_write_to_stdio(&image, file, 0, codes, 3 * width, NULL);
    free(codes);
    if (!written) {
        fclose(file);
        remove(path);
        ImageIoStatus status = fail(path, error, error_size, "cannot write the PNG: %s", image.message);
        png_image_free(&image);
        return status;
    }
    int flush_failed = fflush(file) != 0 || ferror(file);
    int cause = errno;
    if (fclose(file) != 0 && !flush_failed) {
        flush_failed = 1;
        cause = errno;
    }
    if (flush_failed) {
        remove(path);
        return fail(path, error, error_size, "cannot write the file: %s", strerror(cause));
    }
    return IMAGE_IO_OK;
}
