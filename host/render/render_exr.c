#include "render/render_exr.h"

#include <string.h>

ExrImage render_output_exr(const RenderOutput *out)
{
    ExrImage image;
    memset(&image, 0, sizeof image);
    image.width = (int)out->width;
    image.height = (int)out->height;
    image.mean = out->mean;
    image.mon = out->mon;
    image.gmon = out->gmon;
    image.gini = out->gini;
    image.trim = out->trim;
    image.nonfinite = out->rejected;
    image.rounded = out->rejected ? out->rejected + (size_t)out->width * out->height : NULL;
    image.accumulators = out->accumulators;
    image.metadata.software = "gmonrt";
    image.metadata.set_count = out->set_count;
    image.metadata.sample_count = out->sample_count;
    image.metadata.seed = out->seed;
    image.metadata.first_sample = out->first_sample;
    image.metadata.gini_mode = out->gini_mode;
    image.metadata.scene_hash = out->scene_hash;
    image.metadata.max_depth = (int)out->max_depth;
    image.metadata.integrator = out->integrator;
    image.metadata.nonfinite_samples = out->rejected_total;
    image.metadata.rounded_samples = out->rounded_total;
    return image;
}
