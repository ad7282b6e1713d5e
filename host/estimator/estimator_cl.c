#include "estimator/estimator_cl.h"

#include "estimator_core.h"

#include <stdio.h>
#include <stdlib.h>

struct EstimatorProgram {
    ClDevice *device;
    EstimatorSettings settings;
    int outputs;
    cl_program program;
    cl_kernel from_sums;
    cl_kernel from_accumulators;
};

EstimatorProgram *estimator_program_new(ClDevice *device, const EstimatorSettings *settings, int outputs,
                                        const char *kernel_dir)
{
    if (settings->set_count < 1 || settings->set_count > EST_MAX_SETS) {
        fprintf(stderr, "estimator: set count M = %d is out of range 1..%d\n", settings->set_count, EST_MAX_SETS);
        return NULL;
    }
    EstimatorProgram *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->device = device;
    p->settings = *settings;
    p->outputs = outputs;
    char options[256];
    snprintf(options, sizeof options, "-DEST_SETS=%d -DEST_GINI_MODE=%d -DEST_OUTPUTS=%d", settings->set_count,
             (int)settings->gini_mode, outputs);
    p->program = cl_program_build(device, "estimator", options, kernel_dir);
    if (!p->program)
        goto fail;
    cl_int err = CL_SUCCESS;
    p->from_sums = clCreateKernel(p->program, "estimate_from_sums", &err);
    CL_CHECK(err, fail);
    p->from_accumulators = clCreateKernel(p->program, "estimate_from_accumulators", &err);
    CL_CHECK(err, fail);
    return p;
fail:
    estimator_program_destroy(p);
    return NULL;
}

void estimator_program_destroy(EstimatorProgram *p)
{
    if (!p)
        return;
    if (p->from_sums)
        clReleaseKernel(p->from_sums);
    if (p->from_accumulators)
        clReleaseKernel(p->from_accumulators);
    if (p->program)
        clReleaseProgram(p->program);
    free(p);
}

cl_event estimator_program_enqueue(EstimatorProgram *p, cl_mem input, int from_accumulators, size_t pixel_count,
                                   uint64_t sample_count, cl_mem mean, cl_mem mon, cl_mem gmon, cl_mem gini,
                                   cl_mem trim)
{
    cl_kernel k = from_accumulators ? p->from_accumulators : p->from_sums;
    cl_ulong pixels = pixel_count, samples = sample_count;
    cl_mem outputs[5] = {mean, mon, gmon, gini, trim};
    cl_event event = NULL;
    CL_CHECK(clSetKernelArg(k, 0, sizeof input, &input), fail);
    CL_CHECK(clSetKernelArg(k, 1, sizeof pixels, &pixels), fail);
    CL_CHECK(clSetKernelArg(k, 2, sizeof samples, &samples), fail);
    for (cl_uint i = 0; i < 5; ++i)
        CL_CHECK(clSetKernelArg(k, 3 + i, sizeof(cl_mem), outputs[i] ? &outputs[i] : NULL), fail);
    size_t global = pixel_count;
    CL_CHECK(clEnqueueNDRangeKernel(p->device->queue, k, 1, NULL, &global, NULL, 0, NULL, &event), fail);
    return event;
fail:
    return NULL;
}

int estimator_program_run(EstimatorProgram *p, const void *input, int from_accumulators, size_t pixel_count,
                          uint64_t sample_count, EstimatorImages *images)
{
    cl_context ctx = p->device->context;
    cl_command_queue queue = p->device->queue;
    size_t values = (size_t)p->settings.set_count * EST_CHANNELS * pixel_count;
    size_t input_bytes = from_accumulators ? values * 2 * sizeof(uint64_t) : values * sizeof(float);
    size_t image_bytes = pixel_count * EST_CHANNELS * sizeof(float);
    void *hosts[5] = {images->mean, images->mon, images->gmon, images->gini, images->trim};
    const int bits[5] = {ESTIMATOR_OUTPUT_MEAN, ESTIMATOR_OUTPUT_MON, ESTIMATOR_OUTPUT_GMON,
                         ESTIMATOR_OUTPUT_DIAGNOSTICS, ESTIMATOR_OUTPUT_DIAGNOSTICS};
    cl_mem buffers[5] = {0};
    cl_event event = NULL;
    int status = -1;
    cl_int err = CL_SUCCESS;
    cl_mem in = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, input_bytes, (void *)input, &err);
    CL_CHECK(err, done);
    for (int i = 0; i < 5; ++i) {
        if (!(p->outputs & bits[i]) || !hosts[i])
            continue;
        buffers[i] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, image_bytes, NULL, &err);
        CL_CHECK(err, done);
    }
    event = estimator_program_enqueue(p, in, from_accumulators, pixel_count, sample_count, buffers[0], buffers[1],
                                      buffers[2], buffers[3], buffers[4]);
    if (!event)
        goto done;
    for (int i = 0; i < 5; ++i)
        if (buffers[i])
            CL_CHECK(clEnqueueReadBuffer(queue, buffers[i], CL_TRUE, 0, image_bytes, hosts[i], 0, NULL, NULL),
                     done);
    status = 0;
done:
    if (event)
        clReleaseEvent(event);
    for (int i = 0; i < 5; ++i)
        if (buffers[i])
            clReleaseMemObject(buffers[i]);
    if (in)
        clReleaseMemObject(in);
    return status;
}
