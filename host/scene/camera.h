/* Camera, Film, PixelFilter, Sampler, Integrator, Accelerator (camera.c). */
#ifndef HOST_SCENE_CAMERA_H
#define HOST_SCENE_CAMERA_H

#include "scene/directives.h"

/* pbrt-v4's pixel filter when a scene names none: gaussian, radius 1.5. */
SceneFilter default_pixel_filter(void);

/* Directive handlers, for parser.c's table. */
int on_camera(Parser *p, Lexer *lex, const Token *d);
int on_film(Parser *p, Lexer *lex, const Token *d);
int on_sampler(Parser *p, Lexer *lex, const Token *d);
int on_integrator(Parser *p, Lexer *lex, const Token *d);
int on_accelerator(Parser *p, Lexer *lex, const Token *d);
int on_pixel_filter(Parser *p, Lexer *lex, const Token *d);

/* Once the whole scene is read: the film matrix from the sensor, ISO,
 * white balance and the shutter's exposure. Returns 0 or -1. */
int finish_film(Parser *p);

/* Once the whole scene is read: the camera's basis from its transform and
 * the film size. Returns 0 or -1. */
int finish_camera(Parser *p);

#endif
