#include "long_double_reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint64_t ldref_set_samples(uint64_t n, int set_count, int set)
{
    uint64_t m = (uint64_t)set_count, j = (uint64_t)set;
    if (n <= j)
        return 0;
    return (n - j) / m + ((n - j) % m != 0 ? 1 : 0);
}

static int compare_long_double(const void *a, const void *b)
{
    long double x = *(const long double *)a, y = *(const long double *)b;
    return (x > y) - (x < y);
}

long double ldref_gini(const long double *t, int m)
{
    if (m < 1)
        return 0.0L;
    /* Authors' convention for negative means: shift so the smallest is 0. */
    long double shift = t[0] < 0.0L ? -t[0] : 0.0L;
    long double numerator = 0.0L, total = 0.0L;
    for (int j = 1; j <= m; ++j) {
        long double v = t[j - 1] + shift;
        numerator += (long double)(2 * j - m - 1) * v;
        total += v;
    }
    long double denominator = (long double)m * total;
    if (denominator == 0.0L || !isfinite(denominator))
        return 0.0L;
    long double g = numerator / denominator;
    return g < 0.0L ? 0.0L : (g > 1.0L ? 1.0L : g);
}

int ldref_trim_count(long double gini, int m)
{
    int k = m / 2;
    int c = (int)floorl(gini * (long double)k);
    int most = m >= 1 ? (m - 1) / 2 : 0;
    return c < 0 ? 0 : (c > most ? most : c);
}

long double ldref_trimmed_mean(const long double *values, int m, int c)
{
    if (m < 1)
        return 0.0L;
    long double sum = 0.0L;
    for (int j = c; j <= m - 1 - c; ++j)
        sum += values[j];
    return sum / (long double)(m - 2 * c);
}

long double ldref_median(const long double *values, int m)
{
    if (m < 1)
        return 0.0L;
    if (m % 2 == 1)
        return values[m / 2];
    return (values[m / 2 - 1] + values[m / 2]) / 2.0L;
}

/* Set means of the non-empty sets (in set order) and the plain mean. */
static int set_means(const float *sums, int set_count, uint64_t n, long double *means, long double *mean)
{
    long double total = 0.0L;
    uint64_t samples = 0;
    int m = 0;
    for (int j = 0; j < set_count; ++j) {
        uint64_t n_j = ldref_set_samples(n, set_count, j);
        if (n_j == 0)
            continue;
        long double s = isfinite(sums[j]) ? (long double)sums[j] : 0.0L;
        means[m++] = s / (long double)n_j;
        total += s;
        samples += n_j;
    }
    *mean = samples > 0 ? total / (long double)samples : 0.0L;
    return m;
}

void ldref_channel(const float *sums, int set_count, uint64_t sample_count, LdChannel *out)
{
    memset(out, 0, sizeof *out);
    out->m = set_means(sums, set_count, sample_count, out->sorted, &out->mean);
    qsort(out->sorted, (size_t)out->m, sizeof out->sorted[0], compare_long_double);
    out->median = ldref_median(out->sorted, out->m);
    out->gini = ldref_gini(out->sorted, out->m);
    out->trim = ldref_trim_count(out->gini, out->m);
    out->gmon = ldref_trimmed_mean(out->sorted, out->m, out->trim);
}

/* A set seen by the luminance sort. */
typedef struct {
    long double luminance;
    long double rgb[LDREF_CHANNELS];
} LumaSet;

/* By luminance, ties by r, then g, then b: a total order on set contents,
 * so the result cannot depend on how sets were numbered. */
static int compare_luma_set(const void *a, const void *b)
{
    const LumaSet *x = a, *y = b;
    if (x->luminance != y->luminance)
        return x->luminance < y->luminance ? -1 : 1;
    for (int c = 0; c < LDREF_CHANNELS; ++c)
        if (x->rgb[c] != y->rgb[c])
            return x->rgb[c] < y->rgb[c] ? -1 : 1;
    return 0;
}

void ldref_pixel(const float *set_sums, size_t pixel_count, size_t pixel, int set_count, uint64_t sample_count,
                 GiniMode mode, LdPixel *out)
{
    memset(out, 0, sizeof *out);
    long double in_set_order[LDREF_CHANNELS][LDREF_MAX_SETS];
    for (int c = 0; c < LDREF_CHANNELS; ++c) {
        float sums[LDREF_MAX_SETS];
        for (int j = 0; j < set_count; ++j)
            sums[j] = set_sums[((size_t)j * LDREF_CHANNELS + (size_t)c) * pixel_count + pixel];
        LdChannel *ch = &out->channel[c];
        ldref_channel(sums, set_count, sample_count, ch);
        long double unused_mean;
        set_means(sums, set_count, sample_count, in_set_order[c], &unused_mean);
        out->m = ch->m;
        memcpy(out->ordered[c], ch->sorted, sizeof ch->sorted);
        out->mean[c] = ch->mean;
        out->mon[c] = ch->median;
        out->gmon[c] = ch->gmon;
        out->gini[c] = ch->gini;
        out->trim[c] = ch->trim;
        out->lowest[c] = ch->m > 0 ? ch->sorted[0] : 0.0L;
        out->highest[c] = ch->m > 0 ? ch->sorted[ch->m - 1] : 0.0L;
    }
    int m = out->m;

    if (mode == GINI_PER_PIXEL) {
        long double g = (out->gini[0] + out->gini[1] + out->gini[2]) / 3.0L;
        for (int c = 0; c < LDREF_CHANNELS; ++c) {
            out->gini[c] = g;
            out->trim[c] = ldref_trim_count(g, m);
            out->gmon[c] = ldref_trimmed_mean(out->ordered[c], m, out->trim[c]);
        }
    } else if (mode == SORT_BY_LUMINANCE) {
        /* Rec. 709 luminance; whole RGB sets are ordered and trimmed. */
        static const long double weight[LDREF_CHANNELS] = {0.2126L, 0.7152L, 0.0722L};
        LumaSet sets[LDREF_MAX_SETS];
        for (int j = 0; j < m; ++j) {
            sets[j].luminance = 0.0L;
            for (int c = 0; c < LDREF_CHANNELS; ++c) {
                sets[j].rgb[c] = in_set_order[c][j];
                sets[j].luminance += weight[c] * in_set_order[c][j];
            }
        }
        qsort(sets, (size_t)m, sizeof sets[0], compare_luma_set);
        long double luminance[LDREF_MAX_SETS];
        for (int j = 0; j < m; ++j) {
            luminance[j] = sets[j].luminance;
            for (int c = 0; c < LDREF_CHANNELS; ++c)
                out->ordered[c][j] = sets[j].rgb[c];
        }
        long double g = ldref_gini(luminance, m);
        for (int c = 0; c < LDREF_CHANNELS; ++c) {
            out->gini[c] = g;
            out->trim[c] = ldref_trim_count(g, m);
            out->mon[c] = ldref_median(out->ordered[c], m);
            out->gmon[c] = ldref_trimmed_mean(out->ordered[c], m, out->trim[c]);
        }
    }
}
