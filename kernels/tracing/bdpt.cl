/* The integrators with light subpaths: pbrt-v4's light tracer
 * ("lightpath", RENDER_LIGHTPATH: light subpaths connected to the camera)
 * and bidirectional path tracer ("bdpt", RENDER_BDPT). Built only for
 * renders that ask for them; the path tracer (path_tracer.cl) knows
 * nothing of them.
 *
 * Every sample (pixel, sample index) traces one light subpath. Its
 * connections to the camera land on other pixels: splat_samples writes
 * them as records (kernels/film/splats.h) of the sample's set (sample index
 * mod M), and add_splats adds the records, put in pixel order by the host,
 * into each pixel's exact set sums. render_samples adds the strategies
 * that land on the sample's own pixel (bdpt's camera subpaths).
 *
 * Build options: as the path tracer's (-DEST_SETS=M, -DGMON_FEATURES,
 * -DGMON_SAMPLER, -DGMON_SAMPLER_SETS, -DBVH_STACK_SIZE) and
 * -DBDPT_MAX_DEPTH (maxdepth: the subpaths' private arrays), and the
 * per-sample estimators clamp and zirr (-DEST_SAMPLE_PASSES and theirs):
 * a splat updates its pixel's per-sample state as a sample of value its
 * RGB and weight 1 would (the host refuses the others: a splat is not a
 * sample of the pixel, so the per-sample moments are undefined, and bdpt's
 * strategies do not keep direct light apart for clamp-sum). */
#include "../film/accumulate.h"
#include "../film/splats.h"
#include "bdpt.h"

#ifdef EST_SAMPLE_PASSES
#include "../film/sample_passes.h"
#define SAMPLE_PASSES EST_SAMPLE_PASSES
#else
#define SAMPLE_PASSES 0u
#endif
#ifndef EST_CLAMP_LEVEL_COUNT
#define EST_CLAMP_LEVEL_COUNT 0
#endif
#ifndef EST_ZIRR_COUNT
#define EST_ZIRR_COUNT 2
#define EST_ZIRR_BASE 8.0f
#endif

#if SAMPLE_PASSES
/* Adds one value to the per-sample state of `pixel`: a camera sample's
 * film response (times its filter weight in the sets) or a splat's RGB,
 * both as splat_sample_parts makes them (no direct part). */
KERNEL_FN void bdpt_sample_passes_add(__global ulong *sample_state, ulong pixel, ulong pixel_count,
                                      const SampleParts *sample)
{
#if EST_CLAMP_LEVEL_COUNT > 0
    const float levels[EST_CLAMP_LEVEL_COUNT] = {EST_CLAMP_LEVEL_VALUES};
#else
    const float levels[1] = {0.0f};
#endif
    sample_passes_add(sample_state, pixel, pixel_count, SAMPLE_PASSES, EST_CLAMP_LEVEL_COUNT, levels, 0.0f, 0.0f,
                      EST_ZIRR_COUNT, EST_ZIRR_BASE, sample);
}
#endif

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif
#ifndef GMON_SAMPLER
#define GMON_SAMPLER SAMPLER_INDEPENDENT
#endif
#ifndef GMON_SAMPLER_SETS
#define GMON_SAMPLER_SETS EST_SETS
#endif

/* Where splat records go: a buffer of `capacity` records and the count of
 * records made (past the capacity too: the host then runs the launch again
 * in smaller parts, so none is lost). */
typedef struct {
    __global SplatRecord *records;
    __global uint *count;
    uint capacity;
    uint set;
} SplatTarget;

KERNEL_FN void splat_record(const SplatTarget *target, uint pixel, Vec3 value)
{
    uint index = atomic_inc(target->count);
    if (index >= target->capacity)
        return;
    __global SplatRecord *r = target->records + index;
    r->pixel = pixel;
    r->set = target->set;
    r->rgb[0] = value.x;
    r->rgb[1] = value.y;
    r->rgb[2] = value.z;
}

/* Splats a contribution that reached the image at (px, py) (pixels from the
 * top left) onto the pixels whose filter covers it, each by its filter's
 * value over its integral (the tabulated filter camera samples are drawn
 * from, FilterData), so that a pixel's expected splats are its filtered
 * value, as its camera samples'. */
KERNEL_FN void splat(const Scene *scene, const SplatTarget *target, float px, float py, Vec3 value)
{
    __global const CameraData *camera = &scene->constants->camera;
    __global const FilterData *filter = &scene->constants->filter;
    value = film_response(&scene->constants->film, value);
    int width = (int)camera->width, height = (int)camera->height;
    if (!(GMON_HAS_PIXEL_FILTER && filter->table_width > 0u)) {
        int x = (int)floor(px), y = (int)floor(py);
        if (x >= 0 && x < width && y >= 0 && y < height)
            splat_record(target, (uint)(y * width + x), value);
        return;
    }
    __global const float *d = scene->distributions + filter->distribution_offset;
    uint table_width = filter->table_width, table_height = filter->table_height;
    float rx = filter->radius[0], ry = filter->radius[1];
    float scale = filter->weight / (d[0] * 4.0f * rx * ry);
    int x0 = (int)ceil(px - 0.5f - rx), x1 = (int)floor(px - 0.5f + rx);
    int y0 = (int)ceil(py - 0.5f - ry), y1 = (int)floor(py - 0.5f + ry);
    for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < height; ++y)
        for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < width; ++x) {
            float dx = px - ((float)x + 0.5f), dy = py - ((float)y + 0.5f);
            int column = (int)((dx / rx + 1.0f) * 0.5f * (float)table_width);
            int row = (int)((dy / ry + 1.0f) * 0.5f * (float)table_height);
            column = column < 0 ? 0 : (column >= (int)table_width ? (int)table_width - 1 : column);
            row = row < 0 ? 0 : (row >= (int)table_height ? (int)table_height - 1 : row);
            float f = d[DISTRIBUTION_FUNCTION(table_width, table_height) + (uint)row * table_width + (uint)column];
            if (f != 0.0f)
                splat_record(target, (uint)(y * width + x), v_scale(value, f * scale));
        }
}

#ifndef BDPT_MAX_DEPTH
#error "build with -DBDPT_MAX_DEPTH=maxdepth"
#endif
#define LIGHT_VERTICES (BDPT_MAX_DEPTH + 1)
#define CAMERA_VERTICES (BDPT_MAX_DEPTH + 2)

KERNEL_FN int is_light_tracer(const Scene *scene)
{
    return (scene->constants->integrator.flags & RENDER_BDPT) == 0;
}

/* The strategies of one light subpath that end on the camera (t = 1),
 * splatted: for the light tracer every one unweighted (as pbrt-v4's
 * LightPathIntegrator: an area light's own point too, a point light
 * never), for bdpt each by its MIS weight. */
KERNEL_FN void splat_light_subpath(const Scene *scene, const SampleStream *stream, const SplatTarget *target,
                                   uint *rays)
{
    PathVertex light[LIGHT_VERTICES];
    int n = light_subpath(scene, stream, light, (int)scene->constants->integrator.max_depth + 1, rays);
    /* bdpt leaves out s = t = 1 as pbrt-v4 does: a light seen directly is
     * strategy s = 0, t = 2 alone (mis_weight gives paths of two vertices
     * weight 1). */
    for (int s = is_light_tracer(scene) ? 1 : 2; s <= n; ++s) {
        float u1, u2, px, py;
        sample_2d(stream, s == 1 ? LIGHT_DIMENSION + 5u : vertex_dimension(0, s - 1), &u1, &u2);
        PathVertex camera;
        Vec3 L = connect_to_camera(scene, light + s - 1, u1, u2, &camera, &px, &py, rays);
        if (!(v_max_component(L) > 0.0f))
            continue;
        float weight = is_light_tracer(scene) ? 1.0f : mis_weight(scene, light, &camera, &camera, s, 1);
        splat(scene, target, px, py, v_scale(L, weight));
    }
}

/* Strategy s = 1, t >= 2: a light sampled from camera vertex pt, as the
 * path tracer's next-event estimation samples it (the light's fixed
 * chance, then its type's sampler). Returns the unweighted contribution
 * and the light's vertex in *sampled. */
KERNEL_FN Vec3 connect_to_light(const Scene *scene, const SampleStream *stream, const PathVertex *pt, int t,
                                PathVertex *sampled, uint *rays)
{
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
    __global const IntegratorData *integrator = &scene->constants->integrator;
    if (integrator->light_count == 0 || !vertex_connectible(pt))
        return zero;
    uint dim = vertex_dimension(1, t - 1) + 3u;
    float u1, u2;
    sample_2d(stream, dim + 1u, &u1, &u2);
    int index = pick_light(scene->lights, integrator->light_count, sample_1d(stream, dim));
    __global const Light *light = scene->lights + index;
    LightSample ls;
    ls.is_delta = 0;
    ls.distance = INFINITY;
    float pick = light->pick_probability;
    if (!(pick > 0.0f) || !light_sample(scene, light, pt->surface.p, u1, u2, &ls) || !(ls.pdf > 0.0f) ||
        !(ls.distance < INFINITY))
        return zero;
    sampled->type = VERTEX_LIGHT;
    sampled->surface.p = v_add(pt->surface.p, v_scale(ls.wi, ls.distance));
    sampled->surface.n =
        light->type == LIGHT_AREA ? surface_normal(scene->primitives + light->primitive, sampled->surface.p) : zero;
    sampled->surface.ns = sampled->surface.n;
    sampled->beta = v_scale(ls.radiance, 1.0f / (ls.pdf * pick));
    sampled->light = index;
    sampled->delta = 0;
    sampled->radiance = 0;
    sampled->pdf_rev = 0.0f;
    sampled->pdf_fwd = vertex_pdf_light_origin(scene, sampled);
    Vec3 L = v_scale(v_mul(v_mul(pt->beta, vertex_f(pt, sampled)), sampled->beta), fabs(v_dot(ls.wi, pt->surface.ns)));
    if (!(v_max_component(L) > 0.0f))
        return zero;
    ++*rays;
    return vertices_see(scene, pt, sampled) ? L : zero;
}

/* Strategy s >= 2, t >= 2: light vertex qs joined to camera vertex pt. */
KERNEL_FN Vec3 connect_vertices(const Scene *scene, const PathVertex *qs, const PathVertex *pt, uint *rays)
{
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
    if (!vertex_connectible(qs) || !vertex_connectible(pt))
        return zero;
    Vec3 d = v_sub(qs->surface.p, pt->surface.p);
    float distance2 = v_dot(d, d);
    if (!(distance2 > 0.0f))
        return zero;
    d = v_scale(d, 1.0f / sqrt_float(distance2));
    float g = fabs(v_dot(qs->surface.ns, d)) * fabs(v_dot(pt->surface.ns, d)) / distance2;
    Vec3 L = v_scale(v_mul(v_mul(qs->beta, vertex_f(qs, pt)), v_mul(vertex_f(pt, qs), pt->beta)), g);
    if (!(v_max_component(L) > 0.0f))
        return zero;
    ++*rays;
    return vertices_see(scene, qs, pt) ? L : zero;
}

/* The strategies of one sample that land on its own pixel (t >= 2), each
 * by its MIS weight; the camera ray from `ray`. */
KERNEL_FN Vec3 bdpt_camera_strategies(const Scene *scene, const SampleStream *stream, const SampleStream *light_stream,
                                      const CameraRay *ray, uint *rays)
{
    __global const IntegratorData *integrator = &scene->constants->integrator;
    int max_depth = (int)integrator->max_depth;
    PathVertex camera[CAMERA_VERTICES], light[LIGHT_VERTICES];
    PathVertex *c0 = camera;
    c0->type = VERTEX_CAMERA;
    c0->surface.p = ray->origin;
    c0->surface.n = c0->surface.ns = vec3(0.0f, 0.0f, 0.0f);
    c0->beta = vec3(1.0f, 1.0f, 1.0f);
    c0->pdf_fwd = c0->pdf_rev = 0.0f;
    c0->delta = 0;
    c0->light = -1;
    c0->radiance = 1;
    int camera_count = random_walk(scene, stream, camera, 1, max_depth + 2, ray->origin, ray->direction, c0->beta,
                                   camera_pdf_direction(&scene->constants->camera, ray->direction), 1, rays);
    int light_count = light_subpath(scene, light_stream, light, max_depth + 1, rays);
    Vec3 L = vec3(0.0f, 0.0f, 0.0f);
    for (int t = 2; t <= camera_count; ++t)
        for (int s = 0; s <= light_count && s + t - 2 <= max_depth; ++s) {
            PathVertex *pt = camera + t - 1, sampled;
            Vec3 c;
            if (s == 0) {
                if (pt->light < 0)
                    continue;
                c = v_mul(vertex_le(scene, pt, pt->wo), pt->beta);
            } else if (s == 1) {
                c = connect_to_light(scene, stream, pt, t, &sampled, rays);
            } else {
                c = connect_vertices(scene, light + s - 1, pt, rays);
            }
            if (v_max_component(c) > 0.0f)
                L = v_add(L, v_scale(c, mis_weight(scene, light, camera, &sampled, s, t)));
        }
    return L;
}

/* Renders samples [first_sample, first_sample + sample_count) of pixels
 * [first_pixel, first_pixel + pixel_count): bdpt's strategies that land
 * on the sample's pixel (none for the light tracer), added to its set as
 * the path tracer adds samples (its arguments). */
__kernel void render_samples(__global const SceneConstants *constants,
                             GMON_SCENE_ARRAYS(SCENE_ARRAY_PARAMETER) __global ulong *accumulators,
                             __global uint *rejected, __global ulong *ray_counts, ulong first_sample, uint sample_count,
                             ulong first_pixel, ulong pixel_count, ulong buffer_first_pixel, ulong buffer_pixel_count
#if SAMPLE_PASSES
                             ,
                             __global ulong *sample_state
#endif
)
{
    if (get_global_id(0) >= pixel_count)
        return;
    Scene scene;
    scene.constants = constants;
    GMON_SCENE_ARRAYS(SCENE_ARRAY_ASSIGN)
    if (is_light_tracer(&scene))
        return;
    ulong pixel = first_pixel + get_global_id(0), local_pixel = pixel - buffer_first_pixel;
    uint width = constants->camera.width;
    uint x = (uint)(pixel % width), y = (uint)(pixel / width);
    uint nonfinite = 0, rounded = 0, rays = 0;
    for (uint i = 0; i < sample_count; ++i) {
        ulong sample_index = first_sample + i;
        SampleStream stream =
            sample_stream(GMON_SAMPLER, constants->integrator.seed, pixel, sample_index, GMON_SAMPLER_SETS);
        SampleStream light_stream = light_sample_stream(GMON_SAMPLER, constants->integrator.seed, pixel, sample_index,
                                                        GMON_SAMPLER_SETS, (ulong)width * constants->camera.height);
        CameraRay camera = camera_ray(&constants->camera, &constants->filter, distributions, x, y, &stream);
        Vec3 L =
            film_response(&constants->film, bdpt_camera_strategies(&scene, &stream, &light_stream, &camera, &rays));
#if SAMPLE_PASSES
        const float film[EST_CHANNELS] = {L.x, L.y, L.z};
        SampleParts sample = splat_sample_parts(film, set_of_sample(sample_index, EST_SETS), EST_SETS);
        sample.weight = GMON_HAS_PIXEL_FILTER ? camera.weight : 1.0f;
#endif
        if (GMON_HAS_PIXEL_FILTER)
            L = v_scale(L, camera.weight);
        const uint set = set_of_sample(sample_index, EST_SETS);
        int added = accumulate_sample(accumulators, local_pixel, buffer_pixel_count, EST_SETS, set, L.x, L.y, L.z);
#if SAMPLE_PASSES
        bdpt_sample_passes_add(sample_state, local_pixel, buffer_pixel_count, &sample);
#endif
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    rejected[local_pixel] += nonfinite;
    rejected[buffer_pixel_count + local_pixel] += rounded;
    ray_counts[local_pixel] += rays;
}

/* Traces the light subpaths of samples [first_sample, first_sample +
 * sample_count) of pixels [first_pixel, first_pixel + pixel_count), writing
 * their splats to `records` (room for `capacity`; *record_count counts
 * them all) and their rays to light_rays (of pixels from
 * buffer_first_pixel; set, not added, as the host may run the launch
 * again: add_splats adds them). A pure function of the samples. */
__kernel void splat_samples(__global const SceneConstants *constants,
                            GMON_SCENE_ARRAYS(SCENE_ARRAY_PARAMETER) __global SplatRecord *records,
                            __global uint *record_count, uint capacity, __global ulong *light_rays, ulong first_sample,
                            uint sample_count, ulong first_pixel, ulong pixel_count, ulong buffer_first_pixel)
{
    if (get_global_id(0) >= pixel_count)
        return;
    Scene scene;
    scene.constants = constants;
    GMON_SCENE_ARRAYS(SCENE_ARRAY_ASSIGN)
    ulong pixel = first_pixel + get_global_id(0);
    SplatTarget target = {records, record_count, capacity, 0u};
    uint rays = 0;
    for (uint i = 0; i < sample_count; ++i) {
        ulong sample_index = first_sample + i;
        SampleStream stream =
            light_sample_stream(GMON_SAMPLER, constants->integrator.seed, pixel, sample_index, GMON_SAMPLER_SETS,
                                (ulong)constants->camera.width * constants->camera.height);
        target.set = set_of_sample(sample_index, EST_SETS);
        splat_light_subpath(&scene, &stream, &target, &rays);
    }
    light_rays[pixel - buffer_first_pixel] = rays;
}

/* Adds the splat records of a slice's pixels [first_pixel, first_pixel +
 * pixel_count), whose buffers these are, into their set sums, in pixel
 * order (pixel first_pixel + i's are records[offsets[i], offsets[i + 1])):
 * one work item a pixel, as render_samples adds samples, and its light
 * subpaths' rays to its ray count. Non-finite and rounded values are
 * counted as the path tracer counts such samples. With per-sample
 * estimators (clamp, zirr) each record also updates the pixel's
 * per-sample state as a sample of value its RGB and weight 1 would: its
 * exact sums keep the order of the records out of the image too. */
__kernel void add_splats(__global ulong *accumulators, __global uint *rejected, __global ulong *ray_counts,
                         __global const ulong *light_rays, __global const SplatRecord *records,
                         __global const uint *offsets, ulong first_pixel, ulong pixel_count
#if SAMPLE_PASSES
                         ,
                         __global ulong *sample_state
#endif
)
{
    (void)first_pixel;
    if (get_global_id(0) >= pixel_count)
        return;
    ulong i = get_global_id(0);
    uint nonfinite = 0, rounded = 0;
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) {
        __global const SplatRecord *r = records + k;
        int added = accumulate_sample(accumulators, i, pixel_count, EST_SETS, r->set, r->rgb[0], r->rgb[1], r->rgb[2]);
#if SAMPLE_PASSES
        const float rgb[EST_CHANNELS] = {r->rgb[0], r->rgb[1], r->rgb[2]};
        const SampleParts sample = splat_sample_parts(rgb, r->set, EST_SETS);
        bdpt_sample_passes_add(sample_state, i, pixel_count, &sample);
#endif
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    rejected[i] += nonfinite;
    rejected[pixel_count + i] += rounded;
    ray_counts[i] += light_rays[i];
}
