#include "render/pixel_filter.h"

#include <math.h>

static const double pi = 3.14159265358979323846;

static double gaussian(double x, double sigma)
{
    return exp(-x * x / (2.0 * sigma * sigma)) / sqrt(2.0 * pi * sigma * sigma);
}

/* Mitchell and Netravali's cubic on [-2, 2]. */
static double mitchell_1d(double x, double b, double c)
{
    x = fabs(x);
    if (x <= 1.0)
        return ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0;
    if (x <= 2.0)
        return ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x +
                (8.0 * b + 24.0 * c)) /
               6.0;
    return 0.0;
}

static double sinc(double x)
{
    return x == 0.0 ? 1.0 : sin(pi * x) / (pi * x);
}

/* One axis of the filter, over [-radius, radius]. */
static double evaluate_1d(const PixelFilter *f, double x, double radius)
{
    if (fabs(x) > radius)
        return 0.0;
    switch (f->type) {
    case PIXEL_FILTER_BOX:
        return 1.0;
    case PIXEL_FILTER_GAUSSIAN: /* shifted down to reach 0 at the radius */
        return fmax(0.0, gaussian(x, f->sigma) - gaussian(radius, f->sigma));
    case PIXEL_FILTER_MITCHELL:
        return mitchell_1d(2.0 * x / radius, f->b, f->c);
    case PIXEL_FILTER_LANCZOS:
        return sinc(x) * sinc(x / f->tau);
    case PIXEL_FILTER_TRIANGLE:
        return radius - fabs(x);
    }
    return 0.0;
}

double pixel_filter_evaluate(const PixelFilter *filter, double x, double y)
{
    return evaluate_1d(filter, x, filter->radius[0]) * evaluate_1d(filter, y, filter->radius[1]);
}

void pixel_filter_table_size(const PixelFilter *filter, uint32_t size[2])
{
    for (int a = 0; a < 2; ++a) {
        double cells = floor(32.0 * (double)filter->radius[a]);
        size[a] = cells < 1.0 ? 1u : (uint32_t)cells;
    }
}
