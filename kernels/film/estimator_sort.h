/* Sorting the set means of a pixel: comparators and the fixed sorting
 * networks (sorting_networks.h), the same comparators in the same order on
 * the host and in every kernel, branch free per lane. */
#ifndef KERNELS_ESTIMATOR_SORT_H
#define KERNELS_ESTIMATOR_SORT_H

#include "accumulate.h" /* EST_CAPACITY, EST_CHANNELS */
#include "lanes.h"
#include "sorting_networks.h"

/* A comparator: orders v[i] <= v[j]. */
EST_INLINE void compare_exchange(est_float *v, int i, int j)
{
    est_float a = v[i], b = v[j];
    est_mask swap = a > b;
    v[i] = EST_SELECT(swap, b, a);
    v[j] = EST_SELECT(swap, a, b);
}

/* A comparator on whole sets: by luminance, ties by r, g, b (so the order
 * does not depend on how the sets were numbered); the channels follow. */
EST_INLINE void compare_exchange_luminance(est_float *luma, est_float (*t)[EST_CAPACITY], int i, int j)
{
    est_mask swap = (luma[j] < luma[i]) |
                    ((luma[j] == luma[i]) &
                     ((t[0][j] < t[0][i]) |
                      ((t[0][j] == t[0][i]) & ((t[1][j] < t[1][i]) | ((t[1][j] == t[1][i]) & (t[2][j] < t[2][i]))))));
    est_float a = luma[i], b = luma[j];
    luma[i] = EST_SELECT(swap, b, a);
    luma[j] = EST_SELECT(swap, a, b);
    EST_UNROLL
    for (int c = 0; c < EST_CHANNELS; ++c) {
        a = t[c][i];
        b = t[c][j];
        t[c][i] = EST_SELECT(swap, b, a);
        t[c][j] = EST_SELECT(swap, a, b);
    }
}

/* EST_SORTING_NETWORK(set_count, COMPARATOR) runs COMPARATOR(i, j) over the
 * sorting network for set_count values: the same comparators in the same
 * order everywhere. A kernel (set_count must be EST_SETS) expands them
 * inline with constant indices, or, past EST_UNROLL_MAX_SETS, loops over a
 * table of them as the host does (which looks its network up at run time). */
#define EST_NETWORK_PAIR(i, j) {i, j},
#if defined(EST_SETS) && EST_SETS <= EST_UNROLL_MAX_SETS
#define EST_SORTING_NETWORK(set_count, COMPARATOR) EST_PASTE(EST_NETWORK_, EST_SETS)(COMPARATOR)
#else
#ifdef EST_SETS
__constant uchar est_network_pairs[][2] = {EST_PASTE(EST_NETWORK_, EST_SETS)(EST_NETWORK_PAIR)};
#define EST_NETWORK_LENGTH (int)(sizeof est_network_pairs / sizeof est_network_pairs[0])
#define EST_NETWORK_PAIRS(set_count, length) (*(length) = EST_NETWORK_LENGTH, est_network_pairs)
#define EST_NETWORK_TABLE __constant uchar
#else
/* The comparators of the network for set_count values (1..64). */
EST_INLINE const uint8_t (*sorting_network(int set_count, int *length))[2]
{
    static const uint8_t pairs[][2] = {EST_ALL_NETWORKS(EST_NETWORK_PAIR)};
    static const int start[EST_MAX_SETS + 1] = {EST_NETWORK_START};
    *length = start[set_count] - start[set_count - 1];
    return pairs + start[set_count - 1];
}
#define EST_NETWORK_PAIRS(set_count, length) sorting_network(set_count, length)
#define EST_NETWORK_TABLE const uint8_t
#endif

#define EST_SORTING_NETWORK(set_count, COMPARATOR)                                                                     \
    {                                                                                                                  \
        int length_;                                                                                                   \
        EST_NETWORK_TABLE(*pairs_)[2] = EST_NETWORK_PAIRS(set_count, &length_);                                        \
        for (int k_ = 0; k_ < length_; ++k_)                                                                           \
            COMPARATOR(pairs_[k_][0], pairs_[k_][1])                                                                   \
    }
#endif

#endif /* KERNELS_ESTIMATOR_SORT_H */
