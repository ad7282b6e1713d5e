#include "moment_reference.h"

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
