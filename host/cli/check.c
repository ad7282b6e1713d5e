#include "cli/check.h"

#include "render/render_scene.h"
#include "render/scene_convert.h"
#include "scene/scene.h"

#include <stdio.h>

/* "file:line: " (or "file: " for the file as a whole). */
static void print_location(const SceneDiagnostic *d)
{
    if (d->line > 0)
        printf("%s:%d: ", d->file, d->line);
    else
        printf("%s: ", d->file);
}

/* Prints the diagnostics of one kind; returns how many. */
static size_t print_diagnostics(const Scene *scene, SceneDiagnosticKind kind)
{
    size_t count = 0;
    for (size_t i = 0; i < scene->diagnostic_count; ++i) {
        const SceneDiagnostic *d = &scene->diagnostics[i];
        if (d->kind != kind)
            continue;
        print_location(d);
        if (kind == SCENE_DIAGNOSTIC_UNSUPPORTED)
            printf("unsupported: %s; with --allow-unsupported: %s\n", d->message, d->substitute);
        else
            printf("missing file: \"%s\" (%s)\n", d->path, d->message);
        count++;
    }
    return count;
}

int check_command(const Options *o)
{
    Scene scene;
    SceneLoadOptions load = {.check = 1};
    char error[2048];
    if (scene_load(o->input, &load, &scene, error, sizeof error)) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    for (size_t i = 0; i < scene.warning_count; ++i)
        printf("%s\n", scene.warnings[i]);
    for (size_t i = 0; i < scene.note_count; ++i)
        printf("%s\n", scene.notes[i]);
    size_t unsupported = print_diagnostics(&scene, SCENE_DIAGNOSTIC_UNSUPPORTED);
    size_t missing = print_diagnostics(&scene, SCENE_DIAGNOSTIC_MISSING_FILE);
    fflush(stdout); /* before the conversion's own warnings on stderr */

    /* Converted as for a render (BVH and light distribution included), so
     * that what fails there fails here. */
    RenderScene converted;
    SceneSummary summary;
    int failed = scene_convert(&scene, o->input, 0, 0, 0, &converted, &summary, error, sizeof error) ||
                 render_scene_finalize(&converted, error, sizeof error);
    if (!failed && scene.instance_count > 0)
        printf("instancing: %zu object%s, %d instance%s drawn (a two-level BVH)\n", scene.object_count,
               scene.object_count == 1 ? "" : "s", converted.instance_count, converted.instance_count == 1 ? "" : "s");
    render_scene_destroy(&converted);
    scene_destroy(&scene);
    if (failed) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    printf("%zu unsupported feature%s, %zu missing file%s\n", unsupported, unsupported == 1 ? "" : "s", missing,
           missing == 1 ? "" : "s");
    return unsupported > 0 ? 1 : (missing > 0 ? CHECK_ONLY_FILES_MISSING : 0);
}
