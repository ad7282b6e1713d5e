/* huber: Huber's M-estimator of location over one channel's sorted set
 * means (docs/estimators.md): from the median, HUBER_STEPS reweighted
 * means, each set weighted 1 within h = huber.k * (t_{m-q} - t_{q+1}),
 * q = floor(m / 4), of the current estimate and h / distance beyond
 * (form OF_SORTED: the jackknife recomputes it). + - * / only, on values
 * scaled by a power of two so the largest lies in [1, 2): the same bits on
 * every device, exact scaling with the input. Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_HUBER_H
#define KERNELS_ESTIMATORS_HUBER_H

/* A fixed count, for determinism; the reweighted means settle within a few
 * steps on ordinary pixels. */
#define HUBER_STEPS 8

EST_INLINE est_float huber_of_sorted(const est_float *v, int m, const EstimatorParams *params)
{
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float x[EST_CAPACITY];
    EST_UNROLL
    for (int j = 0; j < m; ++j)
        x[j] = scaled(v[j], down);
    const int q = m / 4;
    /* (huber.k >= 1/2: the first step's median lies within h of a set, so
     * the weights never all vanish) */
    est_float h = params->huber_k * (x[m - 1 - q] - x[q]);
    est_float z = median_of_sorted(x, m);
    for (int step = 0; step < HUBER_STEPS; ++step) {
        est_float w[EST_CAPACITY];
        EST_UNROLL
        for (int j = 0; j < m; ++j) {
            est_float d = x[j] - z;
            d = EST_SELECT(d < 0.0f, -d, d);
            /* (d = 0 <= h: h / d is not taken) */
            w[j] = EST_SELECT(d <= h, EST_FLOATS(1.0f), h / d);
        }
        z = weighted_sorted_average(x, m, w);
    }
    return scaled(z, power_of_two(e));
}

#endif /* KERNELS_ESTIMATORS_HUBER_H */
