/* libFuzzer harness: an EXR file -> exr_image_read (host/io/exr_image.c),
 * the reader of `gmonrt estimate` and `merge`. An image read without error
 * must own every layer it reports, at the size its header says. */
#include "fuzz_input.h"
#include "accumulate.h" /* accumulator_planes */
#include "io/exr_image.h"

#include <string.h>

static const char *exr_path;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    exr_path = fuzz_input_path("render.exr");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_write_file(exr_path, data, size);
    ExrImage image;
    char error[1024];
    if (exr_image_read(exr_path, &image, error, sizeof error) == IMAGE_IO_OK) {
        size_t pixels = (size_t)image.width * (size_t)image.height;
        for (int i = 0; i < image.layer_count; ++i) {
            fuzz_touch(image.layers[i].name, strlen(image.layers[i].name) + 1);
            fuzz_touch(image.layers[i].data, 3 * pixels * sizeof(float));
        }
        if (image.nonfinite)
            fuzz_touch(image.nonfinite, pixels * sizeof *image.nonfinite);
        if (image.rounded)
            fuzz_touch(image.rounded, pixels * sizeof *image.rounded);
        if (image.accumulators)
            fuzz_touch(image.accumulators,
                       accumulator_planes((uint32_t)image.metadata.set_count) * pixels * sizeof *image.accumulators);
        const ExrMetadata *meta = &image.metadata;
        const char *strings[] = {meta->software, meta->scene_path, meta->scene_hash};
        for (size_t i = 0; i < sizeof strings / sizeof strings[0]; ++i)
            if (strings[i])
                fuzz_touch(strings[i], strlen(strings[i]) + 1);
        for (size_t i = 0; i < meta->attribute_count; ++i) {
            fuzz_touch(meta->attributes[i].key, strlen(meta->attributes[i].key) + 1);
            fuzz_touch(meta->attributes[i].value, strlen(meta->attributes[i].value) + 1);
        }
        for (size_t i = 0; i < meta->extra_count; ++i) {
            fuzz_touch(meta->extras[i].key, strlen(meta->extras[i].key) + 1);
            fuzz_touch(meta->extras[i].value, strlen(meta->extras[i].value) + 1);
        }
    }
    exr_image_free(&image);
    return 0;
}
