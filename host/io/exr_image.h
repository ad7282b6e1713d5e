/* A render as one OpenEXR file (one scanline part, ZIP compression): the
 * estimator images, optional diagnostics, optional exact per-set sums from
 * which the render can be re-estimated or merged with another, and the
 * render's metadata.
 *
 * Channels (EXR stores them sorted by name; readers match by name):
 *   mean.R mean.G mean.B     FLOAT   plain mean
 *   mon.R  mon.G  mon.B      FLOAT   median of means
 *   gmon.R gmon.G gmon.B     FLOAT   G-MoN
 *   gini.R gini.G gini.B     FLOAT   Gini coefficient used for the trim
 *   trim.R trim.G trim.B     UINT    sets trimmed at each end (c)
 *   nonfinite                UINT    non-finite samples (added as 0)
 *   rounded                  UINT    samples not added exactly (the pixel's
 *                                    values span more than its sums hold)
 *   sets.grid                UINT    the pixel's grid word: 0 (no nonzero
 *                                    sample) or E + 1024, the sums counting
 *                                    units of 2^E (kernels/estimator_core.h);
 *                                    files without it: units of 2^-56
 *   sets.<j>.<R|G|B>.w<k>    UINT    set j's exact sum (signed 128-bit
 *                                    integer, below 2^126 in magnitude) as
 *                                    four 32-bit words, w0 the lowest;
 *                                    j = 0..M-1
 *
 * Metadata attributes (all in one part):
 *   gmon.software     string
 *   gmon.sets         int     M
 *   gmon.samples      string  samples per pixel n, decimal uint64
 *   gmon.seed         string  decimal uint64
 *   gmon.firstSample  string  index of the first sample, decimal uint64
 *   gmon.sceneFile    string
 *   gmon.sceneHash    string  hash of all that determines a sample (scene,
 *                             camera, resolution, max depth, integrator,
 *                             seed, M), taken from the renderer's buffers
 *   gmon.integrator   string  path | bsdf
 *   gmon.maxDepth     int
 *   gmon.giniMode     string  per_channel | per_pixel | sort_by_luminance
 *   gmon.nonfiniteSamples string  non-finite samples, decimal uint64
 *   gmon.roundedSamples   string  samples not added exactly, decimal uint64
 *   <key>             string  free key/value pairs (keys not in "gmon.")
 * 64-bit numbers are decimal strings: EXR has no 64-bit integer attribute
 * and a double would lose values above 2^53. */
#ifndef HOST_IO_EXR_IMAGE_H
#define HOST_IO_EXR_IMAGE_H

#include "estimator/estimator.h" /* GiniMode */
#include "io/image_io.h"

#include <stddef.h>
#include <stdint.h>

#define EXR_IMAGE_MAX_SETS 64
/* Grid words a valid file may hold besides 0: E + 1024 for E in -149..200. */
#define EXR_GRID_WORD_MIN (1024u - 149u)
#define EXR_GRID_WORD_MAX (1024u + 200u)

typedef struct {
    const char *key; /* not starting with "gmon."; at most 31 bytes */
    const char *value;
} ExrKeyValue;

typedef struct {
    const char *software;  /* NULL: not written */
    int set_count;         /* M, 1..64; 0: unknown (only without sets) */
    uint64_t sample_count; /* n, samples per pixel */
    uint64_t seed;
    uint64_t first_sample;  /* index of this render's first sample */
    const char *scene_path; /* NULL: not written */
    const char *scene_hash; /* NULL: not written */
    const char *integrator; /* NULL: not written */
    int max_depth;          /* written with the integrator */
    GiniMode gini_mode;
    uint64_t nonfinite_samples; /* totals over the image */
    uint64_t rounded_samples;
    const ExrKeyValue *extras;
    size_t extra_count;
} ExrMetadata;

/* Pixels are row-major from the top left, pixel p = y * width + x. A NULL
 * layer is absent. RGB layers hold 3 values per pixel, interleaved (as the
 * estimators produce them). */
typedef struct {
    int width;
    int height;
    const float *mean;
    const float *mon;
    const float *gmon;
    const float *gini;
    const int32_t *trim;
    const uint32_t *nonfinite;    /* one value per pixel */
    const uint32_t *rounded;      /* one value per pixel */
    const uint64_t *accumulators; /* metadata.set_count sets: the grid plane,
                                     then planes [set][channel][word][pixel],
                                     as in kernels/estimator_core.h */
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

/* Frees what exr_image_read allocated and clears the struct. */
void exr_image_free(ExrImage *image);

#endif
