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
 * -DGMON_SAMPLER, -DGMON_SAMPLER_SETS, -DBVH_STACK_SIZE); no per-sample
 * estimators. */
#include "../film/accumulate.h"
#include "../film/splats.h"
#include "bsdf.h"
#include "camera.h"
#include "lights.h"
#include "scene.h"
#include "surface.h"

#ifndef EST_SETS
#error "build with -DEST_SETS=M"
#endif
#ifndef GMON_SAMPLER
#define GMON_SAMPLER SAMPLER_INDEPENDENT
#endif
#ifndef GMON_SAMPLER_SETS
#define GMON_SAMPLER_SETS EST_SETS
#endif

/* Random dimensions of a light subpath, apart from the camera path's
 * (which start at 0): the light's pick, the ray's origin (2D) and direction
 * (2D), the lens point of the light's own connection to the camera (2D),
 * then LIGHT_DIMS_PER_VERTEX a vertex: the lens point of its
 * connection to the camera (2D), the BSDF's lobe and direction (2D). */
#define LIGHT_DIMENSION 0x40000000u
#define LIGHT_DIMS_START 7u
#define LIGHT_DIMS_PER_VERTEX 5u

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

/* Whether the segment from p (normal n; 0 for a point light's position)
 * to the lens point of c is unoccluded. */
KERNEL_FN int sees_camera(const Scene *scene, Vec3 p, Vec3 n, const CameraConnection *c, uint *rays)
{
    ++*rays;
    Vec3 origin = v_dot(n, n) > 0.0f ? offset_origin(p, n, c->wi) : p;
    Vec3 to_lens = v_sub(c->lens_point, origin);
    float distance = v_length(to_lens);
    if (!(distance > 0.0f))
        return 0;
    return !occluded(scene, origin, v_scale(to_lens, 1.0f / distance), distance * (1.0f - 1e-4f));
}

/* The light tracer's subpath (pbrt-v4's LightPathIntegrator): a ray
 * leaving a light picked by its fixed chance, each non-specular vertex
 * connected to the camera, up to max_depth bounces, no Russian roulette;
 * an area light's own point connected too (a point light is never seen). */
KERNEL_FN void trace_light_path(const Scene *scene, const SampleStream *stream, const SplatTarget *target, uint *rays)
{
    __global const IntegratorData *integrator = &scene->constants->integrator;
    __global const CameraData *camera = &scene->constants->camera;
    __global const FilterData *filter = &scene->constants->filter;
    if (integrator->light_count == 0)
        return;
    int index = pick_light(scene->lights, integrator->light_count, sample_1d(stream, LIGHT_DIMENSION));
    __global const Light *light = scene->lights + index;
    float pick = light->pick_probability, u1, u2, u3, u4;
    sample_2d(stream, LIGHT_DIMENSION + 1u, &u1, &u2);
    sample_2d(stream, LIGHT_DIMENSION + 3u, &u3, &u4);
    LightEmission e;
    if (!(pick > 0.0f) || !light_sample_emission(scene, light, u1, u2, u3, u4, &e))
        return;
    CameraConnection c;
    sample_2d(stream, LIGHT_DIMENSION + 5u, &u1, &u2);
    if (!e.delta_position && camera_connect(camera, filter, e.origin, u1, u2, &c)) {
        float cos_light = v_dot(e.normal, c.wi);
        if ((light->two_sided || cos_light > 0.0f) && sees_camera(scene, e.origin, e.normal, &c, rays))
            splat(scene, target, c.px, c.py,
                  v_scale(e.radiance, fabs(cos_light) * c.importance / (pick * e.pdf_position * c.pdf)));
    }
    float cos_out = e.delta_position ? 1.0f : fabs(v_dot(e.normal, e.direction));
    Vec3 beta = v_scale(e.radiance, cos_out / (pick * e.pdf_position * e.pdf_direction));
    Vec3 origin = e.delta_position ? e.origin : offset_origin(e.origin, e.normal, e.direction);
    Vec3 direction = e.direction;
    for (uint depth = 0; depth < integrator->max_depth; ++depth) {
        Ray ray = make_ray(origin, direction);
        Hit hit;
        ++*rays;
        if (!scene_intersect(scene, &ray, 0.0f, INFINITY, 0, &hit))
            break;
        Surface surface;
        surface_at_hit(scene, &hit, origin, direction, 0.0f, &surface);
        Vec3 wo_world = v_scale(direction, -1.0f), wo = surface_to_local(&surface, wo_world);
        uint dim = LIGHT_DIMENSION + LIGHT_DIMS_START + depth * LIGHT_DIMS_PER_VERTEX;
        if (!bsdf_is_delta(&surface.material)) {
            sample_2d(stream, dim, &u1, &u2);
            if (camera_connect(camera, filter, surface.p, u1, u2, &c)) {
                float pdf;
                Vec3 f = bsdf_eval_transport(&surface.material, wo, surface_to_local(&surface, c.wi), &pdf, 0);
                float factor = fabs(v_dot(c.wi, surface.ns)) * shading_correction(&surface, wo_world, c.wi, 0) *
                               c.importance / c.pdf;
                if (v_max_component(f) > 0.0f && factor > 0.0f && sees_camera(scene, surface.p, surface.n, &c, rays))
                    splat(scene, target, c.px, c.py, v_scale(v_mul(beta, f), factor));
            }
        }
        BsdfSample bs;
        sample_2d(stream, dim + 3u, &u1, &u2);
        if (!bsdf_sample_transport(&surface.material, wo, sample_1d(stream, dim + 2u), u1, u2, &bs, 0))
            break;
        Vec3 wi_world = surface_to_world(&surface, bs.wi);
        beta = v_mul(beta, v_scale(bs.f, fabs(bs.wi.z) * shading_correction(&surface, wo_world, wi_world, 0) / bs.pdf));
        direction = wi_world;
        origin = offset_origin(surface.p, surface.n, direction);
    }
}

/* The strategies that land on the sample's own pixel: none for the light
 * tracer. */
__kernel void render_samples(__global const SceneConstants *constants,
                             GMON_SCENE_ARRAYS(SCENE_ARRAY_PARAMETER) __global ulong *accumulators,
                             __global uint *rejected, __global ulong *ray_counts, ulong first_sample, uint sample_count,
                             ulong first_pixel, ulong pixel_count, ulong buffer_first_pixel, ulong buffer_pixel_count)
{
    (void)constants, (void)accumulators, (void)rejected, (void)ray_counts, (void)first_sample, (void)sample_count;
    (void)first_pixel, (void)pixel_count, (void)buffer_first_pixel, (void)buffer_pixel_count;
#define SCENE_ARRAY_UNUSED(name, type) (void)name;
    GMON_SCENE_ARRAYS(SCENE_ARRAY_UNUSED)
#undef SCENE_ARRAY_UNUSED
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
            sample_stream(GMON_SAMPLER, constants->integrator.seed, pixel, sample_index, GMON_SAMPLER_SETS);
        target.set = set_of_sample(sample_index, EST_SETS);
        trace_light_path(&scene, &stream, &target, &rays);
    }
    light_rays[pixel - buffer_first_pixel] = rays;
}

/* Adds the splat records of a slice's pixels [first_pixel, first_pixel +
 * pixel_count), whose buffers these are, into their set sums, in pixel
 * order (pixel first_pixel + i's are records[offsets[i], offsets[i + 1])):
 * one work item a pixel, as render_samples adds samples, and its light
 * subpaths' rays to its ray count. Non-finite and rounded values are
 * counted as the path tracer counts such samples. */
__kernel void add_splats(__global ulong *accumulators, __global uint *rejected, __global ulong *ray_counts,
                         __global const ulong *light_rays, __global const SplatRecord *records,
                         __global const uint *offsets, ulong first_pixel, ulong pixel_count)
{
    (void)first_pixel;
    if (get_global_id(0) >= pixel_count)
        return;
    ulong i = get_global_id(0);
    uint nonfinite = 0, rounded = 0;
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) {
        __global const SplatRecord *r = records + k;
        int added = accumulate_sample(accumulators, i, pixel_count, EST_SETS, r->set, r->rgb[0], r->rgb[1], r->rgb[2]);
        nonfinite += added == EST_ADD_NONFINITE;
        rounded += added == EST_ADD_ROUNDED;
    }
    rejected[i] += nonfinite;
    rejected[pixel_count + i] += rounded;
    ray_counts[i] += light_rays[i];
}
