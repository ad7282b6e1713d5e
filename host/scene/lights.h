/* AreaLightSource and LightSource (lights.c). */
#ifndef HOST_SCENE_LIGHTS_H
#define HOST_SCENE_LIGHTS_H

#include "scene/directives.h"

/* Directive handlers, for parser.c's table. */
int on_area_light_source(Parser *p, Lexer *lex, const Token *d);
int on_light_source(Parser *p, Lexer *lex, const Token *d);

#endif
