/* Lights: for each type, sampling a direction toward it from a point
 * (light_sample), the radiance a ray escaping the scene receives from the
 * infinite ones (infinite_radiance) and their densities, for MIS. Types a
 * scene does not use are compiled out (feature_mask.h). The light to sample
 * is picked by the light sampler (pick_light_at): with a fixed chance each
 * (uniform or by power, computed by the host, host/render/render_scene.c),
 * or by the light tree (light_tree.h). */
#ifndef KERNELS_LIGHTS_H
#define KERNELS_LIGHTS_H

#include "light_area.h"
#include "light_distant.h"
#include "light_infinite.h"
#include "light_point.h"
#include "light_tree.h"

/* Index of the light whose CDF interval holds u. */
KERNEL_FN int pick_light(GLOBAL const Light *lights, uint32_t count, float u)
{
    int lo = 0, hi = (int)count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (u < lights[mid].pick_cdf)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* With the light tree, as pbrt-v4's "bvh" sampler: the tree (if there are
 * bounded lights) and each unbounded light have equal chances. */
KERNEL_FN float light_tree_share(const Scene *scene)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    return integrator->light_count > integrator->unbounded_lights ? 1.0f / (float)(integrator->unbounded_lights + 1u)
                                                                  : 0.0f;
}

/* The light to sample for shading point p of geometric normal n, and the
 * chance it was picked (*pmf); -1 if none may light p. */
KERNEL_FN int pick_light_at(const Scene *scene, Vec3 p, Vec3 n, float u, float *pmf)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    if (integrator->light_sampler != LIGHT_SAMPLER_TREE) {
        int i = pick_light(scene->lights, integrator->light_count, u);
        *pmf = scene->lights[i].pick_probability;
        return i;
    }
    float share = light_tree_share(scene);
    if (u < share) {
        int i = light_tree_sample(scene->light_nodes, p, n, fmin(u / share, 0x1.fffffep-1f), pmf);
        *pmf *= share;
        return i;
    }
    uint32_t unbounded = integrator->unbounded_lights;
    uint32_t i = (uint32_t)((u - share) / (1.0f - share) * (float)unbounded);
    i = i < unbounded ? i : unbounded - 1u;
    *pmf = scene->lights[i].pick_probability;
    return (int)i;
}

/* The chance pick_light_at picks `light` for shading point p of normal n. */
KERNEL_FN float light_pick_pmf(const Scene *scene, GLOBAL const Light *light, Vec3 p, Vec3 n)
{
    GLOBAL const IntegratorData *integrator = &scene->constants->integrator;
    uint32_t index = (uint32_t)(light - scene->lights);
    if (integrator->light_sampler != LIGHT_SAMPLER_TREE || index < integrator->unbounded_lights)
        return light->pick_probability;
    return light_tree_share(scene) *
           light_tree_pmf(scene->light_nodes, scene->light_trails[index - integrator->unbounded_lights], p, n);
}

/* Samples light `light` from point p with normal n: its type's function
 * (scene_types.h's GMON_LIGHT_TYPES). Returns 0 when it cannot light p. */
KERNEL_FN int light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2, LightSample *s)
{
    s->is_delta = 0;
    s->distance = INFINITY;
#define LIGHT_SAMPLE_(id, feature, sample, emit)                                                                       \
    if (GMON_HAS(feature) && light->type == LIGHT_##id)                                                                \
        return sample(scene, light, p, u1, u2, s);
    GMON_LIGHT_TYPES(LIGHT_SAMPLE_)
#undef LIGHT_SAMPLE_
    return 0;
}

/* Samples a ray leaving light `light`: its type's function (scene_types.h's
 * GMON_LIGHT_TYPES). Returns 0 when none was sampled. */
KERNEL_FN int light_sample_emission(const Scene *scene, GLOBAL const Light *light, float u1, float u2, float u3,
                                    float u4, LightEmission *e)
{
#define LIGHT_EMIT_(id, feature, sample, emit)                                                                         \
    if (GMON_HAS(feature) && light->type == LIGHT_##id)                                                                \
        return emit(scene, light, u1, u2, u3, u4, e);
    GMON_LIGHT_TYPES(LIGHT_EMIT_)
#undef LIGHT_EMIT_
    return 0;
}

#endif
