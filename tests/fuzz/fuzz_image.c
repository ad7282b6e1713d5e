/* libFuzzer harness: an image file -> the checks (image_probe) and both
 * readers of host/io/image_read.c: image_read_texture (an "imagemap"
 * texture: 8-bit files as bytes) and image_read_rgb (a light's image:
 * linear floats). An image read without error must hold every texel its
 * size promises, and the error text must be printable. */
#include "fuzz_input.h"
#include "io/image_probe.h"
#include "io/image_read.h"

#include <stdlib.h>
#include <string.h>

/* Decoding stays under this many texels: a header within IMAGE_MAX_TEXELS
 * over a file the fuzzer grew to 64 KB (a GIF's LZW data may promise 2730
 * texels a byte) would make stb allocate and clear gigabytes, which is
 * slow and trips libFuzzer's memory limit without being a bug. The checks
 * still see every input. */
#define FUZZ_MAX_TEXELS ((uint64_t)1 << 22)

static const char *image_path;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    image_path = fuzz_input_path("image");
    return 0;
}

static void check_printable(const char *error)
{
    for (const unsigned char *c = (const unsigned char *)error; *c; ++c)
        if (*c < 0x20 || *c >= 0x7f)
            abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ImageHeader header;
    char error[1024];
    if (image_probe(data, size, &header, error, sizeof error) != IMAGE_IO_OK) {
        check_printable(error);
        return 0;
    }
    if ((uint64_t)header.width * header.height > FUZZ_MAX_TEXELS)
        return 0;
    fuzz_write_file(image_path, data, size);
    TextureImage texture;
    error[0] = '\0';
    if (image_read_texture(image_path, &texture, error, sizeof error) == IMAGE_IO_OK) {
        size_t n = (size_t)texture.width * texture.height * texture.channels;
        if (texture.bytes)
            fuzz_touch(texture.bytes, n);
        else
            fuzz_touch(texture.floats, n * sizeof *texture.floats);
    }
    check_printable(error);
    texture_image_free(&texture);
    RgbImage rgb;
    error[0] = '\0';
    if (image_read_rgb(image_path, &rgb, error, sizeof error) == IMAGE_IO_OK)
        fuzz_touch(rgb.rgb, (size_t)rgb.width * rgb.height * 3 * sizeof *rgb.rgb);
    check_printable(error);
    rgb_image_free(&rgb);
    return 0;
}
