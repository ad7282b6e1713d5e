#include "film/sample_estimator_program.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The kernels; zirr's two steps are NULL unless zirr is requested. */
enum { ESTIMATE, ACCUMULATE, ZIRR_MEANS, ZIRR, KERNEL_COUNT };

struct SampleEstimatorProgram {
    ClDevice *device;
    EstimatorSettings settings;
    ClProgram cl;      /* kernels by the enum above */
    size_t local_size; /* 0: the runtime's */
};

/* One work item a pixel, in work groups of p->local_size: on CPUs small
 * ones, as the set estimator's (estimator_program.c: PoCL keeps a copy of a
 * work item's private arrays per item of its group, too many for its stack
 * in groups of thousands). */
static cl_int enqueue_pixels(SampleEstimatorProgram *p, int kernel, size_t pixel_count, cl_event *event)
{
    return cl_program_enqueue(&p->cl, p->cl.kernels[kernel], pixel_count, p->local_size, event);
}

int sample_passes_supported(const ClDevice *device, const EstimatorSettings *settings)
{
    if (!film_sample_needs_double(settings))
        return 1;
    char extensions[4096] = "";
    clGetDeviceInfo(device->info.id, CL_DEVICE_EXTENSIONS, sizeof extensions - 1, extensions, NULL);
    if (strstr(extensions, "cl_khr_fp64"))
        return 1;
    fprintf(stderr,
            "abmm, gabmm and mean-or-mon keep and compute their moments in double precision, which device '%s' "
            "lacks (no cl_khr_fp64): render them on another device\n",
            device->info.name);
    return 0;
}

SampleEstimatorProgram *sample_estimator_program_new(ClDevice *device, const EstimatorSettings *settings,
                                                     const char *kernel_dir)
{
    if (!film_sample_passes(settings)) {
        fprintf(stderr, "sample estimator: no per-sample pass requested\n");
        return NULL;
    }
    SampleEstimatorProgram *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->device = device;
    p->settings = *settings;
    p->local_size = (device->info.type & CL_DEVICE_TYPE_CPU) ? 32 : 0;
    if (!sample_passes_supported(device, settings))
        goto fail;
    char options[768];
    film_sample_estimator_options(settings, options, sizeof options);
    int zirr = (film_sample_passes(settings) & PASS_BIT(PASS_ZIRR)) != 0;
    const char *const kernels[KERNEL_COUNT] = {"estimate_sample_passes", "accumulate_sample_stream",
                                               zirr ? "zirr_means" : NULL, zirr ? "estimate_zirr" : NULL};
    if (cl_program_open(&p->cl, device, "sample_estimator", options, kernel_dir, kernels, KERNEL_COUNT) != 0)
        goto fail;
    return p;
fail:
    sample_estimator_program_destroy(p);
    return NULL;
}

void sample_estimator_program_destroy(SampleEstimatorProgram *p)
{
    if (!p)
        return;
    cl_program_close(&p->cl);
    free(p);
}

/* The images estimate_sample_passes writes: all but zirr's
 * (sample_estimator_program_zirr's, over the whole image). */
static int image_count(const SampleEstimatorProgram *p)
{
    const uint32_t pixel_passes = SAMPLE_PIXEL_PASSES(film_sample_passes(&p->settings));
    return sample_image_slot(pixel_passes, p->settings.params.clamp_level_count, PASS_COUNT, 0);
}

size_t sample_estimator_program_image_bytes(const SampleEstimatorProgram *p, size_t pixel_count)
{
    return (size_t)image_count(p) * pixel_count * EST_CHANNELS * sizeof(float);
}

cl_event sample_estimator_program_enqueue(SampleEstimatorProgram *p, cl_mem state, cl_mem accumulators,
                                          size_t pixel_count, uint64_t sample_count, cl_mem images)
{
    cl_ulong pixels = pixel_count, samples = sample_count, first = p->settings.first_sample;
    cl_event event = NULL;
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 0, sizeof state, &state), fail);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 1, sizeof accumulators, &accumulators), fail);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 2, sizeof pixels, &pixels), fail);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 3, sizeof samples, &samples), fail);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 4, sizeof first, &first), fail);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ESTIMATE], 5, sizeof images, &images), fail);
    CL_CHECK(enqueue_pixels(p, ESTIMATE, pixel_count, &event), fail);
    return event;
fail:
    return NULL;
}

cl_int sample_estimator_program_read(SampleEstimatorProgram *p, cl_mem images, size_t first, size_t pixel_count,
                                     size_t image_pixels, EstimatorImages *host)
{
    const uint32_t pixel_passes = SAMPLE_PIXEL_PASSES(film_sample_passes(&p->settings));
    const int levels = p->settings.params.clamp_level_count;
    const size_t plane = pixel_count * EST_CHANNELS * sizeof(float);
    for (int pass = PASS_CLAMP; pass < PASS_COUNT; ++pass) {
        if (!host->pass[pass])
            continue;
        for (int i = 0; i < sample_pass_images(pixel_passes, levels, pass); ++i) {
            char *target = (char *)host->pass[pass] + ((size_t)i * image_pixels + first) * EST_CHANNELS * sizeof(float);
            cl_int err = clEnqueueReadBuffer(p->device->queue, images, CL_TRUE,
                                             (size_t)sample_image_slot(pixel_passes, levels, pass, i) * plane, plane,
                                             target, 0, NULL, NULL);
            if (err != CL_SUCCESS) {
                cl_report_error("clEnqueueReadBuffer", err, __FILE__, __LINE__);
                return err;
            }
        }
    }
    return CL_SUCCESS;
}

int sample_estimator_program_run_stream(SampleEstimatorProgram *p, const float *parts, size_t stream_length,
                                        size_t pixel_count, uint64_t *accumulators, uint64_t *state,
                                        EstimatorImages *images)
{
    cl_context ctx = p->device->context;
    const size_t state_bytes = film_sample_planes(&p->settings) * pixel_count * sizeof(uint64_t);
    const size_t set_bytes = accumulator_planes((uint32_t)p->settings.set_count) * pixel_count * sizeof(uint64_t);
    memset(state, 0, state_bytes);
    memset(accumulators, 0, set_bytes);
    cl_int err = CL_SUCCESS;
    cl_mem in = NULL, st = NULL, out = NULL, sets = NULL;
    cl_event event = NULL;
    int status = -1;
    in = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        (stream_length ? stream_length : 1) * pixel_count * 10 * sizeof(float), (void *)parts, &err);
    CL_CHECK(err, done);
    st = clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, state_bytes, state, &err);
    CL_CHECK(err, done);
    const size_t image_bytes = sample_estimator_program_image_bytes(p, pixel_count);
    out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, image_bytes ? image_bytes : sizeof(float), NULL, &err);
    CL_CHECK(err, done);
    sets = clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, set_bytes, accumulators, &err);
    CL_CHECK(err, done);
    cl_ulong length = stream_length, pixels = pixel_count;
    float direct = p->settings.params.clamp_sum_direct, indirect = p->settings.params.clamp_sum_indirect;
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 0, sizeof in, &in), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 1, sizeof length, &length), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 2, sizeof sets, &sets), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 3, sizeof st, &st), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 4, sizeof pixels, &pixels), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 5, sizeof direct, &direct), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 6, sizeof indirect, &indirect), done);
    cl_ulong first = p->settings.first_sample;
    CL_CHECK(clSetKernelArg(p->cl.kernels[ACCUMULATE], 7, sizeof first, &first), done);
    CL_CHECK(enqueue_pixels(p, ACCUMULATE, pixel_count, NULL), done);
    CL_CHECK(clEnqueueReadBuffer(p->device->queue, st, CL_TRUE, 0, state_bytes, state, 0, NULL, NULL), done);
    CL_CHECK(clEnqueueReadBuffer(p->device->queue, sets, CL_TRUE, 0, set_bytes, accumulators, 0, NULL, NULL), done);
    event = sample_estimator_program_enqueue(p, st, sets, pixel_count, stream_length, out);
    if (!event)
        goto done;
    CL_CHECK(sample_estimator_program_read(p, out, 0, pixel_count, pixel_count, images), done);
    status = 0;
done:
    if (event)
        clReleaseEvent(event);
    if (out)
        clReleaseMemObject(out);
    if (st)
        clReleaseMemObject(st);
    if (sets)
        clReleaseMemObject(sets);
    if (in)
        clReleaseMemObject(in);
    return status;
}

int sample_estimator_program_zirr(SampleEstimatorProgram *p, const uint64_t *state, const uint64_t *accumulators,
                                  uint32_t width, uint32_t height, uint64_t sample_count, float *image, double *seconds)
{
    if (!p->cl.kernels[ZIRR])
        return -1;
    cl_context ctx = p->device->context;
    const size_t pixel_count = (size_t)width * height;
    const size_t cascade_bytes = film_sample_zirr_planes(&p->settings) * pixel_count * sizeof(uint64_t);
    const size_t set_bytes = accumulator_planes((uint32_t)p->settings.set_count) * pixel_count * sizeof(uint64_t);
    const size_t mean_bytes = (size_t)p->settings.params.zirr_k * pixel_count * EST_CHANNELS * sizeof(float);
    const size_t image_bytes = pixel_count * EST_CHANNELS * sizeof(float);
    cl_int err = CL_SUCCESS;
    cl_mem st = NULL, sets = NULL, means = NULL, out = NULL;
    cl_event events[2] = {NULL, NULL};
    int status = -1;
    st = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, cascade_bytes,
                        (void *)film_sample_zirr_block(&p->settings, state, pixel_count), &err);
    CL_CHECK(err, done);
    sets = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, set_bytes, (void *)accumulators, &err);
    CL_CHECK(err, done);
    means = clCreateBuffer(ctx, CL_MEM_READ_WRITE, mean_bytes, NULL, &err);
    CL_CHECK(err, done);
    out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, image_bytes, NULL, &err);
    CL_CHECK(err, done);
    cl_uint w = width, h = height;
    cl_ulong pixels = pixel_count, samples = sample_count;
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR_MEANS], 0, sizeof st, &st), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR_MEANS], 1, sizeof sets, &sets), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR_MEANS], 2, sizeof pixels, &pixels), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR_MEANS], 3, sizeof samples, &samples), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR_MEANS], 4, sizeof means, &means), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR], 0, sizeof means, &means), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR], 1, sizeof w, &w), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR], 2, sizeof h, &h), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR], 3, sizeof samples, &samples), done);
    CL_CHECK(clSetKernelArg(p->cl.kernels[ZIRR], 4, sizeof out, &out), done);
    CL_CHECK(enqueue_pixels(p, ZIRR_MEANS, pixel_count, &events[0]), done);
    CL_CHECK(enqueue_pixels(p, ZIRR, pixel_count, &events[1]), done);
    CL_CHECK(clEnqueueReadBuffer(p->device->queue, out, CL_TRUE, 0, image_bytes, image, 0, NULL, NULL), done);
    if (seconds)
        *seconds += cl_event_seconds(events[0]) + cl_event_seconds(events[1]);
    status = 0;
done:
    for (int i = 0; i < 2; ++i)
        if (events[i])
            clReleaseEvent(events[i]);
    if (out)
        clReleaseMemObject(out);
    if (means)
        clReleaseMemObject(means);
    if (st)
        clReleaseMemObject(st);
    if (sets)
        clReleaseMemObject(sets);
    return status;
}
