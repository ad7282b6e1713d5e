#include "scene/instance_check.h"

#include <math.h>
#include <stdlib.h>

/* The box of object k's shapes in its own space. */
static void object_bounds(const Scene *s, size_t k, float bounds[2][3])
{
    for (int i = 0; i < 3; ++i) {
        bounds[0][i] = INFINITY;
        bounds[1][i] = -INFINITY;
    }
    const SceneObject *object = &s->objects[k];
    for (size_t j = object->first_shape; j < object->first_shape + object->shape_count; ++j) {
        const SceneShape *shape = &s->shapes[j];
        for (size_t t = shape->first; t < shape->first + shape->count; ++t) {
            if (shape->kind == SCENE_SHAPE_SPHERE) {
                const SceneSphere *sphere = &s->spheres[t];
                for (int i = 0; i < 3; ++i) {
                    bounds[0][i] = fminf(bounds[0][i], sphere->center[i] - sphere->radius);
                    bounds[1][i] = fmaxf(bounds[1][i], sphere->center[i] + sphere->radius);
                }
                continue;
            }
            for (int corner = 0; corner < 3; ++corner) {
                const float *v = &s->positions[3 * (size_t)s->triangles[t].vertex[corner]];
                for (int i = 0; i < 3; ++i) {
                    bounds[0][i] = fminf(bounds[0][i], v[i]);
                    bounds[1][i] = fmaxf(bounds[1][i], v[i]);
                }
            }
        }
    }
}

/* The largest factor by which m's columns (of a 3x3 matrix, [row][column])
 * scale the axes' unit vectors: within a factor sqrt(3) of the largest
 * factor m scales any length by. */
static double largest_column(double m[3][3])
{
    double largest = 0.0;
    for (int c = 0; c < 3; ++c)
        largest = fmax(largest, sqrt(m[0][c] * m[0][c] + m[1][c] * m[1][c] + m[2][c] * m[2][c]));
    return largest;
}

int scene_check_instance(Diagnostics *diag, InstanceCheck *check, size_t index, const char *file, int line)
{
    const Scene *s = diag->scene;
    const SceneInstance *instance = &s->instances[index];
    const char *name = s->objects[instance->object].name;
    const float(*m)[4] = instance->world_from_object; /* [column][row] */
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
        return scene_error(diag, file, line, "ObjectInstance \"%s\": a projective transform is not supported", name);
    double linear[3][3], inverse[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            linear[r][c] = m[c][r];
    double det = linear[0][0] * (linear[1][1] * linear[2][2] - linear[1][2] * linear[2][1]) -
                 linear[0][1] * (linear[1][0] * linear[2][2] - linear[1][2] * linear[2][0]) +
                 linear[0][2] * (linear[1][0] * linear[2][1] - linear[1][1] * linear[2][0]);
    if (!(fabs(det) > 0.0) || !isfinite(det))
        return scene_error(diag, file, line,
                           "ObjectInstance \"%s\": the transform is singular (it flattens the object to no volume)",
                           name);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) { /* the cofactor of (c, r) over the determinant */
            int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
            inverse[r][c] = (linear[r0][c0] * linear[r1][c1] - linear[r0][c1] * linear[r1][c0]) / det;
        }
    double largest = largest_column(linear), smallest = 1.0 / largest_column(inverse);
    if (!(largest <= SCENE_MAX_COORDINATE) || !(smallest >= SCENE_MIN_INSTANCE_SCALE))
        return scene_error(diag, file, line,
                           "ObjectInstance \"%s\": the transform scales lengths by %g, outside [%g, %g] (the "
                           "renderer intersects the object in its own space, in single precision)",
                           name, largest > SCENE_MAX_COORDINATE ? largest : smallest, SCENE_MIN_INSTANCE_SCALE,
                           SCENE_MAX_COORDINATE);

    if (!check->bounds) {
        check->bounds = malloc((s->object_count ? s->object_count : 1) * sizeof *check->bounds);
        if (!check->bounds)
            return scene_error(diag, file, line, "out of memory");
        check->object_count = s->object_count;
        for (size_t k = 0; k < s->object_count; ++k)
            check->bounds[k][0][0] = NAN; /* not computed yet */
    }
    float(*bounds)[3] = check->bounds[instance->object];
    if (isnan(bounds[0][0]))
        object_bounds(s, (size_t)instance->object, bounds);
    if (bounds[0][0] > bounds[1][0])
        return 0; /* no geometry: nothing drawn */
    for (int corner = 0; corner < 8; ++corner) {
        double p[3] = {bounds[corner & 1][0], bounds[corner >> 1 & 1][1], bounds[corner >> 2 & 1][2]}, w[3];
        for (int r = 0; r < 3; ++r)
            w[r] = m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + (double)m[3][r];
        if (!(fabs(w[0]) <= SCENE_MAX_COORDINATE && fabs(w[1]) <= SCENE_MAX_COORDINATE &&
              fabs(w[2]) <= SCENE_MAX_COORDINATE))
            return scene_error(diag, file, line,
                               "ObjectInstance \"%s\": the instance reaches (%g, %g, %g) in world space, beyond %g "
                               "from the origin (the renderer squares distances in single precision)",
                               name, w[0], w[1], w[2], SCENE_MAX_COORDINATE);
    }
    return 0;
}

void instance_check_free(InstanceCheck *check)
{
    free(check->bounds);
    check->bounds = NULL;
    check->object_count = 0;
}
