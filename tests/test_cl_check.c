/* The OpenCL error reporting: the check macro records the call, file, line
 * and error name, and a failed build prints its log and options. */
#include "cl/cl_check.h"
#include "cl/cl_device.h"
#include "cl/kernel_sources.h"
#include "test_device.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static void test_error_names(void **state)
{
    (void)state;
    assert_string_equal(cl_error_name(CL_SUCCESS), "CL_SUCCESS");
    assert_string_equal(cl_error_name(CL_INVALID_VALUE), "CL_INVALID_VALUE");
    assert_string_equal(cl_error_name(CL_BUILD_PROGRAM_FAILURE), "CL_BUILD_PROGRAM_FAILURE");
    assert_string_equal(cl_error_name(CL_INVALID_KERNEL_NAME), "CL_INVALID_KERNEL_NAME");
    assert_string_equal(cl_error_name(-12345), "unknown OpenCL error");
}

static int failing_call(int *line)
{
    /* num_entries 0 with a non-NULL list is CL_INVALID_VALUE. */
    cl_platform_id platform;
    *line = __LINE__ + 1;
    CL_CHECK(clGetPlatformIDs(0, &platform, NULL), fail);
    return 0;
fail:
    return -1;
}

static void test_check_macro_records_call_file_line_and_name(void **state)
{
    (void)state;
    int line = 0;
    cl_set_error_printing(0);
    assert_int_equal(failing_call(&line), -1);
    cl_set_error_printing(1);
    const char *record = cl_last_error();
    char expected_line[32];
    snprintf(expected_line, sizeof expected_line, ":%d:", line);
    assert_non_null(strstr(record, "test_cl_check.c"));
    assert_non_null(strstr(record, expected_line));
    assert_non_null(strstr(record, "clGetPlatformIDs(0, &platform, NULL)"));
    assert_non_null(strstr(record, "CL_INVALID_VALUE"));
}

static void test_bad_kernel_name_is_reported(void **state)
{
    (void)state;
    ClDevice device;
    if (!test_device_open(&device))
        skip();
    cl_set_error_printing(0);
    cl_program program = cl_program_build(&device, "no_such_kernel_file", "", NULL);
    cl_set_error_printing(1);
    assert_null(program);
    cl_device_close(&device);
}

static void test_build_failure_reports_build_program_failure(void **state)
{
    (void)state;
    ClDevice device;
    if (!test_device_open(&device))
        skip();
    /* The estimator refuses to build without M. */
    cl_set_error_printing(0);
    cl_program program = cl_program_build(&device, "estimator", "-DTHIS_BUILD_MUST_FAIL", NULL);
    cl_set_error_printing(1);
    assert_null(program);
    assert_non_null(strstr(cl_last_error(), "CL_BUILD_PROGRAM_FAILURE"));
    cl_device_close(&device);
}

static void test_embedded_source_has_line_markers(void **state)
{
    (void)state;
    char error[256];
    char include_dir[4096];
    char *source = kernel_source_load("estimator", NULL, include_dir, sizeof include_dir, error, sizeof error);
    assert_non_null(source);
    assert_string_equal(include_dir, "");
    assert_non_null(strstr(source, "#line 1 \"kernels/film/estimators.h\""));
    assert_non_null(strstr(source, "#line 1 \"kernels/common/compat.h\""));
    /* The sorting networks the build generated, under their include name. */
    assert_non_null(strstr(source, "#line 1 \"kernels/film/sorting_networks.h\""));
    assert_non_null(strstr(source, "#define EST_NETWORK_64(CE)"));
    assert_non_null(strstr(source, "\"kernels/film/estimator.cl\""));
    assert_null(strstr(source, "#include \"estimators.h\""));
    free(source);
}

static void test_kernel_dir_override(void **state)
{
    (void)state;
    char error[256];
    char include_dir[4096];
    char *source = kernel_source_load("estimator", GMON_SOURCE_DIR "/kernels", include_dir, sizeof include_dir, error,
                                      sizeof error);
    assert_non_null(source);
    assert_string_equal(include_dir, GMON_SOURCE_DIR "/kernels/film");
    assert_non_null(strstr(source, "#include \"estimators.h\""));
    free(source);
    assert_null(
        kernel_source_load("estimator", "/nonexistent-dir", include_dir, sizeof include_dir, error, sizeof error));
    assert_non_null(strstr(error, "/nonexistent-dir/film/estimator.cl"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_names),
        cmocka_unit_test(test_check_macro_records_call_file_line_and_name),
        cmocka_unit_test(test_embedded_source_has_line_markers),
        cmocka_unit_test(test_kernel_dir_override),
        cmocka_unit_test(test_bad_kernel_name_is_reported),
        cmocka_unit_test(test_build_failure_reports_build_program_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
