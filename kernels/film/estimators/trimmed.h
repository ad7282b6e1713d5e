/* trimmed: the mean of t_{1+c} .. t_{m-c} (form FIXED_WEIGHTS); its
 * weights serve gmon-binary's mean of the set means and gmon-authors too.
 * Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_TRIMMED_H
#define KERNELS_ESTIMATORS_TRIMMED_H

/* Weight 1 on v[c .. m-1-c], 0 outside (a trimmed mean). */
EST_INLINE void trim_weights(est_int c, int m, est_float *w)
{
    EST_UNROLL
    for (int j = 0; j < m; ++j)
        w[j] = EST_SELECT((c <= j) & (c <= m - 1 - j), EST_FLOATS(1.0f), EST_FLOATS(0.0f));
}

/* A set count parameter: c >= 0 as given, -1 for floor(m / 4), clamped so
 * that one set at least remains. */
EST_INLINE int sets_to_trim(int32_t c, int m)
{
    int wanted = c < 0 ? m / 4 : c;
    return wanted > (m - 1) / 2 ? (m - 1) / 2 : wanted;
}

EST_INLINE float trimmed_fixed_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    (void)side;
    trim_weights(EST_INTS(sets_to_trim(params->trimmed_c, m)), m, out->w);
    return INFINITY;
}

#endif /* KERNELS_ESTIMATORS_TRIMMED_H */
