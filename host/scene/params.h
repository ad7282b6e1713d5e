/* A directive's parameter list: `"type name" value` or `"type name" [ values ]`,
 * checked against its type as it is read ("float fov" [ "x" ] and "rgb L"
 * with two values are errors), then looked up by name and type. */
#ifndef HOST_SCENE_PARAMS_H
#define HOST_SCENE_PARAMS_H

#include "scene/lexer.h"
#include "scene/spectrum.h"

#include <stddef.h>

typedef enum {
    PARAM_INTEGER,
    PARAM_FLOAT,
    PARAM_POINT2,
    PARAM_VECTOR2,
    PARAM_POINT3,  /* also written "point" */
    PARAM_VECTOR3, /* also "vector" */
    PARAM_NORMAL3, /* also "normal" */
    PARAM_RGB,     /* also "color" */
    PARAM_BLACKBODY,
    PARAM_SPECTRUM,
    PARAM_BOOL,
    PARAM_STRING,
    PARAM_TEXTURE,
} ParamType;

typedef struct {
    ParamType type;
    char *type_name; /* as written, for messages */
    char *name;
    double *numbers; /* numeric types; bools as 0 or 1 */
    char **strings;  /* string, texture; a spectrum given by name */
    size_t count;    /* values in numbers or strings */
    int line;
    int used;
} Param;

typedef struct {
    Param *items;
    size_t count;
    const char *file;
    const char *main_file; /* the scene's main file: .spd names fall back to its directory */
    char owner[96];        /* the directive, e.g. Shape "sphere", for messages */
    Diagnostics *diag;
} ParamList;

/* Reads parameters for as long as the next token is a quoted string.
 * Returns 0, or -1 with an error; free the list either way. */
int params_parse(Lexer *lexer, const char *owner, ParamList *list);
void params_free(ParamList *list);

/* Getters return 1 when the parameter is present (value written), 0 when it
 * is absent (value untouched), -1 on an error (wrong type or count). A
 * texture or spectral value is unsupported: an error, or with
 * allow_unsupported a warning and 0 (the default is used). */
int params_get_float(ParamList *list, const char *name, float *value);
int params_get_int(ParamList *list, const char *name, int *value);
int params_get_bool(ParamList *list, const char *name, int *value);
int params_get_string(ParamList *list, const char *name, const char **value);
/* An "rgb" triple of non-negative values (at most 1 when is_albedo). */
int params_get_rgb(ParamList *list, const char *name, int is_albedo, float value[3]);
/* A spectral parameter reduced to linear sRGB by `kind` (spectrum.h):
 * "rgb" (used as given: pbrt-v4 normalises an RGB emitter by its colour
 * space's illuminant, whose RGB is (1, 1, 1)), "blackbody" (a temperature in
 * kelvin), or "spectrum" given as inline (wavelength, value) pairs, a name
 * of pbrt-v4's (metal-Au-eta, ...) or an .spd file (resolved like Include).
 * Values must not be negative, and an albedo not above 1. */
int params_get_spectrum(ParamList *list, const char *name, SpectrumKind kind, float rgb[3]);
/* A conductor's "eta" and "k", named after `prefix` ("" for conductor,
 * "conductor." for coatedconductor) (defaults: pbrt-v4's copper,
 * metal-Cu-eta and metal-Cu-k). Where both are spectra,
 * spectrum_conductor_rgb fits the pair; an "rgb" one is used as given and
 * the other reduced alone. Returns 1 if either is given, 0 if neither, -1
 * on error. */
int params_get_conductor(ParamList *list, const char *prefix, float eta[3], float k[3]);
/* A dielectric's "float eta", or a spectrum (a named glass such as
 * glass-BK7) reduced to one value by spectrum_eta. */
int params_get_eta(ParamList *list, const char *name, float *eta);
/* A "texture name" parameter: *texture the texture's name (alive until the
 * list is freed); the parameter then leaves the list, so that a value
 * getter for the same name finds nothing. 1 taken, 0 none, -1 error. */
int params_take_texture(ParamList *list, const char *name, const char **texture);
/* Any number of values of one numeric type (P, N, indices). */
int params_get_array(ParamList *list, const char *name, ParamType type, const Param **param);

/* Marks a parameter as read, whatever its type (accepted and ignored). */
void params_ignore(ParamList *list, const char *name);

/* Every parameter no getter read is unsupported: an error, or one warning
 * each with allow_unsupported. Returns 0 or -1. */
int params_check_unused(ParamList *list);

/* "file:line: <owner>: parameter "type name": message". Returns -1. */
int params_error(ParamList *list, const Param *param, const char *format, ...) SCENE_PRINTF(3, 4);

#endif
