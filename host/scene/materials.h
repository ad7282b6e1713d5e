/* Material, MakeNamedMaterial, NamedMaterial (materials.c). */
#ifndef HOST_SCENE_MATERIALS_H
#define HOST_SCENE_MATERIALS_H

#include "scene/directives.h"

/* Directive handlers, for parser.c's table. */
int on_material(Parser *p, Lexer *lex, const Token *d);
int on_make_named_material(Parser *p, Lexer *lex, const Token *d);
int on_named_material(Parser *p, Lexer *lex, const Token *d);

/* The current material's index, creating pbrt's default (diffuse 0.5)
 * once; -1 when out of memory. */
int current_material(Parser *p);

/* Once the whole scene is read: a NamedMaterial whose name is never
 * defined is an error. Returns 0 or -1. */
int finish_named_materials(Parser *p);

#endif
