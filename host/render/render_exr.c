#include "render/render_exr.h"

void render_output_file(FilmFile *file, const RenderOutput *out)
{
    EstimatorImages images = render_output_images(out);
    film_file_init(file, (int)out->width, (int)out->height, &out->estimator, &images);
    ExrImage *image = &file->image;
    image->nonfinite = out->rejected;
    image->rounded = out->rejected ? out->rejected + (size_t)out->width * out->height : NULL;
    image->accumulators = out->accumulators;
    image->metadata.software = "gmonrt";
    image->metadata.set_count = out->set_count;
    image->metadata.sample_count = out->sample_count;
    image->metadata.seed = out->seed;
    image->metadata.first_sample = out->first_sample;
    image->metadata.scene_hash = out->scene_hash;
    image->metadata.max_depth = (int)out->max_depth;
    image->metadata.integrator = out->integrator;
    image->metadata.sampler = sampler_name(out->sampler);
    image->metadata.light_sampler = light_sampler_name(out->light_sampler);
    image->metadata.nonfinite_samples = out->rejected_total;
    image->metadata.rounded_samples = out->rounded_total;
}
