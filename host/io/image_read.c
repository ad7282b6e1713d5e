#include "io/image_read.h"

#include "io/exr_image.h"

#include <stb/stb_image.h>

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void rgb_image_free(RgbImage *image)
{
    free(image->rgb);
    memset(image, 0, sizeof *image);
}

static ImageIoStatus fail(char *error, size_t error_size, const char *path, const char *why)
{
    snprintf(error, error_size, "%s: %s", path, why);
    return IMAGE_IO_ERROR;
}

static int has_extension(const char *path, const char *extension)
{
    size_t n = strlen(path), e = strlen(extension);
    return n > e && strcasecmp(path + n - e, extension) == 0;
}

static ImageIoStatus allocate(RgbImage *image, uint64_t width, uint64_t height, char *error, size_t error_size,
                              const char *path)
{
    if (width == 0 || height == 0 || width > 65536 || height > 65536)
        return fail(error, error_size, path, "image size out of range (1..65536 a side)");
    image->width = (uint32_t)width;
    image->height = (uint32_t)height;
    image->rgb = malloc((size_t)width * height * 3 * sizeof *image->rgb);
    return image->rgb ? IMAGE_IO_OK : fail(error, error_size, path, "out of memory");
}

static ImageIoStatus read_exr(const char *path, RgbImage *image, char *error, size_t error_size)
{
    ExrImage exr;
    if (exr_image_read(path, &exr, error, error_size) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    const ExrRgbLayer *layer = exr_image_layer(&exr, "");
    for (int i = 0; !layer && i < exr.layer_count; ++i)
        if (!exr.layers[i].is_int)
            layer = &exr.layers[i];
    ImageIoStatus status = IMAGE_IO_ERROR;
    if (!layer)
        fail(error, error_size, path, "no R, G, B channels");
    else if (allocate(image, (uint64_t)exr.width, (uint64_t)exr.height, error, error_size, path) == IMAGE_IO_OK) {
        memcpy(image->rgb, layer->data, (size_t)exr.width * exr.height * 3 * sizeof(float));
        status = IMAGE_IO_OK;
    }
    exr_image_free(&exr);
    return status;
}

/* PFM: "PF" (RGB) or "Pf" (grey), width height, scale (negative: little
 * endian), then rows of 32-bit floats from the bottom. */
static ImageIoStatus read_pfm(const char *path, RgbImage *image, char *error, size_t error_size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return fail(error, error_size, path, "cannot open");
    char kind[3] = {0};
    unsigned long width = 0, height = 0;
    double scale = 0.0;
    ImageIoStatus status = IMAGE_IO_ERROR;
    if (fscanf(f, "%2s %lu %lu %lf", kind, &width, &height, &scale) != 4 ||
        (strcmp(kind, "PF") && strcmp(kind, "Pf")) || scale == 0.0 || !isspace(fgetc(f))) {
        fail(error, error_size, path, "not a PFM file (header \"PF|Pf width height scale\")");
    } else if (allocate(image, width, height, error, error_size, path) == IMAGE_IO_OK) {
        int channels = kind[1] == 'F' ? 3 : 1;
        int little = scale < 0.0;
        size_t row_values = (size_t)width * channels;
        unsigned char *row = malloc(row_values * 4);
        status = row ? IMAGE_IO_OK : fail(error, error_size, path, "out of memory");
        for (unsigned long y = 0; y < height && status == IMAGE_IO_OK; ++y) {
            if (fread(row, 4, row_values, f) != row_values) {
                status = fail(error, error_size, path, "truncated pixel data");
                break;
            }
            float *out = image->rgb + (size_t)(height - 1 - y) * width * 3;
            for (size_t i = 0; i < row_values; ++i) {
                const unsigned char *b = row + 4 * i;
                uint32_t bits =
                    little ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                           : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
                float v;
                memcpy(&v, &bits, sizeof v);
                v *= (float)fabs(scale);
                if (channels == 3)
                    out[i] = v;
                else
                    out[3 * i] = out[3 * i + 1] = out[3 * i + 2] = v;
            }
        }
        free(row);
    }
    fclose(f);
    if (status != IMAGE_IO_OK)
        rgb_image_free(image);
    return status;
}

static float srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

static ImageIoStatus read_stb(const char *path, RgbImage *image, char *error, size_t error_size)
{
    int width = 0, height = 0, channels = 0;
    int hdr = stbi_is_hdr(path);
    int wide = !hdr && stbi_is_16_bit(path);
    void *data = hdr    ? (void *)stbi_loadf(path, &width, &height, &channels, 3)
                 : wide ? (void *)stbi_load_16(path, &width, &height, &channels, 3)
                        : (void *)stbi_load(path, &width, &height, &channels, 3);
    if (!data) {
        const char *why = stbi_failure_reason();
        return fail(error, error_size, path, why ? why : "cannot decode the image");
    }
    ImageIoStatus status = allocate(image, (uint64_t)width, (uint64_t)height, error, error_size, path);
    size_t n = (size_t)width * height * 3;
    for (size_t i = 0; i < n && status == IMAGE_IO_OK; ++i) {
        if (hdr)
            image->rgb[i] = ((const float *)data)[i];
        else if (wide)
            image->rgb[i] = srgb_to_linear(((const uint16_t *)data)[i] / 65535.0f);
        else
            image->rgb[i] = srgb_to_linear(((const unsigned char *)data)[i] / 255.0f);
    }
    stbi_image_free(data);
    return status;
}

ImageIoStatus image_read_rgb(const char *path, RgbImage *image, char *error, size_t error_size)
{
    memset(image, 0, sizeof *image);
    if (has_extension(path, ".exr"))
        return read_exr(path, image, error, error_size);
    if (has_extension(path, ".pfm"))
        return read_pfm(path, image, error, error_size);
    return read_stb(path, image, error, error_size);
}

void texture_image_free(TextureImage *image)
{
    free(image->bytes);
    free(image->floats);
    memset(image, 0, sizeof *image);
}

ImageIoStatus image_read_texture(const char *path, TextureImage *image, char *error, size_t error_size)
{
    memset(image, 0, sizeof *image);
    if (has_extension(path, ".exr") || has_extension(path, ".pfm") || stbi_is_hdr(path)) {
        RgbImage rgb;
        if (image_read_rgb(path, &rgb, error, error_size) != IMAGE_IO_OK)
            return IMAGE_IO_ERROR;
        image->width = rgb.width;
        image->height = rgb.height;
        image->channels = 3;
        image->floats = rgb.rgb;
        /* Grey (as the readers replicate grey files to RGB): one channel. */
        size_t n = (size_t)rgb.width * rgb.height, grey = 1;
        for (size_t i = 0; i < n && grey; ++i)
            grey = rgb.rgb[3 * i] == rgb.rgb[3 * i + 1] && rgb.rgb[3 * i] == rgb.rgb[3 * i + 2];
        for (size_t i = 0; i < n && grey; ++i)
            image->floats[i] = rgb.rgb[3 * i];
        image->channels = grey ? 1 : 3;
        return IMAGE_IO_OK;
    }
    int width = 0, height = 0, channels = 0;
    if (!stbi_info(path, &width, &height, &channels)) {
        const char *why = stbi_failure_reason();
        return fail(error, error_size, path, why ? why : "cannot decode the image");
    }
    int wanted = channels <= 2 ? 1 : 3;
    int wide = stbi_is_16_bit(path);
    void *data = wide ? (void *)stbi_load_16(path, &width, &height, &channels, wanted)
                      : (void *)stbi_load(path, &width, &height, &channels, wanted);
    if (!data) {
        const char *why = stbi_failure_reason();
        return fail(error, error_size, path, why ? why : "cannot decode the image");
    }
    if (width <= 0 || height <= 0 || (uint64_t)width * (uint64_t)height > ((uint64_t)1 << 31)) {
        stbi_image_free(data);
        return fail(error, error_size, path, "image size out of range (1 to 2^31 texels)");
    }
    size_t n = (size_t)width * height * wanted;
    image->width = (uint32_t)width;
    image->height = (uint32_t)height;
    image->channels = (uint32_t)wanted;
    if (wide) {
        image->floats = malloc(n * sizeof *image->floats);
        for (size_t i = 0; image->floats && i < n; ++i)
            image->floats[i] = ((const uint16_t *)data)[i] / 65535.0f;
        image->needs_decoding = 1;
    } else {
        image->bytes = malloc(n);
        if (image->bytes)
            memcpy(image->bytes, data, n);
    }
    stbi_image_free(data);
    if (!image->bytes && !image->floats)
        return fail(error, error_size, path, "out of memory");
    return IMAGE_IO_OK;
}
