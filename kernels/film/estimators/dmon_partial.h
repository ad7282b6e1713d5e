/* dmon-partial: Gbar < threshold ? admon(1) : admon(dmon-partial.alpha)
 * (TRAIT_GATED). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_DMON_PARTIAL_H
#define KERNELS_ESTIMATORS_DMON_PARTIAL_H

EST_INLINE est_float dmon_partial_of(est_float gbar, const EstimatorParams *params, est_float admon_one,
                                     est_float admon_alpha)
{
    return EST_SELECT(gbar < params->dmon_partial_threshold, admon_one, admon_alpha);
}

#endif /* KERNELS_ESTIMATORS_DMON_PARTIAL_H */
