#include "render/render_scene.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void render_scene_init(RenderScene *scene)
{
    memset(scene, 0, sizeof *scene);
    scene->constants.integrator.max_depth = 5;
    scene->constants.integrator.flags = RENDER_NEE;
    for (int i = 0; i < 3; ++i)
        scene->constants.film.from_radiance[i][i] = 1.0f;
    scene->constants.film.max_component_value = INFINITY;
}

void render_scene_destroy(RenderScene *scene)
{
    free(scene->materials);
    free(scene->primitives);
    free(scene->lights);
    free(scene->distributions);
    free(scene->texels);
    free(scene->vertex_normals);
    free(scene->shading_normals);
    free(scene->textures);
    free(scene->material_textures);
    free(scene->texture_bytes);
    free(scene->texture_floats);
    free(scene->vertex_uvs);
    free(scene->surface_uvs);
    bvh_destroy(&scene->bvh);
    memset(scene, 0, sizeof *scene);
}

RenderSceneArrays render_scene_arrays(const RenderScene *scene)
{
    RenderSceneArrays a;
    a.nodes = scene->bvh.nodes;
    a.nodes_count = (size_t)scene->bvh.node_count;
    a.primitives = scene->bvh.primitives;
    a.primitives_count = (size_t)scene->bvh.primitive_count;
    a.materials = scene->materials;
    a.materials_count = (size_t)scene->material_count;
    a.lights = scene->lights;
    a.lights_count = (size_t)scene->light_count;
    a.distributions = scene->distributions;
    a.distributions_count = scene->distribution_count;
    a.texels = scene->texels;
    a.texels_count = scene->texel_count;
    a.shading_normals = scene->shading_normals;
    a.shading_normals_count = scene->shading_normals ? 9 * (size_t)scene->bvh.primitive_count : 0;
    a.textures = scene->textures;
    a.textures_count = (size_t)scene->texture_count;
    a.material_textures = scene->material_textures;
    a.material_textures_count = (size_t)scene->material_texture_count;
    a.texture_bytes = scene->texture_bytes;
    a.texture_bytes_count = scene->texture_byte_count;
    a.texture_floats = scene->texture_floats;
    a.texture_floats_count = scene->texture_float_count;
    a.surface_uvs = scene->surface_uvs;
    a.surface_uvs_count = scene->surface_uvs ? SURFACE_UV_FLOATS * (size_t)scene->bvh.primitive_count : 0;
    return a;
}

/* Grows *array (of `size`-byte items) to hold one more; 0 on success. */
static int reserve_one(void **array, int count, int *capacity, size_t size)
{
    if (count < *capacity)
        return 0;
    int grown = *capacity ? 2 * *capacity : 16;
    void *p = realloc(*array, (size_t)grown * size);
    if (!p)
        return -1;
    *array = p;
    *capacity = grown;
    return 0;
}

int render_scene_add_material(RenderScene *scene, const Material *material)
{
    if (reserve_one((void **)&scene->materials, scene->material_count, &scene->material_capacity,
                    sizeof *scene->materials))
        return -1;
    scene->materials[scene->material_count] = *material;
    return scene->material_count++;
}

static int add_primitive(RenderScene *scene, const Primitive *p, const float *emission, int two_sided, float area)
{
    if (reserve_one((void **)&scene->primitives, scene->primitive_count, &scene->primitive_capacity,
                    sizeof *scene->primitives))
        return -1;
    Primitive *added = &scene->primitives[scene->primitive_count];
    *added = *p;
    added->light = -1;
    if (emission && (emission[0] > 0.0f || emission[1] > 0.0f || emission[2] > 0.0f)) {
        Light light;
        memset(&light, 0, sizeof light);
        light.type = LIGHT_AREA;
        memcpy(light.radiance, emission, sizeof light.radiance);
        light.primitive = scene->primitive_count; /* remapped after the BVH build */
        light.area = area;
        light.two_sided = two_sided ? 1u : 0u;
        if (render_scene_add_light(scene, &light))
            return -1;
        added->light = scene->light_count - 1;
    }
    scene->primitive_count++;
    return 0;
}

int render_scene_add_triangle(RenderScene *scene, const float a[3], const float b[3], const float c[3], int material,
                              const float *emission, int two_sided, int flip_normal)
{
    Primitive p;
    memset(&p, 0, sizeof p);
    memcpy(p.a, a, sizeof p.a);
    for (int i = 0; i < 3; ++i) {
        p.b[i] = b[i] - a[i];
        p.c[i] = c[i] - a[i];
    }
    p.kind = PRIM_TRIANGLE | (flip_normal ? PRIM_FLIP_NORMAL : 0u);
    p.material = material;
    double e1[3], e2[3];
    for (int i = 0; i < 3; ++i) {
        e1[i] = (double)b[i] - a[i];
        e2[i] = (double)c[i] - a[i];
    }
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    float area = (float)(0.5 * sqrt(cx * cx + cy * cy + cz * cz));
    return add_primitive(scene, &p, emission, two_sided, area);
}

int render_scene_add_sphere(RenderScene *scene, const float centre[3], float radius, int material,
                            const float *emission, int two_sided, int flip_normal)
{
    Primitive p;
    memset(&p, 0, sizeof p);
    memcpy(p.a, centre, sizeof p.a);
    p.b[0] = radius;
    p.kind = PRIM_SPHERE | (flip_normal ? PRIM_FLIP_NORMAL : 0u);
    p.material = material;
    return add_primitive(scene, &p, emission, two_sided, (float)(4.0 * 3.14159265358979323846 * radius * radius));
}

int render_scene_set_vertex_normals(RenderScene *scene, const float na[3], const float nb[3], const float nc[3])
{
    int last = scene->primitive_count - 1;
    if ((size_t)scene->primitive_capacity > scene->vertex_normal_capacity) {
        size_t capacity = (size_t)scene->primitive_capacity;
        float *grown = realloc(scene->vertex_normals, capacity * 9 * sizeof *grown);
        if (!grown)
            return -1;
        memset(grown + 9 * scene->vertex_normal_capacity, 0,
               (capacity - scene->vertex_normal_capacity) * 9 * sizeof *grown);
        scene->vertex_normals = grown;
        scene->vertex_normal_capacity = capacity;
    }
    float *v = scene->vertex_normals + 9 * (size_t)last;
    memcpy(v, na, 3 * sizeof *v);
    memcpy(v + 3, nb, 3 * sizeof *v);
    memcpy(v + 6, nc, 3 * sizeof *v);
    scene->primitives[last].kind |= PRIM_SHADING_NORMAL;
    return 0;
}

int render_scene_add_light(RenderScene *scene, const Light *light)
{
    if (reserve_one((void **)&scene->lights, scene->light_count, &scene->light_capacity, sizeof *scene->lights))
        return -1;
    scene->lights[scene->light_count++] = *light;
    return 0;
}

int render_scene_add_infinite_light(RenderScene *scene, const float radiance[3])
{
    Light light;
    memset(&light, 0, sizeof light);
    light.type = LIGHT_UNIFORM_INFINITE;
    light.primitive = -1;
    memcpy(light.radiance, radiance, sizeof light.radiance);
    return render_scene_add_light(scene, &light);
}

/* Grows a float array by `more` values; returns where they start, or NULL. */
static float *grow_floats(float **array, size_t *count, size_t *capacity, size_t more)
{
    if (more > SIZE_MAX / sizeof(float) - *count)
        return NULL;
    if (*count + more > *capacity) {
        size_t grown = *capacity * 2 > *count + more ? *capacity * 2 : *count + more;
        float *p = realloc(*array, grown * sizeof(float));
        if (!p)
            return NULL;
        *array = p;
        *capacity = grown;
    }
    float *start = *array + *count;
    *count += more;
    return start;
}

/* Writes a CDF of n values f (n + 1 entries, 0 to 1); uniform when f sums to 0. */
static double write_cdf(const double *f, size_t n, float *cdf)
{
    double total = 0.0;
    for (size_t i = 0; i < n; ++i)
        total += f[i];
    double running = 0.0;
    cdf[0] = 0.0f;
    for (size_t i = 0; i < n; ++i) {
        running += total > 0.0 ? f[i] / total : 1.0 / (double)n;
        cdf[i + 1] = (float)running;
    }
    cdf[n] = 1.0f;
    return total;
}

/* Appends a 2D distribution over the width x height values f (row by row),
 * sampled in proportion to |f|, in scene_types.h's layout: the mean of |f|,
 * the marginal CDF of the rows, each row's CDF, then f itself. Writes
 * where it starts. Returns 0, or -1 when out of memory. */
static int add_distribution(RenderScene *scene, const double *f, uint32_t width, uint32_t height, uint32_t *offset)
{
    size_t n = (size_t)width * height;
    size_t size = DISTRIBUTION_FUNCTION((size_t)width, (size_t)height) + n;
    if (scene->distribution_count + size > UINT32_MAX)
        return -1;
    *offset = (uint32_t)scene->distribution_count;
    double *magnitude = malloc(n * sizeof *magnitude);
    double *rows = magnitude ? malloc(height * sizeof *rows) : NULL;
    float *d = rows
                   ? grow_floats(&scene->distributions, &scene->distribution_count, &scene->distribution_capacity, size)
                   : NULL;
    if (!d) {
        free(magnitude);
        free(rows);
        return -1;
    }
    float *function = d + DISTRIBUTION_FUNCTION((size_t)width, (size_t)height);
    for (size_t i = 0; i < n; ++i) {
        magnitude[i] = fabs(f[i]);
        function[i] = (float)f[i];
    }
    for (uint32_t y = 0; y < height; ++y)
        rows[y] = write_cdf(magnitude + (size_t)y * width, width, d + 1 + (height + 1u) + (size_t)y * (width + 1u));
    double total = write_cdf(rows, height, d + 1);
    d[0] = (float)(total / (double)n);
    free(magnitude);
    free(rows);
    return 0;
}

int render_scene_add_image_light(RenderScene *scene, const Light *light, uint32_t width, uint32_t height,
                                 const float *rgb, char *error, size_t error_size)
{
    /* Goniometric and projection lights are delta lights: never sampled by
     * their image, so they need no distribution. */
    int infinite = light->type != LIGHT_GONIOMETRIC && light->type != LIGHT_PROJECTION;
    size_t texels = (size_t)width * height;
    size_t distribution = infinite ? DISTRIBUTION_FUNCTION((size_t)width, (size_t)height) + texels : 0;
    if (width == 0 || height == 0 || scene->texel_count + 3 * texels > UINT32_MAX ||
        scene->distribution_count + distribution > UINT32_MAX) {
        snprintf(error, error_size, "a light image of %ux%u texels is too large", width, height);
        return -1;
    }
    Light added = *light;
    added.type = infinite ? LIGHT_IMAGE_INFINITE : light->type;
    added.primitive = -1;
    added.image_width = width;
    added.image_height = height;
    added.image_offset = (uint32_t)scene->texel_count;
    added.distribution_offset = (uint32_t)scene->distribution_count;
    float *t = grow_floats(&scene->texels, &scene->texel_count, &scene->texel_capacity, 3 * texels);
    double *f = t && infinite ? malloc(texels * sizeof *f) : NULL;
    for (size_t i = 0; f && i < texels; ++i)
        f[i] = ((double)rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]) / 3.0; /* the channel average */
    int failed = !t || (infinite && (!f || add_distribution(scene, f, width, height, &added.distribution_offset))) ||
                 render_scene_add_light(scene, &added);
    free(f);
    if (failed) {
        snprintf(error, error_size, "out of memory for a light image of %ux%u texels", width, height);
        return -1;
    }
    memcpy(t, rgb, 3 * texels * sizeof *t);
    return 0;
}

RenderCamera render_camera_pinhole(const float position[3], const float forward[3], const float right[3],
                                   const float up[3], float tan_half_fov_x, float tan_half_fov_y, unsigned width,
                                   unsigned height)
{
    RenderCamera c;
    memset(&c, 0, sizeof c);
    c.projection = CAMERA_PERSPECTIVE;
    memcpy(c.position, position, sizeof c.position);
    memcpy(c.forward, forward, sizeof c.forward);
    memcpy(c.right, right, sizeof c.right);
    memcpy(c.up, up, sizeof c.up);
    c.window[0] = -tan_half_fov_x;
    c.window[1] = tan_half_fov_x;
    c.window[2] = -tan_half_fov_y;
    c.window[3] = tan_half_fov_y;
    c.width = width;
    c.height = height;
    return c;
}

void render_scene_set_camera(RenderScene *scene, const RenderCamera *camera)
{
    CameraData *p = &scene->constants.camera;
    memset(p, 0, sizeof *p);
    const float *w = camera->window;
    float centre[2] = {(w[0] + w[1]) / 2.0f, (w[2] + w[3]) / 2.0f},
          half[2] = {(w[1] - w[0]) / 2.0f, (w[3] - w[2]) / 2.0f};
    int orthographic = camera->projection == CAMERA_ORTHOGRAPHIC;
    for (int i = 0; i < 3; ++i) {
        p->position[i] = camera->position[i];
        p->forward[i] = camera->forward[i];
        p->right[i] = camera->right[i] * half[0];
        p->up[i] = camera->up[i] * half[1];
        p->lens_right[i] = camera->right[i] * camera->lens_radius;
        p->lens_up[i] = camera->up[i] * camera->lens_radius;
    }
    /* An off-centre window moves the ray through the image's centre (the
     * orthographic camera's origin, the perspective one's direction). Only
     * then: adding zeros could turn a -0 of forward into +0. */
    if (centre[0] != 0.0f || centre[1] != 0.0f) {
        float *moved = orthographic ? p->position : p->forward;
        for (int i = 0; i < 3; ++i)
            moved[i] += camera->right[i] * centre[0] + camera->up[i] * centre[1];
    }
    p->projection = orthographic ? CAMERA_ORTHOGRAPHIC : CAMERA_PERSPECTIVE;
    p->lens_radius = camera->lens_radius;
    p->focal_distance = camera->focal_distance;
    p->width = camera->width;
    p->height = camera->height;
}

int render_scene_set_filter(RenderScene *scene, const PixelFilter *filter, char *error, size_t error_size)
{
    FilterData *data = &scene->constants.filter;
    memset(data, 0, sizeof *data);
    for (int a = 0; a < 2; ++a)
        if (!(filter->radius[a] > 0.0f && filter->radius[a] <= PIXEL_FILTER_MAX_RADIUS)) {
            snprintf(error, error_size, "the pixel filter's radius %g is not in (0, %g]", (double)filter->radius[a],
                     (double)PIXEL_FILTER_MAX_RADIUS);
            return -1;
        }
    if (filter->type == PIXEL_FILTER_BOX && filter->radius[0] == 0.5f && filter->radius[1] == 0.5f)
        return 0;
    uint32_t size[2];
    pixel_filter_table_size(filter, size);
    size_t n = (size_t)size[0] * size[1];
    double *f = malloc(n * sizeof *f), sum = 0.0, sum_magnitude = 0.0;
    if (!f) {
        snprintf(error, error_size, "out of memory for the pixel filter");
        return -1;
    }
    /* The filter at the centres of the cells over [-radius, radius]^2. */
    for (uint32_t y = 0; y < size[1]; ++y)
        for (uint32_t x = 0; x < size[0]; ++x) {
            double px = filter->radius[0] * (2.0 * (x + 0.5) / size[0] - 1.0);
            double py = filter->radius[1] * (2.0 * (y + 0.5) / size[1] - 1.0);
            double value = pixel_filter_evaluate(filter, px, py);
            f[(size_t)y * size[0] + x] = value;
            sum += value;
            sum_magnitude += fabs(value);
        }
    uint32_t offset = 0;
    int positive = sum > 0.0, failed = !positive || add_distribution(scene, f, size[0], size[1], &offset);
    free(f);
    if (!positive) {
        snprintf(error, error_size, "the pixel filter's integral over its table of %ux%u cells is not positive",
                 size[0], size[1]);
        return -1;
    }
    if (failed) {
        snprintf(error, error_size, "out of memory for the pixel filter");
        return -1;
    }
    data->radius[0] = filter->radius[0];
    data->radius[1] = filter->radius[1];
    data->table_width = size[0];
    data->table_height = size[1];
    data->distribution_offset = offset;
    data->weight = (float)(sum_magnitude / sum);
    return 0;
}

static int is_infinite(const Light *light)
{
    return light->type == LIGHT_UNIFORM_INFINITE || light->type == LIGHT_IMAGE_INFINITE;
}

static double luminance(const float rgb[3])
{
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/* The radius of the sphere around the primitives' bounding box. */
static double scene_radius(const Bvh *bvh)
{
    double lower[3] = {INFINITY, INFINITY, INFINITY}, upper[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < bvh->primitive_count; ++i) {
        const Primitive *p = &bvh->primitives[i];
        for (int k = 0; k < 3; ++k) {
            double lo = p->a[k], hi = p->a[k];
            if ((p->kind & PRIM_KIND_MASK) == PRIM_SPHERE) {
                lo -= p->b[0];
                hi += p->b[0];
            } else {
                double b = p->a[k] + (double)p->b[k], c = p->a[k] + (double)p->c[k];
                lo = fmin(lo, fmin(b, c));
                hi = fmax(hi, fmax(b, c));
            }
            lower[k] = fmin(lower[k], lo);
            upper[k] = fmax(upper[k], hi);
        }
    }
    if (bvh->primitive_count == 0)
        return 0.0;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k)
        d2 += (upper[k] - lower[k]) * (upper[k] - lower[k]);
    return 0.5 * sqrt(d2);
}

double render_scene_imaged_light_power(const Light *light, const float *rgb, uint32_t w, uint32_t h)
{
    double sum = 0.0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float *texel = rgb + 3 * ((size_t)y * w + x);
            float scaled[3] = {texel[0] * light->radiance[0], texel[1] * light->radiance[1],
                               texel[2] * light->radiance[2]};
            double weight = 1.0;
            if (light->type == LIGHT_PROJECTION) {
                double sx = (2.0 * (x + 0.5) / w - 1.0) * light->screen_half[0];
                double sy = (2.0 * (y + 0.5) / h - 1.0) * light->screen_half[1];
                double cos_theta = 1.0 / sqrt(sx * sx + sy * sy + 1.0);
                weight = cos_theta * cos_theta * cos_theta;
            }
            sum += luminance(scaled) * weight;
        }
    double mean = sum / ((double)w * h);
    const double pi = 3.14159265358979323846;
    return light->type == LIGHT_PROJECTION ? 4.0 * light->screen_half[0] * light->screen_half[1] * mean
                                           : 4.0 * pi * mean;
}

/* pbrt-v4's light power (Light::Phi), by luminance. */
static double light_power(const RenderScene *scene, const Light *light, double radius)
{
    const double pi = 3.14159265358979323846;
    double L = luminance(light->radiance);
    switch (light->type) {
    case LIGHT_AREA:
        return pi * (light->two_sided ? 2.0 : 1.0) * light->area * L;
    case LIGHT_POINT:
        return 4.0 * pi * L;
    case LIGHT_SPOT:
        return 2.0 * pi * L *
               ((1.0 - light->cos_falloff_start) + (light->cos_falloff_start - light->cos_total_width) / 2.0);
    case LIGHT_DISTANT:
        return pi * radius * radius * L;
    case LIGHT_UNIFORM_INFINITE:
        return 4.0 * pi * pi * radius * radius * L;
    case LIGHT_IMAGE_INFINITE: {
        const float *t = scene->texels + light->image_offset;
        size_t n = (size_t)light->image_width * light->image_height;
        double sum = 0.0;
        for (size_t i = 0; i < n; ++i) {
            float rgb[3] = {t[3 * i] * light->radiance[0], t[3 * i + 1] * light->radiance[1],
                            t[3 * i + 2] * light->radiance[2]};
            sum += luminance(rgb);
        }
        return 4.0 * pi * pi * radius * radius * sum / (double)n;
    }
    case LIGHT_GONIOMETRIC:
    case LIGHT_PROJECTION:
        return render_scene_imaged_light_power(light, scene->texels + light->image_offset, light->image_width,
                                               light->image_height);
    }
    return 0.0;
}

int render_scene_finalize(RenderScene *scene, char *error, size_t error_size)
{
    bvh_destroy(&scene->bvh);
    if (bvh_build(scene->primitives, scene->primitive_count, &scene->bvh, error, error_size))
        return -1;
    /* Infinite lights first (the kernel loops over them on escape), the
     * others after, each keeping its order. */
    int n = scene->light_count;
    int *new_index = malloc((size_t)(n ? n : 1) * sizeof *new_index);
    Light *ordered = malloc((size_t)(n ? n : 1) * sizeof *ordered);
    if (!new_index || !ordered) {
        free(new_index);
        free(ordered);
        snprintf(error, error_size, "out of memory ordering the lights");
        return -1;
    }
    int next = 0, infinite = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < n; ++i)
            if (is_infinite(&scene->lights[i]) == (pass == 0)) {
                new_index[i] = next;
                ordered[next++] = scene->lights[i];
                infinite += pass == 0;
            }
    if (n > 0)
        memcpy(scene->lights, ordered, (size_t)n * sizeof *ordered);
    free(ordered);
    /* The BVH reordered the primitives: point area lights at the new places. */
    for (int i = 0; i < scene->bvh.primitive_count; ++i) {
        Primitive *p = &scene->bvh.primitives[i];
        if (p->light >= 0) {
            p->light = new_index[p->light];
            scene->lights[p->light].primitive = i;
        }
    }
    free(new_index);

    /* Vertex normals follow their primitives into the BVH's order. */
    free(scene->shading_normals);
    scene->shading_normals = NULL;
    if (scene->vertex_normals && scene->bvh.primitive_count > 0) {
        size_t count = (size_t)scene->bvh.primitive_count;
        scene->shading_normals = calloc(9 * count, sizeof *scene->shading_normals);
        if (!scene->shading_normals) {
            snprintf(error, error_size, "out of memory for the vertex normals");
            return -1;
        }
        for (size_t i = 0; i < count; ++i)
            if (scene->bvh.primitives[i].kind & PRIM_SHADING_NORMAL)
                memcpy(scene->shading_normals + 9 * i, scene->vertex_normals + 9 * (size_t)scene->bvh.order[i],
                       9 * sizeof *scene->shading_normals);
    }

    if (render_scene_finalize_textures(scene, error, error_size))
        return -1;

    /* Pick lights in proportion to their power. */
    double radius = scene_radius(&scene->bvh), total = 0.0;
    for (int i = 0; i < n; ++i)
        total += light_power(scene, &scene->lights[i], radius);
    double running = 0.0;
    for (int i = 0; i < n; ++i) {
        Light *light = &scene->lights[i];
        double p = total > 0.0 ? light_power(scene, light, radius) / total : 1.0 / n;
        running += p;
        light->pick_probability = (float)p;
        light->pick_cdf = i + 1 == n ? 2.0f : (float)running; /* the last catches u = 1 - eps */
    }
    scene->constants.integrator.light_count = (uint32_t)n;
    scene->constants.background.infinite_count = (uint32_t)infinite;
    return 0;
}

uint64_t render_scene_features(const RenderScene *scene)
{
    uint64_t features = 0;
    for (int i = 0; i < scene->primitive_count; ++i)
        features |= (scene->primitives[i].kind & PRIM_KIND_MASK) == PRIM_SPHERE ? FEATURE_SPHERES : FEATURE_TRIANGLES;
    static const uint64_t by_type[] = {
        [MAT_DIFFUSE] = FEATURE_DIFFUSE,
        [MAT_DIELECTRIC] = FEATURE_DIELECTRIC,
        [MAT_CONDUCTOR] = FEATURE_CONDUCTOR,
        [MAT_COATED_DIFFUSE] = FEATURE_COATED_DIFFUSE | FEATURE_LAYERED,
        [MAT_DIFFUSE_TRANSMISSION] = FEATURE_DIFFUSE_TRANSMISSION,
        [MAT_MIX] = FEATURE_MIX,
        [MAT_COATED_CONDUCTOR] = FEATURE_COATED_CONDUCTOR | FEATURE_LAYERED,
        [MAT_THIN_DIELECTRIC] = FEATURE_THIN_DIELECTRIC,
        [MAT_INTERFACE] = 0, /* its shapes are not in the scene */
    };
    for (int i = 0; i < scene->material_count; ++i) {
        const Material *m = &scene->materials[i];
        features |= by_type[m->type];
        /* The types whose alpha is a GGX roughness (the coating's for the coated ones). */
        int has_alpha = m->type == MAT_DIELECTRIC || m->type == MAT_CONDUCTOR || m->type == MAT_COATED_DIFFUSE ||
                        m->type == MAT_COATED_CONDUCTOR;
        if ((has_alpha && (m->alpha_x >= SMOOTH_ALPHA || m->alpha_y >= SMOOTH_ALPHA)) ||
            (m->type == MAT_COATED_CONDUCTOR && (m->base_alpha_x >= SMOOTH_ALPHA || m->base_alpha_y >= SMOOTH_ALPHA)))
            features |= FEATURE_ROUGH;
    }
    static const uint32_t by_light[] = {
        [LIGHT_AREA] = FEATURE_AREA_LIGHTS,
        [LIGHT_POINT] = FEATURE_POINT_LIGHTS,
        [LIGHT_SPOT] = FEATURE_SPOT_LIGHTS,
        [LIGHT_DISTANT] = FEATURE_DISTANT_LIGHTS,
        [LIGHT_UNIFORM_INFINITE] = FEATURE_ENVIRONMENT,
        [LIGHT_IMAGE_INFINITE] = FEATURE_ENVIRONMENT_MAP,
        [LIGHT_GONIOMETRIC] = FEATURE_GONIOMETRIC_LIGHTS,
        [LIGHT_PROJECTION] = FEATURE_PROJECTION_LIGHTS,
    };
    for (int i = 0; i < scene->light_count; ++i)
        features |= by_light[scene->lights[i].type];
    if (scene->constants.integrator.flags & RENDER_NEE)
        features |= FEATURE_NEE;
    if (scene->shading_normals)
        features |= FEATURE_SHADING_NORMALS;
    const FilmData *film = &scene->constants.film;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (film->from_radiance[i][j] != (i == j ? 1.0f : 0.0f))
                features |= FEATURE_FILM_MATRIX;
    if (film->max_component_value < INFINITY)
        features |= FEATURE_FILM_CLAMP;
    const CameraData *camera = &scene->constants.camera;
    if (camera->lens_radius > 0.0f)
        features |= FEATURE_THIN_LENS;
    if (camera->projection == CAMERA_ORTHOGRAPHIC)
        features |= FEATURE_ORTHOGRAPHIC;
    if (scene->constants.filter.table_width > 0)
        features |= FEATURE_PIXEL_FILTER;
    for (int i = 0; i < scene->texture_count; ++i)
        features |= scene->textures[i].type == TEXTURE_IMAGE ? FEATURE_IMAGE_TEXTURES : FEATURE_PROCEDURAL_TEXTURES;
    for (int i = 0; i < scene->material_texture_count && scene->texture_count > 0; ++i) {
        const MaterialTextures *t = &scene->material_textures[i];
        features |= t->displacement >= 0 ? FEATURE_BUMP_MAP : 0;
        features |= t->normal_map >= 0 ? FEATURE_NORMAL_MAP : 0;
        if (scene->materials[i].type != MAT_DIFFUSE && (t->roughness[0] >= 0 || t->roughness[1] >= 0))
            features |= FEATURE_ROUGH;
    }
    return features;
}
