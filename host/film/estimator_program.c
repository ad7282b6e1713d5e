#include "film/estimator_program.h"

#include "estimators.h"

#include <stdio.h>
#include <stdlib.h>

enum { FROM_SUMS, FROM_ACCUMULATORS, KERNEL_COUNT };

struct EstimatorProgram {
    ClDevice *device;
    EstimatorSettings settings;
    EstimatorLaunch launch;
    ClProgram cl; /* kernels by the enum above */
};

/* An integer setting from the environment: *value is -1 when `name` is
 * unset or empty. Returns 0, or -1 (reported) when the value is not an
 * integer in lo..hi or, with power_of_two, not a power of two. */
static int setting_from_environment(const char *name, long lo, long hi, int power_of_two, int *value)
{
    *value = -1;
    const char *text = getenv(name);
    if (!text || !*text)
        return 0;
    char *end = NULL;
    long v = strtol(text, &end, 10);
    if (*end != '\0' || v < lo || v > hi || (power_of_two && v > 0 && (v & (v - 1)) != 0)) {
        fprintf(stderr, "estimator: %s=%s: expected %s in %ld..%ld\n", name, text,
                power_of_two ? "a power of two" : "an integer", lo, hi);
        return -1;
    }
    *value = (int)v;
    return 0;
}

int estimator_launch_from_environment(EstimatorLaunchChoice *choice)
{
    return setting_from_environment(ESTIMATOR_VECTOR_WIDTH_ENV, 1, 16, 1, &choice->vector_width) != 0 ||
                   setting_from_environment(ESTIMATOR_LOCAL_SIZE_ENV, 0, 1 << 16, 0, &choice->local_size) != 0 ||
                   setting_from_environment(ESTIMATOR_PREFETCH_ENV, 0, 64, 0, &choice->prefetch) != 0
               ? -1
               : 0;
}

/* The launch configuration. On CPUs: several pixels a work item, as CPU
 * OpenCL runtimes do not vectorize this kernel across work items: 8, or one
 * per float lane of a wider native vector register (16 with AVX-512) where
 * the estimates' arithmetic outweighs reading the sums (estimates beyond the
 * default set, or standard errors). Measured with bench_estimator at
 * 1920x1080, M = 21: 16 lanes made all estimates with standard errors 1.4x
 * to 1.5x faster than 8 on two AVX-512 machines, but the default set 2.1x
 * slower on one (an AMD EPYC: its fixed-point conversion alone 2x slower a
 * pixel) while 1.3x faster on the other. Then work groups of 256 pixels
 * (below), and the next work item's input prefetched (M * 3 input streams
 * are more than hardware prefetchers follow). Elsewhere one pixel per work
 * item (a GPU runs a work item per SIMD lane) and the runtime's work-group
 * size. `choice` fixes any of them by hand. */
static void choose_launch(const ClDevice *device, const EstimatorSettings *settings,
                          const EstimatorLaunchChoice *choice, EstimatorLaunch *launch)
{
    int cpu = (device->info.type & CL_DEVICE_TYPE_CPU) != 0;
    int arithmetic_bound = settings->with_stderr || (settings->passes & ~PASSES_DEFAULT) != 0;
    launch->vector_width = !cpu ? 1 : arithmetic_bound && device->info.native_float_width >= 16 ? 16 : 8;
    launch->prefetch = cpu ? 1 : 0;
    if (choice->vector_width >= 0)
        launch->vector_width = choice->vector_width;
    /* PoCL keeps a work group's private arrays on one thread's stack: 256
     * pixels a group fit at 8 and 16 lanes, while 16 lanes times 32 items
     * crashed test_estimator_kernel (a stack overflow). */
    launch->local_size = cpu ? 256 / launch->vector_width : 0;
    if (choice->local_size >= 0)
        launch->local_size = choice->local_size;
    if (choice->prefetch >= 0)
        launch->prefetch = choice->prefetch;
    if (!cpu)
        launch->prefetch = 0; /* the kernel's prefetch assumes one flat address space */
}

void estimator_build_options(const EstimatorSettings *settings, const EstimatorLaunch *launch, char *options,
                             size_t size)
{
    snprintf(options, size,
             "-DEST_SETS=%d -DEST_FIRST_SET=%d -DEST_GINI_MODE=%d -DEST_PASSES=0x%x -DEST_STDERR=%d "
             "-DEST_VECTOR_WIDTH=%d -DEST_PREFETCH=%d",
             settings->set_count, (int)(settings->first_sample % (uint64_t)settings->set_count),
             (int)settings->gini_mode, (unsigned)(settings->passes & ~PASSES_SAMPLE), settings->with_stderr ? 1 : 0,
             launch->vector_width, launch->prefetch);
}

EstimatorProgram *estimator_program_new(ClDevice *device, const EstimatorSettings *settings,
                                        const EstimatorLaunchChoice *choice, const char *kernel_dir)
{
    char message[256];
    if (estimator_settings_check(settings, message, sizeof message) != 0) {
        fprintf(stderr, "estimator: %s\n", message);
        return NULL;
    }
    EstimatorProgram *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->device = device;
    p->settings = *settings;
    p->settings.passes &= ~PASSES_SAMPLE; /* sample_estimator_program.h's */
    settings = &p->settings;
    const EstimatorLaunchChoice chosen_per_device = ESTIMATOR_LAUNCH_CHOSEN_PER_DEVICE;
    choose_launch(device, settings, choice ? choice : &chosen_per_device, &p->launch);
    char options[256];
    estimator_build_options(settings, &p->launch, options, sizeof options);
    static const char *const kernels[KERNEL_COUNT] = {"estimate_from_sums", "estimate_from_accumulators"};
    if (cl_program_open(&p->cl, device, "estimator", options, kernel_dir, kernels, KERNEL_COUNT) != 0)
        goto fail;
    return p;
fail:
    estimator_program_destroy(p);
    return NULL;
}

EstimatorLaunch estimator_program_launch(const EstimatorProgram *p)
{
    return p->launch;
}

void estimator_program_destroy(EstimatorProgram *p)
{
    if (!p)
        return;
    cl_program_close(&p->cl);
    free(p);
}

size_t estimator_program_image_bytes(const EstimatorProgram *p, size_t pixel_count)
{
    return (size_t)pass_image_count(p->settings.passes, p->settings.with_stderr) * pixel_count * EST_CHANNELS *
           sizeof(float);
}

cl_event estimator_program_enqueue(EstimatorProgram *p, cl_mem input, int from_accumulators, size_t pixel_count,
                                   uint64_t sample_count, cl_mem images)
{
    cl_kernel k = p->cl.kernels[from_accumulators ? FROM_ACCUMULATORS : FROM_SUMS];
    cl_ulong pixels = pixel_count, samples = sample_count;
    cl_event event = NULL;
    CL_CHECK(clSetKernelArg(k, 0, sizeof input, &input), fail);
    CL_CHECK(clSetKernelArg(k, 1, sizeof pixels, &pixels), fail);
    CL_CHECK(clSetKernelArg(k, 2, sizeof samples, &samples), fail);
    CL_CHECK(clSetKernelArg(k, 3, sizeof p->settings.params, &p->settings.params), fail);
    CL_CHECK(clSetKernelArg(k, 4, sizeof images, &images), fail);
    /* A work item per vector_width pixels. */
    size_t items = (pixel_count + (size_t)p->launch.vector_width - 1) / (size_t)p->launch.vector_width;
    CL_CHECK(cl_program_enqueue(&p->cl, k, items, (size_t)p->launch.local_size, &event), fail);
    return event;
fail:
    return NULL;
}

cl_int estimator_program_read(EstimatorProgram *p, cl_mem images, size_t first, size_t pixel_count,
                              EstimatorImages *host)
{
    const uint32_t passes = p->settings.passes;
    const size_t plane = pixel_count * EST_CHANNELS * sizeof(float), offset = first * EST_CHANNELS * sizeof(float);
    for (int pass = 0; pass < PASS_COUNT; ++pass) {
        if (!(passes & PASS_BIT(pass)))
            continue;
        cl_int err = CL_SUCCESS;
        if (host->pass[pass])
            err = clEnqueueReadBuffer(p->device->queue, images, CL_TRUE, (size_t)pass_slot(passes, pass) * plane, plane,
                                      (char *)host->pass[pass] + offset, 0, NULL, NULL);
        if (err == CL_SUCCESS && p->settings.with_stderr && (PASSES_ESTIMATES & PASS_BIT(pass)) && host->error[pass])
            err = clEnqueueReadBuffer(p->device->queue, images, CL_TRUE, (size_t)stderr_slot(passes, pass) * plane,
                                      plane, (char *)host->error[pass] + offset, 0, NULL, NULL);
        if (err != CL_SUCCESS)
            return err;
    }
    return CL_SUCCESS;
}

int estimator_program_run(EstimatorProgram *p, const void *input, int from_accumulators, size_t pixel_count,
                          uint64_t sample_count, EstimatorImages *images)
{
    cl_context ctx = p->device->context;
    size_t values = (size_t)p->settings.set_count * EST_CHANNELS * pixel_count;
    size_t input_bytes = from_accumulators
                             ? accumulator_planes((uint32_t)p->settings.set_count) * pixel_count * sizeof(uint64_t)
                             : values * sizeof(float);
    cl_event event = NULL;
    cl_mem out = NULL;
    int status = -1;
    cl_int err = CL_SUCCESS;
    cl_mem in = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, input_bytes, (void *)input, &err);
    CL_CHECK(err, done);
    out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, estimator_program_image_bytes(p, pixel_count), NULL, &err);
    CL_CHECK(err, done);
    event = estimator_program_enqueue(p, in, from_accumulators, pixel_count, sample_count, out);
    if (!event)
        goto done;
    CL_CHECK(estimator_program_read(p, out, 0, pixel_count, images), done);
    status = 0;
done:
    if (event)
        clReleaseEvent(event);
    if (out)
        clReleaseMemObject(out);
    if (in)
        clReleaseMemObject(in);
    return status;
}
