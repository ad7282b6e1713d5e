/* Bidirectional path tracing's multiple importance sampling
 * (kernels/tracing/bdpt.h), on the host: the weights mis_weight gives the
 * strategies that make one path sum to 1. */
#include "bdpt.h"
#include "render/render_scene.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* The host's view of a converted scene, as the kernels' Scene. */
static Scene host_scene(const RenderScene *rs)
{
    Scene scene;
    RenderSceneArrays arrays = render_scene_arrays(rs);
    scene.constants = &rs->constants;
#define HOST_SCENE_ARRAY_(name, type) scene.name = arrays.name;
    GMON_SCENE_ARRAYS(HOST_SCENE_ARRAY_)
#undef HOST_SCENE_ARRAY_
    return scene;
}

/* The subpaths that strategy (s, t) splits full path x[0..n) into (x[0]
 * the camera, x[n - 1] on a light), with the densities a random walk
 * gives each vertex in its own direction (vertex_pdf), as the kernels'
 * subpaths hold them. */
static void split_path(const Scene *scene, const PathVertex *x, int n, int s, PathVertex *light, PathVertex *camera)
{
    int t = n - s;
    for (int i = 0; i < t; ++i) {
        camera[i] = x[i];
        camera[i].radiance = 1;
        camera[i].pdf_fwd = i == 0 ? 0.0f : vertex_pdf(scene, i >= 2 ? &x[i - 2] : NULL, &x[i - 1], &x[i]);
        camera[i].pdf_rev = i + 2 < t ? vertex_pdf(scene, &x[i + 2], &x[i + 1], &x[i]) : 0.0f;
    }
    for (int j = 0; j < s; ++j) {
        int i = n - 1 - j; /* light[j] is x[i] */
        light[j] = x[i];
        light[j].radiance = 0;
        if (j == 0)
            light[j].pdf_fwd = vertex_pdf_light_origin(scene, &x[i]);
        else
            light[j].pdf_fwd = vertex_pdf(scene, j >= 2 ? &x[i + 2] : NULL, &x[i + 1], &x[i]);
        light[j].pdf_rev = j + 2 < s ? vertex_pdf(scene, &x[i - 2], &x[i - 1], &x[i]) : 0.0f;
    }
}

/* The MIS weights of every strategy that makes a path sum to 1: full
 * paths of 3 to 6 vertices inside a diffuse sphere with a floor and a
 * small emitting sphere (a camera walk's vertices, then a point of the
 * light), each split at every (s, t) with t >= 1, the subpaths' densities
 * as the walks set them, and mis_weight of each (with the sampled vertex
 * of s = 1 or t = 1). */
static void test_mis_weights_sum_to_one(void **state)
{
    (void)state;
    char error[256];
    RenderScene rs;
    render_scene_init(&rs);
    Material white;
    memset(&white, 0, sizeof white);
    white.type = MAT_DIFFUSE;
    white.reflectance[0] = white.reflectance[1] = white.reflectance[2] = 0.7f;
    int material = render_scene_add_material(&rs, &white);
    const float centre[3] = {0, 0, 0}, lamp[3] = {0.5f, 1.2f, 0.8f}, emission[3] = {5, 5, 5};
    const float a[3] = {-2, -1, -2}, b[3] = {2, -1, 0}, c[3] = {0, -1, 2};
    assert_int_equal(render_scene_add_sphere(&rs, lamp, 0.4f, material, emission, 0, 0), 0);
    assert_int_equal(render_scene_add_sphere(&rs, centre, 3.0f, material, NULL, 0, 1), 0);
    assert_int_equal(render_scene_add_triangle(&rs, a, b, c, material, NULL, 0, 0), 0);
    const float position[3] = {0, 0, -2}, forward[3] = {0, 0, 1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    RenderCamera view = render_camera_pinhole(position, forward, right, up, 0.8f, 0.8f, 16, 16);
    render_scene_set_camera(&rs, &view);
    rs.constants.integrator.flags = RENDER_BDPT;
    assert_int_equal(render_scene_finalize(&rs, error, sizeof error), 0);
    Scene scene = host_scene(&rs);
    const Light *light_source = &rs.lights[0];
    assert_int_equal(light_source->type, LIGHT_AREA);
    int checked = 0;
    double worst = 0.0;
    for (uint64_t sample = 0; sample < 400; ++sample) {
        SampleStream stream = sample_stream(SAMPLER_INDEPENDENT, 11, 3, sample, 1);
        CameraRay ray = camera_ray(&rs.constants.camera, &rs.constants.filter, scene.distributions, 7, 9, &stream);
        PathVertex walk[8], x[8], light[8], camera[8];
        memset(walk, 0, sizeof walk);
        walk[0].type = VERTEX_CAMERA;
        walk[0].surface.p = ray.origin;
        walk[0].beta = vec3(1.0f, 1.0f, 1.0f);
        walk[0].light = -1;
        walk[0].radiance = 1;
        uint32_t rays = 0;
        int count = random_walk(&scene, &stream, walk, 1, 6, ray.origin, ray.direction, walk[0].beta,
                                camera_pdf_direction(&rs.constants.camera, ray.direction), 1, &rays);
        for (int n = 3; n <= count + 1; ++n) {
            /* x[0..n-1) from the walk, x[n - 1] a point of the light. */
            memcpy(x, walk, sizeof x[0] * (size_t)(n - 1));
            if (x[n - 2].light >= 0)
                continue; /* keep the light at the end */
            PathVertex *end = &x[n - 1];
            memset(end, 0, sizeof *end);
            end->type = VERTEX_LIGHT;
            end->light = 0;
            float u1, u2;
            sample_2d(&stream, 0x7000u + (uint32_t)n, &u1, &u2);
            const Primitive *prim = scene.primitives + light_source->primitive;
            end->surface.p = sample_primitive(prim, u1, u2);
            end->surface.n = end->surface.ns = surface_normal(prim, end->surface.p);
            double sum = 0.0;
            for (int s = 0; s < n; ++s) {
                int t = n - s;
                split_path(&scene, x, n, s, light, camera);
                PathVertex sampled;
                if (t == 1) {
                    sampled = x[0];
                    camera[0] = sampled;
                } else if (s == 1) {
                    sampled = light[0];
                }
                sum += mis_weight(&scene, light, camera, &sampled, s, t);
            }
            worst = fabs(sum - 1.0) > worst ? fabs(sum - 1.0) : worst;
            if (fabs(sum - 1.0) > 1e-4)
                printf("  sample %llu, %d vertices: weights sum to %.7f\n", (unsigned long long)sample, n, sum);
            ++checked;
        }
    }
    printf("  %d paths of 3 to 6 vertices: the weights of all their strategies sum to 1 within %.2g\n", checked, worst);
    assert_true(checked > 100);
    assert_true(worst <= 1e-4);
    render_scene_destroy(&rs);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mis_weights_sum_to_one),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
