#define _POSIX_C_SOURCE 200809L /* pread */

#include "io/image_read.h"

#include "io/exr_image.h"
#include "io/image_probe.h"
#include "io/regular_file.h"

#include <stb/stb_image.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Files other than EXR are read whole, then checked and decoded from
 * memory (stb takes an int length). */
#define IMAGE_MAX_FILE_BYTES ((size_t)INT_MAX)

void rgb_image_free(RgbImage *image)
{
    free(image->rgb);
    memset(image, 0, sizeof *image);
}

/* "path: why", every byte outside printable ASCII escaped: causes may
 * quote the file (stb's do), and paths come from the scene. */
static ImageIoStatus fail(char *error, size_t error_size, const char *path, const char *why)
{
    char message[1024];
    snprintf(message, sizeof message, "%s: %s", path, why);
    image_printable(message, error, error_size);
    return IMAGE_IO_ERROR;
}

typedef struct {
    unsigned char *data; /* the whole file; NULL for EXR (read by path) */
    size_t size;
    ImageHeader header;
} ImageFile;

/* The checks every image passes, whatever it is used as: a regular file
 * (opened without blocking), of a format read here, whose header is within
 * the texel limit and whose data is all there (image_probe). */
static ImageIoStatus image_open(const char *path, ImageFile *file, char *error, size_t error_size)
{
    memset(file, 0, sizeof *file);
    char why[512];
    struct stat st;
    int fd = regular_file_open(path, &st, why, sizeof why);
    if (fd < 0)
        return fail(error, error_size, path, why);
    unsigned char magic[4] = {0};
    ssize_t got = pread(fd, magic, sizeof magic, 0);
    close(fd);
    static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (got == (ssize_t)sizeof magic && memcmp(magic, exr_magic, sizeof magic) == 0) {
        /* exr_image_read checks its header against the file's size. */
        file->header.format = IMAGE_FORMAT_EXR;
        return IMAGE_IO_OK;
    }
    if (regular_file_read(path, IMAGE_MAX_FILE_BYTES, &file->data, &file->size, why, sizeof why) != 0 ||
        image_probe(file->data, file->size, &file->header, why, sizeof why) != IMAGE_IO_OK) {
        free(file->data);
        file->data = NULL;
        return fail(error, error_size, path, why);
    }
    return IMAGE_IO_OK;
}

/* stb_image's reason for a failure, which may quote the file's bytes. */
static ImageIoStatus fail_stb(char *error, size_t error_size, const char *path, const ImageFile *file)
{
    const char *reason = stbi_failure_reason();
    char why[256];
    snprintf(why, sizeof why, "cannot decode the %s image (%s)", image_format_name(file->header.format),
             reason && reason[0] ? reason : "no reason given");
    return fail(error, error_size, path, why);
}

/* Whether stb decoded the size the header gave (it should, as image_probe
 * reads the headers as stb does). */
static int decoded_as_probed(const ImageFile *file, int width, int height, int channels)
{
    return width > 0 && height > 0 && (uint32_t)width == file->header.width &&
           (uint32_t)height == file->header.height && channels >= 1 && channels <= 4;
}

static ImageIoStatus allocate(RgbImage *image, uint64_t width, uint64_t height, char *error, size_t error_size,
                              const char *path)
{
    if (width == 0 || height == 0 || width > IMAGE_MAX_TEXELS || height > IMAGE_MAX_TEXELS ||
        width * height > IMAGE_MAX_TEXELS)
        return fail(error, error_size, path, "image size out of range (1 to 16384x16384 texels)");
    image->width = (uint32_t)width;
    image->height = (uint32_t)height;
    image->rgb = malloc((size_t)width * height * 3 * sizeof *image->rgb);
    return image->rgb ? IMAGE_IO_OK : fail(error, error_size, path, "out of memory");
}

static ImageIoStatus read_exr(const char *path, RgbImage *image, char *error, size_t error_size)
{
    ExrImage exr;
    char why[1024];
    if (exr_image_read(path, &exr, why, sizeof why) != IMAGE_IO_OK) {
        /* "path: cause", where the cause may quote the file's channel names. */
        image_printable(why, error, error_size);
        exr_image_free(&exr);
        return IMAGE_IO_ERROR;
    }
    const ExrRgbLayer *layer = exr_image_layer(&exr, ""), *integers = NULL;
    if (layer && layer->is_int) {
        integers = layer;
        layer = NULL;
    }
    for (int i = 0; !layer && !integers && i < exr.layer_count; ++i)
        if (!exr.layers[i].is_int)
            layer = &exr.layers[i];
    ImageIoStatus status = IMAGE_IO_ERROR;
    if (integers) {
        fail(error, error_size, path, "channels R, G, B are UINT (integers); an image needs HALF or FLOAT ones");
    } else if (!layer)
        fail(error, error_size, path, "no HALF or FLOAT R, G, B channels");
    else if (allocate(image, (uint64_t)exr.width, (uint64_t)exr.height, error, error_size, path) == IMAGE_IO_OK) {
        memcpy(image->rgb, layer->data, (size_t)exr.width * exr.height * 3 * sizeof(float));
        status = IMAGE_IO_OK;
    }
    exr_image_free(&exr);
    return status;
}

/* PFM: rows of 32-bit floats from the bottom (image_probe checked the
 * header and that the file holds them). */
static ImageIoStatus read_pfm(const char *path, const ImageFile *file, RgbImage *image, char *error, size_t error_size)
{
    const ImageHeader *h = &file->header;
    if (allocate(image, h->width, h->height, error, error_size, path) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    int little = h->pfm_scale < 0.0, channels = h->pfm_channels;
    float scale = (float)fabs(h->pfm_scale);
    const unsigned char *b = file->data + h->pfm_data;
    for (uint32_t y = 0; y < h->height; ++y) {
        float *out = image->rgb + (size_t)(h->height - 1 - y) * h->width * 3;
        for (size_t i = 0; i < (size_t)h->width * channels; ++i, b += 4) {
            uint32_t bits = little ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                                   : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
            float v;
            memcpy(&v, &bits, sizeof v);
            v *= scale;
            if (channels == 3)
                out[i] = v;
            else
                out[3 * i] = out[3 * i + 1] = out[3 * i + 2] = v;
        }
    }
    return IMAGE_IO_OK;
}

static float srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

static int stb_length(const ImageFile *file)
{
    return (int)file->size; /* at most IMAGE_MAX_FILE_BYTES */
}

/* The image in the file's own channels (grey, grey and alpha, RGB, RGBA):
 * stb 2.27 converts 16-bit PNM channels with its 8-bit code, so
 * conversions are done here. */
static void *load_native(const ImageFile *file, int hdr, int wide, int *width, int *height, int *channels)
{
    if (hdr)
        return stbi_loadf_from_memory(file->data, stb_length(file), width, height, channels, 0);
    if (wide)
        return stbi_load_16_from_memory(file->data, stb_length(file), width, height, channels, 0);
    if (file->header.format == IMAGE_FORMAT_PIC) {
        /* stb 2.27's PIC loader, asked for the file's own channels,
         * converts the NULL image a decoding error leaves (a crash): ask for
         * RGBA, then drop the alpha where the file has none. */
        unsigned char *rgba = stbi_load_from_memory(file->data, stb_length(file), width, height, channels, 4);
        if (rgba && *channels == 3)
            for (size_t i = 0, n = (size_t)*width * (size_t)*height; i < n; ++i)
                for (int c = 0; c < 3; ++c)
                    rgba[3 * i + (size_t)c] = rgba[4 * i + (size_t)c];
        return rgba;
    }
    return stbi_load_from_memory(file->data, stb_length(file), width, height, channels, 0);
}

/* Where channel c (0 to 2; of one channel if grey) of texel i lies. */
static size_t native_index(size_t i, int c, int channels)
{
    return i * (size_t)channels + (channels <= 2 ? 0 : (size_t)c);
}

static ImageIoStatus read_stb(const char *path, const ImageFile *file, RgbImage *image, char *error, size_t error_size)
{
    int width = 0, height = 0, channels = 0;
    int hdr = file->header.format == IMAGE_FORMAT_HDR;
    int wide = !hdr && stbi_is_16_bit_from_memory(file->data, stb_length(file));
    void *data = load_native(file, hdr, wide, &width, &height, &channels);
    if (!data)
        return fail_stb(error, error_size, path, file);
    ImageIoStatus status = decoded_as_probed(file, width, height, channels)
                               ? allocate(image, (uint64_t)width, (uint64_t)height, error, error_size, path)
                               : fail(error, error_size, path, "decoded at another size than its header gives");
    size_t n = (size_t)width * height * 3;
    for (size_t i = 0; i < n && status == IMAGE_IO_OK; ++i) {
        size_t k = native_index(i / 3, (int)(i % 3), channels);
        if (hdr)
            image->rgb[i] = ((const float *)data)[k];
        else if (wide)
            image->rgb[i] = srgb_to_linear(((const uint16_t *)data)[k] / 65535.0f);
        else
            image->rgb[i] = srgb_to_linear(((const unsigned char *)data)[k] / 255.0f);
    }
    stbi_image_free(data);
    return status;
}

static ImageIoStatus read_rgb(const char *path, const ImageFile *file, RgbImage *image, char *error, size_t error_size)
{
    memset(image, 0, sizeof *image);
    ImageIoStatus status = file->header.format == IMAGE_FORMAT_EXR   ? read_exr(path, image, error, error_size)
                           : file->header.format == IMAGE_FORMAT_PFM ? read_pfm(path, file, image, error, error_size)
                                                                     : read_stb(path, file, image, error, error_size);
    if (status != IMAGE_IO_OK)
        rgb_image_free(image);
    return status;
}

ImageIoStatus image_read_rgb(const char *path, RgbImage *image, char *error, size_t error_size)
{
    memset(image, 0, sizeof *image);
    ImageFile file;
    if (image_open(path, &file, error, error_size) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    ImageIoStatus status = read_rgb(path, &file, image, error, error_size);
    free(file.data);
    return status;
}

void texture_image_free(TextureImage *image)
{
    free(image->bytes);
    free(image->floats);
    memset(image, 0, sizeof *image);
}

/* An 8- or 16-bit file through stb: its bytes, or its values as floats. */
static ImageIoStatus read_stb_texture(const char *path, const ImageFile *file, TextureImage *image, char *error,
                                      size_t error_size)
{
    int width = 0, height = 0, channels = 0;
    int wide = stbi_is_16_bit_from_memory(file->data, stb_length(file));
    void *data = load_native(file, 0, wide, &width, &height, &channels);
    if (!data)
        return fail_stb(error, error_size, path, file);
    if (!decoded_as_probed(file, width, height, channels)) {
        stbi_image_free(data);
        return fail(error, error_size, path, "decoded at another size than its header gives");
    }
    int wanted = channels <= 2 ? 1 : 3; /* alpha dropped */
    size_t n = (size_t)width * height * wanted;
    image->width = (uint32_t)width;
    image->height = (uint32_t)height;
    image->channels = (uint32_t)wanted;
    if (wide) {
        image->floats = malloc(n * sizeof *image->floats);
        for (size_t i = 0; image->floats && i < n; ++i)
            image->floats[i] =
                ((const uint16_t *)data)[native_index(i / wanted, (int)(i % wanted), channels)] / 65535.0f;
        image->needs_decoding = 1;
    } else {
        image->bytes = malloc(n);
        for (size_t i = 0; image->bytes && i < n; ++i)
            image->bytes[i] = ((const unsigned char *)data)[native_index(i / wanted, (int)(i % wanted), channels)];
    }
    stbi_image_free(data);
    if (!image->bytes && !image->floats)
        return fail(error, error_size, path, "out of memory");
    return IMAGE_IO_OK;
}

ImageIoStatus image_read_texture(const char *path, TextureImage *image, char *error, size_t error_size)
{
    memset(image, 0, sizeof *image);
    ImageFile file;
    if (image_open(path, &file, error, error_size) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;
    ImageFormat format = file.header.format;
    ImageIoStatus status;
    if (format == IMAGE_FORMAT_EXR || format == IMAGE_FORMAT_PFM || format == IMAGE_FORMAT_HDR) {
        RgbImage rgb;
        status = read_rgb(path, &file, &rgb, error, error_size);
        if (status == IMAGE_IO_OK) {
            image->width = rgb.width;
            image->height = rgb.height;
            image->floats = rgb.rgb;
            /* Grey (as the readers replicate grey files to RGB): one channel. */
            size_t n = (size_t)rgb.width * rgb.height, grey = 1;
            for (size_t i = 0; i < n && grey; ++i)
                grey = rgb.rgb[3 * i] == rgb.rgb[3 * i + 1] && rgb.rgb[3 * i] == rgb.rgb[3 * i + 2];
            for (size_t i = 0; i < n && grey; ++i)
                image->floats[i] = rgb.rgb[3 * i];
            image->channels = grey ? 1 : 3;
        }
    } else {
        status = read_stb_texture(path, &file, image, error, error_size);
        if (status != IMAGE_IO_OK)
            texture_image_free(image);
    }
    free(file.data);
    return status;
}
