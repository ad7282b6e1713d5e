/* The lights: AreaLightSource (which the graphics state carries to the
 * shapes that follow) and LightSource. */
#include "scene/lights.h"

#include "scene/geometry.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A light's radiance (L * scale, in double) must fit a float. */
static int check_radiance(Parser *p, Lexer *lex, const Token *d, const char *light, const double radiance[3])
{
    for (int k = 0; k < 3; ++k)
        if (radiance[k] > FLT_MAX)
            return scene_error(&p->diag, lex->path, d->line,
                               "%s: the radiance L * scale, %g, overflows single precision (at most %g)", light,
                               radiance[k], (double)FLT_MAX);
    return 0;
}

int on_area_light_source(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the area light type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    if (result == 0 && !token_is(&type, "diffuse")) {
        p->state.has_area_light = 0;
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line, "the shapes do not emit",
                                   "AreaLightSource %s is not supported (only \"diffuse\")", shown);
        params_free(&params);
        return result;
    }
    float L[3] = {1.0f, 1.0f, 1.0f}, scale = 1.0f, power = -1.0f;
    int two_sided = 0;
    if (result == 0 &&
        (params_get_spectrum(&params, "L", SPECTRUM_ILLUMINANT, L) < 0 ||
         params_get_float(&params, "scale", &scale) < 0 || params_get_bool(&params, "twosided", &two_sided) < 0 ||
         params_get_float(&params, "power", &power) < 0))
        result = -1;
    if (result == 0 && scale < 0.0f)
        result = scene_error(&p->diag, lex->path, d->line, "AreaLightSource: scale must not be negative");
    if (result == 0 && !(power == -1.0f || power > 0.0f))
        result = scene_error(&p->diag, lex->path, d->line, "AreaLightSource: power must be positive");
    if (result == 0)
        result = params_check_unused(&params);
    double radiance[3] = {(double)L[0] * scale, (double)L[1] * scale, (double)L[2] * scale};
    if (result == 0)
        result = check_radiance(p, lex, d, "AreaLightSource", radiance);
    if (result == 0) {
        p->state.has_area_light = 1;
        for (int k = 0; k < 3; ++k)
            p->state.area_radiance[k] = (float)radiance[k];
        p->state.area_two_sided = two_sided;
        p->state.area_power = power;
        snprintf(p->state.area_origin, sizeof p->state.area_origin, "%s:%d", lex->path, d->line);
    }
    params_free(&params);
    return result;
}

/* Reads the light's point parameter `name` (default `fallback`). */
static int light_point(ParamList *params, const char *name, const float fallback[3], double out[3])
{
    const Param *param = NULL;
    int found = params_get_array(params, name, PARAM_POINT3, &param);
    if (found < 0)
        return -1;
    if (found && param->count != 3)
        return params_error(params, param, "expected one point (3 values), got %zu values", param->count);
    for (int k = 0; k < 3; ++k)
        out[k] = found ? param->numbers[k] : fallback[k];
    return 0;
}

/* pbrt-v4's LightSource directive: point, spot, distant, infinite
 * (uniform, or an equal-area image). Each light's spectrum is scaled by
 * "scale", and "power" (point, spot) or "illuminance" (distant, infinite)
 * replace that scale by one that gives the light this power (W... in
 * pbrt's photometric units) or this illuminance on a surface facing it. */
int on_light_source(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the light type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    if (result == 0)
        result = warn_if_moving(p, lex, d);
    const int is_point = token_is(&type, "point"), is_spot = token_is(&type, "spot");
    const int is_distant = token_is(&type, "distant"), is_infinite = token_is(&type, "infinite");
    const int is_goniometric = token_is(&type, "goniometric"), is_projection = token_is(&type, "projection");
    const int is_imaged = is_goniometric || is_projection; /* point lights shaped by an image */
    if (result == 0 && !is_point && !is_spot && !is_distant && !is_infinite && !is_imaged) {
        char shown[64];
        token_describe(&type, shown, sizeof shown);
        result = scene_unsupported(&p->diag, lex->path, d->line, "skipped",
                                   "LightSource %s is not supported (point, spot, distant, infinite, goniometric, "
                                   "projection)",
                                   shown);
        params_free(&params);
        return result;
    }
    if (result) {
        params_free(&params);
        return result;
    }
    SceneLight light;
    memset(&light, 0, sizeof light);
    light.illuminance = -1.0f;
    light.power = -1.0f;
    light.fov = 90.0f;
    float L[3] = {1.0f, 1.0f, 1.0f}, scale = 1.0f, power = -1.0f, illuminance = -1.0f;
    const char *filename = NULL;
    int has_L = 0;
    const double pi = 3.14159265358979323846;
    mat4 *ctm = &p->state.ctm;
    result = params_get_float(&params, "scale", &scale) < 0;
    if (!result && (is_point || is_spot || is_goniometric))
        result = params_get_spectrum(&params, "I", SPECTRUM_ILLUMINANT, L) < 0;
    if (!result && (is_point || is_spot || is_imaged))
        result = params_get_float(&params, "power", &power) < 0;
    if (!result && is_imaged)
        result = params_get_string(&params, "filename", &filename) < 0;
    if (!result && is_projection) {
        result = params_get_float(&params, "fov", &light.fov) < 0;
        if (!result && !filename)
            result = scene_error(&p->diag, lex->path, d->line, "%s: missing \"string filename\"", params.owner);
        if (!result && !(light.fov > 0.0f && light.fov < 180.0f))
            result = scene_error(&p->diag, lex->path, d->line, "%s: fov must be in (0, 180), got %g", params.owner,
                                 (double)light.fov);
    }
    if (!result && (is_distant || is_infinite))
        result = (has_L = params_get_spectrum(&params, "L", SPECTRUM_ILLUMINANT, L)) < 0 ||
                 params_get_float(&params, "illuminance", &illuminance) < 0;
    if (!result && is_infinite) {
        /* A portal only helps pbrt sample the image: the light is the same. */
        params_ignore(&params, "portal");
        result = params_get_string(&params, "filename", &filename) < 0;
        if (!result && filename && !filename[0])
            filename = NULL;
        if (!result && filename && has_L)
            result = scene_error(&p->diag, lex->path, d->line,
                                 "LightSource \"infinite\": both \"L\" and \"filename\" given (pbrt-v4 refuses this)");
    }
    if (!result && (scale < 0.0f || !(power == -1.0f || power > 0.0f) || !(illuminance == -1.0f || illuminance > 0.0f)))
        result = scene_error(&p->diag, lex->path, d->line,
                             "%s: scale must not be negative, power and illuminance must be positive", params.owner);
    double from[3], to[3];
    static const float origin[3] = {0.0f, 0.0f, 0.0f}, ahead[3] = {0.0f, 0.0f, 1.0f};
    if (!result && !is_infinite && !is_imaged)
        result = light_point(&params, "from", origin, from) || light_point(&params, "to", ahead, to);
    for (int c = 0; c < 3 && is_imaged; ++c)
        from[c] = 0.0; /* at the CTM's origin */
    if (!result && is_spot) {
        float cone = 30.0f, delta = 5.0f;
        result = params_get_float(&params, "coneangle", &cone) < 0 ||
                 params_get_float(&params, "conedeltaangle", &delta) < 0;
        if (!result && !(cone > 0.0f && cone <= 180.0f && delta >= 0.0f && delta <= cone))
            result = scene_error(&p->diag, lex->path, d->line,
                                 "LightSource \"spot\": coneangle must be in (0, 180] and conedeltaangle in [0, "
                                 "coneangle] (got %g and %g)",
                                 (double)cone, (double)delta);
        light.cos_total_width = (float)cos(cone * pi / 180.0);
        light.cos_falloff_start = (float)cos((cone - delta) * pi / 180.0);
    }
    if (!result)
        result = params_check_unused(&params);
    double k = scale;
    if (!result && is_point) {
        light.type = SCENE_LIGHT_POINT;
        if (power > 0.0f)
            k *= power / (4.0 * pi);
    } else if (!result && is_spot) {
        light.type = SCENE_LIGHT_SPOT;
        if (power > 0.0f)
            k *= power / (2.0 * pi *
                          ((1.0 - light.cos_falloff_start) + (light.cos_falloff_start - light.cos_total_width) / 2.0));
    } else if (!result && is_distant) {
        light.type = SCENE_LIGHT_DISTANT;
        if (illuminance > 0.0f)
            k *= illuminance;
    } else if (!result && is_goniometric && !filename) {
        light.type = SCENE_LIGHT_POINT; /* pbrt-v4 warns and renders it without an image */
        result =
            scene_warn(&p->diag, lex->path, d->line, "%s: no \"filename\": an isotropic point light", params.owner);
        if (power > 0.0f)
            k *= power / (4.0 * pi);
    } else if (!result && is_imaged) {
        light.type = is_goniometric ? SCENE_LIGHT_GONIOMETRIC : SCENE_LIGHT_PROJECTION;
        light.power = power; /* needs the image: scene_convert applies it */
    } else if (!result) {
        light.type = filename ? SCENE_LIGHT_IMAGE : SCENE_LIGHT_INFINITE;
        if (filename)
            light.illuminance = illuminance;
        else if (illuminance > 0.0f)
            k *= illuminance / pi; /* a uniform sky of radiance L gives pi L */
    }
    double radiance[3];
    for (int c = 0; c < 3; ++c)
        radiance[c] = (light.type == SCENE_LIGHT_IMAGE || is_projection ? 1.0 : (double)L[c]) * k;
    if (!result)
        result = check_radiance(p, lex, d, params.owner, radiance);
    for (int c = 0; c < 3; ++c)
        light.radiance[c] = (float)radiance[c];

    if (!result && (is_point || is_spot || is_imaged)) {
        float from_f[3] = {(float)from[0], (float)from[1], (float)from[2]};
        transform_point(*ctm, from_f, light.position);
        if (!within_range(light.position))
            result = scene_error(&p->diag, lex->path, d->line, "%s: the light lies beyond %g of the origin",
                                 params.owner, SCENE_MAX_COORDINATE);
    }
    if (!result && (is_spot || is_distant)) {
        /* spot: it shines along to - from; distant: the light is along from - to */
        double v[3], w[3];
        for (int c = 0; c < 3; ++c)
            v[c] = is_spot ? to[c] - from[c] : from[c] - to[c];
        transform_vector_d(*ctm, v, w);
        if (normalize_d(w) == 0.0 || !isfinite(w[0] + w[1] + w[2]))
            result =
                scene_error(&p->diag, lex->path, d->line, "%s: \"from\" and \"to\" give no direction", params.owner);
        for (int c = 0; c < 3; ++c)
            light.direction[c] = (float)w[c];
    }
    if (!result && (light.type == SCENE_LIGHT_IMAGE || is_imaged) && filename) {
        /* Light space is object space: the rows of the CTM's inverse
         * rotation (its transpose, for a rotation times a uniform scale);
         * pbrt-v4 swaps a goniometric light's y and z, and flips a
         * projection light's y (its image's rows run down). */
        double s;
        if (!is_similarity(*ctm, &s) || !(s > 0.0))
            result = scene_unsupported(&p->diag, lex->path, d->line, "its non-uniform scale or shear is ignored",
                                       "%s: the transform is not a rotation and uniform scale", params.owner);
        for (int r = 0; r < 3; ++r) {
            int column = is_goniometric && r > 0 ? 3 - r : r;
            double sign = is_projection && r == 1 ? -1.0 : 1.0;
            double row[3] = {(*ctm)[column][0], (*ctm)[column][1], (*ctm)[column][2]}; /* a column of the CTM */
            normalize_d(row);
            for (int c = 0; c < 3; ++c)
                light.light_from_world[r][c] = (float)(sign * row[c]);
        }
        if (!result) {
            light.filename = resolve_path(p, lex->path, filename);
            int missing =
                light.filename ? scene_missing_file(&p->diag, lex->path, d->line, light.filename, params.owner) : -1;
            if (missing < 0)
                result = out_of_memory(p, lex->path, d->line);
            else if (missing) { /* check mode: listed, and the light skipped */
                free(light.filename);
                params_free(&params);
                return 0;
            } else if (!scene_file_exists(light.filename))
                result =
                    scene_error(&p->diag, lex->path, d->line, "%s: cannot find \"%s\"", params.owner, light.filename);
        }
    }
    if (!result) {
        char where[1024];
        snprintf(where, sizeof where, "%s:%d", lex->path, d->line);
        light.origin = scene_strndup(where, strlen(where));
        Scene *sc = p->scene;
        if (!light.origin ||
            scene_reserve((void **)&sc->lights, &p->light_capacity, sc->light_count + 1, sizeof *sc->lights))
            result = out_of_memory(p, lex->path, d->line);
        else
            sc->lights[sc->light_count++] = light;
    }
    if (result) {
        free(light.filename);
        free(light.origin);
    }
    params_free(&params);
    return result ? -1 : 0; /* the getters' checks above give 1 */
}
