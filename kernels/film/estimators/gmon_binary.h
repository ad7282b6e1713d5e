/* gmon-binary: Gbar < threshold ? the mean of the set means : MoN
 * (form GATED: both sides are fixed weights, the median's included, so the
 * jackknife takes them by rank, with each left-out set's Gbar). Part of
 * estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMON_BINARY_H
#define KERNELS_ESTIMATORS_GMON_BINARY_H

EST_INLINE float gmon_binary_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    if (side == 0)
        trim_weights(EST_INTS(0), m, out->w);
    else
        out->median = 1;
    return params->gmon_binary_threshold;
}

#endif /* KERNELS_ESTIMATORS_GMON_BINARY_H */
