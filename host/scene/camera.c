/* The directives before WorldBegin that set up the camera and the image:
 * Camera, Film, PixelFilter, Sampler, Integrator and Accelerator, and the
 * camera's basis and the film matrix once the whole scene is read. */
#include "scene/camera.h"

#include "scene/geometry.h"
#include "scene/spectrum.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Camera "screenwindow": x_min x_max y_min y_max, each pair apart. */
static int read_screen_window(ParamList *params, SceneCamera *camera)
{
    const Param *window = NULL;
    int found = params_get_array(params, "screenwindow", PARAM_FLOAT, &window);
    if (found <= 0)
        return found;
    if (window->count != 4)
        return params_error(params, window, "expected 4 values (x_min x_max y_min y_max), got %zu", window->count);
    if (window->numbers[0] == window->numbers[1] || window->numbers[2] == window->numbers[3])
        return params_error(params, window, "the window is empty (x_min = x_max or y_min = y_max)");
    for (int i = 0; i < 4; ++i)
        camera->screen_window[i] = (float)window->numbers[i];
    camera->has_screen_window = 1;
    return 0;
}

int on_camera(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the camera type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0)
        result = warn_if_moving(p, lex, d);
    int orthographic = result == 0 && token_is(&type, "orthographic");
    if (result == 0 && !orthographic && !token_is(&type, "perspective")) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line,
                                   "a \"perspective\" camera (fov 90) is used, and its parameters other than the "
                                   "shutter times are ignored",
                                   "Camera %s is not supported (only \"perspective\" and \"orthographic\")", shown);
        /* realistic's lens, spherical's mapping: nothing a perspective camera has */
        for (size_t i = 0; result == 0 && i < params.count; ++i)
            if (strcmp(params.items[i].name, "shutteropen") != 0 && strcmp(params.items[i].name, "shutterclose") != 0)
                params_ignore(&params, params.items[i].name);
    }
    const char *kind = orthographic ? "orthographic" : "perspective";
    SceneCamera camera; /* a Camera given twice replaces the first */
    memset(&camera, 0, sizeof camera);
    camera.projection = orthographic ? SCENE_CAMERA_ORTHOGRAPHIC : SCENE_CAMERA_PERSPECTIVE;
    /* pbrt-v4's defaults; frame NAN: not given (the film's aspect ratio). */
    float fov = 90.0f, lens_radius = 0.0f, focal_distance = 1e6f, frame = NAN;
    if (result == 0 &&
        ((!orthographic && params_get_float(&params, "fov", &fov) < 0) ||
         params_get_float(&params, "lensradius", &lens_radius) < 0 ||
         params_get_float(&params, "focaldistance", &focal_distance) < 0 ||
         params_get_float(&params, "frameaspectratio", &frame) < 0 || read_screen_window(&params, &camera) < 0 ||
         params_get_float(&params, "shutteropen", &p->shutter_open) < 0 ||
         params_get_float(&params, "shutterclose", &p->shutter_close) < 0))
        result = -1;
    if (result == 0 && !(fov > 0.0f && fov < 180.0f))
        result =
            scene_error(&p->diag, lex->path, d->line, "Camera \"perspective\": fov %g is not in (0, 180)", (double)fov);
    if (result == 0 && lens_radius < 0.0f)
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": lensradius %g is negative", kind,
                             (double)lens_radius);
    if (result == 0 && !(focal_distance > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": focaldistance %g is not positive", kind,
                             (double)focal_distance);
    if (result == 0 && !isnan(frame) && !(frame > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Camera \"%s\": frameaspectratio %g is not positive", kind,
                             (double)frame);
    if (result == 0)
        result = params_check_unused(&params);
    mat4 world_from_camera;
    if (result == 0 && (det3(p->state.ctm) == 0.0 || invert_in_double(p->state.ctm, world_from_camera)))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Camera: the camera transform is singular (or its inverse overflows single precision)");
    const float origin[3] = {0.0f, 0.0f, 0.0f};
    float position[3];
    if (result == 0)
        transform_point(world_from_camera, origin, position);
    if (result == 0 && !within_range(position))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Camera: the camera is at (%g, %g, %g), beyond %g from the origin (the renderer squares "
                             "distances in single precision)",
                             (double)position[0], (double)position[1], (double)position[2], SCENE_MAX_COORDINATE);
    if (result == 0) {
        glm_mat4_copy(p->state.ctm, p->camera_from_world);
        glm_mat4_copy(world_from_camera, p->world_from_camera);
        /* pbrt-v4's "camera" space; a moving camera is rendered at the start time. */
        if (define_coordinate_system(p, "camera", 6, world_from_camera, world_from_camera))
            result = out_of_memory(p, lex->path, d->line);
        camera.fov = fov;
        camera.lens_radius = lens_radius; /* camera space until finish_camera */
        camera.focal_distance = focal_distance;
        camera.frame_aspect_ratio = isnan(frame) ? 0.0f : frame;
        p->scene->camera = camera;
        p->camera_file = lex->path;
        p->camera_line = d->line;
        p->scene->camera_medium = p->state.medium_outside; /* pbrt-v4's camera medium */
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's "cropwindow" (fractions x0 x1 y0 y1 of the image, clamped to
 * [0, 1], either order) or "pixelbounds" (pixels x0 x1 y0 y1, clamped to
 * the image; the crop window wins when both are given), as a crop window. */
static int read_film_crop(Parser *p, Lexer *lex, const Token *d, ParamList *params, int width, int height,
                          float crop[4])
{
    const Param *window = NULL, *bounds = NULL;
    int has_window = params_get_array(params, "cropwindow", PARAM_FLOAT, &window);
    int has_bounds = params_get_array(params, "pixelbounds", PARAM_INTEGER, &bounds);
    if (has_window < 0 || has_bounds < 0)
        return -1;
    if (has_window && window->count != 4)
        return params_error(params, window, "expected 4 values (x0 x1 y0 y1), got %zu", window->count);
    if (has_bounds && bounds->count != 4)
        return params_error(params, bounds, "expected 4 values (x0 x1 y0 y1), got %zu", bounds->count);
    const int size[2] = {width, height};
    for (int axis = 0; axis < 2; ++axis) {
        double a = 0.0, b = 1.0;
        if (has_window) {
            a = fmin(window->numbers[2 * axis], window->numbers[2 * axis + 1]);
            b = fmax(window->numbers[2 * axis], window->numbers[2 * axis + 1]);
        } else if (has_bounds) {
            a = bounds->numbers[2 * axis] / size[axis];
            b = bounds->numbers[2 * axis + 1] / size[axis];
        }
        crop[2 * axis] = (float)fmin(fmax(a, 0.0), 1.0);
        crop[2 * axis + 1] = (float)fmin(fmax(b, 0.0), 1.0);
        float lo = (float)size[axis] * crop[2 * axis], hi = (float)size[axis] * crop[2 * axis + 1];
        if (ceilf(lo) >= ceilf(hi)) /* in single precision, as pbrt-v4 */
            return scene_error(&p->diag, lex->path, d->line, "Film: the %s leaves no pixel",
                               has_window ? "crop window" : "pixel bounds");
    }
    return 0;
}

int on_film(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    Scene *s = p->scene;
    int result = read_typed_directive(p, lex, d, "the film type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0 && token_is(&type, "gbuffer")) {
        /* pbrt-v4's gbuffer film adds geometry channels to the same RGB. */
        result =
            scene_warn(&p->diag, lex->path, d->line, "Film \"gbuffer\": rendered as \"rgb\" (no geometry channels)");
        params_ignore(&params, "coordinatesystem");
    } else if (result == 0 && !token_is(&type, "rgb")) {
        result = scene_unsupported(&p->diag, lex->path, d->line, "an \"rgb\" film is used",
                                   "Film: only \"rgb\" and \"gbuffer\" are supported");
    }
    int width = (int)s->width, height = (int)s->height, save_fp16 = s->save_fp16;
    const char *filename = NULL, *sensor = "cie1931";
    float iso = 100.0f, scale = 1.0f, white_balance = 0.0f, max_component = INFINITY, diagonal = s->film_diagonal;
    if (result == 0 &&
        (params_get_int(&params, "xresolution", &width) < 0 || params_get_int(&params, "yresolution", &height) < 0 ||
         params_get_string(&params, "filename", &filename) < 0 || params_get_float(&params, "iso", &iso) < 0 ||
         params_get_float(&params, "scale", &scale) < 0 ||
         params_get_float(&params, "whitebalance", &white_balance) < 0 ||
         params_get_string(&params, "sensor", &sensor) < 0 ||
         params_get_float(&params, "maxcomponentvalue", &max_component) < 0 ||
         params_get_float(&params, "diagonal", &diagonal) < 0 || params_get_bool(&params, "savefp16", &save_fp16) < 0))
        result = -1;
    if (result == 0 && (width < 1 || height < 1 || width > 65536 || height > 65536))
        result = scene_error(&p->diag, lex->path, d->line, "Film: resolution %d x %d is out of range", width, height);
    if (result == 0 && !(iso > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: iso %g must be positive", (double)iso);
    if (result == 0 && !(scale > 0.0f && scale < INFINITY))
        result = scene_error(&p->diag, lex->path, d->line, "Film: scale %g must be positive and finite", (double)scale);
    if (result == 0 && (white_balance < 0.0f || white_balance > 1e5f))
        result = scene_error(&p->diag, lex->path, d->line,
                             "Film: whitebalance %g K is not 0 (none) or a temperature up to 100000 K",
                             (double)white_balance);
    if (result == 0 && !(max_component > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: maxcomponentvalue %g must be positive",
                             (double)max_component);
    if (result == 0 && !(diagonal > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Film: diagonal %g must be positive", (double)diagonal);
    if (result == 0 && (!spectrum_sensor_known(sensor) || strlen(sensor) >= sizeof p->film_sensor)) {
        char known[1024];
        spectrum_sensor_list(known, sizeof known);
        result = scene_error(&p->diag, lex->path, d->line, "Film: unknown sensor \"%s\" (%s)", sensor, known);
    }
    float crop[4] = {0.0f, 1.0f, 0.0f, 1.0f};
    if (result == 0)
        result = read_film_crop(p, lex, d, &params, width, height, crop);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0 && filename)
        result = replace_string(p, lex->path, d->line, &s->film_filename, filename);
    if (result == 0) {
        memcpy(s->crop_window, crop, sizeof crop);
        s->width = (unsigned)width;
        s->height = (unsigned)height;
        s->max_component_value = max_component;
        s->save_fp16 = save_fp16;
        s->film_diagonal = diagonal;
        p->film_iso = iso;
        p->film_scale = scale;
        p->film_white_balance = white_balance;
        snprintf(p->film_sensor, sizeof p->film_sensor, "%s", sensor);
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's imaging ratio takes the exposure from the camera's shutter;
 * the film's "scale" multiplies it (the scale of pbrt-v3's image film,
 * which the scenes that set it carried over). */
int finish_film(Parser *p)
{
    double exposure = (double)p->shutter_close - (double)p->shutter_open;
    if (!(exposure > 0.0))
        return scene_error(&p->diag, p->camera_file ? p->camera_file : p->main_path, p->camera_line,
                           "Camera: shutterclose %g must be after shutteropen %g (the film's exposure time)",
                           (double)p->shutter_close, (double)p->shutter_open);
    /* on_film accepted only known sensors */
    return spectrum_film_from_radiance(p->film_sensor, exposure * p->film_iso / 100.0 * p->film_scale,
                                       p->film_white_balance, p->scene->film_from_radiance);
}

int on_sampler(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the sampler type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    int spp = (int)p->scene->spp;
    if (result == 0 && params_get_int(&params, "pixelsamples", &spp) < 0)
        result = -1;
    if (result == 0 && spp < 1)
        result = scene_error(&p->diag, lex->path, d->line, "Sampler: pixelsamples must be at least 1");
    if (result == 0) {
        /* Any sampler is accepted: its name picks one of the renderer's
         * (sampler_for_scene), whose other parameters (seed, jitter, ...)
         * do not apply. */
        char *name = scene_strndup(type.text, type.length);
        if (!name)
            result = out_of_memory(p, lex->path, d->line);
        else {
            free(p->scene->sampler);
            p->scene->sampler = name;
            p->scene->spp = (unsigned)spp;
        }
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's integrators whose expected image is the path tracer's, and
 * their parameters that only change how fast they converge. Those that
 * render participating media in pbrt-v4 (volpath, simplevolpath, bdpt,
 * mlt) have the path tracer render them too; the others ignore media, as
 * in pbrt-v4 (Scene.integrator_media). */
static const struct {
    const char *name;
    const char *tuning[6];
} same_image_integrators[] = {
    {"path", {NULL}},
    {"volpath", {NULL}},
    {"simplevolpath", {NULL}},
    {"bdpt", {NULL}},
    {"mlt", {"bootstrapsamples", "chains", "mutationsperpixel", "largestepprobability", "sigma", NULL}},
    {"sppm", {"photonsperiteration", "radius", "seed", NULL}},
    {"simplepath", {"samplelights", "samplebsdf", NULL}},
    {"lightpath", {NULL}},
    {"randomwalk", {NULL}},
};

/* Which integrator renders the scene: the path tracer, with a note where
 * pbrt-v4 would use another one with the same expected image, else an
 * unsupported feature (ambientocclusion, aov, ...: their images differ). */
static int choose_integrator(Parser *p, Lexer *lex, const Token *d, const Token *type, ParamList *params)
{
    char shown[64];
    token_describe(type, shown, sizeof shown);
    for (size_t i = 0; i < sizeof same_image_integrators / sizeof same_image_integrators[0]; ++i) {
        if (!token_is(type, same_image_integrators[i].name))
            continue;
        for (const char *const *tuning = same_image_integrators[i].tuning; *tuning; ++tuning)
            params_ignore(params, *tuning);
        int visualize_strategies = 0, visualize_weights = 0; /* bdpt's images of single strategies */
        if (strcmp(same_image_integrators[i].name, "bdpt") == 0 &&
            (params_get_bool(params, "visualizestrategies", &visualize_strategies) < 0 ||
             params_get_bool(params, "visualizeweights", &visualize_weights) < 0))
            return -1;
        if (visualize_strategies || visualize_weights)
            return scene_unsupported(&p->diag, lex->path, d->line, "the path tracer's image is rendered",
                                     "Integrator %s: \"visualizestrategies\" and \"visualizeweights\" are "
                                     "not supported",
                                     shown);
        const char *name = same_image_integrators[i].name;
        p->scene->integrator_media = strcmp(name, "volpath") == 0 || strcmp(name, "simplevolpath") == 0 ||
                                     strcmp(name, "bdpt") == 0 || strcmp(name, "mlt") == 0;
        /* The path tracer is pbrt-v4's path, and its volpath where the scene has media. */
        if (token_is(type, "path") || token_is(type, "volpath"))
            return 0;
        if (token_is(type, "lightpath")) {
            p->scene->light_subpaths = SCENE_LIGHTPATH;
            return 0;
        }
        if (token_is(type, "bdpt")) {
            p->scene->light_subpaths = SCENE_BDPT;
            return 0;
        }
        /* Only bidirectional sampling reaches what a delta light lights
         * through specular surfaces, as these integrators do. */
        if (token_is(type, "mlt") || token_is(type, "sppm")) {
            p->scene->light_subpaths = SCENE_BDPT;
            return scene_note(&p->diag, lex->path, d->line,
                              "Integrator %s is rendered by bidirectional path tracing (\"bdpt\"): the expected "
                              "image is the same, the noise differs",
                              shown);
        }
        return scene_note(&p->diag, lex->path, d->line,
                          "Integrator %s is rendered by the path tracer (\"%s\"): the expected image is the same",
                          shown, p->scene->integrator_media ? "volpath" : "path");
    }
    p->scene->integrator_media = 0;
    return scene_unsupported(&p->diag, lex->path, d->line, "\"path\" is used",
                             "Integrator %s is not supported: its image differs from the path tracer's "
                             "(path, volpath, simplevolpath, bdpt, mlt, sppm, simplepath, lightpath, randomwalk are)",
                             shown);
}

/* Integrator "lightsampler": pbrt-v4's bvh (its default), exhaustive,
 * power or uniform. bvh is gmonrt's light tree, exhaustive too (the same
 * chances from each light's own bounds, which the tree's walk
 * approximates): the expected image is the same. */
static int read_light_sampler(Parser *p, Lexer *lex, const Token *d, ParamList *params)
{
    const char *light_sampler = NULL;
    int found = params_get_string(params, "lightsampler", &light_sampler);
    if (found <= 0)
        return found; /* absent, or an error */
    if (strcmp(light_sampler, "bvh") != 0 && strcmp(light_sampler, "exhaustive") != 0 &&
        strcmp(light_sampler, "power") != 0 && strcmp(light_sampler, "uniform") != 0)
        return scene_error(&p->diag, lex->path, d->line,
                           "Integrator: \"lightsampler\" \"%s\" is not bvh, exhaustive, power or uniform",
                           light_sampler);
    if (replace_string(p, lex->path, d->line, &p->scene->light_sampler, light_sampler))
        return -1;
    if (strcmp(light_sampler, "exhaustive") != 0)
        return 0;
    return scene_note(&p->diag, lex->path, d->line,
                      "Integrator: \"lightsampler\" \"exhaustive\" is rendered with gmonrt's light tree (bvh): "
                      "the expected image is the same");
}

int on_integrator(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the integrator type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    if (result == 0)
        result = choose_integrator(p, lex, d, &type, &params);
    int max_depth = p->scene->max_depth, regularize = 0;
    float rr_threshold = p->scene->rr_threshold;
    /* pbrt-v4's path and volpath integrators take "rrthreshold". */
    int has_roulette_threshold = token_is(&type, "path") || token_is(&type, "volpath");
    if (result == 0 && (params_get_int(&params, "maxdepth", &max_depth) < 0 ||
                        params_get_bool(&params, "regularize", &regularize) < 0 ||
                        (has_roulette_threshold && params_get_float(&params, "rrthreshold", &rr_threshold) < 0)))
        result = -1;
    if (result == 0)
        result = read_light_sampler(p, lex, d, &params);
    if (result == 0 && max_depth < 0)
        result = scene_error(&p->diag, lex->path, d->line, "Integrator: maxdepth must not be negative");
    if (result == 0 && !(rr_threshold >= 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "Integrator: rrthreshold %g must not be negative",
                             (double)rr_threshold);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0) {
        p->scene->max_depth = max_depth;
        p->scene->regularize = regularize;
        p->scene->rr_threshold = rr_threshold;
    }
    params_free(&params);
    return result;
}

/* pbrt-v4's Accelerator: "bvh" (its default) or "kdtree", and their build
 * parameters. They change how fast rays are traced, not the image: gmonrt
 * builds its own BVH and notes that. */
static const struct {
    const char *name;
    const char *tuning[6];
} accelerators[] = {
    {"bvh", {"maxnodeprims", "splitmethod", NULL}},
    {"kdtree", {"intersectcost", "traversalcost", "emptybonus", "maxprims", "maxdepth"}},
};

int on_accelerator(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the accelerator type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    size_t kind = 0;
    while (result == 0 && kind < sizeof accelerators / sizeof accelerators[0] &&
           !token_is(&type, accelerators[kind].name))
        ++kind;
    char shown[64];
    token_describe(&type, shown, sizeof shown);
    if (result == 0 && kind == sizeof accelerators / sizeof accelerators[0])
        result =
            scene_error(&p->diag, lex->path, d->line, "Accelerator %s is not pbrt-v4's \"bvh\" or \"kdtree\"", shown);
    if (result == 0)
        for (const char *const *tuning = accelerators[kind].tuning; *tuning; ++tuning)
            params_ignore(&params, *tuning);
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0)
        result = scene_note(&p->diag, lex->path, d->line,
                            "Accelerator %s: gmonrt builds its own BVH (the accelerator changes the speed, not the "
                            "image)",
                            shown);
    params_free(&params);
    return result;
}

/* A filter parameter that must be positive (at most `largest`). */
static int get_filter_parameter(Parser *p, Lexer *lex, const Token *d, ParamList *params, const char *name,
                                float largest, float *value)
{
    if (params_get_float(params, name, value) < 0)
        return -1;
    if (!(*value > 0.0f && *value <= largest))
        return scene_error(&p->diag, lex->path, d->line, "%s: %s %g is not in (0, %g]", params->owner, name,
                           (double)*value, (double)largest);
    return 0;
}

/* pbrt-v4's filters and their default radii; "lanczos" is accepted for
 * pbrt-v4's "sinc" (its class is LanczosSincFilter). */
static const struct {
    const char *name;
    SceneFilterType type;
    float radius;
} FILTERS[] = {
    {"box", SCENE_FILTER_BOX, 0.5f},           {"gaussian", SCENE_FILTER_GAUSSIAN, 1.5f},
    {"mitchell", SCENE_FILTER_MITCHELL, 2.0f}, {"sinc", SCENE_FILTER_LANCZOS, 4.0f},
    {"lanczos", SCENE_FILTER_LANCZOS, 4.0f},   {"triangle", SCENE_FILTER_TRIANGLE, 2.0f},
};
#define FILTER_KINDS (sizeof FILTERS / sizeof FILTERS[0])
#define DEFAULT_FILTER 1 /* gaussian: pbrt-v4's filter when a scene names none */

/* FILTERS[kind] with pbrt-v4's default parameters. */
static SceneFilter default_filter(size_t kind)
{
    SceneFilter f = {
        FILTERS[kind].type, {FILTERS[kind].radius, FILTERS[kind].radius}, 0.5f, 1.0f / 3.0f, 1.0f / 3.0f, 3.0f};
    return f;
}

SceneFilter default_pixel_filter(void)
{
    return default_filter(DEFAULT_FILTER);
}

int on_pixel_filter(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the filter type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 0);
    size_t kind = 0;
    while (result == 0 && kind < FILTER_KINDS && !token_is(&type, FILTERS[kind].name))
        ++kind;
    if (result == 0 && kind == FILTER_KINDS) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_error(&p->diag, lex->path, d->line,
                             "PixelFilter %s is not supported (only \"box\", \"gaussian\", \"mitchell\", "
                             "\"sinc\" or \"lanczos\", \"triangle\")",
                             shown);
    }
    SceneFilter filter = default_filter(DEFAULT_FILTER);
    if (result == 0) {
        filter = default_filter(kind);
        const float unbounded = FLT_MAX;
        result = get_filter_parameter(p, lex, d, &params, "xradius", SCENE_MAX_FILTER_RADIUS, &filter.radius[0]);
        if (result == 0)
            result = get_filter_parameter(p, lex, d, &params, "yradius", SCENE_MAX_FILTER_RADIUS, &filter.radius[1]);
        if (result == 0 && filter.type == SCENE_FILTER_GAUSSIAN)
            result = get_filter_parameter(p, lex, d, &params, "sigma", unbounded, &filter.sigma);
        if (result == 0 && filter.type == SCENE_FILTER_LANCZOS)
            result = get_filter_parameter(p, lex, d, &params, "tau", unbounded, &filter.tau);
        if (result == 0 && filter.type == SCENE_FILTER_MITCHELL &&
            (params_get_float(&params, "B", &filter.b) < 0 || params_get_float(&params, "C", &filter.c) < 0))
            result = -1;
    }
    if (result == 0)
        result = params_check_unused(&params);
    if (result == 0)
        p->scene->filter = filter;
    params_free(&params);
    return result;
}

/* Turns the camera transform and film size into the camera's basis. */
int finish_camera(Parser *p)
{
    Scene *s = p->scene;
    SceneCamera *camera = &s->camera;
    int affine = is_affine(p->camera_from_world);
    memcpy(camera->world_from_camera, p->world_from_camera, sizeof camera->world_from_camera);
    const float origin[3] = {0, 0, 0};
    transform_point(p->world_from_camera, origin, camera->position);
    float *axes[3] = {camera->right, camera->up, camera->forward};
    for (int a = 0; a < 3; ++a) { /* in double: squaring a 1e20 column overflows a float */
        double v[3] = {p->world_from_camera[a][0], p->world_from_camera[a][1], p->world_from_camera[a][2]};
        normalize_d(v);
        for (int k = 0; k < 3; ++k)
            axes[a][k] = (float)v[k];
    }
    double scale;
    const char *file = p->camera_file ? p->camera_file : p->main_path;
    int similarity = is_similarity(p->world_from_camera, &scale);
    if (!affine || !similarity) {
        if (scene_warn(&p->diag, file, p->camera_line,
                       "Camera: the camera transform is not a rotation with a uniform scale; its axes are "
                       "normalized"))
            return -1;
    }
    scene_camera_tan_half_fov(camera->fov, s->width, s->height, camera->tan_half_fov);
    /* pbrt keeps the camera transform's scale: camera-space lengths (the
     * lens, an orthographic window) scale with it. */
    double lens_radius = camera->lens_radius * scale, focal_distance = camera->focal_distance * scale;
    if (lens_radius > 0.0 && !(lens_radius <= FLT_MAX && focal_distance <= FLT_MAX && focal_distance >= FLT_MIN))
        return scene_error(&p->diag, file, p->camera_line,
                           "Camera: lensradius or focaldistance times the camera transform's scale %g is out of "
                           "single precision's range",
                           scale);
    camera->scale = (float)fmin(scale, FLT_MAX);
    camera->lens_radius = (float)lens_radius;
    camera->focal_distance = (float)fmin(focal_distance, FLT_MAX); /* unused without a lens */
    return 0;
}
