#include "zirr_reference.h"

#include <stdlib.h>

static long double luminance(const long double *rgb)
{
    return 0.2126L * rgb[0] + 0.7152L * rgb[1] + 0.0722L * rgb[2];
}

/* Adds a sample of luminance l to the cascades `sums` (K x RGB). Between
 * the bracketing scales lo < hi the weights solve w_lo + w_hi = 1 and
 * w_lo l / lo + w_hi l / hi = 1 (one sample counted once); at or below
 * the first scale all goes to cascade 0; above the last scale the sample
 * is scaled down to it, in the last cascade. */
static void split_sample(const ZirrReferenceParams *p, const long double *scales, const long double *x,
                         long double *sums)
{
    const long double l = luminance(x);
    const int last = p->cascades - 1;
    if (l <= scales[0]) {
        for (int c = 0; c < 3; ++c)
            sums[c] += x[c];
        return;
    }
    if (l >= scales[last]) {
        for (int c = 0; c < 3; ++c)
            sums[last * 3 + c] += x[c] * scales[last] / l;
        return;
    }
    int k = 0;
    while (!(l < scales[k + 1]))
        ++k;
    const long double lo = scales[k], hi = scales[k + 1];
    /* w_hi (1 / hi - 1 / lo) = 1 / l - 1 / lo */
    const long double w_hi = (1.0L / l - 1.0L / lo) / (1.0L / hi - 1.0L / lo), w_lo = 1.0L - w_hi;
    for (int c = 0; c < 3; ++c) {
        sums[k * 3 + c] += x[c] * w_lo;
        sums[(k + 1) * 3 + c] += x[c] * w_hi;
    }
}

static int clamp_int(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

void reference_zirr(const ZirrReferenceParams *p, const float *samples, size_t n, int width, int height,
                    long double *estimate)
{
    const int K = p->cascades;
    const size_t pixels = (size_t)width * height;
    long double scales[64];
    for (int k = 0; k < K; ++k)
        scales[k] = k == 0 ? 1.0L : scales[k - 1] * p->base;
    /* B_k: each cascade's mean over the n samples. */
    long double *means = calloc(pixels * (size_t)K * 3, sizeof(long double));
    for (size_t q = 0; q < pixels; ++q) {
        for (size_t i = 0; i < n; ++i) {
            long double x[3];
            for (int c = 0; c < 3; ++c)
                x[c] = samples[(q * n + i) * 3 + c];
            split_sample(p, scales, x, means + q * (size_t)K * 3);
        }
        for (int j = 0; j < K * 3; ++j)
            means[q * (size_t)K * 3 + (size_t)j] = n ? means[q * (size_t)K * 3 + (size_t)j] / (long double)n : 0.0L;
    }
    const long double N = (long double)n;
    /* The colour term's factor: b^0.6-like headroom when kappa > 1 (the
     * authors' 0.4 + 0.6 b), none at kappa <= 1. */
    const long double t = 1.0L / p->kappa < 1.0L ? 1.0L / p->kappa : 1.0L;
    const long double factor = (1.0L - t) * (0.4L + 0.6L * p->base) + t;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t q = (size_t)y * width + (size_t)x;
            long double result[3] = {0.0L, 0.0L, 0.0L};
            for (int i = 0; i < K; ++i) {
                /* Estimated sample counts of cascades i-1, i, i+1: at the
                 * pixel, and the mean over the 3x3 neighbourhood (edge
                 * pixels repeated at the border). */
                long double here = 0.0L, around = 0.0L;
                for (int k = i - 1; k <= i + 1; ++k) {
                    if (k < 0 || k >= K)
                        continue;
                    here += luminance(means + (q * (size_t)K + (size_t)k) * 3) * N / scales[k];
                    long double sum = 0.0L;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            size_t r = (size_t)clamp_int(y + dy, 0, height - 1) * width +
                                       (size_t)clamp_int(x + dx, 0, width - 1);
                            sum += luminance(means + (r * (size_t)K + (size_t)k) * 3);
                        }
                    around += sum / 9.0L * N / scales[k];
                }
                const long double count = around >= 1.0L ? here : around;
                long double brightness = luminance(result);
                if (brightness < p->emin)
                    brightness = p->emin;
                long double r = ((count - 1.0L) / p->kappa + brightness * N / (p->kappa * scales[i]) * factor) / 2.0L;
                r = r < 0.0L ? 0.0L : (r > 1.0L ? 1.0L : r);
                for (int c = 0; c < 3; ++c)
                    result[c] += r * means[(q * (size_t)K + (size_t)i) * 3 + c];
            }
            for (int c = 0; c < 3; ++c)
                estimate[q * 3 + c] = result[c];
        }
    free(means);
}
