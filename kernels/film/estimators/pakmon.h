/* pakmon, the authors' PAK-MoN: amon with alpha = the entropy H of the
 * growth of the squared deviations, out to distance rho; a function of one
 * channel's sorted set means (form OF_SORTED; recomputed by the
 * jackknife). Part of estimators.h. */
#ifndef KERNELS_ESTIMATORS_PAKMON_H
#define KERNELS_ESTIMATORS_PAKMON_H

/* ln x for a normal x > 0, with + - * / only, so that every device gives
 * the same bits: x = 2^e f with f in [sqrt(1/2), sqrt(2)), and ln f =
 * 2 atanh(s), s = (f - 1) / (f + 1), |s| < 0.172, by its series to s^9
 * (truncation below 3e-9 relative, under a float ulp; the result is within
 * a few float ulps). */
EST_INLINE est_float natural_log(est_float x)
{
    est_uint bits = EST_FLOAT_BITS(x);
    est_int e = EST_INT_FROM_UINT(bits >> 23) - 127;
    est_float f = EST_FLOAT_FROM_BITS((bits & 0x7fffffu) | 0x3f800000u);
    est_mask high = f > 1.41421356f;
    f = EST_SELECT(high, f * 0.5f, f);
    e = EST_SELECT(high, e + 1, e);
    est_float s = (f - 1.0f) / (f + 1.0f), s2 = s * s;
    est_float series = EST_FLOATS(1.0f / 9.0f);
    series = series * s2 + 1.0f / 7.0f;
    series = series * s2 + 1.0f / 5.0f;
    series = series * s2 + 1.0f / 3.0f;
    series = series * s2 + 1.0f;
    /* ln 2 as a float and the rest, so that e ln 2 keeps its precision */
    est_float ef = EST_FLOAT_FROM_INT(e);
    return ef * 0.693145752f + (2.0f * s * series + ef * 1.42860677e-06f);
}

/* pakmon's entropy H of a channel's sorted values v[0..m-1]: the growth
 * of their squared deviations from the mean, d_j = sum_{i<j} (v_i - mean)^2
 * / (j + 1), j = 2..m-1, as a distribution p_j = d_j^2 / sum d^2, and H =
 * -sum p ln p / ln(m - 2) in [0, 1]; 0 for m <= 3 or equal values. */
EST_INLINE est_float pakmon_entropy(const est_float *v, int m)
{
    if (m <= 3)
        return EST_FLOATS(0.0f);
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float lowest = scaled(v[0], down);
    est_float mean = lowest + sum_of_differences(v, 0, m - 1, down, lowest, 1) / (float)m;
    est_float d[EST_CAPACITY];
    est_float squares = EST_FLOATS(0.0f), largest = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 1; j < m; ++j) {
        est_float deviation = scaled(v[j - 1], down) - mean;
        squares += deviation * deviation;
        if (j >= 2) {
            d[j] = squares * (1.0f / (float)(j + 1)); /* a constant in kernels: no division */
            largest = EST_SELECT(d[j] > largest, d[j], largest);
        }
    }
    /* d relative to the largest, so that the squares below neither
     * underflow nor overflow */
    est_float unit = EST_SELECT(largest > 0.0f, 1.0f / largest, EST_FLOATS(0.0f));
    est_float total = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 2; j < m; ++j) {
        d[j] = d[j] * unit;
        d[j] = d[j] * d[j];
        total += d[j];
    }
    est_float inverse_total = EST_SELECT(total > 0.0f, 1.0f / total, EST_FLOATS(0.0f));
    est_float entropy = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int j = 2; j < m; ++j) {
        est_float p = d[j] * inverse_total;
        est_mask normal = p >= 1.17549435e-38f; /* smaller p add below 1e-36 */
        entropy -= EST_SELECT(normal, p * natural_log(EST_SELECT(normal, p, EST_FLOATS(1.0f))), EST_FLOATS(0.0f));
    }
    est_float h = entropy / natural_log(EST_FLOATS((float)(m - 2)));
    return EST_SELECT(h < 0.0f, EST_FLOATS(0.0f), EST_SELECT(h > 1.0f, EST_FLOATS(1.0f), h));
}

EST_INLINE est_float pakmon_of_sorted(const est_float *v, int m, const EstimatorParams *params)
{
    (void)params;
    est_float h = pakmon_entropy(v, m);
    const int k = m / 2, farthest = m % 2 ? k : k - 1;
    est_int rho = EST_INT_FROM_FLOAT(h * (float)k) - (int)(0.15f * (float)m);
    rho = EST_SELECT(rho < 0, EST_INTS(0), EST_SELECT(rho > farthest, EST_INTS(farthest), rho));
    est_float w[EST_CAPACITY];
    centre_weights(h, rho, m, w);
    return weighted_sorted_average(v, m, w);
}

#endif /* KERNELS_ESTIMATORS_PAKMON_H */
