/* gmonrt: renders a pbrt-v4 scene with the OpenCL path tracer and writes the
 * requested estimators of the same samples (mean, MoN and G-MoN by
 * default) to one EXR plus a PNG preview. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "cl/kernel_sources.h"
#include "cli/check.h"
#include "cli/checkpoints.h"
#include "cli/devices.h"
#include "cli/estimate.h"
#include "cli/interrupt.h"
#include "cli/merge.h"
#include "cli/options.h"
#include "cli/output_files.h"
#include "cli/progress.h"
#include "film/film.h"
#include "film/film_sample.h"
#include "io/exr_image.h"
#include "render/memory_check.h"
#include "render/render_exr.h"
#include "render/caustic_check.h"
#include "render/renderer.h"
#include "render/scene_convert.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GMON_DEFAULT_SCENE
#define GMON_DEFAULT_SCENE "scenes/cornell-glass.pbrt"
#endif

static const char *gini_mode_label(GiniMode mode)
{
    return mode == GINI_PER_PIXEL ? "pixel" : (mode == SORT_BY_LUMINANCE ? "luminance" : "channel");
}

/* The summary: one line for the render, then one per device when there are
 * several (or one failed). */
static void print_summary(const Options *o, const RenderOutput *out)
{
    double samples = (double)out->sample_count * out->width * out->height;
    double seconds = out->seconds > 0.0 ? out->seconds : 1e-9;
    uint64_t total = 0;
    double estimate_seconds = 0.0;
    for (int i = 0; i < out->device_count; ++i) {
        total += out->devices[i].samples;
        estimate_seconds += out->devices[i].estimate_seconds;
    }
    const uint32_t estimates = out->estimator.passes & PASSES_ESTIMATES;
    printf("%ux%u, %llu spp, M = %d, gini %s, %.2f s, %.3g samples/s, %.3g rays/s, %llu non-finite samples, "
           "%llu rounded samples, %zu bytes per pixel, %d device%s\n",
           out->width, out->height, (unsigned long long)out->sample_count, out->set_count,
           gini_mode_label(o->estimator.gini_mode), out->seconds, samples / seconds, (double)out->rays / seconds,
           (unsigned long long)out->rejected_total, (unsigned long long)out->rounded_total, out->bytes_per_pixel,
           out->device_count, out->device_count == 1 ? "" : "s");
    printf("  %d estimator%s%s, estimation %.3f s (device time, every estimation)\n", count_bits32(estimates),
           count_bits32(estimates) == 1 ? "" : "s", out->estimator.with_stderr ? " with standard errors" : "",
           estimate_seconds);
    if (out->sample_bytes_per_pixel) {
        char line[512];
        film_sample_memory_summary(&out->estimator, line, sizeof line);
        char names[256] = "";
        for (int p = 0; p < PASS_COUNT; ++p)
            if (out->estimator.passes & PASSES_SAMPLE & PASS_BIT(p))
                snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", names[0] ? ", " : "",
                         pass_name(p));
        printf("  per-sample estimators %s: %s a pixel (in the bytes per pixel above)\n", names, line);
    }
    for (int i = 0; i < out->device_count; ++i) {
        const RenderDeviceReport *d = &out->devices[i];
        printf("  device %d '%s': %.1f%% of samples, %.3g samples/s, %.1f MiB allocated, build %.2f s%s%s\n", i,
               d->name, total ? 100.0 * (double)d->samples / (double)total : 0.0,
               d->busy_seconds > 0.0 ? (double)d->samples / d->busy_seconds : 0.0,
               (double)d->peak_bytes / (1024.0 * 1024.0), d->build_seconds, d->failed ? ", FAILED: " : "",
               d->failed ? d->error : "");
    }
    printf("  kernel features 0x%" PRIx64
           ", %d rebalance%s, start-up %.2f s (program builds and first-launch compiles)\n",
           out->features, out->rebalances, out->rebalances == 1 ? "" : "s", out->build_seconds);
}

/* The progress callback: once a pass has samples, a signal keeps them. */
static void on_progress(void *user, uint64_t done, uint64_t total, double seconds)
{
    if (done > 0)
        interrupt_keep_samples();
    progress_update(user, done, total, seconds);
}

static int render(const Options *o)
{
    /* The developer settings in the environment, read once here. */
    uint64_t memory_limit;
    EstimatorLaunchChoice launch;
    if (memory_limit_from_environment(&memory_limit) != 0 || estimator_launch_from_environment(&launch) != 0)
        return 2;
    /* Devices first: a --device that names none here is a bad command line,
     * reported before a long scene load. */
    ClDevice devices[DEVICES_MAX];
    int device_count = devices_open(&o->devices, devices, DEVICES_MAX);
    if (device_count <= 0)
        return device_count < 0 ? 2 : 1;
    const char *scene_path = o->input ? o->input : GMON_DEFAULT_SCENE;
    RenderScene scene;
    SceneSummary summary;
    char error[2048];
    if (scene_convert_load(scene_path, o->allow_unsupported, o->width, o->height, o->quiet, &scene, &summary, error,
                           sizeof error)) {
        fprintf(stderr, "gmonrt: %s\n", error);
        devices_close(devices, device_count);
        return 1;
    }
    int status = 1;
    if (o->sampler >= 0)
        scene.constants.integrator.sampler = (uint32_t)o->sampler;
    else if (!o->quiet && summary.sampler[0] &&
             strcmp(summary.sampler, sampler_name(scene.constants.integrator.sampler)) != 0)
        fprintf(stderr, "gmonrt: note: Sampler \"%s\" is rendered with gmonrt's %s sampler (docs/sampling.md)\n",
                summary.sampler, sampler_name(scene.constants.integrator.sampler));
    if (o->light_sampler >= 0)
        render_scene_set_light_sampler(&scene, (uint32_t)o->light_sampler);
    if (o->max_depth >= 0)
        scene.constants.integrator.max_depth = (uint32_t)o->max_depth;
    if (o->light_subpaths >= 0 && o->light_subpaths != summary.light_subpaths)
        scene_convert_light_subpaths(&scene, o->light_subpaths, summary.regularize, scene_path, o->quiet);
    if (!o->quiet && summary.regularize && !(scene.constants.integrator.flags & RENDER_BDPT))
        fprintf(stderr, "gmonrt: note: Integrator \"regularize\" is ignored by the path tracer\n");
    /* The integrator chosen (lightpath, bdpt) stays; --integrator bsdf is the path tracer's. */
    scene.constants.integrator.flags =
        (scene.constants.integrator.flags & (RENDER_LIGHTPATH | RENDER_BDPT | RENDER_REGULARIZE)) |
        (o->bsdf_only ? 0u : RENDER_NEE);
    if (render_scene_finalize(&scene, error, sizeof error)) {
        fprintf(stderr, "gmonrt: %s\n", error);
        goto done;
    }
    if (!o->quiet)
        caustic_check_print(&scene, stderr, "gmonrt: ");
    /* The output path is known now (a scene may name it); check it before
     * the render rather than fail after it. */
    const char *exr_path = o->outfile ? o->outfile : (summary.film_filename[0] ? summary.film_filename : "render.exr");
    char exr_name[4096];
    replace_extension(exr_path, ".exr", exr_name, sizeof exr_name);
    if (check_output_path(exr_name))
        goto done;

    Checkpoints checkpoints;
    if (o->checkpoints) {
        if (checkpoints_open(&checkpoints, o->checkpoints, o->reference, scene.constants.camera.width,
                             scene.constants.camera.height, error, sizeof error)) {
            fprintf(stderr, "gmonrt: %s\n", error);
            goto done;
        }
        checkpoints.scene_path = scene_path;
    }
    RenderSettings settings;
    render_settings_default(&settings);
    settings.estimator = o->estimator;
    settings.seed = o->seed;
    settings.first_sample = o->first_sample;
    settings.sample_count = o->spp ? o->spp : (summary.pixel_samples ? summary.pixel_samples : 64);
    settings.time_budget = o->time_budget;
    settings.cancel = &interrupt_signal;
    settings.kernel_dir = o->kernel_dir ? o->kernel_dir : getenv(KERNEL_DIR_ENV);
    settings.keep_sets = o->write_sets;
    settings.all_features = o->all_features;
    settings.dump_kernel = o->dump_kernel;
    settings.fault = getenv(RENDER_FAULT_ENV);
    settings.host_memory_limit = memory_limit;
    settings.estimator_launch = launch;
    if (o->checkpoints) {
        settings.checkpoint = checkpoints_write;
        settings.checkpoint_user = &checkpoints;
    }
    Progress progress;
    progress_init(&progress, o->quiet, (uint64_t)scene.constants.camera.width * scene.constants.camera.height,
                  o->time_budget);
    settings.progress = on_progress;
    settings.progress_user = &progress;

    RenderOutput out;
    RenderStatus rendered = renderer_run(devices, device_count, &scene, &settings, &out, error, sizeof error);
    progress_finish(&progress);
    int checkpoints_failed = o->checkpoints && checkpoints_close(&checkpoints) != 0;
    if (rendered == RENDER_FAILED) {
        fprintf(stderr, "gmonrt: %s\n", error);
        goto done;
    }
    if (rendered == RENDER_INCOMPLETE)
        fprintf(stderr, "gmonrt: %s writing the %llu samples per pixel saved before\n", error,
                (unsigned long long)out.sample_count);
    if (out.rounded_total > 0)
        fprintf(stderr,
                "gmonrt: warning: %llu samples in %llu pixels were rounded, not added exactly: those pixels' values "
                "span more binary orders than a set sum holds (see docs/design.md, \"Exact sums\")\n",
                (unsigned long long)out.rounded_total, (unsigned long long)out.rounded_pixels);
    if (interrupt_signal && !o->quiet)
        fprintf(stderr, "gmonrt: interrupted: writing the %llu samples per pixel done\n",
                (unsigned long long)out.sample_count);

    if (out.sample_count == 0) {
        /* A black image would replace a good one. */
        fprintf(stderr, "gmonrt: no sample was rendered: %s not written\n", exr_name);
    } else {
        static FilmFile file;
        render_output_file(&file, &out);
        ExrImage *image = &file.image;
        if (!o->diagnostics) {
            image->nonfinite = NULL;
            image->rounded = NULL;
        }
        if (!o->write_sets)
            image->accumulators = NULL;
        image->metadata.scene_path = scene_path;
        status = write_render_files(exr_name, image, out.pass[o->preview], o->exposure, pass_name(o->preview));
    }
    if (!o->quiet)
        print_summary(o, &out);
    /* Even with --quiet: such samples darken the image where they fall. */
    if (out.rejected_total > 0)
        fprintf(stderr,
                "gmonrt: warning: %llu non-finite samples (infinite or NaN radiance) were counted as 0, darkening "
                "the image where they fell (--diagnostics writes where)\n",
                (unsigned long long)out.rejected_total);
    render_output_free(&out);
    if (status == 0 && (rendered == RENDER_INCOMPLETE || checkpoints_failed))
        status = 1;
    if (status == 0 && interrupt_signal)
        status = interrupt_exit_status();
done:
    devices_close(devices, device_count);
    render_scene_destroy(&scene);
    return status;
}

int main(int argc, char **argv)
{
    Options options;
    char error[512];
    interrupt_install();
    int status = options_parse(argc, argv, &options, error, sizeof error);
    if (status) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return status;
    }
    if (options.help) {
        fputs(options_help(options.command), stdout);
        return 0;
    }
    switch (options.command) {
    case COMMAND_LIST_DEVICES:
        return devices_list();
    case COMMAND_ESTIMATE:
        return estimate_command(&options);
    case COMMAND_MERGE:
        return merge_command(&options);
    case COMMAND_CHECK:
        return check_command(&options);
    case COMMAND_RENDER:
        break;
    }
    return render(&options);
}
