/* gmonrt: renders a pbrt-v4 scene with the OpenCL path tracer and writes the
 * mean, MoN and G-MoN of the same samples to one EXR plus a PNG preview. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "estimator/estimator.h"
#include "io/exr_image.h"
#include "io/png_image.h"
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

static int list_devices(void)
{
    ClDeviceInfo devices[64];
    int count = cl_devices_enumerate(devices, 64);
    if (count < 0)
        return 1;
    if (count == 0) {
        fprintf(stderr, "gmonrt: no OpenCL device found (for PoCL, is POCL_CACHE_DIR writable?)\n");
        return 1;
    }
    printf("%-5s %-32s %-44s %-11s %5s %9s\n", "index", "platform", "device", "type", "units", "memory");
    for (int i = 0; i < count; ++i)
        printf("%-5d %-32.32s %-44.44s %-11s %5u %6.1f GiB\n", i, devices[i].platform_name, devices[i].name,
               cl_device_type_name(devices[i].type), devices[i].compute_units,
               (double)devices[i].global_memory / (1024.0 * 1024.0 * 1024.0));
    return 0;
}

/* The device named by --device (first match; multi-device rendering is not
 * implemented yet, so a list uses its first entry). */
static int open_device(const char *spec, ClDevice *device)
{
    ClDeviceInfo devices[64];
    int count = cl_devices_enumerate(devices, 64);
    if (count <= 0) {
        fprintf(stderr, "gmonrt: no OpenCL device found (for PoCL, is POCL_CACHE_DIR writable? "
                        "see gmonrt --list-devices)\n");
        return -1;
    }
    int chosen = 0;
    if (spec && strcmp(spec, "all") != 0) {
        chosen = -1;
        cl_device_type wanted = strcmp(spec, "cpu") == 0   ? CL_DEVICE_TYPE_CPU
                                : strcmp(spec, "gpu") == 0 ? CL_DEVICE_TYPE_GPU
                                                           : 0;
        for (int i = 0; i < count && wanted && chosen < 0; ++i)
            if (devices[i].type & wanted)
                chosen = i;
        if (!wanted) {
            char *end = NULL;
            long index = strtol(spec, &end, 10);
            if (end != spec && (*end == '\0' || *end == ',') && index >= 0 && index < count)
                chosen = (int)index;
        }
        if (chosen < 0) {
            fprintf(stderr, "gmonrt: --device %s: no such device (see gmonrt --list-devices)\n", spec);
            return -1;
        }
    }
    if (cl_device_open(device, &devices[chosen])) {
        fprintf(stderr, "gmonrt: cannot open device '%s'\n", devices[chosen].name);
        return -1;
    }
    return 0;
}

/* PATH with its extension replaced by `extension` (".png"). */
static void replace_extension(const char *path, const char *extension, char *out, size_t size)
{
    snprintf(out, size, "%s", path);
    char *dot = strrchr(out, '.');
    char *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash))
        *dot = '\0';
    size_t length = strlen(out);
    snprintf(out + length, size - length, "%s", extension);
}

static const float *preview_image(const char *name, const float *mean, const float *mon, const float *gmon)
{
    return strcmp(name, "mean") == 0 ? mean : (strcmp(name, "mon") == 0 ? mon : gmon);
}

static int write_outputs(const Options *o, const char *exr_path, ExrImage *image, const float *preview)
{
    char error[1024];
    if (exr_image_write(exr_path, image, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    char png_path[4096];
    replace_extension(exr_path, ".png", png_path, sizeof png_path);
    if (png_write_srgb(png_path, image->width, image->height, preview, o->exposure, error, sizeof error) !=
        IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        return 1;
    }
    if (!o->quiet)
        fprintf(stderr, "wrote %s and %s (preview: %s)\n", exr_path, png_path, o->preview);
    return 0;
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

    ClDevice device;
    if (open_device(o->devices, &device)) {
        render_scene_destroy(&scene);
        return 1;
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
    Progress progress;
    progress_init(&progress, o->quiet, (uint64_t)scene.params.width * scene.params.height, o->time_budget);
    settings.progress = progress_update;
    settings.progress_user = &progress;

    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_interrupt;
    sigaction(SIGINT, &action, NULL);

    RenderOutput out;
    int status = renderer_run(&device, &scene, &settings, &out, error, sizeof error);
    progress_finish(&progress);
    if (status) {
        fprintf(stderr, "gmonrt: %s\n", error);
        cl_device_close(&device);
        render_scene_destroy(&scene);
        return 1;
    }
    if (interrupted && !o->quiet)
        fprintf(stderr, "gmonrt: interrupted: writing the %llu samples per pixel done\n",
                (unsigned long long)out.sample_count);

    const char *exr_path = o->outfile ? o->outfile : (summary.film_filename[0] ? summary.film_filename : "render.exr");
    char exr_name[4096];
    replace_extension(exr_path, ".exr", exr_name, sizeof exr_name);
    ExrImage image = render_output_exr(&out);
    if (!o->diagnostics)
        image.nonfinite = NULL;
    if (!o->write_sets)
        image.accumulators = NULL;
    image.metadata.scene_path = scene_path;
    image.metadata.scene_hash = summary.hash;
    status = write_outputs(o, exr_name, &image, preview_image(o->preview, out.mean, out.mon, out.gmon));

    if (!o->quiet) {
        double samples = (double)out.sample_count * out.width * out.height;
        printf("%ux%u, %llu spp, M = %d, gini %s, %.2f s, %.3g samples/s, %.3g rays/s, %llu non-finite samples, "
               "device %s\n",
               out.width, out.height, (unsigned long long)out.sample_count, out.set_count,
               gini_mode_name(o->estimator.gini_mode), out.seconds, samples / out.seconds,
               (double)out.rays / out.seconds, (unsigned long long)out.rejected_total, device.info.name);
    }
    render_output_free(&out);
    cl_device_close(&device);
    render_scene_destroy(&scene);
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
    EstimatorSettings settings = o->estimator;
    settings.set_count = in.metadata.set_count; /* the file's M */
    size_t pixels = (size_t)in.width * (size_t)in.height;
    size_t values = pixels * 3;
    float *mean = malloc(values * sizeof(float)), *mon = malloc(values * sizeof(float)),
          *gmon = malloc(values * sizeof(float)), *gini = malloc(values * sizeof(float));
    int32_t *trim = malloc(values * sizeof(int32_t));
    int status = 1;
    if (!mean || !mon || !gmon || !gini || !trim) {
        fprintf(stderr, "gmonrt: out of memory\n");
        goto done;
    }
    EstimatorImages images = {mean, mon, gmon, gini, trim, values};
    if (estimator_from_accumulators(&settings, in.accumulators, (size_t)settings.set_count * 3 * 2 * pixels, pixels,
                                    in.metadata.sample_count, &images, error, sizeof error) != ESTIMATOR_OK) {
        fprintf(stderr, "gmonrt: %s\n", error);
        goto done;
    }
    ExrImage out = in;
    out.storage = NULL;
    out.mean = (o->outputs & ESTIMATOR_OUTPUT_MEAN) ? mean : NULL;
    out.mon = (o->outputs & ESTIMATOR_OUTPUT_MON) ? mon : NULL;
    out.gmon = (o->outputs & ESTIMATOR_OUTPUT_GMON) ? gmon : NULL;
    out.gini = o->diagnostics ? gini : NULL;
    out.trim = o->diagnostics ? trim : NULL;
    out.accumulators = o->write_sets ? in.accumulators : NULL;
    out.metadata.gini_mode = settings.gini_mode;
    char exr_name[4096];
    replace_extension(o->outfile ? o->outfile : "estimate.exr", ".exr", exr_name, sizeof exr_name);
    status = write_outputs(o, exr_name, &out, preview_image(o->preview, mean, mon, gmon));
done:
    free(mean);
    free(mon);
    free(gmon);
    free(gini);
    free(trim);
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
        return list_devices();
    case COMMAND_ESTIMATE:
        return estimate(&options);
    case COMMAND_RENDER:
        break;
    }
    return render(&options);
}
