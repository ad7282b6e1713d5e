/* The Shape directive (shapes.c). */
#ifndef HOST_SCENE_SHAPES_H
#define HOST_SCENE_SHAPES_H

#include "scene/directives.h"

/* Directive handlers, for parser.c's table. */
int on_shape(Parser *p, Lexer *lex, const Token *d);

/* Once the whole scene is read: a warning when the geometry lies far from
 * the origin for its size. Returns 0 or -1. */
int check_precision(Parser *p);

#endif
