/* A render as an EXR image: every layer the render produced, and its
 * metadata. Callers clear the layers they do not want written. */
#ifndef HOST_RENDER_RENDER_EXR_H
#define HOST_RENDER_RENDER_EXR_H

#include "film/film_file.h"
#include "render/renderer.h"

/* Fills `file` (in place: see FilmFile); its image points into `output`,
 * which must outlive it. */
void render_output_file(FilmFile *file, const RenderOutput *output);

#endif
