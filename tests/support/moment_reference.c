#include "moment_reference.h"

#include <math.h>
#include <stdlib.h>

ReferenceMoments reference_moments(const float *x, size_t n)
{
    ReferenceMoments r = {0.0L, 0.0L, 0.0L};
    if (n == 0)
        return r;
    for (size_t i = 0; i < n; ++i)
        r.mean += x[i];
    r.mean /= (long double)n;
    for (size_t i = 0; i < n; ++i) {
        long double d = (long double)x[i] - r.mean;
        r.m2 += d * d;
        r.m3 += d * d * d;
    }
    r.m2 /= (long double)n;
    r.m3 /= (long double)n;
    return r;
}

long double reference_abmm(const float *x, size_t n, long double alpha)
{
    ReferenceMoments r = reference_moments(x, n);
    if (!(r.m2 > 0.0L))
        return r.mean;
    return r.mean - r.m3 / (3.0L * r.m2 * ((long double)n * alpha + 2.0L));
}

static int compare(const void *a, const void *b)
{
    long double x = *(const long double *)a, y = *(const long double *)b;
    return (x > y) - (x < y);
}

long double reference_gini(const long double *values, int m)
{
    long double t[64], sum = 0.0L, weighted = 0.0L;
    for (int i = 0; i < m; ++i)
        t[i] = values[i];
    qsort(t, (size_t)m, sizeof t[0], compare);
    for (int i = 0; i < m; ++i) {
        sum += t[i];
        weighted += (long double)(2 * (i + 1) - m - 1) * t[i];
    }
    if (!(sum > 0.0L))
        return 0.0L;
    long double g = weighted / ((long double)m * sum);
    return g < 0.0L ? 0.0L : (g > 1.0L ? 1.0L : g);
}

int reference_set_means(const float *x, size_t n, int sets, uint64_t first_sample, long double *means)
{
    long double sum[64] = {0};
    size_t count[64] = {0};
    for (size_t i = 0; i < n; ++i) {
        int set = (int)((first_sample + i) % (uint64_t)sets);
        sum[set] += x[i];
        ++count[set];
    }
    int m = 0;
    for (int j = 0; j < sets; ++j)
        if (count[j])
            means[m++] = sum[j] / (long double)count[j];
    return m;
}

/* 1.96 s / sqrt(n) of values of set `set` (-1: all of them). */
static long double half_width(const float *x, size_t n, int sets, uint64_t first_sample, int set)
{
    long double sum = 0.0L, squares = 0.0L;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        if (set < 0 || (int)((first_sample + i) % (uint64_t)sets) == set) {
            sum += x[i];
            ++count;
        }
    long double mean = sum / (long double)count;
    for (size_t i = 0; i < n; ++i)
        if (set < 0 || (int)((first_sample + i) % (uint64_t)sets) == set)
            squares += ((long double)x[i] - mean) * ((long double)x[i] - mean);
    return 1.96L * sqrtl(squares / (long double)(count - 1)) / sqrtl((long double)count);
}

typedef struct {
    long double mean;
    int set;
} SetMean;

static int compare_set_means(const void *a, const void *b)
{
    const SetMean *x = a, *y = b;
    return (x->mean > y->mean) - (x->mean < y->mean);
}

ReferenceMeanOrMon reference_mean_or_mon(const float *x, size_t n, int sets, uint64_t first_sample)
{
    ReferenceMeanOrMon r;
    long double sum[64] = {0};
    size_t count[64] = {0};
    for (size_t i = 0; i < n; ++i) {
        int set = (int)((first_sample + i) % (uint64_t)sets);
        sum[set] += x[i];
        ++count[set];
    }
    SetMean by_mean[64];
    for (int j = 0; j < sets; ++j) {
        by_mean[j].mean = sum[j] / (long double)count[j];
        by_mean[j].set = j;
    }
    qsort(by_mean, (size_t)sets, sizeof by_mean[0], compare_set_means);
    const int low = (sets - 1) / 2, high = sets / 2;
    r.mon = (by_mean[low].mean + by_mean[high].mean) / 2.0L;
    r.mon_width = (half_width(x, n, sets, first_sample, by_mean[low].set) +
                   half_width(x, n, sets, first_sample, by_mean[high].set)) /
                  2.0L;
    r.mean = reference_moments(x, n).mean;
    r.mean_width = half_width(x, n, sets, first_sample, -1);
    r.chose_mean = r.mean_width <= r.mon_width;
    r.value = r.chose_mean ? r.mean : r.mon;
    return r;
}
