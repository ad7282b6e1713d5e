/* Opening an OpenCL device in tests. Without a device a test is skipped,
 * except under CI=true, where a missing device is a failure. */
#ifndef TESTS_SUPPORT_TEST_DEVICE_H
#define TESTS_SUPPORT_TEST_DEVICE_H

#include "cl/cl_device.h"

/* Opens the first device into *device. Returns 1 on success; 0 when there is
 * none outside CI (the caller should skip()). Fails the test under CI. */
int test_device_open(ClDevice *device);

/* A cmocka group fixture: opens the first device into test_device and
 * closes it. Without a device the setup fails under CI; elsewhere it
 * succeeds and each test skips itself with REQUIRE_TEST_DEVICE(). */
extern ClDevice test_device;
int test_device_setup(void **state);
int test_device_teardown(void **state);
#define REQUIRE_TEST_DEVICE()                                                                                          \
    do {                                                                                                               \
        if (!test_device.context)                                                                                      \
            skip();                                                                                                    \
    } while (0)

/* True when the CI environment variable is "true". */
int test_running_in_ci(void);

#endif
