/* Distant lights: radiance arriving from one direction. */
#ifndef KERNELS_LIGHT_DISTANT_H
#define KERNELS_LIGHT_DISTANT_H

#include "light_common.h"

KERNEL_FN int distant_light_sample(const Scene *scene, GLOBAL const Light *light, Vec3 p, float u1, float u2,
                                   LightSample *s)
{
    (void)scene;
    (void)p;
    (void)u1;
    (void)u2;
    s->wi = vec3_from_global(light->direction);
    s->radiance = vec3_from_global(light->radiance);
    s->pdf = 1.0f;
    s->is_delta = 1;
    return 1;
}

#endif
