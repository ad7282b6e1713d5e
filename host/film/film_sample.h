/* The host side of the per-sample estimators (kernels/film/sample_passes.h):
 * which state and images a render's settings ask for, the kernels' build
 * options, the layer names, and the host estimation (the reference the
 * kernels are tested against, and what a render without a device left
 * uses). Nothing is allocated for a render that requests none of them.
 *
 * The state is sample_state_planes() planes of uint64 per pixel; a pass's
 * images lie in EstimatorImages.pass[pass], clamp's levels one after the
 * other (image i at i * 3 * pixel_count floats). */
#ifndef HOST_FILM_FILM_SAMPLE_H
#define HOST_FILM_FILM_SAMPLE_H

#include "film/film.h"
#define SAMPLE_PASSES_DOUBLE /* abmm, gabmm, mean-or-mon: their moments in double */
#include "sample_passes.h"   /* kernels/ */

#include <stddef.h>
#include <stdint.h>

/* The requested per-sample passes. */
uint32_t film_sample_passes(const EstimatorSettings *settings);

/* uint64 planes of per-sample state per pixel (0: none requested). */
size_t film_sample_planes(const EstimatorSettings *settings);

/* RGB images of `pass` (0 if not requested). */
int film_sample_pass_images(const EstimatorSettings *settings, int pass);

/* RGB images of every requested per-sample pass together. */
int film_sample_images(const EstimatorSettings *settings);

/* The build options of the path tracer and sample estimator for the
 * settings: "" when none is requested, else " -DEST_SAMPLE_PASSES=..."
 * (with a leading space), with abmm/gabmm/mean-or-mon -DSAMPLE_SUMS_DOUBLE. */
void film_sample_build_options(const EstimatorSettings *settings, char *options, size_t size);

/* The sample estimator's build options: film_sample_build_options,
 * -DEST_SETS=M (every pass reads the set sums), and for
 * abmm/gabmm/mean-or-mon -DSAMPLE_PASSES_DOUBLE. */
void film_sample_estimator_options(const EstimatorSettings *settings, char *options, size_t size);

/* Whether the passes need double precision on the device (cl_khr_fp64). */
int film_sample_needs_double(const EstimatorSettings *settings);

/* Whether the passes need the render's M sets (gabmm's Gbar, mean-or-mon's
 * sets): the render keeps them. The others read the set sums' total only
 * (one set will do). */
int film_sample_needs_sets(const EstimatorSettings *settings);

/* The EXR layer of image `index` of `pass`: clamp-<V> (V as the shortest
 * decimal that reads back as the level), or the pass name. */
void film_sample_layer_name(const EstimatorSettings *settings, int pass, int index, char *name, size_t size);

/* One line for the summary: each requested pass with its bytes per pixel,
 * e.g. "clamp (3 levels) 152 B, clamp-sum 56 B". "" when none. */
void film_sample_memory_summary(const EstimatorSettings *settings, char *line, size_t size);

/* pbrt-v4's Film "maxcomponentvalue" V: selects clamp with level V (added
 * to the levels unless there). Returns the level's index, or -1 when the
 * levels are full. */
int film_sample_select_film_clamp(EstimatorSettings *settings, float max_component_value);

/* Estimates every requested per-sample image but zirr's from the state
 * (length >= film_sample_planes * pixel_count) and the set sums
 * `accumulators` (settings' M and first sample) into images->pass[...]
 * (those not NULL). */
EstimatorStatus film_sample_estimate(const EstimatorSettings *settings, const uint64_t *state, size_t state_length,
                                     const uint64_t *accumulators, size_t pixel_count, uint64_t sample_count,
                                     EstimatorImages *images, char *message, size_t message_size);

/* zirr's block of a state of pixel_count pixels (its cascades: an
 * accumulator of K sums), and its planes. */
const uint64_t *film_sample_zirr_block(const EstimatorSettings *settings, const uint64_t *state, size_t pixel_count);
size_t film_sample_zirr_planes(const EstimatorSettings *settings);

/* zirr's image (RGB, pixel-interleaved, width x height) from the state and
 * set sums of the whole image (pixel y * width + x; state length >=
 * film_sample_planes * width * height): its neighbourhoods need every
 * pixel's cascades, so it runs once they are all gathered. */
EstimatorStatus film_sample_estimate_zirr(const EstimatorSettings *settings, const uint64_t *state, size_t state_length,
                                          const uint64_t *accumulators, uint32_t width, uint32_t height,
                                          uint64_t sample_count, float *image, char *message, size_t message_size);

/* Adds one sample to pixel `pixel` on the host as the path tracer does (the
 * reference of the kernels' accumulation, for tests): to its set (the
 * sample's set of set_count) in `accumulators`, then to its per-sample
 * state. Returns sample_passes_add's EST_ADD_*. */
int film_sample_add(const EstimatorSettings *settings, uint64_t *accumulators, uint64_t *state, size_t pixel,
                    size_t pixel_count, const SampleParts *sample);

/* Adds one splat record's value `rgb` of set `set` (of set_count) to pixel
 * `pixel` on the host as add_splats does (splat_sample_parts): to the set
 * sums, then to clamp's and zirr's state. Returns EST_ADD_*. */
int film_sample_add_splat(const EstimatorSettings *settings, uint64_t *accumulators, uint64_t *state, size_t pixel,
                          size_t pixel_count, uint32_t set, uint32_t set_count, const float *rgb);

#endif
