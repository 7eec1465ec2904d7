/* Tokenizer for pbrt-v3 scene files: words, quoted strings, brackets; skips '#' comments. */
#ifndef CLR_SCENE_TOKENIZER_H
#define CLR_SCENE_TOKENIZER_H

#include <stdbool.h>
#include <stddef.h>
#include "clrender/result.h"

typedef enum clr_token_kind {
  CLR_TOKEN_EOF,
  CLR_TOKEN_WORD,     /* directive name, number, bare true/false */
  CLR_TOKEN_STRING,   /* quoted string; text excludes the quotes, escapes decoded */
  CLR_TOKEN_LBRACKET, /* [ */
  CLR_TOKEN_RBRACKET  /* ] */
} clr_token_kind;

/* A token's text points into its tokenizer's buffer (not NUL-terminated): valid until the
 * tokenizer is freed. `file` is the tokenizer's path. Lines and columns count from 1. */
typedef struct clr_token {
  clr_token_kind kind;
  const char *text;
  size_t length;
  const char *file;
  int line;
  int col;
} clr_token;

typedef struct clr_tokenizer {
  char *buffer; /* owned, decoded in place */
  size_t size;
  size_t pos;
  int line;
  int col;
  const char *path; /* borrowed, names the source in messages */
} clr_tokenizer;

/* Reads a whole file: a regular file of at most CLR_SCENE_MAX_FILE_BYTES (render_input.h). On
 * failure returns CLR_ERROR_IO with the message "<context>: cannot open '<path>': <reason>"
 * (or "cannot read '<path>': is a directory" / "is not a regular file"), or
 * CLR_ERROR_FILE_FORMAT for a file over the limit (context may be NULL). */
clr_result clr_tokenizer_open_file(clr_tokenizer *t, const char *path, const char *context);
/* Tokenizes a copy of `text` (length bytes); `path` names it in messages. */
clr_result clr_tokenizer_open_string(clr_tokenizer *t, const char *text, size_t length,
                                     const char *path);
void clr_tokenizer_close(clr_tokenizer *t);

/* Next token (CLR_TOKEN_EOF at the end). An unterminated string or a bad escape gives
 * CLR_ERROR_PARSE "FILE:LINE:COL: expected ..., got ...". */
clr_result clr_tokenizer_next(clr_tokenizer *t, clr_token *tok);

bool clr_token_is(const clr_token *tok, clr_token_kind kind, const char *text);
/* Human description for messages: 'Shape', string "abc", '[', end of file; at most 16
 * characters quoted, non-printable tokens described as binary data. */
void clr_token_describe(const clr_token *tok, char *buf, size_t size);
/* NUL-terminated heap copy of the token text (NULL when out of memory). */
char *clr_token_strdup(const clr_token *tok);

#endif
