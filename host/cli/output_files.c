#include "cli/output_files.h"

#include "estimator_core.h"
#include "io/png_image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void replace_extension(const char *path, const char *extension, char *out, size_t size)
{
    snprintf(out, size, "%s", path);
    char *dot = strrchr(out, '.');
    char *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash))
        *dot = '\0';
    size_t length = strlen(out);
    snprintf(out + length, size - length, "%s", extension);
}

const float *preview_image(const char *name, const float *mean, const float *mon, const float *gmon)
{
    return strcmp(name, "mean") == 0 ? mean : (strcmp(name, "mon") == 0 ? mon : gmon);
}

int write_render_files(const char *exr_path, const ExrImage *image, const float *preview, float exposure,
                       const char *preview_name, int quiet)
{
    char error[1024];
    if (exr_image_write(exr_path, image, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    char png_path[4096];
    replace_extension(exr_path, ".png", png_path, sizeof png_path);
    if (png_write_srgb(png_path, image->width, image->height, preview, exposure, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    if (!quiet)
        fprintf(stderr, "wrote %s and %s (preview: %s)\n", exr_path, png_path, preview_name);
    return 0;
}

int write_estimates(const Options *o, const ExrImage *sums, int keep_sets, const char *default_path)
{
    EstimatorSettings settings = o->estimator;
    settings.set_count = sums->metadata.set_count;
    settings.first_sample = sums->metadata.first_sample;
    const size_t pixels = (size_t)sums->width * (size_t)sums->height, values = pixels * 3;
    float *mean = malloc(values * sizeof(float)), *mon = malloc(values * sizeof(float)),
          *gmon = malloc(values * sizeof(float)), *gini = malloc(values * sizeof(float));
    int32_t *trim = malloc(values * sizeof(int32_t));
    int status = 1;
    char error[1024];
    EstimatorImages images = {mean, mon, gmon, gini, trim, values};
    if (!mean || !mon || !gmon || !gini || !trim) {
        fprintf(stderr, "gmonrt: out of memory\n");
    } else if (estimator_from_accumulators(&settings, sums->accumulators,
                                           accumulator_planes((uint32_t)settings.set_count) * pixels, pixels,
                                           sums->metadata.sample_count, &images, error, sizeof error) != ESTIMATOR_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
    } else {
        ExrImage out = *sums;
        out.storage = NULL;
        out.mean = (o->outputs & ESTIMATOR_OUTPUT_MEAN) ? mean : NULL;
        out.mon = (o->outputs & ESTIMATOR_OUTPUT_MON) ? mon : NULL;
        out.gmon = (o->outputs & ESTIMATOR_OUTPUT_GMON) ? gmon : NULL;
        out.gini = o->diagnostics ? gini : NULL;
        out.trim = o->diagnostics ? trim : NULL;
        out.accumulators = keep_sets ? sums->accumulators : NULL;
        out.metadata.gini_mode = settings.gini_mode;
        char exr_path[4096];
        replace_extension(o->outfile ? o->outfile : default_path, ".exr", exr_path, sizeof exr_path);
        status = write_render_files(exr_path, &out, preview_image(o->preview, mean, mon, gmon), o->exposure, o->preview,
                                    o->quiet);
    }
    free(mean);
    free(mon);
    free(gmon);
    free(gini);
    free(trim);
    return status;
}
