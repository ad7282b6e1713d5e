/* Fixtures shared by the scene reader's tests (test_scene_parser,
 * test_scene_shapes; each includes this once, after <cmocka.h>): scene text
 * written to a temporary directory, made by `setup` and removed with what
 * was written there by `teardown`, loaded with expectations on the result. */
#ifndef TESTS_SUPPORT_SCENE_FIXTURE_H
#define TESTS_SUPPORT_SCENE_FIXTURE_H

#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char temp_dir[64];
static char *created[512]; /* files and directories to remove, in creation order */
static int created_count;

static inline const char *temp_path(const char *relative)
{
    static char path[4][512];
    static int next;
    char *out = path[next++ % 4];
    snprintf(out, sizeof path[0], "%s/%s", temp_dir, relative);
    return out;
}

static inline void remember(const char *path)
{
    for (int i = 0; i < created_count; ++i)
        if (strcmp(created[i], path) == 0)
            return;
    assert_true(created_count < (int)(sizeof created / sizeof created[0]));
    created[created_count] = malloc(strlen(path) + 1);
    strcpy(created[created_count++], path);
}

/* Writes temp_dir/relative, creating its directories. Returns the path. */
static inline const char *write_bytes(const char *relative, const void *data, size_t size)
{
    char dir[512];
    for (const char *slash = strchr(relative, '/'); slash; slash = strchr(slash + 1, '/')) {
        snprintf(dir, sizeof dir, "%s/%.*s", temp_dir, (int)(slash - relative), relative);
        if (mkdir(dir, 0700) == 0)
            remember(dir);
    }
    const char *path = temp_path(relative);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
    remember(path);
    return path;
}

static inline const char *write_text(const char *relative, const char *text)
{
    return write_bytes(relative, text, strlen(text));
}

static inline int setup(void **state)
{
    (void)state;
    strcpy(temp_dir, "/tmp/gmon-scene-XXXXXX");
    return mkdtemp(temp_dir) ? 0 : -1;
}

static inline int teardown(void **state)
{
    (void)state;
    for (int i = created_count - 1; i >= 0; --i) {
        remove(created[i]);
        free(created[i]);
    }
    created_count = 0;
    return rmdir(temp_dir);
}

static char error[1024];

/* Writes `text` to temp_dir/name and loads it; returns scene_load's result. */
static inline int load_text(const char *name, const char *text, Scene *scene, int allow_unsupported)
{
    SceneLoadOptions options = {.allow_unsupported = allow_unsupported};
    error[0] = '\0';
    return scene_load(write_text(name, text), &options, scene, error, sizeof error);
}

/* Loads text that must succeed without warnings. */
static inline void load_ok(const char *text, Scene *scene)
{
    if (load_text("ok.pbrt", text, scene, 0) != 0)
        fail_msg("unexpected error: %s", error);
    for (size_t i = 0; i < scene->warning_count; ++i)
        print_message("warning: %s\n", scene->warnings[i]);
    assert_int_equal(scene->warning_count, 0);
}

/* Loads text that must fail with "<file>:<line>:" and `needle` in the message. */
static inline void load_fails(const char *text, int line, const char *needle)
{
    Scene scene;
    char name[64], location[600];
    static int counter;
    snprintf(name, sizeof name, "bad%d.pbrt", counter++);
    int result = load_text(name, text, &scene, 0);
    if (result == 0)
        fail_msg("%s loaded, expected an error with \"%s\"", name, needle);
    snprintf(location, sizeof location, "%s:%d: ", temp_path(name), line);
    if (strncmp(error, location, strlen(location)) != 0 || !strstr(error, needle))
        fail_msg("error \"%s\"; expected it to start with \"%s\" and contain \"%s\"", error, location, needle);
    assert_int_equal(scene.shape_count, 0); /* emptied on failure */
    assert_null(scene.triangles);
    scene_destroy(&scene);
}

static inline int has_warning(const Scene *scene, const char *needle)
{
    for (size_t i = 0; i < scene->warning_count; ++i)
        if (strstr(scene->warnings[i], needle))
            return 1;
    return 0;
}

#define assert_near(actual, expected, tolerance)                                                                       \
    do {                                                                                                               \
        double a_ = (actual), e_ = (expected);                                                                         \
        if (!(fabs(a_ - e_) <= (tolerance)))                                                                           \
            fail_msg("%s = %.9g, expected %.9g", #actual, a_, e_);                                                     \
    } while (0)

static inline void assert_vec3(const float *v, double x, double y, double z)
{
    assert_near(v[0], x, 1e-5);
    assert_near(v[1], y, 1e-5);
    assert_near(v[2], z, 1e-5);
}

static inline const float *vertex(const Scene *s, size_t triangle, int corner)
{
    return s->positions + 3 * s->triangles[triangle].vertex[corner];
}

#endif
