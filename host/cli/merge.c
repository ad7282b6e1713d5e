#include "cli/merge.h"

#include "cli/output_files.h"
#include "estimator_core.h"
#include "io/exr_image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Checks that part b can join part a; prints why not. */
static int compatible(const char *a_path, const ExrImage *a, const char *b_path, const ExrImage *b)
{
    const char *a_hash = a->metadata.scene_hash ? a->metadata.scene_hash : "";
    const char *b_hash = b->metadata.scene_hash ? b->metadata.scene_hash : "";
    if (strcmp(a_hash, b_hash) != 0) {
        fprintf(stderr, "gmonrt: merge: %s and %s render different scenes (scene hashes %s and %s)\n", a_path, b_path,
                a_hash, b_hash);
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
    return 1;
}

typedef struct {
    const char *path;
    ExrImage image;
} Part;

static int by_first_sample(const void *x, const void *y)
{
    uint64_t a = ((const Part *)x)->image.metadata.first_sample, b = ((const Part *)y)->image.metadata.first_sample;
    return (a > b) - (a < b);
}

int merge_command(const Options *o)
{
    const int count = o->merge_count;
    Part *parts = calloc((size_t)count, sizeof *parts);
    uint64_t *sums = NULL;
    uint32_t *nonfinite = NULL;
    int status = 1;
    if (!parts)
        goto out_of_memory;
    for (int i = 0; i < count; ++i) {
        char error[1024];
        parts[i].path = o->merge_inputs[i];
        if (exr_image_read(parts[i].path, &parts[i].image, error, sizeof error) != IMAGE_IO_OK) {
            fprintf(stderr, "gmonrt: merge: %s\n", error);
            goto done;
        }
        if (!parts[i].image.accumulators) {
            fprintf(stderr, "gmonrt: merge: %s has no per-set sums (render the parts with --write-sets)\n",
                    parts[i].path);
            goto done;
        }
        if (i > 0 && !compatible(parts[0].path, &parts[0].image, parts[i].path, &parts[i].image))
            goto done;
    }
    /* The ranges, in order, must tile one range: a gap would leave sets
     * with unknown counts, an overlap would count samples twice. */
    qsort(parts, (size_t)count, sizeof *parts, by_first_sample);
    for (int i = 1; i < count; ++i) {
        const ExrMetadata *a = &parts[i - 1].image.metadata, *b = &parts[i].image.metadata;
        uint64_t a_end = a->first_sample + a->sample_count;
        if (b->first_sample != a_end) {
            fprintf(stderr, "gmonrt: merge: %s covers samples [%llu, %llu) and %s [%llu, %llu): %s\n",
                    parts[i - 1].path, (unsigned long long)a->first_sample, (unsigned long long)a_end, parts[i].path,
                    (unsigned long long)b->first_sample, (unsigned long long)(b->first_sample + b->sample_count),
                    b->first_sample < a_end ? "the ranges overlap" : "samples between them are missing");
            goto done;
        }
    }

    const ExrImage *first = &parts[0].image;
    const int m = first->metadata.set_count;
    const size_t pixels = (size_t)first->width * (size_t)first->height;
    const size_t words = (size_t)m * EST_CHANNELS * 2 * pixels;
    sums = calloc(words, sizeof *sums);
    nonfinite = calloc(pixels, sizeof *nonfinite);
    if (!sums || !nonfinite)
        goto out_of_memory;
    uint64_t samples = 0;
    for (int i = 0; i < count; ++i) {
        const ExrImage *part = &parts[i].image;
        for (int j = 0; j < m; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c)
                for (size_t p = 0; p < pixels; ++p) {
                    size_t lo = accumulator_index((uint32_t)j, c, 0, p, pixels);
                    size_t hi = accumulator_index((uint32_t)j, c, 1, p, pixels);
                    FixedSum total = {sums[lo], sums[hi]}, add = {part->accumulators[lo], part->accumulators[hi]};
                    total = fixed_add(total, add);
                    sums[lo] = total.lo;
                    sums[hi] = total.hi;
                }
        for (size_t p = 0; p < pixels && part->nonfinite; ++p)
            nonfinite[p] += part->nonfinite[p];
        samples += part->metadata.sample_count;
    }

    ExrImage merged = *first;
    merged.storage = NULL;
    merged.nonfinite = o->diagnostics ? nonfinite : NULL;
    merged.accumulators = sums;
    merged.metadata.sample_count = samples;
    merged.metadata.software = "gmonrt merge";
    merged.metadata.extras = NULL;
    merged.metadata.extra_count = 0;
    /* The sums stay in the file: a merged render can be merged again. */
    status = write_estimates(o, &merged, 1, "merged.exr");
    if (status == 0 && !o->quiet)
        printf("merged %d parts: samples [%llu, %llu), M = %d, %dx%d\n", count,
               (unsigned long long)first->metadata.first_sample,
               (unsigned long long)(first->metadata.first_sample + samples), m, first->width, first->height);
    goto done;

out_of_memory:
    fprintf(stderr, "gmonrt: merge: out of memory\n");
done:
    for (int i = 0; parts && i < count; ++i)
        exr_image_free(&parts[i].image);
    free(parts);
    free(sums);
    free(nonfinite);
    return status;
}
