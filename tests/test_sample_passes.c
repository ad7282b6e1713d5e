/* The per-sample estimators (kernels/film/sample_passes.h): clamp and clamp-sum
 * on a hand-computed sample stream, the kernels' accumulation and
 * estimation equal to the host's bit for bit, and in renders: clamp at
 * V = infinity equals the mean bit for bit, the set sums and set-based
 * estimates do not change when they are requested, their images do not
 * depend on pass batching, pbrt-v4's Film "maxcomponentvalue" selects
 * clamp, and clamp-sum's direct part is exactly the light a render of
 * maxdepth 1 sees; abmm's moments do not cancel (a pixel of 1e6 with
 * relative variance 1e-6), abmm and gabmm match an independent long-double
 * implementation (tests/support/moment_reference.c), and gabmm goes
 * negative on a single firefly, as the spec says; mean-or-mon's sums of
 * d^2 hold squares past float's range, its half-widths and choice match the
 * reference (the mean without outliers, MoN with one firefly), and it is
 * bit for bit the set-based mean or MoN it chose. */
#include "film/film_sample.h"
#include "film/sample_estimator_program.h"
#include "render/renderer.h"
#include "render/scene_convert.h"
#include "moment_reference.h"
#include "sample_streams.h"
#include "zirr_reference.h"
#include "test_device.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static RenderScene glass;
static int glass_loaded;

static int setup(void **state)
{
    char path[1024], error[1024];
    snprintf(path, sizeof path, "%s/scenes/cornell-glass.pbrt", GMON_SOURCE_DIR);
    SceneSummary summary;
    if (scene_convert_load(path, 0, 24, 18, 1, &glass, &summary, error, sizeof error) ||
        render_scene_finalize(&glass, error, sizeof error)) {
        fprintf(stderr, "%s\n", error);
        return -1;
    }
    glass_loaded = 1;
    return test_device_setup(state);
}

static int teardown(void **state)
{
    if (glass_loaded)
        render_scene_destroy(&glass);
    return test_device_teardown(state);
}

static EstimatorSettings sample_settings(uint32_t passes, const float *levels, int level_count)
{
    EstimatorSettings s;
    estimator_settings_default(&s);
    s.passes = passes;
    s.set_count = 1; /* parts_of's; parts_in_set for more */
    s.params.clamp_level_count = level_count;
    for (int i = 0; i < level_count; ++i)
        s.params.clamp_levels[i] = levels[i];
    return s;
}

static SampleParts parts_of(float fr, float fg, float fb, float dr, float dg, float db, float ir, float ig, float ib,
                            float weight)
{
    SampleParts p = {{fr, fg, fb}, {dr, dg, db}, {ir, ig, ib}, weight, 0, 1};
    return p;
}

/* parts_of for sample index `sample` of a render of `sets` sets. */
static SampleParts parts_in_set(SampleParts p, uint64_t sample, int sets)
{
    p.set = set_of_sample(sample, (uint32_t)sets);
    p.set_count = (uint32_t)sets;
    return p;
}

/* Three samples whose clamped sums are known by hand (every value exact in
 * binary). */
static void test_hand_computed_stream(void **state)
{
    (void)state;
    const float levels[] = {1.0f, 10.0f, INFINITY};
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_CLAMP_SUM), levels, 3);
    s.params.clamp_sum_direct = 2.0f;
    s.params.clamp_sum_indirect = 10.0f;
    assert_int_equal(estimator_settings_check(&s, NULL, 0), 0);
    const size_t planes = film_sample_planes(&s);
    assert_int_equal(planes, accumulator_planes(3) + accumulator_planes(1));
    uint64_t *state_sums = calloc(planes, sizeof(uint64_t)), *sets = calloc(accumulator_planes(1), sizeof(uint64_t));
    const SampleParts stream[] = {
        parts_of(0.5f, 0.25f, 0.125f, 0.5f, 0.25f, 0.125f, 0, 0, 0, 1.0f),
        /* direct |.| sum 4 > 2: halved; indirect 3 <= 10 */
        parts_of(4, 2, 1, 3, 0, 1, 1, 2, 0, 1.0f),
        /* max 16: by 1/16 at V = 1, by 10/16 at V = 10; indirect sum 40 > 10: by 1/4 */
        parts_of(16, 8, 16, 0, 0, 0, 16, 8, 16, 1.0f),
    };
    for (int i = 0; i < 3; ++i)
        assert_int_equal(film_sample_add(&s, sets, state_sums, 0, 1, &stream[i]), EST_ADD_EXACT);
    float clamp[3][3], clamp_sum[3];
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    images.pass[PASS_CLAMP] = clamp;
    images.pass[PASS_CLAMP_SUM] = clamp_sum;
    images.length = 3;
    assert_int_equal(film_sample_estimate(&s, state_sums, planes, sets, 1, 3, &images, NULL, 0), ESTIMATOR_OK);
    const float expected[4][3] = {
        {2.5f, 1.25f, 1.375f}, {14.5f, 7.25f, 11.125f}, {20.5f, 10.25f, 17.125f}, {7.0f, 4.25f, 4.625f}};
    for (int c = 0; c < 3; ++c) {
        for (int level = 0; level < 3; ++level)
            assert_true(clamp[level][c] == expected[level][c] / 3.0f);
        assert_true(clamp_sum[c] == expected[3][c] / 3.0f);
    }
    char name[32];
    film_sample_layer_name(&s, PASS_CLAMP, 0, name, sizeof name);
    assert_string_equal(name, "clamp-1");
    film_sample_layer_name(&s, PASS_CLAMP, 2, name, sizeof name);
    assert_string_equal(name, "clamp-inf");
    s.params.clamp_levels[0] = 0.1f;
    film_sample_layer_name(&s, PASS_CLAMP, 0, name, sizeof name);
    assert_string_equal(name, "clamp-0.1");
    free(state_sums);
    free(sets);
}

/* clamp.levels parses and formats as V:V:...; bad lists are refused. */
static void test_levels_parameter(void **state)
{
    (void)state;
    EstimatorSettings s;
    estimator_settings_default(&s);
    char message[512];
    assert_int_equal(estimator_param_set(&s.params, "clamp.levels=0.5:2:inf", message, sizeof message), 0);
    assert_int_equal(s.params.clamp_level_count, 3);
    assert_true(s.params.clamp_levels[0] == 0.5f && s.params.clamp_levels[1] == 2.0f &&
                isinf(s.params.clamp_levels[2]));
    const char *name;
    char value[160];
    estimator_param_format(&s.params, estimator_param_count() - 1, &name, value, sizeof value);
    assert_string_equal(name, "clamp.levels");
    assert_string_equal(value, "0.5:2:inf");
    assert_int_equal(estimator_param_set(&s.params, "clamp.levels=0:1", message, sizeof message), -1);
    assert_int_equal(estimator_param_set(&s.params, "clamp.levels=1,10", message, sizeof message), -1);
    assert_int_equal(estimator_param_set(&s.params, "clamp.levels=1:2:3:4:5:6:7:8:9", message, sizeof message), -1);
    uint32_t passes = 0;
    assert_int_equal(passes_from_list("all", &passes, message, sizeof message), 0);
    assert_int_equal(passes & PASSES_SAMPLE, 0);
    assert_int_equal(passes_from_list("mean,clamp,clamp-sum", &passes, message, sizeof message), 0);
    assert_int_equal(passes, PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_CLAMP_SUM));
}

static uint32_t lcg(uint32_t *x)
{
    *x = *x * 1664525u + 1013904223u;
    return *x >> 8;
}

static float uniform(uint32_t *x)
{
    return (float)lcg(x) / 16777216.0f;
}

/* Random streams with fireflies, negative filter weights and non-finite
 * samples: the kernel's state and images equal the host's bit for bit. */
static void test_kernel_equals_host(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const float levels[] = {0.5f, 3.0f, INFINITY};
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_CLAMP_SUM), levels, 3);
    s.params.clamp_sum_direct = 1.0f;
    s.params.clamp_sum_indirect = 5.0f;
    enum { PIXELS = 37, LENGTH = 41 };
    float *parts = malloc(sizeof(float) * PIXELS * LENGTH * 10);
    uint32_t seed = 12345;
    for (int i = 0; i < PIXELS * LENGTH; ++i) {
        float *p = parts + i * 10;
        for (int c = 0; c < 3; ++c) {
            p[3 + c] = uniform(&seed) * (uniform(&seed) < 0.05f ? 1e4f : 1.0f);
            p[6 + c] = uniform(&seed) * (uniform(&seed) < 0.05f ? 3e5f : 0.5f);
            p[c] = p[3 + c] + p[6 + c];
        }
        p[9] = uniform(&seed) < 0.1f ? -0.25f : 0.5f + uniform(&seed);
        if (i % 97 == 5)
            p[1] = NAN;
    }
    const size_t planes = film_sample_planes(&s), set_planes = accumulator_planes(1);
    uint64_t *host = calloc(planes * PIXELS, sizeof(uint64_t)), *device = calloc(planes * PIXELS, sizeof(uint64_t));
    uint64_t *host_sets = calloc(set_planes * PIXELS, sizeof(uint64_t));
    uint64_t *device_sets = calloc(set_planes * PIXELS, sizeof(uint64_t));
    for (int pixel = 0; pixel < PIXELS; ++pixel)
        for (int i = 0; i < LENGTH; ++i) {
            const float *p = parts + ((size_t)pixel * LENGTH + (size_t)i) * 10;
            SampleParts sp = parts_of(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9]);
            film_sample_add(&s, host_sets, host, (size_t)pixel, PIXELS, &sp);
        }
    float host_clamp[3][PIXELS][3], host_sum[PIXELS][3], device_clamp[3][PIXELS][3], device_sum[PIXELS][3];
    EstimatorImages hi, di;
    memset(&hi, 0, sizeof hi);
    memset(&di, 0, sizeof di);
    hi.pass[PASS_CLAMP] = host_clamp;
    hi.pass[PASS_CLAMP_SUM] = host_sum;
    di.pass[PASS_CLAMP] = device_clamp;
    di.pass[PASS_CLAMP_SUM] = device_sum;
    hi.length = di.length = PIXELS * 3;
    assert_int_equal(film_sample_estimate(&s, host, planes * PIXELS, host_sets, PIXELS, LENGTH, &hi, NULL, 0),
                     ESTIMATOR_OK);
    SampleEstimatorProgram *program = sample_estimator_program_new(&test_device, &s, NULL);
    assert_non_null(program);
    assert_int_equal(sample_estimator_program_run_stream(program, parts, LENGTH, PIXELS, device_sets, device, &di), 0);
    assert_memory_equal(host_sets, device_sets, set_planes * PIXELS * sizeof(uint64_t));
    assert_memory_equal(host, device, planes * PIXELS * sizeof(uint64_t));
    assert_memory_equal(host_clamp, device_clamp, sizeof host_clamp);
    assert_memory_equal(host_sum, device_sum, sizeof host_sum);
    /* The levels bite: clamp-0.5 <= clamp-3 <= clamp-inf where weights are
     * positive, and they differ somewhere. */
    int differ = 0;
    for (int p = 0; p < PIXELS; ++p)
        for (int c = 0; c < 3; ++c)
            differ |= host_clamp[0][p][c] != host_clamp[2][p][c];
    assert_true(differ);
    sample_estimator_program_destroy(program);
    free(parts);
    free(host);
    free(device);
    free(host_sets);
    free(device_sets);
}

/* A stream of one pixel: each value x (grey) as a sample of weight 1, into
 * the per-sample state and the set sums (the settings' sets). */
static void add_grey_stream(const EstimatorSettings *s, const float *x, size_t n, uint64_t *state,
                            uint64_t *accumulators, size_t pixel, size_t pixel_count)
{
    for (size_t i = 0; i < n; ++i) {
        SampleParts p =
            parts_in_set(parts_of(x[i], x[i], x[i], 0, 0, 0, 0, 0, 0, 1.0f), s->first_sample + i, s->set_count);
        film_sample_add(s, accumulators, state, pixel, pixel_count, &p);
    }
}

/* A pixel of 1e6 with relative variance 1e-6 (sd 1e3): its central
 * moments, about the pixel's first sample, match the two-pass reference
 * (raw moments would lose them: 1e12 against 1e6). */
static void test_moments_do_not_cancel(void **state)
{
    (void)state;
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_ABMM), NULL, 0);
    s.params.clamp_level_count = 1;
    enum { N = 4000 };
    float *x = malloc(N * sizeof(float));
    uint32_t seed = 99;
    for (int i = 0; i < N; ++i) /* uniform: sd = 1e3 for a half-width of 1e3 sqrt(3) */
        x[i] = 1e6f + 1732.0508f * (2.0f * uniform(&seed) - 1.0f) + (i % 50 == 0 ? 4000.0f : 0.0f);
    uint64_t *st = calloc(film_sample_planes(&s), sizeof(uint64_t)),
             *acc = calloc(accumulator_planes(1), sizeof(uint64_t));
    add_grey_stream(&s, x, N, st, acc, 0, 1);
    PixelSetTotals totals;
    pixel_set_totals(acc, 1, 0, 1, &totals);
    PixelMoments m = sample_moments(st, &totals, 1, 0, 1, film_sample_passes(&s), 1, s.params.zirr_k, N, 1);
    ReferenceMoments r = reference_moments(x, N);
    long double sd = sqrtl(r.m2);
    printf("  1e6 +- 1e3: mean %.12Lg (reference %.12Lg), m2 %.12g (%.12Lg), m3 %.6g (%.6Lg)\n", (long double)m.mean,
           r.mean, m.second, r.m2, m.third, r.m3);
    assert_true(fabsl((long double)m.mean - r.mean) <= 1e-12L * r.mean);
    /* d^2 and d^3 are rounded to double per sample (2^-53 relative). */
    assert_true(fabsl((long double)m.second - r.m2) <= 1e-12L * r.m2);
    assert_true(fabsl((long double)m.third - r.m3) <= 1e-10L * sd * sd * sd);
    assert_true(r.m2 > 0.9e6L && r.m2 < 1.5e6L);
    free(x);
    free(st);
    free(acc);
}

/* abmm and gabmm on streams with known moments: a skewed stream and the
 * spec's single firefly (background uniform [0.4, 0.6], one sample of
 * 5e4, n = 1000, M = 21), where gabmm is about -232 with the truth 0.5. */
static void test_abmm_gabmm_against_reference(void **state)
{
    (void)state;
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_ABMM) | PASS_BIT(PASS_GABMM), NULL, 0);
    s.params.clamp_level_count = 1;
    s.set_count = 21;
    enum { N = 1000 };
    float x[2][N];
    uint32_t seed = 5;
    for (int i = 0; i < N; ++i) {
        float u = uniform(&seed);
        x[0][i] = 0.1f / (1.0f - 0.999f * u); /* skewed, heavy right tail */
        x[1][i] = i == 617 ? 5e4f : 0.4f + 0.2f * uniform(&seed);
    }
    const size_t planes = film_sample_planes(&s), sets = accumulator_planes(21);
    uint64_t *st = calloc(planes * 2, sizeof(uint64_t)), *acc = calloc(sets * 2, sizeof(uint64_t));
    for (int p = 0; p < 2; ++p)
        add_grey_stream(&s, x[p], N, st, acc, (size_t)p, 2);
    float abmm[2][3], gabmm[2][3];
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    images.pass[PASS_ABMM] = abmm;
    images.pass[PASS_GABMM] = gabmm;
    images.length = 6;
    assert_int_equal(film_sample_estimate(&s, st, planes * 2, acc, 2, N, &images, NULL, 0), ESTIMATOR_OK);
    for (int p = 0; p < 2; ++p) {
        long double means[64];
        int m = reference_set_means(x[p], N, 21, 0, means);
        long double g = reference_gini(means, m);
        long double want_abmm = reference_abmm(x[p], N, 1.0L), want_gabmm = reference_abmm(x[p], N, 1.0L - g);
        printf("  %s: abmm %.7g (reference %.7Lg), gabmm %.7g (reference %.7Lg, Gbar %.5Lf), mean %.7Lg\n",
               p ? "single firefly" : "skewed stream", abmm[p][0], want_abmm, gabmm[p][0], want_gabmm, g,
               reference_moments(x[p], N).mean);
        assert_true(fabsl(abmm[p][0] - want_abmm) <= 1e-5L * fabsl(want_abmm));
        /* Gbar in float: its rounding moves gabmm by about 1e-6 relative. */
        assert_true(fabsl(gabmm[p][0] - want_gabmm) <= 1e-4L * fabsl(want_gabmm));
        assert_true(abmm[p][1] == abmm[p][0] && gabmm[p][2] == gabmm[p][0]);
    }
    assert_true(gabmm[1][0] < -200.0f && gabmm[1][0] > -260.0f); /* the spec's "about -232" */
    free(st);
    free(acc);
}

/* The kernels' moments and their estimates equal the host's bit for bit
 * (also a render range not starting at set 0). */
static void test_moments_kernel_equals_host(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    EstimatorSettings s = sample_settings(
        PASS_BIT(PASS_ABMM) | PASS_BIT(PASS_GABMM) | PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_MEAN_OR_MON), NULL, 0);
    s.params.clamp_level_count = 1;
    s.params.clamp_levels[0] = 2.0f;
    s.set_count = 7;
    s.first_sample = 3;
    enum { PIXELS = 29, LENGTH = 45 };
    float *parts = malloc(sizeof(float) * PIXELS * LENGTH * 10);
    uint32_t seed = 777;
    for (int i = 0; i < PIXELS * LENGTH; ++i) {
        float *p = parts + i * 10;
        for (int c = 0; c < 3; ++c) {
            /* fireflies in odd pixels only: mean-or-mon takes MoN there, the mean in most even ones */
            const float firefly = (i % PIXELS) % 2 && uniform(&seed) < 0.03f ? 1e4f : 1.0f;
            p[c] = (float)(i % PIXELS + 1) * firefly * uniform(&seed);
            p[3 + c] = p[6 + c] = 0.0f;
        }
        p[9] = uniform(&seed) < 0.1f ? -0.5f : 1.0f;
    }
    const size_t planes = film_sample_planes(&s), sets = accumulator_planes(7);
    uint64_t *host = calloc(planes * PIXELS, sizeof(uint64_t)), *device = calloc(planes * PIXELS, sizeof(uint64_t));
    uint64_t *acc = calloc(sets * PIXELS, sizeof(uint64_t)), *device_acc = calloc(sets * PIXELS, sizeof(uint64_t));
    for (int pixel = 0; pixel < PIXELS; ++pixel)
        for (int i = 0; i < LENGTH; ++i) {
            const float *p = parts + ((size_t)pixel * LENGTH + (size_t)i) * 10;
            SampleParts sp = parts_in_set(parts_of(p[0], p[1], p[2], 0, 0, 0, 0, 0, 0, p[9]), 3 + (uint64_t)i, 7);
            film_sample_add(&s, acc, host, (size_t)pixel, PIXELS, &sp);
        }
    float hc[PIXELS][3], ha[PIXELS][3], hg[PIXELS][3], dc[PIXELS][3], da[PIXELS][3], dg[PIXELS][3];
    float hm[PIXELS][3], dm[PIXELS][3];
    EstimatorImages hi, di;
    memset(&hi, 0, sizeof hi);
    memset(&di, 0, sizeof di);
    hi.pass[PASS_CLAMP] = hc;
    hi.pass[PASS_ABMM] = ha;
    hi.pass[PASS_GABMM] = hg;
    hi.pass[PASS_MEAN_OR_MON] = hm;
    di.pass[PASS_CLAMP] = dc;
    di.pass[PASS_ABMM] = da;
    di.pass[PASS_GABMM] = dg;
    di.pass[PASS_MEAN_OR_MON] = dm;
    hi.length = di.length = PIXELS * 3;
    assert_int_equal(film_sample_estimate(&s, host, planes * PIXELS, acc, PIXELS, LENGTH, &hi, NULL, 0), ESTIMATOR_OK);
    /* abmm alone (no -DEST_SETS) builds too. */
    EstimatorSettings alone = sample_settings(PASS_BIT(PASS_ABMM), NULL, 0);
    SampleEstimatorProgram *abmm_alone = sample_estimator_program_new(&test_device, &alone, NULL);
    assert_non_null(abmm_alone);
    sample_estimator_program_destroy(abmm_alone);
    SampleEstimatorProgram *program = sample_estimator_program_new(&test_device, &s, NULL);
    assert_non_null(program);
    assert_int_equal(sample_estimator_program_run_stream(program, parts, LENGTH, PIXELS, device_acc, device, &di), 0);
    assert_memory_equal(acc, device_acc, sets * PIXELS * sizeof(uint64_t));
    assert_memory_equal(host, device, planes * PIXELS * sizeof(uint64_t));
    assert_memory_equal(hc, dc, sizeof hc);
    assert_memory_equal(ha, da, sizeof ha);
    assert_memory_equal(hg, dg, sizeof hg);
    assert_memory_equal(hm, dm, sizeof hm);
    int differ = 0;
    for (int p = 0; p < PIXELS; ++p)
        differ |= ha[p][0] != hg[p][0];
    assert_true(differ);
    /* mean-or-mon is the set-based mean or MoN of each pixel, and both
     * choices occur (the fireflies). */
    float mean[PIXELS][3], mon[PIXELS][3];
    EstimatorSettings set_based = s;
    set_based.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_MON);
    EstimatorImages si;
    memset(&si, 0, sizeof si);
    si.pass[PASS_MEAN] = mean;
    si.pass[PASS_MON] = mon;
    si.length = PIXELS * 3;
    assert_int_equal(estimator_from_accumulators(&set_based, acc, sets * PIXELS, PIXELS, LENGTH, &si, NULL, 0),
                     ESTIMATOR_OK);
    int chose_mean = 0, chose_mon = 0;
    for (int p = 0; p < PIXELS; ++p) {
        const int is_mean = memcmp(hm[p], mean[p], sizeof hm[p]) == 0,
                  is_mon = memcmp(hm[p], mon[p], sizeof hm[p]) == 0;
        assert_true(is_mean || is_mon);
        chose_mean += is_mean && !is_mon;
        chose_mon += is_mon && !is_mean;
    }
    printf("  mean-or-mon: %d pixels the mean, %d MoN\n", chose_mean, chose_mon);
    assert_true(chose_mean > 0 && chose_mon > 0);
    sample_estimator_program_destroy(program);
    free(parts);
    free(host);
    free(device);
    free(acc);
    free(device_acc);
}

/* The sums of d^2 (d = x - c, c the pixel's first sample, here 0) are
 * doubles by set and channel, past float's range both ways: (2^100)^2 +
 * (3 2^90)^2 = 2^180 (2^20 + 9) and (2^-100)^2, each exact in double, with
 * a non-finite sample as 0. */
static void test_square_sums(void **state)
{
    (void)state;
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_MEAN_OR_MON), NULL, 0);
    s.set_count = 3;
    const size_t planes = film_sample_planes(&s);
    assert_int_equal(planes, EST_CHANNELS + 3 * EST_CHANNELS); /* the shifts, the squares */
    uint64_t *st = calloc(planes, sizeof(uint64_t)), *sets = calloc(accumulator_planes(3), sizeof(uint64_t));
    const float x[] = {0.0f, ldexpf(1.0f, 100), NAN, 3.0f * ldexpf(1.0f, 90)};
    for (int i = 0; i < 4; ++i) {
        SampleParts p = parts_in_set(parts_of(x[i], x[i], 0.0f, 0, 0, 0, 0, 0, 0, 1.0f), 0, 3); /* all in set 0 */
        assert_int_equal(film_sample_add(&s, sets, st, 0, 1, &p), EST_ADD_EXACT);
    }
    SampleParts tiny =
        parts_in_set(parts_of(ldexpf(1.0f, -100), ldexpf(1.0f, -100), 1.0f, 0, 0, 0, 0, 0, 0, 1.0f), 1, 3);
    assert_int_equal(film_sample_add(&s, sets, st, 0, 1, &tiny), EST_ADD_EXACT);
    const double want[3][EST_CHANNELS] = {{ldexp(1048585.0, 180), ldexp(1048585.0, 180), 0.0},
                                          {ldexp(1.0, -200), ldexp(1.0, -200), 1.0},
                                          {0.0, 0.0, 0.0}};
    for (uint32_t j = 0; j < 3; ++j)
        for (int c = 0; c < EST_CHANNELS; ++c) {
            const double sum = sample_square_sum(st, 0, 1, film_sample_passes(&s), 0, s.params.zirr_k, j, c);
            assert_memory_equal(&sum, &want[j][c], sizeof sum);
        }
    free(st);
    free(sets);
}

/* mean-or-mon on grey streams against the long-double reference, for odd
 * and even M: no outlier (the mean), one firefly of 5e4 (MoN), and a pixel
 * of 1e6 with relative variance 1e-6 (the mean, its half-widths not lost to
 * cancellation); each image is bit for bit the set-based estimate chosen. */
static void test_mean_or_mon_against_reference(void **state)
{
    (void)state;
    enum { N = 1000, STREAMS = 3 };
    float *x = malloc(sizeof(float) * STREAMS * N);
    uint32_t seed = 41;
    for (int i = 0; i < N; ++i) {
        x[i] = 0.4f + 0.2f * uniform(&seed);
        x[N + i] = i == 617 ? 5e4f : 0.4f + 0.2f * uniform(&seed);
        x[2 * N + i] = 1e6f + 1732.0508f * (2.0f * uniform(&seed) - 1.0f);
    }
    const int set_counts[] = {21, 20};
    const int want_mean[STREAMS] = {1, 0, 1};
    for (int k = 0; k < 2; ++k) {
        EstimatorSettings s = sample_settings(PASS_BIT(PASS_MEAN_OR_MON), NULL, 0);
        s.set_count = set_counts[k];
        s.first_sample = 5;
        const size_t planes = film_sample_planes(&s), sets = accumulator_planes((uint32_t)s.set_count);
        uint64_t *st = calloc(planes * STREAMS, sizeof(uint64_t)), *acc = calloc(sets * STREAMS, sizeof(uint64_t));
        for (int p = 0; p < STREAMS; ++p)
            add_grey_stream(&s, x + p * N, N, st, acc, (size_t)p, STREAMS);
        float chosen[STREAMS][3], mean[STREAMS][3], mon[STREAMS][3];
        EstimatorImages images, set_images;
        memset(&images, 0, sizeof images);
        memset(&set_images, 0, sizeof set_images);
        images.pass[PASS_MEAN_OR_MON] = chosen;
        set_images.pass[PASS_MEAN] = mean;
        set_images.pass[PASS_MON] = mon;
        images.length = set_images.length = STREAMS * 3;
        assert_int_equal(film_sample_estimate(&s, st, planes * STREAMS, acc, STREAMS, N, &images, NULL, 0),
                         ESTIMATOR_OK);
        EstimatorSettings set_based = s;
        set_based.passes = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_MON);
        set_based.params.clamp_level_count = 1; /* the defaults' count, which sample_settings cleared */
        assert_int_equal(estimator_from_accumulators(&set_based, acc, sets * STREAMS, STREAMS, N, &set_images, NULL, 0),
                         ESTIMATOR_OK);
        for (int p = 0; p < STREAMS; ++p) {
            ReferenceMeanOrMon r = reference_mean_or_mon(x + p * N, N, s.set_count, s.first_sample);
            double mean_width, mon_width;
            PixelSetMeans means;
            pixel_set_means(acc, (uint32_t)s.set_count, (uint64_t)p, STREAMS, s.first_sample, N, &means);
            assert_true(mean_or_mon_half_widths(st, acc, &means, (uint64_t)p, STREAMS, film_sample_passes(&s), 0,
                                                s.params.zirr_k, (uint32_t)s.set_count, N, &mean_width, &mon_width));
            printf("  M %d, stream %d: half-widths mean %.12g (reference %.12Lg), MoN %.12g (%.12Lg); %s %.9g "
                   "(reference %.9Lg)\n",
                   s.set_count, p, mean_width, r.mean_width, mon_width, r.mon_width, r.chose_mean ? "mean" : "MoN",
                   chosen[p][0], r.value);
            assert_int_equal(r.chose_mean, want_mean[p]);
            assert_int_equal(mean_width <= mon_width, want_mean[p]);
            /* d = x - c, d^2 and the sums in double. */
            const long double tolerance = 1e-10L;
            assert_true(fabsl(mean_width - r.mean_width) <= tolerance * r.mean_width);
            assert_true(fabsl(mon_width - r.mon_width) <= tolerance * r.mon_width);
            assert_true(fabsl(chosen[p][0] - r.value) <= 1e-6L * fabsl(r.value));
            assert_memory_equal(chosen[p], want_mean[p] ? mean[p] : mon[p], sizeof chosen[p]);
        }
        free(st);
        free(acc);
    }
    free(x);
}

static RenderSettings glass_settings(uint32_t passes)
{
    RenderSettings s;
    render_settings_default(&s);
    s.estimator.set_count = 5;
    s.estimator.passes = passes;
    s.sample_count = 19;
    s.seed = 3;
    return s;
}

static void render_glass(const RenderSettings *s, RenderOutput *out)
{
    char error[2048];
    if (renderer_run(&test_device, 1, &glass, s, out, error, sizeof error) != RENDER_OK)
        fail_msg("renderer: %s", error);
}

static size_t glass_pixels(const RenderOutput *out)
{
    return (size_t)out->width * out->height;
}

/* clamp at V = infinity is the mean of the same samples (one set: only the
 * mean among the set-based passes) bit for bit. */
static void test_clamp_infinity_is_the_mean(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    RenderSettings s = glass_settings(PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_CLAMP));
    s.estimator.params.clamp_level_count = 2;
    s.estimator.params.clamp_levels[0] = INFINITY;
    s.estimator.params.clamp_levels[1] = 1.0f;
    RenderOutput out;
    render_glass(&s, &out);
    assert_int_equal(out.set_count, 1);
    const size_t values = glass_pixels(&out) * 3;
    assert_memory_equal(out.pass[PASS_MEAN], out.pass[PASS_CLAMP], values * sizeof(float));
    /* V = 1 clamps the light and the caustics. */
    const float *clamped = (const float *)out.pass[PASS_CLAMP] + values;
    int below = 0;
    for (size_t i = 0; i < values; ++i) {
        assert_true(clamped[i] <= ((const float *)out.pass[PASS_MEAN])[i]);
        below += clamped[i] < ((const float *)out.pass[PASS_MEAN])[i];
    }
    assert_true(below > 0);
    assert_int_equal(out.sample_bytes_per_pixel, accumulator_planes(2) * sizeof(uint64_t));
    render_output_free(&out);
}

/* Requesting the per-sample passes changes no set sum and no set-based
 * estimate; their images do not depend on how passes batch samples. */
static void test_sets_unchanged_and_batching(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t set_based = PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_MON) | PASS_BIT(PASS_GMON);
    RenderSettings plain = glass_settings(set_based);
    RenderSettings with = glass_settings(set_based | PASSES_SAMPLE);
    with.estimator.params.clamp_sum_direct = 5.0f;
    with.estimator.params.clamp_sum_indirect = 1.0f;
    RenderSettings batched = with;
    batched.seconds_per_pass = 1e-6; /* a sample a pass */
    RenderOutput a, b, c;
    render_glass(&plain, &a);
    render_glass(&with, &b);
    render_glass(&batched, &c);
    const size_t pixels = glass_pixels(&a);
    assert_int_equal(a.set_count, b.set_count);
    assert_memory_equal(a.accumulators, b.accumulators,
                        accumulator_planes((uint32_t)a.set_count) * pixels * sizeof(uint64_t));
    for (int p = 0; p < PASS_COUNT; ++p)
        if (set_based & PASS_BIT(p))
            assert_memory_equal(a.pass[p], b.pass[p], pixels * 3 * sizeof(float));
    assert_int_equal(b.bytes_per_pixel, a.bytes_per_pixel + b.sample_bytes_per_pixel);
    assert_non_null(b.pass[PASS_ZIRR]); /* zirr too: its cascades change no set sum either */
    assert_memory_equal(b.pass[PASS_CLAMP], c.pass[PASS_CLAMP], 3 * pixels * 3 * sizeof(float));
    for (int p = PASS_CLAMP_SUM; p < PASS_COUNT; ++p)
        assert_memory_equal(b.pass[p], c.pass[p], pixels * 3 * sizeof(float));
    /* mean-or-mon is, pixel by pixel, the render's mean or its MoN. */
    int chose_mon = 0;
    for (size_t i = 0; i < pixels; ++i) {
        const float *chosen = (const float *)b.pass[PASS_MEAN_OR_MON] + 3 * i;
        const int is_mean = memcmp(chosen, (const float *)b.pass[PASS_MEAN] + 3 * i, 3 * sizeof(float)) == 0;
        const int is_mon = memcmp(chosen, (const float *)b.pass[PASS_MON] + 3 * i, 3 * sizeof(float)) == 0;
        assert_true(is_mean || is_mon);
        chose_mon += !is_mean;
    }
    printf("  mean-or-mon in the render: MoN in %d of %zu pixels\n", chose_mon, pixels);
    render_output_free(&a);
    render_output_free(&b);
    render_output_free(&c);
}

/* Film "maxcomponentvalue" V: the render adds clamp at V; the mean stays
 * unclamped. */
static void test_film_max_component_value(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    glass.constants.film.max_component_value = 0.75f;
    RenderSettings s = glass_settings(PASS_BIT(PASS_MEAN));
    RenderOutput out;
    render_glass(&s, &out);
    glass.constants.film.max_component_value = INFINITY;
    assert_true(out.estimator.passes & PASS_BIT(PASS_CLAMP));
    assert_int_equal(out.estimator.params.clamp_level_count, 1);
    assert_true(out.estimator.params.clamp_levels[0] == 0.75f);
    RenderOutput plain;
    render_glass(&s, &plain);
    const size_t values = glass_pixels(&out) * 3;
    assert_memory_equal(out.pass[PASS_MEAN], plain.pass[PASS_MEAN], values * sizeof(float));
    assert_null(plain.pass[PASS_CLAMP]);
    float largest = 0.0f;
    for (size_t i = 0; i < values; ++i)
        largest = fmaxf(largest, ((const float *)out.pass[PASS_CLAMP])[i]);
    assert_true(largest <= 0.75f);
    render_output_free(&out);
    render_output_free(&plain);
}

/* clamp-sum with no direct threshold and an indirect one far below every
 * value keeps the direct light alone: exactly (to the clamped remainder)
 * what a render of maxdepth 1 sees (emission from the camera, and the
 * first surface's light sample and BSDF sample). */
static void test_clamp_sum_direct_part(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t saved_depth = glass.constants.integrator.max_depth;
    RenderSettings s = glass_settings(PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_CLAMP_SUM));
    s.estimator.params.clamp_sum_direct = 0.0f;
    s.estimator.params.clamp_sum_indirect = 1e-30f;
    RenderOutput full, direct;
    render_glass(&s, &full);
    glass.constants.integrator.max_depth = 1;
    render_glass(&s, &direct);
    glass.constants.integrator.max_depth = saved_depth;
    const size_t values = glass_pixels(&full) * 3;
    const float *part = full.pass[PASS_CLAMP_SUM], *one_bounce = direct.pass[PASS_MEAN], *mean = full.pass[PASS_MEAN];
    double worst = 0.0, indirect = 0.0;
    for (size_t i = 0; i < values; ++i) {
        worst = fmax(worst, fabs((double)part[i] - one_bounce[i]) - 1e-6 * fabs((double)one_bounce[i]));
        indirect += mean[i] - part[i];
    }
    printf("  clamp-sum (indirect clamped away) vs maxdepth 1: worst %.3g; indirect light in the mean %.4g\n", worst,
           indirect / (double)values);
    assert_true(worst <= 1e-25);
    assert_true(indirect / (double)values > 1e-3);
    /* At maxdepth 1 nothing is indirect: clamp-sum is the mean. */
    assert_memory_equal(direct.pass[PASS_CLAMP_SUM], direct.pass[PASS_MEAN], values * sizeof(float));
    render_output_free(&full);
    render_output_free(&direct);
}

/* ------------------------------------------------------------------------
 * zirr
 * ---------------------------------------------------------------------- */

static EstimatorSettings zirr_settings(void)
{
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_ZIRR), NULL, 0);
    s.params.clamp_level_count = 1;
    s.params.clamp_levels[0] = 1.0f;
    return s;
}

static ZirrReferenceParams zirr_reference_params(const EstimatorSettings *s)
{
    ZirrReferenceParams p = {s->params.zirr_k, s->params.zirr_base, s->params.zirr_kappa, s->params.zirr_emin};
    return p;
}

/* Host zirr of an image of RGB streams (n samples a pixel, weight 1). */
static void zirr_of_streams(const EstimatorSettings *s, const float *samples, size_t n, int width, int height,
                            float *image)
{
    const size_t pixels = (size_t)width * height, planes = film_sample_planes(s);
    uint64_t *st = calloc(planes * pixels, sizeof(uint64_t));
    uint64_t *sets = calloc(accumulator_planes(1) * pixels, sizeof(uint64_t));
    for (size_t p = 0; p < pixels; ++p)
        for (size_t i = 0; i < n; ++i) {
            const float *x = samples + (p * n + i) * 3;
            SampleParts sp = parts_of(x[0], x[1], x[2], 0, 0, 0, 0, 0, 0, 1.0f);
            assert_int_not_equal(film_sample_add(s, sets, st, p, pixels, &sp), EST_ADD_NONFINITE);
        }
    assert_int_equal(
        film_sample_estimate_zirr(s, st, planes * pixels, sets, (uint32_t)width, (uint32_t)height, n, image, NULL, 0),
        ESTIMATOR_OK);
    free(st);
    free(sets);
}

/* The worst of |host - reference| / max(|reference|, 1e-3) over an image. */
static double zirr_worst_error(const EstimatorSettings *s, const float *samples, size_t n, int width, int height,
                               float *image, long double *reference)
{
    zirr_of_streams(s, samples, n, width, height, image);
    ZirrReferenceParams rp = zirr_reference_params(s);
    reference_zirr(&rp, samples, n, width, height, reference);
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)width * height * 3; ++i) {
        double scale = fabsl(reference[i]) > 1e-3L ? (double)fabsl(reference[i]) : 1e-3;
        worst = fmax(worst, fabs((double)image[i] - (double)reference[i]) / scale);
    }
    return worst;
}

/* Synthetic streams against the independent reference: a constant (below
 * the first scale, and between two scales), one outlier among constants,
 * and Pareto samples (a 2D image, so that neighbourhoods and borders
 * matter), at the default parameters and at others. */
static void test_zirr_streams_against_reference(void **state)
{
    (void)state;
    enum { N = 400, W = 6, H = 5 };
    float *samples = malloc(sizeof(float) * W * H * N * 3), image[W * H * 3];
    long double reference[W * H * 3];
    EstimatorSettings s = zirr_settings();
    assert_int_equal(estimator_settings_check(&s, NULL, 0), 0);
    assert_int_equal(film_sample_planes(&s), accumulator_planes(6)); /* K = 6 RGB sums and a grid word */

    /* One pixel, constant 3 (split between cascades 0 and 1), then one
     * outlier of 1e4 (cascades 4 and 5) in it. */
    for (int i = 0; i < N * 3; ++i)
        samples[i] = 3.0f;
    double worst = zirr_worst_error(&s, samples, N, 1, 1, image, reference);
    printf("  zirr constant 3: %.9g (reference %.9Lg), worst relative error %.3g\n", (double)image[0], reference[0],
           worst);
    assert_true(worst < 1e-5);
    assert_true(fabsf(image[0] - 3.0f) <= 3.0f * 4e-7f);
    samples[7 * 3] = samples[7 * 3 + 1] = samples[7 * 3 + 2] = 1e4f;
    worst = zirr_worst_error(&s, samples, N, 1, 1, image, reference);
    const double mean = (3.0 * (N - 1) + 1e4) / N;
    printf("  zirr one outlier: %.9g (reference %.9Lg, mean %.9g), worst relative error %.3g\n", (double)image[0],
           reference[0], mean, worst);
    assert_true(worst < 1e-5);
    assert_true(image[0] > 3.0f && image[0] < 0.5 * mean); /* the firefly mostly weighed out */

    /* Pareto (alpha 1.5: infinite variance) in colour, over a 2D image. */
    TestRng rng = test_rng(2018);
    for (int i = 0; i < W * H * N; ++i) {
        const double x = 0.2 * test_pareto(&rng, 1.5);
        samples[i * 3] = (float)x;
        samples[i * 3 + 1] = (float)(0.5 * x);
        samples[i * 3 + 2] = (float)(0.25 * x * test_rng_uniform(&rng));
    }
    const struct {
        int k;
        float base, kappa;
    } variants[] = {{6, 8.0f, 1.0f}, {4, 4.0f, 8.0f}, {8, 2.5f, 0.5f}};
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; ++v) {
        s.params.zirr_k = variants[v].k;
        s.params.zirr_base = variants[v].base;
        s.params.zirr_kappa = variants[v].kappa;
        worst = zirr_worst_error(&s, samples, N, W, H, image, reference);
        double estimate = 0.0, plain = 0.0;
        for (int p = 0; p < W * H; ++p) {
            estimate += image[p * 3];
            for (int i = 0; i < N; ++i)
                plain += samples[((size_t)p * N + (size_t)i) * 3];
        }
        printf("  zirr Pareto K = %d, b = %g, kappa = %g: red %.5g (mean %.5g), worst relative error %.3g\n",
               variants[v].k, (double)variants[v].base, (double)variants[v].kappa, estimate / (W * H),
               plain / (W * H * N), worst);
        assert_true(worst < 1e-4);
        assert_true(estimate / (W * H) < plain / (W * H * N)); /* it reweights the tail down */
    }
    free(samples);
}

/* A firefly-free constant image estimates to that constant, on every
 * pixel (also the borders): exactly below the first scale, to rounding
 * between two. */
static void test_zirr_constant_image(void **state)
{
    (void)state;
    enum { N = 64, W = 5, H = 4 };
    EstimatorSettings s = zirr_settings();
    float samples[W * H * N * 3], image[W * H * 3];
    const float values[] = {0.5f, 3.0f, 100.0f};
    for (size_t v = 0; v < sizeof values / sizeof values[0]; ++v) {
        for (int i = 0; i < W * H * N * 3; ++i)
            samples[i] = values[v];
        zirr_of_streams(&s, samples, N, W, H, image);
        for (int i = 0; i < W * H * 3; ++i) {
            if (values[v] <= 1.0f)
                assert_true(image[i] == values[v]);
            else
                assert_true(fabsf(image[i] - values[v]) <= values[v] * 1e-6f);
        }
    }
}

/* Random colour streams with fireflies, negative filter weights and
 * non-finite samples over a 2D image: the kernel's cascades and its zirr
 * image equal the host's bit for bit. */
static void test_zirr_kernel_equals_host(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    EstimatorSettings s = zirr_settings();
    s.passes |= PASS_BIT(PASS_CLAMP); /* zirr's block after another */
    s.params.zirr_base = 5.0f;
    s.params.zirr_kappa = 2.0f;
    enum { W = 9, H = 7, PIXELS = W * H, LENGTH = 33 };
    float *parts = malloc(sizeof(float) * PIXELS * LENGTH * 10);
    uint32_t seed = 4242;
    for (int i = 0; i < PIXELS * LENGTH; ++i) {
        float *p = parts + i * 10;
        for (int c = 0; c < 3; ++c) {
            p[c] = uniform(&seed) * (uniform(&seed) < 0.04f ? 3e4f : 2.0f);
            p[3 + c] = p[6 + c] = 0.0f;
        }
        p[9] = uniform(&seed) < 0.1f ? -0.5f : 0.5f + uniform(&seed);
        if (i % 89 == 3)
            p[2] = INFINITY;
    }
    const size_t planes = film_sample_planes(&s), set_planes = accumulator_planes(1);
    uint64_t *host = calloc(planes * PIXELS, sizeof(uint64_t)), *device = calloc(planes * PIXELS, sizeof(uint64_t));
    uint64_t *host_sets = calloc(set_planes * PIXELS, sizeof(uint64_t));
    uint64_t *device_sets = calloc(set_planes * PIXELS, sizeof(uint64_t));
    for (int pixel = 0; pixel < PIXELS; ++pixel)
        for (int i = 0; i < LENGTH; ++i) {
            const float *p = parts + ((size_t)pixel * LENGTH + (size_t)i) * 10;
            SampleParts sp = parts_of(p[0], p[1], p[2], 0, 0, 0, 0, 0, 0, p[9]);
            film_sample_add(&s, host_sets, host, (size_t)pixel, PIXELS, &sp);
        }
    float clamp_image[PIXELS][3], host_image[PIXELS][3], device_image[PIXELS][3];
    EstimatorImages di;
    memset(&di, 0, sizeof di);
    di.pass[PASS_CLAMP] = clamp_image;
    di.length = PIXELS * 3;
    SampleEstimatorProgram *program = sample_estimator_program_new(&test_device, &s, NULL);
    assert_non_null(program);
    assert_int_equal(sample_estimator_program_run_stream(program, parts, LENGTH, PIXELS, device_sets, device, &di), 0);
    assert_memory_equal(host_sets, device_sets, set_planes * PIXELS * sizeof(uint64_t));
    assert_memory_equal(host, device, planes * PIXELS * sizeof(uint64_t));
    assert_int_equal(
        film_sample_estimate_zirr(&s, host, planes * PIXELS, host_sets, W, H, LENGTH, &host_image[0][0], NULL, 0),
        ESTIMATOR_OK);
    assert_int_equal(
        sample_estimator_program_zirr(program, device, device_sets, W, H, LENGTH, &device_image[0][0], NULL), 0);
    assert_memory_equal(host_image, device_image, sizeof host_image);
    /* Not every cascade at full weight: the fireflies are weighed down
     * somewhere (against sum_k B_k, every reliability 1). */
    int lower = 0;
    float *cascade_means = malloc((size_t)PIXELS * s.params.zirr_k * 3 * sizeof(float));
    for (int p = 0; p < PIXELS; ++p) {
        zirr_pixel_means(host + (size_t)sample_block_first_plane(s.passes, 1, SAMPLE_BLOCK_ZIRR) * PIXELS, host_sets, 1,
                         s.params.zirr_k, (uint64_t)p, PIXELS, LENGTH, cascade_means);
        float all = 0.0f;
        for (int k = 0; k < s.params.zirr_k; ++k)
            all += cascade_means[((size_t)p * s.params.zirr_k + k) * 3];
        lower += host_image[p][0] < 0.5f * all;
    }
    free(cascade_means);
    printf("  zirr kernel == host on %dx%d; %d pixels below half their unweighted cascades\n", W, H, lower);
    assert_true(lower > 0);
    sample_estimator_program_destroy(program);
    free(parts);
    free(host);
    free(device);
    free(host_sets);
    free(device_sets);
}

/* A render with zirr the only per-sample pass: 296 B a pixel at K = 6;
 * the image is finite and no brighter than the mean in total; with few
 * samples the dim pixels' cascade 0 counts fewer than kappa + 1 samples
 * (a sample of luminance l counts l / s_0) and is weighed down, less so
 * with more samples. At 19 spp the ratio to the mean ranged 0.25-0.57
 * over seeds 1-6 and the three samplers: it is bounded below by 0.15. */
static void test_zirr_render(void **state)
{
    (void)state;
    REQUIRE_TEST_DEVICE();
    const uint32_t spp[2] = {19, 256};
    double ratio[2];
    for (int run = 0; run < 2; ++run) {
        RenderSettings s = glass_settings(PASS_BIT(PASS_MEAN) | PASS_BIT(PASS_ZIRR));
        s.sample_count = spp[run];
        RenderOutput out;
        render_glass(&s, &out);
        assert_int_equal(out.sample_bytes_per_pixel, 296);
        const size_t values = glass_pixels(&out) * 3;
        const float *zirr = out.pass[PASS_ZIRR], *mean = out.pass[PASS_MEAN];
        double total = 0.0, plain = 0.0;
        for (size_t i = 0; i < values; ++i) {
            assert_true(isfinite(zirr[i]));
            total += zirr[i];
            plain += mean[i];
        }
        ratio[run] = total / plain;
        printf("  zirr render at %u spp: image mean %.5g, the mean's %.5g (ratio %.3f)\n", spp[run],
               total / (double)values, plain / (double)values, ratio[run]);
        assert_true(ratio[run] <= 1.0001 && ratio[run] > 0.15);
        render_output_free(&out);
    }
    assert_true(ratio[1] > ratio[0]);
}

/* Splats (bdpt, lightpath) on the host reference, as add_splats adds them
 * (film_sample_add_splat): each a sample of value its RGB and weight 1 to
 * clamp (clamped by each level, as pbrt-v4's RGBFilm::AddSplat clamps
 * splats) and to zirr's cascades; n stays the camera samples. Two camera
 * samples and three splats of one pixel, sums known by hand; the estimates
 * do not depend on the order the values come in; zirr's cascades split
 * each value, so their means add up to the mean. */
static void test_splats_hand_computed(void **state)
{
    (void)state;
    const float levels[] = {1.0f, INFINITY};
    EstimatorSettings s = sample_settings(PASS_BIT(PASS_CLAMP) | PASS_BIT(PASS_ZIRR), levels, 2);
    s.set_count = 2;
    assert_int_equal(estimator_settings_check(&s, NULL, 0), 0);
    const size_t planes = film_sample_planes(&s), set_planes = accumulator_planes(2);
    uint64_t *sums[2], *sets[2];
    const float splats[3][3] = {{4.0f, 2.0f, 1.0f}, {0.5f, 0.5f, 0.5f}, {16.0f, 8.0f, 16.0f}};
    const uint32_t splat_sets[3] = {0, 1, 1};
    const SampleParts camera[2] = {
        parts_in_set(parts_of(0.5f, 0.25f, 0.125f, 0, 0, 0, 0.5f, 0.25f, 0.125f, 1.0f), 0, 2),
        parts_in_set(parts_of(0.25f, 0.25f, 0.25f, 0, 0, 0, 0.25f, 0.25f, 0.25f, 1.0f), 1, 2)};
    for (int order = 0; order < 2; ++order) {
        sums[order] = calloc(planes, sizeof(uint64_t));
        sets[order] = calloc(set_planes, sizeof(uint64_t));
        for (int k = 0; k < 5; ++k) {
            const int i = order ? 4 - k : k; /* camera samples, then splats; or reversed */
            if (i < 2)
                assert_int_equal(film_sample_add(&s, sets[order], sums[order], 0, 1, &camera[i]), EST_ADD_EXACT);
            else
                assert_int_equal(
                    film_sample_add_splat(&s, sets[order], sums[order], 0, 1, splat_sets[i - 2], 2, splats[i - 2]),
                    EST_ADD_EXACT);
        }
    }
    /* The sums' grids may differ by order (until normalized), their
     * values and so the estimates not. */
    float clamp[2][3], clamp_reversed[2][3], zirr_reversed[3];
    EstimatorImages images;
    memset(&images, 0, sizeof images);
    images.pass[PASS_CLAMP] = clamp_reversed;
    images.length = 3;
    assert_int_equal(film_sample_estimate(&s, sums[1], planes, sets[1], 1, 2, &images, NULL, 0), ESTIMATOR_OK);
    images.pass[PASS_CLAMP] = clamp;
    assert_int_equal(film_sample_estimate(&s, sums[0], planes, sets[0], 1, 2, &images, NULL, 0), ESTIMATOR_OK);
    assert_memory_equal(clamp, clamp_reversed, sizeof clamp);
    assert_int_equal(film_sample_estimate_zirr(&s, sums[1], planes, sets[1], 1, 1, 2, zirr_reversed, NULL, 0),
                     ESTIMATOR_OK);
    /* V = 1: (4, 2, 1) by 1/4, (16, 8, 16) by 1/16, the rest as they are. */
    const float expected[2][3] = {{3.25f, 2.0f, 2.125f}, {21.25f, 11.0f, 17.875f}};
    for (int level = 0; level < 2; ++level)
        for (int c = 0; c < 3; ++c)
            assert_true(clamp[level][c] == expected[level][c] / 2.0f);
    float zirr_image[3];
    assert_int_equal(film_sample_estimate_zirr(&s, sums[0], planes, sets[0], 1, 1, 2, zirr_image, NULL, 0),
                     ESTIMATOR_OK);
    float means[EST_ZIRR_CASCADES_MAX * 3];
    zirr_pixel_means(film_sample_zirr_block(&s, sums[0], 1), sets[0], 2, s.params.zirr_k, 0, 1, 2, means);
    for (int c = 0; c < 3; ++c) {
        double total = 0.0;
        for (int k = 0; k < s.params.zirr_k; ++k)
            total += means[k * 3 + c];
        assert_true(fabs(total - expected[1][c] / 2.0) <= 1e-5 * expected[1][c]);
        assert_true(isfinite(zirr_image[c]) && zirr_image[c] <= expected[1][c] / 2.0f * 1.0001f);
        assert_true(zirr_image[c] == zirr_reversed[c]);
    }
    for (int order = 0; order < 2; ++order) {
        free(sums[order]);
        free(sets[order]);
    }
}

/* zirr's memory: K = 6 costs 6 RGB sums and a grid word a pixel, and says
 * so in the summary. */
static void test_zirr_memory_summary(void **state)
{
    (void)state;
    EstimatorSettings s = zirr_settings();
    char line[256];
    film_sample_memory_summary(&s, line, sizeof line);
    assert_string_equal(line, "zirr (K = 6 cascades) 296 B");
    assert_int_equal(296, accumulator_planes(6) * sizeof(uint64_t));
    char message[256];
    assert_int_equal(estimator_param_set(&s.params, "zirr.kappa=4", message, sizeof message), 0);
    assert_true(s.params.zirr_kappa == 4.0f);
    assert_int_equal(estimator_param_set(&s.params, "zirr.k=1", message, sizeof message), -1);
    assert_int_equal(estimator_param_set(&s.params, "zirr.k=17", message, sizeof message), -1);
    assert_int_equal(estimator_param_set(&s.params, "zirr.base=1", message, sizeof message), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_computed_stream),
        cmocka_unit_test(test_splats_hand_computed),
        cmocka_unit_test(test_levels_parameter),
        cmocka_unit_test(test_kernel_equals_host),
        cmocka_unit_test(test_clamp_infinity_is_the_mean),
        cmocka_unit_test(test_sets_unchanged_and_batching),
        cmocka_unit_test(test_film_max_component_value),
        cmocka_unit_test(test_clamp_sum_direct_part),
        cmocka_unit_test(test_moments_do_not_cancel),
        cmocka_unit_test(test_abmm_gabmm_against_reference),
        cmocka_unit_test(test_moments_kernel_equals_host),
        cmocka_unit_test(test_zirr_streams_against_reference),
        cmocka_unit_test(test_zirr_constant_image),
        cmocka_unit_test(test_zirr_kernel_equals_host),
        cmocka_unit_test(test_zirr_memory_summary),
        cmocka_unit_test(test_zirr_render),
        cmocka_unit_test(test_square_sums),
        cmocka_unit_test(test_mean_or_mon_against_reference),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
