#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include "film/film_file.h"
#include "film/film_sample.h"

#include <stdio.h>
#include <string.h>

/* The film's attribute names, by FILM_ATTRIBUTE_* id. */
#define FILM_ATTRIBUTE_NAME(id, name, meaning, legacy) RENDER_FILE_PREFIX name,
static const char *const film_attribute_names[FILM_FILE_ATTRIBUTES] = {
    RENDER_FILE_FILM_ATTRIBUTES(FILM_ATTRIBUTE_NAME)};
#undef FILM_ATTRIBUTE_NAME

static const char *const gini_mode_names[] = {"per_channel", "per_pixel", "sort_by_luminance"};
#define GINI_MODE_COUNT ((int)(sizeof gini_mode_names / sizeof gini_mode_names[0]))

const char *gini_mode_name(GiniMode mode)
{
    return (int)mode >= 0 && (int)mode < GINI_MODE_COUNT ? gini_mode_names[mode] : "unknown";
}

int gini_mode_from_name(const char *name)
{
    for (int m = 0; m < GINI_MODE_COUNT; ++m)
        if (strcmp(name, gini_mode_names[m]) == 0)
            return m;
    return -1;
}

/* "<pass>" or "<pass>.stderr". */
static void layer_name(int pass, int with_error, char *name, size_t size)
{
    snprintf(name, size, "%s%s", pass_name(pass), with_error ? RENDER_FILE_STDERR_SUFFIX : "");
}

static void append(char *list, size_t size, const char *item)
{
    size_t used = strlen(list);
    snprintf(list + used, size - used, "%s%s", used ? "," : "", item);
}

void film_file_init(FilmFile *f, int width, int height, const EstimatorSettings *settings,
                    const EstimatorImages *images)
{
    memset(f, 0, sizeof *f);
    f->image.width = width;
    f->image.height = height;
    for (int with_error = 0; with_error <= 1; ++with_error)
        for (int p = 0; p < PASS_COUNT; ++p) {
            if (!(settings->passes & PASS_BIT(p)))
                continue;
            const void *data = with_error ? (const void *)images->error[p] : images->pass[p];
            if (with_error && !(settings->with_stderr && (PASSES_ESTIMATES & PASS_BIT(p))))
                continue;
            if (!data)
                continue;
            if (!with_error)
                append(f->estimators, sizeof f->estimators, pass_name(p));
            if (PASSES_SAMPLE & PASS_BIT(p)) {
                if (with_error)
                    continue;
                for (int i = 0; i < film_sample_pass_images(settings, p); ++i) {
                    char *name = f->sample_layer_names[sample_image_slot(film_sample_passes(settings),
                                                                         settings->params.clamp_level_count, p, i)];
                    film_sample_layer_name(settings, p, i, name, EXR_LAYER_NAME_CAPACITY);
                    ExrRgbLayer *layer = &f->image.layers[f->image.layer_count++];
                    layer->name = name;
                    layer->is_int = 0;
                    layer->data = (const float *)data + (size_t)i * (size_t)width * (size_t)height * EST_CHANNELS;
                }
                continue;
            }
            char *name = f->layer_names[with_error][p];
            layer_name(p, with_error, name, EXR_LAYER_NAME_CAPACITY);
            ExrRgbLayer *layer = &f->image.layers[f->image.layer_count++];
            layer->name = name;
            layer->is_int = !with_error && pass_type(p) == PASS_INT;
            layer->data = data;
        }
    for (int i = 0; i < estimator_param_count(); ++i) {
        const char *name;
        char value[160], item[224];
        estimator_param_format(&settings->params, i, &name, value, sizeof value);
        snprintf(item, sizeof item, "%s=%s", name, value);
        append(f->params, sizeof f->params, item);
    }
    const char *values[FILM_FILE_ATTRIBUTES] = {
        [FILM_ATTRIBUTE_ESTIMATORS] = f->estimators,
        [FILM_ATTRIBUTE_GINI_MODE] = gini_mode_name(settings->gini_mode),
        [FILM_ATTRIBUTE_ESTIMATOR_PARAMS] = f->params,
    };
    for (int i = 0; i < FILM_FILE_ATTRIBUTES; ++i)
        f->attributes[i] = (ExrKeyValue){film_attribute_names[i], values[i]};
    f->image.metadata.attributes = f->attributes;
    f->image.metadata.attribute_count = FILM_FILE_ATTRIBUTES;
}

int film_file_settings(const ExrImage *image, EstimatorSettings *s, char *message, size_t message_size)
{
    estimator_settings_default(s);
    s->set_count = image->metadata.set_count;
    s->first_sample = image->metadata.first_sample;
    const char *mode = exr_image_attribute(image, film_attribute_names[FILM_ATTRIBUTE_GINI_MODE]);
    if (mode) {
        int m = gini_mode_from_name(mode);
        if (m < 0) {
            snprintf(message, message_size, "attribute %s = '%s' is not a known Gini mode",
                     film_attribute_names[FILM_ATTRIBUTE_GINI_MODE], mode);
            return -1;
        }
        s->gini_mode = (GiniMode)m;
    }
    const char *list = exr_image_attribute(image, film_attribute_names[FILM_ATTRIBUTE_ESTIMATORS]);
    char reason[640];
    if (list) {
        uint32_t passes = 0;
        char copy[512];
        snprintf(copy, sizeof copy, "%s", list);
        for (char *save = NULL, *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
            int pass = pass_from_name(item);
            if (pass < 0) {
                snprintf(message, message_size, "attribute %s: unknown pass '%s'",
                         film_attribute_names[FILM_ATTRIBUTE_ESTIMATORS], item);
                return -1;
            }
            passes |= PASS_BIT(pass);
        }
        s->passes = passes;
    }
    const char *params = exr_image_attribute(image, film_attribute_names[FILM_ATTRIBUTE_ESTIMATOR_PARAMS]);
    if (params) {
        char copy[512];
        snprintf(copy, sizeof copy, "%s", params);
        for (char *save = NULL, *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save))
            if (estimator_param_set(&s->params, item, reason, sizeof reason) != 0) {
                snprintf(message, message_size, "attribute %s: %s",
                         film_attribute_names[FILM_ATTRIBUTE_ESTIMATOR_PARAMS], reason);
                return -1;
            }
    }
    for (int p = 0; p < PASS_COUNT; ++p)
        s->with_stderr |= film_file_pass(image, p, 1) != NULL;
    return 0;
}

const void *film_file_pass(const ExrImage *image, int pass, int with_error)
{
    char name[EXR_LAYER_NAME_CAPACITY];
    layer_name(pass, with_error, name, sizeof name);
    const ExrRgbLayer *layer = exr_image_layer(image, name);
    int is_int = !with_error && pass_type(pass) == PASS_INT;
    return layer && layer->is_int == is_int ? layer->data : NULL;
}
