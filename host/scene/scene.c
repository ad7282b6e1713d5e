/* The Scene's lifetime, diagnostics, and the small conversions the renderer
 * needs (fields of view, screen windows, roughness to alpha). */
#define _POSIX_C_SOURCE 200809L /* stat */

#include "scene/scene_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void scene_destroy(Scene *scene)
{
    free(scene->film_filename);
    free(scene->sampler);
    free(scene->light_sampler);
    free(scene->materials);
    for (size_t i = 0; i < scene->medium_count; ++i) {
        free(scene->media[i].name);
        free(scene->media[i].origin);
        free(scene->media[i].density);
        free(scene->media[i].le_scale);
        free(scene->media[i].rgb_sigma_a);
        free(scene->media[i].rgb_sigma_s);
        free(scene->media[i].rgb_le);
        nanovdb_free(&scene->media[i].nanovdb_density);
        nanovdb_free(&scene->media[i].nanovdb_temperature);
    }
    free(scene->media);
    for (size_t i = 0; i < scene->texture_count; ++i) {
        free(scene->textures[i].name);
        free(scene->textures[i].filename);
        free(scene->textures[i].origin);
        free(scene->textures[i].use_parameter);
    }
    free(scene->textures);
    free(scene->shapes);
    for (size_t i = 0; i < scene->area_light_count; ++i)
        free(scene->area_lights[i].origin);
    free(scene->area_lights);
    for (size_t i = 0; i < scene->light_count; ++i) {
        free(scene->lights[i].filename);
        free(scene->lights[i].origin);
    }
    free(scene->lights);
    free(scene->positions);
    free(scene->normals);
    free(scene->uvs);
    free(scene->triangles);
    free(scene->spheres);
    for (size_t i = 0; i < scene->object_count; ++i)
        free(scene->objects[i].name);
    free(scene->objects);
    free(scene->instances);
    for (size_t i = 0; i < scene->warning_count; ++i)
        free(scene->warnings[i]);
    free(scene->warnings);
    for (size_t i = 0; i < scene->note_count; ++i)
        free(scene->notes[i]);
    free(scene->notes);
    for (size_t i = 0; i < scene->diagnostic_count; ++i) {
        SceneDiagnostic *d = &scene->diagnostics[i];
        free(d->file);
        free(d->message);
        free(d->substitute);
        free(d->path);
    }
    free(scene->diagnostics);
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

void scene_roughness_alpha(const float roughness[2], int remap_roughness, float alpha[2])
{
    for (int i = 0; i < 2; ++i)
        alpha[i] = remap_roughness ? sqrtf(roughness[i]) : roughness[i];
}

void scene_material_alpha(const SceneMaterial *material, float alpha[2])
{
    scene_roughness_alpha(material->roughness, material->remap_roughness, alpha);
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

/* Appends a copy of `text` to lines[*count], unless it is there already
 * (the same line of a file included twice says the same thing twice). */
static int append_unique(char ***lines, size_t *count, const char *text)
{
    for (size_t i = 0; i < *count; ++i)
        if (strcmp((*lines)[i], text) == 0)
            return 0;
    char *copy = scene_strndup(text, strlen(text));
    char **grown = copy ? realloc(*lines, (*count + 1) * sizeof *grown) : NULL;
    if (!grown) {
        free(copy);
        return -1;
    }
    *lines = grown;
    (*lines)[(*count)++] = copy;
    return 0;
}

/* "file:line: <prefix>message[; substitute]" appended to lines (once). */
static int add_line(Diagnostics *diag, char ***lines, size_t *count, const char *file, int line, const char *prefix,
                    const char *substitute, const char *format, va_list args)
{
    char text[512];
    format_located(text, sizeof text, file, line, prefix, format, args);
    if (substitute) {
        size_t n = strlen(text);
        snprintf(text + n, sizeof text - n, "; %s", substitute);
    }
    if (append_unique(lines, count, text))
        return scene_error(diag, file, line, "out of memory");
    return 0;
}

int scene_warn(Diagnostics *diag, const char *file, int line, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    Scene *s = diag->scene;
    int result = add_line(diag, &s->warnings, &s->warning_count, file, line, "warning: ", NULL, format, args);
    va_end(args);
    return result;
}

int scene_note(Diagnostics *diag, const char *file, int line, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    Scene *s = diag->scene;
    int result = add_line(diag, &s->notes, &s->note_count, file, line, "note: ", NULL, format, args);
    va_end(args);
    return result;
}

static int same_text(const char *a, const char *b)
{
    return a == b || (a && b && strcmp(a, b) == 0);
}

/* Records a check-mode diagnostic, once for each distinct one. */
static int add_diagnostic(Diagnostics *diag, SceneDiagnosticKind kind, const char *file, int line, const char *message,
                          const char *substitute, const char *path)
{
    Scene *s = diag->scene;
    for (size_t i = 0; i < s->diagnostic_count; ++i) {
        const SceneDiagnostic *d = &s->diagnostics[i];
        if (d->kind == kind && d->line == line && strcmp(d->file, file) == 0 && strcmp(d->message, message) == 0 &&
            same_text(d->substitute, substitute) && same_text(d->path, path))
            return 0;
    }
    SceneDiagnostic *grown = realloc(s->diagnostics, (s->diagnostic_count + 1) * sizeof *grown);
    if (!grown)
        return scene_error(diag, file, line, "out of memory");
    s->diagnostics = grown;
    SceneDiagnostic *d = &s->diagnostics[s->diagnostic_count];
    d->kind = kind;
    d->line = line;
    d->file = scene_strndup(file, strlen(file));
    d->message = scene_strndup(message, strlen(message));
    d->substitute = substitute ? scene_strndup(substitute, strlen(substitute)) : NULL;
    d->path = path ? scene_strndup(path, strlen(path)) : NULL;
    s->diagnostic_count++; /* counted even when a copy failed: scene_destroy frees what there is */
    if (!d->file || !d->message || (substitute && !d->substitute) || (path && !d->path))
        return scene_error(diag, file, line, "out of memory");
    return 0;
}

int scene_unsupported(Diagnostics *diag, const char *file, int line, const char *substitute, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    int result = -1;
    Scene *s = diag->scene;
    if (diag->check) {
        char message[512];
        vsnprintf(message, sizeof message, format, args);
        result = add_diagnostic(diag, SCENE_DIAGNOSTIC_UNSUPPORTED, file, line, message, substitute, NULL);
    } else if (diag->allow_unsupported) {
        result = add_line(diag, &s->warnings, &s->warning_count, file, line, "warning: ", substitute, format, args);
    } else if (diag->error && diag->error_size > 0) {
        format_located(diag->error, diag->error_size, file, line, "", format, args);
    }
    va_end(args);
    return result;
}

int scene_missing_file(Diagnostics *diag, const char *file, int line, const char *path, const char *what)
{
    struct stat st;
    if (!diag->check || stat(path, &st) == 0 || errno != ENOENT)
        return 0; /* there (or unreadable for another reason, which reading reports) */
    return add_diagnostic(diag, SCENE_DIAGNOSTIC_MISSING_FILE, file, line, what, NULL, path) ? -1 : 1;
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

/* stat, not open: opening a FIFO could block. */
int scene_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* A path relative to the directory of `from` (a file), unless absolute. */
static char *path_relative_to(const char *from, const char *name)
{
    if (name[0] == '/' || !from)
        return scene_strndup(name, strlen(name));
    const char *slash = strrchr(from, '/');
    size_t dir = slash ? (size_t)(slash - from) + 1 : 0;
    size_t length = strlen(name);
    char *path = malloc(dir + length + 1);
    if (path) {
        memcpy(path, from, dir);
        memcpy(path + dir, name, length + 1);
    }
    return path;
}

char *scene_resolve_path(const char *file, const char *main_file, const char *name)
{
    char *path = path_relative_to(main_file, name);
    if (path && !scene_file_exists(path)) {
        char *beside = path_relative_to(file, name);
        if (beside && scene_file_exists(beside)) {
            free(path);
            return beside;
        }
        free(beside);
    }
    return path;
}
