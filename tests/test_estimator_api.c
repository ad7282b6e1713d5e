/* Argument validation of the host estimator API: every bad argument returns
 * ESTIMATOR_INVALID_ARGUMENT with a one-line reason, never crashes, and works
 * without a message buffer; valid calls return ESTIMATOR_OK. */
#include "film/film.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define M 4
#define PIXELS 5
#define SUMS (M * 3 * PIXELS)
#define WORDS (2 * SUMS + PIXELS) /* the grid plane and two words a sum */
#define OUTPUTS (3 * PIXELS)

/* Buffers of exactly the valid sizes for M sets and PIXELS pixels. */
typedef struct {
    float sums[SUMS];
    uint64_t accumulators[WORDS];
    float mean[OUTPUTS], mon[OUTPUTS], gmon[OUTPUTS], gini[OUTPUTS];
    int32_t trim[OUTPUTS];
    EstimatorSettings settings;
    EstimatorImages images;
} Fixture;

static void fixture_init(Fixture *f)
{
    memset(f, 0, sizeof *f);
    for (size_t i = 0; i < SUMS; ++i)
        f->sums[i] = (float)(i % 7) * 0.5f;
    /* Every set sum 1.0: low word 2^56 in units of 2^-56 (grid word
     * 1024 - 56), high word 0, in planes [set][channel][word][pixel] after
     * the grid plane. */
    for (size_t p = 0; p < PIXELS; ++p) {
        f->accumulators[p] = 1024 - 56;
        for (size_t plane = 0; plane < (size_t)M * 3; ++plane)
            f->accumulators[(1 + plane * 2) * PIXELS + p] = (uint64_t)1 << 56;
    }
    estimator_settings_default(&f->settings);
    f->settings.set_count = M;
    f->settings.passes = PASSES_DEFAULT | PASSES_DIAGNOSTICS;
    f->images.pass[PASS_MEAN] = f->mean;
    f->images.pass[PASS_MON] = f->mon;
    f->images.pass[PASS_GMON] = f->gmon;
    f->images.pass[PASS_GINI] = f->gini;
    f->images.pass[PASS_TRIM] = f->trim;
    f->images.length = OUTPUTS;
}

static Fixture fixture;

static int setup(void **state)
{
    (void)state;
    fixture_init(&fixture);
    return 0;
}

/* Calls with a message buffer and again without one: both must refuse, the
 * first with a non-empty reason. */
typedef EstimatorStatus (*Call)(char *message, size_t message_size);

static void expect_invalid(Call call)
{
    char message[256];
    memset(message, 0, sizeof message);
    assert_int_equal(call(message, sizeof message), ESTIMATOR_INVALID_ARGUMENT);
    assert_true(strlen(message) > 0);
    assert_non_null(memchr(message, '\0', sizeof message));
    print_message("refused: %s\n", message);
    assert_int_equal(call(NULL, 0), ESTIMATOR_INVALID_ARGUMENT);
    assert_int_equal(call(NULL, sizeof message), ESTIMATOR_INVALID_ARGUMENT);
    /* A one-byte buffer has room for the terminator only. */
    char tiny = 'x';
    assert_int_equal(call(&tiny, 1), ESTIMATOR_INVALID_ARGUMENT);
    assert_int_equal(tiny, '\0');
}

/* The valid call, from sums, from accumulators and the conversion. */
static EstimatorStatus from_sums(const EstimatorSettings *settings, const float *sums, size_t length, size_t pixels,
                                 EstimatorImages *images, char *message, size_t message_size)
{
    return estimator_from_sums(settings, sums, length, pixels, 100, images, message, message_size);
}

static EstimatorStatus from_accumulators(const EstimatorSettings *settings, const uint64_t *accumulators, size_t length,
                                         size_t pixels, EstimatorImages *images, char *message, size_t message_size)
{
    return estimator_from_accumulators(settings, accumulators, length, pixels, 100, images, message, message_size);
}

static void test_valid_calls_succeed(void **state)
{
    (void)state;
    Fixture *f = &fixture;
    char message[256] = "";
    for (int mode = 0; mode < 3; ++mode) {
        f->settings.gini_mode = (GiniMode)mode;
        assert_int_equal(from_sums(&f->settings, f->sums, SUMS, PIXELS, &f->images, message, sizeof message),
                         ESTIMATOR_OK);
        assert_int_equal(
            from_accumulators(&f->settings, f->accumulators, WORDS, PIXELS, &f->images, message, sizeof message),
            ESTIMATOR_OK);
    }
    assert_int_equal(estimator_sums_from_accumulators(M, f->accumulators, WORDS, PIXELS, f->sums, SUMS, NULL, 0),
                     ESTIMATOR_OK);
    assert_true(f->sums[0] == 1.0f && f->sums[SUMS - 1] == 1.0f);
    /* Only one output requested, and no message buffer. */
    EstimatorImages gmon_only = {.pass[PASS_GMON] = f->gmon, .length = OUTPUTS};
    assert_int_equal(from_sums(&f->settings, f->sums, SUMS, PIXELS, &gmon_only, NULL, 0), ESTIMATOR_OK);
    assert_true(f->gmon[0] == 1.0f / 25.0f); /* sums 1, 100 / M = 25 samples per set */
    /* Longer buffers than needed, and zero pixels, are fine. */
    assert_int_equal(from_sums(&f->settings, f->sums, SUMS, PIXELS - 1, &f->images, NULL, 0), ESTIMATOR_OK);
    assert_int_equal(from_sums(&f->settings, f->sums, SUMS, 0, &f->images, NULL, 0), ESTIMATOR_OK);
    /* The ends of the valid range of M (1 and 64 sets, one pixel). */
    static float sums64[64 * 3];
    EstimatorSettings one = f->settings, most = f->settings;
    one.set_count = 1;
    most.set_count = 64;
    most.gini_mode = SORT_BY_LUMINANCE;
    assert_int_equal(from_sums(&one, sums64, 3, 1, &f->images, NULL, 0), ESTIMATOR_OK);
    assert_int_equal(from_sums(&most, sums64, 64 * 3, 1, &f->images, NULL, 0), ESTIMATOR_OK);
}

/* Each bad argument, for each entry point it applies to. The fixture holds
 * the otherwise valid arguments. */
static EstimatorSettings bad_settings;

static EstimatorStatus sums_with_bad_settings(char *message, size_t size)
{
    return from_sums(&bad_settings, fixture.sums, SUMS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus accumulators_with_bad_settings(char *message, size_t size)
{
    return from_accumulators(&bad_settings, fixture.accumulators, WORDS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus conversion_with_bad_set_count(char *message, size_t size)
{
    return estimator_sums_from_accumulators(bad_settings.set_count, fixture.accumulators, WORDS, PIXELS, fixture.sums,
                                            SUMS, message, size);
}

static void test_set_count_out_of_range(void **state)
{
    (void)state;
    static const int bad[] = {0, 65, -1, 1000, INT32_MIN};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        bad_settings = fixture.settings;
        bad_settings.set_count = bad[i];
        expect_invalid(sums_with_bad_settings);
        expect_invalid(accumulators_with_bad_settings);
        expect_invalid(conversion_with_bad_set_count);
    }
}

static void test_unknown_gini_mode(void **state)
{
    (void)state;
    static const int bad[] = {3, -1, 1000};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        bad_settings = fixture.settings;
        bad_settings.gini_mode = (GiniMode)bad[i];
        expect_invalid(sums_with_bad_settings);
        expect_invalid(accumulators_with_bad_settings);
    }
}

/* Passes outside the list, standard errors with sort-by-luminance, and
 * parameters out of their ranges. */
static void test_bad_passes_and_parameters(void **state)
{
    (void)state;
    bad_settings = fixture.settings;
    bad_settings.passes = PASS_BIT(PASS_COUNT);
    expect_invalid(sums_with_bad_settings);
    bad_settings = fixture.settings;
    bad_settings.with_stderr = 1;
    bad_settings.gini_mode = SORT_BY_LUMINANCE;
    expect_invalid(sums_with_bad_settings);
    expect_invalid(accumulators_with_bad_settings);
    bad_settings = fixture.settings;
    bad_settings.params.amon_alpha = 1.5f;
    expect_invalid(sums_with_bad_settings);
    bad_settings = fixture.settings;
    bad_settings.params.gmedian_iterations = 0;
    expect_invalid(accumulators_with_bad_settings);
}

/* The names users give: estimator lists and parameter assignments. */
static void test_names_and_parameters(void **state)
{
    (void)state;
    uint32_t passes = 0;
    char message[640];
    assert_int_equal(passes_from_list("mean,gmon-authors,gmedian", &passes, message, sizeof message), 0);
    assert_int_equal(passes, PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_GMON_AUTHORS) | PASS_BIT(PASS_GMEDIAN));
    assert_int_equal(passes_from_list("all", &passes, message, sizeof message), 0);
    assert_int_equal(passes, PASSES_ESTIMATES);
    static const char *const bad_lists[] = {"", "mean,", ",mean", "median", "gini", "mean,,mon"};
    for (size_t i = 0; i < sizeof bad_lists / sizeof bad_lists[0]; ++i) {
        assert_int_equal(passes_from_list(bad_lists[i], &passes, message, sizeof message), -1);
        print_message("refused '%s': %s\n", bad_lists[i], message);
    }
    for (int p = 0; p < PASS_COUNT; ++p)
        assert_int_equal(pass_from_name(pass_name(p)), p);

    EstimatorParams params = fixture.settings.params;
    assert_int_equal(estimator_param_set(&params, "admon.alpha=0.25", message, sizeof message), 0);
    assert_true(params.admon_alpha == 0.25f);
    assert_int_equal(estimator_param_set(&params, "trimmed.c=3", message, sizeof message), 0);
    assert_int_equal(params.trimmed_c, 3);
    static const char *const bad_params[] = {
        "admon.alpha", "admon.alpha=", "admon.alpha=2",       "admon.alpha=x", "trimmed.c=1.5",
        "nope=1",      "=1",           "gmedian.iterations=0"};
    for (size_t i = 0; i < sizeof bad_params / sizeof bad_params[0]; ++i) {
        assert_int_equal(estimator_param_set(&params, bad_params[i], message, sizeof message), -1);
        print_message("refused '%s': %s\n", bad_params[i], message);
    }
    /* Formatted values read back as the same values. */
    EstimatorParams again = fixture.settings.params;
    for (int i = 0; i < estimator_param_count(); ++i) {
        const char *name;
        char value[32], assignment[96];
        estimator_param_format(&params, i, &name, value, sizeof value);
        snprintf(assignment, sizeof assignment, "%s=%s", name, value);
        assert_int_equal(estimator_param_set(&again, assignment, message, sizeof message), 0);
    }
    assert_memory_equal(&again, &params, sizeof params);
}

static EstimatorStatus sums_null_settings(char *message, size_t size)
{
    return from_sums(NULL, fixture.sums, SUMS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus sums_null_input(char *message, size_t size)
{
    return from_sums(&fixture.settings, NULL, SUMS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus sums_null_images(char *message, size_t size)
{
    return from_sums(&fixture.settings, fixture.sums, SUMS, PIXELS, NULL, message, size);
}

static EstimatorStatus accumulators_null_settings(char *message, size_t size)
{
    return from_accumulators(NULL, fixture.accumulators, WORDS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus accumulators_null_input(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, NULL, WORDS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus accumulators_null_images(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, WORDS, PIXELS, NULL, message, size);
}

static EstimatorStatus conversion_null_accumulators(char *message, size_t size)
{
    return estimator_sums_from_accumulators(M, NULL, WORDS, PIXELS, fixture.sums, SUMS, message, size);
}

static EstimatorStatus conversion_null_sums(char *message, size_t size)
{
    return estimator_sums_from_accumulators(M, fixture.accumulators, WORDS, PIXELS, NULL, SUMS, message, size);
}

static void test_null_arguments(void **state)
{
    (void)state;
    expect_invalid(sums_null_settings);
    expect_invalid(sums_null_input);
    expect_invalid(sums_null_images);
    expect_invalid(accumulators_null_settings);
    expect_invalid(accumulators_null_input);
    expect_invalid(accumulators_null_images);
    expect_invalid(conversion_null_accumulators);
    expect_invalid(conversion_null_sums);
}

static EstimatorImages no_outputs = {.length = OUTPUTS};

static EstimatorStatus sums_no_output(char *message, size_t size)
{
    return from_sums(&fixture.settings, fixture.sums, SUMS, PIXELS, &no_outputs, message, size);
}

static EstimatorStatus accumulators_no_output(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, WORDS, PIXELS, &no_outputs, message, size);
}

static void test_no_output_requested(void **state)
{
    (void)state;
    expect_invalid(sums_no_output);
    expect_invalid(accumulators_no_output);
}

static EstimatorStatus sums_input_short(char *message, size_t size)
{
    return from_sums(&fixture.settings, fixture.sums, SUMS - 1, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus accumulators_input_short(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, WORDS - 1, PIXELS, &fixture.images, message,
                             size);
}

/* Accumulators are two words per value: a float-sized count is too short. */
static EstimatorStatus accumulators_counted_as_floats(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, SUMS, PIXELS, &fixture.images, message, size);
}

static EstimatorStatus conversion_input_short(char *message, size_t size)
{
    return estimator_sums_from_accumulators(M, fixture.accumulators, WORDS - 1, PIXELS, fixture.sums, SUMS, message,
                                            size);
}

static void test_input_too_short(void **state)
{
    (void)state;
    expect_invalid(sums_input_short);
    expect_invalid(accumulators_input_short);
    expect_invalid(accumulators_counted_as_floats);
    expect_invalid(conversion_input_short);
}

static EstimatorImages short_outputs;

static EstimatorStatus sums_output_short(char *message, size_t size)
{
    return from_sums(&fixture.settings, fixture.sums, SUMS, PIXELS, &short_outputs, message, size);
}

static EstimatorStatus accumulators_output_short(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, WORDS, PIXELS, &short_outputs, message, size);
}

static EstimatorStatus conversion_output_short(char *message, size_t size)
{
    return estimator_sums_from_accumulators(M, fixture.accumulators, WORDS, PIXELS, fixture.sums, SUMS - 1, message,
                                            size);
}

static void test_output_too_short(void **state)
{
    (void)state;
    short_outputs = fixture.images;
    short_outputs.length = OUTPUTS - 1;
    expect_invalid(sums_output_short);
    expect_invalid(accumulators_output_short);
    expect_invalid(conversion_output_short);
}

/* Pixel counts whose buffer sizes overflow size_t, with every length
 * claimed as SIZE_MAX: a wrapped-around size check would let the call run
 * off the ends of the small buffers. */
static size_t huge_pixels;
static EstimatorImages huge_outputs;

static EstimatorStatus sums_huge(char *message, size_t size)
{
    return from_sums(&fixture.settings, fixture.sums, SIZE_MAX, huge_pixels, &huge_outputs, message, size);
}

static EstimatorStatus accumulators_huge(char *message, size_t size)
{
    return from_accumulators(&fixture.settings, fixture.accumulators, SIZE_MAX, huge_pixels, &huge_outputs, message,
                             size);
}

static EstimatorStatus conversion_huge(char *message, size_t size)
{
    return estimator_sums_from_accumulators(M, fixture.accumulators, SIZE_MAX, huge_pixels, fixture.sums, SIZE_MAX,
                                            message, size);
}

static void test_huge_pixel_count(void **state)
{
    (void)state;
    huge_outputs = fixture.images;
    huge_outputs.length = SIZE_MAX;
    /* Just past what M * 3 floats (or 2 * M * 3 words) per pixel can
     * address; 2^(bits - 2), where both products wrap around to exactly 0
     * (M * 3 = 12 = 3 * 4); and the largest. */
    const size_t choices[] = {SIZE_MAX / ((size_t)M * 3) + 1, (size_t)1 << (sizeof(size_t) * 8 - 2), SIZE_MAX};
    for (size_t i = 0; i < sizeof choices / sizeof choices[0]; ++i) {
        huge_pixels = choices[i];
        expect_invalid(sums_huge);
        expect_invalid(accumulators_huge);
        expect_invalid(conversion_huge);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_valid_calls_succeed, setup),
        cmocka_unit_test_setup(test_set_count_out_of_range, setup),
        cmocka_unit_test_setup(test_unknown_gini_mode, setup),
        cmocka_unit_test_setup(test_null_arguments, setup),
        cmocka_unit_test_setup(test_bad_passes_and_parameters, setup),
        cmocka_unit_test_setup(test_names_and_parameters, setup),
        cmocka_unit_test_setup(test_no_output_requested, setup),
        cmocka_unit_test_setup(test_input_too_short, setup),
        cmocka_unit_test_setup(test_output_too_short, setup),
        cmocka_unit_test_setup(test_huge_pixel_count, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
