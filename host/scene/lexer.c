#include "scene/lexer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void lexer_init(Lexer *lexer, const char *path, char *data, size_t size, Diagnostics *diag)
{
    memset(lexer, 0, sizeof *lexer);
    lexer->path = path;
    lexer->data = data;
    lexer->size = size;
    lexer->line = 1;
    lexer->diag = diag;
}

void lexer_destroy(Lexer *lexer)
{
    free(lexer->data);
    memset(lexer, 0, sizeof *lexer);
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

static int ends_word(char c)
{
    return is_space(c) || c == '"' || c == '[' || c == ']' || c == '#';
}

/* Decodes the string that starts after the opening quote at data[pos - 1],
 * in place. */
static int lex_string(Lexer *lexer, Token *token)
{
    char *out = lexer->data + lexer->pos;
    token->kind = TOKEN_STRING;
    token->text = out;
    token->line = lexer->line;
    size_t length = 0;
    while (lexer->pos < lexer->size) {
        char c = lexer->data[lexer->pos++];
        if (c == '"') {
            token->length = length;
            return 0;
        }
        if (c == '\n')
            break; /* pbrt strings do not span lines */
        if (c == '\\') {
            if (lexer->pos >= lexer->size)
                break;
            static const char names[] = "bfnrt\\'\"", values[] = "\b\f\n\r\t\\'\"";
            char e = lexer->data[lexer->pos++];
            const char *found = e ? strchr(names, e) : NULL;
            if (!found)
                return scene_error(lexer->diag, lexer->path, lexer->line, "unknown escape '\\%c' in a string",
                                   (e >= 32 && e < 127) ? e : '?');
            c = values[found - names];
        }
        out[length++] = c;
    }
    return scene_error(lexer->diag, lexer->path, token->line, "unterminated string");
}

static int lex(Lexer *lexer, Token *token)
{
    const char *data = lexer->data;
    for (;;) {
        while (lexer->pos < lexer->size && is_space(data[lexer->pos])) {
            if (data[lexer->pos] == '\n')
                lexer->line++;
            lexer->pos++;
        }
        if (lexer->pos < lexer->size && data[lexer->pos] == '#') {
            while (lexer->pos < lexer->size && data[lexer->pos] != '\n')
                lexer->pos++;
            continue;
        }
        break;
    }
    token->line = lexer->line;
    token->text = data + lexer->pos;
    token->length = 0;
    if (lexer->pos >= lexer->size) {
        token->kind = TOKEN_END;
        return 0;
    }
    char c = data[lexer->pos++];
    if (c == '"')
        return lex_string(lexer, token);
    if (c == '[' || c == ']') {
        token->kind = c == '[' ? TOKEN_OPEN : TOKEN_CLOSE;
        token->length = 1;
        return 0;
    }
    token->kind = TOKEN_WORD;
    while (lexer->pos < lexer->size && !ends_word(data[lexer->pos]))
        lexer->pos++;
    token->length = (size_t)(data + lexer->pos - token->text);
    return 0;
}

int lexer_next(Lexer *lexer, Token *token)
{
    if (lexer->has_peeked) {
        lexer->has_peeked = 0;
        *token = lexer->peeked;
        return 0;
    }
    return lex(lexer, token);
}

int lexer_peek(Lexer *lexer, Token *token)
{
    if (!lexer->has_peeked) {
        if (lex(lexer, &lexer->peeked))
            return -1;
        lexer->has_peeked = 1;
    }
    *token = lexer->peeked;
    return 0;
}

int token_is(const Token *token, const char *text)
{
    size_t n = strlen(text);
    return token->length == n && memcmp(token->text, text, n) == 0;
}

int token_number(const Token *token, double *value)
{
    char buffer[64];
    if (token->kind != TOKEN_WORD || token->length == 0 || token->length >= sizeof buffer)
        return -1;
    memcpy(buffer, token->text, token->length);
    buffer[token->length] = '\0';
    char *end = NULL;
    double v = strtod(buffer, &end);
    if (end != buffer + token->length || !isfinite(v))
        return -1;
    *value = v;
    return 0;
}

void token_describe(const Token *token, char *out, size_t size)
{
    switch (token->kind) {
    case TOKEN_END:
        snprintf(out, size, "end of file");
        return;
    case TOKEN_OPEN:
        snprintf(out, size, "'['");
        return;
    case TOKEN_CLOSE:
        snprintf(out, size, "']'");
        return;
    default:
        break;
    }
    char text[48];
    size_t n = token->length < 40 ? token->length : 40;
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)token->text[i];
        text[i] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    text[n] = '\0';
    const char *more = token->length > n ? "..." : "";
    if (token->kind == TOKEN_STRING)
        snprintf(out, size, "\"%s%s\"", text, more);
    else
        snprintf(out, size, "'%s%s'", text, more);
}
