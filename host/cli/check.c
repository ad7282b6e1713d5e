#include "cli/check.h"

#include "render/render_scene.h"
#include "render/caustic_check.h"
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

/* The warnings, notes, unsupported features and missing files, in that
 * order; returns how many unsupported features and missing files. */
static void print_findings(const Scene *scene, size_t *unsupported, size_t *missing)
{
    for (size_t i = 0; i < scene->warning_count; ++i)
        printf("%s\n", scene->warnings[i]);
    for (size_t i = 0; i < scene->note_count; ++i)
        printf("%s\n", scene->notes[i]);
    *unsupported = print_diagnostics(scene, SCENE_DIAGNOSTIC_UNSUPPORTED);
    *missing = print_diagnostics(scene, SCENE_DIAGNOSTIC_MISSING_FILE);
    fflush(stdout); /* before what follows on stderr */
}

int check_command(const Options *o)
{
    Scene scene;
    SceneLoadOptions load = {.check = 1};
    char error[2048];
    size_t unsupported, missing;
    if (scene_load(o->input, &load, &scene, error, sizeof error)) {
        /* What was found before the error, then the error: the scene was
         * not read to its end, so the lists may be incomplete. */
        print_findings(&scene, &unsupported, &missing);
        scene_destroy(&scene);
        printf("check stopped at an error: %zu unsupported feature%s, %zu missing file%s found before it\n",
               unsupported, unsupported == 1 ? "" : "s", missing, missing == 1 ? "" : "s");
        fflush(stdout);
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    print_findings(&scene, &unsupported, &missing);

    /* Converted as for a render (BVH and light distribution included), so
     * that what fails there fails here. */
    RenderScene converted;
    SceneSummary summary;
    int failed = scene_convert(&scene, o->input, 0, 0, 0, &converted, &summary, error, sizeof error) ||
                 render_scene_finalize(&converted, error, sizeof error);
    if (!failed)
        caustic_check_print(&converted, stdout, "");
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
