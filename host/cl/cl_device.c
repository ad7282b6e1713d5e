#define _POSIX_C_SOURCE 200809L
#include "cl/cl_device.h"

#include "cl/kernel_sources.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cl_devices_enumerate(ClDeviceInfo *devices, int capacity)
{
    cl_platform_id platforms[16];
    cl_uint platform_count = 0;
    cl_int err = clGetPlatformIDs(16, platforms, &platform_count);
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR: no ICD installed */ || platform_count == 0)
        return 0;
    CL_CHECK(err, fail);
    if (platform_count > 16)
        platform_count = 16;
    int found = 0;
    for (cl_uint p = 0; p < platform_count; ++p) {
        cl_device_id ids[64];
        cl_uint count = 0;
        err = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 64, ids, &count);
        if (err == CL_DEVICE_NOT_FOUND)
            continue;
        CL_CHECK(err, fail);
        if (count > 64)
            count = 64;
        for (cl_uint d = 0; d < count && found < capacity; ++d) {
            ClDeviceInfo *info = &devices[found++];
            memset(info, 0, sizeof *info);
            info->platform = platforms[p];
            info->id = ids[d];
            cl_device_fp_config fp = 0;
            CL_CHECK(clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof info->platform_name, info->platform_name,
                                       NULL),
                     fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_NAME, sizeof info->name, info->name, NULL), fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_TYPE, sizeof info->type, &info->type, NULL), fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof info->compute_units,
                                     &info->compute_units, NULL),
                     fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof info->global_memory,
                                     &info->global_memory, NULL),
                     fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof info->max_allocation,
                                     &info->max_allocation, NULL),
                     fail);
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL), fail);
            info->correctly_rounded_divide = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
            CL_CHECK(clGetDeviceInfo(ids[d], CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT, sizeof info->native_float_width,
                                     &info->native_float_width, NULL),
                     fail);
        }
    }
    return found;
fail:
    return -1;
}

const char *cl_device_type_name(cl_device_type type)
{
    if (type & CL_DEVICE_TYPE_GPU)
        return "GPU";
    if (type & CL_DEVICE_TYPE_CPU)
        return "CPU";
    if (type & CL_DEVICE_TYPE_ACCELERATOR)
        return "accelerator";
    return "other";
}

int cl_device_open(ClDevice *device, const ClDeviceInfo *info)
{
    cl_int err = CL_SUCCESS;
    memset(device, 0, sizeof *device);
    device->info = *info;
    cl_context_properties properties[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)info->platform, 0};
    device->context = clCreateContext(properties, 1, &info->id, NULL, NULL, &err);
    CL_CHECK(err, fail);
    device->queue = clCreateCommandQueue(device->context, info->id, CL_QUEUE_PROFILING_ENABLE, &err);
    CL_CHECK(err, fail);
    return 0;
fail:
    cl_device_close(device);
    return -1;
}

void cl_device_close(ClDevice *device)
{
    if (device->queue)
        clReleaseCommandQueue(device->queue);
    if (device->context)
        clReleaseContext(device->context);
    device->queue = NULL;
    device->context = NULL;
}

static void print_build_log(const ClDevice *device, cl_program program, const char *name, const char *options)
{
    size_t size = 0;
    clGetProgramBuildInfo(program, device->info.id, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
    char *log = malloc(size + 1);
    if (log && clGetProgramBuildInfo(program, device->info.id, CL_PROGRAM_BUILD_LOG, size, log, NULL) == CL_SUCCESS)
        log[size] = '\0';
    fprintf(stderr, "OpenCL program '%s' failed to build on device '%s' (%s)\n  options: %s\n  build log:\n%s\n", name,
            device->info.name, device->info.platform_name, options, log ? log : "(unavailable)");
    free(log);
}

cl_program cl_program_build(ClDevice *device, const char *name, const char *options, const char *kernel_dir)
{
    char error[512];
    char include_dir[4096];
    char *source = kernel_source_load(name, kernel_dir, include_dir, sizeof include_dir, error, (int)sizeof error);
    if (!source) {
        fprintf(stderr, "%s\n", error);
        return NULL;
    }
    /* Correctly rounded division keeps devices that default to approximate
     * division (GPUs) bit-identical with the host. Sources read from a
     * directory include its headers, then the ones the build generated. */
    const char *generated_dir = kernel_source_generated_dir();
    size_t length = strlen(options) + strlen(include_dir) + 2 * strlen(generated_dir) + 128;
    char *all_options = malloc(length);
    if (!all_options) {
        free(source);
        return NULL;
    }
    int used = snprintf(all_options, length, "-cl-std=CL1.2%s",
                        device->info.correctly_rounded_divide ? " -cl-fp32-correctly-rounded-divide-sqrt" : "");
    if (include_dir[0])
        used += snprintf(all_options + used, length - (size_t)used, " -I %s -I %s/film -I %s/tracing", include_dir,
                         generated_dir, generated_dir);
    snprintf(all_options + used, length - (size_t)used, " %s", options);

    cl_int err = CL_SUCCESS;
    const char *sources[] = {source};
    cl_program program = clCreateProgramWithSource(device->context, 1, sources, NULL, &err);
    CL_CHECK(err, fail);
    err = clBuildProgram(program, 1, &device->info.id, all_options, NULL, NULL);
    if (err != CL_SUCCESS) {
        cl_report_error("clBuildProgram", err, __FILE__, __LINE__);
        print_build_log(device, program, name, all_options);
        goto fail;
    }
    free(source);
    free(all_options);
    return program;
fail:
    if (program)
        clReleaseProgram(program);
    free(source);
    free(all_options);
    return NULL;
}

int cl_program_open(ClProgram *p, ClDevice *device, const char *name, const char *options, const char *kernel_dir,
                    const char *const *kernel_names, int count)
{
    memset(p, 0, sizeof *p);
    p->device = device;
    if (count > CL_PROGRAM_KERNELS_MAX) {
        fprintf(stderr, "OpenCL program '%s': more than %d kernels\n", name, CL_PROGRAM_KERNELS_MAX);
        return -1;
    }
    p->program = cl_program_build(device, name, options, kernel_dir);
    if (!p->program)
        return -1;
    for (int i = 0; i < count; ++i) {
        if (!kernel_names[i])
            continue;
        cl_int err = CL_SUCCESS;
        p->kernels[i] = clCreateKernel(p->program, kernel_names[i], &err);
        CL_CHECK(err, fail);
    }
    return 0;
fail:
    cl_program_close(p);
    return -1;
}

void cl_program_close(ClProgram *p)
{
    for (int i = 0; i < CL_PROGRAM_KERNELS_MAX; ++i)
        if (p->kernels[i])
            clReleaseKernel(p->kernels[i]);
    if (p->program)
        clReleaseProgram(p->program);
    memset(p, 0, sizeof *p);
}

cl_int cl_program_enqueue(const ClProgram *p, cl_kernel kernel, size_t items, size_t local, cl_event *event)
{
    size_t global = local > 0 ? (items + local - 1) / local * local : items;
    return clEnqueueNDRangeKernel(p->device->queue, kernel, 1, NULL, &global, local > 0 ? &local : NULL, 0, NULL,
                                  event);
}

int cl_device_open_first(ClDevice *device, const char *cache_dir)
{
    if (cache_dir && !getenv("POCL_CACHE_DIR"))
        setenv("POCL_CACHE_DIR", cache_dir, 0);
    ClDeviceInfo infos[8];
    int count = cl_devices_enumerate(infos, 8);
    if (count < 0)
        return -1;
    if (count == 0)
        return 1;
    return cl_device_open(device, &infos[0]);
}

double cl_event_seconds(cl_event event)
{
    cl_ulong start = 0, end = 0;
    clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof start, &start, NULL);
    clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end, &end, NULL);
    return (double)(end - start) * 1e-9;
}
