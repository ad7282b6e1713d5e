/* The Scene's lifetime, diagnostics, and the small conversions the renderer
 * needs (fields of view, screen windows, roughness to alpha). */
#define _POSIX_C_SOURCE 200809L /* open, fstat, O_CLOEXEC */

#include "scene/scene_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

void scene_destroy(Scene *scene)
{
    free(scene->film_filename);
    free(scene->sampler);
    free(scene->materials);
    free(scene->shapes);
    free(scene->area_lights);
    free(scene->positions);
    free(scene->normals);
    free(scene->triangles);
    free(scene->spheres);
    for (size_t i = 0; i < scene->warning_count; ++i)
        free(scene->warnings[i]);
    free(scene->warnings);
    memset(scene, 0, sizeof *scene);
}

void scene_camera_window(const SceneCamera *camera, unsigned width, unsigned height, float window[4])
{
    double k = camera->projection == SCENE_CAMERA_PERSPECTIVE
                   ? tan(0.5 * (double)camera->fov * 3.14159265358979323846 / 180.0)
                   : (double)camera->scale;
    if (camera->has_screen_window) {
        for (int i = 0; i < 4; ++i)
            window[i] = (float)(camera->screen_window[i] * k);
        return;
    }
    double frame =
        camera->frame_aspect_ratio > 0.0f ? (double)camera->frame_aspect_ratio : (double)width / (double)height;
    float x = (float)(frame > 1.0 ? k * frame : k), y = (float)(frame > 1.0 ? k : k / frame);
    window[0] = -x;
    window[1] = x;
    window[2] = -y;
    window[3] = y;
}

void scene_camera_tan_half_fov(float fov_degrees, unsigned width, unsigned height, float tan_half[2])
{
    SceneCamera camera;
    memset(&camera, 0, sizeof camera);
    camera.projection = SCENE_CAMERA_PERSPECTIVE;
    camera.fov = fov_degrees;
    float window[4];
    scene_camera_window(&camera, width, height, window);
    tan_half[0] = window[1];
    tan_half[1] = window[3];
}

void scene_material_alpha(const SceneMaterial *material, float alpha[2])
{
    for (int i = 0; i < 2; ++i) {
        float r = material->roughness[i];
        alpha[i] = material->remap_roughness ? sqrtf(r) : r;
    }
}

static void format_located(char *out, size_t size, const char *file, int line, const char *prefix, const char *format,
                           va_list args)
{
    int n =
        line > 0 ? snprintf(out, size, "%s:%d: %s", file, line, prefix) : snprintf(out, size, "%s: %s", file, prefix);
    if (n >= 0 && (size_t)n < size)
        vsnprintf(out + n, size - (size_t)n, format, args);
}

int scene_error(Diagnostics *diag, const char *file, int line, const char *format, ...)
{
    if (!diag->error || diag->error_size == 0)
        return -1;
    va_list args;
    va_start(args, format);
    format_located(diag->error, diag->error_size, file, line, "", format, args);
    va_end(args);
    return -1;
}

static int add_warning(Diagnostics *diag, const char *file, int line, const char *substitute, const char *format,
                       va_list args)
{
    char text[512];
    format_located(text, sizeof text, file, line, "warning: ", format, args);
    if (substitute) {
        size_t n = strlen(text);
        snprintf(text + n, sizeof text - n, "; %s", substitute);
    }
    Scene *scene = diag->scene;
    char *copy = scene_strndup(text, strlen(text));
    char **grown = copy ? realloc(scene->warnings, (scene->warning_count + 1) * sizeof *grown) : NULL;
    if (!grown) {
        free(copy);
        return scene_error(diag, file, line, "out of memory");
    }
    scene->warnings = grown;
    scene->warnings[scene->warning_count++] = copy;
    return 0;
}

int scene_warn(Diagnostics *diag, const char *file, int line, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    int result = add_warning(diag, file, line, NULL, format, args);
    va_end(args);
    return result;
}

int scene_unsupported(Diagnostics *diag, const char *file, int line, const char *substitute, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    int result = -1;
    if (diag->allow_unsupported)
        result = add_warning(diag, file, line, substitute, format, args);
    else if (diag->error && diag->error_size > 0)
        format_located(diag->error, diag->error_size, file, line, "", format, args);
    va_end(args);
    return result;
}

int scene_reserve(void **array, size_t *capacity, size_t needed, size_t item_size)
{
    if (needed <= *capacity)
        return 0;
    size_t grown = *capacity ? *capacity : 16;
    while (grown < needed) {
        if (grown > SIZE_MAX / 2)
            return -1;
        grown *= 2;
    }
    if (grown > SIZE_MAX / item_size)
        return -1;
    void *p = realloc(*array, grown * item_size);
    if (!p)
        return -1;
    *array = p;
    *capacity = grown;
    return 0;
}

char *scene_strndup(const char *text, size_t length)
{
    char *copy = malloc(length + 1);
    if (copy) {
        memcpy(copy, text, length);
        copy[length] = '\0';
    }
    return copy;
}

/* "1 GiB" for the size limits in messages. */
static void format_bytes(size_t bytes, char *out, size_t size)
{
    if (bytes >= ((size_t)1 << 30) && bytes % ((size_t)1 << 30) == 0)
        snprintf(out, size, "%zu GiB", bytes >> 30);
    else
        snprintf(out, size, "%zu bytes", bytes);
}

int scene_read_file(const char *path, size_t max_size, char **data, size_t *size, char *why, size_t why_size)
{
    *data = NULL;
    *size = 0;
    /* O_NONBLOCK: opening a FIFO without a writer would wait for one. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        return -1;
    }
    struct stat st;
    char limit[32];
    format_bytes(max_size, limit, sizeof limit);
    if (fstat(fd, &st) != 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(why, why_size, "not a regular file (a directory, device or FIFO)");
        close(fd);
        return -1;
    }
    if ((uintmax_t)st.st_size > max_size) {
        snprintf(why, why_size, "%jd bytes, over the %s limit", (intmax_t)st.st_size, limit);
        close(fd);
        return -1;
    }
    /* Read to the end, not just st_size bytes (the file may have grown),
     * but never more than one byte past the limit, plus the NUL. */
    size_t most = max_size + 2, capacity = (size_t)st.st_size + 2, length = 0;
    char *buffer = malloc(capacity);
    int failed = buffer == NULL;
    if (failed)
        snprintf(why, why_size, "out of memory for %zu bytes", capacity);
    while (!failed) {
        if (length + 1 == capacity) {
            if (capacity == most)
                break; /* one byte past the limit */
            size_t grown = capacity > most / 2 ? most : 2 * capacity;
            char *p = realloc(buffer, grown);
            if (!p) {
                snprintf(why, why_size, "out of memory for %zu bytes", grown);
                failed = 1;
                break;
            }
            buffer = p;
            capacity = grown;
        }
        ssize_t n = read(fd, buffer + length, capacity - 1 - length);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            snprintf(why, why_size, "%s", strerror(errno));
            failed = 1;
        } else if (n == 0) {
            break;
        } else {
            length += (size_t)n;
        }
    }
    close(fd);
    if (!failed && length > max_size) {
        snprintf(why, why_size, "over the %s limit", limit);
        failed = 1;
    }
    if (failed) {
        free(buffer);
        return -1;
    }
    buffer[length] = '\0';
    *data = buffer;
    *size = length;
    return 0;
}
