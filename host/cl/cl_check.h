/* Checked OpenCL calls.
 *
 *   CL_CHECK(clFinish(queue), fail);
 *   cl_mem m = clCreateBuffer(ctx, flags, size, NULL, &err);
 *   CL_CHECK(err, fail);
 *
 * On failure the call's text, file, line and the error's name are printed to
 * stderr, recorded (cl_last_error) and control jumps to the cleanup label. */
#ifndef HOST_CL_CL_CHECK_H
#define HOST_CL_CL_CHECK_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

/* The name of an OpenCL error code, e.g. "CL_INVALID_VALUE". */
const char *cl_error_name(cl_int code);

/* Prints and records a failed call. */
void cl_report_error(const char *call, cl_int code, const char *file, int line);

/* The last failure recorded on this thread: "file:line: call failed: NAME (code)",
 * or "" if none. */
const char *cl_last_error(void);

/* Makes cl_report_error record without printing (tests of the reporting). */
void cl_set_error_printing(int enabled);

#define CL_CHECK(call, label)                                                                                          \
    do {                                                                                                               \
        cl_int cl_check_code_ = (call);                                                                                \
        if (cl_check_code_ != CL_SUCCESS) {                                                                            \
            cl_report_error(#call, cl_check_code_, __FILE__, __LINE__);                                                \
            goto label;                                                                                                \
        }                                                                                                              \
    } while (0)

#endif
