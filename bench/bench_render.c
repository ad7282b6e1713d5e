/* Path tracer throughput: samples/s and rays/s on a scene (default: the
 * diffuse Cornell box at 256x256, maxdepth 8, 64 spp, next-event
 * estimation), on one device, median of several runs.
 *
 *   bench_render [--scene FILE] [--spp N] [--resolution WxH] [--maxdepth N]
 *                [--repeats R] [--device I] [--integrator nee|bsdf]
 *                [--sampler NAME] [--light-sampler NAME] [--allow-unsupported]
 *                [--estimators LIST]
 *                [--estimator-param NAME=VALUE]...
 * (--estimators as gmonrt's, e.g. the per-sample estimators' cost:
 * mean,mon,gmon against mean,mon,gmon,clamp,clamp-sum,abmm,gabmm).
 * It also prints the scene's load time and the device memory of a run. */
#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"
#include "film/film_sample.h"
#include "render/renderer.h"
#include "render/scene_convert.h"

#include <stdio.h>
#include <time.h>
#include <stdlib.h>
#include <string.h>

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int usage(const char *message)
{
    if (message)
        fprintf(stderr, "bench_render: %s\n", message);
    fprintf(message ? stderr : stdout,
            "usage: bench_render [--scene FILE] [--spp N] [--resolution WxH] [--maxdepth N] [--repeats R]\n"
            "                    [--device I] [--integrator nee|bsdf] [--sampler NAME] [--light-sampler NAME]\n"
            "                    [--allow-unsupported] [--estimators LIST] [--estimator-param NAME=VALUE]...\n"
            "defaults: the diffuse Cornell box, 64 spp, 256x256, maxdepth 8, 5 repeats, device 0, nee,\n"
            "the scene's sampler and light sampler (as gmonrt's), mean,mon,gmon; --allow-unsupported:\n"
            "skip or substitute what gmonrt lacks, as gmonrt's option\n");
    return message ? 2 : 0;
}

int main(int argc, char **argv)
{
    const char *scene_path = GMON_SOURCE_DIR "/scenes/cornell-diffuse.pbrt";
    unsigned long spp = 64, width = 256, height = 256, max_depth = 8, repeats = 5, device_index = 0;
    int bsdf_only = 0, allow_unsupported = 0, sampler = -1, light_sampler = -1;
    RenderSettings settings;
    render_settings_default(&settings);
    char message[640];
    for (int i = 1; i < argc; ++i) {
        const char *flag = argv[i];
        if (strcmp(flag, "--help") == 0)
            return usage(NULL);
        if (strcmp(flag, "--allow-unsupported") == 0) {
            allow_unsupported = 1;
            continue;
        }
        if (i + 1 >= argc)
            return usage("every option takes a value");
        const char *value = argv[++i];
        char *end = NULL;
        if (strcmp(flag, "--scene") == 0)
            scene_path = value;
        else if (strcmp(flag, "--spp") == 0)
            spp = strtoul(value, &end, 10);
        else if (strcmp(flag, "--maxdepth") == 0)
            max_depth = strtoul(value, &end, 10);
        else if (strcmp(flag, "--repeats") == 0)
            repeats = strtoul(value, &end, 10);
        else if (strcmp(flag, "--device") == 0)
            device_index = strtoul(value, &end, 10);
        else if (strcmp(flag, "--estimators") == 0) {
            if (passes_from_list(value, &settings.estimator.passes, message, sizeof message))
                return usage(message);
        } else if (strcmp(flag, "--estimator-param") == 0) {
            if (estimator_param_set(&settings.estimator.params, value, message, sizeof message))
                return usage(message);
        } else if (strcmp(flag, "--resolution") == 0) {
            if (sscanf(value, "%lux%lu", &width, &height) != 2 || width == 0 || height == 0)
                return usage("--resolution takes WIDTHxHEIGHT");
        } else if (strcmp(flag, "--light-sampler") == 0) {
            if ((light_sampler = light_sampler_from_name(value)) < 0)
                return usage("--light-sampler takes bvh, power or uniform");
        } else if (strcmp(flag, "--sampler") == 0) {
            if ((sampler = sampler_from_name(value)) < 0)
                return usage("--sampler takes sobol-sets, sobol-pixel or independent");
        } else if (strcmp(flag, "--integrator") == 0) {
            if (strcmp(value, "nee") && strcmp(value, "bsdf"))
                return usage("--integrator takes nee or bsdf");
            bsdf_only = strcmp(value, "bsdf") == 0;
        } else
            return usage("unknown option");
        if (end && (*end || spp == 0 || repeats == 0 || repeats > 100))
            return usage("bad number");
    }

    ClDeviceInfo devices[16];
    int count = cl_devices_enumerate(devices, 16);
    if (count <= (int)device_index) {
        fprintf(stderr, "bench_render: no OpenCL device %lu (POCL_CACHE_DIR set?)\n", device_index);
        return 1;
    }
    ClDevice device;
    if (cl_device_open(&device, &devices[device_index]))
        return 1;
    RenderScene scene;
    SceneSummary summary;
    char error[1024];
    struct timespec load_start, load_end;
    clock_gettime(CLOCK_MONOTONIC, &load_start);
    if (scene_convert_load(scene_path, allow_unsupported, (unsigned)width, (unsigned)height, 1, &scene, &summary, error,
                           sizeof error)) {
        fprintf(stderr, "bench_render: %s\n", error);
        return 1;
    }
    clock_gettime(CLOCK_MONOTONIC, &load_end);
    double load_seconds =
        (double)(load_end.tv_sec - load_start.tv_sec) + 1e-9 * (double)(load_end.tv_nsec - load_start.tv_nsec);
    scene.constants.integrator.max_depth = (uint32_t)max_depth;
    scene.constants.integrator.flags = bsdf_only ? 0u : RENDER_NEE;
    if (sampler >= 0)
        scene.constants.integrator.sampler = (uint32_t)sampler;
    if (light_sampler >= 0)
        scene.constants.integrator.light_sampler = (uint32_t)light_sampler;
    if (render_scene_finalize(&scene, error, sizeof error)) {
        fprintf(stderr, "bench_render: %s\n", error);
        return 1;
    }
    settings.sample_count = spp;
    settings.seconds_per_pass = 1.0;

    printf("device:     %s (%s, %u compute units)\n", device.info.name, device.info.platform_name,
           device.info.compute_units);
    printf("scene:      %s, %lux%lu, maxdepth %lu, %lu spp, %s, %s sampler, %s light sampler, M = %d\n", scene_path,
           width, height, max_depth, spp, bsdf_only ? "BSDF sampling only" : "NEE + MIS",
           sampler_name(scene.constants.integrator.sampler),
           light_sampler_name(scene.constants.integrator.light_sampler), settings.estimator.set_count);
    printf("estimators: 0x%x (%zu bytes of per-sample state a pixel)\n", (unsigned)settings.estimator.passes,
           film_sample_planes(&settings.estimator) * sizeof(uint64_t));
    printf("primitives: %d, BVH nodes %d, depth %d; loaded and built in %.2f s, %.1f MiB of texels\n",
           scene.bvh.primitive_count, scene.bvh.node_count, scene.bvh.depth, load_seconds,
           (double)summary.texture_bytes / (1024.0 * 1024.0));
    double samples_per_second[100], rays_per_second[100], seconds[100];
    for (unsigned long r = 0; r <= repeats; ++r) {
        RenderOutput out;
        if (renderer_run(&device, 1, &scene, &settings, &out, error, sizeof error)) {
            fprintf(stderr, "bench_render: %s\n", error);
            return 1;
        }
        double samples = (double)out.sample_count * out.width * out.height;
        if (r == 0) {
            printf("warm-up:    %.2f s (program builds %.2f s), device memory %.1f MiB\n", out.seconds,
                   out.build_seconds, (double)out.devices[0].peak_bytes / (1024.0 * 1024.0));
        } else {
            seconds[r - 1] = out.seconds;
            samples_per_second[r - 1] = samples / out.seconds;
            rays_per_second[r - 1] = (double)out.rays / out.seconds;
            printf("run %2lu:     %.3f s  %.3f Msamples/s  %.3f Mrays/s  (%.2f rays/sample, %.3f s estimating)\n", r,
                   out.seconds, samples_per_second[r - 1] * 1e-6, rays_per_second[r - 1] * 1e-6,
                   (double)out.rays / samples, out.devices[0].estimate_seconds);
        }
        render_output_free(&out);
    }
    qsort(seconds, repeats, sizeof(double), compare_doubles);
    qsort(samples_per_second, repeats, sizeof(double), compare_doubles);
    qsort(rays_per_second, repeats, sizeof(double), compare_doubles);
    printf("median:     %.3f s  %.3f Msamples/s  %.3f Mrays/s\n", seconds[repeats / 2],
           samples_per_second[repeats / 2] * 1e-6, rays_per_second[repeats / 2] * 1e-6);
    printf("reference:  Mitsuba 3 llvm_ad_rgb, Cornell box 256x256 maxdepth 8: about 1.6 Msamples/s on 2 cores "
           "(from the issue)\n");
    render_scene_destroy(&scene);
    cl_device_close(&device);
    return 0;
}
