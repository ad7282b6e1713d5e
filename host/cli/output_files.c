#include "cli/output_files.h"

#include "io/png_image.h"

#include <stdio.h>
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
