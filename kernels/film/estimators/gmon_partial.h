/* gmon-partial: Gbar < threshold ? amon(1) : amon(gmon-partial.alpha)
 * (form GATED). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMON_PARTIAL_H
#define KERNELS_ESTIMATORS_GMON_PARTIAL_H

EST_INLINE float gmon_partial_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    amon_weights(EST_FLOATS(side == 0 ? 1.0f : params->gmon_partial_alpha), m, out->w);
    return params->gmon_partial_threshold;
}

#endif /* KERNELS_ESTIMATORS_GMON_PARTIAL_H */
