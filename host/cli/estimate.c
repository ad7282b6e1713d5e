#include "cli/estimate.h"

#include "cli/output_files.h"
#include "io/exr_image.h"

#include <stdio.h>

int estimate_command(const Options *o)
{
    ExrImage in;
    Options chosen;
    char error[1024];
    int status = 1;
    if (exr_image_read(o->input, &in, error, sizeof error) != IMAGE_IO_OK)
        fprintf(stderr, "gmonrt: %s\n", error);
    else if (!in.accumulators)
        fprintf(stderr, "gmonrt: %s has no per-set sums (render with --write-sets)\n", o->input);
    else if (in.metadata.sample_count == 0) /* sums of no samples: an all-zero image */
        fprintf(stderr, "gmonrt: %s has no sample count (attribute gmon.samples missing or 0)\n", o->input);
    else if (options_for_file(o, &in, &chosen, error, sizeof error) != 0)
        fprintf(stderr, "gmonrt: %s: %s\n", o->input, error);
    else
        status = write_estimates(&chosen, &chosen.estimator, &in, o->write_sets, "estimate.exr");
    exr_image_free(&in);
    return status;
}
