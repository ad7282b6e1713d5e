#include "family_reference.h"

#include "long_double_reference.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The non-empty sets of one pixel: all that any estimator here depends on. */
typedef struct {
    int m;
    long double sum[REF_CHANNELS][REF_MAX_SETS];
    uint64_t count[REF_MAX_SETS];
} Sets;

/* Each channel's set means, ascending. */
typedef struct {
    int m;
    long double t[REF_CHANNELS][REF_MAX_SETS];
} SortedMeans;

typedef void (*Estimator)(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS]);

void ref_family_params_default(RefFamilyParams *p)
{
    p->amon_alpha = 0.5L;
    p->admon_alpha = 0.5L;
    p->gmon_binary_threshold = 0.25L;
    p->gmon_partial_threshold = 0.25L;
    p->dmon_partial_threshold = 0.25L;
    p->gmon_partial_alpha = 0.5L;
    p->dmon_partial_alpha = 0.5L;
    p->trimmed_c = -1;
    p->winsorized_c = -1;
    p->gmedian_iterations = 0;
    p->huber_k = 1.0L;
}

static int compare_long_double(const void *a, const void *b)
{
    long double x = *(const long double *)a, y = *(const long double *)b;
    return (x > y) - (x < y);
}

static void sort_ascending(long double *values, int count)
{
    qsort(values, (size_t)count, sizeof values[0], compare_long_double);
}

static void sorted_means(const Sets *sets, SortedMeans *out)
{
    out->m = sets->m;
    for (int c = 0; c < REF_CHANNELS; ++c) {
        for (int j = 0; j < sets->m; ++j)
            out->t[c][j] = sets->sum[c][j] / (long double)sets->count[j];
        sort_ascending(out->t[c], sets->m);
    }
}

/* ------------------------------------------------------------------------
 * Pieces on one channel's ascending means t[0 .. m - 1] (0-based here; the
 * spec's t_i is t[i - 1]), k = m / 2.
 * ---------------------------------------------------------------------- */

/* Weights alpha^d by distance d from the median, for d <= max_distance and 0
 * beyond, divided by the sum of the weights. Odd m: the centre is t[k]. Even
 * m: the centre is the middle pair's average, then t[k-1-d] and t[k+d]. The
 * weights are built by multiplication, so alpha^0 = 1 also for alpha = 0. */
static long double weighted_around_median(const long double *t, int m, long double alpha, int max_distance)
{
    int k = m / 2, odd = m % 2;
    int farthest = odd ? k : k - 1;
    if (max_distance < farthest)
        farthest = max_distance;
    long double numerator = odd ? t[k] : (t[k - 1] + t[k]) / 2.0L, weights = 1.0L, weight = 1.0L;
    for (int d = 1; d <= farthest; ++d) {
        weight *= alpha;
        numerator += weight * (t[k - d - (odd ? 0 : 1)] + t[k + d]);
        weights += 2.0L * weight;
    }
    return numerator / weights;
}

static long double amon(const long double *t, int m, long double alpha)
{
    return weighted_around_median(t, m, alpha, m);
}

/* Odd m: the mean of the median and its u = floor(k alpha) neighbours each
 * side. Even m (alpha unused): every set, the middle pair at half weight. */
static long double admon(const long double *t, int m, long double alpha)
{
    int k = m / 2;
    if (m % 2 == 1) {
        int u = (int)floorl((long double)k * alpha);
        u = u < 0 ? 0 : (u > k ? k : u);
        return ldref_trimmed_mean(t, m, k - u);
    }
    long double others = 0.0L;
    for (int i = 0; i < m; ++i)
        if (i != k - 1 && i != k)
            others += t[i];
    return (others + (t[k - 1] + t[k]) / 2.0L) / (long double)(m - 1);
}

static long double mean_of_set_means(const long double *t, int m)
{
    return ldref_trimmed_mean(t, m, 0);
}

/* A user's trim count (-1: floor(m / 4)), clamped to [0, floor((m - 1) / 2)]. */
static int trim_count(int requested, int m)
{
    int c = requested < 0 ? m / 4 : requested, most = (m - 1) / 2;
    return c > most ? most : c;
}

static long double winsorized(const long double *t, int m, int c)
{
    long double sum = 0.0L;
    for (int i = 0; i < m; ++i)
        sum += t[i < c ? c : (i > m - 1 - c ? m - 1 - c : i)];
    return sum / (long double)m;
}

/* The authors' Gini: means shifted by -t_1 when t_1 < 0, plus 1e-11 each,
 * in the textbook formula G' = sum_i (2i - m - 1) t'_i / (m sum_i t'_i), on
 * ascending t. The numerator does not change when every value moves by the
 * same amount (its coefficients sum to 0), so it is taken on t itself: t'
 * would lose means far below 1e-11 even in long double. */
static long double authors_gini(const long double *t, int m)
{
    long double numerator = 0.0L, total = 0.0L;
    for (int i = 0; i < m; ++i) {
        numerator += (long double)(2 * i + 1 - m) * t[i]; /* 2 (i + 1) - m - 1 */
        total += (t[0] < 0.0L ? t[i] - t[0] : t[i]) + 1e-11L;
    }
    long double g = numerator / ((long double)m * total);
    if (m < 2 || !isfinite(g) || total == 0.0L)
        return 0.0L;
    return g < 0.0L ? 0.0L : (g > 1.0L ? 1.0L : g);
}

/* pakmon's normalised entropy H of d_j = sum_{i<j} (s_i - Sbar)^2 / (j + 1),
 * j = 2 .. m - 1, on one channel's ascending set means s (the authors' code
 * takes the set sums: the same H when every set holds as many samples, H
 * being scale invariant; the means when some hold one more). */
static long double pakmon_entropy(const long double *s, int m)
{
    if (m <= 3)
        return 0.0L; /* ln(m - 2) <= 0 */
    long double mean = 0.0L;
    for (int i = 0; i < m; ++i)
        mean += s[i];
    mean /= (long double)m;
    long double d[REF_MAX_SETS], squares = (s[0] - mean) * (s[0] - mean), total = 0.0L;
    for (int j = 2; j <= m - 1; ++j) {
        squares += (s[j - 1] - mean) * (s[j - 1] - mean); /* now over i = 0 .. j - 1 */
        d[j] = squares / (long double)(j + 1);
        total += d[j] * d[j];
    }
    if (total == 0.0L || !isfinite(total))
        return 0.0L;
    long double entropy = 0.0L;
    for (int j = 2; j <= m - 1; ++j) {
        long double p = d[j] * d[j] / total;
        if (p > 0.0L)
            entropy -= p * logl(p);
    }
    long double h = entropy / logl((long double)(m - 2));
    return h < 0.0L ? 0.0L : (h > 1.0L ? 1.0L : h);
}

/* ------------------------------------------------------------------------
 * The estimators, each on the sets of one pixel.
 * ---------------------------------------------------------------------- */

static long double gini_bar(const SortedMeans *s)
{
    long double g = 0.0L;
    for (int c = 0; c < REF_CHANNELS; ++c)
        g += ldref_gini(s->t[c], s->m);
    return g / (long double)REF_CHANNELS;
}

static void estimate_mean(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    long double samples = 0.0L;
    for (int j = 0; j < sets->m; ++j)
        samples += (long double)sets->count[j];
    for (int c = 0; c < REF_CHANNELS; ++c) {
        long double total = 0.0L;
        for (int j = 0; j < sets->m; ++j)
            total += sets->sum[c][j];
        out[c] = total / samples;
    }
}

static void estimate_mon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    SortedMeans s;
    sorted_means(sets, &s);
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = ldref_median(s.t[c], s.m);
}

static void estimate_gmon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    SortedMeans s;
    sorted_means(sets, &s);
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = ldref_trimmed_mean(s.t[c], s.m, ldref_trim_count(ldref_gini(s.t[c], s.m), s.m));
}

/* A rule with one alpha, e.g. amon or admon, on every channel of a pixel. */
typedef long double (*AlphaRule)(const long double *t, int m, long double alpha);

static void each_channel(const SortedMeans *s, AlphaRule rule, long double alpha, long double out[REF_CHANNELS])
{
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = rule(s->t[c], s->m, alpha);
}

static void estimate_amon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    each_channel(&s, amon, p->amon_alpha, out);
}

static void estimate_admon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    each_channel(&s, admon, p->admon_alpha, out);
}

static void estimate_ggmon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    SortedMeans s;
    sorted_means(sets, &s);
    each_channel(&s, amon, 1.0L - gini_bar(&s), out);
}

static void estimate_gmon_binary(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    int below = gini_bar(&s) < p->gmon_binary_threshold;
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = below ? mean_of_set_means(s.t[c], s.m) : ldref_median(s.t[c], s.m);
}

static void estimate_gmon_partial(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    each_channel(&s, amon, gini_bar(&s) < p->gmon_partial_threshold ? 1.0L : p->gmon_partial_alpha, out);
}

static void estimate_dmon_partial(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    each_channel(&s, admon, gini_bar(&s) < p->dmon_partial_threshold ? 1.0L : p->dmon_partial_alpha, out);
}

/* Odd m trims ceil(k G'bar) per side; even m never trims. */
static void estimate_gmon_authors(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    SortedMeans s;
    sorted_means(sets, &s);
    int m = s.m, k = m / 2;
    long double g = 0.0L;
    for (int c = 0; c < REF_CHANNELS; ++c)
        g += authors_gini(s.t[c], m);
    g /= (long double)REF_CHANNELS;
    int trim = 0;
    if (m % 2 == 1) {
        trim = (int)ceill((long double)k * g);
        trim = trim < 0 ? 0 : (trim > k ? k : trim);
    }
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = ldref_trimmed_mean(s.t[c], m, trim);
}

/* The entropy and the weighted mean both come from the sorted means;
 * floor(0.15 m) in integers, as exact as the rest. */
static void estimate_pakmon(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    (void)p;
    SortedMeans s;
    sorted_means(sets, &s);
    int m = s.m, k = m / 2, farthest = m % 2 == 1 ? k : k - 1;
    for (int c = 0; c < REF_CHANNELS; ++c) {
        long double h = pakmon_entropy(s.t[c], m);
        int rho = (int)floorl((long double)k * h) - 15 * m / 100;
        rho = rho < 0 ? 0 : (rho > farthest ? farthest : rho);
        out[c] = weighted_around_median(s.t[c], m, h, rho);
    }
}

static void estimate_trimmed(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = ldref_trimmed_mean(s.t[c], s.m, trim_count(p->trimmed_c, s.m));
}

static void estimate_winsorized(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = winsorized(s.t[c], s.m, trim_count(p->winsorized_c, s.m));
}

/* Huber's M-estimator (docs/estimators.md, "huber"): from the median, a
 * fixed number of reweighted means, weight 1 within h = k (t_{m-q} -
 * t_{q+1}), q = floor(m / 4), of the estimate and h / distance beyond. */
#define HUBER_STEPS 8

static long double huber(const long double *t, int m, long double k)
{
    int q = m / 4;
    long double h = k * (t[m - 1 - q] - t[q]);
    long double z = ldref_median(t, m);
    for (int step = 0; step < HUBER_STEPS; ++step) {
        long double numerator = 0.0L, weights = 0.0L;
        for (int j = 0; j < m; ++j) {
            long double d = fabsl(t[j] - z), w = d <= h ? 1.0L : h / d;
            numerator += w * t[j];
            weights += w;
        }
        z = numerator / weights;
    }
    return z;
}

static void estimate_huber(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    SortedMeans s;
    sorted_means(sets, &s);
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = huber(s.t[c], s.m, p->huber_k);
}

/* Steps stop shrinking at long double's rounding (cycles with relative steps
 * of about 1.5e-19 were seen), so a step of 1e-30 relative is never reached:
 * stop at 8 ulp (8.7e-19) instead. On 200 heavy-tailed pixels (M = 21) this
 * agrees with 10000 iterations to 3e-17 relative, 80 times faster. */
#define WEISZFELD_ITERATIONS 10000
#define WEISZFELD_RELATIVE_STEP (8.0L * LDBL_EPSILON)

static long double distance(const long double a[REF_CHANNELS], const long double b[REF_CHANNELS])
{
    long double squares = 0.0L;
    for (int c = 0; c < REF_CHANNELS; ++c)
        squares += (a[c] - b[c]) * (a[c] - b[c]);
    return sqrtl(squares);
}

/* Weiszfeld iterations from the componentwise median. Sets at distance 0
 * from z get weight 0 in a step. Without more, a minimiser that IS a set
 * mean is never kept: z reaches it, the step then ignores it and jumps away.
 * So at a set mean z stops when it is the minimiser: the unit vectors toward
 * the other sets sum to a length of at most the number of sets at z (0 is in
 * the subgradient there). */
/* Weiszfeld's iteration for the geometric median of `points` from z: to
 * convergence (steps = 0), stopping at a set mean that is the minimiser,
 * or exactly `steps` steps of Vardi and Zhang's modification (Proc. Natl.
 * Acad. Sci. 97, 2000): with eta points at z and R the sum of the unit
 * vectors from z to the others, z moves to (1 - eta / |R|)^+ T + min(1,
 * eta / |R|) z, T the others' Weiszfeld mean. */
static void weiszfeld(long double points[][REF_CHANNELS], int m, int steps, long double z[REF_CHANNELS])
{
    static const long double origin[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
    int limit = steps > 0 ? steps : WEISZFELD_ITERATIONS;
    for (int iteration = 0; iteration < limit; ++iteration) {
        long double weighted[REF_CHANNELS] = {0.0L, 0.0L, 0.0L}, pull[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
        long double weights = 0.0L;
        int at_z = 0;
        for (int j = 0; j < m; ++j) {
            long double d = distance(points[j], z);
            if (d == 0.0L) {
                ++at_z;
                continue;
            }
            for (int c = 0; c < REF_CHANNELS; ++c) {
                weighted[c] += points[j][c] / d;
                pull[c] += (points[j][c] - z[c]) / d;
            }
            weights += 1.0L / d;
        }
        long double r = distance(pull, origin);
        if (weights == 0.0L || (at_z > 0 && r <= (long double)at_z)) {
            if (steps > 0)
                continue; /* stays */
            break;
        }
        long double next[REF_CHANNELS], keep = at_z > 0 ? (long double)at_z / r : 0.0L;
        for (int c = 0; c < REF_CHANNELS; ++c)
            next[c] = (1.0L - keep) * (weighted[c] / weights) + keep * z[c];
        long double step = distance(next, z);
        memcpy(z, next, sizeof next);
        if (steps == 0 && step <= WEISZFELD_RELATIVE_STEP * distance(z, origin))
            break;
    }
}

static void set_means(const Sets *sets, long double points[][REF_CHANNELS])
{
    for (int j = 0; j < sets->m; ++j)
        for (int c = 0; c < REF_CHANNELS; ++c)
            points[j][c] = sets->sum[c][j] / (long double)sets->count[j];
}

static void estimate_gmedian(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    long double points[REF_MAX_SETS][REF_CHANNELS], z[REF_CHANNELS];
    set_means(sets, points);
    estimate_mon(p, sets, z);
    weiszfeld(points, sets->m, p->gmedian_iterations, z);
    memcpy(out, z, sizeof z);
}

/* gmedian's jackknife with a fixed step count: each leave-one-out estimate
 * restarts from the estimate of all sets, for a quarter of the steps. */
static void gmedian_jackknife_fixed(const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    int m = sets->m, steps = p->gmedian_iterations / 4 > 1 ? p->gmedian_iterations / 4 : 1;
    long double points[REF_MAX_SETS][REF_CHANNELS], full[REF_CHANNELS], leave_out[REF_MAX_SETS][REF_CHANNELS];
    set_means(sets, points);
    estimate_gmedian(p, sets, full);
    long double average[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
    for (int j = 0; j < m; ++j) {
        long double rest[REF_MAX_SETS][REF_CHANNELS];
        for (int i = 0, k = 0; i < m; ++i)
            if (i != j)
                memcpy(rest[k++], points[i], sizeof points[i]);
        memcpy(leave_out[j], full, sizeof full);
        weiszfeld(rest, m - 1, steps, leave_out[j]);
        for (int c = 0; c < REF_CHANNELS; ++c)
            average[c] += leave_out[j][c] / (long double)m;
    }
    for (int c = 0; c < REF_CHANNELS; ++c) {
        long double squares = 0.0L;
        for (int j = 0; j < m; ++j)
            squares += (leave_out[j][c] - average[c]) * (leave_out[j][c] - average[c]);
        out[c] = sqrtl((long double)(m - 1) / (long double)m * squares);
    }
}

typedef struct {
    const char *name;
    Estimator estimate;
} NamedEstimator;

static const NamedEstimator estimators[] = {
    {"mean", estimate_mean},
    {"mon", estimate_mon},
    {"gmon", estimate_gmon},
    {"amon", estimate_amon},
    {"admon", estimate_admon},
    {"ggmon", estimate_ggmon},
    {"gmon-binary", estimate_gmon_binary},
    {"gmon-partial", estimate_gmon_partial},
    {"dmon-partial", estimate_dmon_partial},
    {"gmon-authors", estimate_gmon_authors},
    {"pakmon", estimate_pakmon},
    {"trimmed", estimate_trimmed},
    {"winsorized", estimate_winsorized},
    {"gmedian", estimate_gmedian},
    {"huber", estimate_huber},
};

static Estimator find_estimator(const char *name)
{
    for (size_t i = 0; i < sizeof estimators / sizeof estimators[0]; ++i)
        if (strcmp(estimators[i].name, name) == 0)
            return estimators[i].estimate;
    return NULL;
}

/* The non-empty sets of sums laid out by round robin; 0 if set_count is
 * outside 1..64. */
static int gather_sets(float sums[REF_CHANNELS][REF_MAX_SETS], uint64_t sample_count, int set_count, Sets *out)
{
    if (set_count < 1 || set_count > REF_MAX_SETS)
        return 0;
    out->m = 0;
    for (int j = 0; j < set_count; ++j) {
        uint64_t n_j = ldref_set_samples(sample_count, set_count, j);
        if (n_j == 0)
            continue;
        for (int c = 0; c < REF_CHANNELS; ++c)
            out->sum[c][out->m] = isfinite(sums[c][j]) ? (long double)sums[c][j] : 0.0L;
        out->count[out->m++] = n_j;
    }
    return 1;
}

static void fill_nan(long double out[REF_CHANNELS])
{
    for (int c = 0; c < REF_CHANNELS; ++c)
        out[c] = (long double)NAN;
}

static void jackknife(Estimator estimate, const RefFamilyParams *p, const Sets *sets, long double out[REF_CHANNELS])
{
    int m = sets->m;
    long double leave_out[REF_MAX_SETS][REF_CHANNELS], average[REF_CHANNELS] = {0.0L, 0.0L, 0.0L};
    for (int j = 0; j < m; ++j) {
        Sets rest = {.m = 0};
        for (int i = 0; i < m; ++i) {
            if (i == j)
                continue;
            for (int c = 0; c < REF_CHANNELS; ++c)
                rest.sum[c][rest.m] = sets->sum[c][i];
            rest.count[rest.m++] = sets->count[i];
        }
        estimate(p, &rest, leave_out[j]);
        for (int c = 0; c < REF_CHANNELS; ++c)
            average[c] += leave_out[j][c];
    }
    for (int c = 0; c < REF_CHANNELS; ++c) {
        average[c] /= (long double)m;
        long double squares = 0.0L;
        for (int j = 0; j < m; ++j)
            squares += (leave_out[j][c] - average[c]) * (leave_out[j][c] - average[c]);
        out[c] = sqrtl((long double)(m - 1) / (long double)m * squares);
    }
}

/* sqrt(m / (m - 1) * sum_j (n_j (t_j - mu))^2) / n: with equal counts,
 * sd(set means) / sqrt(m). */
static void mean_stderr(const Sets *sets, long double out[REF_CHANNELS])
{
    long double mu[REF_CHANNELS], samples = 0.0L;
    estimate_mean(NULL, sets, mu);
    for (int j = 0; j < sets->m; ++j)
        samples += (long double)sets->count[j];
    for (int c = 0; c < REF_CHANNELS; ++c) {
        long double squares = 0.0L;
        for (int j = 0; j < sets->m; ++j) {
            long double n_j = (long double)sets->count[j];
            long double deviation = n_j * (sets->sum[c][j] / n_j - mu[c]);
            squares += deviation * deviation;
        }
        out[c] = sqrtl((long double)sets->m / (long double)(sets->m - 1) * squares) / samples;
    }
}

typedef enum { ESTIMATE, STANDARD_ERROR, JACKKNIFE } Output;

static int evaluate(Output output, const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                    uint64_t sample_count, int set_count, long double out[REF_CHANNELS])
{
    Estimator estimate = find_estimator(name);
    Sets sets;
    if (!estimate || !gather_sets(sums, sample_count, set_count, &sets))
        return -1;
    if (output == ESTIMATE && sets.m == 0)
        memset(out, 0, REF_CHANNELS * sizeof out[0]);
    else if (output == ESTIMATE)
        estimate(p, &sets, out);
    else if (sets.m < 2)
        fill_nan(out);
    else if (output == STANDARD_ERROR && estimate == estimate_mean)
        mean_stderr(&sets, out);
    else if (estimate == estimate_gmedian && p->gmedian_iterations > 0)
        gmedian_jackknife_fixed(p, &sets, out);
    else
        jackknife(estimate, p, &sets, out);
    return 0;
}

int ref_family_estimate(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                        uint64_t sample_count, int set_count, long double out[REF_CHANNELS])
{
    return evaluate(ESTIMATE, name, p, sums, sample_count, set_count, out);
}

int ref_family_stderr(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                      uint64_t sample_count, int set_count, long double out[REF_CHANNELS])
{
    return evaluate(STANDARD_ERROR, name, p, sums, sample_count, set_count, out);
}

int ref_family_jackknife(const char *name, const RefFamilyParams *p, float sums[REF_CHANNELS][REF_MAX_SETS],
                         uint64_t sample_count, int set_count, long double out[REF_CHANNELS])
{
    return evaluate(JACKKNIFE, name, p, sums, sample_count, set_count, out);
}
