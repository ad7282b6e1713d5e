/* gmon-partial: Gbar < threshold ? amon(1) : amon(gmon-partial.alpha)
 * (TRAIT_GATED). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMON_PARTIAL_H
#define KERNELS_ESTIMATORS_GMON_PARTIAL_H

EST_INLINE est_float gmon_partial_of(est_float gbar, const EstimatorParams *params, est_float amon_one,
                                     est_float amon_alpha)
{
    return EST_SELECT(gbar < params->gmon_partial_threshold, amon_one, amon_alpha);
}

#endif /* KERNELS_ESTIMATORS_GMON_PARTIAL_H */
