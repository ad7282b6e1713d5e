/* Tokens of one pbrt file: words (directives, numbers, bare true/false),
 * quoted strings and brackets, each with its line. '#' starts a comment
 * that runs to the end of the line. */
#ifndef HOST_SCENE_LEXER_H
#define HOST_SCENE_LEXER_H

#include "scene/scene_internal.h"

#include <stddef.h>

typedef enum {
    TOKEN_END, /* end of file */
    TOKEN_WORD,
    TOKEN_STRING,
    TOKEN_OPEN,  /* [ */
    TOKEN_CLOSE, /* ] */
} TokenKind;

typedef struct {
    TokenKind kind;
    const char *text; /* not NUL-terminated; a string's escapes are decoded */
    size_t length;
    int line;
} Token;

typedef struct {
    const char *path; /* the file's name, for messages */
    char *data;       /* the whole file, owned; strings are decoded in place */
    size_t size, pos;
    int line;
    Token peeked;
    int has_peeked;
    Diagnostics *diag;
} Lexer;

/* Takes ownership of data[0, size) (which must be followed by a NUL). */
void lexer_init(Lexer *lexer, const char *path, char *data, size_t size, Diagnostics *diag);
void lexer_destroy(Lexer *lexer);

/* The next token, consumed or not. Return 0, or -1 with an error message
 * (an unterminated string). */
int lexer_next(Lexer *lexer, Token *token);
int lexer_peek(Lexer *lexer, Token *token);

int token_is(const Token *token, const char *text);

/* Parses a word as a finite number. Returns 0, or -1 when it is not one. */
int token_number(const Token *token, double *value);

/* The token as it would be quoted in a message: "end of file", "[", the
 * word, or the string in quotes (shortened, unprintable bytes as '?'). */
void token_describe(const Token *token, char *out, size_t size);

#endif
