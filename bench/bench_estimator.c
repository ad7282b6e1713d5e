/* bench_estimator: throughput of the estimator kernel against a plain copy.
 *
 * The estimator is a streaming kernel: each pixel reads its M set sums per
 * channel once and writes a few RGB images. Its practical limit is memory
 * bandwidth, measured here by the copy kernel (kernels/bench_copy.cl) moving
 * the same input bytes. The goal is an estimator bandwidth of at least 50% of
 * the copy's.
 *
 * Bandwidth is reported two ways, for both kernels:
 *   - (bytes read + bytes written) / time: like for like, each kernel
 *     credited with all the traffic it causes;
 *   - bytes read / time: how fast the set sums are consumed.
 * GB = 10^9 bytes. Times are medians over the timed repeats, taken from the
 * kernels' profiling events and, separately, by the wall clock from the
 * first enqueue to the return of clFinish.
 *
 * Inputs larger than the device's maximum allocation are split into tiles of
 * whole pixels (each tile a separate buffer and launch, with its own
 * pixel_count); times are summed over the tiles of one run. */
#define _POSIX_C_SOURCE 200809L

#include "cl/cl_check.h"
#include "cl/cl_device.h"
#include "film/film.h"
#include "film/film_cl.h"
#include "estimators.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_DEVICES 32
#define GOAL_RATIO 0.5
#define CHECK_PIXELS 64 /* pixels compared with the host reference */
#define OUTPUT_MASK PASSES_DEFAULT
#define OUTPUT_IMAGES 3
#define COPY_ALIGN 16 /* the copy kernel moves float4s */

typedef struct {
    long width;
    long height;
    long sets;
    long samples; /* 0: 64 * sets */
    long repeats;
    long device;
    int from_accumulators;
} Options;

static void print_usage(FILE *out)
{
    fprintf(out,
            "usage: bench_estimator [--width W] [--height H] [--sets M] [--samples N] [--repeats R]\n"
            "                       [--device I] [--from-accumulators] [--help]\n"
            "\n"
            "Times the estimator kernel (mean, MoN and G-MoN images) against a copy kernel\n"
            "that reads and writes as many bytes as the estimator reads, and reports whether\n"
            "the estimator reaches %.0f%% of the copy's bandwidth.\n"
            "\n"
            "  --width W            image width in pixels (default 1920)\n"
            "  --height H           image height in pixels (default 1080)\n"
            "  --sets M             sets per pixel, 1..%d (default %d)\n"
            "  --samples N          samples per pixel n (default 64*M); the set sums stay those\n"
            "                       of 64 samples a set, only the counts change: N not a\n"
            "                       multiple of M times unequal counts, N < M few samples\n"
            "  --repeats R          timed runs after one warm-up, median reported (default 7)\n"
            "  --device I           OpenCL device index over all platforms (default 0)\n"
            "  --from-accumulators  time estimate_from_accumulators: exact 128-bit set\n"
            "                       accumulators as input (4x the bytes of float set sums)\n"
            "  --help               show this help\n"
            "\n"
            "PoCL needs POCL_CACHE_DIR set to a writable directory.\n",
            GOAL_RATIO * 100.0, EST_MAX_SETS, ESTIMATOR_DEFAULT_SETS);
}

/* Parses a decimal integer in [lo, hi]. Returns 0 on success. */
static int parse_long(const char *text, long lo, long hi, long *value)
{
    if (!text || !*text)
        return -1;
    char *end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno != 0 || *end != '\0' || v < lo || v > hi)
        return -1;
    *value = v;
    return 0;
}

/* Returns 0 to run, 1 after --help, 2 on a bad command line (reported). */
static int parse_options(int argc, char **argv, Options *o)
{
    o->width = 1920;
    o->height = 1080;
    o->sets = ESTIMATOR_DEFAULT_SETS;
    o->samples = 0;
    o->repeats = 7;
    o->device = 0;
    o->from_accumulators = 0;
    for (int i = 1; i < argc; ++i) {
        const char *flag = argv[i];
        long *target = NULL;
        long lo = 1, hi = 1L << 20;
        if (strcmp(flag, "--help") == 0 || strcmp(flag, "-h") == 0) {
            print_usage(stdout);
            return 1;
        } else if (strcmp(flag, "--from-accumulators") == 0) {
            o->from_accumulators = 1;
            continue;
        } else if (strcmp(flag, "--width") == 0) {
            target = &o->width;
        } else if (strcmp(flag, "--height") == 0) {
            target = &o->height;
        } else if (strcmp(flag, "--sets") == 0) {
            target = &o->sets;
            hi = EST_MAX_SETS;
        } else if (strcmp(flag, "--samples") == 0) {
            target = &o->samples;
            hi = 1L << 40;
        } else if (strcmp(flag, "--repeats") == 0) {
            target = &o->repeats;
            hi = 1000;
        } else if (strcmp(flag, "--device") == 0) {
            target = &o->device;
            lo = 0;
            hi = MAX_DEVICES - 1;
        } else {
            fprintf(stderr, "bench_estimator: unknown flag '%s' (see --help)\n", flag);
            return 2;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "bench_estimator: %s needs a value (see --help)\n", flag);
            return 2;
        }
        if (parse_long(argv[i + 1], lo, hi, target) != 0) {
            fprintf(stderr, "bench_estimator: bad value '%s' for %s: expected an integer in %ld..%ld\n", argv[i + 1],
                    flag, lo, hi);
            return 2;
        }
        ++i;
    }
    return 0;
}

/* ------------------------------------------------------------------------
 * Deterministic input: every value is a hash of its (pixel, set, channel),
 * so any tile and the host check regenerate the same numbers.
 * ---------------------------------------------------------------------- */

static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* Uniform in [0, 1). */
static double unit(uint64_t h)
{
    return (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

/* The sum of the 64 samples of set `set`, channel `channel` of `pixel`:
 * a smooth per-pixel radiance with noise, and in about one set in 400 a
 * firefly (one sample 10^2..10^5 times brighter, on all channels). */
static float set_sum_value(uint64_t pixel, uint32_t set, uint32_t channel)
{
    const double samples_per_set = 64.0;
    uint64_t pixel_hash = mix64(pixel * 4 + channel);
    double radiance = 0.01 + 4.0 * unit(pixel_hash) * unit(mix64(pixel_hash));
    uint64_t set_hash = mix64(pixel * 131 + set);
    uint64_t value_hash = mix64(set_hash ^ (0x51ed2701ull * (channel + 1)));
    double noise = 0.6 + 0.8 * unit(value_hash);
    double sum = samples_per_set * radiance * noise;
    if ((set_hash & 1023u) < 3u) { /* a firefly in this set (same for every channel) */
        double magnitude = 100.0;
        for (int k = (int)((set_hash >> 10) % 4u); k > 0; --k)
            magnitude *= 10.0;
        sum += radiance * magnitude * (0.5 + unit(mix64(value_hash)));
    }
    return (float)sum;
}

/* Input bytes per pixel: M * 3 floats, or M * 3 two-word accumulators. */
static size_t input_bytes_per_pixel(int sets, int from_accumulators)
{
    size_t values = (size_t)sets * EST_CHANNELS;
    return from_accumulators ? accumulator_planes((uint32_t)sets) * sizeof(uint64_t) : values * sizeof(float);
}

/* Accumulators of the bench's set sums: on the grid 2^-56 (every value is
 * a multiple of it). */
#define BENCH_GRID_EXPONENT (-56)

static void store_fixed(uint64_t *words, uint32_t set, uint32_t channel, size_t pixel, size_t count, float v)
{
    int inexact = 0;
    FixedSum f = fixed_from_float(v, BENCH_GRID_EXPONENT, &inexact);
    words[grid_index(pixel)] = (uint64_t)(BENCH_GRID_EXPONENT + EST_GRID_BIAS);
    words[accumulator_index(set, channel, 0, pixel, count)] = f.lo;
    words[accumulator_index(set, channel, 1, pixel, count)] = f.hi;
}

/* Fills a host tile (pixels first .. first + count - 1 of the image) in the
 * kernel's plane layout for `count` pixels. */
static void fill_tile(void *host, int sets, int from_accumulators, uint64_t first, size_t count)
{
    for (uint32_t j = 0; j < (uint32_t)sets; ++j)
        for (uint32_t c = 0; c < EST_CHANNELS; ++c)
            for (size_t p = 0; p < count; ++p) {
                float v = set_sum_value(first + p, j, c);
                if (from_accumulators) {
                    store_fixed(host, j, c, p, count, v);
                } else {
                    float *sums = host;
                    sums[set_sum_index(j, c, p, count)] = v;
                }
            }
}

/* ------------------------------------------------------------------------
 * Timing helpers.
 * ---------------------------------------------------------------------- */

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(const double *values, int count)
{
    double sorted[1000];
    memcpy(sorted, values, (size_t)count * sizeof *sorted);
    qsort(sorted, (size_t)count, sizeof *sorted, compare_double);
    return count % 2 ? sorted[count / 2] : 0.5 * (sorted[count / 2 - 1] + sorted[count / 2]);
}

typedef struct {
    double event_seconds[1000]; /* per timed run, summed over tiles */
    double wall_seconds[1000];
    double event_median;
    double event_min;
    double event_max;
    double wall_median;
} Timings;

static void summarize(Timings *t, int count)
{
    t->event_median = median(t->event_seconds, count);
    t->wall_median = median(t->wall_seconds, count);
    t->event_min = t->event_max = t->event_seconds[0];
    for (int i = 1; i < count; ++i) {
        t->event_min = t->event_seconds[i] < t->event_min ? t->event_seconds[i] : t->event_min;
        t->event_max = t->event_seconds[i] > t->event_max ? t->event_seconds[i] : t->event_max;
    }
}

/* ------------------------------------------------------------------------
 * The benchmark.
 * ---------------------------------------------------------------------- */

typedef struct {
    size_t first; /* first pixel */
    size_t count; /* pixels */
    size_t input_bytes;
    size_t copy_bytes; /* input_bytes rounded up to whole float4s */
    cl_mem input;
} Tile;

typedef struct {
    ClDevice device;
    int device_open;
    EstimatorProgram *estimator;
    cl_program copy_program;
    cl_kernel copy_kernel;
    Tile *tiles;
    size_t tile_count;
    cl_mem copy_output;
    cl_mem images; /* every tile's images, one after another (pass_slot) */
    void *host_tile;
} Bench;

static void bench_release(Bench *b)
{
    for (size_t t = 0; b->tiles && t < b->tile_count; ++t)
        if (b->tiles[t].input)
            clReleaseMemObject(b->tiles[t].input);
    free(b->tiles);
    if (b->images)
        clReleaseMemObject(b->images);
    if (b->copy_output)
        clReleaseMemObject(b->copy_output);
    if (b->copy_kernel)
        clReleaseKernel(b->copy_kernel);
    if (b->copy_program)
        clReleaseProgram(b->copy_program);
    estimator_program_destroy(b->estimator);
    free(b->host_tile);
    if (b->device_open)
        cl_device_close(&b->device);
}

/* M sets, the default passes (mean, MoN, G-MoN). */
static EstimatorSettings default_settings(int sets)
{
    EstimatorSettings settings;
    estimator_settings_default(&settings);
    settings.set_count = sets;
    settings.passes = OUTPUT_MASK;
    return settings;
}

/* One run of the estimator over all tiles: returns 0 and the summed event
 * time and the wall time to clFinish. */
static int run_estimator(Bench *b, uint64_t sample_count, int from_accumulators, double *event_s, double *wall_s)
{
    cl_event events[64] = {0};
    int status = -1;
    double start = wall_seconds();
    for (size_t t = 0; t < b->tile_count; ++t) {
        events[t] = estimator_program_enqueue(b->estimator, b->tiles[t].input, from_accumulators, b->tiles[t].count,
                                              sample_count, b->images);
        if (!events[t])
            goto done;
    }
    CL_CHECK(clFinish(b->device.queue), done);
    *wall_s = wall_seconds() - start;
    *event_s = 0.0;
    for (size_t t = 0; t < b->tile_count; ++t)
        *event_s += cl_event_seconds(events[t]);
    status = 0;
done:
    for (size_t t = 0; t < b->tile_count; ++t)
        if (events[t])
            clReleaseEvent(events[t]);
    return status;
}

/* One run of the copy over all tiles, moving each tile's input bytes. */
static int run_copy(Bench *b, double *event_s, double *wall_s)
{
    cl_event events[64] = {0};
    int status = -1;
    double start = wall_seconds();
    for (size_t t = 0; t < b->tile_count; ++t) {
        cl_ulong count = b->tiles[t].copy_bytes / COPY_ALIGN;
        size_t global = (size_t)count;
        /* A global size with large power-of-two factors lets the runtime pick
         * a good work-group size; the kernel skips the items past count. */
        global = (global + 255) / 256 * 256;
        CL_CHECK(clSetKernelArg(b->copy_kernel, 0, sizeof(cl_mem), &b->tiles[t].input), done);
        CL_CHECK(clSetKernelArg(b->copy_kernel, 1, sizeof(cl_mem), &b->copy_output), done);
        CL_CHECK(clSetKernelArg(b->copy_kernel, 2, sizeof count, &count), done);
        CL_CHECK(clEnqueueNDRangeKernel(b->device.queue, b->copy_kernel, 1, NULL, &global, NULL, 0, NULL, &events[t]),
                 done);
    }
    CL_CHECK(clFinish(b->device.queue), done);
    *wall_s = wall_seconds() - start;
    *event_s = 0.0;
    for (size_t t = 0; t < b->tile_count; ++t)
        *event_s += cl_event_seconds(events[t]);
    status = 0;
done:
    for (size_t t = 0; t < b->tile_count; ++t)
        if (events[t])
            clReleaseEvent(events[t]);
    return status;
}

/* Compares CHECK_PIXELS pixels spread over the last tile (the output images
 * hold its results after a run) with the host reference, bit for bit.
 * Returns the number of mismatching values, or -1 on an error. */
static int check_against_host(Bench *b, const Options *o, uint64_t sample_count)
{
    const int sets = (int)o->sets;
    EstimatorSettings settings = default_settings(sets);
    int mismatches = 0;
    const Tile *last = &b->tiles[b->tile_count - 1];
    size_t samples = last->count < CHECK_PIXELS ? last->count : CHECK_PIXELS;
    size_t image_floats = last->count * EST_CHANNELS;
    float *device_images = malloc(OUTPUT_IMAGES * image_floats * sizeof(float));
    uint64_t *accumulators = malloc(accumulator_planes((uint32_t)sets) * samples * sizeof(uint64_t));
    float *sums = malloc((size_t)sets * EST_CHANNELS * samples * sizeof(float));
    float *host_images = malloc(OUTPUT_IMAGES * samples * EST_CHANNELS * sizeof(float));
    if (!device_images || !accumulators || !sums || !host_images) {
        fprintf(stderr, "bench_estimator: out of host memory for the check\n");
        mismatches = -1;
        goto done;
    }
    CL_CHECK(clEnqueueReadBuffer(b->device.queue, b->images, CL_TRUE, 0, OUTPUT_IMAGES * image_floats * sizeof(float),
                                 device_images, 0, NULL, NULL),
             fail);
    for (size_t s = 0; s < samples; ++s) {
        size_t p = samples > 1 ? s * (last->count - 1) / (samples - 1) : 0; /* pixel within the tile */
        for (uint32_t j = 0; j < (uint32_t)sets; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
                float v = set_sum_value(last->first + p, j, c);
                sums[set_sum_index(j, c, s, samples)] = v;
                store_fixed(accumulators, j, c, s, samples, v);
            }
    }
    EstimatorImages images = {.pass[PASS_MEAN] = host_images,
                              .pass[PASS_MON] = host_images + samples * EST_CHANNELS,
                              .pass[PASS_GMON] = host_images + 2 * samples * EST_CHANNELS,
                              .length = samples * EST_CHANNELS};
    char message[256] = "";
    EstimatorStatus st =
        o->from_accumulators
            ? estimator_from_accumulators(&settings, accumulators, accumulator_planes((uint32_t)sets) * samples,
                                          samples, sample_count, &images, message, sizeof message)
            : estimator_from_sums(&settings, sums, (size_t)sets * EST_CHANNELS * samples, samples, sample_count,
                                  &images, message, sizeof message);
    if (st != ESTIMATOR_OK) {
        fprintf(stderr, "bench_estimator: host reference failed: %s\n", message);
        mismatches = -1;
        goto done;
    }
    for (size_t s = 0; s < samples; ++s) {
        size_t p = samples > 1 ? s * (last->count - 1) / (samples - 1) : 0;
        for (int i = 0; i < OUTPUT_IMAGES; ++i)
            for (int c = 0; c < EST_CHANNELS; ++c) {
                float host = host_images[(size_t)i * samples * EST_CHANNELS + s * EST_CHANNELS + (size_t)c];
                float dev = device_images[(size_t)i * image_floats + p * EST_CHANNELS + (size_t)c];
                if (memcmp(&host, &dev, sizeof host) != 0) {
                    if (mismatches < 5)
                        fprintf(stderr, "  mismatch: pixel %zu image %d channel %d: kernel %.9g host %.9g\n",
                                last->first + p, i, c, (double)dev, (double)host);
                    ++mismatches;
                }
            }
    }
    goto done;
fail:
    mismatches = -1;
done:
    free(device_images);
    free(accumulators);
    free(sums);
    free(host_images);
    return mismatches;
}

static void print_row(const char *name, const Timings *t, size_t pixels, double bytes_read, double bytes_written)
{
    double s = t->event_median;
    printf("  %-9s  %10.3f  %9.3f  %9.3f  %10.3f  %10.1f  %9.2f  %9.2f\n", name, s * 1e3, t->event_min * 1e3,
           t->event_max * 1e3, t->wall_median * 1e3, (double)pixels / s * 1e-6, (bytes_read + bytes_written) / s * 1e-9,
           bytes_read / s * 1e-9);
}

int main(int argc, char **argv)
{
    Options o;
    int parsed = parse_options(argc, argv, &o);
    if (parsed == 1)
        return 0;
    if (parsed != 0)
        return 2;

    Bench b;
    memset(&b, 0, sizeof b);
    int status = 1;
    const int sets = (int)o.sets;
    const int repeats = (int)o.repeats;
    const uint64_t sample_count = o.samples > 0 ? (uint64_t)o.samples : 64u * (uint64_t)sets;
    const size_t pixel_count = (size_t)o.width * (size_t)o.height;
    const size_t bytes_per_pixel = input_bytes_per_pixel(sets, o.from_accumulators);
    cl_int err = CL_SUCCESS;

    ClDeviceInfo infos[MAX_DEVICES];
    int device_count = cl_devices_enumerate(infos, MAX_DEVICES);
    if (device_count < 0) {
        fprintf(stderr, "bench_estimator: cannot list OpenCL devices\n");
        return 1;
    }
    if (device_count == 0) {
        fprintf(stderr, "bench_estimator: no OpenCL device found (PoCL needs POCL_CACHE_DIR set to a writable "
                        "directory)\n");
        return 1;
    }
    if (o.device >= device_count) {
        fprintf(stderr, "bench_estimator: --device %ld: only %d device(s), 0..%d\n", o.device, device_count,
                device_count - 1);
        return 2;
    }
    if (cl_device_open(&b.device, &infos[o.device]) != 0) {
        fprintf(stderr, "bench_estimator: cannot open device %ld\n", o.device);
        return 1;
    }
    b.device_open = 1;
    const ClDeviceInfo *info = &b.device.info;

    /* Tiles: as many pixels per buffer as the device's allocation limit (and
     * the copy's float4 count) allow. */
    size_t max_alloc = (size_t)info->max_allocation;
    size_t tile_pixels = (max_alloc - COPY_ALIGN) / bytes_per_pixel;
    if (tile_pixels > (size_t)UINT32_MAX)
        tile_pixels = (size_t)UINT32_MAX;
    if (tile_pixels == 0) {
        fprintf(stderr, "bench_estimator: one pixel does not fit the device's maximum allocation\n");
        goto done;
    }
    b.tile_count = (pixel_count + tile_pixels - 1) / tile_pixels;
    if (b.tile_count > 64) {
        fprintf(stderr, "bench_estimator: the input needs %zu tiles of the device's maximum allocation; at most 64\n",
                b.tile_count);
        goto done;
    }
    tile_pixels = (pixel_count + b.tile_count - 1) / b.tile_count; /* even tiles */
    b.tiles = calloc(b.tile_count, sizeof *b.tiles);
    b.host_tile = malloc(tile_pixels * bytes_per_pixel);
    if (!b.tiles || !b.host_tile) {
        fprintf(stderr, "bench_estimator: out of host memory\n");
        goto done;
    }

    printf("device:     %s (%s, %s, %u compute units)\n", info->name, info->platform_name,
           cl_device_type_name(info->type), info->compute_units);
    printf("kernel:     %s, outputs mean, MoN, G-MoN\n",
           o.from_accumulators ? "estimate_from_accumulators (128-bit fixed-point accumulators)"
                               : "estimate_from_sums (float set sums)");
    printf("resolution: %ldx%ld (%zu pixels), M = %d, n = %" PRIu64 " samples per pixel\n", o.width, o.height,
           pixel_count, sets, sample_count);
    fflush(stdout);

    /* Programs. */
    EstimatorSettings settings = default_settings(sets);
    double build_start = wall_seconds();
    b.estimator = estimator_program_new(&b.device, &settings, NULL);
    if (!b.estimator)
        goto done;
    b.copy_program = cl_program_build(&b.device, "bench_copy", "", NULL);
    if (!b.copy_program)
        goto done;
    b.copy_kernel = clCreateKernel(b.copy_program, "copy_float4", &err);
    CL_CHECK(err, done);
    double build_seconds = wall_seconds() - build_start;
    EstimatorLaunch launch = estimator_program_launch(b.estimator);
    char group[64] = "the runtime's choice";
    if (launch.local_size > 0)
        snprintf(group, sizeof group, "%d work items", launch.local_size);
    printf("launch:     %d pixel(s) per work item, work groups of %s, prefetch %d work item(s) ahead\n",
           launch.vector_width, group, launch.prefetch);

    /* Buffers and input. */
    double fill_start = wall_seconds();
    size_t largest_copy = 0;
    for (size_t t = 0; t < b.tile_count; ++t) {
        Tile *tile = &b.tiles[t];
        tile->first = t * tile_pixels;
        tile->count = pixel_count - tile->first < tile_pixels ? pixel_count - tile->first : tile_pixels;
        tile->input_bytes = tile->count * bytes_per_pixel;
        tile->copy_bytes = (tile->input_bytes + COPY_ALIGN - 1) / COPY_ALIGN * COPY_ALIGN;
        largest_copy = tile->copy_bytes > largest_copy ? tile->copy_bytes : largest_copy;
        /* Allocated at copy_bytes so the copy's last float4 stays inside. */
        tile->input = clCreateBuffer(b.device.context, CL_MEM_READ_ONLY, tile->copy_bytes, NULL, &err);
        CL_CHECK(err, done);
        fill_tile(b.host_tile, sets, o.from_accumulators, tile->first, tile->count);
        CL_CHECK(clEnqueueWriteBuffer(b.device.queue, tile->input, CL_TRUE, 0, tile->input_bytes, b.host_tile, 0, NULL,
                                      NULL),
                 done);
        if (tile->copy_bytes > tile->input_bytes) {
            static const unsigned char zeros[COPY_ALIGN] = {0};
            CL_CHECK(clEnqueueWriteBuffer(b.device.queue, tile->input, CL_TRUE, tile->input_bytes,
                                          tile->copy_bytes - tile->input_bytes, zeros, 0, NULL, NULL),
                     done);
        }
    }
    b.copy_output = clCreateBuffer(b.device.context, CL_MEM_WRITE_ONLY, largest_copy, NULL, &err);
    CL_CHECK(err, done);
    b.images = clCreateBuffer(b.device.context, CL_MEM_WRITE_ONLY,
                              estimator_program_image_bytes(b.estimator, tile_pixels), NULL, &err);
    CL_CHECK(err, done);
    double fill_seconds = wall_seconds() - fill_start;

    const double estimator_read = (double)(pixel_count * bytes_per_pixel);
    const double estimator_written = (double)(pixel_count * EST_CHANNELS * sizeof(float) * OUTPUT_IMAGES);
    double copy_bytes = 0.0;
    for (size_t t = 0; t < b.tile_count; ++t)
        copy_bytes += (double)b.tiles[t].copy_bytes;
    printf("tiles:      %zu (device max allocation %.0f MiB)\n", b.tile_count, (double)max_alloc / 1048576.0);
    printf("setup:      %.1f s build, %.1f s input fill and upload\n", build_seconds, fill_seconds);
    printf("per run:    estimator reads %.0f bytes, writes %.0f bytes\n", estimator_read, estimator_written);
    printf("            copy      reads %.0f bytes, writes %.0f bytes\n", copy_bytes, copy_bytes);
    printf("repeats:    1 warm-up + %d timed runs of each kernel, medians below\n", repeats);
    fflush(stdout);

    /* Warm-up, then the timed runs (estimator and copy alternate, so slow
     * drifts such as clock or thermal changes hit both alike). */
    static Timings est, copy;
    double ignored_event = 0.0, ignored_wall = 0.0;
    if (run_estimator(&b, sample_count, o.from_accumulators, &ignored_event, &ignored_wall) != 0 ||
        run_copy(&b, &ignored_event, &ignored_wall) != 0)
        goto done;
    for (int r = 0; r < repeats; ++r) {
        if (run_estimator(&b, sample_count, o.from_accumulators, &est.event_seconds[r], &est.wall_seconds[r]) != 0 ||
            run_copy(&b, &copy.event_seconds[r], &copy.wall_seconds[r]) != 0)
            goto done;
    }
    summarize(&est, repeats);
    summarize(&copy, repeats);

    int mismatches = check_against_host(&b, &o, sample_count);
    if (mismatches < 0)
        goto done;

    printf("\n  %-9s  %10s  %9s  %9s  %10s  %10s  %9s  %9s\n", "kernel", "event ms", "min ms", "max ms", "wall ms",
           "Mpixels/s", "GB/s r+w", "GB/s read");
    print_row("estimator", &est, pixel_count, estimator_read, estimator_written);
    print_row("copy", &copy, pixel_count, copy_bytes, copy_bytes);
    printf("  (event and wall ms are medians, min/max over the event times; rates use the median event\n"
           "   time; GB = 1e9 bytes)\n\n");

    double ratio_rw =
        ((estimator_read + estimator_written) / est.event_median) / (2.0 * copy_bytes / copy.event_median);
    double ratio_read = (estimator_read / est.event_median) / (copy_bytes / copy.event_median);
    double ratio_rw_wall =
        ((estimator_read + estimator_written) / est.wall_median) / (2.0 * copy_bytes / copy.wall_median);
    printf("estimator / copy bandwidth (read + written): %.1f%%  (wall clock: %.1f%%)\n", ratio_rw * 100.0,
           ratio_rw_wall * 100.0);
    printf("estimator / copy bandwidth (read only):      %.1f%%\n", ratio_read * 100.0);
    printf("goal: >= %.0f%% (read + written): %s\n", GOAL_RATIO * 100.0, ratio_rw >= GOAL_RATIO ? "MET" : "NOT MET");
    printf("check: %d of %d sampled output values differ from the host reference\n", mismatches,
           (int)(OUTPUT_IMAGES * EST_CHANNELS *
                 (b.tiles[b.tile_count - 1].count < CHECK_PIXELS ? b.tiles[b.tile_count - 1].count : CHECK_PIXELS)));
    status = mismatches == 0 ? 0 : 1;
done:
    bench_release(&b);
    return status;
}
