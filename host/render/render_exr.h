/* A render as an EXR image: every layer the render produced, and its
 * metadata. Callers clear the layers they do not want written. */
#ifndef HOST_RENDER_RENDER_EXR_H
#define HOST_RENDER_RENDER_EXR_H

#include "io/exr_image.h"
#include "render/renderer.h"

/* The image points into `output`, which must outlive it. */
ExrImage render_output_exr(const RenderOutput *output);

#endif
