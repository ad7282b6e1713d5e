#include "render/render_scene.h"

#include "render/light_tree_build.h"
#include "nanovdb.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void render_scene_init(RenderScene *scene)
{
    memset(scene, 0, sizeof *scene);
    scene->open_object = -1;
    scene->constants.integrator.max_depth = 5;
    scene->constants.integrator.flags = RENDER_NEE;
    scene->constants.integrator.sampler = SAMPLER_DEFAULT;
    scene->constants.integrator.light_sampler = LIGHT_SAMPLER_TREE;
    scene->constants.integrator.rr_threshold = 1.0f;
    for (int i = 0; i < 3; ++i)
        scene->constants.film.from_radiance[i][i] = 1.0f;
    scene->constants.film.max_component_value = INFINITY;
    scene->constants.media.camera_medium = -1;
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
    free(scene->objects);
    free(scene->instance_inputs);
    free(scene->alphas);
    free(scene->instances);
    free(scene->light_nodes);
    free(scene->light_trails);
    free(scene->media);
    free(scene->medium_values);
    free(scene->medium_interfaces);
    free(scene->primitive_media);
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
    a.light_nodes = scene->light_nodes;
    a.light_nodes_count = (size_t)scene->light_node_count;
    a.light_trails = scene->light_trails;
    a.light_trails_count =
        scene->light_trails ? (size_t)(scene->light_count - scene->constants.integrator.unbounded_lights) : 0;
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
    a.instances = scene->instances;
    a.instances_count = (size_t)scene->instance_count;
    a.alphas = scene->alphas;
    a.alphas_count = (size_t)scene->alpha_count;
    a.media = scene->media;
    a.media_count = scene->constants.media.count;
    a.primitive_media = scene->primitive_media;
    a.primitive_media_count = scene->primitive_media ? (size_t)scene->bvh.primitive_count : 0;
    a.medium_values = scene->medium_values;
    a.medium_values_count = scene->medium_value_count;
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
    if (scene->open_object < 0 && emission && (emission[0] > 0.0f || emission[1] > 0.0f || emission[2] > 0.0f)) {
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

/* A grid medium's largest sigma_t (any channel) in cell i: uniformgrid's
 * density times its largest sigma_a + sigma_s, rgbgrid's coefficients (1
 * where a grid is absent) times scale. */
static double cell_sigma_t(const RenderScene *scene, const Medium *m, size_t i)
{
    const float *v = scene->medium_values;
    double largest = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (m->type == MEDIUM_CLOUD) { /* its density is at most 1 */
            largest = fmax(largest, (double)m->sigma_a[k] + m->sigma_s[k]);
            continue;
        }
        int uniform = m->type == MEDIUM_UNIFORM_GRID;
        double a = uniform ? v[m->density + i] : m->rgb_sigma_a >= 0 ? v[m->rgb_sigma_a + 3 * i + (size_t)k] : 1.0;
        double s = uniform ? v[m->density + i] : m->rgb_sigma_s >= 0 ? v[m->rgb_sigma_s + 3 * i + (size_t)k] : 1.0;
        largest = fmax(largest, a * m->sigma_a[k] + s * m->sigma_s[k]);
    }
    return largest;
}

/* pbrt-v4's majorant grid: per cell of a MEDIUM_MAJORANT_GRID^3 division
 * of the unit cube, the largest sigma_t of the grid cells a trilinear
 * lookup in it may read (those whose centres are within one cell of it),
 * a little above, so float lookups stay under it; m->majorant the largest
 * of all (a cloud's density is at most 1: sigma_t everywhere). Returns 0,
 * or -1 when out of memory. */
static int add_majorant_grid(RenderScene *scene, Medium *m)
{
    enum { R = MEDIUM_MAJORANT_GRID };
    if (m->type == MEDIUM_NANOVDB) /* scene_convert.c gathers them from the grid's tree */
        return 0;
    float grid[R * R * R];
    double overall = 0.0;
    for (int z = 0; z < R; ++z)
        for (int y = 0; y < R; ++y)
            for (int x = 0; x < R; ++x) {
                int at[3] = {x, y, z}, lo[3], hi[3];
                for (int k = 0; k < 3; ++k) {
                    int n = m->type == MEDIUM_CLOUD ? 1 : (int)m->size[k];
                    lo[k] = (int)floor((double)at[k] / R * n - 0.5);
                    hi[k] = (int)floor((double)(at[k] + 1) / R * n - 0.5) + 1;
                    lo[k] = lo[k] < 0 ? 0 : lo[k];
                    hi[k] = hi[k] > n - 1 ? n - 1 : hi[k];
                }
                double largest = 0.0;
                for (int k = lo[2]; k <= hi[2]; ++k)
                    for (int j = lo[1]; j <= hi[1]; ++j)
                        for (int i = lo[0]; i <= hi[0]; ++i) {
                            size_t cell = ((size_t)k * m->size[1] + (size_t)j) * m->size[0] + (size_t)i;
                            largest = fmax(largest, cell_sigma_t(scene, m, cell));
                        }
                grid[(z * R + y) * R + x] = (float)(largest * (1.0 + 1e-5));
                overall = fmax(overall, largest);
            }
    m->majorant = (float)(overall * (1.0 + 1e-5));
    return (m->majorants = render_scene_add_medium_values(scene, grid, R * R * R)) < 0 ? -1 : 0;
}

int render_scene_add_medium(RenderScene *scene, const Medium *medium)
{
    int count = (int)scene->constants.media.count;
    if (count >= (int)MEDIUM_MAX_COUNT ||
        reserve_one((void **)&scene->media, count, &scene->medium_capacity, sizeof *scene->media))
        return -1;
    scene->media[count] = *medium;
    if (medium->type != MEDIUM_HOMOGENEOUS && add_majorant_grid(scene, &scene->media[count]))
        return -1;
    scene->constants.media.count++;
    return count;
}

/* A medium index as primitive_media packs it. */
static uint32_t packed_medium(int medium)
{
    return medium < 0 ? MEDIUM_VACUUM : (uint32_t)medium;
}

int render_scene_set_media(RenderScene *scene, int inside, int outside)
{
    if ((size_t)scene->primitive_capacity > scene->medium_interface_capacity) {
        size_t capacity = (size_t)scene->primitive_capacity;
        uint32_t *grown = realloc(scene->medium_interfaces, capacity * sizeof *grown);
        if (!grown)
            return -1;
        /* Primitives added before any interface keep the ray's medium. */
        for (size_t i = scene->medium_interface_capacity; i < capacity; ++i)
            grown[i] = MEDIUM_VACUUM | MEDIUM_VACUUM << 16;
        scene->medium_interfaces = grown;
        scene->medium_interface_capacity = capacity;
    }
    scene->medium_interfaces[scene->primitive_count - 1] = packed_medium(inside) | packed_medium(outside) << 16;
    return 0;
}

int render_scene_begin_object(RenderScene *scene)
{
    if (reserve_one((void **)&scene->objects, scene->object_count, &scene->object_capacity, sizeof *scene->objects))
        return -1;
    scene->objects[scene->object_count].first = scene->primitive_count;
    scene->objects[scene->object_count].count = 0;
    scene->open_object = scene->object_count;
    return scene->object_count++;
}

void render_scene_end_object(RenderScene *scene)
{
    RenderObject *object = &scene->objects[scene->open_object];
    object->count = scene->primitive_count - object->first;
    scene->open_object = -1;
}

/* The inverse of an affine matrix (rows of 3x4), in double; 0 when singular. */
static int invert_affine(const double m[3][4], double inverse[3][4])
{
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(fabs(det) > 0.0) || !isfinite(det))
        return 0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            /* The cofactor of (c, r) over the determinant. */
            int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
            inverse[r][c] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    for (int r = 0; r < 3; ++r)
        inverse[r][3] = -(inverse[r][0] * m[0][3] + inverse[r][1] * m[1][3] + inverse[r][2] * m[2][3]);
    return 1;
}

int render_scene_add_instance(RenderScene *scene, int object, const double world_from_object[3][4], char *error,
                              size_t error_size)
{
    double inverse[3][4];
    if (!invert_affine(world_from_object, inverse)) {
        snprintf(error, error_size, "the instance's transform is singular or not finite");
        return -1;
    }
    if (reserve_one((void **)&scene->instance_inputs, scene->instance_input_count, &scene->instance_input_capacity,
                    sizeof *scene->instance_inputs)) {
        snprintf(error, error_size, "out of memory for the instances");
        return -1;
    }
    RenderInstance *added = &scene->instance_inputs[scene->instance_input_count++];
    added->object = object;
    memcpy(added->world_from_object, world_from_object, sizeof added->world_from_object);
    return 0;
}

int render_scene_set_alpha(RenderScene *scene, float alpha, int texture)
{
    if (texture >= 0)
        alpha = 1.0f; /* unused: one slot per texture */
    int slot = scene->alpha_count - 1;
    while (slot >= 0 && (scene->alphas[slot].value != alpha || scene->alphas[slot].texture != texture))
        --slot;
    if (slot < 0) {
        if (scene->alpha_count >= (int)PRIM_MAX_ALPHA_SLOTS ||
            reserve_one((void **)&scene->alphas, scene->alpha_count, &scene->alpha_capacity, sizeof *scene->alphas))
            return -1;
        slot = scene->alpha_count++;
        scene->alphas[slot].value = alpha;
        scene->alphas[slot].texture = texture;
    }
    Primitive *p = &scene->primitives[scene->primitive_count - 1];
    p->kind = (p->kind & ((1u << PRIM_ALPHA_SHIFT) - 1u)) | PRIM_ALPHA | (uint32_t)slot << PRIM_ALPHA_SHIFT;
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

int32_t render_scene_add_medium_bytes(RenderScene *scene, const void *bytes, size_t size)
{
    size_t padding = (NANOVDB_ALIGNMENT_FLOATS - scene->medium_value_count % NANOVDB_ALIGNMENT_FLOATS) %
                     NANOVDB_ALIGNMENT_FLOATS,
           count = (size + sizeof(float) - 1) / sizeof(float);
    if (scene->medium_value_count + padding + count > INT32_MAX)
        return -1;
    float *at =
        grow_floats(&scene->medium_values, &scene->medium_value_count, &scene->medium_value_capacity, padding + count);
    if (!at)
        return -1;
    memset(at, 0, (padding + count) * sizeof *at);
    memcpy(at + padding, bytes, size);
    return (int32_t)(at + padding - scene->medium_values);
}

int32_t render_scene_add_medium_values(RenderScene *scene, const float *values, size_t count)
{
    if (scene->medium_value_count + count > INT32_MAX)
        return -1;
    float *at = grow_floats(&scene->medium_values, &scene->medium_value_count, &scene->medium_value_capacity, count);
    if (!at)
        return -1;
    memcpy(at, values, count * sizeof *at);
    return (int32_t)(at - scene->medium_values);
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

/* The order of render_scene_finalize's light array: infinite, distant,
 * bounded. */
static int light_rank(const Light *light)
{
    return is_infinite(light) ? 0 : light->type == LIGHT_DISTANT ? 1 : 2;
}

static double luminance(const float rgb[3])
{
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/* The radius of the sphere around the bounding box of the top-level
 * tree's primitives (instances by their boxes). */
static double scene_radius(const RenderScene *scene)
{
    const Bvh *bvh = &scene->bvh;
    double lower[3] = {INFINITY, INFINITY, INFINITY}, upper[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < scene->world_primitive_count; ++i) {
        const Primitive *p = &bvh->primitives[i];
        for (int k = 0; k < 3; ++k) {
            double lo = p->a[k], hi = p->a[k];
            if ((p->kind & PRIM_KIND_MASK) == PRIM_SPHERE) {
                lo -= p->b[0];
                hi += p->b[0];
            } else if ((p->kind & PRIM_KIND_MASK) == PRIM_INSTANCE) {
                hi = p->b[k];
            } else {
                double b = p->a[k] + (double)p->b[k], c = p->a[k] + (double)p->c[k];
                lo = fmin(lo, fmin(b, c));
                hi = fmax(hi, fmax(b, c));
            }
            lower[k] = fmin(lower[k], lo);
            upper[k] = fmax(upper[k], hi);
        }
    }
    if (scene->world_primitive_count == 0)
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

/* An object's BVH moved to blocks from node_offset and primitives from
 * primitive_offset of the combined arrays: its references follow. */
static void offset_tree(BvhNode *nodes, int block, int node_offset, int primitive_offset)
{
    BvhWideNode *node = &nodes[block].node;
    for (int j = 0; j < BVH_WIDTH; ++j) {
        if (node->count[j] < 0)
            continue;
        if (node->count[j] == 0) {
            offset_tree(nodes, node->child[j], node_offset, primitive_offset);
            node->child[j] += node_offset;
        } else {
            node->child[j] += primitive_offset;
        }
        if (node->packet[j] >= 0)
            node->packet[j] += node_offset;
    }
}

/* The world-space box of a box under an affine transform, widened by a
 * little more than float rounding: the instance's tree is traversed with
 * the ray rounded in object space, which may meet geometry a world-space
 * test of the exact box would pass by. */
static void transformed_box(const double m[3][4], const float lower[3], const float upper[3], float out_lower[3],
                            float out_upper[3])
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, reach = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        double p[3] = {corner & 1 ? upper[0] : lower[0], corner & 2 ? upper[1] : lower[1],
                       corner & 4 ? upper[2] : lower[2]};
        for (int r = 0; r < 3; ++r) {
            double w = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
            lo[r] = fmin(lo[r], w);
            hi[r] = fmax(hi[r], w);
            reach = fmax(reach, fabs(w));
        }
    }
    for (int r = 0; r < 3; ++r) {
        out_lower[r] = (float)(lo[r] - 1e-6 * reach);
        out_upper[r] = (float)(hi[r] + 1e-6 * reach);
    }
}

/* The bounds of a BVH's root children. */
static void root_box(const Bvh *bvh, float lower[3], float upper[3])
{
    const BvhWideNode *root = &bvh->nodes[0].node;
    for (int i = 0; i < 3; ++i) {
        lower[i] = INFINITY;
        upper[i] = -INFINITY;
        for (int j = 0; j < BVH_WIDTH; ++j)
            if (root->count[j] >= 0) {
                lower[i] = fminf(lower[i], root->lower[i][j]);
                upper[i] = fmaxf(upper[i], root->upper[i][j]);
            }
    }
}

/* The two-level BVH: one tree per object, and the top-level tree over the
 * world's primitives and one PRIM_INSTANCE per instance of a non-empty
 * object, all in one node and one primitive array (top level first). */
static int build_instanced_bvh(RenderScene *scene, char *error, size_t error_size)
{
    int objects = scene->object_count, in_object = 0;
    Bvh *trees = calloc((size_t)objects, sizeof *trees);
    char *is_object_primitive = calloc((size_t)(scene->primitive_count ? scene->primitive_count : 1), 1);
    char *drawn = calloc((size_t)objects, 1);
    int *top_order = malloc((size_t)(scene->primitive_count + scene->instance_input_count + 1) * sizeof *top_order);
    Primitive *top = malloc((size_t)(scene->primitive_count + scene->instance_input_count + 1) * sizeof *top);
    scene->instances = malloc((size_t)(scene->instance_input_count + 1) * sizeof *scene->instances);
    Bvh world;
    memset(&world, 0, sizeof world);
    int result = -1, stack_need = 0;
    if (!trees || !is_object_primitive || !drawn || !top_order || !top || !scene->instances) {
        snprintf(error, error_size, "out of memory building the instanced BVH");
        goto done;
    }
    for (int i = 0; i < scene->instance_input_count; ++i)
        drawn[scene->instance_inputs[i].object] = 1;
    for (int k = 0; k < objects; ++k) {
        const RenderObject *o = &scene->objects[k];
        memset(is_object_primitive + o->first, 1, (size_t)o->count);
        if (o->count == 0 || !drawn[k])
            continue; /* no tree for an object without instances */
        in_object += o->count;
        if (bvh_build(scene->primitives + o->first, o->count, &trees[k], error, error_size))
            goto done;
        if (trees[k].stack_need > stack_need)
            stack_need = trees[k].stack_need;
    }
    int top_count = 0;
    for (int i = 0; i < scene->primitive_count; ++i)
        if (!is_object_primitive[i]) {
            top_order[top_count] = i;
            top[top_count++] = scene->primitives[i];
        }
    scene->instance_count = 0;
    for (int i = 0; i < scene->instance_input_count; ++i) {
        const RenderInstance *in = &scene->instance_inputs[i];
        if (scene->objects[in->object].count == 0)
            continue; /* nothing to draw */
        double inverse[3][4];
        invert_affine(in->world_from_object, inverse);
        Instance *out = &scene->instances[scene->instance_count];
        memset(out, 0, sizeof *out);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c)
                out->object_from_world[r][c] = (float)inverse[r][c];
        out->root = in->object; /* the object's index until the trees are placed */
        Primitive p;
        memset(&p, 0, sizeof p);
        float lower[3], upper[3];
        root_box(&trees[in->object], lower, upper);
        transformed_box(in->world_from_object, lower, upper, p.a, p.b);
        p.kind = PRIM_INSTANCE;
        p.material = scene->instance_count++;
        p.light = -1;
        top_order[top_count] = -1;
        top[top_count++] = p;
    }
    if (bvh_build(top, top_count, &world, error, error_size))
        goto done;
    /* An object's tree is traversed above the top level's entries when its
     * instance is entered. */
    int need = world.stack_need;
    if (world.instance_entry_need > 0 && world.instance_entry_need + stack_need > need)
        need = world.instance_entry_need + stack_need;
    int node_count = world.node_count, primitive_count = world.primitive_count + in_object;
    for (int k = 0; k < objects; ++k)
        node_count += trees[k].node_count;
    Bvh *all = &scene->bvh;
    memset(all, 0, sizeof *all);
    all->nodes = malloc((size_t)node_count * sizeof *all->nodes);
    all->primitives = malloc((size_t)primitive_count * sizeof *all->primitives);
    all->order = malloc((size_t)primitive_count * sizeof *all->order);
    if (!all->nodes || !all->primitives || !all->order) {
        snprintf(error, error_size, "out of memory building the instanced BVH");
        goto done;
    }
    memcpy(all->nodes, world.nodes, (size_t)world.node_count * sizeof *all->nodes);
    memcpy(all->primitives, world.primitives, (size_t)world.primitive_count * sizeof *all->primitives);
    for (int i = 0; i < world.primitive_count; ++i)
        all->order[i] = top_order[world.order[i]];
    int *root = malloc((size_t)(objects + 1) * sizeof *root);
    if (!root) {
        snprintf(error, error_size, "out of memory building the instanced BVH");
        goto done;
    }
    int nodes_at = world.node_count, primitives_at = world.primitive_count;
    for (int k = 0; k < objects; ++k) {
        const Bvh *t = &trees[k];
        root[k] = nodes_at;
        if (t->node_count == 0)
            continue;
        memcpy(all->nodes + nodes_at, t->nodes, (size_t)t->node_count * sizeof *all->nodes);
        offset_tree(all->nodes + nodes_at, 0, nodes_at, primitives_at);
        memcpy(all->primitives + primitives_at, t->primitives, (size_t)t->primitive_count * sizeof *all->primitives);
        for (int i = 0; i < t->primitive_count; ++i)
            all->order[primitives_at + i] = scene->objects[k].first + t->order[i];
        nodes_at += t->node_count;
        primitives_at += t->primitive_count;
    }
    for (int i = 0; i < scene->instance_count; ++i)
        scene->instances[i].root = root[scene->instances[i].root];
    free(root);
    all->node_count = node_count;
    all->primitive_count = primitive_count;
    all->depth = world.depth;
    all->largest_leaf = world.largest_leaf;
    all->stack_need = need;
    scene->world_primitive_count = world.primitive_count;
    result = 0;
done:
    for (int k = 0; k < objects && trees; ++k)
        bvh_destroy(&trees[k]);
    free(trees);
    free(is_object_primitive);
    free(drawn);
    free(top_order);
    free(top);
    bvh_destroy(&world);
    return result;
}

int render_scene_finalize(RenderScene *scene, char *error, size_t error_size)
{
    bvh_destroy(&scene->bvh);
    free(scene->instances);
    scene->instances = NULL;
    scene->instance_count = 0;
    if (scene->object_count == 0) {
        if (bvh_build(scene->primitives, scene->primitive_count, &scene->bvh, error, error_size))
            return -1;
        scene->world_primitive_count = scene->bvh.primitive_count;
    } else if (build_instanced_bvh(scene, error, error_size)) {
        return -1;
    }
    /* Infinite lights first (the kernel loops over them on escape), then
     * the distant ones (the other lights the tree does not hold), then the
     * bounded ones, each keeping its order. */
    int n = scene->light_count;
    int *new_index = malloc((size_t)(n ? n : 1) * sizeof *new_index);
    Light *ordered = malloc((size_t)(n ? n : 1) * sizeof *ordered);
    if (!new_index || !ordered) {
        free(new_index);
        free(ordered);
        snprintf(error, error_size, "out of memory ordering the lights");
        return -1;
    }
    int next = 0, infinite = 0, unbounded = 0;
    for (int rank = 0; rank < 3; ++rank)
        for (int i = 0; i < n; ++i)
            if (light_rank(&scene->lights[i]) == rank) {
                new_index[i] = next;
                ordered[next++] = scene->lights[i];
                infinite += rank == 0;
                unbounded += rank < 2;
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

    /* So do the media's interfaces. */
    free(scene->primitive_media);
    scene->primitive_media = NULL;
    if (scene->constants.media.count > 0 && scene->bvh.primitive_count > 0) {
        size_t count = (size_t)scene->bvh.primitive_count;
        scene->primitive_media = malloc(count * sizeof *scene->primitive_media);
        if (!scene->primitive_media) {
            snprintf(error, error_size, "out of memory for the media's interfaces");
            return -1;
        }
        for (size_t i = 0; i < count; ++i) {
            int input = scene->bvh.order[i];
            scene->primitive_media[i] =
                scene->medium_interfaces && input >= 0 && (size_t)input < scene->medium_interface_capacity
                    ? scene->medium_interfaces[input]
                    : MEDIUM_VACUUM | MEDIUM_VACUUM << 16;
        }
    }

    if (render_scene_finalize_textures(scene, error, error_size))
        return -1;

    scene->constants.integrator.light_count = (uint32_t)n;
    scene->constants.integrator.unbounded_lights = (uint32_t)unbounded;
    scene->constants.background.infinite_count = (uint32_t)infinite;

    int bounded = n - unbounded;
    LightBounds *bounds = malloc((size_t)(bounded ? bounded : 1) * sizeof *bounds);
    if (!bounds) {
        snprintf(error, error_size, "out of memory bounding the lights");
        return -1;
    }
    double radius = scene_radius(scene);
    for (int i = 0; i < bounded; ++i) {
        const Light *light = &scene->lights[unbounded + i];
        bounds[i] = light_bounds(light, scene->bvh.primitives, light_power(scene, light, radius));
    }
    free(scene->light_nodes);
    free(scene->light_trails);
    int failed = light_tree_build(bounds, bounded, unbounded, &scene->light_nodes, &scene->light_node_count,
                                  &scene->light_trails);
    free(bounds);
    if (failed) {
        snprintf(error, error_size, "out of memory for the light tree of %d lights", bounded);
        return -1;
    }
    render_scene_set_light_sampler(scene, scene->constants.integrator.light_sampler);
    return 0;
}

void render_scene_set_light_sampler(RenderScene *scene, uint32_t light_sampler)
{
    IntegratorData *integrator = &scene->constants.integrator;
    integrator->light_sampler = light_sampler;
    int n = scene->light_count, unbounded = (int)integrator->unbounded_lights;
    double radius = scene_radius(scene), total = 0.0, unbounded_total = 0.0;
    for (int i = 0; i < n; ++i) {
        double power = light_power(scene, &scene->lights[i], radius);
        total += power;
        unbounded_total += i < unbounded ? power : 0.0;
    }
    double tree_share = n > unbounded ? 1.0 / (unbounded + 1) : 0.0, running = 0.0;
    for (int i = 0; i < n; ++i) {
        Light *light = &scene->lights[i];
        double p = 1.0 / n, power = light_power(scene, light, radius);
        if (light_sampler == LIGHT_SAMPLER_POWER && total > 0.0)
            p = power / total;
        else if (light_sampler == LIGHT_SAMPLER_TREE)
            p = i < unbounded ? (1.0 - tree_share) / unbounded
                              : tree_share * (total > unbounded_total ? power / (total - unbounded_total)
                                                                      : 1.0 / (n - unbounded));
        running += p;
        light->pick_probability = (float)p;
        light->pick_cdf = i + 1 == n ? 2.0f : (float)running; /* the last catches u = 1 - eps */
    }
}

static const char *const light_sampler_names[LIGHT_SAMPLER_COUNT] = {"uniform", "power", "bvh"};

const char *light_sampler_name(uint32_t light_sampler)
{
    return light_sampler < LIGHT_SAMPLER_COUNT ? light_sampler_names[light_sampler] : "unknown";
}

int light_sampler_from_name(const char *name)
{
    if (strcmp(name, "exhaustive") == 0)
        return LIGHT_SAMPLER_TREE;
    for (uint32_t i = 0; i < LIGHT_SAMPLER_COUNT; ++i)
        if (strcmp(name, light_sampler_names[i]) == 0)
            return (int)i;
    return -1;
}

static const char *const sampler_names[SAMPLER_COUNT] = {"independent", "sobol-pixel", "sobol-sets"};

const char *sampler_name(uint32_t sampler)
{
    return sampler < SAMPLER_COUNT ? sampler_names[sampler] : "unknown";
}

int sampler_from_name(const char *name)
{
    for (uint32_t i = 0; i < SAMPLER_COUNT; ++i)
        if (strcmp(name, sampler_names[i]) == 0)
            return (int)i;
    return -1;
}

uint32_t sampler_for_scene(const char *name)
{
    return strcmp(name, "independent") == 0 ? SAMPLER_INDEPENDENT : SAMPLER_DEFAULT;
}

uint64_t render_scene_features(const RenderScene *scene)
{
    uint64_t features = 0;
    for (int i = 0; i < scene->primitive_count; ++i) {
        features |= (scene->primitives[i].kind & PRIM_KIND_MASK) == PRIM_SPHERE ? FEATURE_SPHERES : FEATURE_TRIANGLES;
        if (scene->primitives[i].kind & PRIM_ALPHA)
            features |= FEATURE_ALPHA;
    }
    for (int i = 0; i < scene->alpha_count; ++i)
        if (scene->alphas[i].texture >= 0)
            features |= FEATURE_ALPHA_TEXTURE;
    if (scene->instance_count > 0)
        features |= FEATURE_INSTANCING;
    if (scene->constants.media.count > 0)
        features |= FEATURE_MEDIA;
    for (uint32_t i = 0; i < scene->constants.media.count; ++i)
        if (scene->media[i].type == MEDIUM_NANOVDB)
            features |= FEATURE_NANOVDB;
    static const uint64_t by_type[] = {
        [MAT_DIFFUSE] = FEATURE_DIFFUSE,
        [MAT_DIELECTRIC] = FEATURE_DIELECTRIC,
        [MAT_CONDUCTOR] = FEATURE_CONDUCTOR,
        [MAT_COATED_DIFFUSE] = FEATURE_COATED_DIFFUSE | FEATURE_LAYERED,
        [MAT_DIFFUSE_TRANSMISSION] = FEATURE_DIFFUSE_TRANSMISSION,
        [MAT_MIX] = FEATURE_MIX,
        [MAT_COATED_CONDUCTOR] = FEATURE_COATED_CONDUCTOR | FEATURE_LAYERED,
        [MAT_THIN_DIELECTRIC] = FEATURE_THIN_DIELECTRIC,
        [MAT_INTERFACE] = 0, /* FEATURE_MEDIA's boundaries, else its shapes are not in the scene */
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
#define LIGHT_FEATURE_(id, feature, sample, emit) [LIGHT_##id] = feature,
    static const uint64_t by_light[LIGHT_TYPE_COUNT] = {GMON_LIGHT_TYPES(LIGHT_FEATURE_)};
#undef LIGHT_FEATURE_
    for (int i = 0; i < scene->light_count; ++i)
        features |= by_light[scene->lights[i].type];
    if (scene->constants.integrator.flags & RENDER_NEE)
        features |= FEATURE_NEE;
    if (scene->constants.integrator.flags & RENDER_REGULARIZE)
        features |= FEATURE_ROUGH; /* regularized specular lobes are rough */
    if (scene->shading_normals)
        features |= FEATURE_SHADING_NORMALS;
    const FilmData *film = &scene->constants.film;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (film->from_radiance[i][j] != (i == j ? 1.0f : 0.0f))
                features |= FEATURE_FILM_MATRIX;
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
        if ((scene->materials[i].type != MAT_DIFFUSE && (t->roughness[0] >= 0 || t->roughness[1] >= 0)) ||
            t->base_roughness[0] >= 0 || t->base_roughness[1] >= 0)
            features |= FEATURE_ROUGH;
    }
    return features;
}
