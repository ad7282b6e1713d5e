/* Participating media: MakeNamedMedium with pbrt-v4's types and
 * parameters, MediumInterface (the graphics state's inside and outside
 * media, which the shapes and the camera take), and the names bound once
 * the whole scene is read, as pbrt-v4 binds them. */
#include "scene/media.h"
#include "scene/spectrum.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* pbrt-v4's named media ("preset"), measured by Jensen et al. (SIGGRAPH
 * 2001) and Narasimhan et al. (SIGGRAPH 2006): per RGB channel the reduced
 * scattering coefficient, which pbrt-v4 takes as sigma_s, and the
 * absorption coefficient, in mm^-1. */
static const struct {
    const char *name;
    float sigma_s[3], sigma_a[3];
} presets[] = {
    {"Apple", {2.29f, 2.39f, 1.97f}, {0.0030f, 0.0034f, 0.046f}},
    {"Chicken1", {0.15f, 0.21f, 0.38f}, {0.015f, 0.077f, 0.19f}},
    {"Chicken2", {0.19f, 0.25f, 0.32f}, {0.018f, 0.088f, 0.20f}},
    {"Cream", {7.38f, 5.47f, 3.15f}, {0.0002f, 0.0028f, 0.0163f}},
    {"Ketchup", {0.18f, 0.07f, 0.03f}, {0.061f, 0.97f, 1.45f}},
    {"Marble", {2.19f, 2.62f, 3.00f}, {0.0021f, 0.0041f, 0.0071f}},
    {"Potato", {0.68f, 0.70f, 0.55f}, {0.0024f, 0.0090f, 0.12f}},
    {"Skimmilk", {0.70f, 1.22f, 1.90f}, {0.0014f, 0.0025f, 0.0142f}},
    {"Skin1", {0.74f, 0.88f, 1.01f}, {0.032f, 0.17f, 0.48f}},
    {"Skin2", {1.09f, 1.59f, 1.79f}, {0.013f, 0.070f, 0.145f}},
    {"Spectralon", {11.6f, 20.4f, 14.9f}, {0.0f, 0.0f, 0.0f}},
    {"Wholemilk", {2.55f, 3.21f, 3.77f}, {0.0011f, 0.0024f, 0.014f}},
    {"Lowfat Milk", {0.89187f, 1.5136f, 2.532f}, {0.002875f, 0.00575f, 0.0115f}},
    {"Reduced Milk", {2.4858f, 3.1669f, 4.5214f}, {0.0025556f, 0.0051111f, 0.012778f}},
    {"Regular Milk", {4.5513f, 5.8294f, 7.136f}, {0.0015333f, 0.0046f, 0.019933f}},
    {"Espresso", {0.72378f, 0.84557f, 1.0247f}, {4.7984f, 6.5751f, 8.8493f}},
    {"Mint Mocha Coffee", {0.31602f, 0.38538f, 0.48131f}, {3.772f, 5.8228f, 7.82f}},
    {"Lowfat Soy Milk", {0.30576f, 0.34233f, 0.61664f}, {0.0014375f, 0.0071875f, 0.035937f}},
    {"Regular Soy Milk", {0.59223f, 0.73866f, 1.4693f}, {0.0019167f, 0.0095833f, 0.065167f}},
    {"Lowfat Chocolate Milk", {0.64925f, 0.83916f, 1.1057f}, {0.0115f, 0.0368f, 0.1564f}},
    {"Regular Chocolate Milk", {1.4585f, 2.1289f, 2.9527f}, {0.010063f, 0.043125f, 0.14375f}},
    {"Coke", {8.9053e-05f, 8.372e-05f, 0.0f}, {0.10014f, 0.16503f, 0.2468f}},
    {"Pepsi", {6.1697e-05f, 4.2564e-05f, 0.0f}, {0.091641f, 0.14158f, 0.20729f}},
    {"Sprite", {6.0306e-06f, 6.4139e-06f, 6.5504e-06f}, {0.001886f, 0.0018308f, 0.0020025f}},
    {"Gatorade", {0.0024574f, 0.003007f, 0.0037325f}, {0.024794f, 0.019289f, 0.008878f}},
    {"Chardonnay", {1.7982e-05f, 1.3758e-05f, 1.2023e-05f}, {0.010782f, 0.011855f, 0.023997f}},
    {"White Zinfandel", {1.7501e-05f, 1.9069e-05f, 1.288e-05f}, {0.012072f, 0.016184f, 0.019843f}},
    {"Merlot", {2.1129e-05f, 0.0f, 0.0f}, {0.11632f, 0.25191f, 0.29434f}},
    {"Budweiser Beer", {2.4356e-05f, 2.4079e-05f, 1.0564e-05f}, {0.011492f, 0.024911f, 0.057786f}},
    {"Coors Light Beer", {5.0922e-05f, 4.301e-05f, 0.0f}, {0.006164f, 0.013984f, 0.034983f}},
    {"Clorox", {0.0024035f, 0.0031373f, 0.003991f}, {0.0033542f, 0.014892f, 0.026297f}},
    {"Apple Juice", {0.00013612f, 0.00015836f, 0.000227f}, {0.012957f, 0.023741f, 0.052184f}},
    {"Cranberry Juice", {0.00010402f, 0.00011646f, 7.8139e-05f}, {0.039437f, 0.094223f, 0.12426f}},
    {"Grape Juice", {5.382e-05f, 0.0f, 0.0f}, {0.10404f, 0.23958f, 0.29325f}},
    {"Ruby Grapefruit Juice", {0.011002f, 0.010927f, 0.011036f}, {0.085867f, 0.18314f, 0.25262f}},
    {"White Grapefruit Juice", {0.22826f, 0.23998f, 0.32748f}, {0.0138f, 0.018831f, 0.056781f}},
    {"Shampoo", {0.0007176f, 0.0008303f, 0.0009016f}, {0.014107f, 0.045693f, 0.061717f}},
    {"Strawberry Shampoo", {0.00015671f, 0.00015947f, 1.518e-05f}, {0.01449f, 0.05796f, 0.075823f}},
    {"Head & Shoulders Shampoo", {0.023805f, 0.028804f, 0.034306f}, {0.084621f, 0.15688f, 0.20365f}},
    {"Lemon Tea Powder", {0.040224f, 0.045264f, 0.051081f}, {2.4288f, 4.5757f, 7.2127f}},
    {"Orange Powder", {0.00015617f, 0.00017482f, 0.0001762f}, {0.001449f, 0.003441f, 0.007863f}},
    {"Pink Lemonade Powder", {0.00012103f, 0.00013073f, 0.00012528f}, {0.001165f, 0.002366f, 0.003195f}},
    {"Cappuccino Powder", {1.8436f, 2.5851f, 2.1662f}, {35.844f, 49.547f, 61.084f}},
    {"Salt Powder", {0.027333f, 0.032451f, 0.031979f}, {0.28415f, 0.3257f, 0.34148f}},
    {"Sugar Powder", {0.00022272f, 0.00025513f, 0.000271f}, {0.012638f, 0.031051f, 0.050124f}},
    {"Suisse Mocha Powder", {2.7979f, 3.5452f, 4.3365f}, {17.502f, 27.004f, 35.433f}},
    {"Pacific Ocean Surface Water", {0.0001764f, 0.00032095f, 0.00019617f}, {0.031845f, 0.031324f, 0.030147f}},
};

/* The medium called name[0, length) (-1 for "", vacuum): its index in
 * Scene.media, a new entry, not yet defined, the first time it is named. */
static int medium_index(Parser *p, const char *file, int line, const char *name, size_t length, int *index)
{
    Scene *s = p->scene;
    *index = -1;
    if (length == 0)
        return 0;
    for (size_t i = 0; i < s->medium_count; ++i)
        if (strlen(s->media[i].name) == length && memcmp(s->media[i].name, name, length) == 0) {
            *index = (int)i;
            return 0;
        }
    if (scene_reserve((void **)&s->media, &p->medium_capacity, s->medium_count + 1, sizeof *s->media) ||
        scene_reserve((void **)&p->medium_names, &p->medium_name_capacity, s->medium_count + 1,
                      sizeof *p->medium_names))
        return out_of_memory(p, file, line);
    SceneMedium *m = &s->media[s->medium_count];
    memset(m, 0, sizeof *m);
    if (!(m->name = scene_strndup(name, length)))
        return out_of_memory(p, file, line);
    p->medium_names[s->medium_count] = (struct MediumName){0, file, line};
    *index = (int)s->medium_count++;
    return 0;
}

/* MediumInterface "inside" ["outside"]: one name sets both, as in pbrt-v4. */
int on_medium_interface(Parser *p, Lexer *lex, const Token *d)
{
    Token inside, outside;
    if (expect_string(p, lex, d, "the inside medium's name", &inside) || lexer_peek(lex, &outside))
        return -1;
    if (outside.kind == TOKEN_STRING) {
        if (lexer_next(lex, &outside))
            return -1;
    } else {
        outside = inside;
    }
    int in, out;
    if (medium_index(p, lex->path, d->line, inside.text, inside.length, &in) ||
        medium_index(p, lex->path, d->line, outside.text, outside.length, &out))
        return -1;
    p->state.medium_inside = in;
    p->state.medium_outside = out;
    return 0;
}

/* Reads a float that must lie in [low, high] (default unchanged). */
static int get_float_in(Parser *p, Lexer *lex, const Token *d, ParamList *params, const char *name, float low,
                        float high, float *value)
{
    if (params_get_float(params, name, value) < 0)
        return -1;
    if (!(*value >= low && *value <= high))
        return scene_error(&p->diag, lex->path, d->line, "%s: \"%s\" %g must lie in [%g, %g]", params->owner, name,
                           (double)*value, (double)low, (double)high);
    return 0;
}

/* What every type reads: sigma_a and sigma_s (default 1) times "scale",
 * and g, which must lie strictly between -1 and 1 (a Henyey-Greenstein
 * lobe). The products must fit a float. */
static int read_coefficients(Parser *p, Lexer *lex, const Token *d, ParamList *params, int from_preset, SceneMedium *m)
{
    float scale = 1.0f;
    if (!from_preset) {
        for (int k = 0; k < 3; ++k)
            m->sigma_a[k] = m->sigma_s[k] = 1.0f;
        if (params_get_spectrum(params, "sigma_a", SPECTRUM_UNBOUNDED, m->sigma_a) < 0 ||
            params_get_spectrum(params, "sigma_s", SPECTRUM_UNBOUNDED, m->sigma_s) < 0)
            return -1;
    }
    if (get_float_in(p, lex, d, params, "scale", 0.0f, FLT_MAX, &scale) ||
        get_float_in(p, lex, d, params, "g", -0.999f, 0.999f, &m->g))
        return -1;
    for (int k = 0; k < 3; ++k) {
        double a = (double)m->sigma_a[k] * scale, s = (double)m->sigma_s[k] * scale;
        if (a > FLT_MAX || s > FLT_MAX)
            return scene_error(&p->diag, lex->path, d->line, "%s: sigma_a or sigma_s times scale overflows a float",
                               params->owner);
        m->sigma_a[k] = (float)a;
        m->sigma_s[k] = (float)s;
    }
    return 0;
}

/* "Le" (an emitter's spectrum, 0 when absent) times "Lescale". */
static int read_emission(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    float scale = 1.0f;
    if (params_get_spectrum(params, "Le", SPECTRUM_ILLUMINANT, m->emission) < 0 ||
        get_float_in(p, lex, d, params, "Lescale", 0.0f, FLT_MAX, &scale))
        return -1;
    for (int k = 0; k < 3; ++k) {
        double e = (double)m->emission[k] * scale;
        if (e > FLT_MAX)
            return scene_error(&p->diag, lex->path, d->line, "%s: Le times Lescale overflows a float", params->owner);
        m->emission[k] = (float)e;
    }
    return 0;
}

static int read_homogeneous(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    const char *preset = NULL;
    if (params_get_string(params, "preset", &preset) < 0)
        return -1;
    int from_preset = 0;
    for (size_t i = 0; preset && *preset && !from_preset && i < sizeof presets / sizeof presets[0]; ++i)
        if (strcmp(presets[i].name, preset) == 0) {
            memcpy(m->sigma_a, presets[i].sigma_a, sizeof m->sigma_a);
            memcpy(m->sigma_s, presets[i].sigma_s, sizeof m->sigma_s);
            from_preset = 1;
        }
    /* pbrt-v4 warns and goes on with sigma_a and sigma_s. */
    if (preset && *preset && !from_preset &&
        scene_warn(&p->diag, lex->path, d->line,
                   "%s: preset \"%s\" is not one of pbrt-v4's; sigma_a and sigma_s are "
                   "used",
                   params->owner, preset))
        return -1;
    m->rendered = 1;
    return read_coefficients(p, lex, d, params, from_preset, m) || read_emission(p, lex, d, params, m) ? -1 : 0;
}

/* A grid's "nx", "ny", "nz" (default 1, at least 1) and their product. */
static int grid_size(Parser *p, Lexer *lex, const Token *d, ParamList *params, int n[3], size_t *count)
{
    static const char *const names[3] = {"nx", "ny", "nz"};
    *count = 1;
    for (int k = 0; k < 3; ++k) {
        n[k] = 1;
        if (params_get_int(params, names[k], &n[k]) < 0)
            return -1;
        if (n[k] < 1)
            return scene_error(&p->diag, lex->path, d->line, "%s: \"%s\" must be at least 1", params->owner, names[k]);
        *count *= (size_t)n[k];
    }
    return 0;
}

/* A copy of a numeric parameter's values as floats (NULL when absent).
 * Returns 0 or -1. */
static int copy_values(Parser *p, Lexer *lex, const Token *d, ParamList *params, const char *name, ParamType type,
                       float **out)
{
    const Param *param = NULL;
    *out = NULL;
    if (params_get_array(params, name, type, &param) <= 0)
        return 0; /* absent (an error was reported by grid_values) */
    if (!(*out = malloc((param->count ? param->count : 1) * sizeof **out)))
        return out_of_memory(p, lex->path, d->line);
    for (size_t i = 0; i < param->count; ++i)
        (*out)[i] = (float)param->numbers[i];
    return 0;
}

/* A float array of `count` values, none negative (absent: 0 values read). */
static int grid_values(Parser *p, Lexer *lex, const Token *d, ParamList *params, const char *name, ParamType type,
                       size_t count, int required)
{
    const Param *param = NULL;
    int found = params_get_array(params, name, type, &param);
    if (found < 0)
        return -1;
    if (!found)
        return required
                   ? scene_error(&p->diag, lex->path, d->line, "%s: \"%s\" values are required", params->owner, name)
                   : 0;
    size_t per_value = type == PARAM_RGB ? 3 : 1;
    if (param->count != count * per_value)
        return params_error(params, param, "%zu values for a grid of %zu (nx * ny * nz)", param->count / per_value,
                            count);
    for (size_t i = 0; i < param->count; ++i)
        if (!(param->numbers[i] >= 0.0))
            return params_error(params, param, "value %zu, %g, is negative", i, param->numbers[i]);
    return 0;
}

/* The box the grid spans in the medium's space, "p0" to "p1" (default
 * the unit cube), each side longer than 0; the CTM places the medium. */
static int read_transform(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m);

static int read_bounds(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    static const char *const names[2] = {"p0", "p1"};
    for (int i = 0; i < 2; ++i) {
        const Param *param = NULL;
        int found = params_get_array(params, names[i], PARAM_POINT3, &param);
        if (found < 0)
            return -1;
        if (found && param->count != 3)
            return params_error(params, param, "expected one point (3 values), got %zu values", param->count);
        for (int k = 0; k < 3; ++k)
            m->bounds[i][k] = found ? (float)param->numbers[k] : (float)i;
    }
    for (int k = 0; k < 3; ++k)
        if (!(m->bounds[1][k] > m->bounds[0][k]))
            return scene_error(&p->diag, lex->path, d->line, "%s: \"p1\" must exceed \"p0\" along every axis",
                               params->owner);
    return read_transform(p, lex, d, params, m);
}

/* The medium's space: the CTM at MakeNamedMedium, which must be invertible. */
static int read_transform(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    memcpy(m->world_from_medium, p->state.ctm, sizeof m->world_from_medium);
    if (!(fabs(glm_mat3_det((mat3){{p->state.ctm[0][0], p->state.ctm[0][1], p->state.ctm[0][2]},
                                   {p->state.ctm[1][0], p->state.ctm[1][1], p->state.ctm[1][2]},
                                   {p->state.ctm[2][0], p->state.ctm[2][1], p->state.ctm[2][2]}})) > 1e-30))
        return scene_error(&p->diag, lex->path, d->line, "%s: the transform is singular", params->owner);
    return 0;
}

/* A uniformgrid with a "temperature" grid, made the rgbgrid it equals:
 * per cell sigma_a and sigma_s times the density, and as Le the blackbody
 * of the cell's temperature (pbrt-v4's BlackbodySpectrum, peak 1, none at
 * 100 K or below) in linear sRGB times the cell's "Lescale" value. pbrt-v4 interpolates the
 * temperature and then takes its blackbody; interpolating the cells' RGB
 * approximates that. */
static int temperature_to_rgb_grid(Parser *p, Lexer *lex, const Token *d, const Param *temperature, float offset,
                                   float temperature_scale, size_t n, SceneMedium *m)
{
    float *a = malloc(3 * n * sizeof *a), *s = malloc(3 * n * sizeof *s), *le = malloc(3 * n * sizeof *le);
    if (!a || !s || !le) {
        free(a);
        free(s);
        free(le);
        return out_of_memory(p, lex->path, d->line);
    }
    for (size_t i = 0; i < n; ++i) {
        double rgb[3];
        spectrum_blackbody_srgb((temperature->numbers[i] - (double)offset) * (double)temperature_scale, rgb);
        double cell = m->le_scale ? (double)m->le_scale[i] : 1.0;
        for (int k = 0; k < 3; ++k) {
            a[3 * i + (size_t)k] = m->density[i] * m->sigma_a[k];
            s[3 * i + (size_t)k] = m->density[i] * m->sigma_s[k];
            le[3 * i + (size_t)k] = (float)(rgb[k] * cell);
        }
    }
    free(m->density);
    free(m->le_scale);
    m->density = m->le_scale = NULL;
    m->rgb_sigma_a = a;
    m->rgb_sigma_s = s;
    m->rgb_le = le;
    for (int k = 0; k < 3; ++k) {
        m->sigma_a[k] = m->sigma_s[k] = 1.0f;
        m->emission[k] = 1.0f;
    }
    m->type = SCENE_MEDIUM_RGB_GRID;
    m->rendered = 1;
    return 0;
}

static int read_uniform_grid(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    size_t n;
    const Param *le = NULL, *temperature = NULL;
    if (grid_size(p, lex, d, params, m->size, &n) || grid_values(p, lex, d, params, "density", PARAM_FLOAT, n, 1) ||
        grid_values(p, lex, d, params, "temperature", PARAM_FLOAT, n, 0) ||
        params_get_array(params, "temperature", PARAM_FLOAT, &temperature) < 0)
        return -1;
    /* Le: one spectrum, scaled per cell by the "Lescale" grid. */
    for (size_t i = 0; i < params->count; ++i)
        if (strcmp(params->items[i].name, "Le") == 0)
            le = &params->items[i];
    if (le && temperature)
        return scene_error(&p->diag, lex->path, d->line, "%s: both \"Le\" and \"temperature\" are given",
                           params->owner);
    /* pbrt-v4: T = (t - "temperatureoffset") * "temperaturescale", the
     * offset defaulting to "temperaturecutoff" (default 0). */
    float cutoff = 0.0f, offset, temperature_scale = 1.0f;
    if (params_get_spectrum(params, "Le", SPECTRUM_ILLUMINANT, m->emission) < 0 ||
        grid_values(p, lex, d, params, "Lescale", PARAM_FLOAT, n, 0) ||
        params_get_float(params, "temperaturecutoff", &cutoff) < 0 || ((offset = cutoff), 0) ||
        params_get_float(params, "temperatureoffset", &offset) < 0 ||
        params_get_float(params, "temperaturescale", &temperature_scale) < 0 || read_bounds(p, lex, d, params, m) ||
        read_coefficients(p, lex, d, params, 0, m) ||
        copy_values(p, lex, d, params, "density", PARAM_FLOAT, &m->density) ||
        copy_values(p, lex, d, params, "Lescale", PARAM_FLOAT, &m->le_scale))
        return -1;
    if (temperature)
        return temperature_to_rgb_grid(p, lex, d, temperature, offset, temperature_scale, n, m);
    if (m->le_scale) {
        memcpy(m->le_size, m->size, sizeof m->le_size);
    } else { /* pbrt-v4's one cell of 1 (its Le's normalisation, applied to Le here) */
        if (!(m->le_scale = malloc(sizeof *m->le_scale)))
            return out_of_memory(p, lex->path, d->line);
        m->le_scale[0] = 1.0f;
        m->le_size[0] = m->le_size[1] = m->le_size[2] = 1;
    }
    m->rendered = 1;
    return 0;
}

static int read_rgb_grid(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    size_t n;
    const Param *sigma_a = NULL, *sigma_s = NULL, *le = NULL;
    if (grid_size(p, lex, d, params, m->size, &n) || params_get_array(params, "sigma_a", PARAM_RGB, &sigma_a) < 0 ||
        params_get_array(params, "sigma_s", PARAM_RGB, &sigma_s) < 0 ||
        params_get_array(params, "Le", PARAM_RGB, &le) < 0)
        return -1;
    if (!sigma_a && !sigma_s)
        return scene_error(&p->diag, lex->path, d->line, "%s: \"sigma_a\" or \"sigma_s\" values are required",
                           params->owner);
    if (le && !sigma_a)
        return scene_error(&p->diag, lex->path, d->line, "%s: \"Le\" needs \"sigma_a\"", params->owner);
    float scale = 1.0f, le_scale = 1.0f;
    if (grid_values(p, lex, d, params, "sigma_a", PARAM_RGB, n, 0) ||
        grid_values(p, lex, d, params, "sigma_s", PARAM_RGB, n, 0) ||
        grid_values(p, lex, d, params, "Le", PARAM_RGB, n, 0) ||
        get_float_in(p, lex, d, params, "scale", 0.0f, FLT_MAX, &scale) ||
        get_float_in(p, lex, d, params, "Lescale", 0.0f, FLT_MAX, &le_scale) ||
        get_float_in(p, lex, d, params, "g", -0.999f, 0.999f, &m->g) || read_bounds(p, lex, d, params, m) ||
        copy_values(p, lex, d, params, "sigma_a", PARAM_RGB, &m->rgb_sigma_a) ||
        copy_values(p, lex, d, params, "sigma_s", PARAM_RGB, &m->rgb_sigma_s) ||
        copy_values(p, lex, d, params, "Le", PARAM_RGB, &m->rgb_le))
        return -1;
    for (int k = 0; k < 3; ++k) {
        m->sigma_a[k] = m->sigma_s[k] = scale;
        m->emission[k] = le_scale;
    }
    m->rendered = 1;
    return 0;
}

static int read_cloud(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    m->cloud[0] = 1.0f; /* density, wispiness, frequency: pbrt-v4's defaults */
    m->cloud[1] = 1.0f;
    m->cloud[2] = 5.0f;
    if (get_float_in(p, lex, d, params, "density", 0.0f, FLT_MAX, &m->cloud[0]) ||
        params_get_float(params, "wispiness", &m->cloud[1]) < 0 ||
        params_get_float(params, "frequency", &m->cloud[2]) < 0)
        return -1;
    m->rendered = 1;
    return read_bounds(p, lex, d, params, m) || read_coefficients(p, lex, d, params, 0, m) ? -1 : 0;
}

/* One grid of a NanoVDB file: 0, 1 when the file has none of that name
 * (and `required` is 0), or -1 after a file:line error. */
static int read_nanovdb_grid(Parser *p, Lexer *lex, const Token *d, const char *owner, const char *path,
                             const char *name, int required, NanoGrid *grid)
{
    char error[512];
    int found = nanovdb_read(path, name, grid, error, sizeof error);
    if (found < 0)
        return scene_error(&p->diag, lex->path, d->line, "%s: \"%s\": %s", owner, path, error);
    if (found == 1 && required)
        return scene_error(&p->diag, lex->path, d->line, "%s: \"%s\" has no grid \"%s\"", owner, path, name);
    return found;
}

/* A NanoVDB file's "density" grid (its name "gridname") and, where the file
 * has one, its "temperature" grid ("temperaturename"), with the parameters
 * pbrt-v4 reads: sigma_a, sigma_s (default 1), scale, g, Lescale and the
 * temperature's cutoff, offset (default the cutoff) and scale. */
static int read_nanovdb(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m)
{
    const char *filename = NULL, *gridname = "density", *temperaturename = "temperature";
    float cutoff = 0.0f, le_scale = 1.0f;
    m->temperature_scale = 1.0f;
    if (params_get_string(params, "filename", &filename) < 0 || params_get_string(params, "gridname", &gridname) < 0 ||
        params_get_string(params, "temperaturename", &temperaturename) < 0 ||
        params_get_float(params, "temperaturecutoff", &cutoff) < 0 || ((m->temperature_offset = cutoff), 0) ||
        params_get_float(params, "temperatureoffset", &m->temperature_offset) < 0 ||
        get_float_in(p, lex, d, params, "temperaturescale", 0.0f, FLT_MAX, &m->temperature_scale) ||
        get_float_in(p, lex, d, params, "Lescale", 0.0f, FLT_MAX, &le_scale) ||
        read_coefficients(p, lex, d, params, 0, m) || read_transform(p, lex, d, params, m))
        return -1;
    if (!filename || !*filename)
        return scene_error(&p->diag, lex->path, d->line, "%s: \"filename\" is required", params->owner);
    char *path = resolve_path(p, lex->path, filename);
    if (!path)
        return out_of_memory(p, lex->path, d->line);
    int result = scene_missing_file(&p->diag, lex->path, d->line, path, params->owner);
    if (result == 0)
        result = read_nanovdb_grid(p, lex, d, params->owner, path, gridname, 1, &m->nanovdb_density);
    if (result == 0 &&
        read_nanovdb_grid(p, lex, d, params->owner, path, temperaturename, 0, &m->nanovdb_temperature) < 0)
        result = -1;
    free(path);
    if (result != 0)
        return result < 0 ? -1 : 0;
    for (int k = 0; k < 3; ++k) {
        m->emission[k] = le_scale;
        double lo = m->nanovdb_density.world_bounds[0][k], hi = m->nanovdb_density.world_bounds[1][k];
        if (m->nanovdb_temperature.data) {
            lo = fmin(lo, m->nanovdb_temperature.world_bounds[0][k]);
            hi = fmax(hi, m->nanovdb_temperature.world_bounds[1][k]);
        }
        m->bounds[0][k] = (float)lo;
        m->bounds[1][k] = (float)hi;
        if (!(m->bounds[1][k] > m->bounds[0][k]))
            return scene_error(&p->diag, lex->path, d->line, "%s: the grids' box is empty along an axis",
                               params->owner);
    }
    m->rendered = 1;
    return 0;
}

static const struct {
    const char *name;
    SceneMediumType type;
    int (*read)(Parser *p, Lexer *lex, const Token *d, ParamList *params, SceneMedium *m);
} medium_types[] = {
    {"homogeneous", SCENE_MEDIUM_HOMOGENEOUS, read_homogeneous},
    {"uniformgrid", SCENE_MEDIUM_UNIFORM_GRID, read_uniform_grid},
    {"rgbgrid", SCENE_MEDIUM_RGB_GRID, read_rgb_grid},
    {"cloud", SCENE_MEDIUM_CLOUD, read_cloud},
    {"nanovdb", SCENE_MEDIUM_NANOVDB, read_nanovdb},
};

int on_make_named_medium(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the medium's name", &name, &params);
    int index = -1;
    if (result == 0)
        result = medium_index(p, lex->path, d->line, name.text, name.length, &index);
    if (result == 0 && index < 0)
        result = scene_error(&p->diag, lex->path, d->line, "MakeNamedMedium: the name must not be empty");
    if (result == 0 && p->medium_names[index].defined)
        result = scene_error(&p->diag, lex->path, d->line, "MakeNamedMedium: \"%s\" is defined twice",
                             p->scene->media[index].name);
    const char *type = NULL;
    if (result == 0 && params_get_string(&params, "type", &type) < 0)
        result = -1;
    if (result == 0 && !type)
        result = scene_error(&p->diag, lex->path, d->line, "MakeNamedMedium \"%s\": missing \"string type\"",
                             p->scene->media[index].name);
    size_t kind = 0;
    while (result == 0 && kind < sizeof medium_types / sizeof medium_types[0] &&
           strcmp(medium_types[kind].name, type) != 0)
        ++kind;
    if (result == 0 && kind == sizeof medium_types / sizeof medium_types[0])
        result = scene_error(&p->diag, lex->path, d->line,
                             "MakeNamedMedium \"%s\": unknown type \"%s\" (homogeneous, uniformgrid, rgbgrid, cloud, "
                             "nanovdb)",
                             p->scene->media[index].name, type);
    SceneMedium m;
    memset(&m, 0, sizeof m);
    if (result == 0) {
        m.type = medium_types[kind].type;
        result = medium_types[kind].read(p, lex, d, &params, &m);
    }
    if (result == 0)
        result = params_check_unused(&params);
    char origin[512];
    snprintf(origin, sizeof origin, "%s:%d", lex->path, d->line);
    if (result == 0 && !(m.origin = scene_strndup(origin, strlen(origin))))
        result = out_of_memory(p, lex->path, d->line);
    if (result == 0) {
        m.name = p->scene->media[index].name;
        p->scene->media[index] = m;
        p->medium_names[index].defined = 1;
    } else {
        free(m.density);
        free(m.le_scale);
        free(m.rgb_sigma_a);
        free(m.rgb_sigma_s);
        free(m.rgb_le);
        nanovdb_free(&m.nanovdb_density);
        nanovdb_free(&m.nanovdb_temperature);
    }
    params_free(&params);
    return result;
}

int finish_media(Parser *p)
{
    Scene *s = p->scene;
    for (size_t i = 0; i < s->medium_count; ++i)
        if (!p->medium_names[i].defined && !files_missing(p))
            return scene_error(&p->diag, p->medium_names[i].file, p->medium_names[i].line,
                               "medium \"%s\" is not defined (MakeNamedMedium)", s->media[i].name);
    int used = s->camera_medium >= 0;
    for (size_t i = 0; i < s->shape_count && !used; ++i)
        used = s->shapes[i].medium_inside != s->shapes[i].medium_outside;
    if (used && !s->integrator_media)
        return scene_note(&p->diag, p->main_path, 0,
                          "the integrator ignores the scene's participating media, as pbrt-v4's does (\"volpath\" "
                          "renders them)");
    return 0;
}
