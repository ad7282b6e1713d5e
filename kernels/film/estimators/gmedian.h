/* gmedian: the geometric median of the RGB set means (Minsker 2015), by a
 * fixed number of Weiszfeld steps (form WHOLE_PIXEL). Its leave-one-out
 * estimates restart from the full estimate, their first steps from prefix
 * and suffix sums of every set's terms (gmedian_step_sums). Part of
 * estimators.h. */
#ifndef KERNELS_ESTIMATORS_GMEDIAN_H
#define KERNELS_ESTIMATORS_GMEDIAN_H

/* root_of(x, 1) for x in [1, 16), in the same steps (the same bits)
 * without its range reduction: Weiszfeld's distances, on a scale where
 * the largest coordinate lies in [1, 2). */
EST_INLINE est_float inverse_root_small(est_float x)
{
    est_mask high = x >= 4.0f;
    return inverse_root_reduced(EST_SELECT(high, x * 0.25f, x)) * EST_SELECT(high, EST_FLOATS(0.5f), EST_FLOATS(1.0f));
}

/* The sums of a Weiszfeld step from z over a set of points: their weights
 * 1 / |x_j - z| (total), the weighted differences (shift), the unit vectors
 * toward z, on the common scale (pull), and the points at z (at_z). */
typedef struct {
    est_float shift[EST_CHANNELS];
    est_float pull[EST_CHANNELS];
    est_float total;
    est_float at_z;
} WeiszfeldSums;

EST_INLINE WeiszfeldSums weiszfeld_start(void)
{
    WeiszfeldSums s;
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        s.shift[c] = EST_FLOATS(0.0f);
        s.pull[c] = EST_FLOATS(0.0f);
    }
    s.total = EST_FLOATS(0.0f);
    s.at_z = EST_FLOATS(0.0f);
    return s;
}

/* Adds point j's terms of the step from z (see weiszfeld). */
EST_INLINE void weiszfeld_add(WeiszfeldSums *s, const est_float (*x)[EST_CAPACITY], int j, const est_float *ratio,
                              const est_float *z)
{
    est_float d[EST_CHANNELS], common[EST_CHANNELS], largest = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        d[c] = x[c][j] - z[c];
        common[c] = d[c] * ratio[c];
        largest = larger_magnitude(largest, common[c]);
    }
    /* (a point within 2^-100 of z, on the largest channel's scale, counts
     * as at z: its weight would overflow) */
    est_mask here = largest < 7.88860905e-31f; /* 2^-100 */
    est_int e = scale_exponent(largest);
    est_float unit = power_of_two(-EST_SELECT(here, EST_INTS(0), e)), square = EST_FLOATS(0.0f);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        common[c] = common[c] * unit;
        square += common[c] * common[c];
    }
    est_float r = EST_SELECT(here, EST_FLOATS(0.0f), inverse_root_small(square)); /* square in [1, 12) */
    est_float w = r * unit;                                                       /* 1 / distance */
    s->total += w;
    s->at_z += EST_SELECT(here, EST_FLOATS(1.0f), EST_FLOATS(0.0f));
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        s->shift[c] += w * d[c];
        s->pull[c] += r * common[c];
    }
}

/* a + b, term by term: the sums over two sets of points. */
EST_INLINE WeiszfeldSums weiszfeld_union(const WeiszfeldSums *a, const WeiszfeldSums *b)
{
    WeiszfeldSums s;
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        s.shift[c] = a->shift[c] + b->shift[c];
        s.pull[c] = a->pull[c] + b->pull[c];
    }
    s.total = a->total + b->total;
    s.at_z = a->at_z + b->at_z;
    return s;
}

/* The step itself: moves z by the sums of the step from it. */
EST_INLINE void weiszfeld_move(const WeiszfeldSums *s, est_float *z)
{
    est_float norm = root_of(s->pull[0] * s->pull[0] + s->pull[1] * s->pull[1] + s->pull[2] * s->pull[2], 0);
    est_float part = EST_SELECT(s->at_z > 0.0f, 1.0f - s->at_z / norm, EST_FLOATS(1.0f));
    part = EST_SELECT((part > 0.0f) & (s->total > 0.0f), part, EST_FLOATS(0.0f));
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c)
        z[c] = z[c] + part * (s->shift[c] / EST_SELECT(s->total > 0.0f, s->total, EST_FLOATS(1.0f)));
}

/* The geometric median of the m RGB points (x[0][j], x[1][j], x[2][j]):
 * `iterations` Weiszfeld steps from z (updated in place). Each channel is
 * kept on its own scale (x[c][j] and z[c] in units of 2^e_c), since
 * a step moves each coordinate to a weighted mean of that channel's
 * values; only the distances, which weigh the points, are on one scale
 * common to the channels (`ratio[c]` = 2^(e_c - e), e the largest e_c),
 * each difference rescaled by a power of two so that no square underflows.
 * At one or more of the points (eta of them) the plain step is undefined:
 * there Vardi and Zhang's step (2000) moves only by (1 - eta / |R|)^+ of
 * the step toward the others' weighted mean (R the sum of the unit vectors
 * from z to them), and stays where that point is the median (|R| <= eta),
 * as it is of a majority of equal points. */
EST_INLINE void weiszfeld(const est_float (*x)[EST_CAPACITY], int m, const est_float *ratio, int iterations,
                          est_float *z)
{
    for (int step = 0; step < iterations; ++step) {
        WeiszfeldSums sums = weiszfeld_start();
        EST_UNROLL
        for (int j = 0; j < m; ++j)
            weiszfeld_add(&sums, x, j, ratio, z);
        weiszfeld_move(&sums, z);
    }
}

/* The RGB set means t[c][0..m-1] on the channels' scales `down`. */
EST_INLINE void gmedian_points(const est_float (*t)[EST_CAPACITY], int m, const est_float *down,
                               est_float (*points)[EST_CAPACITY])
{
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        EST_UNROLL
        for (int j = 0; j < m; ++j)
            points[c][j] = scaled(t[c][j], down[c]);
    }
}

/* gmedian of m sets (t by set, v sorted) from shared->z, on the scales
 * shared->down and distance ratios shared->ratio (family_shared's), into
 * value[c]: shared->iterations steps, z left at the result. */
EST_INLINE void gmedian_estimate(const est_float (*v)[EST_CAPACITY], const est_float (*t)[EST_CAPACITY], int m,
                                 const EstimatorParams *params, FamilyShared *shared, est_float *value)
{
    (void)params;
    est_float points[EST_CHANNELS][EST_CAPACITY]; /* on the channels' scales, once for every step */
    gmedian_points(t, m, shared->down, points);
    weiszfeld((const est_float(*)[EST_CAPACITY])points, m, shared->ratio, shared->iterations, shared->z);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) /* 1 / down: exact, a power of two */
        value[c] = clamp_lanes(shared->z[c] * (1.0f / shared->down[c]), v[c][0], v[c][m - 1]);
}

/* The leave-one-out estimates all start from the full estimate z, so their
 * first steps share every set's terms: summed once over the sets before
 * each set (before[j], sets < j) and once over those after it (after[j],
 * sets >= j), the first step without set j moves by the union of
 * before[j] and after[j + 1] (gmedian_first_step_without). */
EST_INLINE void gmedian_step_sums(const est_float (*t)[EST_CAPACITY], int m, const est_float *down,
                                  const est_float *ratio, const est_float *z, WeiszfeldSums *before,
                                  WeiszfeldSums *after)
{
    est_float points[EST_CHANNELS][EST_CAPACITY];
    gmedian_points(t, m, down, points);
    before[0] = weiszfeld_start();
    EST_UNROLL
    for (int j = 0; j < m; ++j) {
        before[j + 1] = before[j];
        weiszfeld_add(&before[j + 1], (const est_float(*)[EST_CAPACITY])points, j, ratio, z);
    }
    after[m] = weiszfeld_start();
    EST_UNROLL
    for (int j = m - 1; j >= 0; --j) {
        after[j] = after[j + 1];
        weiszfeld_add(&after[j], (const est_float(*)[EST_CAPACITY])points, j, ratio, z);
    }
}

EST_INLINE void gmedian_first_step_without(const WeiszfeldSums *before, const WeiszfeldSums *after, int left_out,
                                           est_float *z)
{
    WeiszfeldSums first = weiszfeld_union(&before[left_out], &after[left_out + 1]);
    weiszfeld_move(&first, z);
}

#endif /* KERNELS_ESTIMATORS_GMEDIAN_H */
