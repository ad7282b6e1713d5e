/* Writes the EXR harness's seeds into a directory with the project's own
 * writer: small renders with every layer and two sets, and with the mean
 * alone. Usage: make_exr_seeds DIR */
#include "accumulate.h" /* accumulator_planes */
#include "io/exr_image.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int write_seed(const char *directory, const char *name, const ExrImage *image)
{
    char path[4096], error[1024];
    snprintf(path, sizeof path, "%s/%s", directory, name);
    if (exr_image_write(path, image, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "make_exr_seeds: %s\n", error);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_exr_seeds DIR\n");
        return 2;
    }
    enum { WIDTH = 3, HEIGHT = 2, PIXELS = WIDTH * HEIGHT, SETS = 2 };
    float rgb[3 * PIXELS];
    int32_t trim[3 * PIXELS];
    uint32_t nonfinite[PIXELS], rounded[PIXELS];
    size_t words = accumulator_planes(SETS) * PIXELS; /* the grid plane, then [set][channel][word][pixel] */
    uint64_t *sums = calloc(words, sizeof *sums);
    if (!sums)
        return 1;
    for (int i = 0; i < 3 * PIXELS; ++i) {
        rgb[i] = 0.125f * (float)i;
        trim[i] = i % 2;
    }
    for (int i = 0; i < PIXELS; ++i) {
        nonfinite[i] = (uint32_t)i;
        rounded[i] = (uint32_t)(i % 2);
        sums[i] = i == 0 ? 0 : EXR_GRID_WORD_MIN + (uint64_t)i; /* grid words */
    }
    for (size_t i = PIXELS; i < words; ++i)
        sums[i] = (uint64_t)i << 40;
    const ExrKeyValue extras[] = {{"render.device", "fuzz seed"}};
    const ExrKeyValue attributes[] = {{"gmon.giniMode", "per_pixel"}, {"gmon.estimators", "mean,mon,gmon,gini,trim"}};
    ExrImage full = {
        .width = WIDTH,
        .height = HEIGHT,
        .layers = {{"mean", 0, rgb}, {"mon", 0, rgb}, {"gmon", 0, rgb}, {"gmon.stderr", 0, rgb}, {"trim", 1, trim}},
        .layer_count = 5,
        .nonfinite = nonfinite,
        .rounded = rounded,
        .accumulators = sums,
        .metadata = {.software = "make_exr_seeds",
                     .set_count = SETS,
                     .sample_count = 4,
                     .seed = 7,
                     .first_sample = 0,
                     .scene_path = "scene.pbrt",
                     .scene_hash = "0123456789abcdef",
                     .attributes = attributes,
                     .attribute_count = 2,
                     .nonfinite_samples = 15,
                     .rounded_samples = 3,
                     .extras = extras,
                     .extra_count = 1},
    };
    ExrImage mean_only = {
        .width = 2, .height = 1, .layers = {{"mean", 0, rgb}}, .layer_count = 1, .metadata = {.sample_count = 1}};
    int failed = write_seed(argv[1], "full.exr", &full) || write_seed(argv[1], "mean-only.exr", &mean_only);
    free(sums);
    return failed;
}
