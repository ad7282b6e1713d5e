/* ggmon, the authors' GG-MoN: amon with alpha = 1 - Gbar, so its weights
 * follow the whole pixel (form WHOLE_PIXEL); recomputed by the jackknife.
 * Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_GGMON_H
#define KERNELS_ESTIMATORS_GGMON_H

/* One set of weights for the three channels. */
EST_INLINE void ggmon_estimate(const est_float (*v)[EST_CAPACITY], const est_float (*t)[EST_CAPACITY], int m,
                               const EstimatorParams *params, FamilyShared *shared, est_float *value)
{
    (void)t;
    (void)params;
    est_float w[EST_CAPACITY];
    amon_weights(1.0f - shared->gbar, m, w);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        value[c] = weighted_sorted_average(v[c], m, w);
}

#endif /* KERNELS_ESTIMATORS_GGMON_H */
