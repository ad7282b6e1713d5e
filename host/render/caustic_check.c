#include "render/caustic_check.h"

#include "lights.h"

#include <stdio.h>
#include <string.h>

static const char *light_type_name(uint32_t type)
{
    switch (type) {
    case LIGHT_POINT:
        return "point";
    case LIGHT_SPOT:
        return "spot";
    case LIGHT_GONIOMETRIC:
        return "goniometric";
    case LIGHT_PROJECTION:
        return "projection";
    }
    return "delta";
}

/* The share of light's power that first meets a specular surface, from
 * `directions` rays of its emission sampler on a stratified grid. */
static double specular_share(const Scene *scene, const Light *light, int directions)
{
    int side = 1;
    while (side * side < directions)
        ++side;
    double total = 0.0, specular = 0.0;
    for (int i = 0; i < side * side; ++i) {
        float u1 = ((float)(i % side) + 0.5f) / (float)side, u2 = ((float)(i / side) + 0.5f) / (float)side;
        LightEmission e;
        if (!light_sample_emission(scene, light, u1, u2, 0.5f, 0.5f, &e))
            continue;
        double power = (e.radiance.x + e.radiance.y + e.radiance.z) / e.pdf_direction;
        total += power;
        Ray ray = make_ray(e.origin, e.direction);
        Hit hit;
        if (!scene_intersect(scene, &ray, 0.0f, INFINITY, 0, &hit))
            continue;
        const Primitive *prim = scene->primitives + hit.primitive;
        Material m = scene->materials[prim->material];
        if (m.type != MAT_MIX && bsdf_is_delta(&m))
            specular += power;
    }
    return total > 0.0 ? specular / total : 0.0;
}

int caustic_check(const RenderScene *rs, char *message, size_t size)
{
    if (size)
        message[0] = '\0';
    if (rs->constants.integrator.flags & (RENDER_BDPT | RENDER_LIGHTPATH))
        return 0;
    Scene scene;
    RenderSceneArrays arrays = render_scene_arrays(rs);
    scene.constants = &rs->constants;
#define CAUSTIC_SCENE_ARRAY_(name, type) scene.name = arrays.name;
    GMON_SCENE_ARRAYS(CAUSTIC_SCENE_ARRAY_)
#undef CAUSTIC_SCENE_ARRAY_
    int found = 0;
    size_t used = 0;
    for (int i = 0; i < rs->light_count; ++i) {
        const Light *light = &rs->lights[i];
        if (light->type != LIGHT_POINT && light->type != LIGHT_SPOT && light->type != LIGHT_GONIOMETRIC &&
            light->type != LIGHT_PROJECTION)
            continue;
        double share = specular_share(&scene, light, 4096);
        if (share < 0.01)
            continue;
        ++found;
        int n = snprintf(message + used, used < size ? size - used : 0,
                         "%sthe %s light at (%g, %g, %g) sends %.0f%% of its power first to specular surfaces",
                         found > 1 ? "\n" : "", light_type_name(light->type), (double)light->position[0],
                         (double)light->position[1], (double)light->position[2], 100.0 * share);
        used += n > 0 ? (size_t)n : 0;
    }
    return found;
}

void caustic_check_print(const RenderScene *scene, FILE *out, const char *prefix)
{
    char message[4096];
    if (!caustic_check(scene, message, sizeof message))
        return;
    for (char *line = message; line && *line;) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        fprintf(out,
                "%swarning: %s: the path tracer renders none of the light it casts on diffuse surfaces through them "
                "(no camera path reaches a delta light through a specular surface); Integrator \"bdpt\" renders "
                "it\n",
                prefix, line);
        line = end ? end + 1 : NULL;
    }
}
