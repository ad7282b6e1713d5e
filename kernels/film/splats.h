/* Splats: the contributions a light subpath makes to the pixel its
 * connection to the camera lands on (bdpt and lightpath), which is not the
 * pixel whose sample made it. Each is recorded as (pixel, set, RGB) and
 * added into that pixel's set sums by the pixel's own work item
 * (add_splats in kernels/tracing/bdpt.cl, after the host has put the
 * records in pixel order), through the same exact accumulation as camera
 * samples: the sums do not depend on the order of the records, so images
 * stay bit-identical across devices, slices and passes.
 *
 * Valid C11 and OpenCL C 1.2: the host sorts the records the kernels
 * write. */
#ifndef KERNELS_SPLATS_H
#define KERNELS_SPLATS_H

#include "../common/compat.h"

/* 20 bytes, every member 4: the same layout in C and OpenCL C. */
typedef struct {
    uint32_t pixel; /* of the image */
    uint32_t set;   /* that of the sample whose light subpath made it */
    float rgb[3];
} SplatRecord;

#endif
