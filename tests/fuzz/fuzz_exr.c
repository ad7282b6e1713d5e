/* libFuzzer harness: an EXR file -> exr_image_read (host/io/exr_image.c),
 * the reader of `gmonrt estimate` and `merge`. An image read without error
 * must own every layer it reports, at the size its header says. */
#include "fuzz_input.h"
#include "estimator_core.h" /* accumulator_planes */
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
        const float *rgb_layers[] = {image.mean, image.mon, image.gmon, image.gini};
        for (size_t i = 0; i < sizeof rgb_layers / sizeof rgb_layers[0]; ++i)
            if (rgb_layers[i])
                fuzz_touch(rgb_layers[i], 3 * pixels * sizeof(float));
        if (image.trim)
            fuzz_touch(image.trim, 3 * pixels * sizeof *image.trim);
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
        for (size_t i = 0; i < meta->extra_count; ++i) {
            fuzz_touch(meta->extras[i].key, strlen(meta->extras[i].key) + 1);
            fuzz_touch(meta->extras[i].value, strlen(meta->extras[i].value) + 1);
        }
    }
    exr_image_free(&image);
    return 0;
}
