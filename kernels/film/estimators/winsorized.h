/* winsorized: the c lowest and highest set means replaced by their nearest
 * kept neighbours, then the mean (form FIXED_WEIGHTS). Part of
 * estimators.h. */
#ifndef KERNELS_ESTIMATORS_WINSORIZED_H
#define KERNELS_ESTIMATORS_WINSORIZED_H

/* The winsorized mean's weights: v[c] and v[m-1-c] also stand for the c
 * values beyond them. */
EST_INLINE void winsor_weights(int c, int m, est_float *w)
{
    EST_UNROLL
    for (int j = 0; j < m; ++j)
        w[j] = EST_FLOATS((j == c ? c : 0) + (j == m - 1 - c ? c : 0) + (j >= c && j <= m - 1 - c ? 1 : 0));
}

EST_INLINE float winsorized_fixed_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    (void)side;
    winsor_weights(sets_to_trim(params->winsorized_c, m), m, out->w);
    return INFINITY;
}

#endif /* KERNELS_ESTIMATORS_WINSORIZED_H */
