#define _DEFAULT_SOURCE /* mkstemps, fdopen */
/* Image output: EXR round trips (every layer bit for bit, metadata, exact
 * set sums), the EXR layout as OpenEXR itself sees it, errors on missing and
 * damaged files; PNG files decoded with libpng against independently
 * computed sRGB codes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "io/exr_image.h"
#include "io/png_image.h"
#include "io/image_read.h"

#include <openexr.h>
#include <png.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ------------------------------------------------------------------------
 * Helpers
 * ---------------------------------------------------------------------- */

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* The whole file; NULL if it cannot be read. */
static uint8_t *read_whole_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t capacity = 4096, used = 0;
    uint8_t *data = malloc(capacity);
    size_t n;
    while (data && (n = fread(data + used, 1, capacity - used, f)) > 0) {
        used += n;
        if (used == capacity) {
            uint8_t *bigger = realloc(data, capacity * 2);
            if (!bigger) {
                free(data);
                data = NULL;
                break;
            }
            data = bigger;
            capacity *= 2;
        }
    }
    fclose(f);
    *size = used;
    return data;
}

static void write_whole_file(const char *path, const uint8_t *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f)
        fclose(f);
    return f != NULL;
}

/* ------------------------------------------------------------------------
 * EXR
 * ---------------------------------------------------------------------- */

/* RGB layers of a test image: any names (a dot inside included), float or
 * int32. */
#define TEST_LAYERS 6
static const char *const test_layer_names[TEST_LAYERS] = {"mean", "mon", "gmon", "gini", "gmon.stderr", "trim"};
static const ExrKeyValue test_attributes[] = {
    {"gmon.giniMode", "sort_by_luminance"},
    {"gmon.estimators", "mean,mon,gmon,gini,trim"},
};

/* The data of RGB layer `name`, or NULL. */
static const void *layer_data(const ExrImage *image, const char *name)
{
    const ExrRgbLayer *layer = exr_image_layer(image, name);
    return layer ? layer->data : NULL;
}

/* Buffers behind a test image. */
typedef struct {
    ExrImage image;
    float *rgb[TEST_LAYERS - 1];
    int32_t *trim;
    uint32_t *nonfinite;
    uint32_t *rounded;
    uint64_t *accumulators;
} TestImage;

static const ExrKeyValue test_extras[] = {
    {"comments", "G-MoN round trip"},
    {"render.device", "PoCL / cpu"},
    {"render.command", "gmonrt --spp 1024 --sets 21 scenes/cornell.pbrt"},
};

/* An image with every layer filled with random bits (so NaN payloads,
 * infinities, -0 and denormals appear), sets full of random 128-bit values. */
static TestImage make_full_image(int width, int height, int set_count, uint64_t seed)
{
    TestImage t;
    memset(&t, 0, sizeof t);
    size_t pixels = (size_t)width * (size_t)height;
    uint64_t state = seed;
    for (int layer = 0; layer < TEST_LAYERS - 1; ++layer) {
        t.rgb[layer] = malloc(pixels * 3 * sizeof(float));
        assert_non_null(t.rgb[layer]);
        for (size_t i = 0; i < pixels * 3; ++i) {
            uint32_t bits = (uint32_t)splitmix64(&state);
            memcpy(&t.rgb[layer][i], &bits, sizeof bits);
        }
    }
    t.trim = malloc(pixels * 3 * sizeof(int32_t));
    t.nonfinite = malloc(pixels * sizeof(uint32_t));
    t.rounded = malloc(pixels * sizeof(uint32_t));
    assert_non_null(t.rounded);
    size_t words = (1 + (size_t)set_count * 3 * 2) * pixels;
    t.accumulators = malloc(words * sizeof(uint64_t));
    assert_non_null(t.trim);
    assert_non_null(t.nonfinite);
    assert_non_null(t.accumulators);
    for (size_t i = 0; i < pixels * 3; ++i)
        t.trim[i] = (int32_t)(splitmix64(&state) % 33);
    t.trim[0] = -1; /* any int32 survives, not only valid trims */
    for (size_t i = 0; i < pixels; ++i) {
        t.nonfinite[i] = (uint32_t)splitmix64(&state);
        t.rounded[i] = (uint32_t)splitmix64(&state);
    }
    /* Any valid sums: grid words 0 or in range (the grid plane first),
     * sums below 2^126 in magnitude (the high word's top two bits equal). */
    for (size_t i = 0; i < words; ++i) {
        uint64_t r = splitmix64(&state);
        size_t plane = i / pixels;
        if (plane == 0)
            r = r % 5 == 0 ? 0 : EXR_GRID_WORD_MIN + r % (EXR_GRID_WORD_MAX - EXR_GRID_WORD_MIN + 1);
        else if ((plane - 1) % 2 == 1)
            r = (r & ~((uint64_t)1 << 62)) | ((r >> 1) & ((uint64_t)1 << 62));
        t.accumulators[i] = r;
    }
    t.accumulators[pixels] = 0xffffffffffffffffu;     /* -1 unit in the low word... */
    t.accumulators[2 * pixels] = 0xffffffffffffffffu; /* ...and high word: -1 */

    t.image.width = width;
    t.image.height = height;
    for (int layer = 0; layer < TEST_LAYERS; ++layer) {
        int is_int = layer == TEST_LAYERS - 1;
        const void *data = is_int ? (const void *)t.trim : t.rgb[layer];
        t.image.layers[layer] = (ExrRgbLayer){test_layer_names[layer], is_int, data};
    }
    t.image.layer_count = TEST_LAYERS;
    t.image.nonfinite = t.nonfinite;
    t.image.rounded = t.rounded;
    t.image.accumulators = t.accumulators;
    ExrMetadata *meta = &t.image.metadata;
    meta->software = "gmon 0.1 (test)";
    meta->set_count = set_count;
    meta->sample_count = 0xfedcba9876543211u; /* above 2^53: a double would round it */
    meta->nonfinite_samples = 0x123456789abcdef0u;
    meta->rounded_samples = 0xfedcba987654321u;
    meta->seed = 18446744073709551615u;
    meta->first_sample = 9007199254740993u; /* 2^53 + 1 */
    meta->scene_path = "scenes/cornell box/scene.pbrt";
    meta->scene_hash = "sha256:9f86d081884c7d659a2feaa0c55ad015a3bf4f1b2b0b822cd15d6c15b0f00a08";
    meta->attributes = test_attributes;
    meta->attribute_count = sizeof test_attributes / sizeof test_attributes[0];
    meta->extras = test_extras;
    meta->extra_count = sizeof test_extras / sizeof test_extras[0];
    return t;
}

static void free_test_image(TestImage *t)
{
    for (int layer = 0; layer < TEST_LAYERS - 1; ++layer)
        free(t->rgb[layer]);
    free(t->trim);
    free(t->nonfinite);
    free(t->rounded);
    free(t->accumulators);
}

static void assert_same_bytes(const void *a, const void *b, size_t size)
{
    if (!a || !b) {
        assert_true(a == NULL && b == NULL);
        return;
    }
    assert_memory_equal(a, b, size);
}

static void assert_same_string(const char *a, const char *b)
{
    if (!a || !b) {
        assert_true(a == NULL && b == NULL);
        return;
    }
    assert_string_equal(a, b);
}

static const char *find_extra(const ExrMetadata *meta, const char *key)
{
    for (size_t i = 0; i < meta->extra_count; ++i)
        if (strcmp(meta->extras[i].key, key) == 0)
            return meta->extras[i].value;
    return NULL;
}

static void assert_images_equal(const ExrImage *expected, const ExrImage *actual)
{
    assert_int_equal(actual->width, expected->width);
    assert_int_equal(actual->height, expected->height);
    size_t pixels = (size_t)expected->width * (size_t)expected->height;
    assert_int_equal(actual->layer_count, expected->layer_count);
    for (int i = 0; i < expected->layer_count; ++i) {
        const ExrRgbLayer *want = &expected->layers[i], *got = exr_image_layer(actual, want->name);
        if (!got)
            fail_msg("layer %s missing", want->name);
        assert_int_equal(got->is_int, want->is_int);
        assert_same_bytes(want->data, got->data, pixels * 3 * sizeof(float));
    }
    assert_same_bytes(expected->nonfinite, actual->nonfinite, pixels * sizeof(uint32_t));
    assert_same_bytes(expected->rounded, actual->rounded, pixels * sizeof(uint32_t));
    const ExrMetadata *e = &expected->metadata, *a = &actual->metadata;
    assert_int_equal(a->set_count, e->set_count);
    if (expected->accumulators)
        assert_same_bytes(expected->accumulators, actual->accumulators,
                          (1 + (size_t)e->set_count * 3 * 2) * pixels * sizeof(uint64_t));
    else
        assert_null(actual->accumulators);
    assert_same_string(e->software, a->software);
    assert_true(a->sample_count == e->sample_count);
    assert_true(a->seed == e->seed);
    assert_true(a->first_sample == e->first_sample);
    assert_true(a->nonfinite_samples == e->nonfinite_samples);
    assert_true(a->rounded_samples == e->rounded_samples);
    assert_same_string(e->scene_path, a->scene_path);
    assert_same_string(e->scene_hash, a->scene_hash);
    assert_int_equal(a->attribute_count, e->attribute_count);
    for (size_t i = 0; i < e->attribute_count; ++i) {
        const char *value = exr_image_attribute(actual, e->attributes[i].key);
        assert_non_null(value);
        assert_string_equal(value, e->attributes[i].value);
    }
    assert_int_equal(a->extra_count, e->extra_count);
    for (size_t i = 0; i < e->extra_count; ++i) {
        const char *value = find_extra(a, e->extras[i].key);
        assert_non_null(value);
        assert_string_equal(value, e->extras[i].value);
    }
}

static void round_trip(int width, int height, int set_count, uint64_t seed)
{
    char path[64], error[512] = "";
    snprintf(path, sizeof path, "test_image_io_%dx%d_m%d.exr", width, height, set_count);
    TestImage t = make_full_image(width, height, set_count, seed);
    if (exr_image_write(path, &t.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    ExrImage read;
    if (exr_image_read(path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    assert_images_equal(&t.image, &read);
    exr_image_free(&read);
    assert_int_equal(read.layer_count, 0);
    assert_null(read.storage);
    free_test_image(&t);
    remove(path);
}

static void test_exr_round_trip_m21_7x5(void **state)
{
    (void)state;
    round_trip(7, 5, 21, 1);
}

static void test_exr_round_trip_m1(void **state)
{
    (void)state;
    round_trip(7, 5, 1, 2);
    round_trip(1, 1, 1, 3);
}

/* Several ZIP chunks (16 rows each), the last one partial; M = 64. */
static void test_exr_round_trip_many_chunks(void **state)
{
    (void)state;
    round_trip(37, 35, 21, 4);
    round_trip(3, 17, 64, 5);
}

/* A 32x32 image (mean, MoN, G-MoN) one of whose 16-row chunks ZIP does not
 * shrink: OpenEXR 3.1 stored it compressed at exactly the raw size, which
 * readers take for raw data (garbage). The writer must store it raw. */
static void test_exr_chunk_that_zip_does_not_shrink(void **state)
{
    (void)state;
    ExrImage original, again;
    char error[1024], path[512];
    assert_int_equal(
        exr_image_read(GMON_SOURCE_DIR "/tests/data/zip-chunk-as-large-as-raw.exr", &original, error, sizeof error),
        IMAGE_IO_OK);
    snprintf(path, sizeof path, "test_image_io_zip_equal.exr");
    assert_int_equal(exr_image_write(path, &original, error, sizeof error), IMAGE_IO_OK);
    assert_int_equal(exr_image_read(path, &again, error, sizeof error), IMAGE_IO_OK);
    size_t values = (size_t)original.width * original.height * 3;
    assert_int_equal(original.width, 32);
    assert_int_equal(original.layer_count, 3);
    for (int i = 0; i < 3; ++i)
        assert_memory_equal(layer_data(&again, test_layer_names[i]), layer_data(&original, test_layer_names[i]),
                            values * sizeof(float));
    exr_image_free(&original);
    exr_image_free(&again);
    remove(path);
}

static void test_exr_mean_only(void **state)
{
    (void)state;
    const char *path = "test_image_io_mean_only.exr";
    char error[512] = "";
    float mean[4 * 3 * 3];
    for (size_t i = 0; i < sizeof mean / sizeof mean[0]; ++i)
        mean[i] = (float)i * 0.25f - 1.0f;
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = 4;
    image.height = 3;
    image.layers[image.layer_count++] = (ExrRgbLayer){"mean", 0, mean};
    if (exr_image_write(path, &image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    ExrImage read;
    if (exr_image_read(path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    assert_images_equal(&image, &read);
    assert_int_equal(read.layer_count, 1);
    assert_null(read.nonfinite);
    assert_null(read.accumulators);
    assert_int_equal(read.metadata.set_count, 0);
    assert_null(read.metadata.software);
    assert_int_equal(read.metadata.extra_count, 0);
    exr_image_free(&read);
    remove(path);
}

/* Set sums a renderer cannot leave (a forged or corrupt file) are refused
 * on reading, so that merging them cannot wrap 128 bits: a sum of 2^126 or
 * more in magnitude, or a grid word out of range. */
static void test_exr_refuses_out_of_range_set_sums(void **state)
{
    (void)state;
    const char *path = "test_image_io_forged.exr";
    const struct {
        size_t word; /* in a 2x2 image with M = 1: the grid plane, then R lo, R hi, ... */
        uint64_t value;
        const char *message;
    } cases[] = {
        {2 * 4 + 1, (uint64_t)1 << 62, "out of range (2^126 or more)"}, /* R hi of pixel 1: +2^126 */
        {2 * 4 + 1, (uint64_t)1 << 63, "out of range (2^126 or more)"}, /* -2^127 */
        {2, 5, "not a grid word"},                                      /* E = 5 - 1024 */
        {3, EXR_GRID_WORD_MAX + 1, "not a grid word"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        TestImage t = make_full_image(2, 2, 1, 40 + i);
        memset(t.accumulators, 0, 7 * 4 * sizeof(uint64_t));
        t.accumulators[cases[i].word] = cases[i].value;
        char error[512] = "";
        if (exr_image_write(path, &t.image, error, sizeof error) != IMAGE_IO_OK)
            fail_msg("write failed: %s", error);
        ExrImage read;
        assert_int_equal(exr_image_read(path, &read, error, sizeof error), IMAGE_IO_ERROR);
        if (!strstr(error, cases[i].message))
            fail_msg("case %zu: '%s' does not say '%s'", i, error, cases[i].message);
        exr_image_free(&read);
        free_test_image(&t);
    }
    remove(path);
}

/* A damaged header claiming far more pixels than the file can hold (found
 * by fuzzing: 509 bytes claiming 2x671088641 pixels) is refused before
 * anything is allocated for it. */
static void test_exr_data_window_larger_than_the_file(void **state)
{
    (void)state;
    char path[1024], error[512] = "";
    snprintf(path, sizeof path, "%s/tests/fuzz/corpus/exr/huge-data-window.exr", GMON_SOURCE_DIR);
    ExrImage read;
    assert_int_equal(exr_image_read(path, &read, error, sizeof error), IMAGE_IO_ERROR);
    if (!strstr(error, "more than a 509-byte file can hold"))
        fail_msg("unexpected error: %s", error);
    exr_image_free(&read);
}

/* The file as OpenEXR itself reads it: one scanline part, ZIP, the channel
 * names, types and order, attribute types. */
static void test_exr_layout_seen_by_openexr(void **state)
{
    (void)state;
    const char *path = "test_image_io_layout.exr";
    char error[512] = "";
    TestImage t = make_full_image(5, 4, 2, 6);
    if (exr_image_write(path, &t.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);

    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
    int parts = 0;
    assert_int_equal(exr_get_count(ctxt, &parts), EXR_ERR_SUCCESS);
    assert_int_equal(parts, 1);
    exr_storage_t storage;
    assert_int_equal(exr_get_storage(ctxt, 0, &storage), EXR_ERR_SUCCESS);
    assert_int_equal(storage, EXR_STORAGE_SCANLINE);
    exr_compression_t compression;
    assert_int_equal(exr_get_compression(ctxt, 0, &compression), EXR_ERR_SUCCESS);
    assert_int_equal(compression, EXR_COMPRESSION_ZIP);
    exr_attr_box2i_t window;
    assert_int_equal(exr_get_data_window(ctxt, 0, &window), EXR_ERR_SUCCESS);
    assert_int_equal(window.min.x, 0);
    assert_int_equal(window.min.y, 0);
    assert_int_equal(window.max.x, 4);
    assert_int_equal(window.max.y, 3);

    const exr_attr_chlist_t *channels = NULL;
    assert_int_equal(exr_get_channels(ctxt, 0, &channels), EXR_ERR_SUCCESS);
    /* 5 float layers + trim (3 each) + nonfinite + rounded + sets.grid +
     * 2 sets x 3 x 4 words */
    assert_int_equal(channels->num_channels, 6 * 3 + 3 + 2 * 3 * 4);
    const char *expected[][2] = {
        {"gini.B", "f"},      {"gmon.R", "f"},        {"mean.G", "f"},  {"mon.B", "f"},
        {"nonfinite", "u"},   {"gmon.stderr.G", "f"}, {"rounded", "u"}, {"sets.0.R.w0", "u"},
        {"sets.1.B.w3", "u"}, {"sets.grid", "u"},     {"trim.G", "u"},
    };
    for (size_t e = 0; e < sizeof expected / sizeof expected[0]; ++e) {
        int found = 0;
        for (int i = 0; i < channels->num_channels; ++i) {
            if (strcmp(channels->entries[i].name.str, expected[e][0]) != 0)
                continue;
            found = 1;
            exr_pixel_type_t type = expected[e][1][0] == 'f' ? EXR_PIXEL_FLOAT : EXR_PIXEL_UINT;
            assert_int_equal(channels->entries[i].pixel_type, type);
        }
        if (!found)
            fail_msg("channel %s missing", expected[e][0]);
    }
    for (int i = 1; i < channels->num_channels; ++i)
        assert_true(strcmp(channels->entries[i - 1].name.str, channels->entries[i].name.str) < 0);

    int32_t sets = 0;
    assert_int_equal(exr_attr_get_int(ctxt, 0, "gmon.sets", &sets), EXR_ERR_SUCCESS);
    assert_int_equal(sets, 2);
    int32_t length = 0;
    const char *text = NULL;
    assert_int_equal(exr_attr_get_string(ctxt, 0, "gmon.samples", &length, &text), EXR_ERR_SUCCESS);
    assert_int_equal(length, (int32_t)strlen("18364758544493064721"));
    assert_memory_equal(text, "18364758544493064721", (size_t)length);
    assert_int_equal(exr_attr_get_string(ctxt, 0, "gmon.giniMode", &length, &text), EXR_ERR_SUCCESS);
    assert_memory_equal(text, "sort_by_luminance", (size_t)length);
    assert_int_equal(exr_attr_get_string(ctxt, 0, "render.device", &length, &text), EXR_ERR_SUCCESS);
    assert_memory_equal(text, "PoCL / cpu", (size_t)length);
    exr_finish(&ctxt);
    free_test_image(&t);
    remove(path);
}

/* HALF values and the floats they stand for, subnormals and specials
 * included. */
static const struct {
    uint16_t half;
    float value;
} half_values[] = {
    {0x3c00, 1.0f},     {0x3800, 0.5f},  {0xc000, -2.0f},    {0x0001, 5.9604645e-8f},   {0x03ff, 6.0975552e-5f},
    {0x7bff, 65504.0f}, {0x8000, -0.0f}, {0x7c00, INFINITY}, {0x3555, 0.333251953125f},
};
#define HALF_VALUE_COUNT (sizeof half_values / sizeof half_values[0])

/* A file from another writer: HALF mean channels, a foreign FLOAT channel
 * sorted before them, no gmon attributes, no compression. The mean is read
 * as float, nothing else is present. */
static void test_exr_foreign_file(void **state)
{
    (void)state;
    const char *path = "test_image_io_foreign.exr";
    enum { width = 3, height = 2 };
    const char *names[] = {"Z", "mean.B", "mean.G", "mean.R"};
    uint16_t halves[3][width * height]; /* B, G, R planes */
    float depth[width * height];
    for (int p = 0; p < width * height; ++p) {
        for (int c = 0; c < 3; ++c)
            halves[c][p] = half_values[(size_t)(p + 3 * c) % HALF_VALUE_COUNT].half;
        depth[p] = (float)p;
    }
    exr_context_t ctxt = NULL;
    int part = 0;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, NULL), EXR_ERR_SUCCESS);
    assert_int_equal(exr_add_part(ctxt, "beauty", EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, width, height, EXR_COMPRESSION_NONE),
                     EXR_ERR_SUCCESS);
    for (int c = 0; c < 4; ++c)
        assert_int_equal(exr_add_channel(ctxt, part, names[c], c == 0 ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF,
                                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         EXR_ERR_SUCCESS);
    assert_int_equal(exr_attr_set_string(ctxt, part, "owner", "someone else"), EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);
    exr_encode_pipeline_t encoder;
    memset(&encoder, 0, sizeof encoder);
    for (int y = 0; y < height; ++y) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, y, &chunk), EXR_ERR_SUCCESS);
        assert_int_equal(y == 0 ? exr_encoding_initialize(ctxt, part, &chunk, &encoder)
                                : exr_encoding_update(ctxt, part, &chunk, &encoder),
                         EXR_ERR_SUCCESS);
        assert_int_equal(encoder.channel_count, 4);
        for (int c = 0; c < encoder.channel_count; ++c) {
            exr_coding_channel_info_t *channel = &encoder.channels[c];
            assert_string_equal(channel->channel_name, names[c]);
            int is_depth = c == 0;
            channel->user_bytes_per_element = is_depth ? 4 : 2;
            channel->user_data_type = is_depth ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF;
            channel->user_pixel_stride = channel->user_bytes_per_element;
            channel->user_line_stride = channel->user_bytes_per_element * width;
            channel->encode_from_ptr =
                is_depth ? (const uint8_t *)(depth + y * width) : (const uint8_t *)(halves[c - 1] + y * width);
        }
        if (y == 0)
            assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &encoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_encoding_run(ctxt, part, &encoder), EXR_ERR_SUCCESS);
    }
    exr_encoding_destroy(ctxt, &encoder);
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);

    char error[512] = "";
    ExrImage read;
    if (exr_image_read(path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    assert_int_equal(read.width, width);
    assert_int_equal(read.height, height);
    const float *mean = layer_data(&read, "mean");
    assert_non_null(mean);
    for (int p = 0; p < width * height; ++p) {
        for (int c = 0; c < 3; ++c) { /* c: R, G, B; planes are B, G, R */
            float expected = half_values[(size_t)(p + 3 * (2 - c)) % HALF_VALUE_COUNT].value;
            assert_memory_equal(&mean[p * 3 + c], &expected, sizeof expected);
        }
    }
    assert_int_equal(read.layer_count, 1); /* Z is no RGB layer */
    assert_null(read.nonfinite);
    assert_null(read.accumulators);
    assert_int_equal(read.metadata.set_count, 0);
    assert_true(read.metadata.sample_count == 0);
    assert_null(read.metadata.scene_path);
    assert_int_equal(read.metadata.attribute_count, 0);
    assert_string_equal(find_extra(&read.metadata, "owner"), "someone else");
    exr_image_free(&read);
    remove(path);
}

static void assert_read_fails(const char *path, const char *what)
{
    char error[512] = "";
    ExrImage read;
    if (exr_image_read(path, &read, error, sizeof error) == IMAGE_IO_OK)
        fail_msg("reading %s succeeded", what);
    assert_non_null(strstr(error, path));
    assert_true(strlen(error) > strlen(path) + 2);
    exr_image_free(&read); /* safe after a failure */
}

static void test_exr_missing_and_damaged_files(void **state)
{
    (void)state;
    assert_read_fails("test_image_io_no_such_file.exr", "a missing file");

    const char *path = "test_image_io_damaged_source.exr";
    const char *damaged = "test_image_io_damaged.exr";
    char error[512] = "";
    TestImage t = make_full_image(9, 40, 3, 7);
    if (exr_image_write(path, &t.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    size_t size = 0;
    uint8_t *bytes = read_whole_file(path, &size);
    assert_non_null(bytes);
    assert_true(size > 1000);

    /* Truncated: empty, inside the magic, inside the header, inside the
     * chunk table, inside the pixels, just short of the end. */
    size_t cuts[] = {0, 3, 60, size / 4, size / 2, size - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; ++i) {
        write_whole_file(damaged, bytes, cuts[i]);
        char what[64];
        snprintf(what, sizeof what, "a file cut to %zu of %zu bytes", cuts[i], size);
        assert_read_fails(damaged, what);
    }

    /* Not an EXR at all. */
    const uint8_t text[] = "this is not an OpenEXR file, just text\n";
    write_whole_file(damaged, text, sizeof text);
    assert_read_fails(damaged, "a text file");

    /* Compressed pixel data overwritten: zlib must notice. */
    uint8_t *garbled = malloc(size);
    assert_non_null(garbled);
    memcpy(garbled, bytes, size);
    for (size_t i = size / 2; i < size / 2 + 64; ++i)
        garbled[i] ^= 0x5a;
    write_whole_file(damaged, garbled, size);
    assert_read_fails(damaged, "a file with garbled pixel data");

    free(garbled);
    free(bytes);
    free_test_image(&t);
    remove(path);
    remove(damaged);
}

static void test_exr_write_errors(void **state)
{
    (void)state;
    char error[512] = "";
    float mean[3] = {1, 2, 3};
    uint64_t accumulators[6] = {0};
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = 1;
    image.height = 1;

    assert_int_equal(exr_image_write("test_image_io_empty.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "no layer"));
    image.layers[image.layer_count++] = (ExrRgbLayer){"mean", 0, mean};

    image.accumulators = accumulators; /* without M */
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "test_image_io_bad.exr"));
    image.accumulators = NULL;

    ExrKeyValue reserved[] = {{"gmon.seed", "1"}};
    image.metadata.extras = reserved;
    image.metadata.extra_count = 1;
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "reserved"));
    ExrKeyValue twice[] = {{"note", "a"}, {"note", "b"}};
    image.metadata.extras = twice;
    image.metadata.extra_count = 2;
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    image.metadata.extra_count = 0;

    /* Film attributes: gmon.* keys, none of the file's own. */
    ExrKeyValue not_film[] = {{"giniMode", "per_pixel"}}, own[] = {{"gmon.samples", "3"}};
    image.metadata.attributes = not_film;
    image.metadata.attribute_count = 1;
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    image.metadata.attributes = own;
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    image.metadata.attribute_count = 0;

    /* RGB layer names: not the counters' or the sums', not twice ("" is
     * plain R, G, B). */
    static const char *const bad_names[] = {"sets", "nonfinite", "rounded", "a-name-longer-than-24-byte"};
    for (size_t i = 0; i < sizeof bad_names / sizeof bad_names[0]; ++i) {
        image.layers[0].name = bad_names[i];
        assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    }
    image.layers[0].name = "mean";
    image.layers[image.layer_count++] = (ExrRgbLayer){"mean", 0, mean};
    assert_int_equal(exr_image_write("test_image_io_bad.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "twice"));
    image.layer_count = 1;

    /* A directory that does not exist: the library's message. */
    assert_int_equal(exr_image_write("no_such_directory/x.exr", &image, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "no_such_directory/x.exr"));
    assert_false(file_exists("test_image_io_bad.exr"));
    assert_false(file_exists("test_image_io_empty.exr"));

    /* NULL error buffer is allowed. */
    assert_int_equal(exr_image_write(NULL, &image, NULL, 0), IMAGE_IO_ERROR);
}

/* Sets the header's compression byte ("compression", type "compression",
 * size 1) of an EXR file: for the compressions OpenEXRCore 3.1 cannot write
 * (DWAA, DWAB). */
static void patch_compression(const char *path, exr_compression_t compression)
{
    static const char attribute[] = "compression\0compression\0\1\0\0";
    size_t size = 0;
    uint8_t *bytes = read_whole_file(path, &size);
    assert_non_null(bytes);
    uint8_t *at = NULL;
    for (size_t i = 0; !at && i + sizeof attribute < size; ++i)
        if (memcmp(bytes + i, attribute, sizeof attribute) == 0)
            at = bytes + i + sizeof attribute;
    assert_non_null(at);
    *at = (uint8_t)compression;
    write_whole_file(path, bytes, size);
    free(bytes);
}

/* Re-saves `source` as `path` the way another tool might: the same channels
 * and attributes, another compression (the pixels are zeros: the reader
 * must judge the compression before it decodes them). */
static void resave_with_compression(const char *source, const char *path, exr_compression_t compression)
{
    const int patched = compression == EXR_COMPRESSION_DWAA || compression == EXR_COMPRESSION_DWAB;
    const exr_compression_t written = patched ? EXR_COMPRESSION_NONE : compression;
    exr_context_t in = NULL, out = NULL;
    int part = 0;
    assert_int_equal(exr_start_read(&in, source, NULL), EXR_ERR_SUCCESS);
    exr_attr_box2i_t window;
    assert_int_equal(exr_get_data_window(in, 0, &window), EXR_ERR_SUCCESS);
    const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
    assert_int_equal(exr_start_write(&out, path, EXR_WRITE_FILE_DIRECTLY, NULL), EXR_ERR_SUCCESS);
    assert_int_equal(exr_add_part(out, NULL, EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(out, part, width, height, written), EXR_ERR_SUCCESS);
    assert_int_equal(exr_copy_unset_attributes(out, part, in, 0), EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(out), EXR_ERR_SUCCESS);
    int32_t rows_per_chunk = 0;
    assert_int_equal(exr_get_scanlines_per_chunk(out, part, &rows_per_chunk), EXR_ERR_SUCCESS);
    uint8_t *zeros = calloc((size_t)width * (size_t)rows_per_chunk, 4);
    assert_non_null(zeros);
    exr_encode_pipeline_t encoder;
    memset(&encoder, 0, sizeof encoder);
    for (int y = 0; y < height; y += rows_per_chunk) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_write_scanline_chunk_info(out, part, y, &chunk), EXR_ERR_SUCCESS);
        assert_int_equal(y == 0 ? exr_encoding_initialize(out, part, &chunk, &encoder)
                                : exr_encoding_update(out, part, &chunk, &encoder),
                         EXR_ERR_SUCCESS);
        for (int c = 0; c < encoder.channel_count; ++c) {
            exr_coding_channel_info_t *channel = &encoder.channels[c];
            channel->user_bytes_per_element = channel->bytes_per_element;
            channel->user_data_type = channel->data_type;
            channel->user_pixel_stride = channel->bytes_per_element;
            channel->user_line_stride = channel->bytes_per_element * width;
            channel->encode_from_ptr = zeros;
        }
        if (y == 0)
            assert_int_equal(exr_encoding_choose_default_routines(out, part, &encoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_encoding_run(out, part, &encoder), EXR_ERR_SUCCESS);
    }
    exr_encoding_destroy(out, &encoder);
    assert_int_equal(exr_finish(&out), EXR_ERR_SUCCESS);
    exr_finish(&in);
    free(zeros);
    if (patched)
        patch_compression(path, compression);
}

/* Set sums re-saved with a lossy compression, or B44 (decoded wrongly by
 * OpenEXR 3.1.5, without an error), are refused with the compression's
 * name; lossless compressions read. */
static void test_exr_set_sums_refused_with_lossy_compression(void **state)
{
    (void)state;
    const char *source = "test_image_io_compression_source.exr", *path = "test_image_io_compression.exr";
    char error[512] = "";
    TestImage t = make_full_image(5, 3, 2, 11);
    if (exr_image_write(source, &t.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    static const struct {
        exr_compression_t compression;
        const char *name;
        int refused;
    } cases[] = {{EXR_COMPRESSION_NONE, "NONE", 0}, {EXR_COMPRESSION_RLE, "RLE", 0},
                 {EXR_COMPRESSION_ZIPS, "ZIPS", 0}, {EXR_COMPRESSION_ZIP, "ZIP", 0},
                 {EXR_COMPRESSION_PIZ, "PIZ", 0},   {EXR_COMPRESSION_PXR24, "PXR24", 1},
                 {EXR_COMPRESSION_B44, "B44", 1},   {EXR_COMPRESSION_B44A, "B44A", 1},
                 {EXR_COMPRESSION_DWAA, "DWAA", 1}, {EXR_COMPRESSION_DWAB, "DWAB", 1}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        resave_with_compression(source, path, cases[i].compression);
        ExrImage read;
        ImageIoStatus status = exr_image_read(path, &read, error, sizeof error);
        if (cases[i].refused) {
            if (status == IMAGE_IO_OK)
                fail_msg("set sums with %s compression were read", cases[i].name);
            char expected[64];
            snprintf(expected, sizeof expected, "with %s compression", cases[i].name);
            if (!strstr(error, expected) || !strstr(error, path))
                fail_msg("the error for %s does not name it and the file: '%s'", cases[i].name, error);
        } else {
            if (status != IMAGE_IO_OK)
                fail_msg("set sums with %s compression: %s", cases[i].name, error);
            assert_non_null(read.accumulators);
            assert_int_equal(read.metadata.set_count, 2);
        }
        exr_image_free(&read);
    }
    /* Without set sums a lossy file is an ordinary image. */
    t.image.accumulators = NULL;
    if (exr_image_write(source, &t.image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    resave_with_compression(source, path, EXR_COMPRESSION_B44);
    ExrImage read;
    if (exr_image_read(path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("an image without set sums, B44: %s", error);
    exr_image_free(&read);
    free_test_image(&t);
    remove(source);
    remove(path);
}

/* ------------------------------------------------------------------------
 * PNG
 * ---------------------------------------------------------------------- */

/* libpng's errors and warnings fail the test (cmocka's fail_msg does not
 * return), so reading needs no setjmp here. */
static void png_test_error(png_structp png, png_const_charp message)
{
    (void)png;
    fail_msg("libpng: %s", message);
}

static void png_test_warning(png_structp png, png_const_charp message)
{
    (void)png;
    fail_msg("libpng warning: %s", message);
}

/* The pixels of a PNG as libpng decodes it (3 bytes per pixel, row-major
 * from the top left), after checking that it is 8-bit RGB, not interlaced,
 * and marked sRGB. */
static uint8_t *decode_png(const char *path, uint32_t *width, uint32_t *height)
{
    FILE *file = fopen(path, "rb");
    assert_non_null(file);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, png_test_error, png_test_warning);
    assert_non_null(png);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    png_init_io(png, file);
    png_read_info(png, info);
    int bit_depth, color_type, interlace;
    png_get_IHDR(png, info, width, height, &bit_depth, &color_type, &interlace, NULL, NULL);
    assert_int_equal(bit_depth, 8);
    assert_int_equal(color_type, PNG_COLOR_TYPE_RGB);
    assert_int_equal(interlace, PNG_INTERLACE_NONE);
    int intent = -1;
    assert_int_equal(png_get_sRGB(png, info, &intent), PNG_INFO_sRGB);
    assert_int_equal(intent, PNG_sRGB_INTENT_PERCEPTUAL);
    size_t row_size = png_get_rowbytes(png, info);
    assert_int_equal(row_size, 3 * (size_t)*width);
    uint8_t *pixels = malloc(row_size * *height);
    png_bytep *rows = malloc(sizeof *rows * *height);
    assert_non_null(pixels);
    assert_non_null(rows);
    for (uint32_t y = 0; y < *height; ++y)
        rows[y] = pixels + y * row_size;
    png_read_image(png, rows);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    fclose(file);
    return pixels;
}

/* The 8-bit sRGB code of a linear value, found independently of the
 * writer's formula: the number of code boundaries at or below the value,
 * each boundary the midpoint between two codes decoded with the inverse
 * sRGB transfer function (IEC 61966-2-1). NaN and negatives give 0. */
static uint8_t reference_srgb_code(double linear)
{
    int code = 0;
    for (; code < 255; ++code) {
        double midpoint = (code + 0.5) / 255.0;
        double boundary = midpoint <= 0.04045 ? midpoint / 12.92 : pow((midpoint + 0.055) / 1.055, 2.4);
        if (!(linear >= boundary))
            break;
    }
    return (uint8_t)code;
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long size = ftell(f);
    fclose(f);
    return size;
}

static void test_png_srgb_codes(void **state)
{
    (void)state;
    assert_int_equal(png_srgb_byte(0.0f), 0);
    assert_int_equal(png_srgb_byte(1.0f), 255);
    assert_int_equal(png_srgb_byte(0.5f), 188);      /* 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 */
    assert_int_equal(png_srgb_byte(0.0031308f), 10); /* 12.92 * 0.0031308 = 0.04045 -> 10.3 */
    assert_int_equal(png_srgb_byte(0.18f), 118);     /* 0.4614 * 255 = 117.7 */
    assert_int_equal(png_srgb_byte(-0.5f), 0);
    assert_int_equal(png_srgb_byte(NAN), 0);
    assert_int_equal(png_srgb_byte(-NAN), 0);
    assert_int_equal(png_srgb_byte(2.0f), 255);
    assert_int_equal(png_srgb_byte(INFINITY), 255);
    assert_int_equal(png_srgb_byte(-INFINITY), 0);
    /* Monotonic over the whole range. */
    uint8_t previous = 0;
    for (int i = 0; i <= 4096; ++i) {
        uint8_t code = png_srgb_byte((float)i / 4096.0f);
        assert_true(code >= previous);
        previous = code;
    }
    assert_int_equal(previous, 255);
}

static void test_png_small_image(void **state)
{
    (void)state;
    const char *path = "test_image_io_small.png";
    /* 3x2: known values and their sRGB codes (after exposure 2). */
    const float rgb[2 * 3][3] = {
        {0.0f, 0.5f, 0.25f},        /* 0, 1.0, 0.5 */
        {NAN, -1.0f, INFINITY},     /* 0, 0, 1 */
        {1.0f, 0.00156540f, 0.09f}, /* 2 -> 1, 0.0031308, 0.18 */
        {0.0f, 0.0f, 0.0f},         /* 0 */
        {0.5f, 0.5f, 0.5f},         /* 1.0 */
        {0.25f, 0.125f, 0.0f},      /* 0.5, 0.25, 0 */
    };
    const uint8_t expected[2][3 * 3] = {
        {0, 255, 188, 0, 0, 255, 255, 10, 118},
        {0, 0, 0, 255, 255, 255, 188, 137, 0},
    };
    char error[512] = "";
    if (png_write_srgb(path, 3, 2, &rgb[0][0], 2.0f, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    uint32_t width = 0, height = 0;
    uint8_t *pixels = decode_png(path, &width, &height);
    assert_int_equal(width, 3);
    assert_int_equal(height, 2);
    assert_memory_equal(pixels, expected, sizeof expected);
    free(pixels);
    remove(path);
}

/* Every code of a larger image, with an exposure, against the reference. */
static void test_png_large_image(void **state)
{
    (void)state;
    const char *path = "test_image_io_large.png";
    const int width = 301, height = 250;
    const float exposure = 1.5f;
    const size_t count = 3 * (size_t)width * (size_t)height;
    float *rgb = malloc(sizeof(float) * count);
    assert_non_null(rgb);
    for (size_t i = 0; i < count; ++i)
        rgb[i] = (float)(i % 1021) / 1020.0f - 0.01f; /* a few negatives, and values past 1 after the exposure */
    rgb[5] = NAN;
    rgb[6] = INFINITY;
    char error[512] = "";
    if (png_write_srgb(path, width, height, rgb, exposure, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    uint32_t decoded_width = 0, decoded_height = 0;
    uint8_t *pixels = decode_png(path, &decoded_width, &decoded_height);
    assert_int_equal(decoded_width, width);
    assert_int_equal(decoded_height, height);
    for (size_t i = 0; i < count; ++i)
        if (pixels[i] != reference_srgb_code(rgb[i] * exposure))
            fail_msg("value %zu: linear %g, code %d, expected %d", i, (double)(rgb[i] * exposure), pixels[i],
                     reference_srgb_code(rgb[i] * exposure));
    free(pixels);
    free(rgb);
    remove(path);
}

/* A smooth 256x256 preview is deflate-compressed: far below the 3 bytes per
 * pixel (196608 bytes raw) that stored blocks took. */
static void test_png_compressed(void **state)
{
    (void)state;
    const char *path = "test_image_io_compressed.png";
    enum { SIDE = 256 };
    float *rgb = malloc(sizeof(float) * 3 * SIDE * SIDE);
    assert_non_null(rgb);
    for (int y = 0; y < SIDE; ++y)
        for (int x = 0; x < SIDE; ++x) {
            float *p = rgb + 3 * (y * SIDE + x);
            p[0] = (float)x / SIDE;
            p[1] = (float)y / SIDE;
            p[2] = 0.25f;
        }
    char error[512] = "";
    if (png_write_srgb(path, SIDE, SIDE, rgb, PNG_DEFAULT_EXPOSURE, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    long size = file_size(path);
    print_message("256x256 gradient preview: %ld bytes\n", size);
    assert_true(size < 3 * SIDE * SIDE / 10);
    uint32_t width = 0, height = 0;
    uint8_t *pixels = decode_png(path, &width, &height);
    assert_int_equal(width, SIDE);
    assert_int_equal(height, SIDE);
    for (int i = 0; i < 3 * SIDE * SIDE; ++i)
        assert_int_equal(pixels[i], reference_srgb_code(rgb[i]));
    free(pixels);
    free(rgb);
    remove(path);
}

/* image_read_rgb: an EXR of plain R, G, B channels (what pbrt-v4's
 * environment maps are), a PFM (rows stored bottom-up), a PNG (decoded
 * from sRGB); rows come back from the top. */
static void test_read_rgb_images(void **state)
{
    (void)state;
    char error[512] = "";
    float rgb[2 * 2 * 3] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    char exr_path[] = "/tmp/gmon-read-XXXXXX.exr";
    close(mkstemps(exr_path, 4));
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = 2;
    image.height = 2;
    image.layers[image.layer_count++] = (ExrRgbLayer){"", 0, rgb};
    if (exr_image_write(exr_path, &image, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("write failed: %s", error);
    RgbImage read;
    if (image_read_rgb(exr_path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    assert_int_equal(read.width, 2);
    assert_memory_equal(read.rgb, rgb, sizeof rgb);
    rgb_image_free(&read);
    remove(exr_path);

    char pfm_path[] = "/tmp/gmon-read-XXXXXX.pfm";
    int fd = mkstemps(pfm_path, 4);
    FILE *f = fdopen(fd, "wb");
    fprintf(f, "PF\n2 2\n-1.0\n");
    for (int y = 1; y >= 0; --y) /* bottom row first, little-endian floats */
        assert_int_equal(fwrite(rgb + 6 * y, sizeof(float), 6, f), 6);
    fclose(f);
    if (image_read_rgb(pfm_path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    assert_memory_equal(read.rgb, rgb, sizeof rgb);
    rgb_image_free(&read);
    remove(pfm_path);

    char png_path[] = "/tmp/gmon-read-XXXXXX.png";
    close(mkstemps(png_path, 4));
    const float linear[2 * 2 * 3] = {0, 0.001f, 0.01f, 0.1f, 0.2f, 0.3f, 0.5f, 0.7f, 0.9f, 1, 1, 1};
    assert_int_equal(png_write_srgb(png_path, 2, 2, linear, 1.0f, error, sizeof error), IMAGE_IO_OK);
    if (image_read_rgb(png_path, &read, error, sizeof error) != IMAGE_IO_OK)
        fail_msg("read failed: %s", error);
    for (int i = 0; i < 12; ++i) { /* the code written, decoded by the sRGB curve */
        double code = png_srgb_byte(linear[i]) / 255.0;
        double decoded = code <= 0.04045 ? code / 12.92 : pow((code + 0.055) / 1.055, 2.4);
        assert_true(fabs(read.rgb[i] - decoded) < 1e-6);
    }
    rgb_image_free(&read);
    assert_int_equal(image_read_rgb("/nonexistent.png", &read, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "/nonexistent.png"));
    remove(png_path);
}

static void test_png_errors(void **state)
{
    (void)state;
    char error[512] = "";
    const float rgb[3] = {0.5f, 0.5f, 0.5f};
    remove("test_image_io_bad.png"); /* left by an earlier, failed run */
    assert_int_equal(png_write_srgb("no_such_directory/x.png", 1, 1, rgb, 1.0f, error, sizeof error), IMAGE_IO_ERROR);
    assert_non_null(strstr(error, "no_such_directory/x.png"));
    assert_int_equal(png_write_srgb("test_image_io_bad.png", 0, 1, rgb, 1.0f, error, sizeof error), IMAGE_IO_ERROR);
    assert_int_equal(png_write_srgb("test_image_io_bad.png", 1, 1, NULL, 1.0f, error, sizeof error), IMAGE_IO_ERROR);
    assert_int_equal(png_write_srgb("test_image_io_bad.png", 1, 1, rgb, NAN, error, sizeof error), IMAGE_IO_ERROR);
    assert_int_equal(png_write_srgb("test_image_io_bad.png", 1, 1, rgb, -1.0f, NULL, 0), IMAGE_IO_ERROR);
    assert_false(file_exists("test_image_io_bad.png"));

    /* An error inside libpng (wider than its 1000000-pixel limit): the
     * message names the file and no partial file is left. */
    const int too_wide = 1000001;
    float *row = calloc(3 * (size_t)too_wide, sizeof(float));
    assert_non_null(row);
    assert_int_equal(png_write_srgb("test_image_io_bad.png", too_wide, 1, row, 1.0f, error, sizeof error),
                     IMAGE_IO_ERROR);
    print_message("libpng's failure: %s\n", error);
    assert_non_null(strstr(error, "test_image_io_bad.png: cannot write the PNG: "));
    assert_false(file_exists("test_image_io_bad.png"));
    free(row);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exr_round_trip_m21_7x5),
        cmocka_unit_test(test_exr_round_trip_m1),
        cmocka_unit_test(test_exr_round_trip_many_chunks),
        cmocka_unit_test(test_exr_chunk_that_zip_does_not_shrink),
        cmocka_unit_test(test_exr_mean_only),
        cmocka_unit_test(test_exr_layout_seen_by_openexr),
        cmocka_unit_test(test_exr_refuses_out_of_range_set_sums),
        cmocka_unit_test(test_exr_data_window_larger_than_the_file),
        cmocka_unit_test(test_exr_foreign_file),
        cmocka_unit_test(test_exr_missing_and_damaged_files),
        cmocka_unit_test(test_exr_write_errors),
        cmocka_unit_test(test_exr_set_sums_refused_with_lossy_compression),
        cmocka_unit_test(test_png_srgb_codes),
        cmocka_unit_test(test_png_small_image),
        cmocka_unit_test(test_png_large_image),
        cmocka_unit_test(test_png_compressed),
        cmocka_unit_test(test_png_errors),
        cmocka_unit_test(test_read_rgb_images),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
