/* A render on one or several OpenCL devices at once: progressive passes of
 * the path tracer into exact per-set accumulators, then the estimator
 * kernel.
 *
 * Each device owns a contiguous range of pixels and every sample of those
 * pixels, so a pixel's sums live in one place. Shares start even and are
 * re-weighted between passes from each device's measured speed; the sums
 * move with the pixels (through a host copy). Samples depend only on (seed,
 * pixel, sample index) and sums are exact integers, so the image does not
 * depend on the devices or the split. A device that fails is dropped and
 * its pixels go to the others, which re-render them from the last host copy
 * of the sums (the same samples again, so the image is unchanged). */
#ifndef HOST_RENDER_RENDERER_H
#define HOST_RENDER_RENDERER_H

#include "cl/cl_device.h"
#include "film/estimator_program.h"
#include "film/film.h"
#include "render/render_scene.h"

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#define RENDER_MAX_DEVICES 16

/* Fault injection for tests, "<device>:build" or "<device>:pass:<n>" (device:
 * index among the render's devices, n: 1 for the first pass), several
 * separated by commas: that device fails to build or fails in that pass.
 * gmonrt reads it from this environment variable into RenderSettings.fault. */
#define RENDER_FAULT_ENV "GMON_FAULT"

typedef struct RenderOutput RenderOutput;

typedef struct {
    EstimatorSettings estimator; /* M, Gini mode, passes, parameters (its first_sample is set from first_sample) */
    int keep_sets;               /* keep M sets even when only the mean is asked for (--write-sets) */
    int all_features;            /* build the all-features kernels instead of specializing */
    uint32_t seed;
    uint64_t first_sample;               /* render samples [first, first + count) */
    uint64_t sample_count;               /* samples per pixel */
    double time_budget;                  /* seconds; 0 for none. Stops after the pass that reaches it */
    double seconds_per_pass;             /* pass length target (default 0.5 s) */
    const volatile sig_atomic_t *cancel; /* stop after the current pass when set */
    void (*progress)(void *user, uint64_t done, uint64_t total, double seconds);
    void *progress_user;
    /* With a checkpoint callback, passes end at every power of two samples
     * (and at the last sample), and the callback gets the estimates so far
     * (output->seconds: render time to that point, without the callbacks).
     * A non-zero return stops the render with an error. */
    int (*checkpoint)(void *user, const RenderOutput *output);
    void *checkpoint_user;
    const char *dump_kernel; /* write the specialized path tracer source here; NULL: no */
    const char *kernel_dir;  /* NULL: embedded kernels */
    /* The largest buffer a device gets (0: its maximum allocation): a
     * device's pixels whose state or images would pass it are held and
     * launched in several slices (tests set it to make slices). */
    uint64_t slice_bytes;
    /* The most splat records one launch of bdpt's or the light tracer's
     * light subpaths may leave on a device before it runs again in halves
     * (0: the default, 2^22; tests make it small). */
    uint64_t splat_records;
    /* Developer settings, which gmonrt reads once from the environment:
     * the host memory to assume (0: what the machine says; memory_check.h),
     * the estimator kernels' launch fixed by hand (estimator_program.h), and
     * injected device faults (RENDER_FAULT_ENV's form; NULL: none). */
    uint64_t host_memory_limit;
    EstimatorLaunchChoice estimator_launch;
    const char *fault;
} RenderSettings;

typedef struct {
    char name[256];
    int failed;              /* dropped: at build time or during the render */
    char error[512];         /* why it was dropped */
    uint64_t samples;        /* pixel samples it delivered to the image */
    double busy_seconds;     /* its path tracer kernels' run time */
    double estimate_seconds; /* its estimator kernels' run time, every estimation */
    double build_seconds;    /* its program builds */
    size_t peak_bytes;       /* device memory allocated, at most */
    int slices;              /* buffers of its state its pixels were cut into, at most (slice_bytes) */
} RenderDeviceReport;

struct RenderOutput {
    unsigned width, height;
    int set_count;               /* M as rendered: 1 when only the mean was asked for */
    EstimatorSettings estimator; /* as the images were estimated (set_count M as rendered) */
    uint32_t seed;
    uint64_t first_sample;
    uint64_t sample_count; /* samples per pixel actually rendered */
    char scene_hash[17];   /* of everything that determines a sample (renderer.c) */
    uint32_t max_depth;
    const char *integrator;        /* render_integrator_name */
    uint32_t sampler;              /* SAMPLER_* (kernels/tracing/sampler.h) */
    uint32_t light_sampler;        /* LIGHT_SAMPLER_* (kernels/tracing/scene_types.h) */
    uint64_t *accumulators;        /* exact set sums, accumulator_planes(set_count) planes (accumulate.h) */
    uint32_t *rejected;            /* per pixel, REJECTED_PLANES planes: non-finite samples, then rounded ones */
    uint64_t rejected_total;       /* non-finite samples (added as 0) */
    uint64_t rounded_total;        /* samples not added exactly (see accumulate.h), in ... */
    uint64_t rounded_pixels;       /* ... this many pixels */
    size_t bytes_per_pixel;        /* per-pixel state on the devices and in each host copy */
    size_t sample_bytes_per_pixel; /* of which the per-sample estimators' state (film_sample.h) */
    uint64_t rays;
    double seconds;       /* rendering passes and estimates */
    double build_seconds; /* program builds, all devices */
    uint64_t features;    /* the kernels' feature mask (feature_mask.h) */
    int rebalances;       /* times pixels moved between devices */
    int device_count;
    RenderDeviceReport devices[RENDER_MAX_DEVICES];
    /* The images (RGB per pixel) by pass, as EstimatorImages; NULL where
     * not requested (a per-sample pass may hold several: film_sample.h). */
    void *pass[PASS_COUNT];
    float *error[PASS_COUNT];
};

/* The output's images as estimator arguments. */
EstimatorImages render_output_images(const RenderOutput *output);

/* Counters per pixel: non-finite samples, rounded samples. */
#define REJECTED_PLANES 2

/* The state one pixel needs with `sets` sets: sums, counters, ray count. */
size_t render_bytes_per_pixel(size_t sets);

typedef enum {
    RENDER_OK = 0,
    RENDER_FAILED = -1,    /* no image; the message says why */
    RENDER_INCOMPLETE = 1, /* every device failed; the output holds the samples saved before */
} RenderStatus;

void render_settings_default(RenderSettings *settings);

/* The path tracer's build options: M (the estimator's set_count, the sets
 * kept), the scene's features, the sampler and the M it deals samples to,
 * the traversal stack the scene's BVH needs (Bvh.stack_need), and the
 * per-sample estimators' defines. */
void path_tracer_build_options(const EstimatorSettings *estimator, uint64_t features, uint32_t sampler,
                               int sampler_sets, int stack_need, char *options, size_t size);

/* Renders `scene` (finalized) on devices[0 .. device_count - 1]. A
 * cancelled or time-limited render succeeds with fewer samples. On
 * RENDER_FAILED the output is empty and `error` says why; on
 * RENDER_INCOMPLETE `error` names the failures and the output is a valid
 * render of fewer samples (possibly 0). */
RenderStatus renderer_run(ClDevice *devices, int device_count, const RenderScene *scene, const RenderSettings *settings,
                          RenderOutput *output, char *error, size_t error_size);

void render_output_free(RenderOutput *output);

/* The integrator IntegratorData.flags asks for: "path" (NEE and MIS),
 * "bsdf" (BSDF sampling only), "lightpath" or "bdpt". */
const char *render_integrator_name(uint32_t flags);

#endif
