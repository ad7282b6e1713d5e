#define _POSIX_C_SOURCE 200809L
#include "cli/checkpoints.h"

#include "cli/output_files.h"
#include "film/film_sample.h"
#include "render/render_exr.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int checkpoints_open(Checkpoints *c, const char *directory, const char *reference_path, unsigned width, unsigned height,
                     char *error, size_t error_size)
{
    memset(c, 0, sizeof *c);
    c->directory = directory;
    if (mkdir(directory, 0777) != 0 && errno != EEXIST) {
        snprintf(error, error_size, "--checkpoints: cannot create directory %s: %s", directory, strerror(errno));
        return -1;
    }
    if (reference_path) {
        ExrImage reference;
        char message[1024];
        if (exr_image_read(reference_path, &reference, message, sizeof message) != IMAGE_IO_OK) {
            snprintf(error, error_size, "--reference: %s", message);
            exr_image_free(&reference);
            return -1;
        }
        const float *mean = film_file_pass(&reference, PASS_MEAN, 0);
        int usable = mean && reference.width == (int)width && reference.height == (int)height;
        if (usable) {
            size_t bytes = (size_t)width * height * 3 * sizeof(float);
            if ((c->reference = malloc(bytes)))
                memcpy(c->reference, mean, bytes);
        }
        exr_image_free(&reference);
        if (!usable) {
            snprintf(error, error_size, "--reference %s: needs a mean layer of %ux%u pixels", reference_path, width,
                     height);
            return -1;
        }
        if (!c->reference) {
            snprintf(error, error_size, "out of memory");
            return -1;
        }
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/checkpoints.csv", directory);
    c->csv = fopen(path, "w");
    if (!c->csv) {
        snprintf(error, error_size, "--checkpoints: cannot write %s: %s", path, strerror(errno));
        free(c->reference);
        c->reference = NULL;
        return -1;
    }
    fprintf(c->csv, "spp,seconds,estimator,rmse,relmse\n");
    return 0;
}

void image_errors(const float *image, const float *reference, size_t values, double *rmse, double *relmse)
{
    double squared = 0.0, relative = 0.0;
    for (size_t i = 0; i < values; ++i) {
        double d = (double)image[i] - (double)reference[i];
        double r = reference[i];
        squared += d * d;
        relative += d * d / (r * r + 0.01);
    }
    *rmse = sqrt(squared / (double)values);
    *relmse = relative / (double)values;
}

int checkpoints_write(void *user, const RenderOutput *out)
{
    Checkpoints *c = user;
    char path[4096], seconds[32];
    snprintf(path, sizeof path, "%s/spp-%06llu.exr", c->directory, (unsigned long long)out->sample_count);
    snprintf(seconds, sizeof seconds, "%.6f", out->seconds);
    static FilmFile file; /* large; checkpoints are written one at a time */
    render_output_file(&file, out);
    ExrImage *image = &file.image;
    image->accumulators = NULL;
    image->nonfinite = NULL;
    image->rounded = NULL;
    image->metadata.scene_path = c->scene_path;
    const ExrKeyValue extras[] = {{"seconds", seconds}};
    image->metadata.extras = extras;
    image->metadata.extra_count = 1;
    if (write_exr_file(path, image))
        ++c->failures;
    /* A row for every estimate: the set-based ones and each image of the
     * per-sample ones (clamp's by level), by their layer names. */
    const size_t values = (size_t)out->width * out->height * 3;
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!((PASSES_ESTIMATES | PASSES_SAMPLE) & PASS_BIT(p)) || !out->pass[p])
            continue;
        const int images = (PASSES_SAMPLE & PASS_BIT(p)) ? film_sample_pass_images(&out->estimator, p) : 1;
        for (int i = 0; i < images; ++i) {
            char name[EXR_LAYER_NAME_CAPACITY];
            film_sample_layer_name(&out->estimator, p, i, name, sizeof name); /* pass_name but clamp's */
            fprintf(c->csv, "%llu,%.6f,%s,", (unsigned long long)out->sample_count, out->seconds, name);
            if (c->reference) {
                double rmse = 0.0, relmse = 0.0;
                image_errors((const float *)out->pass[p] + (size_t)i * values, c->reference, values, &rmse, &relmse);
                fprintf(c->csv, "%.9g,%.9g\n", rmse, relmse);
            } else {
                fprintf(c->csv, ",\n");
            }
        }
    }
    if (fflush(c->csv) != 0) {
        fprintf(stderr, "gmonrt: writing %s/checkpoints.csv failed: %s\n", c->directory, strerror(errno));
        ++c->failures;
    }
    return 0;
}

int checkpoints_close(Checkpoints *c)
{
    int status = c->failures ? -1 : 0;
    if (c->csv && fclose(c->csv) != 0) {
        fprintf(stderr, "gmonrt: writing %s/checkpoints.csv failed: %s\n", c->directory, strerror(errno));
        status = -1;
    }
    free(c->reference);
    memset(c, 0, sizeof *c);
    return status;
}
