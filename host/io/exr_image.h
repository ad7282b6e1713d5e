/* A render as one OpenEXR file (one scanline part, ZIP compression): RGB
 * image layers, per-pixel counters, optional exact per-set sums from which
 * the render can be re-estimated or merged with another, and metadata.
 * This module knows EXR; which RGB layers and film attributes a render has,
 * and what they mean, is the film's (host/film/film_file.h).
 *
 * The file's layers and attributes, their types, meanings and the values
 * read for files without them are listed in io/render_file_schema.h; this
 * module writes and reads the layers and gmon.* attributes listed there as
 * its own (RENDER_FILE_LAYERS, RENDER_FILE_ATTRIBUTES: ExrMetadata has a
 * field per attribute), the film's gmon.* attributes (`attributes`) and
 * free key/value pairs (`extras`, keys not starting with "gmon."). */
#ifndef HOST_IO_EXR_IMAGE_H
#define HOST_IO_EXR_IMAGE_H

#include "io/image_io.h"
#include "io/render_file_schema.h"

#include <stddef.h>
#include <stdint.h>

#define EXR_MAX_RGB_LAYERS 64
#define EXR_LAYER_NAME_CAPACITY 25 /* a layer name: at most 24 bytes */
/* Grid words a valid file may hold besides 0: E + 1024 for E in -149..200. */
#define EXR_GRID_WORD_MIN (1024u - 149u)
#define EXR_GRID_WORD_MAX (1024u + 200u)

typedef struct {
    const char *key; /* extras: not starting with "gmon."; attributes: starting with it; at most 31 bytes */
    const char *value;
} ExrKeyValue;

typedef struct {
    const char *software;  /* NULL: not written */
    int set_count;         /* M, 1..64; 0: unknown (only without sets) */
    uint64_t sample_count; /* n, samples per pixel */
    uint64_t seed;
    uint64_t first_sample;      /* index of this render's first sample */
    const char *scene_path;     /* NULL: not written */
    const char *scene_hash;     /* NULL: not written */
    const char *integrator;     /* NULL: not written */
    const char *sampler;        /* NULL: not written */
    const char *light_sampler;  /* NULL: not written */
    int max_depth;              /* written with the integrator */
    uint64_t nonfinite_samples; /* totals over the image */
    uint64_t rounded_samples;
    const ExrKeyValue *attributes; /* the film's gmon.* string attributes (none of the above) */
    size_t attribute_count;
    const ExrKeyValue *extras;
    size_t extra_count;
} ExrMetadata;

/* An RGB layer: channels <name>.R, .G, .B, 3 values per pixel,
 * interleaved. */
typedef struct {
    const char *name; /* not "sets", "nonfinite" or "rounded"; 1..24 bytes */
    int is_int;       /* int32 values (UINT channels); else floats */
    const void *data;
} ExrRgbLayer;

/* Pixels are row-major from the top left, pixel p = y * width + x. A NULL
 * layer is absent. */
typedef struct {
    int width;
    int height;
    ExrRgbLayer layers[EXR_MAX_RGB_LAYERS]; /* read: in the file's (sorted) order */
    int layer_count;
    const uint32_t *nonfinite;    /* one value per pixel */
    const uint32_t *rounded;      /* one value per pixel */
    const uint64_t *accumulators; /* metadata.set_count sets: the grid plane,
                                     then planes [set][channel][word][pixel],
                                     as in kernels/film/accumulate.h */
    ExrMetadata metadata;
    void *storage; /* memory owned by an image from exr_image_read */
} ExrImage;

/* Writes `image` to `path`, directly (gmonrt replaces its outputs through a
 * temporary file: write_replacing in host/cli/output_files.h).
 * On failure returns IMAGE_IO_ERROR with a message in `error` (may be
 * NULL). */
ImageIoStatus exr_image_write(const char *path, const ExrImage *image, char *error, size_t error_size);

/* Reads a file into `image`, every layer found in the same layout as above,
 * bit for bit; layers the file lacks are NULL, missing metadata is 0 or NULL.
 * Float layers may also be stored as HALF. Free the result with
 * exr_image_free, also after a failure. */
ImageIoStatus exr_image_read(const char *path, ExrImage *image, char *error, size_t error_size);

/* The RGB layer named `name`, or NULL. */
const ExrRgbLayer *exr_image_layer(const ExrImage *image, const char *name);

/* The film attribute (metadata.attributes) named `key`, or NULL. */
const char *exr_image_attribute(const ExrImage *image, const char *key);

/* Frees what exr_image_read allocated and clears the struct. */
void exr_image_free(ExrImage *image);

#endif
