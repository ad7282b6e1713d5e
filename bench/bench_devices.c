/* Two benchmarks of the renderer's device handling, medians of several runs:
 *
 *   bench_devices --mode devices   multi-device efficiency: samples/s of all
 *                                  devices together over the sum of each
 *                                  device's samples/s alone
 *   bench_devices --mode features  specialized kernels against the
 *                                  all-features kernels: samples/s, and cold
 *                                  (empty PoCL cache) and warm build times
 *
 * In features mode POCL_CACHE_DIR is pointed at a new empty directory first,
 * so that the first build of each variant is cold. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "film/estimator_program.h"
#include "render/renderer.h"
#include "render/scene_convert.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEVICES 16
#define MAX_REPEATS 50

typedef struct {
    const char *scene;
    unsigned long spp, width, height, repeats;
    const char *mode;
} Options;

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *values, unsigned long count)
{
    qsort(values, count, sizeof *values, compare_doubles);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

static int usage(const char *message)
{
    if (message)
        fprintf(stderr, "bench_devices: %s\n", message);
    fprintf(message ? stderr : stdout,
            "usage: bench_devices [--mode devices|features] [--scene FILE] [--spp N] [--resolution WxH]\n"
            "                     [--repeats R]\n"
            "defaults: devices mode, the diffuse Cornell box, 16 spp, 256x256, 3 repeats; features mode\n"
            "          without --scene runs the diffuse and the glass Cornell boxes\n");
    return message ? 2 : 0;
}

static int load_scene(const char *path, const Options *o, RenderScene *scene)
{
    SceneSummary summary;
    char error[1024];
    if (scene_convert_load(path, 0, (unsigned)o->width, (unsigned)o->height, 1, scene, &summary, error, sizeof error) ||
        render_scene_finalize(scene, error, sizeof error)) {
        fprintf(stderr, "bench_devices: %s\n", error);
        return -1;
    }
    return 0;
}

/* One render: its samples/s and build time; the output is kept in *kept
 * when that is not NULL (caller frees). */
static int run_once(ClDevice *devices, int count, const RenderScene *scene, const RenderSettings *s, double *speed,
                    double *build, RenderOutput *kept)
{
    char error[2048];
    RenderOutput out;
    if (renderer_run(devices, count, scene, s, &out, error, sizeof error) != RENDER_OK) {
        fprintf(stderr, "bench_devices: %s\n", error);
        return -1;
    }
    *speed = (double)out.sample_count * out.width * out.height / out.seconds;
    *build = out.build_seconds;
    if (kept)
        *kept = out;
    else
        render_output_free(&out);
    return 0;
}

/* One warm-up render, then the median samples/s of `repeats` renders; the
 * last render's output stays in *last (caller frees). */
static int measure(ClDevice *devices, int count, const RenderScene *scene, const RenderSettings *s,
                   unsigned long repeats, double *samples_per_second, RenderOutput *last)
{
    double speeds[MAX_REPEATS], build = 0.0;
    for (unsigned long r = 0; r <= repeats; ++r)
        if (run_once(devices, count, scene, s, r ? &speeds[r - 1] : &build, &build, r == repeats ? last : NULL))
            return -1;
    *samples_per_second = median(speeds, repeats);
    return 0;
}

static int devices_mode(ClDevice *devices, int count, const Options *o)
{
    RenderScene scene;
    if (load_scene(o->scene, o, &scene))
        return 1;
    RenderSettings s;
    render_settings_default(&s);
    s.sample_count = o->spp;
    printf("scene: %s, %lux%lu, %lu spp, M = %d; medians of %lu runs\n", o->scene, o->width, o->height, o->spp,
           s.estimator.set_count, o->repeats);
    double alone[MAX_DEVICES], sum = 0.0;
    RenderOutput out;
    for (int i = 0; i < count; ++i) {
        if (measure(&devices[i], 1, &scene, &s, o->repeats, &alone[i], &out))
            return 1;
        render_output_free(&out);
        printf("device %d alone: %.3f Msamples/s  (%s)\n", i, alone[i] * 1e-6, devices[i].info.name);
        sum += alone[i];
    }
    double together = 0.0;
    if (measure(devices, count, &scene, &s, o->repeats, &together, &out))
        return 1;
    printf("all %d devices: %.3f Msamples/s, %d rebalances in the last run\n", count, together * 1e-6, out.rebalances);
    uint64_t total = 0;
    for (int i = 0; i < count; ++i)
        total += out.devices[i].samples;
    for (int i = 0; i < count; ++i)
        printf("  device %d: %.1f%% of samples, %.3f Msamples/s while busy\n", i,
               100.0 * (double)out.devices[i].samples / (double)total,
               out.devices[i].busy_seconds > 0.0 ? (double)out.devices[i].samples / out.devices[i].busy_seconds * 1e-6
                                                 : 0.0);
    printf("efficiency: %.3f Msamples/s / %.3f Msamples/s (sum alone) = %.1f%%\n", together * 1e-6, sum * 1e-6,
           100.0 * together / sum);
    render_output_free(&out);
    render_scene_destroy(&scene);
    return 0;
}

static int features_mode(ClDevice *device, const Options *o)
{
    const char *scenes[2] = {o->scene, NULL};
    if (!o->scene) {
        scenes[0] = GMON_SOURCE_DIR "/scenes/cornell-diffuse.pbrt";
        scenes[1] = GMON_SOURCE_DIR "/scenes/cornell-glass.pbrt";
    }
    printf("%lux%lu, %lu spp, medians of %lu runs, device %s\n", o->width, o->height, o->spp, o->repeats,
           device->info.name);
    /* Build the estimator (the same program for both variants) first, so
     * that the cold builds below are the path tracer's alone. */
    RenderSettings defaults;
    render_settings_default(&defaults);
    EstimatorProgram *estimator = estimator_program_new(device, &defaults.estimator, NULL, NULL);
    if (!estimator)
        return 1;
    estimator_program_destroy(estimator);
    printf("(cold build: the path tracer's first build in this process, from an empty cache; the all-features\n"
           " program is the same for every scene, so only its first scene builds it cold)\n");
    printf("%-28s %-12s %8s %12s %12s %12s\n", "scene", "kernels", "features", "Msamples/s", "cold build",
           "warm build");
    for (int k = 0; k < 2 && scenes[k]; ++k) {
        RenderScene scene;
        if (load_scene(scenes[k], o, &scene))
            return 1;
        /* The two variants' runs alternate, so that drifts in the machine's
         * speed hit both alike. */
        RenderSettings settings[2];
        double cold[2], warm[2][MAX_REPEATS], speeds[2][MAX_REPEATS], speed[2], ignored = 0.0;
        RenderOutput last[2];
        for (int all = 0; all < 2; ++all) {
            render_settings_default(&settings[all]);
            settings[all].sample_count = o->spp;
            settings[all].all_features = all;
            if (run_once(device, 1, &scene, &settings[all], &ignored, &cold[all], NULL))
                return 1;
        }
        for (unsigned long r = 0; r < o->repeats; ++r)
            for (int all = 0; all < 2; ++all)
                if (run_once(device, 1, &scene, &settings[all], &speeds[all][r], &warm[all][r],
                             r + 1 == o->repeats ? &last[all] : NULL))
                    return 1;
        const char *name = strrchr(scenes[k], '/');
        for (int all = 0; all < 2; ++all) {
            speed[all] = median(speeds[all], o->repeats);
            printf("%-28s %-12s %8x %12.3f %10.2f s %10.2f s\n", name ? name + 1 : scenes[k],
                   all ? "all" : "specialized", (unsigned)last[all].features, speed[all] * 1e-6, cold[all],
                   median(warm[all], o->repeats));
            render_output_free(&last[all]);
        }
        printf("%-28s specialized / all: %.3f\n", "", speed[0] / speed[1]);
        render_scene_destroy(&scene);
    }
    return 0;
}

int main(int argc, char **argv)
{
    Options o = {NULL, 16, 256, 256, 3, "devices"};
    for (int i = 1; i < argc; ++i) {
        const char *flag = argv[i];
        if (strcmp(flag, "--help") == 0)
            return usage(NULL);
        if (i + 1 >= argc)
            return usage("every option takes a value");
        const char *value = argv[++i];
        char *end = NULL;
        if (strcmp(flag, "--scene") == 0)
            o.scene = value;
        else if (strcmp(flag, "--mode") == 0)
            o.mode = value;
        else if (strcmp(flag, "--spp") == 0)
            o.spp = strtoul(value, &end, 10);
        else if (strcmp(flag, "--repeats") == 0)
            o.repeats = strtoul(value, &end, 10);
        else if (strcmp(flag, "--resolution") == 0) {
            if (sscanf(value, "%lux%lu", &o.width, &o.height) != 2 || o.width == 0 || o.height == 0)
                return usage("--resolution takes WIDTHxHEIGHT");
        } else
            return usage("unknown option");
        if (end && (*end || o.spp == 0 || o.repeats == 0 || o.repeats > MAX_REPEATS))
            return usage("bad number");
    }
    int features = strcmp(o.mode, "features") == 0;
    if (!features && strcmp(o.mode, "devices") != 0)
        return usage("--mode takes devices or features");
    if (!features && !o.scene)
        o.scene = GMON_SOURCE_DIR "/scenes/cornell-diffuse.pbrt";
    if (features) {
        static char cache[] = "/tmp/gmon-bench-cache-XXXXXX";
        if (!mkdtemp(cache) || setenv("POCL_CACHE_DIR", cache, 1)) {
            fprintf(stderr, "bench_devices: cannot make a fresh PoCL cache directory\n");
            return 1;
        }
        printf("PoCL cache: %s (new and empty: first builds are cold)\n", cache);
    }

    ClDeviceInfo infos[MAX_DEVICES];
    ClDevice devices[MAX_DEVICES];
    int count = cl_devices_enumerate(infos, MAX_DEVICES), opened = 0;
    for (int i = 0; i < count; ++i)
        if (cl_device_open(&devices[opened], &infos[i]) == 0)
            ++opened;
    if (opened == 0) {
        fprintf(stderr, "bench_devices: no OpenCL device (POCL_CACHE_DIR set?)\n");
        return 1;
    }
    int status = features ? features_mode(&devices[0], &o) : devices_mode(devices, opened, &o);
    for (int i = 0; i < opened; ++i)
        cl_device_close(&devices[i]);
    return status;
}
