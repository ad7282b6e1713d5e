#define _POSIX_C_SOURCE 200809L
#include "render/renderer.h"
#include "render/scene_upload.h"

#include "render/memory_check.h"

#include "cl/kernel_sources.h"
#include "../kernels/film/splats.h"
#include "film/estimator_program.h"
#include "film/sample_estimator_program.h"
#include "estimators.h"
#include "feature_mask.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The deepest subpaths bdpt.cl's private arrays hold (maxdepth). */
#define BDPT_MOST_DEPTH 100

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *render_integrator_name(uint32_t flags)
{
    if (flags & RENDER_BDPT)
        return "bdpt";
    if (flags & RENDER_LIGHTPATH)
        return "lightpath";
    return (flags & RENDER_NEE) ? "path" : "bsdf";
}

void render_settings_default(RenderSettings *s)
{
    memset(s, 0, sizeof *s);
    estimator_settings_default(&s->estimator);
    s->sample_count = 64;
    s->seconds_per_pass = 0.5;
    s->estimator_launch = ESTIMATOR_LAUNCH_CHOSEN_PER_DEVICE;
}

void render_output_free(RenderOutput *o)
{
    free(o->accumulators);
    free(o->rejected);
    for (int p = 0; p < PASS_COUNT; ++p) {
        free(o->pass[p]);
        free(o->error[p]);
    }
    memset(o, 0, sizeof *o);
}

EstimatorImages render_output_images(const RenderOutput *o)
{
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    for (int p = 0; p < PASS_COUNT; ++p) {
        images.pass[p] = o->pass[p];
        images.error[p] = o->error[p];
    }
    images.length = (size_t)o->width * o->height * EST_CHANNELS;
    return images;
}

/* The sums and counters of pixels, as planes of `pixels` values: the
 * accumulators' planes, the rejected counts (REJECTED_PLANES: non-finite,
 * rounded), then the ray counts. */
typedef struct {
    uint64_t *accumulators;
    uint32_t *rejected;
    uint64_t *rays;
    uint64_t *samples; /* per-sample state (film_sample.h); NULL when none is requested */
} HostState;

/* Some of a worker's pixels, in buffers of their own: a share whose
 * buffers would pass the device's largest allocation is cut into several
 * slices, each launched on its own. */
typedef struct {
    cl_mem accumulators, rejected, rays, samples;
    cl_mem light_rays;   /* with splats: the rays of its pixels' light subpaths in a pass */
    size_t first, count; /* its pixels */
    cl_event pass;
} Slice;

#define RENDER_MAX_SLICES 64

/* One device's part of the render. */
typedef struct {
    ClDevice *device;
    RenderDeviceReport *report;
    int live;
    int fault_pass; /* injected failure in this pass (1-based); 0: none */
    cl_program program;
    cl_kernel kernel;
    /* With splats (bdpt, lightpath): the kernels that trace light subpaths
     * and add their records, the records' buffer (room for record_capacity)
     * with its counter, and the offsets of a slice's pixels in it. */
    cl_kernel splat_kernel, add_kernel;
    cl_mem records, record_count, offsets;
    size_t record_capacity, offset_capacity;
    EstimatorProgram *estimator;              /* NULL when no set-based pass is requested */
    SampleEstimatorProgram *sample_estimator; /* NULL when no per-sample pass is */
    cl_mem scene[SCENE_BUFFERS];
    Slice slices[RENDER_MAX_SLICES];
    int slice_count;     /* 0: no state allocated */
    size_t first, count; /* its pixels, its slices' in order */
    size_t scene_bytes;
    double pass_seconds;
    uint64_t unsaved_samples; /* pixel samples since the last host copy */
} Worker;

typedef struct {
    const RenderScene *scene;
    const RenderSettings *settings;
    EstimatorSettings estimator; /* as the workers estimate: M as rendered, the first sample */
    SceneUpload upload;
    int sets;   /* M as rendered */
    int splats; /* the integrator has light subpaths (bdpt.cl): records splatted each pass */
    /* A pass's splat records from every device, then put in pixel order
     * (splat_offsets: pixel p's are sorted[offsets[p], offsets[p + 1])). */
    SplatRecord *splat_records, *splat_sorted;
    size_t splat_count, splat_capacity;
    uint32_t *splat_offsets;
    size_t pixels;        /* of the image */
    size_t planes;        /* accumulator planes: accumulator_planes(sets) */
    size_t sample_planes; /* per-sample state planes (film_sample.h), 0 for none */
    Worker workers[RENDER_MAX_DEVICES];
    int worker_count;
    HostState saved; /* every pixel's state after saved_samples samples */
    /* Where a new copy is gathered before it replaces `saved`, with several
     * devices (so that one failing mid-copy leaves `saved` consistent); one
     * device is read straight into `saved`, and if that read fails no
     * consistent copy is left (saved_lost): a third less host memory for
     * the common case, against an image lost to a device failing exactly
     * while its sums are read. */
    HostState scratch;
    int saved_lost;
    uint64_t saved_samples;
    double save_seconds; /* cost of the last copy */
    double saved_at;
    double start;            /* of the first pass */
    double callback_seconds; /* spent in the checkpoint callbacks, not counted as render time */
} Render;

static int live_workers(const Render *r)
{
    int live = 0;
    for (int i = 0; i < r->worker_count; ++i)
        live += r->workers[i].live;
    return live;
}

static void release_state(Worker *w)
{
    for (int k = 0; k < w->slice_count; ++k) {
        Slice *slice = &w->slices[k];
        cl_mem *state[] = {&slice->accumulators, &slice->rejected, &slice->rays, &slice->samples, &slice->light_rays};
        for (int i = 0; i < 5; ++i)
            if (*state[i])
                clReleaseMemObject(*state[i]);
        if (slice->pass)
            clReleaseEvent(slice->pass);
        memset(slice, 0, sizeof *slice);
    }
    w->slice_count = 0;
}

static void release_worker(Worker *w)
{
    release_state(w);
    for (int i = 0; i < SCENE_BUFFERS; ++i)
        if (w->scene[i])
            clReleaseMemObject(w->scene[i]);
    estimator_program_destroy(w->estimator);
    sample_estimator_program_destroy(w->sample_estimator);
    w->sample_estimator = NULL;
    cl_kernel kernels[] = {w->kernel, w->splat_kernel, w->add_kernel};
    for (int i = 0; i < 3; ++i)
        if (kernels[i])
            clReleaseKernel(kernels[i]);
    cl_mem buffers[] = {w->records, w->record_count, w->offsets};
    for (int i = 0; i < 3; ++i)
        if (buffers[i])
            clReleaseMemObject(buffers[i]);
    w->splat_kernel = w->add_kernel = NULL;
    w->records = w->record_count = w->offsets = NULL;
    w->record_capacity = w->offset_capacity = 0;
    if (w->program)
        clReleaseProgram(w->program);
    memset(w->scene, 0, sizeof w->scene);
    w->estimator = NULL;
    w->kernel = NULL;
    w->program = NULL;
}

/* Drops a device from the render: its pixels go to the others. */
static void drop_worker(Render *r, Worker *w, const char *why)
{
    w->live = 0;
    w->report->failed = 1;
    snprintf(w->report->error, sizeof w->report->error, "%s", why);
    release_worker(w);
    int left = live_workers(r);
    fprintf(stderr, "gmonrt: device %d '%s' failed: %s; %s\n", (int)(w - r->workers), w->report->name, why,
            left ? "going on without it (its pixels are re-rendered by the others from the last saved sums)"
                 : "no device left");
}

static void drop_on_cl_error(Render *r, Worker *w, const char *what)
{
    char why[512];
    snprintf(why, sizeof why, "%s: %s", what, cl_last_error());
    drop_worker(r, w, why);
}

size_t render_bytes_per_pixel(size_t sets)
{
    return accumulator_planes((uint32_t)sets) * sizeof(uint64_t) + REJECTED_PLANES * sizeof(uint32_t) +
           sizeof(uint64_t);
}

/* The state of one pixel in this render: sums and counters, and the
 * per-sample state. */
static size_t pixel_state_bytes(const Render *r)
{
    return render_bytes_per_pixel((size_t)r->sets) + r->sample_planes * sizeof(uint64_t);
}

/* Device memory a worker holds now, plus `extra`. */
static size_t worker_bytes(const Render *r, const Worker *w, size_t extra)
{
    size_t state = w->slice_count ? w->count * pixel_state_bytes(r) : 0;
    return w->scene_bytes + state + extra;
}

static void track_peak(const Render *r, Worker *w, size_t extra)
{
    size_t bytes = worker_bytes(r, w, extra);
    if (bytes > w->report->peak_bytes)
        w->report->peak_bytes = bytes;
}

/* The fault injected in device `index` (RenderSettings.fault): -1 to fail
 * its build, a pass number, or 0 for no fault. */
static int injected_fault(const char *spec, int index)
{
    while (spec && *spec) {
        int device = -1, pass = 0, used = 0;
        if (sscanf(spec, "%d:pass:%d%n", &device, &pass, &used) == 2 && device == index)
            return pass;
        if (sscanf(spec, "%d:build%n", &device, &used) == 1 && used > 0 && device == index)
            return -1;
        spec = strchr(spec, ',');
        spec = spec ? spec + 1 : NULL;
    }
    return 0;
}

/* Builds the programs and uploads the scene. Returns 0, or -1 after
 * dropping the worker. */
static int start_worker(Render *r, Worker *w, const char *options)
{
    const RenderSettings *s = r->settings;
    double start = now_seconds();
    if (w->fault_pass < 0) {
        drop_worker(r, w, "the path tracer failed to build (injected by " RENDER_FAULT_ENV ")");
        return -1;
    }
    if (r->sample_planes && !sample_passes_supported(w->device, &r->estimator)) {
        drop_worker(r, w, "the device cannot keep the per-sample passes' moments");
        return -1;
    }
    w->program = cl_program_build(w->device, r->splats ? "bdpt" : "path_tracer", options, s->kernel_dir);
    if (!w->program) {
        drop_worker(r, w, "the path tracer failed to build (build log above)");
        return -1;
    }
    cl_int err = CL_SUCCESS;
    w->kernel = clCreateKernel(w->program, "render_samples", &err);
    if (err != CL_SUCCESS) {
        drop_worker(r, w, "clCreateKernel(render_samples) failed");
        return -1;
    }
    if (r->splats) {
        w->splat_kernel = clCreateKernel(w->program, "splat_samples", &err);
        if (err == CL_SUCCESS)
            w->add_kernel = clCreateKernel(w->program, "add_splats", &err);
        if (err == CL_SUCCESS)
            w->record_count = clCreateBuffer(w->device->context, CL_MEM_READ_WRITE, sizeof(cl_uint), NULL, &err);
        if (err != CL_SUCCESS) {
            drop_on_cl_error(r, w, "creating the splat kernels");
            return -1;
        }
    }
    if (r->estimator.passes & PASSES_ALL) {
        w->estimator = estimator_program_new(w->device, &r->estimator, &s->estimator_launch, s->kernel_dir);
        if (!w->estimator) {
            drop_worker(r, w, "the estimator failed to build (build log above)");
            return -1;
        }
    }
    if (r->sample_planes) {
        w->sample_estimator = sample_estimator_program_new(w->device, &r->estimator, s->kernel_dir);
        if (!w->sample_estimator) {
            drop_worker(r, w, "the per-sample estimator failed to build (build log above)");
            return -1;
        }
    }
    w->report->build_seconds = now_seconds() - start;

    if (scene_upload_create(&r->upload, w->device->context, w->kernel, w->scene) != CL_SUCCESS ||
        (w->splat_kernel && scene_upload_bind(w->splat_kernel, w->scene) != CL_SUCCESS)) {
        drop_worker(r, w, "cannot allocate the scene's buffers");
        return -1;
    }
    w->scene_bytes = scene_upload_bytes(&r->upload);
    track_peak(r, w, 0);
    return 0;
}

/* Copies a slice's state to (write = 0) or from (write = 1) a host copy of
 * the whole image: rectangles of `count` values out of every plane. */
static cl_int transfer_slice(const Render *r, const Worker *w, const Slice *slice, int write, HostState *host)
{
    struct {
        cl_mem buffer;
        void *host;
        size_t element, planes;
    } parts[4] = {{slice->accumulators, host->accumulators, sizeof(uint64_t), r->planes},
                  {slice->rejected, host->rejected, sizeof(uint32_t), REJECTED_PLANES},
                  {slice->rays, host->rays, sizeof(uint64_t), 1},
                  {slice->samples, host->samples, sizeof(uint64_t), r->sample_planes}};
    for (int i = 0; i < (r->sample_planes ? 4 : 3); ++i) {
        size_t element = parts[i].element;
        size_t buffer_origin[3] = {0, 0, 0}, host_origin[3] = {slice->first * element, 0, 0};
        size_t region[3] = {slice->count * element, parts[i].planes, 1};
        size_t buffer_pitch = slice->count * element, host_pitch = r->pixels * element;
        cl_int err =
            write ? clEnqueueWriteBufferRect(w->device->queue, parts[i].buffer, CL_TRUE, buffer_origin, host_origin,
                                             region, buffer_pitch, 0, host_pitch, 0, parts[i].host, 0, NULL, NULL)
                  : clEnqueueReadBufferRect(w->device->queue, parts[i].buffer, CL_TRUE, buffer_origin, host_origin,
                                            region, buffer_pitch, 0, host_pitch, 0, parts[i].host, 0, NULL, NULL);
        if (err != CL_SUCCESS) {
            cl_report_error(write ? "clEnqueueWriteBufferRect" : "clEnqueueReadBufferRect", err, __FILE__, __LINE__);
            return err;
        }
    }
    return CL_SUCCESS;
}

/* transfer_slice for each of the worker's slices. */
static cl_int transfer_state(const Render *r, const Worker *w, int write, HostState *host)
{
    for (int k = 0; k < w->slice_count; ++k) {
        cl_int err = transfer_slice(r, w, &w->slices[k], write, host);
        if (err != CL_SUCCESS)
            return err;
    }
    return CL_SUCCESS;
}

/* The most pixels one slice of worker w may hold: its largest buffer (a
 * plane set of the state, or the images of an estimate) within the
 * device's largest allocation, or the settings' smaller limit. */
static size_t slice_pixels(const Render *r, const Worker *w)
{
    size_t largest = r->planes * sizeof(uint64_t);
    size_t others[] = {r->sample_planes * sizeof(uint64_t), REJECTED_PLANES * sizeof(uint32_t),
                       w->estimator ? estimator_program_image_bytes(w->estimator, 1) : 0,
                       w->sample_estimator ? sample_estimator_program_image_bytes(w->sample_estimator, 1) : 0};
    for (size_t i = 0; i < sizeof others / sizeof others[0]; ++i)
        largest = others[i] > largest ? others[i] : largest;
    uint64_t limit = w->device->info.max_allocation;
    if (r->settings->slice_bytes > 0 && r->settings->slice_bytes < limit)
        limit = r->settings->slice_bytes;
    return (size_t)(limit / largest);
}

/* Allocates a slice's buffers for its pixels. */
static cl_int allocate_slice(const Render *r, const Worker *w, Slice *slice)
{
    cl_int err = CL_SUCCESS;
    cl_context context = w->device->context;
    size_t count = slice->count;
    slice->accumulators = clCreateBuffer(context, CL_MEM_READ_WRITE, count * r->planes * sizeof(uint64_t), NULL, &err);
    if (err == CL_SUCCESS)
        slice->rejected =
            clCreateBuffer(context, CL_MEM_READ_WRITE, count * REJECTED_PLANES * sizeof(uint32_t), NULL, &err);
    if (err == CL_SUCCESS)
        slice->rays = clCreateBuffer(context, CL_MEM_READ_WRITE, count * sizeof(uint64_t), NULL, &err);
    if (err == CL_SUCCESS && r->sample_planes)
        slice->samples =
            clCreateBuffer(context, CL_MEM_READ_WRITE, count * r->sample_planes * sizeof(uint64_t), NULL, &err);
    if (err == CL_SUCCESS && r->splats)
        slice->light_rays = clCreateBuffer(context, CL_MEM_READ_WRITE, count * sizeof(uint64_t), NULL, &err);
    if (err != CL_SUCCESS)
        cl_report_error("clCreateBuffer", err, __FILE__, __LINE__);
    return err;
}

/* Splits the image among the live workers in proportion to `weights` (each
 * gets at least one pixel) and gives each the saved state of its pixels; a
 * worker whose pixels stay the same keeps its state unless `reload` (its
 * state is newer than the saved one after a failure). Returns 0; -1 if a
 * worker failed (dropped: call again); -2 if a share does not fit a device
 * (message in `error`). */
static int assign_pixels(Render *r, const double *weights, int reload, char *error, size_t error_size)
{
    double total = 0.0;
    int live = live_workers(r);
    for (int i = 0; i < r->worker_count; ++i)
        if (r->workers[i].live)
            total += weights[i] > 0.0 ? weights[i] : 0.0;
    size_t first = 0;
    int seen = 0;
    double cumulative = 0.0;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (!w->live)
            continue;
        ++seen;
        cumulative += total > 0.0 ? (weights[i] > 0.0 ? weights[i] : 0.0) / total : 1.0 / live;
        size_t end = seen == live ? r->pixels : (size_t)(cumulative * (double)r->pixels + 0.5);
        size_t most = r->pixels - (size_t)(live - seen); /* leave a pixel for each worker after */
        end = end < first + 1 ? first + 1 : (end > most ? most : end);
        size_t count = end - first;
        int unchanged = !reload && w->slice_count && w->first == first && w->count == count;
        if (!unchanged) {
            release_state(w);
            size_t most = slice_pixels(r, w);
            size_t slices = most ? (count + most - 1) / most : 0;
            if (slices == 0 || slices > RENDER_MAX_SLICES) {
                snprintf(error, error_size,
                         "the exact set sums of %zu pixels with M = %d need %.2f GiB; device '%s' holds them in at "
                         "most %d buffers of %zu pixels (its largest allocation %.2f GiB): lower the resolution or "
                         "--sets, or add devices",
                         count, r->sets, (double)(count * r->planes * sizeof(uint64_t)) / 1073741824.0,
                         w->device->info.name, RENDER_MAX_SLICES, most,
                         (double)w->device->info.max_allocation / 1073741824.0);
                return -2;
            }
            w->first = first;
            w->count = count;
            w->slice_count = (int)slices;
            if (w->slice_count > w->report->slices)
                w->report->slices = w->slice_count;
            /* even slices, in pixel order */
            cl_int err = CL_SUCCESS;
            for (size_t k = 0; k < slices && err == CL_SUCCESS; ++k) {
                Slice *slice = &w->slices[k];
                slice->first = first + count * k / slices;
                slice->count = first + count * (k + 1) / slices - slice->first;
                err = allocate_slice(r, w, slice);
            }
            if (err == CL_SUCCESS)
                err = transfer_state(r, w, 1, &r->saved);
            if (err != CL_SUCCESS) {
                drop_on_cl_error(r, w, "allocating and filling the accumulators");
                return -1;
            }
            track_peak(r, w, 0);
        }
        first = end;
    }
    return 0;
}

/* assign_pixels with every worker reloaded from the saved state, again
 * while workers fail. Returns 0, -1 when none is left, -2 as
 * assign_pixels. */
static int assign_until_settled(Render *r, const double *weights, char *error, size_t error_size)
{
    for (;;) {
        if (live_workers(r) == 0)
            return -1;
        int status = assign_pixels(r, weights, 1, error, error_size);
        if (status != -1)
            return status;
    }
}

/* Gathers every worker's state into the host copy. Returns 0, or -1 after
 * dropping a worker that failed (the previous copy stays). */
static int save_state(Render *r, uint64_t samples)
{
    double start = now_seconds();
    HostState *target = r->scratch.accumulators ? &r->scratch : &r->saved;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (w->live && transfer_state(r, w, 0, target) != CL_SUCCESS) {
            r->saved_lost |= target == &r->saved;
            drop_on_cl_error(r, w, "reading back its sums");
            return -1;
        }
    }
    if (target == &r->scratch) {
        HostState swap = r->saved;
        r->saved = r->scratch;
        r->scratch = swap;
    }
    r->saved_samples = samples;
    for (int i = 0; i < r->worker_count; ++i) {
        r->workers[i].report->samples += r->workers[i].unsaved_samples;
        r->workers[i].unsaved_samples = 0;
    }
    r->saved_at = now_seconds();
    r->save_seconds = r->saved_at - start;
    return 0;
}

/* A device buffer of at least `bytes`, grown (contents lost) when smaller
 * than that; *capacity counts its elements of `element` bytes. */
static cl_int ensure_buffer(Worker *w, cl_mem *buffer, size_t *capacity, size_t needed, size_t element)
{
    if (*buffer && *capacity >= needed)
        return CL_SUCCESS;
    if (*buffer)
        clReleaseMemObject(*buffer);
    cl_int err = CL_SUCCESS;
    size_t grown = needed + needed / 4 + 1024;
    *buffer = clCreateBuffer(w->device->context, CL_MEM_READ_WRITE, grown * element, NULL, &err);
    *capacity = err == CL_SUCCESS ? grown : 0;
    if (err != CL_SUCCESS)
        *buffer = NULL;
    return err;
}

/* About the most splat records a pass gathers on the host (20 B each, held
 * twice: gathered and sorted), unless one sample a pixel makes more. */
#define SPLATS_PER_PASS 16777216.0

/* The most splat records one launch may leave on a device: a launch that
 * makes more is run again in halves (records are never dropped). */
static size_t most_records(const Render *r, const Worker *w)
{
    size_t by_allocation = (size_t)(w->device->info.max_allocation / sizeof(SplatRecord));
    size_t limit = r->settings->splat_records ? (size_t)r->settings->splat_records : (size_t)1 << 22; /* 80 MiB */
    return by_allocation < limit ? by_allocation : limit;
}

/* Appends records to the pass's host list. Returns 0, -1 out of memory. */
static int keep_records(Render *r, size_t n)
{
    if (r->splat_count + n <= r->splat_capacity)
        return 0;
    size_t capacity = (r->splat_count + n) * 2;
    SplatRecord *grown = realloc(r->splat_records, capacity * sizeof *grown);
    if (!grown)
        return -1;
    r->splat_records = grown;
    r->splat_capacity = capacity;
    return 0;
}

/* Traces the light subpaths of samples [first_sample, + count) of pixels
 * [first, first + pixels) of a slice and appends their splat records to
 * the host list; a launch whose records pass the buffer runs again with a
 * larger one, or in halves (pixels, then samples). Returns a CL error. */
static cl_int trace_splats(Render *r, Worker *w, const Slice *slice, size_t first, size_t pixels, uint64_t first_sample,
                           uint32_t count)
{
    for (;;) {
        const size_t most = most_records(r, w);
        const cl_uint zero = 0, capacity = (cl_uint)(w->record_capacity < most ? w->record_capacity : most);
        const cl_ulong first_sample_arg = first_sample, first_pixel = first, pixel_count = pixels,
                       buffer_first = slice->first;
        cl_mem records = w->records;
        if (!records) {
            cl_int err = ensure_buffer(w, &w->records, &w->record_capacity, 1 << 16, sizeof(SplatRecord));
            if (err != CL_SUCCESS)
                return err;
            continue;
        }
        cl_kernel k = w->splat_kernel;
        cl_uint a = SCENE_BUFFERS;
        size_t local = (w->device->info.type & CL_DEVICE_TYPE_CPU) ? 8 : 64;
        size_t global = (pixels + local - 1) / local * local;
        cl_uint made = 0;
        CL_CHECK(clEnqueueWriteBuffer(w->device->queue, w->record_count, CL_TRUE, 0, sizeof zero, &zero, 0, NULL, NULL),
                 failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof records, &records), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof w->record_count, &w->record_count), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof capacity, &capacity), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof slice->light_rays, &slice->light_rays), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof first_sample_arg, &first_sample_arg), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof count, &count), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof first_pixel, &first_pixel), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof pixel_count, &pixel_count), failed);
        CL_CHECK(clSetKernelArg(k, a++, sizeof buffer_first, &buffer_first), failed);
        CL_CHECK(clEnqueueNDRangeKernel(w->device->queue, k, 1, NULL, &global, &local, 0, NULL, NULL), failed);
        CL_CHECK(clEnqueueReadBuffer(w->device->queue, w->record_count, CL_TRUE, 0, sizeof made, &made, 0, NULL, NULL),
                 failed);
        if (made <= capacity) {
            if (keep_records(r, made))
                return CL_OUT_OF_HOST_MEMORY;
            if (made)
                CL_CHECK(clEnqueueReadBuffer(w->device->queue, records, CL_TRUE, 0, made * sizeof(SplatRecord),
                                             r->splat_records + r->splat_count, 0, NULL, NULL),
                         failed);
            r->splat_count += made;
            return CL_SUCCESS;
        }
        /* The counter stops at 2^32 - 1 at worst: split before trusting it. */
        if (made < UINT32_MAX && made <= most) {
            cl_int err = ensure_buffer(w, &w->records, &w->record_capacity, made, sizeof(SplatRecord));
            if (err != CL_SUCCESS)
                return err;
            continue;
        }
        if (pixels > 1) {
            cl_int err = trace_splats(r, w, slice, first, pixels / 2, first_sample, count);
            return err == CL_SUCCESS
                       ? trace_splats(r, w, slice, first + pixels / 2, pixels - pixels / 2, first_sample, count)
                       : err;
        }
        if (count > 1) {
            cl_int err = trace_splats(r, w, slice, first, pixels, first_sample, count / 2);
            return err == CL_SUCCESS
                       ? trace_splats(r, w, slice, first, pixels, first_sample + count / 2, count - count / 2)
                       : err;
        }
        return CL_OUT_OF_RESOURCES; /* one light subpath past the limit: cannot happen at sane depths */
    failed:
        return CL_INVALID_OPERATION; /* reported by CL_CHECK */
    }
}

/* Adds the sorted records of a slice's pixels (and its light subpaths'
 * rays) into its sums. Returns a CL error. */
static cl_int add_slice_splats(Render *r, Worker *w, const Slice *slice)
{
    const uint32_t *offsets = r->splat_offsets + slice->first;
    size_t n = offsets[slice->count] - offsets[0];
    cl_int err = ensure_buffer(w, &w->records, &w->record_capacity, n, sizeof(SplatRecord));
    if (err == CL_SUCCESS)
        err = ensure_buffer(w, &w->offsets, &w->offset_capacity, slice->count + 1, sizeof(cl_uint));
    if (err != CL_SUCCESS)
        return err;
    /* Offsets relative to the slice's first record. */
    cl_uint *relative = malloc((slice->count + 1) * sizeof *relative);
    if (!relative)
        return CL_OUT_OF_HOST_MEMORY;
    for (size_t i = 0; i <= slice->count; ++i)
        relative[i] = offsets[i] - offsets[0];
    const cl_ulong first = slice->first, count = slice->count;
    cl_kernel k = w->add_kernel;
    cl_uint a = 0;
    size_t local = (w->device->info.type & CL_DEVICE_TYPE_CPU) ? 8 : 64;
    size_t global = (slice->count + local - 1) / local * local;
    if (n)
        CL_CHECK(clEnqueueWriteBuffer(w->device->queue, w->records, CL_TRUE, 0, n * sizeof(SplatRecord),
                                      r->splat_sorted + offsets[0], 0, NULL, NULL),
                 failed);
    CL_CHECK(clEnqueueWriteBuffer(w->device->queue, w->offsets, CL_TRUE, 0, (slice->count + 1) * sizeof *relative,
                                  relative, 0, NULL, NULL),
             failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof slice->accumulators, &slice->accumulators), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof slice->rejected, &slice->rejected), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof slice->rays, &slice->rays), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof slice->light_rays, &slice->light_rays), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof w->records, &w->records), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof w->offsets, &w->offsets), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof first, &first), failed);
    CL_CHECK(clSetKernelArg(k, a++, sizeof count, &count), failed);
    if (r->sample_planes)
        CL_CHECK(clSetKernelArg(k, a++, sizeof slice->samples, &slice->samples), failed);
    CL_CHECK(clEnqueueNDRangeKernel(w->device->queue, k, 1, NULL, &global, &local, 0, NULL, NULL), failed);
    CL_CHECK(clFinish(w->device->queue), failed);
    free(relative);
    return CL_SUCCESS;
failed:
    free(relative);
    return CL_INVALID_OPERATION; /* reported by CL_CHECK */
}

/* Puts the pass's records in pixel order (a counting sort; the sums do not
 * depend on the order within a pixel). Returns 0, -1 out of memory or
 * past the 2^32 records the offsets count. */
static int sort_splats(Render *r)
{
    free(r->splat_sorted);
    r->splat_sorted = malloc((r->splat_count ? r->splat_count : 1) * sizeof *r->splat_sorted);
    if (!r->splat_offsets)
        r->splat_offsets = malloc((r->pixels + 1) * sizeof *r->splat_offsets);
    if (!r->splat_sorted || !r->splat_offsets || r->splat_count >= UINT32_MAX)
        return -1;
    uint32_t *o = r->splat_offsets;
    memset(o, 0, (r->pixels + 1) * sizeof *o);
    for (size_t i = 0; i < r->splat_count; ++i)
        ++o[r->splat_records[i].pixel + 1];
    for (size_t p = 0; p < r->pixels; ++p)
        o[p + 1] += o[p];
    for (size_t i = 0; i < r->splat_count; ++i) {
        const SplatRecord *record = &r->splat_records[i];
        r->splat_sorted[o[record->pixel]++] = *record;
    }
    /* The scatter moved each offset to its pixel's end: shift back. */
    memmove(o + 1, o, r->pixels * sizeof *o);
    o[0] = 0;
    return 0;
}

/* The pass's splats: every live worker traces its pixels' light subpaths
 * (samples [first_sample, + count)), the host gathers and sorts the
 * records by pixel, and every worker adds those of its own pixels. A
 * failure drops the worker: the caller rolls every worker back to the
 * saved sums, as for a failed pass. Returns the number of failures. */
static int splat_pass(Render *r, uint64_t first_sample, uint32_t count)
{
    r->splat_count = 0;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        double start = now_seconds();
        cl_int err = CL_SUCCESS;
        for (int k = 0; k < w->slice_count && w->live && err == CL_SUCCESS; ++k)
            err = trace_splats(r, w, &w->slices[k], w->slices[k].first, w->slices[k].count, first_sample, count);
        if (err != CL_SUCCESS) {
            drop_on_cl_error(r, w, "tracing light subpaths");
            return 1;
        }
        w->pass_seconds += now_seconds() - start;
        w->report->busy_seconds += now_seconds() - start;
    }
    if (sort_splats(r)) {
        for (int i = 0; i < r->worker_count; ++i)
            if (r->workers[i].live) {
                drop_worker(r, &r->workers[i], "out of host memory for the splat records");
                return 1;
            }
    }
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        double start = now_seconds();
        cl_int err = CL_SUCCESS;
        for (int k = 0; k < w->slice_count && w->live && err == CL_SUCCESS; ++k)
            err = add_slice_splats(r, w, &w->slices[k]);
        if (err != CL_SUCCESS) {
            drop_on_cl_error(r, w, "adding splats");
            return 1;
        }
        w->pass_seconds += now_seconds() - start;
        w->report->busy_seconds += now_seconds() - start;
    }
    return 0;
}

/* Renders samples [first_sample, first_sample + count) on every live
 * worker's pixels, all devices at once. Returns the number of workers that
 * failed (dropped). */
static int run_pass(Render *r, uint64_t first_sample, uint32_t count, int pass_number)
{
    int failures = 0;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (!w->live)
            continue;
        if (w->fault_pass > 0 && w->fault_pass == pass_number) {
            drop_worker(r, w, "a pass failed (injected by " RENDER_FAULT_ENV ")");
            ++failures;
            continue;
        }
        for (int k = 0; k < w->slice_count; ++k) {
            Slice *slice = &w->slices[k];
            RenderPassArguments args = {
                slice->accumulators, slice->rejected, slice->rays,  first_sample, count,
                slice->first,        slice->count,    slice->first, slice->count, slice->samples};
            /* A fixed work-group size (the kernel skips items past the
             * end): PoCL compiles a kernel per work-group size, on first
             * use, and a size of the runtime's choosing would follow every
             * new share. */
            size_t local = (w->device->info.type & CL_DEVICE_TYPE_CPU) ? 8 : 64;
            size_t global = (slice->count + local - 1) / local * local;
            CL_CHECK(scene_upload_bind_pass(w->kernel, &args), failed);
            CL_CHECK(
                clEnqueueNDRangeKernel(w->device->queue, w->kernel, 1, NULL, &global, &local, 0, NULL, &slice->pass),
                failed);
        }
        CL_CHECK(clFlush(w->device->queue), failed);
        continue;
    failed:
        drop_on_cl_error(r, w, "starting a pass");
        ++failures;
    }
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (!w->live || !w->slice_count || !w->slices[0].pass)
            continue;
        cl_int err = CL_SUCCESS;
        double seconds = 0.0;
        for (int k = 0; k < w->slice_count && err == CL_SUCCESS; ++k) {
            Slice *slice = &w->slices[k];
            cl_int status = CL_SUCCESS;
            err = clWaitForEvents(1, &slice->pass);
            if (err == CL_SUCCESS)
                err = clGetEventInfo(slice->pass, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, NULL);
            if (err == CL_SUCCESS && status < 0)
                err = status;
            if (err == CL_SUCCESS)
                seconds += cl_event_seconds(slice->pass);
        }
        if (err != CL_SUCCESS) {
            cl_report_error("the path tracer kernel", err, __FILE__, __LINE__);
            drop_on_cl_error(r, w, "a pass failed");
            ++failures;
            continue;
        }
        w->pass_seconds = seconds;
        w->report->busy_seconds += w->pass_seconds;
        w->unsaved_samples += (uint64_t)count * w->count;
        for (int k = 0; k < w->slice_count; ++k) {
            clReleaseEvent(w->slices[k].pass);
            w->slices[k].pass = NULL;
        }
    }
    if (failures == 0 && r->splats && count > 0)
        failures += splat_pass(r, first_sample, count);
    return failures;
}

static int allocate_images(RenderOutput *out, const EstimatorSettings *settings, size_t pixels)
{
    const size_t bytes = pixels * EST_CHANNELS * sizeof(float);
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(settings->passes & PASS_BIT(p)))
            continue;
        const size_t images = (PASSES_SAMPLE & PASS_BIT(p)) ? (size_t)film_sample_pass_images(settings, p) : 1;
        if (!out->pass[p] && !(out->pass[p] = malloc(images * bytes)))
            return -1;
        if (settings->with_stderr && (PASSES_ESTIMATES & PASS_BIT(p)) && !out->error[p] &&
            !(out->error[p] = malloc(bytes)))
            return -1;
    }
    return 0;
}

/* zirr's image: its 3x3 neighbourhoods cross the workers' pixel ranges,
 * so it is estimated from every worker's cascades gathered on the host
 * (exact sums: the same whatever the split), by the first live worker's
 * kernel. Returns 0, or -1 after dropping a worker. */
static int estimate_zirr_on_device(Render *r, uint64_t samples, RenderOutput *out)
{
    if (!(r->estimator.passes & PASS_BIT(PASS_ZIRR)))
        return 0;
    if (r->saved_samples != samples && save_state(r, samples) != 0)
        return -1;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (!w->live || !w->sample_estimator)
            continue;
        track_peak(r, w,
                   ((film_sample_zirr_planes(&r->estimator) + r->planes) * sizeof(uint64_t) +
                    (size_t)(r->estimator.params.zirr_k + 1) * EST_CHANNELS * sizeof(float)) *
                       r->pixels);
        if (sample_estimator_program_zirr(w->sample_estimator, r->saved.samples, r->saved.accumulators,
                                          r->scene->constants.camera.width, r->scene->constants.camera.height, samples,
                                          out->pass[PASS_ZIRR], &w->report->estimate_seconds) != 0) {
            drop_on_cl_error(r, w, "the zirr estimator failed");
            return -1;
        }
        return 0;
    }
    return -1;
}

/* The estimates of one slice's pixels into the output's images. */
static cl_int estimate_slice(const Render *r, Worker *w, const Slice *slice, uint64_t samples, EstimatorImages *host)
{
    cl_int err = CL_SUCCESS;
    if (w->estimator) {
        const size_t bytes = estimator_program_image_bytes(w->estimator, slice->count);
        cl_mem images = clCreateBuffer(w->device->context, CL_MEM_WRITE_ONLY, bytes, NULL, &err);
        cl_event done = NULL;
        if (err == CL_SUCCESS) {
            track_peak(r, w, bytes);
            done = estimator_program_enqueue(w->estimator, slice->accumulators, 1, slice->count, samples, images);
            err = done ? CL_SUCCESS : CL_OUT_OF_RESOURCES;
        }
        if (err == CL_SUCCESS)
            err = estimator_program_read(w->estimator, images, slice->first, slice->count, host);
        if (done) {
            w->report->estimate_seconds += cl_event_seconds(done);
            clReleaseEvent(done);
        }
        if (images)
            clReleaseMemObject(images);
    }
    const size_t sample_image_bytes =
        w->sample_estimator ? sample_estimator_program_image_bytes(w->sample_estimator, slice->count) : 0;
    if (err == CL_SUCCESS && sample_image_bytes) { /* zirr alone: estimate_zirr_on_device's */
        const size_t bytes = sample_image_bytes;
        cl_mem images = clCreateBuffer(w->device->context, CL_MEM_WRITE_ONLY, bytes, NULL, &err);
        cl_event done = NULL;
        if (err == CL_SUCCESS) {
            track_peak(r, w, bytes);
            done = sample_estimator_program_enqueue(w->sample_estimator, slice->samples, slice->accumulators,
                                                    slice->count, samples, images);
            err = done ? CL_SUCCESS : CL_OUT_OF_RESOURCES;
        }
        if (err == CL_SUCCESS)
            err =
                sample_estimator_program_read(w->sample_estimator, images, slice->first, slice->count, r->pixels, host);
        if (done) {
            w->report->estimate_seconds += cl_event_seconds(done);
            clReleaseEvent(done);
        }
        if (images)
            clReleaseMemObject(images);
    }
    return err;
}

/* The estimates of `samples` samples per pixel, each worker on its pixels,
 * into the output's images. Returns 0, or -1 after dropping a worker. */
static int estimate_on_devices(Render *r, uint64_t samples, RenderOutput *out)
{
    EstimatorImages host = render_output_images(out);
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        if (!w->live)
            continue;
        cl_int err = CL_SUCCESS;
        for (int k = 0; k < w->slice_count && err == CL_SUCCESS; ++k)
            err = estimate_slice(r, w, &w->slices[k], samples, &host);
        if (err != CL_SUCCESS) {
            drop_on_cl_error(r, w, "the estimator failed");
            return -1;
        }
    }
    return estimate_zirr_on_device(r, samples, out);
}

/* The same on the host from the saved state (bit-identical to the kernels),
 * for when no device is left. */
static int estimate_on_host(const Render *r, uint64_t samples, RenderOutput *out)
{
    EstimatorImages images = render_output_images(out);
    if ((r->estimator.passes & PASSES_ALL) &&
        estimator_from_accumulators(&r->estimator, r->saved.accumulators, r->planes * r->pixels, r->pixels, samples,
                                    &images, NULL, 0) != ESTIMATOR_OK)
        return -1;
    if (r->sample_planes &&
        film_sample_estimate(&r->estimator, r->saved.samples, r->sample_planes * r->pixels, r->saved.accumulators,
                             r->pixels, samples, &images, NULL, 0) != ESTIMATOR_OK)
        return -1;
    if ((r->estimator.passes & PASS_BIT(PASS_ZIRR)) &&
        film_sample_estimate_zirr(&r->estimator, r->saved.samples, r->sample_planes * r->pixels, r->saved.accumulators,
                                  r->scene->constants.camera.width, r->scene->constants.camera.height, samples,
                                  out->pass[PASS_ZIRR], NULL, 0) != ESTIMATOR_OK)
        return -1;
    return 0;
}

/* After a failure: every worker goes back to the saved state, split among
 * those left, and renders the samples since again (the same samples, so the
 * image does not change). Returns -2 as assign_pixels, else 0. */
static int roll_back(Render *r, const double *weights, uint64_t *done_samples, char *error, size_t error_size)
{
    for (int i = 0; i < r->worker_count; ++i)
        r->workers[i].unsaved_samples = 0;
    *done_samples = r->saved_samples;
    return assign_until_settled(r, weights, error, error_size) == -2 ? -2 : 0;
}

static int is_power_of_two(uint64_t x)
{
    return x && !(x & (x - 1));
}

/* Writes the specialized path tracer source with its defines. */
void path_tracer_build_options(const EstimatorSettings *estimator, uint64_t features, uint32_t sampler,
                               int sampler_sets, int stack_need, char *options, size_t size)
{
    char sample_options[768];
    film_sample_build_options(estimator, sample_options, sizeof sample_options);
    /* Rounded up to a multiple of 16, so that scenes of about the same
     * depth share a cached build. */
    int stack_size = (stack_need > 1 ? stack_need + 15 : 16) / 16 * 16;
    snprintf(options, size,
             "-DEST_SETS=%d -DGMON_FEATURES=0x%" PRIx64 "ul -DGMON_SAMPLER=%u -DGMON_SAMPLER_SETS=%d "
             "-DBVH_STACK_SIZE=%d -cl-unsafe-math-optimizations%s",
             estimator->set_count, features, (unsigned)sampler, sampler_sets, stack_size, sample_options);
}

static int dump_kernel(const RenderSettings *s, const char *program, const char *options, char *error,
                       size_t error_size)
{
    char include_dir[4096], message[512];
    char *source =
        kernel_source_load(program, s->kernel_dir, include_dir, sizeof include_dir, message, (int)sizeof message);
    if (!source) {
        snprintf(error, error_size, "%s", message);
        return -1;
    }
    FILE *f = fopen(s->dump_kernel, "w");
    int ok = f != NULL;
    if (f) {
        fprintf(f, "/* gmonrt: the %s kernels as built for this render.\n * Build options: %s */\n", program, options);
        /* The -DNAME=VALUE options as defines. */
        char defines[1024];
        snprintf(defines, sizeof defines, "%s", options);
        for (char *save = NULL, *item = strtok_r(defines, " ", &save); item; item = strtok_r(NULL, " ", &save)) {
            char *equals = strchr(item, '=');
            if (strncmp(item, "-D", 2) == 0 && equals) {
                *equals = ' ';
                fprintf(f, "#define %s\n", item + 2);
            }
        }
        fputs(source, f);
        ok = fclose(f) == 0 && ok;
    }
    free(source);
    if (!ok)
        snprintf(error, error_size, "cannot write %s", s->dump_kernel);
    return ok ? 0 : -1;
}

static double gib(uint64_t bytes)
{
    return (double)bytes / (1024.0 * 1024.0 * 1024.0);
}

/* Host copies of the per-pixel state: see Render.scratch. */
static int host_copies(int device_count)
{
    return device_count > 1 ? 2 : 1;
}

/* Refuses, with both figures, a render whose memory does not fit: on the
 * host its copies of the per-pixel state, the images, and what a CPU
 * device allocates (its memory is the host's); on each device its first
 * share of the state, its images and the scene. */
static int check_memory(const Render *r, ClDevice *devices, int device_count, char *error, size_t error_size)
{
    const int images = pass_image_count(r->estimator.passes, r->estimator.with_stderr);
    const uint64_t state = pixel_state_bytes(r),
                   image = EST_CHANNELS * sizeof(float) * (images + film_sample_images(&r->estimator));
    const uint64_t scene = scene_upload_bytes(&r->upload);
    /* Where the scene is most of it, fewer pixels or sets would not help. */
    char largest[256];
    scene_upload_describe(&r->upload, 2, largest, sizeof largest);
    const char *scene_hint = "the scene is most of it: smaller images (textures, environment maps) or less geometry";
    const int copies = host_copies(device_count);
    uint64_t host = (copies * state + image) * r->pixels + scene, scene_on_host = scene;
    const uint64_t share = (r->pixels + (size_t)device_count - 1) / (size_t)device_count;
    for (int i = 0; i < device_count; ++i) {
        uint64_t device = (state + image) * share + scene;
        if (devices[i].info.type & CL_DEVICE_TYPE_CPU) {
            host += device;
            scene_on_host += scene;
        }
        if (device > devices[i].info.global_memory) {
            snprintf(error, error_size,
                     "the render needs %.2f GiB on device '%s' (%llu B of set sums and counters and %llu B of images "
                     "a pixel, M = %d, for %llu pixels; the scene %.1f MiB: %s), which has %.2f GiB: %s",
                     gib(device), devices[i].info.name, (unsigned long long)state, (unsigned long long)image, r->sets,
                     (unsigned long long)share, 1024.0 * gib(scene), largest, gib(devices[i].info.global_memory),
                     2 * scene > device ? scene_hint : "lower --resolution or --sets, or add devices");
            return -1;
        }
    }
    char source[128];
    uint64_t available = memory_host_available(r->settings->host_memory_limit, source, sizeof source);
    if (host > available) {
        snprintf(error, error_size,
                 "the render needs %.2f GiB of host memory (%llu B of set sums and counters a pixel at M = %d, %s "
                 "on the host and once more on each CPU device, %llu B of images a pixel, %ux%u pixels; the scene "
                 "%.1f MiB, as many times: %s), but %.2f GiB is available (%s): %s",
                 gib(host), (unsigned long long)state, r->sets, copies == 1 ? "once" : "twice",
                 (unsigned long long)image, r->scene->constants.camera.width, r->scene->constants.camera.height,
                 1024.0 * gib(scene), largest, gib(available), source,
                 2 * scene_on_host > host
                     ? scene_hint
                     : "lower --resolution or --sets, or ask for the mean alone (--estimators mean)");
        return -1;
    }
    return 0;
}

static void free_state(HostState *h)
{
    free(h->accumulators);
    free(h->rejected);
    free(h->rays);
    free(h->samples);
    memset(h, 0, sizeof *h);
}

static int allocate_state(HostState *h, size_t planes, size_t sample_planes, size_t pixels)
{
    h->accumulators = calloc(planes * pixels, sizeof(uint64_t));
    h->rejected = calloc(REJECTED_PLANES * pixels, sizeof(uint32_t));
    h->rays = calloc(pixels, sizeof(uint64_t));
    h->samples = sample_planes ? calloc(sample_planes * pixels, sizeof(uint64_t)) : NULL;
    return h->accumulators && h->rejected && h->rays && (h->samples || !sample_planes) ? 0 : -1;
}

/* Step 1: what the render keeps (M sets, or one sum when only the mean is
 * asked for; the per-sample state) and what the output records of its
 * settings. Returns 0, or -1 with the reason in `error`. */
static int plan_render(Render *r, int device_count, const RenderScene *scene, const RenderSettings *s,
                       RenderOutput *out, char *error, size_t error_size)
{
    const int m = s->estimator.set_count;
    r->scene = scene;
    r->settings = s;
    scene_upload_init(&r->upload, scene, s->seed);
    /* Only the mean needs no sets: one sum per pixel (the per-sample passes
     * keep their own state). */
    r->sets = (s->estimator.passes & PASSES_ALL & ~PASS_BIT(PASS_MEAN)) || s->estimator.with_stderr || s->keep_sets ||
                      film_sample_needs_sets(&s->estimator)
                  ? m
                  : 1;
    r->estimator = s->estimator;
    r->estimator.set_count = r->sets;
    /* pbrt-v4's Film "maxcomponentvalue" is the per-sample clamp at that
     * level: the sets get the samples as they are. */
    if (scene->constants.film.max_component_value < INFINITY &&
        film_sample_select_film_clamp(&r->estimator, scene->constants.film.max_component_value) < 0) {
        snprintf(error, error_size, "Film \"maxcomponentvalue\" needs a clamp level, but clamp.levels has %d already",
                 EST_CLAMP_LEVELS_MAX);
        return -1;
    }
    r->sample_planes = film_sample_planes(&r->estimator);
    r->splats = (scene->constants.integrator.flags & (RENDER_LIGHTPATH | RENDER_BDPT)) != 0;
    if (r->splats && scene->constants.integrator.max_depth > BDPT_MOST_DEPTH) {
        snprintf(error, error_size,
                 "bdpt and lightpath keep a sample's subpaths in private memory: maxdepth %u is over the %d they "
                 "take (lower Integrator \"maxdepth\" or --maxdepth)",
                 scene->constants.integrator.max_depth, BDPT_MOST_DEPTH);
        return -1;
    }
    /* A splat updates clamp's and zirr's sums as a sample of its value
     * would (add_splats). It is not a sample of the pixel, so the moments
     * of abmm, gabmm and mean-or-mon are undefined with splats; bdpt's
     * strategies do not keep direct light apart for clamp-sum. */
    if (r->splats && (film_sample_passes(&r->estimator) & ~(PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_ZIRR)))) {
        snprintf(error, error_size,
                 "bdpt's and lightpath's splats are not samples of the pixel they land on: the per-sample moments "
                 "of abmm, gabmm and mean-or-mon are undefined with them, and clamp-sum needs direct light apart "
                 "(ask for clamp, zirr or the set-based estimators)");
        return -1;
    }
    r->estimator.first_sample = s->first_sample;
    r->pixels = (size_t)scene->constants.camera.width * scene->constants.camera.height;
    r->planes = accumulator_planes((uint32_t)r->sets);
    r->worker_count = device_count;
    scene_upload_hash(&r->upload, m, out->scene_hash, sizeof out->scene_hash);
    out->max_depth = scene->constants.integrator.max_depth;
    out->integrator = render_integrator_name(scene->constants.integrator.flags);
    out->sampler = scene->constants.integrator.sampler;
    out->light_sampler = scene->constants.integrator.light_sampler;
    out->width = scene->constants.camera.width;
    out->height = scene->constants.camera.height;
    out->set_count = r->sets;
    out->estimator = r->estimator;
    out->seed = s->seed;
    out->first_sample = s->first_sample;
    out->device_count = device_count;
    out->features = s->all_features ? FEATURES_ALL : render_scene_features(scene);
    return 0;
}

/* Step 2: host memory, the programs on every device (the path tracer
 * specialized for the scene's features), the first split of the pixels,
 * and a launch of nothing so that runtimes finish compiling before the
 * clock starts. Returns 0; -1 with the reason in `error`; -2 out of host
 * memory. */
static int start_devices(Render *r, ClDevice *devices, RenderOutput *out, double *weights, char *error,
                         size_t error_size)
{
    const RenderSettings *s = r->settings;
    if (check_memory(r, devices, r->worker_count, error, error_size))
        return -1;
    if (allocate_state(&r->saved, r->planes, r->sample_planes, r->pixels) ||
        (host_copies(r->worker_count) > 1 && allocate_state(&r->scratch, r->planes, r->sample_planes, r->pixels)) ||
        allocate_images(out, &r->estimator, r->pixels))
        return -2;
    /* The path tracer needs no bit-exact agreement with the host (only its
     * integer accumulation does, which no float option touches), so it may
     * reassociate: about 10% faster on PoCL. */
    char options[1024];
    path_tracer_build_options(&r->estimator, out->features, out->sampler, s->estimator.set_count,
                              r->scene->bvh.stack_need, options, sizeof options);
    if (r->splats) /* bdpt.cl's subpaths are private arrays of maxdepth + 2 vertices */
        snprintf(options + strlen(options), sizeof options - strlen(options), " -DBDPT_MAX_DEPTH=%u",
                 r->scene->constants.integrator.max_depth);
    if (s->dump_kernel && dump_kernel(s, r->splats ? "bdpt" : "path_tracer", options, error, error_size))
        return -1;
    for (int i = 0; i < r->worker_count; ++i) {
        Worker *w = &r->workers[i];
        w->device = &devices[i];
        w->report = &out->devices[i];
        w->live = 1;
        w->fault_pass = injected_fault(s->fault, i);
        snprintf(w->report->name, sizeof w->report->name, "%s", devices[i].info.name);
    }
    for (int i = 0; i < r->worker_count; ++i) {
        start_worker(r, &r->workers[i], options);
        out->build_seconds += r->workers[i].report->build_seconds;
    }
    for (int i = 0; i < r->worker_count; ++i)
        weights[i] = 1.0;
    if (assign_until_settled(r, weights, error, error_size) == -2)
        return -1;
    /* Runtimes such as PoCL finish compiling a kernel at its first launch:
     * a pass of no samples and an estimate of nothing do that here, so that
     * build times include it and render times (and checkpoints) do not. */
    double prime_start = now_seconds();
    if (run_pass(r, s->first_sample, 0, 0) > 0 || estimate_on_devices(r, 0, out) != 0) {
        if (assign_until_settled(r, weights, error, error_size) == -2)
            return -1;
    }
    out->build_seconds += now_seconds() - prime_start;
    return 0;
}

/* Step 3: progressive passes, all devices on the same samples, until the
 * samples, the time budget or a cancel end them; host copies of the sums
 * along the way, the split rebalanced, checkpoints written. Returns 0, or
 * -1 with the reason in `error`. */
static int render_passes(Render *r, double *weights, RenderOutput *out, char *error, size_t error_size)
{
    const RenderSettings *s = r->settings;
    /* The first pass renders one sample per pixel, later ones as many as
     * fit the pass length, judged from the slowest device's speed. */
    const double target = s->seconds_per_pass > 0.0 ? s->seconds_per_pass : 0.5;
    const double start = r->start = now_seconds();
    uint64_t done_samples = 0;
    uint32_t per_pass = 1;
    int pass_number = 0, stop = 0;
    r->saved_at = start;
    while (live_workers(r) > 0) {
        if (done_samples >= s->sample_count || stop) {
            if (save_state(r, done_samples) == 0)
                break;
            /* A device failed while its sums were read. */
            if (roll_back(r, weights, &done_samples, error, error_size))
                return -1;
            continue;
        }
        if (s->cancel && *s->cancel) {
            stop = 1;
            continue;
        }
        uint64_t remaining = s->sample_count - done_samples;
        uint32_t count = remaining < per_pass ? (uint32_t)remaining : per_pass;
        if (s->checkpoint) { /* end the pass at the next power of two */
            uint64_t next = 1;
            while (next <= done_samples)
                next *= 2;
            if (next - done_samples < count)
                count = (uint32_t)(next - done_samples);
        }
        int failures = run_pass(r, s->first_sample + done_samples, count, ++pass_number);
        if (failures > 0) {
            if (roll_back(r, weights, &done_samples, error, error_size))
                return -1;
            per_pass = 1;
            continue;
        }
        done_samples += count;
        double elapsed = now_seconds() - start - r->callback_seconds;
        if (s->progress)
            s->progress(s->progress_user, done_samples, s->sample_count, elapsed);
        if (s->time_budget > 0.0 && elapsed >= s->time_budget)
            stop = 1;

        /* Speeds, the slowest device's time a sample, and whether the split
         * should change (as Cycles' work balancer: when the slowest device
         * takes 10% longer than the fastest). */
        double slowest = 0.0, fastest = 0.0;
        int live = 0;
        for (int i = 0; i < r->worker_count; ++i) {
            Worker *w = &r->workers[i];
            if (!w->live)
                continue;
            double seconds = w->pass_seconds > 1e-9 ? w->pass_seconds : 1e-9;
            weights[i] = (double)w->count / seconds;
            slowest = live == 0 || seconds > slowest ? seconds : slowest;
            fastest = live == 0 || seconds < fastest ? seconds : fastest;
            ++live;
        }
        int rebalance = live > 1 && slowest > 1.1 * fastest && !stop && done_samples < s->sample_count;
        /* A host copy of the sums whenever it costs under 5% of the time
         * since the last one, so that a failure loses little. */
        int save_due = now_seconds() - r->saved_at >= 20.0 * r->save_seconds;
        if ((rebalance || save_due) && done_samples < s->sample_count && !stop) {
            if (save_state(r, done_samples) != 0 ||
                (rebalance && (++out->rebalances, assign_pixels(r, weights, 0, error, error_size) != 0))) {
                if (roll_back(r, weights, &done_samples, error, error_size))
                    return -1;
                per_pass = 1;
                continue;
            }
        }
        if (s->checkpoint && (is_power_of_two(done_samples) || done_samples == s->sample_count)) {
            if (estimate_on_devices(r, done_samples, out) != 0) {
                if (roll_back(r, weights, &done_samples, error, error_size))
                    return -1;
                continue;
            }
            double callback_start = now_seconds();
            out->sample_count = done_samples;
            out->seconds = callback_start - start - r->callback_seconds;
            int refused = s->checkpoint(s->checkpoint_user, out);
            r->callback_seconds += now_seconds() - callback_start;
            if (refused) {
                snprintf(error, error_size, "writing the checkpoint at %llu samples failed",
                         (unsigned long long)done_samples);
                return -1;
            }
        }
        double per_sample = slowest / count;
        double budget_left = s->time_budget > 0.0 ? s->time_budget - elapsed : target;
        double fit = (budget_left < target ? budget_left : target) / (per_sample > 0.0 ? per_sample : 1e-9);
        per_pass = fit < 1.0 ? 1u : (fit > 4096.0 ? 4096u : (uint32_t)fit);
        /* Splat records are held on the host for a pass: at most about
         * SPLATS_PER_PASS, judged from this pass's records a sample. */
        if (r->splats && r->splat_count > 0) {
            double records = (double)r->splat_count / ((double)count * (double)r->pixels);
            double most = SPLATS_PER_PASS / (records * (double)r->pixels);
            per_pass = most < 1.0 ? 1u : (most < per_pass ? (uint32_t)most : per_pass);
        }
    }

    return 0;
}

/* Step 4: the image from the saved state, estimated on the devices (or on
 * the host when none is left), and the sums and counters handed to the
 * output. Returns RENDER_OK, RENDER_INCOMPLETE (every device failed; the
 * host estimated), RENDER_FAILED with the reason in `error`, or -2 out of
 * host memory. */
static int finish_render(Render *r, RenderOutput *out, char *error, size_t error_size)
{
    /* The image: the saved state, estimated on the devices (or on the host
     * when none is left). */
    out->sample_count = r->saved_samples;
    int complete = live_workers(r) > 0;
    if (complete && estimate_on_devices(r, r->saved_samples, out) != 0)
        complete = 0;
    if (!complete && r->saved_lost) {
        snprintf(error, error_size,
                 "the only device failed while its sums were copied to the host: no consistent copy of them is left");
        return RENDER_FAILED;
    }
    if (!complete && estimate_on_host(r, r->saved_samples, out) != 0)
        return -2;
    out->seconds = now_seconds() - r->start - r->callback_seconds;
    /* The sums in their canonical form: the same bits for the same sums,
     * whatever the devices, passes and pixel moves that built them. */
    for (size_t p = 0; p < r->pixels; ++p)
        accumulators_normalize(r->saved.accumulators, p, r->pixels, (uint32_t)r->sets);
    out->accumulators = r->saved.accumulators;
    out->rejected = r->saved.rejected;
    for (size_t i = 0; i < r->pixels; ++i) {
        out->rays += r->saved.rays[i];
        out->rejected_total += r->saved.rejected[i];
        out->rounded_total += r->saved.rejected[r->pixels + i];
        out->rounded_pixels += r->saved.rejected[r->pixels + i] != 0;
    }
    out->bytes_per_pixel = pixel_state_bytes(r);
    out->sample_bytes_per_pixel = r->sample_planes * sizeof(uint64_t);
    r->saved.accumulators = NULL;
    r->saved.rejected = NULL;
    if (complete)
        return RENDER_OK;
    size_t used = (size_t)snprintf(error, error_size, "every device failed:");
    for (int i = 0; i < r->worker_count && used < error_size; ++i)
        used += (size_t)snprintf(error + used, error_size - used, " '%s': %s;", out->devices[i].name,
                                 out->devices[i].error);
    return RENDER_INCOMPLETE;
}

RenderStatus renderer_run(ClDevice *devices, int device_count, const RenderScene *scene, const RenderSettings *s,
                          RenderOutput *out, char *error, size_t error_size)
{
    memset(out, 0, sizeof *out);
    if (estimator_settings_check(&s->estimator, error, error_size) != 0)
        return RENDER_FAILED;
    if (device_count < 1 || device_count > RENDER_MAX_DEVICES) {
        snprintf(error, error_size, "%d devices given, 1..%d supported", device_count, RENDER_MAX_DEVICES);
        return RENDER_FAILED;
    }
    Render r;
    memset(&r, 0, sizeof r);
    double weights[RENDER_MAX_DEVICES];
    int status = plan_render(&r, device_count, scene, s, out, error, error_size);
    if (status == 0)
        status = start_devices(&r, devices, out, weights, error, error_size);
    if (status == 0)
        status = render_passes(&r, weights, out, error, error_size);
    status = status == 0 ? finish_render(&r, out, error, error_size) : status == -2 ? -2 : RENDER_FAILED;
    if (status == -2) {
        snprintf(error, error_size, "out of memory for a %ux%u image with M = %d", out->width, out->height, r.sets);
        status = RENDER_FAILED;
    }
    for (int i = 0; i < r.worker_count; ++i)
        release_worker(&r.workers[i]);
    free_state(&r.saved);
    free_state(&r.scratch);
    free(r.splat_records);
    free(r.splat_sorted);
    free(r.splat_offsets);
    if (status == RENDER_FAILED)
        render_output_free(out);
    return (RenderStatus)status;
}
