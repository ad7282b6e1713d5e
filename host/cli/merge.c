#include "cli/merge.h"

#include "cli/output_files.h"
#include "film/film_merge.h"
#include "io/exr_image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Whether two parts' values of a string attribute agree (`absent`: the
 * value of a file without it); prints why not. */
static int same_setting(const char *a_path, const char *b_path, const char *what, const char *a, const char *b,
                        const char *absent)
{
    a = a ? a : absent;
    b = b ? b : absent;
    if (strcmp(a, b) == 0)
        return 1;
    fprintf(stderr, "gmonrt: merge: %s and %s differ in %s (%s vs %s)\n", a_path, b_path, what, a, b);
    return 0;
}

/* Checks that part b can join part a; prints why not. */
static int compatible(const char *a_path, const ExrImage *a, const char *b_path, const ExrImage *b)
{
    if (!same_setting(a_path, b_path, "integrator", a->metadata.integrator, b->metadata.integrator, "(unknown)") ||
        !same_setting(a_path, b_path, "sampler", a->metadata.sampler, b->metadata.sampler,
                      RENDER_FILE_LEGACY_SAMPLER) ||
        !same_setting(a_path, b_path, "light sampler", a->metadata.light_sampler, b->metadata.light_sampler,
                      RENDER_FILE_LEGACY_LIGHT_SAMPLER))
        return 0;
    if (a->metadata.max_depth != b->metadata.max_depth) {
        fprintf(stderr, "gmonrt: merge: %s and %s differ in maxdepth (%d vs %d)\n", a_path, b_path,
                a->metadata.max_depth, b->metadata.max_depth);
        return 0;
    }
    if (a->width != b->width || a->height != b->height) {
        fprintf(stderr, "gmonrt: merge: %s is %dx%d but %s is %dx%d\n", a_path, a->width, a->height, b_path, b->width,
                b->height);
        return 0;
    }
    if (a->metadata.set_count != b->metadata.set_count) {
        fprintf(stderr, "gmonrt: merge: %s has M = %d sets but %s has M = %d\n", a_path, a->metadata.set_count, b_path,
                b->metadata.set_count);
        return 0;
    }
    if (a->metadata.seed != b->metadata.seed) {
        fprintf(stderr, "gmonrt: merge: %s has seed %llu but %s has seed %llu\n", a_path,
                (unsigned long long)a->metadata.seed, b_path, (unsigned long long)b->metadata.seed);
        return 0;
    }
    /* Last: what the checks above do not name (the scene file's content:
     * geometry, materials, lights, camera). */
    const char *a_hash = a->metadata.scene_hash ? a->metadata.scene_hash : "";
    const char *b_hash = b->metadata.scene_hash ? b->metadata.scene_hash : "";
    if (strcmp(a_hash, b_hash) != 0) {
        fprintf(stderr,
                "gmonrt: merge: %s and %s render different scenes: geometry, materials, lights or camera differ "
                "(hashes %s and %s)\n",
                a_path, b_path, a_hash, b_hash);
        return 0;
    }
    return 1;
}

/* A part's sample range, kept after its pixels are freed. */
typedef struct {
    const char *path;
    uint64_t first, count;
} Range;

static int by_first_sample(const void *x, const void *y)
{
    uint64_t a = ((const Range *)x)->first, b = ((const Range *)y)->first;
    return (a > b) - (a < b);
}

/* a + b into *sum; 0 if it wraps 64 bits. */
static int add_checked(uint64_t a, uint64_t b, uint64_t *sum)
{
    *sum = a + b;
    return *sum >= a;
}

/* The ranges, in order, must tile one range: a gap would leave sets with
 * unknown counts, an overlap would count samples twice. */
static int check_ranges(Range *ranges, int count)
{
    qsort(ranges, (size_t)count, sizeof *ranges, by_first_sample);
    for (int i = 1; i < count; ++i) {
        const Range *a = &ranges[i - 1], *b = &ranges[i];
        uint64_t a_end = a->first + a->count;
        if (b->first != a_end) {
            fprintf(stderr, "gmonrt: merge: %s covers samples [%llu, %llu) and %s [%llu, %llu): %s\n", a->path,
                    (unsigned long long)a->first, (unsigned long long)a_end, b->path, (unsigned long long)b->first,
                    (unsigned long long)(b->first + b->count),
                    b->first < a_end ? "the ranges overlap" : "samples between them are missing");
            return 0;
        }
    }
    return 1;
}

/* Reads one part; 0 after printing why it cannot be merged. */
static int read_part(const char *path, ExrImage *image, Range *range)
{
    char error[1024];
    if (exr_image_read(path, image, error, sizeof error) != IMAGE_IO_OK) {
        fprintf(stderr, "gmonrt: merge: %s\n", error);
        return 0;
    }
    if (!image->accumulators) {
        fprintf(stderr, "gmonrt: merge: %s has no per-set sums (render the parts with --write-sets)\n", path);
        return 0;
    }
    range->path = path;
    range->first = image->metadata.first_sample;
    range->count = image->metadata.sample_count;
    uint64_t end;
    if (!add_checked(range->first, range->count, &end)) {
        fprintf(stderr, "gmonrt: merge: %s: its sample range [%llu, +%llu) passes 2^64\n", path,
                (unsigned long long)range->first, (unsigned long long)range->count);
        return 0;
    }
    return 1;
}

/* Parts are read one at a time and added to the first part's sums, so
 * memory does not grow with their number. Exact sums are associative, so
 * the order does not matter; the ranges are checked once all are known. */
int merge_command(const Options *o)
{
    const int count = o->merge_count;
    Range *ranges = calloc((size_t)count, sizeof *ranges);
    ExrImage total, part;
    memset(&total, 0, sizeof total);
    memset(&part, 0, sizeof part);
    uint32_t *nonfinite = NULL, *rounded = NULL;
    int status = 1;
    if (!ranges)
        goto out_of_memory;
    if (!read_part(o->merge_inputs[0], &total, &ranges[0]))
        goto done;
    const uint32_t m = (uint32_t)total.metadata.set_count;
    const size_t pixels = (size_t)total.width * (size_t)total.height;
    /* The first part's arrays are its reader's: writable copies of the
     * counters, and its sums are written in place. */
    nonfinite = calloc(pixels, sizeof *nonfinite);
    rounded = calloc(pixels, sizeof *rounded);
    if (!nonfinite || !rounded)
        goto out_of_memory;
    uint64_t *sums = (uint64_t *)total.accumulators;
    uint64_t samples = 0, nonfinite_total = 0, rounded_total = 0, inexact_pixels = 0;
    for (int i = 0; i < count; ++i) {
        const ExrImage *image = &total;
        if (i > 0) {
            exr_image_free(&part);
            if (!read_part(o->merge_inputs[i], &part, &ranges[i]) ||
                !compatible(ranges[0].path, &total, ranges[i].path, &part))
                goto done;
            image = &part;
            inexact_pixels += (uint64_t)film_merge(sums, (uint64_t *)part.accumulators, pixels, (int)m, rounded);
        }
        for (size_t p = 0; p < pixels; ++p) {
            nonfinite[p] += image->nonfinite ? image->nonfinite[p] : 0;
            rounded[p] += image->rounded ? image->rounded[p] : 0;
        }
        if (!add_checked(samples, image->metadata.sample_count, &samples) ||
            !add_checked(nonfinite_total, image->metadata.nonfinite_samples, &nonfinite_total) ||
            !add_checked(rounded_total, image->metadata.rounded_samples, &rounded_total)) {
            fprintf(stderr, "gmonrt: merge: the parts' sample counts add up to 2^64 or more\n");
            goto done;
        }
    }
    exr_image_free(&part);
    if (!check_ranges(ranges, count))
        goto done;
    if (inexact_pixels > 0) {
        rounded_total += inexact_pixels;
        fprintf(stderr,
                "gmonrt: merge: warning: %llu pixel sums could not be added exactly (their values span more binary "
                "orders than a set sum holds); counted as rounded samples\n",
                (unsigned long long)inexact_pixels);
    }

    ExrImage merged = total;
    merged.storage = NULL;
    merged.nonfinite = o->diagnostics ? nonfinite : NULL;
    merged.rounded = o->diagnostics ? rounded : NULL;
    merged.metadata.first_sample = ranges[0].first;
    merged.metadata.sample_count = samples;
    merged.metadata.nonfinite_samples = nonfinite_total;
    merged.metadata.rounded_samples = rounded_total;
    merged.metadata.software = "gmonrt merge";
    merged.metadata.extras = NULL;
    merged.metadata.extra_count = 0;
    /* The first part's estimators unless --estimators says otherwise. */
    Options chosen;
    char error[1024];
    if (options_for_file(o, &total, &chosen, error, sizeof error) != 0) {
        fprintf(stderr, "gmonrt: merge: %s: %s\n", ranges[0].path, error);
        goto done;
    }
    /* The sums stay in the file: a merged render can be merged again. */
    status = write_estimates(&chosen, &chosen.estimator, &merged, 1, "merged.exr");
    if (status == 0 && !o->quiet)
        printf("merged %d parts: samples [%llu, %llu), M = %d, %dx%d\n", count, (unsigned long long)ranges[0].first,
               (unsigned long long)(ranges[0].first + samples), (int)m, total.width, total.height);
    goto done;

out_of_memory:
    fprintf(stderr, "gmonrt: merge: out of memory\n");
done:
    exr_image_free(&part);
    exr_image_free(&total);
    free(ranges);
    free(nonfinite);
    free(rounded);
    return status;
}
