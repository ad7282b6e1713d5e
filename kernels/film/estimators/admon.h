/* admon, alpha-distance MoN (docs/estimators.md): the median and its
 * floor(k alpha) nearest neighbours (odd m; form FIXED_WEIGHTS); its
 * weights serve dmon-partial too. Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_ADMON_H
#define KERNELS_ESTIMATORS_ADMON_H

/* admon's weights: odd m, 1 within distance u of the median, else 0; even
 * m (the authors' rule, u unused): every set at 1, the middle pair at 1/2. */
EST_INLINE void band_weights(est_int u, int m, est_float *w)
{
    const int k = m / 2;
    EST_UNROLL
    for (int j = 0; j < m; ++j) {
        int d = j < k ? k - j : j - k;
        if (m % 2)
            w[j] = EST_SELECT(d <= u, EST_FLOATS(1.0f), EST_FLOATS(0.0f));
        else
            w[j] = EST_FLOATS(j == k - 1 || j == k ? 0.5f : 1.0f);
    }
}

EST_INLINE void admon_weights(est_float alpha, int m, est_float *w)
{
    est_int u = EST_INT_FROM_FLOAT(alpha * (float)(m / 2));
    band_weights(EST_SELECT(u < 0, EST_INTS(0), u), m, w);
}

EST_INLINE float admon_fixed_weights(int side, int m, const EstimatorParams *params, FixedWeights *out)
{
    (void)side;
    admon_weights(EST_FLOATS(params->admon_alpha), m, out->w);
    return INFINITY;
}

#endif /* KERNELS_ESTIMATORS_ADMON_H */
