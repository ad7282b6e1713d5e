/* --checkpoints: the estimates of one progressive render at 1, 2, 4, ...
 * samples per pixel, each as an EXR, with the render time so far and, given
 * a reference image, each estimator's error, as rows of a CSV file:
 *   spp,seconds,estimator,rmse,relmse
 * rmse = sqrt(mean over pixels and channels of (x - r)^2), relmse = mean of
 * (x - r)^2 / (r^2 + 0.01); both empty without a reference. */
#ifndef HOST_CLI_CHECKPOINTS_H
#define HOST_CLI_CHECKPOINTS_H

#include "render/renderer.h"

#include <stddef.h>
#include <stdio.h>

typedef struct {
    const char *directory;
    FILE *csv;
    float *reference; /* RGB per pixel, or NULL */
    const char *scene_path;
    int failures; /* checkpoints or CSV rows that could not be written */
} Checkpoints;

/* Creates the directory if needed, opens DIR/checkpoints.csv and reads the
 * reference's mean layer (NULL: none), which must have the render's size.
 * Returns 0, or -1 with a message. */
int checkpoints_open(Checkpoints *checkpoints, const char *directory, const char *reference_path, unsigned width,
                     unsigned height, char *error, size_t error_size);

/* A RenderSettings.checkpoint callback; `user` is the Checkpoints. A
 * checkpoint that cannot be written is reported and counted, and the render
 * goes on (so that it still writes its image): always returns 0. */
int checkpoints_write(void *user, const RenderOutput *output);

/* Closes the CSV; returns 0, or -1 after reporting it if it or any
 * checkpoint could not be written. */
int checkpoints_close(Checkpoints *checkpoints);

/* The two errors of `image` against `reference` (3 * pixels values). */
void image_errors(const float *image, const float *reference, size_t values, double *rmse, double *relmse);

#endif
