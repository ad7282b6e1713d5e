/* Pixel filters as pbrt-v4 defines them (box, gaussian, mitchell, Lanczos
 * sinc, triangle): the filter function, which the renderer tabulates for
 * filter importance sampling (render_scene_set_filter). */
#ifndef HOST_RENDER_PIXEL_FILTER_H
#define HOST_RENDER_PIXEL_FILTER_H

#include <stdint.h>

typedef enum {
    PIXEL_FILTER_BOX,
    PIXEL_FILTER_GAUSSIAN,
    PIXEL_FILTER_MITCHELL,
    PIXEL_FILTER_LANCZOS,
    PIXEL_FILTER_TRIANGLE,
} PixelFilterType;

/* Each parameter applies to its filter only: gaussian sigma, mitchell b
 * and c, Lanczos tau. radius in pixels, x and y. */
typedef struct {
    PixelFilterType type;
    float radius[2];
    float sigma;
    float b, c;
    float tau;
} PixelFilter;

/* The filter's value at offset (x, y) pixels from the pixel's centre. */
double pixel_filter_evaluate(const PixelFilter *filter, double x, double y);

/* The filter's table for importance sampling: 32 cells per pixel of
 * radius along each axis, as pbrt-v4's FilterSampler (at least one). */
void pixel_filter_table_size(const PixelFilter *filter, uint32_t size[2]);

/* The largest radius a filter may have (its table's size grows with the
 * square of it). */
#define PIXEL_FILTER_MAX_RADIUS 32.0f

#endif
