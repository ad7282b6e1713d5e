#include "test_device.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

int test_running_in_ci(void)
{
    const char *ci = getenv("CI");
    return ci && strcmp(ci, "true") == 0;
}

int test_device_open(ClDevice *device)
{
    /* CTest sets POCL_CACHE_DIR; this covers running a test binary by hand. */
    int status = cl_device_open_first(device, "/tmp/gmon-pocl-cache");
    if (status == 0)
        return 1;
    if (test_running_in_ci())
        fail_msg("no usable OpenCL device (status %d) and CI=true: a missing device is a failure. "
                 "Is pocl-opencl-icd installed and POCL_CACHE_DIR writable?",
                 status);
    fprintf(stderr, "no OpenCL device: skipping (this would fail under CI=true)\n");
    return 0;
}

ClDevice test_device;

int test_device_setup(void **state)
{
    (void)state;
    test_device_open(&test_device); /* fails the group under CI */
    return 0;
}

int test_device_teardown(void **state)
{
    (void)state;
    cl_device_close(&test_device);
    return 0;
}
