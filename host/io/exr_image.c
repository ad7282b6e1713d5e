#include "io/exr_image.h"

#include "accumulate.h" /* kernels/: the sums' layout in memory */

#include <openexr.h>

#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define RGB_CHANNELS 3
#define SUM_WORDS 4      /* 32-bit channels per 128-bit set sum */
#define GRID_SET (-1)    /* the set of the grid channel, sets.grid */
#define NAME_CAPACITY 32 /* EXR short names: at most 31 bytes */

/* ------------------------------------------------------------------------
 * Channels
 * ---------------------------------------------------------------------- */

/* The layers: the RGB ones, then RENDER_FILE_LAYERS. */
#define LAYER_ID(id, name, type, meaning, legacy) LAYER_##id,
#define LAYER_NAME(id, name, type, meaning, legacy) name,
typedef enum {
    LAYER_RGB, /* one of the image's RGB layers */
    RENDER_FILE_LAYERS(LAYER_ID) LAYER_COUNT
} Layer;

static const char *const layer_names[LAYER_COUNT] = {"", RENDER_FILE_LAYERS(LAYER_NAME)};
#undef LAYER_ID
#undef LAYER_NAME
static const char channel_letters[RGB_CHANNELS] = {'R', 'G', 'B'};

/* One EXR channel and where its values live in an ExrImage. */
typedef struct {
    char name[NAME_CAPACITY];
    Layer layer;
    int rgb;     /* LAYER_RGB: index in image->layers */
    int is_int;  /* LAYER_RGB: int32 values */
    int set;     /* LAYER_SETS only; GRID_SET for the grid words */
    int channel; /* R, G, B = 0, 1, 2; 0 for the counters and the grid */
    int word;    /* LAYER_SETS only: 32-bit word, 0 the lowest */
} ChannelSpec;

static exr_pixel_type_t spec_pixel_type(const ChannelSpec *spec)
{
    return spec->layer == LAYER_RGB && !spec->is_int ? EXR_PIXEL_FLOAT : EXR_PIXEL_UINT;
}

static ChannelSpec rgb_channel(const char *layer_name, int rgb, int is_int, int channel)
{
    ChannelSpec spec = {{0}, LAYER_RGB, rgb, is_int, 0, channel, 0};
    if (layer_name[0]) /* "<layer>.R"; plain "R" for the layer "" */
        snprintf(spec.name, sizeof spec.name, "%s.%c", layer_name, channel_letters[channel]);
    else
        snprintf(spec.name, sizeof spec.name, "%c", channel_letters[channel]);
    return spec;
}

static ChannelSpec set_channel(int set, int channel, int word)
{
    ChannelSpec spec = {{0}, LAYER_SETS, 0, 0, set, channel, word};
    snprintf(spec.name, sizeof spec.name, "%s.%d.%c.w%d", layer_names[LAYER_SETS], set, channel_letters[channel], word);
    return spec;
}

static ChannelSpec grid_channel(void)
{
    ChannelSpec spec = {{0}, LAYER_SETS, 0, 0, GRID_SET, 0, 0};
    snprintf(spec.name, sizeof spec.name, "%s." RENDER_FILE_GRID_CHANNEL, layer_names[LAYER_SETS]);
    return spec;
}

static ChannelSpec counter_channel(Layer layer)
{
    ChannelSpec spec = {{0}, layer, 0, 0, 0, 0, 0};
    snprintf(spec.name, sizeof spec.name, "%s", layer_names[layer]);
    return spec;
}

/* A valid RGB layer name: 1..24 bytes, not one of the other layers. */
static int rgb_layer_name_is_valid(const char *name, size_t length)
{
    if (length == 0 || length >= EXR_LAYER_NAME_CAPACITY)
        return 0;
    for (int layer = LAYER_NONFINITE; layer < LAYER_COUNT; ++layer)
        if (strlen(layer_names[layer]) == length && strncmp(name, layer_names[layer], length) == 0)
            return 0;
    return 1;
}

/* The spec a channel name stands for; 0 if it is none of ours. RGB
 * channels come back with rgb = -1 and their layer's name length in
 * spec->word (the caller finds or adds the layer). Only the canonical
 * spelling of set channels matches ("sets.07.R.w0" does not). */
static int channel_from_name(const char *name, ChannelSpec *spec)
{
    for (int layer = LAYER_NONFINITE; layer <= LAYER_ROUNDED; ++layer) {
        *spec = counter_channel((Layer)layer);
        if (strcmp(name, spec->name) == 0)
            return 1;
    }
    *spec = grid_channel();
    if (strcmp(name, spec->name) == 0)
        return 1;
    int set, word, length = 0;
    char letter;
    size_t sets_length = strlen(layer_names[LAYER_SETS]);
    if (strncmp(name, layer_names[LAYER_SETS], sets_length) == 0 && name[sets_length] == '.') {
        const char *rest = name + sets_length + 1;
        if (sscanf(rest, "%2d.%c.w%1d%n", &set, &letter, &word, &length) != 3 || rest[length] != '\0')
            return 0;
        if (set < 0 || set >= EST_MAX_SETS || word < 0 || word >= SUM_WORDS)
            return 0;
        const char *found = memchr(channel_letters, letter, RGB_CHANNELS);
        if (!found)
            return 0;
        *spec = set_channel(set, (int)(found - channel_letters), word);
        return strcmp(name, spec->name) == 0;
    }
    size_t total = strlen(name);
    const char *plain = total == 1 ? memchr(channel_letters, name[0], RGB_CHANNELS) : NULL;
    if (plain) { /* R, G, B of an image without layers: the layer "" */
        *spec = rgb_channel("", -1, 0, (int)(plain - channel_letters));
        return 1;
    }
    if (total < 3 || name[total - 2] != '.')
        return 0;
    const char *found = memchr(channel_letters, name[total - 1], RGB_CHANNELS);
    if (!found || !rgb_layer_name_is_valid(name, total - 2))
        return 0;
    *spec = rgb_channel("", -1, 0, (int)(found - channel_letters));
    snprintf(spec->name, sizeof spec->name, "%s", name);
    spec->word = (int)(total - 2);
    return 1;
}

const ExrRgbLayer *exr_image_layer(const ExrImage *image, const char *name)
{
    for (int i = 0; i < image->layer_count; ++i)
        if (strcmp(image->layers[i].name, name) == 0)
            return &image->layers[i];
    return NULL;
}

const char *exr_image_attribute(const ExrImage *image, const char *key)
{
    for (size_t i = 0; i < image->metadata.attribute_count; ++i)
        if (strcmp(image->metadata.attributes[i].key, key) == 0)
            return image->metadata.attributes[i].value;
    return NULL;
}

/* ------------------------------------------------------------------------
 * Errors: "<file>: <what failed>: <cause>". The library reports its details
 * through the context's error handler; the first report of a call is kept.
 * ---------------------------------------------------------------------- */

typedef struct {
    const char *path;
    char *error;
    size_t error_size;
    char library_message[512];
} IoContext;

static void capture_library_error(exr_const_context_t ctxt, exr_result_t code, const char *message)
{
    void *user = NULL;
    (void)code;
    if (!ctxt || !message || exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    IoContext *io = user;
    if (io->library_message[0] == '\0')
        snprintf(io->library_message, sizeof io->library_message, "%s", message);
}

static ImageIoStatus fail(IoContext *io, const char *format, ...)
{
    if (io->error && io->error_size > 0) {
        int used = snprintf(io->error, io->error_size, "%s: ", io->path);
        if (used >= 0 && (size_t)used < io->error_size) {
            va_list args;
            va_start(args, format);
            vsnprintf(io->error + used, io->error_size - (size_t)used, format, args);
            va_end(args);
        }
    }
    return IMAGE_IO_ERROR;
}

static exr_result_t clear_library_message(IoContext *io)
{
    io->library_message[0] = '\0';
    return EXR_ERR_SUCCESS;
}

/* Non-zero (after recording the message) if `result` is a failure. */
static int library_failed(IoContext *io, exr_result_t result, const char *action)
{
    if (result == EXR_ERR_SUCCESS)
        return 0;
    const char *cause = io->library_message[0] ? io->library_message : exr_get_default_error_message(result);
    fail(io, "%s: %s", action, cause);
    return 1;
}

/* EXR_FAILED(io, call, action): runs an OpenEXR call; on failure records
 * "<action>: <cause>" and is true. */
#define EXR_FAILED(io, call, action) (clear_library_message(io), library_failed((io), (call), (action)))

static exr_context_initializer_t context_initializer(IoContext *io)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = capture_library_error;
    init.user_data = io;
    return init;
}

/* ------------------------------------------------------------------------
 * Metadata values
 * ---------------------------------------------------------------------- */

/* The gmon.* attributes this module reads and writes itself
 * (RENDER_FILE_ATTRIBUTES); any other gmon.* string attribute is one of
 * the film's. */
typedef enum { ATTRIBUTE_STRING, ATTRIBUTE_INT, ATTRIBUTE_UINT64 } AttributeType;

typedef struct {
    const char *name;
    AttributeType type;
    size_t offset; /* of its field in ExrMetadata */
    int min, max;  /* ATTRIBUTE_INT: the values read */
} OwnAttribute;

#define OWN_ATTRIBUTE(field, name, type, min, max, written, meaning, legacy)                                           \
    {RENDER_FILE_PREFIX name, ATTRIBUTE_##type, offsetof(ExrMetadata, field), min, max},
static const OwnAttribute own_attributes[] = {RENDER_FILE_ATTRIBUTES(OWN_ATTRIBUTE)};
#undef OWN_ATTRIBUTE
#define OWN_ATTRIBUTE_COUNT (sizeof own_attributes / sizeof own_attributes[0])

/* Each row's field has its type's C type. */
#define FIELD_TYPE_STRING const char *
#define FIELD_TYPE_INT int
#define FIELD_TYPE_UINT64 uint64_t
#define CHECK_FIELD_TYPE(field, name, type, min, max, written, meaning, legacy)                                        \
    _Static_assert(_Generic(((ExrMetadata *)0)->field, FIELD_TYPE_##type : 1, default : 0),                            \
                   "ExrMetadata." #field " is not of type " #type);
RENDER_FILE_ATTRIBUTES(CHECK_FIELD_TYPE)
#undef CHECK_FIELD_TYPE

static int attribute_is_own(const char *key)
{
    for (size_t i = 0; i < OWN_ATTRIBUTE_COUNT; ++i)
        if (strcmp(key, own_attributes[i].name) == 0)
            return 1;
    return 0;
}

static int is_film_attribute(const char *key)
{
    return strncmp(key, RENDER_FILE_PREFIX, strlen(RENDER_FILE_PREFIX)) == 0 && !attribute_is_own(key);
}

/* Decimal digits only, no sign or spaces, at most UINT64_MAX. */
static int parse_uint64(const char *text, uint64_t *value)
{
    if (!text[0] || strlen(text) > 20)
        return 0;
    for (const char *p = text; *p; ++p)
        if (*p < '0' || *p > '9')
            return 0;
    errno = 0;
    unsigned long long parsed = strtoull(text, NULL, 10);
    if (errno == ERANGE)
        return 0;
    *value = (uint64_t)parsed;
    return 1;
}

/* Attribute names EXR itself uses, which free key/value pairs must avoid. */
static int key_is_reserved(const char *key)
{
    static const char *const reserved[] = {"channels",
                                           "compression",
                                           "dataWindow",
                                           "displayWindow",
                                           "lineOrder",
                                           "pixelAspectRatio",
                                           "screenWindowCenter",
                                           "screenWindowWidth",
                                           "name",
                                           "type",
                                           "version",
                                           "chunkCount",
                                           "tiles"};
    if (strncmp(key, RENDER_FILE_PREFIX, strlen(RENDER_FILE_PREFIX)) == 0)
        return 1;
    for (size_t i = 0; i < sizeof reserved / sizeof reserved[0]; ++i)
        if (strcmp(key, reserved[i]) == 0)
            return 1;
    return 0;
}

/* ------------------------------------------------------------------------
 * Writing
 * ---------------------------------------------------------------------- */

static ImageIoStatus check_image(IoContext *io, const ExrImage *image)
{
    if (!image)
        return fail(io, "no image given");
    if (image->width < 1 || image->height < 1)
        return fail(io, "image size %dx%d is empty", image->width, image->height);
    if (image->layer_count < 0 || image->layer_count > EXR_MAX_RGB_LAYERS)
        return fail(io, "%d RGB layers given, 0..%d supported", image->layer_count, EXR_MAX_RGB_LAYERS);
    for (int i = 0; i < image->layer_count; ++i) {
        const ExrRgbLayer *layer = &image->layers[i];
        if (!layer->name || (layer->name[0] && !rgb_layer_name_is_valid(layer->name, strlen(layer->name))) ||
            !layer->data)
            return fail(io, "RGB layer %d has no data or an invalid name '%s'", i, layer->name ? layer->name : "");
        for (int j = 0; j < i; ++j)
            if (strcmp(layer->name, image->layers[j].name) == 0)
                return fail(io, "RGB layer '%s' is given twice", layer->name);
    }
    if (image->layer_count == 0 && !image->nonfinite && !image->rounded && !image->accumulators)
        return fail(io, "the image has no layer to write");
    const ExrMetadata *meta = &image->metadata;
    if (meta->set_count < 0 || meta->set_count > EST_MAX_SETS)
        return fail(io, "set count M = %d is out of range 1..%d", meta->set_count, EST_MAX_SETS);
    if (image->accumulators && meta->set_count == 0)
        return fail(io, "accumulators given without a set count M");
    size_t pixels = (size_t)image->width * (size_t)image->height;
    size_t bytes_per_pixel = accumulator_planes(EST_MAX_SETS) * sizeof(uint64_t);
    if (pixels > SIZE_MAX / bytes_per_pixel)
        return fail(io, "image size %dx%d is too large", image->width, image->height);
    if (meta->attribute_count > 0 && !meta->attributes)
        return fail(io, "%zu attributes announced but none given", meta->attribute_count);
    for (size_t i = 0; i < meta->attribute_count; ++i) {
        const char *key = meta->attributes[i].key;
        if (!key || !meta->attributes[i].value || strlen(key) >= NAME_CAPACITY || !is_film_attribute(key))
            return fail(io,
                        "attribute %zu ('%s') is not a film attribute (gmon.*, at most %d bytes, not one of "
                        "this file's own)",
                        i, key ? key : "", NAME_CAPACITY - 1);
    }
    if (meta->extra_count > 0 && !meta->extras)
        return fail(io, "%zu extra attributes announced but none given", meta->extra_count);
    for (size_t i = 0; i < meta->extra_count; ++i) {
        const char *key = meta->extras[i].key;
        if (!key || !key[0] || !meta->extras[i].value)
            return fail(io, "extra attribute %zu has no key or no value", i);
        if (strlen(key) >= NAME_CAPACITY)
            return fail(io, "extra attribute key '%s' is longer than %d bytes", key, NAME_CAPACITY - 1);
        if (key_is_reserved(key))
            return fail(io, "extra attribute key '%s' is reserved (EXR or " RENDER_FILE_PREFIX "*)", key);
        for (size_t j = 0; j < i; ++j)
            if (strcmp(key, meta->extras[j].key) == 0)
                return fail(io, "extra attribute key '%s' is given twice", key);
    }
    return IMAGE_IO_OK;
}

/* The channels of every present layer; NULL if out of memory. */
static ChannelSpec *channels_of_image(const ExrImage *image, int *count)
{
    int sets = image->accumulators ? image->metadata.set_count : 0;
    ChannelSpec *specs =
        malloc(sizeof *specs * (size_t)(image->layer_count * RGB_CHANNELS + 3 + sets * RGB_CHANNELS * SUM_WORDS));
    if (!specs)
        return NULL;
    int n = 0;
    for (int i = 0; i < image->layer_count; ++i)
        for (int c = 0; c < RGB_CHANNELS; ++c)
            specs[n++] = rgb_channel(image->layers[i].name, i, image->layers[i].is_int, c);
    if (image->nonfinite)
        specs[n++] = counter_channel(LAYER_NONFINITE);
    if (image->rounded)
        specs[n++] = counter_channel(LAYER_ROUNDED);
    if (sets)
        specs[n++] = grid_channel();
    for (int j = 0; j < sets; ++j)
        for (int c = 0; c < RGB_CHANNELS; ++c)
            for (int w = 0; w < SUM_WORDS; ++w)
                specs[n++] = set_channel(j, c, w);
    *count = n;
    return specs;
}

/* A word of the sums in memory, in the layout of kernels/film/accumulate.h. */
static size_t accumulator_word(int set, int channel, int word, size_t pixel, size_t pixel_count)
{
    if (set == GRID_SET)
        return (size_t)grid_index(pixel);
    return (size_t)accumulator_index((uint32_t)set, (uint32_t)channel, (uint32_t)word, pixel, pixel_count);
}

/* Copies rows [first_row, first_row + rows) of one channel into `out`. */
static void gather_channel(const ExrImage *image, const ChannelSpec *spec, int first_row, int rows, uint32_t *out)
{
    size_t width = (size_t)image->width;
    size_t pixel_count = width * (size_t)image->height;
    size_t first = (size_t)first_row * width;
    size_t count = (size_t)rows * width;
    for (size_t i = 0; i < count; ++i) {
        size_t p = first + i;
        size_t rgb = p * RGB_CHANNELS + (size_t)spec->channel;
        switch (spec->layer) {
        case LAYER_RGB:
            memcpy(&out[i], (const uint32_t *)image->layers[spec->rgb].data + rgb, sizeof out[i]);
            break;
        case LAYER_NONFINITE:
            out[i] = image->nonfinite[p];
            break;
        case LAYER_ROUNDED:
            out[i] = image->rounded[p];
            break;
        case LAYER_SETS: {
            uint64_t word64 =
                image->accumulators[accumulator_word(spec->set, spec->channel, spec->word / 2, p, pixel_count)];
            out[i] = (uint32_t)(spec->word % 2 ? word64 >> 32 : word64);
            break;
        }
        default:
            break;
        }
    }
}

/* Index of `name` in specs, or -1. */
static int find_spec(const ChannelSpec *specs, int count, const char *name)
{
    for (int i = 0; i < count; ++i)
        if (strcmp(specs[i].name, name) == 0)
            return i;
    return -1;
}

/* A 64-bit number as a decimal string attribute (EXR has no 64-bit
 * integer attribute, and a double would round values above 2^53). */
static ImageIoStatus write_uint64_attribute(IoContext *io, exr_context_t ctxt, int part, const char *name,
                                            uint64_t value)
{
    char number[24], action[NAME_CAPACITY + 32];
    snprintf(number, sizeof number, "%" PRIu64, value);
    snprintf(action, sizeof action, "cannot set attribute %s", name);
    return EXR_FAILED(io, exr_attr_set_string(ctxt, part, name, number), action) ? IMAGE_IO_ERROR : IMAGE_IO_OK;
}

static ImageIoStatus write_metadata(IoContext *io, exr_context_t ctxt, int part, const ExrMetadata *meta)
{
#define WRITTEN(field, name, type, min, max, written, meaning, legacy) (written) != 0,
    const int written[OWN_ATTRIBUTE_COUNT] = {RENDER_FILE_ATTRIBUTES(WRITTEN)};
#undef WRITTEN
    for (size_t i = 0; i < OWN_ATTRIBUTE_COUNT; ++i) {
        const OwnAttribute *own = &own_attributes[i];
        const char *field = (const char *)meta + own->offset;
        if (!written[i])
            continue;
        char action[NAME_CAPACITY + 32];
        snprintf(action, sizeof action, "cannot set attribute %s", own->name);
        if (own->type == ATTRIBUTE_UINT64) {
            uint64_t value;
            memcpy(&value, field, sizeof value);
            if (write_uint64_attribute(io, ctxt, part, own->name, value) != IMAGE_IO_OK)
                return IMAGE_IO_ERROR;
        } else if (own->type == ATTRIBUTE_INT) {
            int value;
            memcpy(&value, field, sizeof value);
            if (EXR_FAILED(io, exr_attr_set_int(ctxt, part, own->name, value), action))
                return IMAGE_IO_ERROR;
        } else {
            const char *value;
            memcpy(&value, field, sizeof value);
            if (EXR_FAILED(io, exr_attr_set_string(ctxt, part, own->name, value), action))
                return IMAGE_IO_ERROR;
        }
    }
    for (size_t i = 0; i < meta->attribute_count; ++i) {
        char action[NAME_CAPACITY + 32];
        snprintf(action, sizeof action, "cannot set attribute %s", meta->attributes[i].key);
        if (EXR_FAILED(io, exr_attr_set_string(ctxt, part, meta->attributes[i].key, meta->attributes[i].value), action))
            return IMAGE_IO_ERROR;
    }
    for (size_t i = 0; i < meta->extra_count; ++i) {
        char action[NAME_CAPACITY + 32];
        snprintf(action, sizeof action, "cannot set attribute %s", meta->extras[i].key);
        if (EXR_FAILED(io, exr_attr_set_string(ctxt, part, meta->extras[i].key, meta->extras[i].value), action))
            return IMAGE_IO_ERROR;
    }
    return IMAGE_IO_OK;
}

/* OpenEXR 3.1's encoder can store a compressed chunk exactly as large as
 * its uncompressed data, which readers then take for uncompressed data
 * (upstream issue 2306: the chunk reads back as garbage). A chunk that does
 * not get smaller is stored uncompressed, as the format intends. The
 * library's own compressor is kept in encoding_user_data. */
typedef exr_result_t (*CompressFn)(exr_encode_pipeline_t *);

static exr_result_t compress_or_store(exr_encode_pipeline_t *encoder)
{
    CompressFn compress = *(CompressFn *)encoder->encoding_user_data;
    exr_result_t result = compress(encoder);
    if (result == EXR_ERR_SUCCESS && encoder->compressed_bytes >= encoder->packed_bytes) {
        if (encoder->compressed_alloc_size < encoder->packed_bytes)
            return EXR_ERR_OUT_OF_MEMORY;
        memcpy(encoder->compressed_buffer, encoder->packed_buffer, encoder->packed_bytes);
        encoder->compressed_bytes = encoder->packed_bytes;
    }
    return result;
}

/* Encodes and writes every scanline chunk. */
static ImageIoStatus write_pixels(IoContext *io, exr_context_t ctxt, int part, const ExrImage *image,
                                  const ChannelSpec *specs, int spec_count)
{
    int32_t rows_per_chunk = 0;
    if (EXR_FAILED(io, exr_get_scanlines_per_chunk(ctxt, part, &rows_per_chunk), "cannot query the chunk size"))
        return IMAGE_IO_ERROR;
    size_t plane = (size_t)rows_per_chunk * (size_t)image->width; /* values per channel and chunk */
    uint32_t *scratch = malloc(sizeof *scratch * plane * (size_t)spec_count);
    int *spec_of_channel = malloc(sizeof *spec_of_channel * (size_t)spec_count);
    if (!scratch || !spec_of_channel) {
        free(scratch);
        free(spec_of_channel);
        return fail(io, "out of memory for a %d-row chunk of %d channels", (int)rows_per_chunk, spec_count);
    }

    ImageIoStatus status = IMAGE_IO_OK;
    exr_encode_pipeline_t encoder;
    memset(&encoder, 0, sizeof encoder);
    CompressFn library_compress = NULL;
    int initialized = 0;
    for (int y = 0; y < image->height && status == IMAGE_IO_OK; y += rows_per_chunk) {
        exr_chunk_info_t chunk;
        if (EXR_FAILED(io, exr_write_scanline_chunk_info(ctxt, part, y, &chunk), "cannot start a scanline chunk")) {
            status = IMAGE_IO_ERROR;
            break;
        }
        exr_result_t result = initialized ? exr_encoding_update(ctxt, part, &chunk, &encoder)
                                          : exr_encoding_initialize(ctxt, part, &chunk, &encoder);
        if (library_failed(io, result, "cannot set up the encoder")) {
            status = IMAGE_IO_ERROR;
            break;
        }
        if (!initialized && encoder.channel_count != spec_count) {
            status = fail(io, "encoder has %d channels, %d defined", (int)encoder.channel_count, spec_count);
            break;
        }
        for (int i = 0; i < encoder.channel_count; ++i) {
            exr_coding_channel_info_t *channel = &encoder.channels[i];
            if (!initialized) {
                spec_of_channel[i] = find_spec(specs, spec_count, channel->channel_name);
                if (spec_of_channel[i] < 0) {
                    status = fail(io, "encoder has unknown channel %s", channel->channel_name);
                    break;
                }
            }
            const ChannelSpec *spec = &specs[spec_of_channel[i]];
            uint32_t *values = scratch + plane * (size_t)i;
            gather_channel(image, spec, chunk.start_y, chunk.height, values);
            channel->user_data_type = (uint16_t)spec_pixel_type(spec);
            channel->user_bytes_per_element = 4;
            channel->user_pixel_stride = 4;
            channel->user_line_stride = 4 * image->width;
            channel->encode_from_ptr = (const uint8_t *)values;
        }
        if (status != IMAGE_IO_OK)
            break;
        if (!initialized) {
            initialized = 1;
            if (EXR_FAILED(io, exr_encoding_choose_default_routines(ctxt, part, &encoder),
                           "cannot choose the encoding routines")) {
                status = IMAGE_IO_ERROR;
                break;
            }
            if (encoder.compress_fn) {
                library_compress = encoder.compress_fn;
                encoder.encoding_user_data = &library_compress;
                encoder.compress_fn = compress_or_store;
            }
        }
        if (EXR_FAILED(io, exr_encoding_run(ctxt, part, &encoder), "cannot encode or write a scanline chunk"))
            status = IMAGE_IO_ERROR;
    }
    if (initialized)
        exr_encoding_destroy(ctxt, &encoder);
    free(scratch);
    free(spec_of_channel);
    return status;
}

ImageIoStatus exr_image_write(const char *path, const ExrImage *image, char *error, size_t error_size)
{
    IoContext io = {path ? path : "(no file name)", error, error_size, {0}};
    if (!path || !path[0])
        return fail(&io, "no file name given");
    if (check_image(&io, image) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;

    int spec_count = 0;
    ChannelSpec *specs = channels_of_image(image, &spec_count);
    if (!specs)
        return fail(&io, "out of memory");

    /* Written directly: gmonrt replaces files through a temporary name of
     * its own (write_replacing), which it removes when interrupted. */
    exr_context_initializer_t init = context_initializer(&io);
    exr_context_t ctxt = NULL;
    ImageIoStatus status = IMAGE_IO_ERROR;
    int part = 0;
    if (EXR_FAILED(&io, exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), "cannot create the file"))
        goto done;
    if (EXR_FAILED(&io, exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), "cannot add an image part") ||
        EXR_FAILED(&io,
                   exr_initialize_required_attr_simple(ctxt, part, image->width, image->height, EXR_COMPRESSION_ZIP),
                   "cannot set the image size and compression"))
        goto done;
    for (int i = 0; i < spec_count; ++i) {
        char action[NAME_CAPACITY + 32];
        snprintf(action, sizeof action, "cannot add channel %s", specs[i].name);
        if (EXR_FAILED(&io,
                       exr_add_channel(ctxt, part, specs[i].name, spec_pixel_type(&specs[i]),
                                       EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                       action))
            goto done;
    }
    if (write_metadata(&io, ctxt, part, &image->metadata) != IMAGE_IO_OK)
        goto done;
    if (EXR_FAILED(&io, exr_write_header(ctxt), "cannot write the header"))
        goto done;
    if (write_pixels(&io, ctxt, part, image, specs, spec_count) != IMAGE_IO_OK)
        goto done;
    /* exr_finish writes the chunk table and renames the file into place. */
    if (EXR_FAILED(&io, exr_finish(&ctxt), "cannot finish the file"))
        goto done;
    status = IMAGE_IO_OK;
done:
    if (ctxt)
        exr_finish(&ctxt); /* after a failure: discards the temporary file */
    free(specs);
    return status;
}

/* ------------------------------------------------------------------------
 * Reading
 * ---------------------------------------------------------------------- */

/* Memory an image read from a file owns: a list of blocks. */
typedef struct StorageBlock {
    struct StorageBlock *next;
    max_align_t data[];
} StorageBlock;

static void *storage_alloc(ExrImage *image, size_t size)
{
    if (size > SIZE_MAX - sizeof(StorageBlock))
        return NULL;
    StorageBlock *block = calloc(1, sizeof(StorageBlock) + size);
    if (!block)
        return NULL;
    block->next = image->storage;
    image->storage = block;
    return block->data;
}

static char *storage_string(ExrImage *image, const char *text, size_t length)
{
    char *copy = storage_alloc(image, length + 1);
    if (copy) {
        memcpy(copy, text, length);
        copy[length] = '\0';
    }
    return copy;
}

void exr_image_free(ExrImage *image)
{
    if (!image)
        return;
    StorageBlock *block = image->storage;
    while (block) {
        StorageBlock *next = block->next;
        free(block);
        block = next;
    }
    memset(image, 0, sizeof *image);
}

/* A string attribute: 1 and the text (copied into the image) if present, 0
 * if absent, -1 after recording an error. */
static int read_string_attribute(IoContext *io, exr_const_context_t ctxt, ExrImage *image, const char *name,
                                 const char **text)
{
    const exr_attribute_t *attribute = NULL;
    exr_result_t result = exr_get_attribute_by_name(ctxt, 0, name, &attribute);
    if (result == EXR_ERR_NO_ATTR_BY_NAME)
        return 0;
    char action[NAME_CAPACITY + 40];
    snprintf(action, sizeof action, "cannot read attribute %s", name);
    if (library_failed(io, result, action))
        return -1;
    if (attribute->type != EXR_ATTR_STRING || !attribute->string) {
        fail(io, "attribute %s is of type %s, expected string", name, attribute->type_name);
        return -1;
    }
    const exr_attr_string_t *string = attribute->string;
    *text = storage_string(image, string->str ? string->str : "", string->length > 0 ? (size_t)string->length : 0);
    if (!*text) {
        fail(io, "out of memory");
        return -1;
    }
    return 1;
}

static int read_uint64_attribute(IoContext *io, exr_const_context_t ctxt, ExrImage *image, const char *name,
                                 uint64_t *value)
{
    const char *text = NULL;
    int found = read_string_attribute(io, ctxt, image, name, &text);
    if (found == 1 && !parse_uint64(text, value)) {
        fail(io, "attribute %s = '%s' is not an unsigned 64-bit decimal number", name, text);
        return -1;
    }
    return found;
}

static ImageIoStatus read_metadata(IoContext *io, exr_const_context_t ctxt, ExrImage *image)
{
    ExrMetadata *meta = &image->metadata;
    const exr_attribute_t *attribute = NULL;
    for (size_t i = 0; i < OWN_ATTRIBUTE_COUNT; ++i) {
        const OwnAttribute *own = &own_attributes[i];
        char *field = (char *)meta + own->offset;
        if (own->type == ATTRIBUTE_UINT64) {
            uint64_t value = 0;
            int found = read_uint64_attribute(io, ctxt, image, own->name, &value);
            if (found < 0)
                return IMAGE_IO_ERROR;
            if (found)
                memcpy(field, &value, sizeof value);
        } else if (own->type == ATTRIBUTE_STRING) {
            const char *value = NULL;
            int found = read_string_attribute(io, ctxt, image, own->name, &value);
            if (found < 0)
                return IMAGE_IO_ERROR;
            if (found)
                memcpy(field, &value, sizeof value);
        } else {
            exr_result_t result = exr_get_attribute_by_name(ctxt, 0, own->name, &attribute);
            if (result == EXR_ERR_NO_ATTR_BY_NAME)
                continue;
            char action[NAME_CAPACITY + 40];
            snprintf(action, sizeof action, "cannot read attribute %s", own->name);
            if (library_failed(io, result, action))
                return IMAGE_IO_ERROR;
            if (attribute->type != EXR_ATTR_INT)
                return fail(io, "attribute %s is of type %s, expected int", own->name, attribute->type_name);
            if (attribute->i < own->min || attribute->i > own->max)
                return fail(io, "attribute %s = %d is out of range %d..%d", own->name, (int)attribute->i, own->min,
                            own->max);
            int value = attribute->i;
            memcpy(field, &value, sizeof value);
        }
    }
    /* The film's attributes (gmon.*, not ours) and the free key/value
     * pairs: every other string attribute. */
    int32_t count = 0;
    if (EXR_FAILED(io, exr_get_attribute_count(ctxt, 0, &count), "cannot count the attributes"))
        return IMAGE_IO_ERROR;
    ExrKeyValue *extras = storage_alloc(image, sizeof *extras * (size_t)(count > 0 ? count : 1));
    ExrKeyValue *attributes = storage_alloc(image, sizeof *attributes * (size_t)(count > 0 ? count : 1));
    if (!extras || !attributes)
        return fail(io, "out of memory");
    size_t extra_count = 0, attribute_count = 0;
    for (int32_t i = 0; i < count; ++i) {
        if (EXR_FAILED(io, exr_get_attribute_by_index(ctxt, 0, EXR_ATTR_LIST_FILE_ORDER, i, &attribute),
                       "cannot read an attribute"))
            return IMAGE_IO_ERROR;
        if (attribute->type != EXR_ATTR_STRING || !attribute->string)
            continue;
        int film = is_film_attribute(attribute->name);
        if (!film && key_is_reserved(attribute->name))
            continue;
        ExrKeyValue *pair = film ? &attributes[attribute_count++] : &extras[extra_count++];
        const exr_attr_string_t *string = attribute->string;
        pair->key = storage_string(image, attribute->name, strlen(attribute->name));
        pair->value =
            storage_string(image, string->str ? string->str : "", string->length > 0 ? (size_t)string->length : 0);
        if (!pair->key || !pair->value)
            return fail(io, "out of memory");
    }
    meta->extras = extra_count ? extras : NULL;
    meta->extra_count = extra_count;
    meta->attributes = attribute_count ? attributes : NULL;
    meta->attribute_count = attribute_count;
    return IMAGE_IO_OK;
}

/* The output arrays being filled, writable. */
typedef struct {
    uint32_t *rgb[EXR_MAX_RGB_LAYERS];
    uint32_t *nonfinite;
    uint32_t *rounded;
    uint64_t *accumulators;
} ReadTarget;

static void scatter_channel(const ReadTarget *target, const ChannelSpec *spec, size_t width, size_t pixel_count,
                            int first_row, int rows, const uint32_t *values)
{
    size_t first = (size_t)first_row * width;
    size_t count = (size_t)rows * width;
    for (size_t i = 0; i < count; ++i) {
        size_t p = first + i;
        size_t rgb = p * RGB_CHANNELS + (size_t)spec->channel;
        switch (spec->layer) {
        case LAYER_RGB:
            target->rgb[spec->rgb][rgb] = values[i];
            break;
        case LAYER_NONFINITE:
            target->nonfinite[p] = values[i];
            break;
        case LAYER_ROUNDED:
            target->rounded[p] = values[i];
            break;
        case LAYER_SETS: {
            uint64_t *word =
                &target->accumulators[accumulator_word(spec->set, spec->channel, spec->word / 2, p, pixel_count)];
            *word |= (uint64_t)values[i] << (spec->word % 2 ? 32 : 0);
            break;
        }
        default:
            break;
        }
    }
}

/* A HALF value as the bits of the equal float. */
static uint32_t half_to_float_bits(uint16_t half)
{
    uint32_t sign = (uint32_t)(half & 0x8000u) << 16;
    uint32_t exponent = (half >> 10) & 0x1fu;
    uint32_t mantissa = half & 0x3ffu;
    if (exponent == 0x1f) /* infinity, NaN */
        return sign | 0x7f800000u | (mantissa << 13);
    if (exponent != 0)
        return sign | ((exponent + 127 - 15) << 23) | (mantissa << 13);
    if (mantissa == 0)
        return sign;
    /* Subnormal, mantissa * 2^-24: normalize to 1.m * 2^(-14 - shift). */
    uint32_t shift = 0;
    while (!(mantissa & 0x400u)) {
        mantissa <<= 1;
        ++shift;
    }
    return sign | ((127 - 14 - shift) << 23) | ((mantissa & 0x3ffu) << 13);
}

/* Unpacks a decompressed scanline chunk (for each row, for each channel,
 * little-endian values) into the wanted channels as 32-bit values, HALF
 * converted to float. Replaces the library's choice: OpenEXR 3.1's
 * specialised unpackers assume every channel is wanted (a skipped channel
 * crashes them) and one misplaces the third of three HALF channels. */
static exr_result_t unpack_chunk(exr_decode_pipeline_t *decode)
{
    const uint8_t *source = decode->unpacked_buffer;
    uint64_t remaining = decode->chunk.unpacked_size;
    for (int y = 0; y < decode->chunk.height; ++y) {
        int row = decode->chunk.start_y + y;
        for (int c = 0; c < decode->channel_count; ++c) {
            const exr_coding_channel_info_t *channel = &decode->channels[c];
            if (channel->height == 0 || (channel->y_samples > 1 && row % channel->y_samples != 0))
                continue;
            int element = channel->bytes_per_element;
            uint64_t bytes = (uint64_t)channel->width * (uint64_t)element;
            if (!source || bytes > remaining)
                return EXR_ERR_CORRUPT_CHUNK;
            if (channel->decode_to_ptr) {
                uint8_t *out = channel->decode_to_ptr + (size_t)y * (size_t)channel->user_line_stride;
                for (int x = 0; x < channel->width; ++x) {
                    const uint8_t *in = source + (size_t)x * (size_t)element;
                    uint32_t value = element == 2 ? half_to_float_bits((uint16_t)(in[0] | in[1] << 8))
                                                  : (uint32_t)in[0] | (uint32_t)in[1] << 8 | (uint32_t)in[2] << 16 |
                                                        (uint32_t)in[3] << 24;
                    memcpy(out + (size_t)x * (size_t)channel->user_pixel_stride, &value, sizeof value);
                }
            }
            source += bytes;
            remaining -= bytes;
        }
    }
    return EXR_ERR_SUCCESS;
}

/* Decodes every scanline chunk into the channels of `specs` (indexed by the
 * file's channel order; layer LAYER_COUNT marks a channel to skip). */
static ImageIoStatus read_pixels(IoContext *io, exr_const_context_t ctxt, const exr_attr_box2i_t *window,
                                 const ChannelSpec *specs, int channel_count, int wanted, const ReadTarget *target)
{
    int width = window->max.x - window->min.x + 1;
    int height = window->max.y - window->min.y + 1;
    size_t pixel_count = (size_t)width * (size_t)height;
    int32_t rows_per_chunk = 0;
    if (EXR_FAILED(io, exr_get_scanlines_per_chunk(ctxt, 0, &rows_per_chunk), "cannot query the chunk size"))
        return IMAGE_IO_ERROR;
    if (rows_per_chunk < 1)
        return fail(io, "invalid chunk size of %d rows", (int)rows_per_chunk);
    size_t plane = (size_t)rows_per_chunk * (size_t)width;
    uint32_t *scratch = malloc(sizeof *scratch * plane * (size_t)wanted);
    int *plane_of_channel = malloc(sizeof *plane_of_channel * (size_t)channel_count);
    if (!scratch || !plane_of_channel) {
        free(scratch);
        free(plane_of_channel);
        return fail(io, "out of memory for a %d-row chunk", (int)rows_per_chunk);
    }
    for (int i = 0, next = 0; i < channel_count; ++i)
        plane_of_channel[i] = specs[i].layer == LAYER_COUNT ? -1 : next++;

    ImageIoStatus status = IMAGE_IO_OK;
    exr_decode_pipeline_t decoder;
    memset(&decoder, 0, sizeof decoder);
    int initialized = 0;
    for (int y = window->min.y; y <= window->max.y && status == IMAGE_IO_OK; y += rows_per_chunk) {
        exr_chunk_info_t chunk;
        if (EXR_FAILED(io, exr_read_scanline_chunk_info(ctxt, 0, y, &chunk), "cannot locate a scanline chunk")) {
            status = IMAGE_IO_ERROR;
            break;
        }
        int first_row = chunk.start_y - window->min.y;
        if (chunk.height < 1 || first_row < 0 || first_row + chunk.height > height) {
            status = fail(io, "scanline chunk at row %d is out of the image", (int)chunk.start_y);
            break;
        }
        exr_result_t result = initialized ? exr_decoding_update(ctxt, 0, &chunk, &decoder)
                                          : exr_decoding_initialize(ctxt, 0, &chunk, &decoder);
        if (library_failed(io, result, "cannot set up the decoder")) {
            status = IMAGE_IO_ERROR;
            break;
        }
        if (decoder.channel_count != channel_count) {
            status = fail(io, "decoder has %d channels, the header %d", (int)decoder.channel_count, channel_count);
            break;
        }
        for (int i = 0; i < channel_count; ++i) {
            exr_coding_channel_info_t *channel = &decoder.channels[i];
            if (plane_of_channel[i] < 0) {
                channel->decode_to_ptr = NULL;
                continue;
            }
            if (!channel->channel_name || strcmp(channel->channel_name, specs[i].name) != 0) {
                status = fail(io, "decoder channel %d is not %s", i, specs[i].name);
                break;
            }
            channel->user_data_type = (uint16_t)spec_pixel_type(&specs[i]);
            channel->user_bytes_per_element = 4;
            channel->user_pixel_stride = 4;
            channel->user_line_stride = 4 * width;
            channel->decode_to_ptr = (uint8_t *)(scratch + plane * (size_t)plane_of_channel[i]);
        }
        if (status != IMAGE_IO_OK)
            break;
        if (!initialized) {
            initialized = 1;
            if (EXR_FAILED(io, exr_decoding_choose_default_routines(ctxt, 0, &decoder),
                           "cannot choose the decoding routines")) {
                status = IMAGE_IO_ERROR;
                break;
            }
            /* NULL: uncompressed data read straight into the planes. */
            if (decoder.unpack_and_convert_fn)
                decoder.unpack_and_convert_fn = unpack_chunk;
        }
        if (EXR_FAILED(io, exr_decoding_run(ctxt, 0, &decoder), "cannot read or decode a scanline chunk")) {
            status = IMAGE_IO_ERROR;
            break;
        }
        for (int i = 0; i < channel_count; ++i)
            if (plane_of_channel[i] >= 0)
                scatter_channel(target, &specs[i], (size_t)width, pixel_count, first_row, chunk.height,
                                scratch + plane * (size_t)plane_of_channel[i]);
    }
    if (initialized)
        exr_decoding_destroy(ctxt, &decoder);
    free(scratch);
    free(plane_of_channel);
    return status;
}

/* Finds the RGB layer of channel `spec` (name length in spec->word, see
 * channel_from_name) in the image, or adds it: its index, or -1 after
 * recording an error. */
static int rgb_layer_of(IoContext *io, ExrImage *image, const ChannelSpec *spec)
{
    size_t length = (size_t)spec->word;
    for (int i = 0; i < image->layer_count; ++i)
        if (strlen(image->layers[i].name) == length && strncmp(image->layers[i].name, spec->name, length) == 0) {
            if (image->layers[i].is_int != spec->is_int) {
                fail(io, "layer %s mixes UINT channels with FLOAT or HALF ones", image->layers[i].name);
                return -1;
            }
            return i;
        }
    if (image->layer_count == EXR_MAX_RGB_LAYERS) {
        fail(io, "the file has more than %d RGB layers", EXR_MAX_RGB_LAYERS);
        return -1;
    }
    const char *name = storage_string(image, spec->name, length);
    if (!name) {
        fail(io, "out of memory");
        return -1;
    }
    ExrRgbLayer *layer = &image->layers[image->layer_count];
    layer->name = name;
    layer->is_int = spec->is_int;
    layer->data = NULL;
    return image->layer_count++;
}

/* Checks the file's channels and maps each to a spec (layer LAYER_COUNT:
 * not ours), adding the RGB layers to the image. Sets found_layers and the
 * number of sets found. */
static ImageIoStatus map_channels(IoContext *io, const exr_attr_chlist_t *list, ExrImage *image, ChannelSpec *specs,
                                  int found_layers[LAYER_COUNT], int *set_count, int *grid_found, int *wanted)
{
    int counter_found[LAYER_COUNT] = {0};
    int rgb_found[EXR_MAX_RGB_LAYERS][RGB_CHANNELS];
    memset(rgb_found, 0, sizeof rgb_found);
    unsigned char words_found[EST_MAX_SETS][RGB_CHANNELS][SUM_WORDS];
    memset(words_found, 0, sizeof words_found);
    int highest_set = -1;
    *wanted = 0;
    *grid_found = 0;
    for (int i = 0; i < list->num_channels; ++i) {
        const exr_attr_chlist_entry_t *entry = &list->entries[i];
        const char *name = entry->name.str ? entry->name.str : "";
        ChannelSpec spec;
        if (!channel_from_name(name, &spec)) {
            specs[i].layer = LAYER_COUNT;
            continue;
        }
        if (entry->x_sampling != 1 || entry->y_sampling != 1)
            return fail(io, "channel %s is subsampled (%d, %d)", name, (int)entry->x_sampling, (int)entry->y_sampling);
        int is_float = entry->pixel_type == EXR_PIXEL_FLOAT || entry->pixel_type == EXR_PIXEL_HALF;
        if (spec.layer == LAYER_RGB) {
            if (!is_float && entry->pixel_type != EXR_PIXEL_UINT)
                return fail(io, "channel %s has pixel type %d, expected FLOAT, HALF or UINT", name,
                            (int)entry->pixel_type);
            spec.is_int = !is_float;
            spec.rgb = rgb_layer_of(io, image, &spec);
            if (spec.rgb < 0)
                return IMAGE_IO_ERROR;
            spec.word = 0;
            rgb_found[spec.rgb][spec.channel] = 1;
        } else if (entry->pixel_type != EXR_PIXEL_UINT) {
            return fail(io, "channel %s has pixel type %d, expected UINT", name, (int)entry->pixel_type);
        } else if (spec.layer == LAYER_SETS && spec.set == GRID_SET) {
            *grid_found = 1;
        } else if (spec.layer == LAYER_SETS) {
            words_found[spec.set][spec.channel][spec.word] = 1;
            highest_set = spec.set > highest_set ? spec.set : highest_set;
        } else {
            counter_found[spec.layer] = 1;
        }
        specs[i] = spec;
        ++*wanted;
    }
    for (int layer = 0; layer < image->layer_count; ++layer) {
        int n = rgb_found[layer][0] + rgb_found[layer][1] + rgb_found[layer][2];
        if (n != RGB_CHANNELS)
            return fail(io, "layer %s has only %d of its 3 channels", image->layers[layer].name, n);
    }
    found_layers[LAYER_RGB] = image->layer_count > 0;
    found_layers[LAYER_NONFINITE] = counter_found[LAYER_NONFINITE];
    found_layers[LAYER_ROUNDED] = counter_found[LAYER_ROUNDED];
    *set_count = highest_set + 1;
    for (int j = 0; j < *set_count; ++j)
        for (int c = 0; c < RGB_CHANNELS; ++c)
            for (int w = 0; w < SUM_WORDS; ++w)
                if (!words_found[j][c][w])
                    return fail(io, "set sums are incomplete: channel %s is missing", set_channel(j, c, w).name);
    found_layers[LAYER_SETS] = *set_count > 0;
    if (*grid_found && *set_count == 0)
        return fail(io, "channel %s is present without set sums", grid_channel().name);
    return IMAGE_IO_OK;
}

/* Set sums as the renderer leaves them, or the file is corrupt (or forged):
 * grid words 0 or EXR_GRID_WORD_MIN..MAX, sums below 2^126 in magnitude
 * (their top two bits equal), so that adding two cannot wrap. */
static ImageIoStatus check_set_sums(IoContext *io, const ExrImage *image, int set_count)
{
    size_t pixels = (size_t)image->width * (size_t)image->height;
    for (size_t p = 0; p < pixels; ++p) {
        uint64_t grid = image->accumulators[accumulator_word(GRID_SET, 0, 0, p, pixels)];
        if (grid != 0 && (grid < EXR_GRID_WORD_MIN || grid > EXR_GRID_WORD_MAX))
            return fail(io, "channel %s of pixel (%zu, %zu) holds %llu, not a grid word", grid_channel().name,
                        p % (size_t)image->width, p / (size_t)image->width, (unsigned long long)grid);
        for (int j = 0; j < set_count; ++j)
            for (int c = 0; c < RGB_CHANNELS; ++c) {
                uint64_t top = image->accumulators[accumulator_word(j, c, 1, p, pixels)] >> 62;
                if (top == 1 || top == 2)
                    return fail(io, "set %d, channel %c of pixel (%zu, %zu) is out of range (2^126 or more)", j,
                                channel_letters[c], p % (size_t)image->width, p / (size_t)image->width);
            }
    }
    return IMAGE_IO_OK;
}

/* Set sums must read back exactly: a file re-saved with a lossy
 * compression, or with B44 (which OpenEXR 3.1.5 decodes wrongly for them,
 * without an error), is refused rather than read as other sums. */
static ImageIoStatus check_sums_compression(IoContext *io, exr_compression_t compression)
{
    static const struct {
        exr_compression_t compression;
        const char *name;
    } refused[] = {{EXR_COMPRESSION_PXR24, "PXR24"},
                   {EXR_COMPRESSION_B44, "B44"},
                   {EXR_COMPRESSION_B44A, "B44A"},
                   {EXR_COMPRESSION_DWAA, "DWAA"},
                   {EXR_COMPRESSION_DWAB, "DWAB"}};
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; ++i)
        if (compression == refused[i].compression)
            return fail(io,
                        "the per-set sums are stored with %s compression, which does not read them back exactly "
                        "(re-save with NONE, RLE, ZIPS, ZIP or PIZ, or render again)",
                        refused[i].name);
    return IMAGE_IO_OK;
}

/* A header can claim any data window; before allocating for it, the file
 * must be large enough to hold that many pixels at the best ratio its
 * compression can reach (deflate's is about 1032:1, RLE's 64:1; the
 * others get a generous bound), so a small damaged file cannot make the
 * reader allocate gigabytes (found by fuzzing). */
static ImageIoStatus check_size_against_file(IoContext *io, exr_compression_t compression,
                                             const exr_attr_chlist_t *list, const ExrImage *image)
{
    size_t pixels = (size_t)image->width * (size_t)image->height;
    struct stat file;
    if (stat(io->path, &file) != 0)
        return fail(io, "cannot stat the file: %s", strerror(errno));
    double ratio = compression == EXR_COMPRESSION_NONE || compression == EXR_COMPRESSION_RLE ||
                           compression == EXR_COMPRESSION_ZIPS || compression == EXR_COMPRESSION_ZIP
                       ? 1100.0
                       : 65536.0;
    double bytes_per_pixel = 0.0;
    for (int i = 0; i < list->num_channels; ++i)
        bytes_per_pixel += list->entries[i].pixel_type == EXR_PIXEL_HALF ? 2.0 : 4.0;
    double data = bytes_per_pixel * (double)pixels;
    if (data > ratio * (double)file.st_size + 65536.0)
        return fail(io, "the header claims %dx%d pixels (%.3g bytes of data), more than a %lld-byte file can hold",
                    image->width, image->height, data, (long long)file.st_size);
    return IMAGE_IO_OK;
}

static ImageIoStatus read_opened(IoContext *io, exr_const_context_t ctxt, ExrImage *image)
{
    int part_count = 0;
    if (EXR_FAILED(io, exr_get_count(ctxt, &part_count), "cannot count the parts"))
        return IMAGE_IO_ERROR;
    if (part_count < 1)
        return fail(io, "the file has no image part");
    exr_storage_t storage;
    if (EXR_FAILED(io, exr_get_storage(ctxt, 0, &storage), "cannot read the storage type"))
        return IMAGE_IO_ERROR;
    if (storage != EXR_STORAGE_SCANLINE)
        return fail(io, "only scanline images are supported (the first part is tiled or deep)");
    exr_attr_box2i_t window;
    if (EXR_FAILED(io, exr_get_data_window(ctxt, 0, &window), "cannot read the data window"))
        return IMAGE_IO_ERROR;
    int64_t width = (int64_t)window.max.x - window.min.x + 1;
    int64_t height = (int64_t)window.max.y - window.min.y + 1;
    if (width < 1 || height < 1 || width > INT32_MAX || height > INT32_MAX)
        return fail(io, "invalid data window (%d, %d)-(%d, %d)", (int)window.min.x, (int)window.min.y,
                    (int)window.max.x, (int)window.max.y);
    image->width = (int)width;
    image->height = (int)height;

    if (read_metadata(io, ctxt, image) != IMAGE_IO_OK)
        return IMAGE_IO_ERROR;

    const exr_attr_chlist_t *list = NULL;
    if (EXR_FAILED(io, exr_get_channels(ctxt, 0, &list), "cannot read the channel list"))
        return IMAGE_IO_ERROR;
    if (!list || list->num_channels < 1)
        return fail(io, "the file has no channels");
    exr_compression_t compression;
    if (EXR_FAILED(io, exr_get_compression(ctxt, 0, &compression), "cannot read the compression"))
        return IMAGE_IO_ERROR;
    ChannelSpec *specs = malloc(sizeof *specs * (size_t)list->num_channels);
    if (!specs)
        return fail(io, "out of memory");
    int found[LAYER_COUNT];
    int set_count = 0, grid_found = 0, wanted = 0;
    ImageIoStatus status = map_channels(io, list, image, specs, found, &set_count, &grid_found, &wanted);
    if (status == IMAGE_IO_OK)
        status = check_size_against_file(io, compression, list, image);
    if (status == IMAGE_IO_OK && found[LAYER_SETS])
        status = check_sums_compression(io, compression);
    if (status == IMAGE_IO_OK && found[LAYER_SETS]) {
        if (image->metadata.set_count == 0)
            image->metadata.set_count = set_count;
        else if (image->metadata.set_count != set_count)
            status = fail(io, "attribute " RENDER_FILE_PREFIX "sets = %d but the file holds %d sets",
                          image->metadata.set_count, set_count);
    }

    size_t pixels = (size_t)image->width * (size_t)image->height;
    size_t most = accumulator_planes(EST_MAX_SETS) * sizeof(uint64_t);
    if (status == IMAGE_IO_OK && pixels > SIZE_MAX / most)
        status = fail(io, "image size %dx%d is too large", image->width, image->height);

    ReadTarget target;
    memset(&target, 0, sizeof target);
    for (int i = 0; i < image->layer_count && status == IMAGE_IO_OK; ++i) {
        size_t bytes = pixels * RGB_CHANNELS * sizeof(uint32_t);
        target.rgb[i] = storage_alloc(image, bytes);
        image->layers[i].data = target.rgb[i];
        if (!target.rgb[i])
            status = fail(io, "out of memory for layer %s (%zu bytes)", image->layers[i].name, bytes);
    }
    for (int layer = LAYER_NONFINITE; layer < LAYER_COUNT && status == IMAGE_IO_OK; ++layer) {
        if (!found[layer])
            continue;
        size_t bytes = layer == LAYER_SETS ? pixels * accumulator_planes((uint32_t)set_count) * sizeof(uint64_t)
                                           : pixels * sizeof(uint32_t);
        void *data = storage_alloc(image, bytes);
        if (!data) {
            status = fail(io, "out of memory for layer %s (%zu bytes)", layer_names[layer], bytes);
            break;
        }
        switch ((Layer)layer) {
        case LAYER_NONFINITE:
            target.nonfinite = data;
            image->nonfinite = data;
            break;
        case LAYER_ROUNDED:
            target.rounded = data;
            image->rounded = data;
            break;
        case LAYER_SETS:
            target.accumulators = data;
            image->accumulators = data;
            /* A file from before the grid channel: units of 2^-56. */
            for (size_t p = 0; p < pixels && !grid_found; ++p)
                target.accumulators[p] = RENDER_FILE_LEGACY_GRID_WORD;
            break;
        default:
            break;
        }
    }

    if (status == IMAGE_IO_OK && wanted > 0)
        status = read_pixels(io, ctxt, &window, specs, list->num_channels, wanted, &target);
    if (status == IMAGE_IO_OK && image->accumulators)
        status = check_set_sums(io, image, set_count);
    free(specs);
    return status;
}

ImageIoStatus exr_image_read(const char *path, ExrImage *image, char *error, size_t error_size)
{
    IoContext io = {path ? path : "(no file name)", error, error_size, {0}};
    if (!image)
        return fail(&io, "no image to read into");
    memset(image, 0, sizeof *image);
    if (!path || !path[0])
        return fail(&io, "no file name given");
    exr_context_initializer_t init = context_initializer(&io);
    exr_context_t ctxt = NULL;
    if (EXR_FAILED(&io, exr_start_read(&ctxt, path, &init), "cannot open as OpenEXR")) {
        if (ctxt)
            exr_finish(&ctxt);
        return IMAGE_IO_ERROR;
    }
    ImageIoStatus status = read_opened(&io, ctxt, image);
    exr_finish(&ctxt);
    return status;
}
