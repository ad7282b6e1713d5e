/* Writing a render's files: the EXR and its PNG preview beside it. */
#ifndef HOST_CLI_OUTPUT_FILES_H
#define HOST_CLI_OUTPUT_FILES_H

#include "cli/options.h"
#include "io/exr_image.h"

#include <stddef.h>

/* PATH with its extension replaced by `extension` (e.g. ".png"). */
void replace_extension(const char *path, const char *extension, char *out, size_t size);

/* Writes one output file: writer(temporary, data, ...) writes it under a
 * temporary name beside PATH (PATH.partial-PID), renamed to PATH once
 * complete, so that a failed or interrupted write never leaves a truncated
 * file in place of a good one. The writer returns 0, or non-zero with a
 * message. Returns 0, or -1 with a message (the temporary file removed). */
typedef int (*OutputWriter)(const char *path, const void *data, char *error, size_t error_size);
int write_replacing(const char *path, OutputWriter writer, const void *data, char *error, size_t error_size);

/* Writes `image` to PATH through write_replacing. Returns 0, or 1 after
 * printing the error. */
int write_exr_file(const char *path, const ExrImage *image);

/* Checks, before a render, that PATH can be written: its directory exists
 * and is writable, and PATH is not a directory. Returns 0, or 1 after
 * printing why not. */
int check_output_path(const char *path);

/* Writes `image` to exr_path and the sRGB preview of `preview` beside it,
 * and prints the paths written. Returns 0, or 1 after printing the error. */
int write_render_files(const char *exr_path, const ExrImage *image, const float *preview, float exposure,
                       const char *preview_name);

/* Estimates the set sums of `sums` (its accumulators, M, first sample and
 * sample count) on the host with `settings` (its M and first sample from
 * the file), and writes `sums` with those images instead of its own (its
 * counters and metadata as they are; the sums themselves only with
 * keep_sets) to --outfile, else default_path, and the options' preview
 * beside it. Returns 0, or 1 after printing the error. */
/* The options for re-estimating a file: as given, and without
 * --estimators the estimators the file records (the default ones if it
 * records none), with the preview checked. 0, or -1 with a message. */
int options_for_file(const Options *options, const ExrImage *file, Options *chosen, char *error, size_t error_size);

int write_estimates(const Options *options, const EstimatorSettings *settings, const ExrImage *sums, int keep_sets,
                    const char *default_path);

#endif
