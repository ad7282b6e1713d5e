#define _POSIX_C_SOURCE 200809L
#include "render/renderer.h"

#include "estimator/estimator_cl.h"
#include "estimator_core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void render_settings_default(RenderSettings *s)
{
    memset(s, 0, sizeof *s);
    s->estimator.set_count = ESTIMATOR_DEFAULT_SETS;
    s->estimator.gini_mode = GINI_PER_CHANNEL;
    s->outputs = ESTIMATOR_OUTPUT_MEAN | ESTIMATOR_OUTPUT_MON | ESTIMATOR_OUTPUT_GMON;
    s->sample_count = 64;
    s->seconds_per_pass = 0.5;
}

void render_output_free(RenderOutput *o)
{
    free(o->accumulators);
    free(o->rejected);
    free(o->mean);
    free(o->mon);
    free(o->gmon);
    free(o->gini);
    free(o->trim);
    memset(o, 0, sizeof *o);
}

typedef struct {
    cl_mem params, nodes, primitives, materials, emitters;
    cl_mem accumulators, rejected, rays;
    cl_mem images[5];
} DeviceBuffers;

static void release_buffers(DeviceBuffers *b)
{
    cl_mem *all[] = {&b->params,       &b->nodes,     &b->primitives, &b->materials, &b->emitters,
                     &b->accumulators, &b->rejected,  &b->rays,       &b->images[0], &b->images[1],
                     &b->images[2],    &b->images[3], &b->images[4]};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i)
        if (*all[i]) {
            clReleaseMemObject(*all[i]);
            *all[i] = NULL;
        }
}

/* A read-only buffer initialised from host data (at least one byte, as
 * OpenCL refuses empty buffers). */
static cl_mem upload(ClDevice *device, const void *data, size_t bytes, cl_int *err)
{
    static const uint64_t zero = 0;
    return clCreateBuffer(device->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes ? bytes : sizeof zero,
                          bytes ? (void *)data : (void *)&zero, err);
}

static cl_mem zeroed(ClDevice *device, size_t bytes, cl_int *err)
{
    cl_mem m = clCreateBuffer(device->context, CL_MEM_READ_WRITE, bytes, NULL, err);
    if (*err != CL_SUCCESS)
        return NULL;
    const cl_uchar zero = 0;
    *err = clEnqueueFillBuffer(device->queue, m, &zero, 1, 0, bytes, 0, NULL, NULL);
    return m;
}

int renderer_run(ClDevice *device, const RenderScene *scene, const RenderSettings *s, RenderOutput *out, char *error,
                 size_t error_size)
{
    memset(out, 0, sizeof *out);
    const int m = s->estimator.set_count;
    if (m < 1 || m > EST_MAX_SETS) {
        snprintf(error, error_size, "set count M = %d is out of range 1..%d", m, EST_MAX_SETS);
        return -1;
    }
    const size_t pixels = (size_t)scene->params.width * scene->params.height;
    const size_t words = (size_t)m * EST_CHANNELS * 2 * pixels;
    const size_t accumulator_bytes = words * sizeof(uint64_t);
    if (accumulator_bytes > device->info.max_allocation) {
        snprintf(error, error_size,
                 "the exact set sums of a %ux%u image with M = %d need %.2f GiB in one buffer, but device '%s' "
                 "allows %.2f GiB: lower the resolution or --sets",
                 scene->params.width, scene->params.height, m, (double)accumulator_bytes / 1073741824.0,
                 device->info.name, (double)device->info.max_allocation / 1073741824.0);
        return -1;
    }
    out->width = scene->params.width;
    out->height = scene->params.height;
    out->set_count = m;
    out->gini_mode = s->estimator.gini_mode;
    out->seed = s->seed;
    out->first_sample = s->first_sample;

    DeviceBuffers b;
    memset(&b, 0, sizeof b);
    cl_program program = NULL;
    cl_kernel kernel = NULL;
    EstimatorProgram *estimator = NULL;
    int status = -1;
    cl_int err = CL_SUCCESS;

    double build_start = now_seconds();
    /* The path tracer needs no bit-exact agreement with the host (only its
     * integer accumulation does, which no float option touches), so it may
     * reassociate: about 10% faster on PoCL. Results stay deterministic for
     * a given device and compiler. */
    char options[96];
    snprintf(options, sizeof options, "-DEST_SETS=%d -cl-unsafe-math-optimizations", m);
    program = cl_program_build(device, "path_tracer", options, s->kernel_dir);
    if (!program) {
        snprintf(error, error_size, "the path tracer failed to build on device '%s'", device->info.name);
        goto done;
    }
    kernel = clCreateKernel(program, "render_samples", &err);
    CL_CHECK(err, cl_failed);
    estimator = estimator_program_new(device, &s->estimator, s->outputs, s->kernel_dir);
    if (!estimator) {
        snprintf(error, error_size, "the estimator failed to build on device '%s'", device->info.name);
        goto done;
    }
    out->build_seconds = now_seconds() - build_start;

    RenderParams params = scene->params;
    params.seed = s->seed;
    b.params = upload(device, &params, sizeof params, &err);
    CL_CHECK(err, cl_failed);
    b.nodes = upload(device, scene->bvh.nodes, (size_t)scene->bvh.node_count * sizeof(BvhNode), &err);
    CL_CHECK(err, cl_failed);
    b.primitives = upload(device, scene->bvh.primitives, (size_t)scene->bvh.primitive_count * sizeof(Primitive), &err);
    CL_CHECK(err, cl_failed);
    b.materials = upload(device, scene->materials, (size_t)scene->material_count * sizeof(Material), &err);
    CL_CHECK(err, cl_failed);
    b.emitters = upload(device, scene->emitters, (size_t)scene->emitter_count * sizeof(Emitter), &err);
    CL_CHECK(err, cl_failed);
    b.accumulators = zeroed(device, accumulator_bytes, &err);
    CL_CHECK(err, cl_failed);
    b.rejected = zeroed(device, pixels * sizeof(uint32_t), &err);
    CL_CHECK(err, cl_failed);
    b.rays = zeroed(device, pixels * sizeof(uint64_t), &err);
    CL_CHECK(err, cl_failed);

    cl_ulong first_pixel = 0, pixel_count = pixels;
    CL_CHECK(clSetKernelArg(kernel, 0, sizeof(cl_mem), &b.params), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 1, sizeof(cl_mem), &b.nodes), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 2, sizeof(cl_mem), &b.primitives), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 3, sizeof(cl_mem), &b.materials), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 4, sizeof(cl_mem), &b.emitters), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 5, sizeof(cl_mem), &b.accumulators), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 6, sizeof(cl_mem), &b.rejected), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 7, sizeof(cl_mem), &b.rays), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 10, sizeof first_pixel, &first_pixel), cl_failed);
    CL_CHECK(clSetKernelArg(kernel, 11, sizeof pixel_count, &pixel_count), cl_failed);

    /* Progressive passes: the first renders one sample per pixel, later ones
     * as many as fit the pass length, judged from the speed so far. */
    double start = now_seconds();
    uint64_t done_samples = 0;
    uint32_t per_pass = 1;
    double target = s->seconds_per_pass > 0.0 ? s->seconds_per_pass : 0.5;
    while (done_samples < s->sample_count) {
        if (s->cancel && *s->cancel)
            break;
        uint64_t remaining = s->sample_count - done_samples;
        uint32_t count = remaining < per_pass ? (uint32_t)remaining : per_pass;
        cl_ulong first = s->first_sample + done_samples;
        CL_CHECK(clSetKernelArg(kernel, 8, sizeof first, &first), cl_failed);
        CL_CHECK(clSetKernelArg(kernel, 9, sizeof count, &count), cl_failed);
        double pass_start = now_seconds();
        size_t global = pixels;
        CL_CHECK(clEnqueueNDRangeKernel(device->queue, kernel, 1, NULL, &global, NULL, 0, NULL, NULL), cl_failed);
        CL_CHECK(clFinish(device->queue), cl_failed);
        double pass_seconds = now_seconds() - pass_start;
        done_samples += count;
        double elapsed = now_seconds() - start;
        if (s->progress)
            s->progress(s->progress_user, done_samples, s->sample_count, elapsed);
        if (s->time_budget > 0.0 && elapsed >= s->time_budget)
            break;
        double per_sample = pass_seconds / count;
        double budget_left = s->time_budget > 0.0 ? s->time_budget - elapsed : target;
        double fit = (budget_left < target ? budget_left : target) / (per_sample > 0.0 ? per_sample : 1e-9);
        per_pass = fit < 1.0 ? 1u : (fit > 4096.0 ? 4096u : (uint32_t)fit);
    }
    out->seconds = now_seconds() - start;
    out->sample_count = done_samples;

    /* Estimates, on the device, from the exact accumulators. */
    const int bits[5] = {ESTIMATOR_OUTPUT_MEAN, ESTIMATOR_OUTPUT_MON, ESTIMATOR_OUTPUT_GMON,
                         ESTIMATOR_OUTPUT_DIAGNOSTICS, ESTIMATOR_OUTPUT_DIAGNOSTICS};
    void **hosts[5] = {(void **)&out->mean, (void **)&out->mon, (void **)&out->gmon, (void **)&out->gini,
                       (void **)&out->trim};
    const size_t image_bytes = pixels * EST_CHANNELS * sizeof(float);
    for (int i = 0; i < 5; ++i) {
        if (!(s->outputs & bits[i]))
            continue;
        b.images[i] = clCreateBuffer(device->context, CL_MEM_WRITE_ONLY, image_bytes, NULL, &err);
        CL_CHECK(err, cl_failed);
        *hosts[i] = malloc(image_bytes);
        if (!*hosts[i])
            goto out_of_memory;
    }
    cl_event estimated = estimator_program_enqueue(estimator, b.accumulators, 1, pixels, done_samples, b.images[0],
                                                   b.images[1], b.images[2], b.images[3], b.images[4]);
    if (!estimated)
        goto cl_failed;
    clReleaseEvent(estimated);
    for (int i = 0; i < 5; ++i)
        if (b.images[i])
            CL_CHECK(clEnqueueReadBuffer(device->queue, b.images[i], CL_TRUE, 0, image_bytes, *hosts[i], 0, NULL, NULL),
                     cl_failed);

    out->accumulators = malloc(words * sizeof(uint64_t));
    out->rejected = malloc(pixels * sizeof(uint32_t));
    uint64_t *rays = malloc(pixels * sizeof(uint64_t));
    if (!out->accumulators || !out->rejected || !rays) {
        free(rays);
        goto out_of_memory;
    }
    CL_CHECK(clEnqueueReadBuffer(device->queue, b.accumulators, CL_TRUE, 0, words * sizeof(uint64_t), out->accumulators,
                                 0, NULL, NULL),
             cl_failed);
    CL_CHECK(clEnqueueReadBuffer(device->queue, b.rejected, CL_TRUE, 0, pixels * sizeof(uint32_t), out->rejected, 0,
                                 NULL, NULL),
             cl_failed);
    err = clEnqueueReadBuffer(device->queue, b.rays, CL_TRUE, 0, pixels * sizeof(uint64_t), rays, 0, NULL, NULL);
    for (size_t i = 0; i < pixels && err == CL_SUCCESS; ++i) {
        out->rays += rays[i];
        out->rejected_total += out->rejected[i];
    }
    free(rays);
    CL_CHECK(err, cl_failed);
    status = 0;
    goto done;

out_of_memory:
    snprintf(error, error_size, "out of memory for a %ux%u image with M = %d", out->width, out->height, m);
    goto done;
cl_failed:
    snprintf(error, error_size, "OpenCL failure on device '%s': %s", device->info.name, cl_last_error());
done:
    release_buffers(&b);
    estimator_program_destroy(estimator);
    if (kernel)
        clReleaseKernel(kernel);
    if (program)
        clReleaseProgram(program);
    if (status != 0)
        render_output_free(out);
    return status;
}
