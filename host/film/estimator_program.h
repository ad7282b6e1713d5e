/* The estimator kernels (kernels/film/estimator.cl) on an OpenCL device. */
#ifndef HOST_FILM_ESTIMATOR_PROGRAM_H
#define HOST_FILM_ESTIMATOR_PROGRAM_H

#include "cl/cl_device.h"
#include "film/film.h"

typedef struct EstimatorProgram EstimatorProgram;

/* How the estimator kernels run; chosen per device by
 * estimator_program_new, each fixable by hand (EstimatorLaunchChoice, from
 * an environment variable: for experiments). */
typedef struct {
    int vector_width; /* pixels per work item, one per vector lane: 1, 2, 4, 8 or 16
                         (ESTIMATOR_VECTOR_WIDTH_ENV; default on CPUs 8, or 16 with AVX-512
                         for estimates beyond the default set or standard errors; 1 elsewhere) */
    int local_size;   /* work items per work group, 0 for the runtime's choice
                         (ESTIMATOR_LOCAL_SIZE_ENV; default 256 / vector_width on CPUs, 0 elsewhere) */
    int prefetch;     /* CPUs: prefetch the input of the work item this many ahead, 0 for
                         none (ESTIMATOR_PREFETCH_ENV; default 1 on CPUs, 0 elsewhere) */
} EstimatorLaunch;

#define ESTIMATOR_VECTOR_WIDTH_ENV "GMON_ESTIMATOR_VECTOR_WIDTH"
#define ESTIMATOR_LOCAL_SIZE_ENV "GMON_ESTIMATOR_LOCAL_SIZE"
#define ESTIMATOR_PREFETCH_ENV "GMON_ESTIMATOR_PREFETCH"

/* Launch settings fixed by hand (developer options: main programs read
 * them once from the environment, estimator_launch_from_environment); a
 * field of -1 leaves its choice to estimator_program_new. */
typedef struct {
    int vector_width, local_size, prefetch;
} EstimatorLaunchChoice;
#define ESTIMATOR_LAUNCH_CHOSEN_PER_DEVICE ((EstimatorLaunchChoice){-1, -1, -1})

/* Fills *choice from ESTIMATOR_VECTOR_WIDTH_ENV, ESTIMATOR_LOCAL_SIZE_ENV
 * and ESTIMATOR_PREFETCH_ENV (-1 where unset or empty). Returns 0, or -1
 * after reporting a value out of range. */
int estimator_launch_from_environment(EstimatorLaunchChoice *choice);

/* The estimator kernel's build options for the settings (their per-sample
 * passes left out) and launch. */
void estimator_build_options(const EstimatorSettings *settings, const EstimatorLaunch *launch, char *options,
                             size_t size);

/* Builds the estimator program for the settings (M, Gini mode, passes,
 * standard errors; the parameters go with each run), launched as `choice`
 * fixes (NULL: chosen per device). Returns NULL after printing the reason.
 * kernel_dir: see kernel_sources.h. */
EstimatorProgram *estimator_program_new(ClDevice *device, const EstimatorSettings *settings,
                                        const EstimatorLaunchChoice *choice, const char *kernel_dir);
void estimator_program_destroy(EstimatorProgram *program);

EstimatorLaunch estimator_program_launch(const EstimatorProgram *program);

/* Bytes of the images of pixel_count pixels: one buffer of RGB planes, in
 * the order of pass_slot and stderr_slot (passes.h). */
size_t estimator_program_image_bytes(const EstimatorProgram *program, size_t pixel_count);

/* Enqueues the estimator on device buffers: `input` holds float set sums
 * or, with from_accumulators, exact accumulators; `images` is
 * estimator_program_image_bytes large. Returns the kernel's event (caller
 * releases), or NULL on error. */
cl_event estimator_program_enqueue(EstimatorProgram *program, cl_mem input, int from_accumulators, size_t pixel_count,
                                   uint64_t sample_count, cl_mem images);

/* Reads the images of pixels [first, first + pixel_count) from `images`
 * (as enqueued for pixel_count pixels) into host images, at those pixels;
 * blocking. Returns a CL error code. */
cl_int estimator_program_read(EstimatorProgram *program, cl_mem images, size_t first, size_t pixel_count,
                              EstimatorImages *host);

/* Convenience for tests: uploads host input, runs, downloads into `images`
 * (buffers not in the mask are left alone). Returns 0 on success. */
int estimator_program_run(EstimatorProgram *program, const void *input, int from_accumulators, size_t pixel_count,
                          uint64_t sample_count, EstimatorImages *images);

#endif
