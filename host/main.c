/* gmonrt: renders a pbrt-v4 scene with the OpenCL path tracer and writes the
 * mean, MoN and G-MoN of the same samples to one EXR plus a PNG preview. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "cli/checkpoints.h"
#include "cli/devices.h"
#include "cli/merge.h"
#include "cli/options.h"
#include "cli/output_files.h"
#include "cli/progress.h"
#include "estimator/estimator.h"
#include "io/exr_image.h"
#include "render/render_exr.h"
#include "render/renderer.h"
#include "render/scene_convert.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GMON_DEFAULT_SCENE
#define GMON_DEFAULT_SCENE "scenes/cornell-glass.pbrt"
#endif

static volatile sig_atomic_t interrupted;

static void on_interrupt(int signal_number)
{
    (void)signal_number;
    interrupted = 1;
}

static const char *gini_mode_name(GiniMode mode)
{
    return mode == GINI_PER_PIXEL ? "pixel" : (mode == SORT_BY_LUMINANCE ? "luminance" : "channel");
}

/* The summary: one line for the render, then one per device when there are
 * several (or one failed). */
static void print_summary(const Options *o, const RenderOutput *out)
{
    double samples = (double)out->sample_count * out->width * out->height;
    double seconds = out->seconds > 0.0 ? out->seconds : 1e-9;
    printf("%ux%u, %llu spp, M = %d, gini %s, %.2f s, %.3g samples/s, %.3g rays/s, %llu non-finite samples, "
           "%llu rounded samples, %zu bytes per pixel, %d device%s\n",
           out->width, out->height, (unsigned long long)out->sample_count, out->set_count,
           gini_mode_name(o->estimator.gini_mode), out->seconds, samples / seconds, (double)out->rays / seconds,
           (unsigned long long)out->rejected_total, (unsigned long long)out->rounded_total, out->bytes_per_pixel,
           out->device_count, out->device_count == 1 ? "" : "s");
    uint64_t total = 0;
    for (int i = 0; i < out->device_count; ++i)
        total += out->devices[i].samples;
    for (int i = 0; i < out->device_count; ++i) {
        const RenderDeviceReport *d = &out->devices[i];
        printf("  device %d '%s': %.1f%% of samples, %.3g samples/s, %.1f MiB allocated, build %.2f s%s%s\n", i,
               d->name, total ? 100.0 * (double)d->samples / (double)total : 0.0,
               d->busy_seconds > 0.0 ? (double)d->samples / d->busy_seconds : 0.0,
               (double)d->peak_bytes / (1024.0 * 1024.0), d->build_seconds, d->failed ? ", FAILED: " : "",
               d->failed ? d->error : "");
    }
    printf("  kernel features 0x%x, %d rebalance%s, start-up %.2f s (program builds and first-launch compiles)\n",
           (unsigned)out->features, out->rebalances, out->rebalances == 1 ? "" : "s", out->build_seconds);
}

static int render(const Options *o)
{
    const char *scene_path = o->input ? o->input : GMON_DEFAULT_SCENE;
    RenderScene scene;
    SceneSummary summary;
    char error[2048];
    if (scene_convert_load(scene_path, o->allow_unsupported, o->width, o->height, o->quiet, &scene, &summary, error,
                           sizeof error)) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    if (!o->quiet && strcmp(summary.sampler, "independent") != 0 && summary.sampler[0])
        fprintf(stderr,
                "gmonrt: note: Sampler \"%s\" replaced by an independent sampler (median of means needs "
                "independent samples)\n",
                summary.sampler);
    if (!o->quiet && summary.regularize)
        fprintf(stderr, "gmonrt: note: Integrator \"regularize\" is ignored\n");
    if (o->max_depth >= 0)
        scene.params.max_depth = (uint32_t)o->max_depth;
    scene.params.flags = o->bsdf_only ? 0u : RENDER_NEE;
    if (render_scene_finalize(&scene, error, sizeof error)) {
        fprintf(stderr, "gmonrt: %s\n", error);
        render_scene_destroy(&scene);
        return 1;
    }

    ClDevice devices[DEVICES_MAX];
    int device_count = devices_open(o->devices, devices, DEVICES_MAX);
    if (device_count == 0) {
        render_scene_destroy(&scene);
        return 1;
    }
    Checkpoints checkpoints;
    if (o->checkpoints) {
        if (checkpoints_open(&checkpoints, o->checkpoints, o->reference, scene.params.width, scene.params.height, error,
                             sizeof error)) {
            fprintf(stderr, "gmonrt: %s\n", error);
            devices_close(devices, device_count);
            render_scene_destroy(&scene);
            return 1;
        }
        checkpoints.scene_path = scene_path;
        checkpoints.diagnostics = o->diagnostics;
    }
    RenderSettings settings;
    render_settings_default(&settings);
    settings.estimator = o->estimator;
    settings.outputs = o->outputs | (o->diagnostics ? ESTIMATOR_OUTPUT_DIAGNOSTICS : 0);
    settings.seed = o->seed;
    settings.first_sample = o->first_sample;
    settings.sample_count = o->spp ? o->spp : (summary.pixel_samples ? summary.pixel_samples : 64);
    settings.time_budget = o->time_budget;
    settings.cancel = &interrupted;
    settings.kernel_dir = o->kernel_dir;
    settings.keep_sets = o->write_sets;
    settings.all_features = o->all_features;
    settings.dump_kernel = o->dump_kernel;
    if (o->checkpoints) {
        settings.checkpoint = checkpoints_write;
        settings.checkpoint_user = &checkpoints;
    }
    Progress progress;
    progress_init(&progress, o->quiet, (uint64_t)scene.params.width * scene.params.height, o->time_budget);
    settings.progress = progress_update;
    settings.progress_user = &progress;

    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_interrupt;
    sigaction(SIGINT, &action, NULL);

    RenderOutput out;
    RenderStatus rendered = renderer_run(devices, device_count, &scene, &settings, &out, error, sizeof error);
    progress_finish(&progress);
    int checkpoints_failed = o->checkpoints && checkpoints_close(&checkpoints) != 0;
    if (checkpoints_failed)
        fprintf(stderr, "gmonrt: writing %s/checkpoints.csv failed\n", o->checkpoints);
    if (rendered == RENDER_FAILED) {
        fprintf(stderr, "gmonrt: %s\n", error);
        devices_close(devices, device_count);
        render_scene_destroy(&scene);
        return 1;
    }
    if (rendered == RENDER_INCOMPLETE)
        fprintf(stderr, "gmonrt: %s writing the %llu samples per pixel saved before\n", error,
                (unsigned long long)out.sample_count);
    if (out.rounded_total > 0)
        fprintf(stderr,
                "gmonrt: warning: %llu samples in %llu pixels were rounded, not added exactly: those pixels' values "
                "span more binary orders than a set sum holds (see the README, \"Exact sums\")\n",
                (unsigned long long)out.rounded_total, (unsigned long long)out.rounded_pixels);
    if (interrupted && !o->quiet)
        fprintf(stderr, "gmonrt: interrupted: writing the %llu samples per pixel done\n",
                (unsigned long long)out.sample_count);

    const char *exr_path = o->outfile ? o->outfile : (summary.film_filename[0] ? summary.film_filename : "render.exr");
    char exr_name[4096];
    replace_extension(exr_path, ".exr", exr_name, sizeof exr_name);
    ExrImage image = render_output_exr(&out);
    if (!o->diagnostics) {
        image.nonfinite = NULL;
        image.rounded = NULL;
    }
    if (!o->write_sets)
        image.accumulators = NULL;
    image.metadata.scene_path = scene_path;
    int status = write_render_files(exr_name, &image, preview_image(o->preview, out.mean, out.mon, out.gmon),
                                    o->exposure, o->preview, o->quiet);
    if (!o->quiet)
        print_summary(o, &out);
    render_output_free(&out);
    devices_close(devices, device_count);
    render_scene_destroy(&scene);
    if (status == 0 && (rendered == RENDER_INCOMPLETE || checkpoints_failed))
        status = 1;
    return status == 0 && interrupted ? 130 : status;
}

/* Recomputes the estimators of an EXR written with --write-sets. */
static int estimate(const Options *o)
{
    ExrImage in;
    char error[1024];
    if (exr_image_read(o->input, &in, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        exr_image_free(&in);
        return 1;
    }
    if (!in.accumulators) {
        fprintf(stderr, "gmonrt: %s has no per-set sums (render with --write-sets)\n", o->input);
        exr_image_free(&in);
        return 1;
    }
    int status = write_estimates(o, &in, o->write_sets, "estimate.exr");
    exr_image_free(&in);
    return status;
}

int main(int argc, char **argv)
{
    Options options;
    char error[512];
    int status = options_parse(argc, argv, &options, error, sizeof error);
    if (status) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return status;
    }
    switch (options.command) {
    case COMMAND_HELP:
        fputs(options_help(), stdout);
        return 0;
    case COMMAND_LIST_DEVICES:
        return devices_list();
    case COMMAND_ESTIMATE:
        return estimate(&options);
    case COMMAND_MERGE:
        return merge_command(&options);
    case COMMAND_RENDER:
        break;
    }
    return render(&options);
}
