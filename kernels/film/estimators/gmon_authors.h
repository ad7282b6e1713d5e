/* gmon-authors, the authors' G-MoN ("gini-dmon"): their G' (on the means
 * plus 1e-11) averaged over the channels, odd m trimming ceil(k G'bar)
 * sets per side (form WHOLE_PIXEL; recomputed by the jackknife). Part of
 * estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMON_AUTHORS_H
#define KERNELS_ESTIMATORS_GMON_AUTHORS_H

/* The authors' G of one channel (gini-dmon): on the means plus 1e-11, in
 * the pixel's units (`epsilon`: 1e-11 in the units of v). */
EST_INLINE est_float gini_authors(const est_float *v, int m, est_float epsilon)
{
    est_int e = sorted_range_exponent(v, 0, m - 1);
    est_float down = power_of_two(-e);
    est_float lowest = scaled(v[0], down);
    return gini_sorted_offset(v, m, down, lowest, sum_of_differences(v, 0, m - 1, down, lowest, 1),
                              scale_by_power(epsilon, -e));
}

/* Its weights over m sorted sets from G'bar: odd m, ceil(k G') sets off
 * each end; even m, no trim. */
EST_INLINE void gmon_authors_weights(est_float authors_gbar, int m, est_float *w)
{
    const int k = m / 2;
    est_float x = authors_gbar * (float)k;
    est_int c_floor = EST_INT_FROM_FLOAT(x);
    est_int trim = c_floor + EST_SELECT(EST_FLOAT_FROM_INT(c_floor) < x, EST_INTS(1), EST_INTS(0));
    trim = EST_SELECT(trim > k, EST_INTS(k), trim);
    trim_weights(m % 2 ? trim : EST_INTS(0), m, w);
}

EST_INLINE void gmon_authors_estimate(const est_float (*v)[EST_CAPACITY], const est_float (*t)[EST_CAPACITY], int m,
                                      const EstimatorParams *params, FamilyShared *shared, est_float *value)
{
    (void)t;
    (void)params;
    est_float authors_gbar = (gini_authors(v[0], m, shared->epsilon) + gini_authors(v[1], m, shared->epsilon) +
                              gini_authors(v[2], m, shared->epsilon)) /
                             3.0f;
    est_float w[EST_CAPACITY];
    gmon_authors_weights(authors_gbar, m, w);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        value[c] = weighted_sorted_average(v[c], m, w);
}

#endif /* KERNELS_ESTIMATORS_GMON_AUTHORS_H */
