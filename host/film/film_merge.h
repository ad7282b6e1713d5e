/* Merging the films of renders of disjoint sample ranges of one scene:
 * their exact set sums add (kernels/film/accumulate.h), so the merged film holds
 * the sums one render of the whole range would have. */
#ifndef HOST_FILM_FILM_MERGE_H
#define HOST_FILM_FILM_MERGE_H

#include <stddef.h>
#include <stdint.h>

/* Adds the sums of `part` to those of `total` (both accumulator_planes(M)
 * planes of pixel_count pixels, both modified: grids are aligned in place)
 * and puts `total` in canonical form. A pixel whose sums cannot be added
 * exactly (values spanning more binary orders than a sum holds) is rounded
 * and gets 1 added to rounded[pixel] (rounded may be NULL). Returns the
 * number of such pixels, or -1 if M is out of range. */
int64_t film_merge(uint64_t *total, uint64_t *part, size_t pixel_count, int set_count, uint32_t *rounded);

#endif
