/* ggmon, the authors' GG-MoN: amon with alpha = 1 - Gbar, so its weights
 * follow the whole pixel (TRAIT_WHOLE_PIXEL); recomputed by the jackknife.
 * Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_GGMON_H
#define KERNELS_ESTIMATORS_GGMON_H

/* Its weights over m sorted sets: one set for the three channels. */
EST_INLINE void ggmon_weights(est_float gbar, int m, est_float *w)
{
    amon_weights(1.0f - gbar, m, w);
}

#endif /* KERNELS_ESTIMATORS_GGMON_H */
