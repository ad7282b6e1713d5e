#include "render/render_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void render_scene_init(RenderScene *scene)
{
    memset(scene, 0, sizeof *scene);
    scene->params.max_depth = 5;
    scene->params.flags = RENDER_NEE;
}

void render_scene_destroy(RenderScene *scene)
{
    free(scene->materials);
    free(scene->primitives);
    free(scene->emitters);
    bvh_destroy(&scene->bvh);
    memset(scene, 0, sizeof *scene);
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
    added->emitter = -1;
    if (emission && (emission[0] > 0.0f || emission[1] > 0.0f || emission[2] > 0.0f)) {
        if (reserve_one((void **)&scene->emitters, scene->emitter_count, &scene->emitter_capacity,
                        sizeof *scene->emitters))
            return -1;
        Emitter *e = &scene->emitters[scene->emitter_count];
        memset(e, 0, sizeof *e);
        memcpy(e->radiance, emission, sizeof e->radiance);
        e->primitive = scene->primitive_count; /* remapped after the BVH build */
        e->area = area;
        e->two_sided = two_sided ? 1u : 0u;
        added->emitter = scene->emitter_count++;
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

void render_scene_set_camera(RenderScene *scene, const float position[3], const float forward[3], const float right[3],
                             const float up[3], float tan_half_fov_x, float tan_half_fov_y, unsigned width,
                             unsigned height)
{
    RenderParams *p = &scene->params;
    for (int i = 0; i < 3; ++i) {
        p->camera_position[i] = position[i];
        p->camera_forward[i] = forward[i];
        p->camera_right[i] = right[i] * tan_half_fov_x;
        p->camera_up[i] = up[i] * tan_half_fov_y;
    }
    p->width = width;
    p->height = height;
}

int render_scene_finalize(RenderScene *scene, char *error, size_t error_size)
{
    bvh_destroy(&scene->bvh);
    if (bvh_build(scene->primitives, scene->primitive_count, &scene->bvh, error, error_size))
        return -1;
    /* The BVH reordered the primitives: point emitters at the new places. */
    for (int i = 0; i < scene->bvh.primitive_count; ++i)
        if (scene->bvh.primitives[i].emitter >= 0)
            scene->emitters[scene->bvh.primitives[i].emitter].primitive = i;

    /* Pick lights in proportion to their power. */
    double total = 0.0;
    for (int i = 0; i < scene->emitter_count; ++i) {
        const Emitter *e = &scene->emitters[i];
        double luminance = 0.2126 * e->radiance[0] + 0.7152 * e->radiance[1] + 0.0722 * e->radiance[2];
        total += luminance * e->area * (e->two_sided ? 2.0 : 1.0);
    }
    double running = 0.0;
    for (int i = 0; i < scene->emitter_count; ++i) {
        Emitter *e = &scene->emitters[i];
        double luminance = 0.2126 * e->radiance[0] + 0.7152 * e->radiance[1] + 0.0722 * e->radiance[2];
        double power = luminance * e->area * (e->two_sided ? 2.0 : 1.0);
        double p = total > 0.0 ? power / total : 1.0 / scene->emitter_count;
        running += p;
        e->pick_probability = (float)p;
        e->pick_cdf = i + 1 == scene->emitter_count ? 2.0f : (float)running; /* the last catches u = 1 - eps */
    }
    RenderParams *params = &scene->params;
    int has_environment =
        params->environment[0] > 0.0f || params->environment[1] > 0.0f || params->environment[2] > 0.0f;
    params->emitter_count = (uint32_t)scene->emitter_count;
    params->environment_pick = has_environment ? (scene->emitter_count > 0 ? 0.5f : 1.0f) : 0.0f;
    return 0;
}

uint32_t render_scene_features(const RenderScene *scene)
{
    uint32_t features = 0;
    for (int i = 0; i < scene->primitive_count; ++i)
        features |= (scene->primitives[i].kind & PRIM_KIND_MASK) == PRIM_SPHERE ? FEATURE_SPHERES : FEATURE_TRIANGLES;
    static const uint32_t by_type[] = {
        [MAT_DIFFUSE] = FEATURE_DIFFUSE,
        [MAT_DIELECTRIC] = FEATURE_DIELECTRIC,
        [MAT_CONDUCTOR] = FEATURE_CONDUCTOR,
        [MAT_COATED_DIFFUSE] = FEATURE_COATED_DIFFUSE,
    };
    for (int i = 0; i < scene->material_count; ++i) {
        const Material *m = &scene->materials[i];
        features |= by_type[m->type];
        if (m->type != MAT_DIFFUSE && (m->alpha_x >= SMOOTH_ALPHA || m->alpha_y >= SMOOTH_ALPHA))
            features |= FEATURE_ROUGH;
    }
    if (scene->emitter_count > 0)
        features |= FEATURE_AREA_LIGHTS;
    const float *environment = scene->params.environment;
    if (environment[0] > 0.0f || environment[1] > 0.0f || environment[2] > 0.0f)
        features |= FEATURE_ENVIRONMENT;
    if (scene->params.flags & RENDER_NEE)
        features |= FEATURE_NEE;
    return features;
}
