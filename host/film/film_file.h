/* A film as a render file: the RGB layers of its passes, their standard
 * errors and the per-sample images, and the film's gmon.* attributes
 * (io/exr_image.h writes and reads them without knowing what they mean).
 * Their names, types, meanings and the values read for files without them
 * are in io/render_file_schema.h (RENDER_FILE_FILM_ATTRIBUTES and the
 * film's RGB layers); this file writes and parses them. */
#ifndef HOST_FILM_FILM_FILE_H
#define HOST_FILM_FILM_FILE_H

#include "film/film.h"
#include "io/exr_image.h"

/* The film's attributes, in RENDER_FILE_FILM_ATTRIBUTES' order. */
#define FILM_ATTRIBUTE_ID(id, name, meaning, legacy) FILM_ATTRIBUTE_##id,
enum { RENDER_FILE_FILM_ATTRIBUTES(FILM_ATTRIBUTE_ID) FILM_FILE_ATTRIBUTES };
#undef FILM_ATTRIBUTE_ID

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
