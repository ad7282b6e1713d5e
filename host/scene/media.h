/* Participating media: MakeNamedMedium, MediumInterface (media.c). */
#ifndef HOST_SCENE_MEDIA_H
#define HOST_SCENE_MEDIA_H

#include "scene/directives.h"

/* Directive handlers, for parser.c's table. */
int on_make_named_medium(Parser *p, Lexer *lex, const Token *d);
int on_medium_interface(Parser *p, Lexer *lex, const Token *d);

/* Once the whole scene is read: every medium named is defined (else a
 * file:line error at its first use), and a note where the integrator
 * ignores the scene's media. Returns 0 or -1. */
int finish_media(Parser *p);

#endif
