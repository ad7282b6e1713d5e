/* Checks of ObjectInstance transforms against what the renderer can draw:
 * the limits non-instanced shapes meet in the parser, applied to an
 * object's geometry as each instance places it. Not part of the public API. */
#ifndef HOST_SCENE_INSTANCE_CHECK_H
#define HOST_SCENE_INSTANCE_CHECK_H

#include "scene/scene_internal.h"

#include <stddef.h>

/* An instance's transform may scale lengths by at most
 * SCENE_MAX_COORDINATE and at least its inverse: the kernels traverse an
 * object's tree with the ray in object space, and a direction scaled by
 * more would overflow single precision when squared, one scaled by less
 * would underflow it. */
#define SCENE_MIN_INSTANCE_SCALE (1.0 / SCENE_MAX_COORDINATE)

/* Each object's bounds, computed once for all its instances. */
typedef struct {
    float (*bounds)[2][3]; /* per object: lower, upper (lower > upper: empty) */
    size_t object_count;
} InstanceCheck;

/* Refuses instance `index` of diag->scene (its object resolved), at
 * file:line, when its transform is projective, singular, scales lengths
 * beyond [SCENE_MIN_INSTANCE_SCALE, SCENE_MAX_COORDINATE], or places its
 * object beyond SCENE_MAX_COORDINATE from the origin. Returns 0, or -1
 * with "file:line: ObjectInstance \"name\": ..." in the error. */
int scene_check_instance(Diagnostics *diag, InstanceCheck *check, size_t index, const char *file, int line);

void instance_check_free(InstanceCheck *check);

#endif
