/* gmon-binary: Gbar < threshold ? the mean of the set means : MoN
 * (TRAIT_GATED: both are fixed-weight, so the jackknife takes them by
 * rank, with each left-out set's Gbar). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMON_BINARY_H
#define KERNELS_ESTIMATORS_GMON_BINARY_H

EST_INLINE est_float gmon_binary_of(est_float gbar, const EstimatorParams *params, est_float mean_of_means,
                                    est_float median)
{
    return EST_SELECT(gbar < params->gmon_binary_threshold, mean_of_means, median);
}

#endif /* KERNELS_ESTIMATORS_GMON_BINARY_H */
