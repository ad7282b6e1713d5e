#include "render/scene_convert.h"

#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static Material convert_material(const SceneMaterial *in)
{
    Material m;
    memset(&m, 0, sizeof m);
    float alpha[2];
    scene_material_alpha(in, alpha);
    m.alpha_x = alpha[0];
    m.alpha_y = alpha[1];
    m.eta = in->eta;
    memcpy(m.reflectance, in->reflectance, sizeof m.reflectance);
    switch (in->type) {
    case SCENE_MATERIAL_DIFFUSE:
        m.type = MAT_DIFFUSE;
        break;
    case SCENE_MATERIAL_DIELECTRIC:
        m.type = MAT_DIELECTRIC;
        break;
    case SCENE_MATERIAL_COATED_DIFFUSE:
        m.type = MAT_COATED_DIFFUSE;
        break;
    case SCENE_MATERIAL_CONDUCTOR:
        m.type = MAT_CONDUCTOR;
        for (int c = 0; c < 3; ++c) {
            if (in->use_reflectance) {
                /* pbrt-v4: a reflectance r is a conductor with eta = 1 and
                 * k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence
                 * reflectance is r. */
                float r =
                    in->reflectance[c] < 0.0f ? 0.0f : (in->reflectance[c] > 0.9999f ? 0.9999f : in->reflectance[c]);
                m.conductor_eta[c] = 1.0f;
                m.conductor_k[c] = 2.0f * sqrtf(r) / sqrtf(1.0f - r);
            } else {
                m.conductor_eta[c] = in->conductor_eta[c];
                m.conductor_k[c] = in->conductor_k[c];
            }
        }
        break;
    }
    return m;
}

_Static_assert((int)SCENE_MAX_FILTER_RADIUS == (int)PIXEL_FILTER_MAX_RADIUS, "the parser checks the renderer's limit");

/* The camera and the pixel filter, for a width x height image. Returns 0,
 * or -1 with the reason in `why`. */
static int convert_camera(const Scene *scene, unsigned width, unsigned height, RenderScene *out, char *why,
                          size_t why_size)
{
    const SceneCamera *in = &scene->camera;
    RenderCamera camera;
    memset(&camera, 0, sizeof camera);
    camera.projection = in->projection == SCENE_CAMERA_ORTHOGRAPHIC ? CAMERA_ORTHOGRAPHIC : CAMERA_PERSPECTIVE;
    memcpy(camera.position, in->position, sizeof camera.position);
    memcpy(camera.forward, in->forward, sizeof camera.forward);
    memcpy(camera.right, in->right, sizeof camera.right);
    memcpy(camera.up, in->up, sizeof camera.up);
    scene_camera_window(in, width, height, camera.window);
    for (int i = 0; i < 4; ++i)
        if (!isfinite(camera.window[i])) {
            snprintf(why, why_size, "Camera: the screen window overflows single precision");
            return -1;
        }
    camera.lens_radius = in->lens_radius;
    camera.focal_distance = in->focal_distance;
    camera.width = width;
    camera.height = height;
    render_scene_set_camera(out, &camera);

    static const PixelFilterType types[] = {
        [SCENE_FILTER_BOX] = PIXEL_FILTER_BOX,           [SCENE_FILTER_GAUSSIAN] = PIXEL_FILTER_GAUSSIAN,
        [SCENE_FILTER_MITCHELL] = PIXEL_FILTER_MITCHELL, [SCENE_FILTER_LANCZOS] = PIXEL_FILTER_LANCZOS,
        [SCENE_FILTER_TRIANGLE] = PIXEL_FILTER_TRIANGLE,
    };
    const SceneFilter *f = &scene->filter;
    PixelFilter filter = {types[f->type], {f->radius[0], f->radius[1]}, f->sigma, f->b, f->c, f->tau};
    char reason[192];
    if (render_scene_set_filter(out, &filter, reason, sizeof reason)) {
        snprintf(why, why_size, "PixelFilter: %s", reason);
        return -1;
    }
    return 0;
}

int scene_convert_load(const char *path, int allow_unsupported, unsigned width, unsigned height, int quiet,
                       RenderScene *out, SceneSummary *summary, char *error, size_t error_size)
{
    memset(summary, 0, sizeof *summary);
    render_scene_init(out);
    Scene scene;
    SceneLoadOptions options = {allow_unsupported};
    if (scene_load(path, &options, &scene, error, error_size))
        return -1;
    for (size_t i = 0; i < scene.warning_count && !quiet; ++i)
        fprintf(stderr, "%s\n", scene.warnings[i]); /* "file:line: warning: ..." */

    if (scene.film_filename)
        snprintf(summary->film_filename, sizeof summary->film_filename, "%s", scene.film_filename);
    if (scene.sampler)
        snprintf(summary->sampler, sizeof summary->sampler, "%s", scene.sampler);
    summary->pixel_samples = scene.spp;
    summary->regularize = scene.regularize;

    if (width == 0 || height == 0) {
        width = scene.width;
        height = scene.height;
    }
    char why[256];
    if (convert_camera(&scene, width, height, out, why, sizeof why)) {
        snprintf(error, error_size, "%s: %s", path, why);
        scene_destroy(&scene);
        render_scene_destroy(out);
        return -1;
    }
    out->constants.integrator.max_depth = scene.max_depth >= 0 ? (uint32_t)scene.max_depth : 5u;

    int failed = 0;
    if (scene.has_environment)
        failed = render_scene_add_infinite_light(out, scene.environment) != 0;
    for (size_t i = 0; i < scene.material_count && !failed; ++i) {
        Material m = convert_material(&scene.materials[i]);
        summary->coated_diffuse |= m.type == MAT_COATED_DIFFUSE;
        failed = render_scene_add_material(out, &m) < 0;
    }
    for (size_t i = 0; i < scene.triangle_count && !failed; ++i) {
        const SceneTriangle *t = &scene.triangles[i];
        const SceneShape *shape = &scene.shapes[t->shape];
        const SceneAreaLight *light = shape->area_light >= 0 ? &scene.area_lights[shape->area_light] : NULL;
        failed = render_scene_add_triangle(
                     out, &scene.positions[3 * (size_t)t->vertex[0]], &scene.positions[3 * (size_t)t->vertex[1]],
                     &scene.positions[3 * (size_t)t->vertex[2]], shape->material, light ? light->radiance : NULL,
                     light && light->two_sided, shape->flip_normal) != 0;
    }
    for (size_t i = 0; i < scene.sphere_count && !failed; ++i) {
        const SceneSphere *sphere = &scene.spheres[i];
        const SceneShape *shape = &scene.shapes[sphere->shape];
        const SceneAreaLight *light = shape->area_light >= 0 ? &scene.area_lights[shape->area_light] : NULL;
        failed =
            render_scene_add_sphere(out, sphere->center, sphere->radius, shape->material,
                                    light ? light->radiance : NULL, light && light->two_sided, shape->flip_normal) != 0;
    }
    scene_destroy(&scene);
    if (failed) {
        snprintf(error, error_size, "%s: out of memory converting the scene", path);
        render_scene_destroy(out);
        return -1;
    }
    if (out->light_count == 0 && !quiet)
        fprintf(stderr, "warning: %s: the scene has no light: the image will be black\n", path);
    if (summary->coated_diffuse && !quiet)
        fprintf(stderr,
                "warning: %s: \"coateddiffuse\" is approximated: a Fresnel-weighted dielectric coat "
                "over a Lambertian base, without inter-reflection between them\n",
                path);
    return 0;
}
