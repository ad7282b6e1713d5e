/* The path tracer's blind spot: a delta light (point, spot, goniometric,
 * projection) whose light reaches diffuse surfaces through specular ones
 * (glass, mirrors) casts caustics no camera path can find. */
#ifndef HOST_RENDER_CAUSTIC_CHECK_H
#define HOST_RENDER_CAUSTIC_CHECK_H

#include "render/render_scene.h"

#include <stddef.h>
#include <stdio.h>

/* For a scene rendered by the path tracer (not bdpt or lightpath): the
 * delta lights that send at least 1% of their power (over 4096 directions
 * drawn from their emission) first to a specular surface, each named in a
 * line of `message` ("the spot light at (0, 5, 9) sends 12% of its power
 * first to specular surfaces"). Returns their count (0 with bdpt). A
 * conservative sign: such light may end on a diffuse surface the camera
 * sees, which the path tracer then renders without it. Distant lights are
 * not checked (no emission sampler yet). */
int caustic_check(const RenderScene *scene, char *message, size_t size);

/* Prints caustic_check's lights as warnings to `out`, each line after
 * `prefix` ("gmonrt: " or ""). */
void caustic_check_print(const RenderScene *scene, FILE *out, const char *prefix);

#endif
