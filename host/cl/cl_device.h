/* OpenCL devices: enumeration, a context and queue per device, and program
 * builds that always show the build log and options on failure. */
#ifndef HOST_CL_CL_DEVICE_H
#define HOST_CL_CL_DEVICE_H

#include "cl/cl_check.h"

#include <stddef.h>

typedef struct {
    cl_platform_id platform;
    cl_device_id id;
    char platform_name[128];
    char name[256];
    cl_device_type type;
    cl_uint compute_units;
    cl_ulong global_memory;
    cl_ulong max_allocation;
    int correctly_rounded_divide; /* CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT */
    cl_uint native_float_width;   /* CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT: floats in a register */
} ClDeviceInfo;

/* Fills up to `capacity` entries with every device of every platform.
 * Returns the number found (0 when there is no platform or device), or -1 on
 * an OpenCL error. */
int cl_devices_enumerate(ClDeviceInfo *devices, int capacity);

/* "CPU", "GPU", "accelerator" or "other". */
const char *cl_device_type_name(cl_device_type type);

typedef struct {
    ClDeviceInfo info;
    cl_context context;
    cl_command_queue queue;
} ClDevice;

/* Opens a context and an in-order queue (with profiling) on one device.
 * Returns 0 on success. */
int cl_device_open(ClDevice *device, const ClDeviceInfo *info);
void cl_device_close(ClDevice *device);

/* Builds kernel file `name` (see kernel_sources.h) for the device with
 * `options` (defines etc.). On failure prints the device, the options and
 * the build log, and returns NULL. kernel_dir may be NULL. */
cl_program cl_program_build(ClDevice *device, const char *name, const char *options, const char *kernel_dir);

/* A built program with its kernels: what the estimator programs
 * (host/film/estimator_program.h, sample_estimator_program.h) wrap. */
#define CL_PROGRAM_KERNELS_MAX 8
typedef struct {
    ClDevice *device;
    cl_program program;
    cl_kernel kernels[CL_PROGRAM_KERNELS_MAX];
} ClProgram;

/* Builds kernel file `name` (as cl_program_build) and creates the `count`
 * kernels named in kernel_names, in that order (a NULL name leaves its
 * kernel NULL). Returns 0, or -1 after reporting the error and releasing
 * what was made. */
int cl_program_open(ClProgram *p, ClDevice *device, const char *name, const char *options, const char *kernel_dir,
                    const char *const *kernel_names, int count);
void cl_program_close(ClProgram *p);

/* Enqueues `kernel` over `items` work items in work groups of `local` (0:
 * the runtime's choice), rounded up to whole groups: the kernels skip the
 * items past the end. */
cl_int cl_program_enqueue(const ClProgram *p, cl_kernel kernel, size_t items, size_t local, cl_event *event);

/* Opens the first device, for tests and tools that need one. Sets
 * POCL_CACHE_DIR to `cache_dir` first if it is unset (PoCL lists no device
 * without a writable cache). Returns 0 on success, 1 if no device exists,
 * -1 on an OpenCL error. */
int cl_device_open_first(ClDevice *device, const char *cache_dir);

/* Seconds between an event's start and end (needs the profiling queue). */
double cl_event_seconds(cl_event event);

#endif
