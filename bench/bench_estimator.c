/* bench_estimator: the estimator kernel, each estimator and the whole
 * family, against a plain copy and against a render.
 *
 * The estimator is a streaming kernel: each pixel reads its M set sums per
 * channel once and writes a few RGB images. Its practical limit is memory
 * bandwidth, measured here by the copy kernel (kernels/film/bench_copy.cl) moving
 * the same input bytes. Timed, each a program of its own (builds timed
 * apart): every estimate alone, the default set (mean, MoN, G-MoN), all
 * estimates, and all estimates with their standard errors. The goals: the
 * default set reaches 50% of the copy's bandwidth, and the whole family with
 * standard errors costs under 10% of a 64 spp render of
 * scenes/cornell-glass.pbrt at the same resolution (timed in the same run,
 * without its program builds).
 *
 * Bandwidth is reported two ways, for both kernels:
 *   - (bytes read + bytes written) / time: like for like, each kernel
 *     credited with all the traffic it causes;
 *   - bytes read / time: how fast the set sums are consumed.
 * GB = 10^9 bytes. Times are medians over the timed repeats, taken from the
 * kernels' profiling events and, separately, by the wall clock from the
 * first enqueue to the return of clFinish. The copy runs alternate with the
 * estimator runs of every variant (slow drifts such as clock or thermal
 * changes hit both alike); its median is over all of them.
 *
 * Inputs larger than the device's maximum allocation are split into tiles of
 * whole pixels (each tile a separate buffer and launch, with its own
 * pixel_count); times are summed over the tiles of one run. */
#define _POSIX_C_SOURCE 200809L

#include "cl/cl_check.h"
#include "cl/cl_device.h"
#include "film/film.h"
#include "film/estimator_program.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "estimators.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_DEVICES 32
#define GOAL_RATIO 0.5           /* the default set's bandwidth over the copy's */
#define GOAL_RENDER_FRACTION 0.1 /* the family with standard errors over the render */
#define RENDER_SCENE GMON_SOURCE_DIR "/scenes/cornell-glass.pbrt"
#define RENDER_SPP 64
#define CHECK_PIXELS 64 /* pixels compared with the host reference */
#define COPY_ALIGN 16   /* the copy kernel moves float4s */
#define MAX_VARIANTS (2 * PASS_COUNT + 3)

typedef struct {
    long width;
    long height;
    long sets;
    long samples; /* 0: 64 * sets */
    long repeats;
    long device;
    int from_accumulators;
    int each_with_stderr; /* also time every estimate alone with its standard error */
    int groups_only;      /* time only the default set, all, all with standard errors */
    const char *only;     /* NULL, or the names of the variants to time, comma separated */
    int render;           /* time the render the family is compared with */
} Options;

static void print_usage(FILE *out)
{
    fprintf(out,
            "usage: bench_estimator [--width W] [--height H] [--sets M] [--samples N] [--repeats R]\n"
            "                       [--device I] [--from-accumulators | --from-sums] [--each-with-stderr]\n"
            "                       [--groups-only] [--only LIST] [--no-render] [--help]\n"
            "\n"
            "Times the estimator kernel, each estimate alone, the default set (mean, MoN,\n"
            "G-MoN), all estimates and all estimates with standard errors, against a copy\n"
            "kernel that reads and writes as many bytes as the estimator reads, checks each\n"
            "against the host estimation, and times a %d spp render of cornell-glass.pbrt at\n"
            "the same resolution. Goals: the default set reaches %.0f%% of the copy's\n"
            "bandwidth; all estimates with standard errors take under %.0f%% of the render.\n"
            "\n"
            "  --width W            image width in pixels, estimators and render (default 1920)\n"
            "  --height H           image height in pixels, estimators and render (default 1080)\n"
            "  --sets M             sets per pixel, 1..%d (default %d)\n"
            "  --samples N          samples per pixel n (default 64*M); the set sums stay those\n"
            "                       of 64 samples a set, only the counts change: N not a\n"
            "                       multiple of M times unequal counts, N < M few samples\n"
            "  --repeats R          timed runs of each variant after one warm-up, median\n"
            "                       reported (default 7)\n"
            "  --device I           OpenCL device index over all platforms (default 0)\n"
            "  --from-accumulators  input: exact 128-bit set accumulators, as a render\n"
            "                       estimates from (estimate_from_accumulators; the default)\n"
            "  --from-sums          input: float set sums, 1/4 of the bytes (estimate_from_sums)\n"
            "  --each-with-stderr   also time each estimate alone with its standard error\n"
            "  --groups-only        time only the default set, all estimates and all with\n"
            "                       standard errors (not each estimate alone)\n"
            "  --only LIST          time only the variants named in LIST, comma separated, as\n"
            "                       the table names them (e.g. 'mean,default set,all+stderr');\n"
            "                       a goal whose variant is not timed is not measured\n"
            "  --no-render          skip the render (about two minutes at 1920x1080 on 2 cores)\n"
            "  --help               show this help\n"
            "\n"
            "Exits 1 when a device image differs from the host reference; missed goals are\n"
            "reported, not an error. PoCL needs POCL_CACHE_DIR set to a writable directory.\n",
            RENDER_SPP, GOAL_RATIO * 100.0, GOAL_RENDER_FRACTION * 100.0, EST_MAX_SETS, ESTIMATOR_DEFAULT_SETS);
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
    o->from_accumulators = 1;
    o->each_with_stderr = 0;
    o->groups_only = 0;
    o->only = NULL;
    o->render = 1;
    for (int i = 1; i < argc; ++i) {
        const char *flag = argv[i];
        long *target = NULL;
        long lo = 1, hi = 1L << 20;
        if (strcmp(flag, "--help") == 0 || strcmp(flag, "-h") == 0) {
            print_usage(stdout);
            return 1;
        } else if (strcmp(flag, "--from-accumulators") == 0 || strcmp(flag, "--from-sums") == 0) {
            o->from_accumulators = strcmp(flag, "--from-accumulators") == 0;
            continue;
        } else if (strcmp(flag, "--each-with-stderr") == 0) {
            o->each_with_stderr = 1;
            continue;
        } else if (strcmp(flag, "--groups-only") == 0) {
            o->groups_only = 1;
            continue;
        } else if (strcmp(flag, "--only") == 0) {
            if (i + 1 >= argc) {
                fprintf(stderr, "bench_estimator: --only needs a list of variants (see --help)\n");
                return 2;
            }
            o->only = argv[++i];
            continue;
        } else if (strcmp(flag, "--no-render") == 0) {
            o->render = 0;
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

/* Sorts `values` in place. */
static double median(double *values, int count)
{
    qsort(values, (size_t)count, sizeof *values, compare_double);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

typedef struct {
    double *event_seconds; /* per timed run, summed over tiles */
    double *wall_seconds;
    int count; /* runs recorded */
    double event_median;
    double event_min;
    double event_max;
    double wall_median;
} Timings;

static int timings_alloc(Timings *t, int capacity)
{
    memset(t, 0, sizeof *t);
    t->event_seconds = malloc((size_t)capacity * sizeof(double));
    t->wall_seconds = malloc((size_t)capacity * sizeof(double));
    return t->event_seconds && t->wall_seconds ? 0 : -1;
}

static void timings_free(Timings *t)
{
    free(t->event_seconds);
    free(t->wall_seconds);
}

static void summarize(Timings *t)
{
    t->event_median = median(t->event_seconds, t->count);
    t->wall_median = median(t->wall_seconds, t->count);
    t->event_min = t->event_seconds[0]; /* median() sorted them */
    t->event_max = t->event_seconds[t->count - 1];
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
    EstimatorProgram *estimator;         /* the variant being timed */
    EstimatorLaunchChoice launch_choice; /* fixed by hand in the environment (GMON_ESTIMATOR_*) */
    EstimatorLaunch launch;              /* the estimator's (the same for every variant) */
    cl_program copy_program;
    cl_kernel copy_kernel;
    Tile *tiles;
    size_t tile_count;
    cl_mem copy_output;
    cl_mem images; /* the images of one tile (pass_slot and stderr_slot order), each tile's run overwriting them */
    void *host_tile;
} Bench;

/* An estimator program to time: its passes, with or without standard
 * errors. */
typedef struct {
    char name[32];
    uint32_t passes;
    int with_stderr;
    double build_seconds;
    Timings timings;
    int mismatches; /* sampled values that differ from the host reference */
    int checked;    /* sampled values compared */
} Variant;

/* The device buffers and programs (the device stays open). */
static void bench_release_buffers(Bench *b)
{
    for (size_t t = 0; b->tiles && t < b->tile_count; ++t)
        if (b->tiles[t].input)
            clReleaseMemObject(b->tiles[t].input);
    free(b->tiles);
    b->tiles = NULL;
    if (b->images)
        clReleaseMemObject(b->images);
    b->images = NULL;
    if (b->copy_output)
        clReleaseMemObject(b->copy_output);
    b->copy_output = NULL;
    if (b->copy_kernel)
        clReleaseKernel(b->copy_kernel);
    b->copy_kernel = NULL;
    if (b->copy_program)
        clReleaseProgram(b->copy_program);
    b->copy_program = NULL;
    estimator_program_destroy(b->estimator);
    b->estimator = NULL;
    free(b->host_tile);
    b->host_tile = NULL;
}

static void bench_release(Bench *b)
{
    bench_release_buffers(b);
    if (b->device_open)
        cl_device_close(&b->device);
}

/* M sets and the variant's passes, the parameters' defaults. */
static EstimatorSettings variant_settings(const Variant *v, int sets)
{
    EstimatorSettings settings;
    estimator_settings_default(&settings);
    settings.set_count = sets;
    settings.passes = v->passes;
    settings.with_stderr = v->with_stderr;
    return settings;
}

/* Every estimate alone (and, with each_with_stderr, with its standard
 * error; none with groups_only), the default set, all estimates, all
 * estimates with standard errors. Returns the number of variants. */
static int list_variants(int each_with_stderr, int groups_only, Variant *variants)
{
    int count = 0;
    for (int pass = 0; pass < PASS_COUNT && !groups_only; ++pass) {
        if (!(PASSES_ESTIMATES & PASS_BIT(pass)))
            continue;
        for (int with_stderr = 0; with_stderr <= each_with_stderr; ++with_stderr) {
            Variant *v = &variants[count++];
            snprintf(v->name, sizeof v->name, "%s%s", pass_name(pass), with_stderr ? "+stderr" : "");
            v->passes = PASS_BIT(pass);
            v->with_stderr = with_stderr;
        }
    }
    const Variant sets[] = {{.name = "default set", .passes = PASSES_DEFAULT},
                            {.name = "all", .passes = PASSES_ESTIMATES},
                            {.name = "all+stderr", .passes = PASSES_ESTIMATES, .with_stderr = 1}};
    for (size_t i = 0; i < sizeof sets / sizeof sets[0]; ++i)
        variants[count++] = sets[i];
    return count;
}

/* Whether `name` is one of the comma-separated names of `list`. */
static int listed(const char *list, const char *name)
{
    const size_t length = strlen(name);
    for (const char *item = list; item; item = strchr(item, ',') ? strchr(item, ',') + 1 : NULL) {
        const char *end = strchr(item, ',');
        if ((size_t)(end ? end - item : (ptrdiff_t)strlen(item)) == length && strncmp(item, name, length) == 0)
            return 1;
    }
    return 0;
}

/* Keeps the variants that `only` names (all when it is NULL); returns their
 * number, or -1 (reported) when it names one that is not in the list. */
static int keep_variants(const char *only, Variant *variants, int count)
{
    if (!only)
        return count;
    for (const char *item = only; item; item = strchr(item, ',') ? strchr(item, ',') + 1 : NULL) {
        const size_t length = strchr(item, ',') ? (size_t)(strchr(item, ',') - item) : strlen(item);
        int known = 0;
        for (int i = 0; i < count && !known; ++i)
            known = strlen(variants[i].name) == length && strncmp(item, variants[i].name, length) == 0;
        if (!known) {
            fprintf(stderr, "bench_estimator: --only: no variant '%.*s'; the variants are:", (int)length, item);
            for (int i = 0; i < count; ++i)
                fprintf(stderr, "%s '%s'", i ? "," : "", variants[i].name);
            fprintf(stderr, " (--each-with-stderr adds each estimate's +stderr)\n");
            return -1;
        }
    }
    int kept = 0;
    for (int i = 0; i < count; ++i)
        if (listed(only, variants[i].name))
            variants[kept++] = variants[i];
    return kept;
}

/* The timed variant called `name`, or NULL. */
static const Variant *find_variant(const Variant *variants, int count, const char *name)
{
    for (int i = 0; i < count; ++i)
        if (strcmp(variants[i].name, name) == 0)
            return &variants[i];
    return NULL;
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

/* The name of image plane `plane` of a variant's images: "<pass>" or
 * "<pass>.stderr". */
static void plane_name(const Variant *v, int plane, char *name, size_t size)
{
    snprintf(name, size, "plane %d", plane);
    for (int pass = 0; pass < PASS_COUNT; ++pass) {
        if (!(v->passes & PASS_BIT(pass)))
            continue;
        if (pass_slot(v->passes, pass) == plane)
            snprintf(name, size, "%s", pass_name(pass));
        else if (v->with_stderr && (PASSES_ESTIMATES & PASS_BIT(pass)) && stderr_slot(v->passes, pass) == plane)
            snprintf(name, size, "%s.stderr", pass_name(pass));
    }
}

/* Compares CHECK_PIXELS pixels spread over the last tile (the output images
 * hold its results after a run) with the host reference, bit for bit, in
 * every image of the variant (its estimates, then their standard errors).
 * Sets v->mismatches and v->checked; returns 0, or -1 on an error. */
static int check_against_host(Bench *b, const Options *o, uint64_t sample_count, Variant *v)
{
    const int sets = (int)o->sets;
    EstimatorSettings settings = variant_settings(v, sets);
    const int planes = pass_image_count(v->passes, v->with_stderr);
    const Tile *last = &b->tiles[b->tile_count - 1];
    const size_t samples = last->count < CHECK_PIXELS ? last->count : CHECK_PIXELS;
    const size_t image_floats = last->count * EST_CHANNELS, sample_floats = samples * EST_CHANNELS;
    int status = -1;
    float *device_images = malloc((size_t)planes * image_floats * sizeof(float));
    uint64_t *accumulators = malloc(accumulator_planes((uint32_t)sets) * samples * sizeof(uint64_t));
    float *sums = malloc((size_t)sets * EST_CHANNELS * samples * sizeof(float));
    float *host_images = malloc((size_t)planes * sample_floats * sizeof(float));
    if (!device_images || !accumulators || !sums || !host_images) {
        fprintf(stderr, "bench_estimator: out of host memory for the check\n");
        goto done;
    }
    CL_CHECK(clEnqueueReadBuffer(b->device.queue, b->images, CL_TRUE, 0, (size_t)planes * image_floats * sizeof(float),
                                 device_images, 0, NULL, NULL),
             done);
    for (size_t s = 0; s < samples; ++s) {
        size_t p = samples > 1 ? s * (last->count - 1) / (samples - 1) : 0; /* pixel within the tile */
        for (uint32_t j = 0; j < (uint32_t)sets; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
                float value = set_sum_value(last->first + p, j, c);
                sums[set_sum_index(j, c, s, samples)] = value;
                store_fixed(accumulators, j, c, s, samples, value);
            }
    }
    EstimatorImages images = {.length = sample_floats};
    for (int pass = 0; pass < PASS_COUNT; ++pass) {
        if (!(v->passes & PASS_BIT(pass)))
            continue;
        images.pass[pass] = host_images + (size_t)pass_slot(v->passes, pass) * sample_floats;
        if (v->with_stderr && (PASSES_ESTIMATES & PASS_BIT(pass)))
            images.error[pass] = host_images + (size_t)stderr_slot(v->passes, pass) * sample_floats;
    }
    char message[256] = "";
    EstimatorStatus st =
        o->from_accumulators
            ? estimator_from_accumulators(&settings, accumulators, accumulator_planes((uint32_t)sets) * samples,
                                          samples, sample_count, &images, message, sizeof message)
            : estimator_from_sums(&settings, sums, (size_t)sets * EST_CHANNELS * samples, samples, sample_count,
                                  &images, message, sizeof message);
    if (st != ESTIMATOR_OK) {
        fprintf(stderr, "bench_estimator: host reference failed: %s\n", message);
        goto done;
    }
    v->mismatches = 0;
    v->checked = planes * (int)sample_floats;
    for (size_t s = 0; s < samples; ++s) {
        size_t p = samples > 1 ? s * (last->count - 1) / (samples - 1) : 0;
        for (int i = 0; i < planes; ++i)
            for (int c = 0; c < EST_CHANNELS; ++c) {
                float host = host_images[(size_t)i * sample_floats + s * EST_CHANNELS + (size_t)c];
                float dev = device_images[(size_t)i * image_floats + p * EST_CHANNELS + (size_t)c];
                if (memcmp(&host, &dev, sizeof host) != 0) {
                    if (v->mismatches < 5) {
                        char name[64];
                        plane_name(v, i, name, sizeof name);
                        fprintf(stderr, "  %s: mismatch: pixel %zu %s channel %d: kernel %.9g host %.9g\n", v->name,
                                last->first + p, name, c, (double)dev, (double)host);
                    }
                    ++v->mismatches;
                }
            }
    }
    status = 0;
done:
    free(device_images);
    free(accumulators);
    free(sums);
    free(host_images);
    return status;
}

/* Builds the variant's program, times it (one warm-up, then `repeats` runs
 * alternating with the copy, whose times go to `copy`), checks it and
 * destroys it. Returns 0, or -1 on an error. */
static int time_variant(Bench *b, const Options *o, uint64_t sample_count, Variant *v, Timings *copy)
{
    const int repeats = (int)o->repeats;
    EstimatorSettings settings = variant_settings(v, (int)o->sets);
    if (timings_alloc(&v->timings, repeats) != 0) {
        fprintf(stderr, "bench_estimator: out of host memory\n");
        return -1;
    }
    double build_start = wall_seconds();
    b->estimator = estimator_program_new(&b->device, &settings, &b->launch_choice, NULL);
    if (!b->estimator)
        return -1;
    v->build_seconds = wall_seconds() - build_start;
    b->launch = estimator_program_launch(b->estimator);
    double ignored_event = 0.0, ignored_wall = 0.0;
    /* The warm-up also finishes the build: PoCL compiles a kernel at its
     * first launch. */
    double warm_start = wall_seconds();
    if (run_estimator(b, sample_count, o->from_accumulators, &ignored_event, &ignored_wall) != 0)
        return -1;
    double warm_seconds = wall_seconds() - warm_start;
    printf("  %-20s  build %6.1f s, warm-up run %6.1f s\n", v->name, v->build_seconds, warm_seconds);
    fflush(stdout);
    for (int r = 0; r < repeats; ++r) {
        Timings *t = &v->timings;
        if (run_estimator(b, sample_count, o->from_accumulators, &t->event_seconds[t->count],
                          &t->wall_seconds[t->count]) != 0 ||
            run_copy(b, &copy->event_seconds[copy->count], &copy->wall_seconds[copy->count]) != 0)
            return -1;
        ++t->count;
        ++copy->count;
    }
    summarize(&v->timings);
    int status = check_against_host(b, o, sample_count, v);
    estimator_program_destroy(b->estimator);
    b->estimator = NULL;
    return status;
}

/* The bytes a variant writes: its images. */
static double variant_written(const Variant *v, size_t pixels)
{
    return (double)pass_image_count(v->passes, v->with_stderr) * (double)pixels * EST_CHANNELS * sizeof(float);
}

static void print_table_header(void)
{
    printf("\n  %-20s  %6s  %9s  %9s  %9s  %9s  %8s  %8s  %9s  %6s  %9s\n", "variant", "images", "event ms", "min ms",
           "max ms", "wall ms", "ms/Mpix", "GB/s r+w", "GB/s read", "% copy", "check");
}

static void print_row(const char *name, int images, const Timings *t, size_t pixels, double bytes_read,
                      double bytes_written, double copy_bandwidth, const char *check)
{
    double s = t->event_median;
    double bandwidth = (bytes_read + bytes_written) / s;
    printf("  %-20s  %6d  %9.2f  %9.2f  %9.2f  %9.2f  %8.2f  %8.2f  %9.2f  %5.1f%%  %9s\n", name, images, s * 1e3,
           t->event_min * 1e3, t->event_max * 1e3, t->wall_median * 1e3, s * 1e3 / ((double)pixels * 1e-6),
           bandwidth * 1e-9, bytes_read / s * 1e-9, bandwidth / copy_bandwidth * 100.0, check);
}

/* A 64 spp render of cornell-glass.pbrt at the bench's resolution with the
 * default estimators (M as the bench's): its time without program builds.
 * Returns 0, or -1 (reported). */
static int time_render(ClDevice *device, const Options *o, double *seconds)
{
    RenderScene scene;
    SceneSummary summary;
    char error[2048];
    if (scene_convert_load(RENDER_SCENE, 0, (unsigned)o->width, (unsigned)o->height, 1, &scene, &summary, error,
                           sizeof error)) {
        fprintf(stderr, "bench_estimator: %s\n", error);
        return -1;
    }
    int status = -1;
    scene.constants.integrator.flags = RENDER_NEE; /* as gmonrt renders by default */
    if (render_scene_finalize(&scene, error, sizeof error)) {
        fprintf(stderr, "bench_estimator: %s\n", error);
        goto done;
    }
    RenderSettings settings;
    render_settings_default(&settings);
    settings.sample_count = RENDER_SPP;
    settings.estimator.set_count = (int)o->sets;
    RenderOutput out;
    if (renderer_run(device, 1, &scene, &settings, &out, error, sizeof error) != RENDER_OK) {
        fprintf(stderr, "bench_estimator: render: %s\n", error);
        goto done;
    }
    *seconds = out.seconds;
    printf("render:     %s, %ldx%ld, %" PRIu64 " spp, maxdepth %u, M = %d, default estimators\n", RENDER_SCENE,
           o->width, o->height, out.sample_count, out.max_depth, out.set_count);
    printf("            %.2f s (passes and final estimate; program builds %.2f s not counted), %.3f Msamples/s,\n"
           "            its own estimate (mean, MoN, G-MoN) %.1f ms, the sums in %d slice(s) of the device's largest\n"
           "            allocation\n",
           out.seconds, out.build_seconds, (double)out.sample_count * out.width * out.height / out.seconds * 1e-6,
           out.devices[0].estimate_seconds * 1e3, out.devices[0].slices);
    render_output_free(&out);
    status = 0;
done:
    render_scene_destroy(&scene);
    return status;
}

static const char *goal_word(int met)
{
    return met ? "PASS" : "MISS";
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
    if (estimator_launch_from_environment(&b.launch_choice) != 0)
        return 2;
    static Variant variants[MAX_VARIANTS];
    const int variant_count =
        keep_variants(o.only, variants, list_variants(o.each_with_stderr, o.groups_only, variants));
    if (variant_count < 0)
        return 2;
    Timings copy;
    int status = 1;
    const int sets = (int)o.sets;
    const int repeats = (int)o.repeats;
    const uint64_t sample_count = o.samples > 0 ? (uint64_t)o.samples : 64u * (uint64_t)sets;
    const size_t pixel_count = (size_t)o.width * (size_t)o.height;
    const size_t bytes_per_pixel = input_bytes_per_pixel(sets, o.from_accumulators);
    cl_int err = CL_SUCCESS;
    if (timings_alloc(&copy, variant_count * repeats) != 0) {
        fprintf(stderr, "bench_estimator: out of host memory\n");
        goto done;
    }

    ClDeviceInfo infos[MAX_DEVICES];
    int device_count = cl_devices_enumerate(infos, MAX_DEVICES);
    if (device_count < 0) {
        fprintf(stderr, "bench_estimator: cannot list OpenCL devices\n");
        goto done;
    }
    if (device_count == 0) {
        fprintf(stderr, "bench_estimator: no OpenCL device found (PoCL needs POCL_CACHE_DIR set to a writable "
                        "directory)\n");
        goto done;
    }
    if (o.device >= device_count) {
        fprintf(stderr, "bench_estimator: --device %ld: only %d device(s), 0..%d\n", o.device, device_count,
                device_count - 1);
        status = 2;
        goto done;
    }
    if (cl_device_open(&b.device, &infos[o.device]) != 0) {
        fprintf(stderr, "bench_estimator: cannot open device %ld\n", o.device);
        goto done;
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
    printf("kernel:     %s\n", o.from_accumulators ? "estimate_from_accumulators (128-bit fixed-point accumulators)"
                                                   : "estimate_from_sums (float set sums)");
    printf("resolution: %ldx%ld (%zu pixels), M = %d, n = %" PRIu64 " samples per pixel\n", o.width, o.height,
           pixel_count, sets, sample_count);
    fflush(stdout);

    double build_start = wall_seconds();
    b.copy_program = cl_program_build(&b.device, "bench_copy", "", NULL);
    if (!b.copy_program)
        goto done;
    b.copy_kernel = clCreateKernel(b.copy_program, "copy_float4", &err);
    CL_CHECK(err, done);
    double copy_build_seconds = wall_seconds() - build_start;

    /* Buffers and input; the images buffer fits the variant with the most
     * images. */
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
    int most_images = 0;
    for (int i = 0; i < variant_count; ++i) {
        int images = pass_image_count(variants[i].passes, variants[i].with_stderr);
        most_images = images > most_images ? images : most_images;
    }
    b.images = clCreateBuffer(b.device.context, CL_MEM_WRITE_ONLY,
                              (size_t)most_images * tile_pixels * EST_CHANNELS * sizeof(float), NULL, &err);
    CL_CHECK(err, done);
    double fill_seconds = wall_seconds() - fill_start;

    const double estimator_read = (double)(pixel_count * bytes_per_pixel);
    double copy_bytes = 0.0;
    for (size_t t = 0; t < b.tile_count; ++t)
        copy_bytes += (double)b.tiles[t].copy_bytes;
    printf("tiles:      %zu (device max allocation %.0f MiB)\n", b.tile_count, (double)max_alloc / 1048576.0);
    printf("setup:      %.1f s copy kernel build, %.1f s input fill and upload\n", copy_build_seconds, fill_seconds);
    printf("per run:    estimator reads %.0f bytes, writes 12 bytes a pixel per image\n", estimator_read);
    printf("            copy      reads %.0f bytes, writes %.0f bytes\n", copy_bytes, copy_bytes);
    printf("repeats:    per variant 1 warm-up + %d timed runs, each followed by a copy run\n", repeats);
    printf("builds:     (not in the timings)\n");
    fflush(stdout);

    int mismatches = 0;
    for (int i = 0; i < variant_count; ++i) {
        if (time_variant(&b, &o, sample_count, &variants[i], &copy) != 0)
            goto done;
        mismatches += variants[i].mismatches;
    }
    summarize(&copy);
    char group[64] = "the runtime's choice";
    if (b.launch.local_size > 0)
        snprintf(group, sizeof group, "%d work items", b.launch.local_size);
    printf("launch:     %d pixel(s) per work item, work groups of %s, prefetch %d work item(s) ahead\n",
           b.launch.vector_width, group, b.launch.prefetch);
    const double copy_bandwidth = 2.0 * copy_bytes / copy.event_median;

    print_table_header();
    for (int i = 0; i < variant_count; ++i) {
        const Variant *v = &variants[i];
        char check[32];
        snprintf(check, sizeof check, "%d/%d", v->mismatches, v->checked);
        print_row(v->name, pass_image_count(v->passes, v->with_stderr), &v->timings, pixel_count, estimator_read,
                  variant_written(v, pixel_count), copy_bandwidth, check);
    }
    print_row("copy", 0, &copy, pixel_count, copy_bytes, copy_bytes, copy_bandwidth, "");
    printf("  (event and wall ms are medians, min/max over the event times; ms/Mpix, GB/s and %% copy\n"
           "   (read + written bandwidth over the copy's) use the median event time; GB = 1e9 bytes;\n"
           "   check: sampled output values differing from the host reference / values compared)\n\n");

    const Variant *default_set = find_variant(variants, variant_count, "default set");
    const Variant *family = find_variant(variants, variant_count, "all+stderr");
    if (default_set) {
        const double default_written = variant_written(default_set, pixel_count);
        const Timings *dt = &default_set->timings;
        double ratio_rw = ((estimator_read + default_written) / dt->event_median) / copy_bandwidth;
        double ratio_read = (estimator_read / dt->event_median) / (copy_bytes / copy.event_median);
        double ratio_rw_wall =
            ((estimator_read + default_written) / dt->wall_median) / (2.0 * copy_bytes / copy.wall_median);
        printf("default set / copy bandwidth (read + written): %.1f%%  (wall clock: %.1f%%)\n", ratio_rw * 100.0,
               ratio_rw_wall * 100.0);
        printf("default set / copy bandwidth (read only):      %.1f%%\n", ratio_read * 100.0);
        printf("goal: default set >= %.0f%% of the copy's bandwidth (read + written): %s\n", GOAL_RATIO * 100.0,
               goal_word(ratio_rw >= GOAL_RATIO));
    } else {
        printf("goal: default set >= %.0f%% of the copy's bandwidth: not measured (not timed)\n", GOAL_RATIO * 100.0);
    }
    printf("check: %d sampled output values differ from the host reference\n", mismatches);
    fflush(stdout);

    if (o.render && family) {
        /* The render needs the memory the input holds. */
        bench_release_buffers(&b);
        double render_seconds = 0.0;
        printf("\n");
        if (time_render(&b.device, &o, &render_seconds) != 0)
            goto done;
        double fraction = family->timings.event_median / render_seconds;
        printf("goal: all estimates with standard errors (%.1f ms) < %.0f%% of the render (%.2f s): %.2f%%: %s\n",
               family->timings.event_median * 1e3, GOAL_RENDER_FRACTION * 100.0, render_seconds, fraction * 100.0,
               goal_word(fraction < GOAL_RENDER_FRACTION));
    } else {
        printf("goal: all estimates with standard errors < %.0f%% of the render: not measured (%s)\n",
               GOAL_RENDER_FRACTION * 100.0, family ? "--no-render" : "all+stderr not timed");
    }
    status = mismatches == 0 ? 0 : 1;
done:
    for (int i = 0; i < variant_count; ++i)
        timings_free(&variants[i].timings);
    timings_free(&copy);
    bench_release(&b);
    return status;
}
