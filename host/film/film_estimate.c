#include "film/film.h"

#include "estimators.h" /* kernels/: the shared code */

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static EstimatorStatus invalid(char *message, size_t message_size, const char *format, ...)
{
    if (message && message_size > 0) {
        va_list args;
        va_start(args, format);
        vsnprintf(message, message_size, format, args);
        va_end(args);
    }
    return ESTIMATOR_INVALID_ARGUMENT;
}

#define PASS_NAME_(id, name, type, kind, form, fn) name,
#define PASS_TYPE_(id, name, type, kind, form, fn) type,
static const char *const pass_names[PASS_COUNT] = {GMON_PASSES(PASS_NAME_)};
static const int pass_types[PASS_COUNT] = {GMON_PASSES(PASS_TYPE_)};

const char *pass_name(int pass)
{
    return pass >= 0 && pass < PASS_COUNT ? pass_names[pass] : NULL;
}

int pass_from_name(const char *name)
{
    for (int p = 0; p < PASS_COUNT; ++p)
        if (strcmp(name, pass_names[p]) == 0)
            return p;
    return -1;
}

int pass_type(int pass)
{
    return pass_types[pass];
}

int passes_from_list(const char *list, uint32_t *passes, char *message, size_t message_size)
{
    *passes = 0;
    const char *p = list;
    while (1) {
        const char *end = strchr(p, ',');
        size_t length = end ? (size_t)(end - p) : strlen(p);
        char name[32];
        if (length == 0 || length >= sizeof name) {
            invalid(message, message_size, "'%s' is not a list of estimator names", list);
            return -1;
        }
        memcpy(name, p, length);
        name[length] = '\0';
        int pass = pass_from_name(name);
        if (strcmp(name, "all") == 0) {
            *passes |= PASSES_ESTIMATES;
        } else if (pass < 0 || !((PASSES_ESTIMATES | PASSES_SAMPLE) & PASS_BIT(pass))) {
            char known[512] = "";
            for (int q = 0; q < PASS_COUNT; ++q)
                if ((PASSES_ESTIMATES | PASSES_SAMPLE) & PASS_BIT(q))
                    snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", q ? ", " : "", pass_names[q]);
            invalid(message, message_size, "unknown estimator '%s' (known: %s, or all)", name, known);
            return -1;
        } else {
            *passes |= PASS_BIT(pass);
        }
        if (!end)
            return 0;
        p = end + 1;
    }
}

/* The parameter table: name, kind, offset in EstimatorParams, range. */
typedef struct {
    const char *name;
    int is_float;
    size_t offset;
    double lowest, highest;
} ParamSpec;

#define PARAM_IS_FLOAT_float 1
#define PARAM_IS_FLOAT_int32_t 0
#define PARAM_SPEC_(type, field, name, value, lowest, highest)                                                         \
    {name, PARAM_IS_FLOAT_##type, offsetof(EstimatorParams, field), lowest, highest},
static const ParamSpec param_specs[] = {GMON_ESTIMATOR_PARAMS(PARAM_SPEC_)};
#define PARAM_COUNT ((int)(sizeof param_specs / sizeof param_specs[0]))

/* clamp.levels, a list (passes.h), follows the table's parameters. */
#define CLAMP_LEVELS_NAME "clamp.levels"

static void params_default(EstimatorParams *p)
{
#define PARAM_DEFAULT_(type, field, name, value, lowest, highest) p->field = value;
    GMON_ESTIMATOR_PARAMS(PARAM_DEFAULT_)
#undef PARAM_DEFAULT_
    static const float levels[] = {1.0f, 10.0f, 100.0f};
    p->clamp_level_count = 3;
    memset(p->clamp_levels, 0, sizeof p->clamp_levels);
    memcpy(p->clamp_levels, levels, sizeof levels);
}

int estimator_param_count(void)
{
    return PARAM_COUNT + 1;
}

/* Parses "V:V:..." (each > 0, inf allowed). 0, or -1 with a reason. */
static int clamp_levels_set(EstimatorParams *params, const char *text, char *message, size_t message_size)
{
    float levels[EST_CLAMP_LEVELS_MAX];
    int count = 0;
    const char *p = text;
    for (;;) {
        char *end = NULL;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno != 0 || !(v > 0.0) || count == EST_CLAMP_LEVELS_MAX || (*end != ':' && *end != '\0')) {
            invalid(message, message_size,
                    CLAMP_LEVELS_NAME ": '%s' is not 1..%d levels > 0 (inf allowed) separated by ':', e.g. 1:10:100",
                    text, EST_CLAMP_LEVELS_MAX);
            return -1;
        }
        levels[count++] = (float)v;
        if (*end == '\0')
            break;
        p = end + 1;
    }
    memset(params->clamp_levels, 0, sizeof params->clamp_levels);
    memcpy(params->clamp_levels, levels, (size_t)count * sizeof levels[0]);
    params->clamp_level_count = count;
    return 0;
}

static double param_value(const EstimatorParams *params, const ParamSpec *spec)
{
    const char *base = (const char *)params + spec->offset;
    float f;
    int32_t i;
    if (spec->is_float) {
        memcpy(&f, base, sizeof f);
        return f;
    }
    memcpy(&i, base, sizeof i);
    return i;
}

void estimator_param_format(const EstimatorParams *params, int index, const char **name, char *value, size_t value_size)
{
    if (index == PARAM_COUNT) {
        *name = CLAMP_LEVELS_NAME;
        size_t used = 0;
        value[0] = '\0';
        for (int i = 0; i < params->clamp_level_count && used < value_size; ++i)
            used += (size_t)snprintf(value + used, value_size - used, "%s%.9g", i ? ":" : "",
                                     (double)params->clamp_levels[i]);
        return;
    }
    const ParamSpec *spec = &param_specs[index];
    *name = spec->name;
    snprintf(value, value_size, spec->is_float ? "%.9g" : "%.0f", param_value(params, spec));
}

int estimator_param_set(EstimatorParams *params, const char *assignment, char *message, size_t message_size)
{
    const char *equals = strchr(assignment, '=');
    size_t length = equals ? (size_t)(equals - assignment) : 0;
    if (equals && length == strlen(CLAMP_LEVELS_NAME) && strncmp(assignment, CLAMP_LEVELS_NAME, length) == 0)
        return clamp_levels_set(params, equals + 1, message, message_size);
    for (int i = 0; equals && i < PARAM_COUNT; ++i) {
        const ParamSpec *spec = &param_specs[i];
        if (strlen(spec->name) != length || strncmp(spec->name, assignment, length) != 0)
            continue;
        const char *text = equals + 1;
        char *end = NULL;
        errno = 0;
        double v = spec->is_float ? strtod(text, &end) : (double)strtol(text, &end, 10);
        if (end == text || *end != '\0' || errno != 0 || !(v >= spec->lowest && v <= spec->highest)) {
            invalid(message, message_size, "%s: '%s' is not %s in %g..%g", spec->name, text,
                    spec->is_float ? "a number" : "an integer", spec->lowest, spec->highest);
            return -1;
        }
        char *base = (char *)params + spec->offset;
        if (spec->is_float) {
            float f = (float)v;
            memcpy(base, &f, sizeof f);
        } else {
            int32_t n = (int32_t)v;
            memcpy(base, &n, sizeof n);
        }
        return 0;
    }
    char known[512] = "";
    for (int i = 0; i < PARAM_COUNT; ++i)
        snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", i ? ", " : "", param_specs[i].name);
    snprintf(known + strlen(known), sizeof known - strlen(known), ", %s", CLAMP_LEVELS_NAME);
    invalid(message, message_size, "'%s' is not <name>=<value> for a known parameter (%s)", assignment, known);
    return -1;
}

void estimator_settings_default(EstimatorSettings *s)
{
    memset(s, 0, sizeof *s);
    s->set_count = ESTIMATOR_DEFAULT_SETS;
    s->gini_mode = GINI_PER_CHANNEL;
    s->passes = PASSES_DEFAULT;
    params_default(&s->params);
}

int film_check_set_count(int set_count, char *message, size_t message_size)
{
    if (set_count >= 1 && set_count <= FILM_MAX_SETS)
        return 0;
    invalid(message, message_size, "set count M = %d is out of range 1..%d", set_count, FILM_MAX_SETS);
    return -1;
}

int estimator_settings_check(const EstimatorSettings *s, char *message, size_t message_size)
{
    if (!s) {
        invalid(message, message_size, "settings is NULL");
        return -1;
    }
    if (film_check_set_count(s->set_count, message, message_size) != 0)
        return -1;
    if (s->gini_mode != GINI_PER_CHANNEL && s->gini_mode != GINI_PER_PIXEL && s->gini_mode != SORT_BY_LUMINANCE) {
        invalid(message, message_size, "unknown Gini mode %d", (int)s->gini_mode);
        return -1;
    }
    if (s->passes & ~(PASSES_ALL | PASSES_SAMPLE)) {
        invalid(message, message_size, "unknown passes in mask 0x%x", (unsigned)s->passes);
        return -1;
    }
    if (s->with_stderr && s->gini_mode == SORT_BY_LUMINANCE) {
        invalid(message, message_size,
                "standard errors are not available with the Gini mode sort_by_luminance (its G-MoN trims whole RGB "
                "sets)");
        return -1;
    }
    for (int i = 0; i < PARAM_COUNT; ++i) {
        double v = param_value(&s->params, &param_specs[i]);
        if (!(v >= param_specs[i].lowest && v <= param_specs[i].highest)) {
            invalid(message, message_size, "estimator parameter %s = %g is out of range %g..%g", param_specs[i].name, v,
                    param_specs[i].lowest, param_specs[i].highest);
            return -1;
        }
    }
    if (s->params.clamp_level_count < 1 || s->params.clamp_level_count > EST_CLAMP_LEVELS_MAX) {
        invalid(message, message_size, "%s: %d levels, 1..%d allowed", CLAMP_LEVELS_NAME,
                (int)s->params.clamp_level_count, EST_CLAMP_LEVELS_MAX);
        return -1;
    }
    for (int i = 0; i < s->params.clamp_level_count; ++i)
        if (!(s->params.clamp_levels[i] > 0.0f)) {
            invalid(message, message_size, "%s: level %g is not > 0", CLAMP_LEVELS_NAME,
                    (double)s->params.clamp_levels[i]);
            return -1;
        }
    return 0;
}

/* accumulators: the input is accumulators (else float set sums). */
static EstimatorStatus check_common(const EstimatorSettings *settings, size_t input_length, int accumulators,
                                    size_t pixel_count, const EstimatorImages *images, char *message,
                                    size_t message_size)
{
    if (estimator_settings_check(settings, message, message_size) != 0)
        return ESTIMATOR_INVALID_ARGUMENT;
    size_t needed =
        accumulators ? accumulator_planes((uint32_t)settings->set_count) : (size_t)settings->set_count * EST_CHANNELS;
    if (pixel_count > SIZE_MAX / needed)
        return invalid(message, message_size, "pixel count %zu is too large", pixel_count);
    if (input_length < needed * pixel_count)
        return invalid(message, message_size, "input holds %zu values, %zu needed (M = %d, %zu pixels)", input_length,
                       needed * pixel_count, settings->set_count, pixel_count);
    if (!images)
        return invalid(message, message_size, "images is NULL");
    int any = 0;
    for (int p = 0; p < PASS_COUNT; ++p)
        any |= (settings->passes & PASS_BIT(p)) && (images->pass[p] || (settings->with_stderr && images->error[p]));
    if (!any)
        return invalid(message, message_size, "no output image requested");
    if (images->length / EST_CHANNELS < pixel_count)
        return invalid(message, message_size, "output images hold %zu values, %zu needed", images->length,
                       pixel_count * EST_CHANNELS);
    return ESTIMATOR_OK;
}

static void store(const EstimatorSettings *settings, const PixelEstimates *e, size_t pixel, EstimatorImages *images)
{
    for (int p = 0; p < PASS_COUNT; ++p) {
        if (!(settings->passes & PASS_BIT(p)))
            continue;
        for (int c = 0; c < EST_CHANNELS; ++c) {
            size_t i = pixel * EST_CHANNELS + (size_t)c;
            if (images->pass[p] && pass_types[p] == PASS_INT)
                ((int32_t *)images->pass[p])[i] = (int32_t)e->value[p][c];
            else if (images->pass[p])
                ((float *)images->pass[p])[i] = e->value[p][c];
            if (settings->with_stderr && images->error[p])
                images->error[p][i] = e->error[p][c];
        }
    }
}

/* The sums of one pixel in grid units, sums[c][j] from set (j + first_set)
 * mod m (so that j counts sets in the order the samples filled them); returns
 * the pixel's grid exponent. */
static int sums_of_pixel(const uint64_t *accumulators, uint32_t m, uint32_t first_set, size_t pixel, size_t pixel_count,
                         float sums[EST_CHANNELS][EST_CAPACITY])
{
    for (uint32_t j = 0; j < m; ++j)
        for (uint32_t c = 0; c < EST_CHANNELS; ++c) {
            FixedSum s;
            uint32_t set = (j + first_set) % m;
            s.lo = accumulators[accumulator_index(set, c, 0, pixel, pixel_count)];
            s.hi = accumulators[accumulator_index(set, c, 1, pixel, pixel_count)];
            sums[c][j] = fixed_to_float(s);
        }
    return grid_exponent(accumulators[grid_index(pixel)]);
}

/* Estimates every pixel from float set sums or (when given) accumulators,
 * as the kernels do: accumulators' sums are in grid units, scaled back
 * after estimation. */
static EstimatorStatus estimate_all(const EstimatorSettings *requested, const float *set_sums,
                                    const uint64_t *accumulators, size_t input_length, size_t pixel_count,
                                    uint64_t sample_count, EstimatorImages *images, char *message, size_t message_size)
{
    if (!requested)
        return invalid(message, message_size, "settings is NULL");
    /* The per-sample passes are film_sample.h's. */
    EstimatorSettings set_based = *requested;
    set_based.passes &= ~PASSES_SAMPLE;
    const EstimatorSettings *settings = &set_based;
    const int from_accumulators = accumulators != NULL;
    EstimatorStatus status =
        check_common(settings, input_length, from_accumulators, pixel_count, images, message, message_size);
    if (status != ESTIMATOR_OK)
        return status;
    const uint32_t m = (uint32_t)settings->set_count;
    const uint32_t first_set = (uint32_t)(settings->first_sample % m);
    const int sets = sample_count < m ? (int)sample_count : (int)m;
    for (size_t p = 0; p < pixel_count; ++p) {
        float sums[EST_CHANNELS][EST_CAPACITY];
        int exponent = 0;
        if (from_accumulators)
            exponent = sums_of_pixel(accumulators, m, first_set, p, pixel_count, sums);
        else
            for (uint32_t j = 0; j < m; ++j)
                for (uint32_t c = 0; c < EST_CHANNELS; ++c)
                    sums[c][j] = set_sums[set_sum_index((j + first_set) % m, c, p, pixel_count)];
        PixelEstimates e;
        estimate_lanes(sums, sample_count, (int)m, sets, settings->passes, settings->with_stderr,
                       (int)settings->gini_mode, &settings->params, exponent, from_accumulators, &e);
        finish_estimates(&e, settings->passes, from_accumulators, exponent);
        store(settings, &e, p, images);
    }
    return ESTIMATOR_OK;
}

EstimatorStatus estimator_from_sums(const EstimatorSettings *settings, const float *set_sums, size_t set_sums_length,
                                    size_t pixel_count, uint64_t sample_count, EstimatorImages *images, char *message,
                                    size_t message_size)
{
    if (!set_sums)
        return invalid(message, message_size, "set sums are NULL");
    return estimate_all(settings, set_sums, NULL, set_sums_length, pixel_count, sample_count, images, message,
                        message_size);
}

EstimatorStatus estimator_from_accumulators(const EstimatorSettings *settings, const uint64_t *accumulators,
                                            size_t accumulators_length, size_t pixel_count, uint64_t sample_count,
                                            EstimatorImages *images, char *message, size_t message_size)
{
    if (!accumulators)
        return invalid(message, message_size, "accumulators are NULL");
    return estimate_all(settings, NULL, accumulators, accumulators_length, pixel_count, sample_count, images, message,
                        message_size);
}

EstimatorStatus estimator_sums_from_accumulators(int set_count, const uint64_t *accumulators,
                                                 size_t accumulators_length, size_t pixel_count, float *set_sums,
                                                 size_t set_sums_length, char *message, size_t message_size)
{
    if (!accumulators || !set_sums)
        return invalid(message, message_size, "accumulators or set sums are NULL");
    if (film_check_set_count(set_count, message, message_size) != 0)
        return ESTIMATOR_INVALID_ARGUMENT;
    size_t values = (size_t)set_count * EST_CHANNELS, planes = accumulator_planes((uint32_t)set_count);
    if (pixel_count > SIZE_MAX / planes)
        return invalid(message, message_size, "pixel count %zu is too large", pixel_count);
    if (accumulators_length < planes * pixel_count || set_sums_length < values * pixel_count)
        return invalid(message, message_size, "buffers too short for M = %d and %zu pixels", set_count, pixel_count);
    for (size_t p = 0; p < pixel_count; ++p) {
        float sums[EST_CHANNELS][EST_CAPACITY];
        int exponent = sums_of_pixel(accumulators, (uint32_t)set_count, 0, p, pixel_count, sums);
        for (uint32_t j = 0; j < (uint32_t)set_count; ++j)
            for (uint32_t c = 0; c < EST_CHANNELS; ++c)
                set_sums[set_sum_index(j, c, p, pixel_count)] = scale_by_grid(sums[c][j], exponent);
    }
    return ESTIMATOR_OK;
}
