#include "film/film_merge.h"

#include "accumulate.h" /* kernels/ */
#include "film/film.h"

int64_t film_merge(uint64_t *total, uint64_t *part, size_t pixel_count, int set_count, uint32_t *rounded)
{
    if (film_check_set_count(set_count, NULL, 0) != 0)
        return -1;
    int64_t inexact_pixels = 0;
    for (size_t p = 0; p < pixel_count; ++p) {
        int inexact = accumulators_merge_pixel(total, part, p, pixel_count, (uint32_t)set_count);
        if (rounded)
            rounded[p] += (uint32_t)inexact;
        inexact_pixels += inexact;
    }
    return inexact_pixels;
}
