/* A render on one OpenCL device: progressive passes of the path tracer into
 * exact per-set accumulators, then the estimator kernel. */
#ifndef HOST_RENDER_RENDERER_H
#define HOST_RENDER_RENDERER_H

#include "cl/cl_device.h"
#include "estimator/estimator.h"
#include "render/render_scene.h"

#include <signal.h>
#include <stdint.h>

typedef struct {
    EstimatorSettings estimator; /* M and the Gini mode */
    int outputs;                 /* ESTIMATOR_OUTPUT_* mask */
    uint32_t seed;
    uint64_t first_sample;               /* render samples [first, first + count) */
    uint64_t sample_count;               /* samples per pixel */
    double time_budget;                  /* seconds; 0 for none. Stops after the pass that reaches it */
    double seconds_per_pass;             /* pass length target (default 0.5 s) */
    const volatile sig_atomic_t *cancel; /* stop after the current pass when set */
    void (*progress)(void *user, uint64_t done, uint64_t total, double seconds);
    void *progress_user;
    const char *kernel_dir; /* NULL: embedded kernels */
} RenderSettings;

typedef struct {
    unsigned width, height;
    int set_count;
    GiniMode gini_mode;
    uint32_t seed;
    uint64_t first_sample;
    uint64_t sample_count;  /* samples per pixel actually rendered */
    uint64_t *accumulators; /* exact set sums, planes [set][channel][word][pixel] */
    uint32_t *rejected;     /* per pixel: non-finite or out-of-range samples */
    uint64_t rejected_total;
    uint64_t rays;
    double seconds;       /* rendering passes only */
    double build_seconds; /* program builds */
    /* Estimates (RGB per pixel); NULL where not requested. */
    float *mean, *mon, *gmon, *gini;
    int32_t *trim;
} RenderOutput;

void render_settings_default(RenderSettings *settings);

/* Renders `scene` (finalized). Returns 0 on success, -1 with a message. A
 * cancelled or time-limited render succeeds with fewer samples. */
int renderer_run(ClDevice *device, const RenderScene *scene, const RenderSettings *settings, RenderOutput *output,
                 char *error, size_t error_size);

void render_output_free(RenderOutput *output);

#endif
