#include "scene/params.h"
#include "scene/read_file.h"
#include "scene/scene_internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    const char *name;
    ParamType type;
} param_types[] = {
    {"integer", PARAM_INTEGER},     {"float", PARAM_FLOAT},       {"point2", PARAM_POINT2},
    {"vector2", PARAM_VECTOR2},     {"point3", PARAM_POINT3},     {"point", PARAM_POINT3},
    {"vector3", PARAM_VECTOR3},     {"vector", PARAM_VECTOR3},    {"normal3", PARAM_NORMAL3},
    {"normal", PARAM_NORMAL3},      {"rgb", PARAM_RGB},           {"color", PARAM_RGB},
    {"blackbody", PARAM_BLACKBODY}, {"spectrum", PARAM_SPECTRUM}, {"bool", PARAM_BOOL},
    {"string", PARAM_STRING},       {"texture", PARAM_TEXTURE},
};

/* How many numbers one value of a numeric type takes (0: not numeric). */
static size_t type_arity(ParamType type)
{
    switch (type) {
    case PARAM_INTEGER:
    case PARAM_FLOAT:
    case PARAM_BLACKBODY:
        return 1;
    case PARAM_POINT2:
    case PARAM_VECTOR2:
        return 2;
    case PARAM_POINT3:
    case PARAM_VECTOR3:
    case PARAM_NORMAL3:
    case PARAM_RGB:
        return 3;
    default:
        return 0;
    }
}

int params_error(ParamList *list, const Param *param, const char *format, ...)
{
    char message[320];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return scene_error(list->diag, list->file, param->line, "%s: parameter \"%s %s\": %s", list->owner,
                       param->type_name, param->name, message);
}

static void param_free(Param *p)
{
    free(p->type_name);
    free(p->name);
    free(p->numbers);
    if (p->strings)
        for (size_t i = 0; i < p->count; ++i)
            free(p->strings[i]);
    free(p->strings);
}

void params_free(ParamList *list)
{
    for (size_t i = 0; i < list->count; ++i)
        param_free(&list->items[i]);
    free(list->items);
    list->items = NULL;
    list->count = 0;
}

/* Splits "type name" into its two words. */
static int parse_declaration(ParamList *list, const Token *decl, Param *p)
{
    const char *s = decl->text, *end = decl->text + decl->length;
    const char *words[3];
    size_t lengths[3];
    int n = 0;
    while (s < end) {
        while (s < end && (*s == ' ' || *s == '\t'))
            s++;
        if (s == end)
            break;
        const char *start = s;
        while (s < end && *s != ' ' && *s != '\t')
            s++;
        if (n == 3)
            break;
        words[n] = start;
        lengths[n] = (size_t)(s - start);
        n++;
    }
    char shown[64];
    token_describe(decl, shown, sizeof shown);
    if (n != 2)
        return scene_error(list->diag, list->file, decl->line, "%s: malformed parameter %s: expected \"type name\"",
                           list->owner, shown);
    p->type_name = scene_strndup(words[0], lengths[0]);
    p->name = scene_strndup(words[1], lengths[1]);
    if (!p->type_name || !p->name)
        return scene_error(list->diag, list->file, decl->line, "out of memory");
    for (size_t i = 0; i < sizeof param_types / sizeof param_types[0]; ++i)
        if (strcmp(p->type_name, param_types[i].name) == 0) {
            p->type = param_types[i].type;
            return 0;
        }
    return scene_error(list->diag, list->file, decl->line, "%s: unknown parameter type \"%s\" in %s", list->owner,
                       p->type_name, shown);
}

/* Collects the value tokens: one token, or everything between brackets. */
static int read_values(Lexer *lexer, ParamList *list, Param *p, Token **values, size_t *count)
{
    Token t;
    char shown[64];
    if (lexer_next(lexer, &t))
        return -1;
    size_t capacity = 0;
    *values = NULL;
    *count = 0;
    if (t.kind == TOKEN_WORD || t.kind == TOKEN_STRING) {
        *values = malloc(sizeof **values);
        if (!*values)
            return scene_error(list->diag, list->file, t.line, "out of memory");
        (*values)[0] = t;
        *count = 1;
        return 0;
    }
    if (t.kind != TOKEN_OPEN) {
        token_describe(&t, shown, sizeof shown);
        return params_error(list, p, "expected a value or '[', got %s", shown);
    }
    int open_line = t.line;
    for (;;) {
        if (lexer_next(lexer, &t))
            return -1;
        if (t.kind == TOKEN_CLOSE)
            return 0;
        if (t.kind == TOKEN_END)
            return scene_error(list->diag, list->file, open_line,
                               "%s: parameter \"%s %s\": unterminated '[' (end of file before ']')", list->owner,
                               p->type_name, p->name);
        if (t.kind == TOKEN_OPEN)
            return params_error(list, p, "unexpected '[' inside a list (missing ']'?)");
        if (scene_reserve((void **)values, &capacity, *count + 1, sizeof **values))
            return scene_error(list->diag, list->file, t.line, "out of memory");
        (*values)[(*count)++] = t;
    }
}

/* Converts value tokens to the parameter's type. */
static int convert_values(ParamList *list, Param *p, const Token *values, size_t count)
{
    char shown[64];
    size_t arity = type_arity(p->type);
    p->count = count;
    int numeric =
        arity > 0 || p->type == PARAM_BOOL || (p->type == PARAM_SPECTRUM && count > 0 && values[0].kind == TOKEN_WORD);
    if (numeric) {
        p->numbers = malloc((count ? count : 1) * sizeof *p->numbers);
        if (!p->numbers)
            return params_error(list, p, "out of memory");
    } else {
        p->strings = calloc(count ? count : 1, sizeof *p->strings);
        if (!p->strings)
            return params_error(list, p, "out of memory");
    }
    for (size_t i = 0; i < count; ++i) {
        const Token *v = &values[i];
        token_describe(v, shown, sizeof shown);
        if (p->type == PARAM_BOOL) {
            if (token_is(v, "true"))
                p->numbers[i] = 1.0;
            else if (token_is(v, "false"))
                p->numbers[i] = 0.0;
            else
                return params_error(list, p, "expected true or false, got %s", shown);
        } else if (numeric) {
            double x;
            if (v->kind != TOKEN_WORD || token_number(v, &x))
                return params_error(list, p, "expected a finite number, got %s", shown);
            if (p->type == PARAM_INTEGER) {
                if (x != floor(x) || x < -2147483648.0 || x > 2147483647.0)
                    return params_error(list, p, "expected a 32-bit integer, got %s", shown);
            } else if (fabs(x) > FLT_MAX) {
                return params_error(list, p, "%s is too large for a float", shown);
            }
            p->numbers[i] = x;
        } else {
            if (v->kind != TOKEN_STRING)
                return params_error(list, p, "expected a quoted string, got %s", shown);
            p->strings[i] = scene_strndup(v->text, v->length);
            if (!p->strings[i])
                return params_error(list, p, "out of memory");
        }
    }
    if (arity > 1 && count % arity != 0)
        return params_error(list, p, "expected a multiple of %zu values, got %zu", arity, count);
    return 0;
}

/* A parameter named again in the same list: pbrt-v4's lookups take the
 * last one (ParameterDictionary reverses the list) and never see the
 * earlier, so the earlier is dropped, with a warning. Returns 0 or -1. */
static int drop_earlier_duplicate(ParamList *list)
{
    Param *last = &list->items[list->count - 1];
    for (size_t i = 0; i + 1 < list->count; ++i) {
        Param *earlier = &list->items[i];
        if (strcmp(earlier->name, last->name) != 0)
            continue;
        if (scene_warn(list->diag, list->file, last->line,
                       "%s: parameter \"%s\" given twice (first at line %d): the last one is used, as pbrt-v4 does",
                       list->owner, last->name, earlier->line))
            return -1;
        param_free(earlier);
        memmove(earlier, earlier + 1, (list->count - 1 - i) * sizeof *earlier);
        list->count--;
        return 0; /* there was at most one: each duplicate is dropped when it is read */
    }
    return 0;
}

int params_parse(Lexer *lexer, const char *owner, ParamList *list)
{
    memset(list, 0, sizeof *list);
    list->file = lexer->path;
    list->diag = lexer->diag;
    snprintf(list->owner, sizeof list->owner, "%s", owner);
    size_t capacity = 0;
    for (;;) {
        Token decl;
        if (lexer_peek(lexer, &decl))
            return -1;
        if (decl.kind != TOKEN_STRING)
            return 0;
        lexer_next(lexer, &decl);
        if (scene_reserve((void **)&list->items, &capacity, list->count + 1, sizeof *list->items))
            return scene_error(list->diag, list->file, decl.line, "out of memory");
        Param *p = &list->items[list->count++];
        memset(p, 0, sizeof *p);
        p->line = decl.line;
        if (parse_declaration(list, &decl, p))
            return -1;
        Token *values = NULL;
        size_t count = 0;
        int result = read_values(lexer, list, p, &values, &count);
        if (result == 0)
            result = convert_values(list, p, values, count);
        free(values);
        if (result || drop_earlier_duplicate(list))
            return -1;
    }
}

static Param *find(ParamList *list, const char *name)
{
    for (size_t i = 0; i < list->count; ++i)
        if (list->items[i].name && strcmp(list->items[i].name, name) == 0) {
            list->items[i].used = 1;
            return &list->items[i];
        }
    return NULL;
}

static const char *type_word(ParamType type)
{
    for (size_t i = 0; i < sizeof param_types / sizeof param_types[0]; ++i)
        if (param_types[i].type == type)
            return param_types[i].name;
    return "?";
}

/* Checks the type and, when count > 0, the number of values. Returns 0, -1
 * on an error, or 1 for a texture or spectral value that allow_unsupported
 * lets through with a warning (the caller treats it as absent). */
static int check(ParamList *list, const Param *p, ParamType type, size_t count)
{
    if (p->type == PARAM_TEXTURE || p->type == PARAM_SPECTRUM || p->type == PARAM_BLACKBODY)
        return scene_unsupported(list->diag, list->file, p->line, "the default is used",
                                 "%s: parameter \"%s %s\": %s values are not supported, only \"%s %s\"", list->owner,
                                 p->type_name, p->name, p->type_name, type_word(type), p->name)
                   ? -1
                   : 1;
    if (p->type != type)
        return params_error(list, p, "wrong type, expected \"%s %s\"", type_word(type), p->name);
    if (count > 0 && p->count != count)
        return params_error(list, p, "expected %zu value%s, got %zu", count, count == 1 ? "" : "s", p->count);
    return 0;
}

/* Finds and checks a parameter: 1 found and valid, 0 absent, -1 error. */
static int lookup(ParamList *list, const char *name, ParamType type, size_t count, const Param **param)
{
    const Param *p = find(list, name);
    if (!p)
        return 0;
    int status = check(list, p, type, count);
    if (status)
        return status < 0 ? -1 : 0;
    *param = p;
    return 1;
}

int params_take_texture(ParamList *list, const char *name, const char **texture)
{
    for (size_t i = 0; i < list->count; ++i) {
        Param *p = &list->items[i];
        if (!p->name || strcmp(p->name, name) != 0 || p->type != PARAM_TEXTURE)
            continue;
        if (p->count != 1)
            return params_error(list, p, "expected 1 texture name, got %zu", p->count);
        *texture = p->strings[0];
        p->used = 1;
        free(p->name); /* out of the lookups: the value's getters see no texture */
        p->name = NULL;
        return 1;
    }
    return 0;
}

int params_get_float(ParamList *list, const char *name, float *value)
{
    const Param *p = NULL;
    int found = lookup(list, name, PARAM_FLOAT, 1, &p);
    if (found == 1)
        *value = (float)p->numbers[0];
    return found;
}

int params_get_int(ParamList *list, const char *name, int *value)
{
    const Param *p = NULL;
    int found = lookup(list, name, PARAM_INTEGER, 1, &p);
    if (found == 1)
        *value = (int)p->numbers[0];
    return found;
}

int params_get_bool(ParamList *list, const char *name, int *value)
{
    const Param *p = NULL;
    int found = lookup(list, name, PARAM_BOOL, 1, &p);
    if (found == 1)
        *value = p->numbers[0] != 0.0;
    return found;
}

int params_get_string(ParamList *list, const char *name, const char **value)
{
    const Param *p = NULL;
    int found = lookup(list, name, PARAM_STRING, 1, &p);
    if (found == 1)
        *value = p->strings[0];
    return found;
}

int params_get_rgb(ParamList *list, const char *name, int is_albedo, float value[3])
{
    const Param *p = NULL;
    int found = lookup(list, name, PARAM_RGB, 3, &p);
    if (found != 1)
        return found;
    for (int i = 0; i < 3; ++i) {
        if (p->numbers[i] < 0.0)
            return params_error(list, p, "negative value %g", p->numbers[i]);
        if (is_albedo && p->numbers[i] > 1.0)
            return params_error(list, p, "reflectance %g is above 1", p->numbers[i]);
    }
    for (int i = 0; i < 3; ++i)
        value[i] = (float)p->numbers[i];
    return 1;
}

/* A spectrum name that is neither built in nor a readable file: bad input,
 * an error. Check mode lists it and goes on with a constant 1 (which passes
 * every range check), so that the rest of the scene is checked too. */
static int unknown_spectrum(ParamList *list, const Param *p, const char *path, const char *why, Spectrum *s)
{
    if (!list->diag->check)
        return params_error(list, p, "\"%s\" is not a named spectrum, and cannot read \"%s\": %s", p->strings[0], path,
                            why);
    if (scene_unsupported(list->diag, list->file, p->line, "check goes on with a constant 1",
                          "%s: parameter \"%s %s\": \"%s\" is not a named spectrum, and cannot read \"%s\": %s",
                          list->owner, p->type_name, p->name, p->strings[0], path, why))
        return -1;
    double lambda = 550.0, one = 1.0;
    spectrum_from_pairs(&lambda, &one, 1, 1, s);
    return 0;
}

/* The spectrum a "spectrum" parameter names: built in, else an .spd file. */
static int named_or_file_spectrum(ParamList *list, const Param *p, Spectrum *s)
{
    if (p->count != 1)
        return params_error(list, p, "expected one name or file name, got %zu strings", p->count);
    if (spectrum_named(p->strings[0], s) == 0)
        return 0;
    char *path = scene_resolve_path(list->file, list->main_file, p->strings[0]);
    if (!path)
        return params_error(list, p, "out of memory");
    char *text = NULL, why[160];
    size_t size = 0;
    int result = 0;
    if (scene_read_file(path, SCENE_MAX_TEXT_BYTES, &text, &size, why, sizeof why))
        result = unknown_spectrum(list, p, path, why, s);
    else if (spectrum_parse_spd(text, s, why, sizeof why))
        result = params_error(list, p, "\"%s\": %s", path, why);
    free(text);
    free(path);
    return result;
}

static int inline_spectrum(ParamList *list, const Param *p, Spectrum *s)
{
    if (p->count < 2 || p->count % 2 != 0)
        return params_error(list, p, "expected (wavelength, value) pairs, got %zu value%s", p->count,
                            p->count == 1 ? "" : "s");
    size_t n = p->count / 2;
    double *lambda = malloc(n * sizeof *lambda), *value = malloc(n * sizeof *value);
    int result = lambda && value ? 0 : params_error(list, p, "out of memory");
    for (size_t i = 0; result == 0 && i < n; ++i) {
        lambda[i] = p->numbers[2 * i];
        value[i] = p->numbers[2 * i + 1];
        if (i > 0 && !(lambda[i] > lambda[i - 1]))
            result = params_error(list, p, "wavelengths do not increase at pair %zu (%g after %g)", i + 1, lambda[i],
                                  lambda[i - 1]);
    }
    if (result == 0)
        spectrum_from_pairs(lambda, value, n, 1, s); /* pbrt-v4 holds the end values of inline spectra */
    free(lambda);
    free(value);
    return result;
}

/* Reads a blackbody or spectrum parameter onto the grid and checks its values. */
static int read_spectrum(ParamList *list, const Param *p, SpectrumKind kind, Spectrum *s)
{
    if (p->type == PARAM_BLACKBODY) {
        if (p->count != 1)
            return params_error(list, p, "expected one temperature, got %zu values", p->count);
        if (!(p->numbers[0] > 0.0))
            return params_error(list, p, "temperature %g K is not positive", p->numbers[0]);
        spectrum_blackbody(p->numbers[0], s);
    } else if ((p->strings ? named_or_file_spectrum(list, p, s) : inline_spectrum(list, p, s)) < 0) {
        return -1;
    }
    for (int i = 0; i < SPECTRUM_SAMPLES; ++i) {
        if (s->value[i] < 0.0)
            return params_error(list, p, "negative value %g at %d nm", s->value[i], SPECTRUM_LAMBDA_MIN + i);
        if (kind == SPECTRUM_ALBEDO && s->value[i] > 1.0)
            return params_error(list, p, "reflectance %g at %d nm is above 1", s->value[i], SPECTRUM_LAMBDA_MIN + i);
    }
    return 0;
}

static int wrong_spectrum_type(ParamList *list, const Param *p, const char *plain)
{
    return params_error(list, p, "wrong type, expected \"%s %s\", \"spectrum %s\" or \"blackbody %s\"", plain, p->name,
                        p->name, p->name);
}

/* A spectrum outside the sRGB gamut has a negative channel (and an albedo
 * one above 1): clipped, the renderer's radiance is never negative. */
static void clipped_rgb(const double value[3], SpectrumKind kind, float rgb[3])
{
    for (int k = 0; k < 3; ++k) {
        double v = value[k] < 0.0 ? 0.0 : value[k];
        rgb[k] = (float)(kind == SPECTRUM_ALBEDO && v > 1.0 ? 1.0 : v);
    }
}

int params_get_spectrum(ParamList *list, const char *name, SpectrumKind kind, float rgb[3])
{
    Param *p = find(list, name);
    if (!p)
        return 0;
    if (p->type == PARAM_RGB)
        return params_get_rgb(list, name, kind == SPECTRUM_ALBEDO, rgb);
    if (p->type == PARAM_TEXTURE)
        return check(list, p, PARAM_RGB, 3) < 0 ? -1 : 0;
    if (p->type != PARAM_SPECTRUM && p->type != PARAM_BLACKBODY)
        return wrong_spectrum_type(list, p, "rgb");
    Spectrum s;
    if (read_spectrum(list, p, kind, &s))
        return -1;
    double value[3];
    spectrum_to_rgb(&s, kind, value);
    clipped_rgb(value, kind, rgb);
    return 1;
}

int params_get_conductor(ParamList *list, const char *prefix, float eta[3], float k[3])
{
    char names[2][64];
    snprintf(names[0], sizeof names[0], "%seta", prefix);
    snprintf(names[1], sizeof names[1], "%sk", prefix);
    float *rgb[2] = {eta, k};
    Spectrum s[2];
    double value[2][3];
    spectrum_named("metal-Cu-eta", &s[0]); /* pbrt-v4's default conductor: copper */
    spectrum_named("metal-Cu-k", &s[1]);
    spectrum_conductor_rgb(&s[0], &s[1], value[0], value[1]);
    int spectral[2], given = 0;
    for (int i = 0; i < 2; ++i) {
        clipped_rgb(value[i], SPECTRUM_UNBOUNDED, rgb[i]);
        Param *p = find(list, names[i]);
        given |= p != NULL;
        spectral[i] = !p || p->type == PARAM_SPECTRUM || p->type == PARAM_BLACKBODY;
        if (p && (spectral[i] ? read_spectrum(list, p, SPECTRUM_UNBOUNDED, &s[i])
                              : params_get_spectrum(list, names[i], SPECTRUM_UNBOUNDED, rgb[i]) < 0))
            return -1;
    }
    if (!given)
        return 0;
    if (spectral[0] && spectral[1])
        spectrum_conductor_rgb(&s[0], &s[1], value[0], value[1]);
    else /* an rgb one leaves the other spectrum nothing to be fitted with */
        for (int i = 0; i < 2; ++i)
            spectrum_to_rgb(&s[i], SPECTRUM_UNBOUNDED, value[i]);
    for (int i = 0; i < 2; ++i)
        if (spectral[i])
            clipped_rgb(value[i], SPECTRUM_UNBOUNDED, rgb[i]);
    return 1;
}

int params_get_eta(ParamList *list, const char *name, float *eta)
{
    Param *p = find(list, name);
    if (!p)
        return 0;
    if (p->type == PARAM_FLOAT || p->type == PARAM_TEXTURE)
        return params_get_float(list, name, eta);
    if (p->type != PARAM_SPECTRUM && p->type != PARAM_BLACKBODY)
        return wrong_spectrum_type(list, p, "float");
    Spectrum s;
    if (read_spectrum(list, p, SPECTRUM_UNBOUNDED, &s))
        return -1;
    *eta = (float)spectrum_eta(&s);
    return 1;
}

int params_get_array(ParamList *list, const char *name, ParamType type, const Param **param)
{
    return lookup(list, name, type, 0, param);
}

void params_ignore(ParamList *list, const char *name)
{
    find(list, name);
}

int params_check_unused(ParamList *list)
{
    for (size_t i = 0; i < list->count; ++i) {
        const Param *p = &list->items[i];
        if (!p->used && scene_unsupported(list->diag, list->file, p->line, "ignored",
                                          "%s: unsupported parameter \"%s %s\"", list->owner, p->type_name, p->name))
            return -1;
    }
    return 0;
}
