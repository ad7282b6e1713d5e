/* dmon-partial: Gbar < threshold ? admon(1) : admon(dmon-partial.alpha)
 * (form GATED). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_DMON_PARTIAL_H
#define KERNELS_ESTIMATORS_DMON_PARTIAL_H

EST_INLINE float dmon_partial_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    admon_weights(EST_FLOATS(side == 0 ? 1.0f : params->dmon_partial_alpha), m, out->w);
    return params->dmon_partial_threshold;
}

#endif /* KERNELS_ESTIMATORS_DMON_PARTIAL_H */
