/* amon, alpha-MoN (docs/estimators.md): weight alpha^d at distance d from
 * the median (form FIXED_WEIGHTS: its estimate and leave-one-out estimates
 * are estimators.h's weighted_sorted_average and leave_one_out_averages of
 * these weights). Its centre weights serve ggmon, gmon-partial and pakmon
 * too. Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_AMON_H
#define KERNELS_ESTIMATORS_AMON_H

/* amon's weights: alpha^d at distance d from the centre of m sorted values
 * (odd m: the median, d = |j - k|; even m: the middle pair, each at 1/2,
 * then d = 1.. outwards), 0 past distance `reach`. alpha^0 = 1. */
EST_INLINE void centre_weights(est_float alpha, est_int reach, int m, est_float *w)
{
    const int k = m / 2;
    est_float power = EST_FLOATS(1.0f);
    if (m % 2) {
        w[k] = EST_FLOATS(1.0f);
        EST_UNROLL
        for (int d = 1; d <= k; ++d) {
            power = power * alpha;
            est_float x = EST_SELECT(d <= reach, power, EST_FLOATS(0.0f));
            w[k - d] = x;
            w[k + d] = x;
        }
    } else {
        w[k - 1] = EST_FLOATS(0.5f);
        w[k] = EST_FLOATS(0.5f);
        EST_UNROLL
        for (int d = 1; d < k; ++d) {
            power = power * alpha;
            est_float x = EST_SELECT(d <= reach, power, EST_FLOATS(0.0f));
            w[k - 1 - d] = x;
            w[k + d] = x;
        }
    }
}

EST_INLINE void amon_weights(est_float alpha, int m, est_float *w)
{
    centre_weights(alpha, EST_INTS(m), m, w);
}

EST_INLINE float amon_fixed_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    (void)side;
    amon_weights(EST_FLOATS(params->amon_alpha), m, out->w);
    return INFINITY;
}

#endif /* KERNELS_ESTIMATORS_AMON_H */
