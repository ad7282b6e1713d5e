#define _POSIX_C_SOURCE 200809L
#include "cli/output_files.h"

#include "cli/interrupt.h"
#include "accumulate.h"
#include "film/film_file.h"
#include "io/png_image.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

int write_replacing(const char *path, OutputWriter writer, const void *data, char *error, size_t error_size)
{
    char temporary[4096];
    if ((size_t)snprintf(temporary, sizeof temporary, "%s.partial-%ld", path, (long)getpid()) >= sizeof temporary) {
        snprintf(error, error_size, "%s: path too long", path);
        return -1;
    }
    interrupt_temporary_file(temporary);
    int status = writer(temporary, data, error, error_size) == 0 ? 0 : -1;
    if (status == 0 && rename(temporary, path) != 0) {
        snprintf(error, error_size, "%s: cannot replace it with %s: %s", path, temporary, strerror(errno));
        status = -1;
    }
    if (status != 0)
        unlink(temporary);
    interrupt_temporary_file(NULL);
    return status;
}

static int write_exr(const char *path, const void *image, char *error, size_t error_size)
{
    return exr_image_write(path, image, error, error_size) != IMAGE_IO_OK;
}

int write_exr_file(const char *path, const ExrImage *image)
{
    char error[1024];
    if (write_replacing(path, write_exr, image, error, sizeof error) == 0)
        return 0;
    fprintf(stderr, "gmonrt: %s\n", error);
    return 1;
}

typedef struct {
    int width, height;
    const float *rgb;
    float exposure;
} PngPreview;

static int write_png(const char *path, const void *data, char *error, size_t error_size)
{
    const PngPreview *p = data;
    return png_write_srgb(path, p->width, p->height, p->rgb, p->exposure, error, error_size) != IMAGE_IO_OK;
}

int check_output_path(const char *path)
{
    char directory[4096];
    snprintf(directory, sizeof directory, "%s", path);
    char *slash = strrchr(directory, '/');
    if (!slash)
        snprintf(directory, sizeof directory, ".");
    else
        slash[slash == directory] = '\0'; /* "/x.exr": the root */
    struct stat info;
    const char *problem = NULL;
    if (stat(directory, &info) != 0)
        problem = strerror(errno);
    else if (!S_ISDIR(info.st_mode))
        problem = "not a directory";
    else if (access(directory, W_OK | X_OK) != 0)
        problem = strerror(errno);
    if (problem) {
        fprintf(stderr, "gmonrt: cannot write %s: directory %s: %s\n", path, directory, problem);
        return 1;
    }
    if (stat(path, &info) == 0 && S_ISDIR(info.st_mode)) {
        fprintf(stderr, "gmonrt: cannot write %s: it is a directory\n", path);
        return 1;
    }
    return 0;
}

int write_render_files(const char *exr_path, const ExrImage *image, const float *preview, float exposure,
                       const char *preview_name)
{
    if (write_exr_file(exr_path, image))
        return 1;
    char png_path[4096], error[1024];
    replace_extension(exr_path, ".png", png_path, sizeof png_path);
    const PngPreview png = {image->width, image->height, preview, exposure};
    if (write_replacing(png_path, write_png, &png, error, sizeof error) != 0) {
        fprintf(stderr, "gmonrt: wrote %s, but not its preview: %s\n", exr_path, error);
        return 1;
    }
    /* Always: a scene's Film "filename" may point anywhere. */
    fprintf(stderr, "wrote %s and %s (preview: %s)\n", exr_path, png_path, preview_name);
    return 0;
}

int options_for_file(const Options *o, const ExrImage *in, Options *chosen, char *error, size_t size)
{
    *chosen = *o;
    if (!o->estimators_given) {
        EstimatorSettings recorded;
        if (film_file_settings(in, &recorded, error, size) != 0)
            return -1;
        chosen->estimator.passes = (recorded.passes & PASSES_ESTIMATES) | (o->estimator.passes & PASSES_DIAGNOSTICS);
        /* Never approximated from other layers: left out, and said so. */
        for (int p = 0; p < PASS_COUNT; ++p)
            if (recorded.passes & PASSES_SAMPLE & PASS_BIT(p))
                fprintf(stderr,
                        "gmonrt: note: the file's %s layers are left out: that estimator needs per-sample state "
                        "that only a render keeps, not the set sums\n",
                        pass_name(p));
        if (!(chosen->estimator.passes & PASSES_ESTIMATES))
            chosen->estimator.passes |= PASSES_DEFAULT;
    }
    return options_check_preview(chosen, error, size) == 0 ? 0 : -1;
}

int write_estimates(const Options *o, const EstimatorSettings *requested, const ExrImage *sums, int keep_sets,
                    const char *default_path)
{
    EstimatorSettings settings = *requested;
    settings.set_count = sums->metadata.set_count;
    settings.first_sample = sums->metadata.first_sample;
    const size_t pixels = (size_t)sums->width * (size_t)sums->height, values = pixels * 3;
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    images.length = values;
    int status = 1, allocated = 1;
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(settings.passes & PASS_BIT(p)))
            continue;
        allocated &= (images.pass[p] = malloc(values * sizeof(float))) != NULL;
        if (settings.with_stderr && (PASSES_ESTIMATES & PASS_BIT(p)))
            allocated &= (images.error[p] = malloc(values * sizeof(float))) != NULL;
    }
    char error[1024];
    if (!allocated) {
        fprintf(stderr, "gmonrt: out of memory\n");
    } else if (estimator_from_accumulators(&settings, sums->accumulators,
                                           accumulator_planes((uint32_t)settings.set_count) * pixels, pixels,
                                           sums->metadata.sample_count, &images, error, sizeof error) != ESTIMATOR_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
    } else {
        static FilmFile file;
        film_file_init(&file, sums->width, sums->height, &settings, &images);
        ExrImage *out = &file.image;
        out->metadata = sums->metadata;
        out->metadata.attributes = file.attributes;
        out->metadata.attribute_count = FILM_FILE_ATTRIBUTES;
        out->nonfinite = sums->nonfinite;
        out->rounded = sums->rounded;
        out->accumulators = keep_sets ? sums->accumulators : NULL;
        char exr_path[4096];
        replace_extension(o->outfile ? o->outfile : default_path, ".exr", exr_path, sizeof exr_path);
        status = write_render_files(exr_path, out, images.pass[o->preview], o->exposure, pass_name(o->preview));
    }
    for (int p = 0; p < PASS_COUNT; ++p) {
        free(images.pass[p]);
        free(images.error[p]);
    }
    return status;
}
