/* The render file's schema: which EXR layers and attributes hold a film's
 * images and estimator settings (io/exr_image.h writes and reads them
 * without knowing what they mean).
 *   <pass>.R/G/B         a pass (passes.h names it): FLOAT, or UINT for the
 *                        trim counts
 *   <estimate>.stderr.*  an estimate's standard error (--stderr)
 *   clamp-<V>.R/G/B, clamp-sum.R/G/B  the per-sample estimators
 *                        (film_sample.h), one clamp-<V> per level
 *   gmon.estimators      the passes estimated, comma-separated names
 *   gmon.giniMode        per_channel | per_pixel | sort_by_luminance
 *   gmon.estimatorParams the estimators' parameters, name=value,...
 * Files from before this schema have neither gmon.estimators nor
 * gmon.estimatorParams: they read as the defaults. */
#ifndef HOST_FILM_FILM_FILE_H
#define HOST_FILM_FILM_FILE_H

#include "film/film.h"
#include "io/exr_image.h"

#define FILM_FILE_ATTRIBUTES 3

/* An ExrImage of a film, with the storage its names and attributes point
 * to: fill it in place (it points into itself) and do not copy it. */
typedef struct {
    ExrImage image;
    ExrKeyValue attributes[FILM_FILE_ATTRIBUTES];
    char layer_names[2][PASS_COUNT][EXR_LAYER_NAME_CAPACITY];                            /* passes, their errors */
    char sample_layer_names[EST_CLAMP_LEVELS_MAX + PASS_COUNT][EXR_LAYER_NAME_CAPACITY]; /* per-sample images */
    char estimators[512];
    char params[512];
} FilmFile;

/* Sets file->image (cleared first) to width x height with an RGB layer per
 * image of `images` in settings->passes (and their standard errors), and
 * the film's attributes. The caller adds the sums, counters and the rest of
 * the metadata. */
void film_file_init(FilmFile *file, int width, int height, const EstimatorSettings *settings,
                    const EstimatorImages *images);

/* The estimator settings a file records (M and the first sample from its
 * metadata), the defaults where it records none. 0, or -1 with a reason. */
int film_file_settings(const ExrImage *image, EstimatorSettings *settings, char *message, size_t message_size);

/* The file's image of `pass` (with_error: its standard error), of the
 * pass's type, or NULL. */
const void *film_file_pass(const ExrImage *image, int pass, int with_error);

/* The name of a Gini mode in files and its value: -1 if unknown. */
const char *gini_mode_name(GiniMode mode);
int gini_mode_from_name(const char *name);

#endif
