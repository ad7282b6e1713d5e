/* The per-sample estimators' kernels (kernels/film/sample_estimator.cl) on an
 * OpenCL device: film_sample.h's estimation, bit for bit. */
#ifndef HOST_FILM_SAMPLE_ESTIMATOR_PROGRAM_H
#define HOST_FILM_SAMPLE_ESTIMATOR_PROGRAM_H

#include "cl/cl_device.h"
#include "film/film_sample.h"

typedef struct SampleEstimatorProgram SampleEstimatorProgram;

/* Whether `device` can accumulate and estimate the settings' per-sample
 * passes (abmm, gabmm and mean-or-mon need cl_khr_fp64); if not, prints
 * why and returns 0. */
int sample_passes_supported(const ClDevice *device, const EstimatorSettings *settings);

/* Builds the program for the settings' per-sample passes (none requested:
 * an error). Returns NULL after printing the reason. */
SampleEstimatorProgram *sample_estimator_program_new(ClDevice *device, const EstimatorSettings *settings,
                                                     const char *kernel_dir);
void sample_estimator_program_destroy(SampleEstimatorProgram *program);

/* Bytes of the images of pixel_count pixels that sample_estimator_program_enqueue
 * writes (every per-sample image but zirr's; 0 for zirr alone). */
size_t sample_estimator_program_image_bytes(const SampleEstimatorProgram *program, size_t pixel_count);

/* Enqueues the estimation of `state` and the set sums `accumulators`
 * (pixel_count pixels) into `images`; returns the kernel's event (caller
 * releases) or NULL. */
cl_event sample_estimator_program_enqueue(SampleEstimatorProgram *program, cl_mem state, cl_mem accumulators,
                                          size_t pixel_count, uint64_t sample_count, cl_mem images);

/* Reads the images (as enqueued for pixel_count pixels) into host images
 * at pixels [first, first + pixel_count); blocking. */
cl_int sample_estimator_program_read(SampleEstimatorProgram *program, cl_mem images, size_t first, size_t pixel_count,
                                     size_t image_pixels, EstimatorImages *host);

/* Tests: runs the kernel's accumulation on a stream (stream_length
 * samples a pixel, SampleParts as 10 floats, sets by the settings' M and
 * first sample) into host set sums and state (both zeroed first), then
 * estimates into host images. 0 on success. */
int sample_estimator_program_run_stream(SampleEstimatorProgram *program, const float *parts, size_t stream_length,
                                        size_t pixel_count, uint64_t *accumulators, uint64_t *state,
                                        EstimatorImages *images);

/* zirr's image (film_sample_estimate_zirr's, computed by the kernel
 * estimate_zirr) from the host state and set sums of a whole width x
 * height image, its cascades and set sums uploaded for it; adds the
 * kernel's time to *seconds (if not NULL). Returns 0, or -1 (zirr not
 * requested, or an OpenCL error, reported). */
int sample_estimator_program_zirr(SampleEstimatorProgram *program, const uint64_t *state, const uint64_t *accumulators,
                                  uint32_t width, uint32_t height, uint64_t sample_count, float *image,
                                  double *seconds);

#endif
