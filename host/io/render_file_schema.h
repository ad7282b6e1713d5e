/* The render file's schema, in one place: every layer family and attribute
 * of a render saved as OpenEXR, with its name, type, meaning and the value
 * read for files that predate it. The code that writes and reads the file
 * derives from the tables below: io/exr_image.c expands the layer and
 * attribute tables it owns, film/film_file.c the film's attribute table
 * (the io layer only carries the film's rows as data: it treats any other
 * gmon.* string attribute as the film's and does not look inside). Adding
 * a metadata field is one row here plus its field in ExrMetadata (or the
 * film's value and parsing in film_file.c).
 *
 * Channels (EXR stores them sorted by name; readers match by name):
 *   <layer>.R <layer>.G <layer>.B  FLOAT (or HALF, read as float), or UINT
 *                        holding int32 bits: an RGB layer (io/exr_image.h);
 *                        the film's are
 *     <pass>             a pass (film/passes.h names it): FLOAT, or UINT
 *                        for the trim counts
 *     <pass>.stderr      an estimate's standard error (--stderr), FLOAT
 *     clamp-<V>, clamp-sum  the per-sample estimators (film/film_sample.h),
 *                        one clamp-<V> per level, FLOAT
 *   the layers of RENDER_FILE_LAYERS, and the grid channel
 *   sets.grid   UINT     the pixel's grid word: 0 (no nonzero sample) or
 *                        E + 1024, the sums counting units of 2^E
 *                        (kernels/film/accumulate.h); files without it:
 *                        RENDER_FILE_LEGACY_GRID_WORD (units of 2^-56)
 *
 * Attributes (all in one part): RENDER_FILE_ATTRIBUTES (the io's),
 * RENDER_FILE_FILM_ATTRIBUTES (the film's, strings), and free key/value
 * string pairs whose keys do not start with RENDER_FILE_PREFIX. 64-bit
 * numbers are decimal strings: EXR has no 64-bit integer attribute and a
 * double would lose values above 2^53. */
#ifndef HOST_IO_RENDER_FILE_SCHEMA_H
#define HOST_IO_RENDER_FILE_SCHEMA_H

#include <limits.h>

#define RENDER_FILE_PREFIX "gmon."

/* The layers besides the RGB ones (no RGB layer may take their names):
 * X(id, name, type, meaning, files without it). */
#define RENDER_FILE_LAYERS(X)                                                                                          \
    X(NONFINITE, "nonfinite", UINT, "non-finite samples (added as 0), one channel", "read as absent (NULL)")           \
    X(ROUNDED, "rounded", UINT,                                                                                        \
      "samples not added exactly (the pixel's values span more than its sums hold), one channel",                      \
      "read as absent (NULL)")                                                                                         \
    X(SETS, "sets", UINT,                                                                                              \
      "sets.<j>.<R|G|B>.w<k>: set j's exact sum (signed 128-bit integer, below 2^126 in magnitude) as four 32-bit "    \
      "words, w0 the lowest; j = 0..M-1; and sets.grid",                                                               \
      "read as absent (NULL): the file cannot be re-estimated or merged")

#define RENDER_FILE_STDERR_SUFFIX ".stderr"        /* <pass>.stderr */
#define RENDER_FILE_GRID_CHANNEL "grid"            /* sets.grid */
#define RENDER_FILE_LEGACY_GRID_WORD (1024u - 56u) /* EST_GRID_BIAS of kernels/film/accumulate.h */

/* Values of files without gmon.sampler and gmon.lightSampler. */
#define RENDER_FILE_LEGACY_SAMPLER "independent"
#define RENDER_FILE_LEGACY_LIGHT_SAMPLER "power"

/* The io's gmon.* attributes, in the order they are written:
 * X(field of ExrMetadata, name after the prefix, type, min, max, written
 *   when (an expression of `meta`, the ExrMetadata), meaning, files
 *   without it).
 * Types: STRING (const char *), INT (int, an EXR int, read in min..max;
 * EST_MAX_SETS is kernels/film/accumulate.h's),
 * UINT64 (uint64_t, a decimal string). A file without an attribute reads
 * as 0 or NULL in its field; the last column says what that stands for. */
#define RENDER_FILE_ATTRIBUTES(X)                                                                                      \
    X(software, "software", STRING, 0, 0, meta->software, "the program that wrote the file", "NULL")                   \
    X(set_count, "sets", INT, 1, EST_MAX_SETS, meta->set_count > 0, "M, the number of sets",                           \
      "0: unknown (only files without sets)")                                                                          \
    X(sample_count, "samples", UINT64, 0, 0, 1, "samples per pixel n", "0")                                            \
    X(seed, "seed", UINT64, 0, 0, 1, "the seed", "0")                                                                  \
    X(first_sample, "firstSample", UINT64, 0, 0, 1, "index of the render's first sample", "0")                         \
    X(nonfinite_samples, "nonfiniteSamples", UINT64, 0, 0, 1, "non-finite samples over the image", "0")                \
    X(rounded_samples, "roundedSamples", UINT64, 0, 0, 1, "samples not added exactly over the image", "0")             \
    X(scene_path, "sceneFile", STRING, 0, 0, meta->scene_path, "the scene's file", "NULL")                             \
    X(scene_hash, "sceneHash", STRING, 0, 0, meta->scene_hash,                                                         \
      "hash of all that determines a sample (scene, camera, resolution, max depth, integrator, seed, M), taken "       \
      "from the renderer's buffers",                                                                                   \
      "NULL")                                                                                                          \
    X(integrator, "integrator", STRING, 0, 0, meta->integrator, "path | bsdf", "NULL: unknown")                        \
    X(max_depth, "maxDepth", INT, INT_MIN, INT_MAX, meta->integrator, "the integrator's maximum depth", "0")           \
    X(sampler, "sampler", STRING, 0, 0, meta->sampler, "independent | sobol-pixel | sobol-sets",                       \
      "NULL: " RENDER_FILE_LEGACY_SAMPLER)                                                                             \
    X(light_sampler, "lightSampler", STRING, 0, 0, meta->light_sampler, "bvh | power | uniform",                       \
      "NULL: " RENDER_FILE_LEGACY_LIGHT_SAMPLER)

/* The film's gmon.* string attributes (film/film_file.c writes and parses
 * them), in the order they are written: X(id, name after the prefix,
 * meaning, files without it). */
#define RENDER_FILE_FILM_ATTRIBUTES(X)                                                                                 \
    X(ESTIMATORS, "estimators", "the passes estimated, comma-separated pass names (film/passes.h)",                    \
      "the default passes")                                                                                            \
    X(GINI_MODE, "giniMode", "per_channel | per_pixel | sort_by_luminance", "the default mode (per_channel)")          \
    X(ESTIMATOR_PARAMS, "estimatorParams", "the estimators' parameters, name=value,...", "the defaults")

#endif
