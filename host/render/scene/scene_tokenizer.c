/* Tokenizer for pbrt-v3 scene files (same token rules as pbrt-v3's parser.cpp Tokenizer). */
#include "scene_tokenizer.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"
#include "render_input.h"

clr_result clr_tokenizer_open_file(clr_tokenizer *t, const char *path, const char *context) {
  memset(t, 0, sizeof *t);
  CLR_CHECK(clr_read_input_file(path, context ? context : "clr_scene_parse_file",
                                CLR_SCENE_MAX_FILE_BYTES, &t->buffer, &t->size));
  t->line = 1;
  t->col = 1;
  t->path = path;
  return CLR_SUCCESS;
}

clr_result clr_tokenizer_open_string(clr_tokenizer *t, const char *text, size_t length,
                                     const char *path) {
  memset(t, 0, sizeof *t);
  t->buffer = malloc(length + 1);
  if (!t->buffer)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_scene_parse_string: out of memory (%zu bytes)", length);
  memcpy(t->buffer, text, length);
  t->buffer[length] = 0;
  t->size = length;
  t->line = 1;
  t->col = 1;
  t->path = path;
  return CLR_SUCCESS;
}

void clr_tokenizer_close(clr_tokenizer *t) {
  free(t->buffer);
  memset(t, 0, sizeof *t);
}

static int peek_char(const clr_tokenizer *t) {
  return t->pos < t->size ? (unsigned char)t->buffer[t->pos] : EOF;
}

static int get_char(clr_tokenizer *t) {
  int ch = peek_char(t);
  if (ch == EOF) return EOF;
  ++t->pos;
  if (ch == '\n') {
    ++t->line;
    t->col = 1;
  } else {
    ++t->col;
  }
  return ch;
}

static bool is_space(int ch) {
  return ch == ' ' || ch == '\n' || ch == '\t' || ch == '\r' || ch == '\f' || ch == '\v';
}

static bool ends_word(int ch) {
  return ch == EOF || is_space(ch) || ch == '"' || ch == '[' || ch == ']' || ch == '#';
}

static int decode_escape(int ch) {
  switch (ch) {
    case 'b':
      return '\b';
    case 'f':
      return '\f';
    case 'n':
      return '\n';
    case 'r':
      return '\r';
    case 't':
      return '\t';
    case '\\':
      return '\\';
    case '\'':
      return '\'';
    case '"':
      return '"';
    default:
      return -1;
  }
}

/* Scans a quoted string whose opening quote was consumed; decodes escapes in place. */
static clr_result scan_string(clr_tokenizer *t, clr_token *tok) {
  char *out = t->buffer + t->pos;
  tok->text = out;
  for (;;) {
    int ch = get_char(t);
    if (ch == '"') break;
    if (ch == EOF || ch == '\n')
      return clr_set_last_error(CLR_ERROR_PARSE,
                                "%s:%d:%d: expected '\"' closing the string, got %s", t->path,
                                tok->line, tok->col, ch == EOF ? "end of file" : "end of line");
    if (ch == '\\') {
      int esc_line = t->line, esc_col = t->col - 1;
      int next = get_char(t);
      int decoded = next == EOF ? -1 : decode_escape(next);
      if (decoded < 0)
        return clr_set_last_error(
            CLR_ERROR_PARSE, "%s:%d:%d: expected an escape (\\n \\t \\\" \\\\ ...), got %s",
            t->path, esc_line, esc_col, next == EOF ? "end of file" : "an unknown escape");
      ch = decoded;
    }
    *out++ = (char)ch;
  }
  tok->length = (size_t)(out - tok->text);
  tok->kind = CLR_TOKEN_STRING;
  return CLR_SUCCESS;
}

clr_result clr_tokenizer_next(clr_tokenizer *t, clr_token *tok) {
  for (;;) {
    tok->file = t->path;
    tok->line = t->line;
    tok->col = t->col;
    tok->text = t->buffer + t->pos;
    tok->length = 0;
    int ch = get_char(t);
    if (ch == EOF) {
      tok->kind = CLR_TOKEN_EOF;
      return CLR_SUCCESS;
    }
    if (is_space(ch)) continue;
    if (ch == '#') {
      while (peek_char(t) != EOF && peek_char(t) != '\n' && peek_char(t) != '\r') get_char(t);
      continue;
    }
    if (ch == '"') return scan_string(t, tok);
    if (ch == '[' || ch == ']') {
      tok->kind = ch == '[' ? CLR_TOKEN_LBRACKET : CLR_TOKEN_RBRACKET;
      tok->length = 1;
      return CLR_SUCCESS;
    }
    while (!ends_word(peek_char(t))) get_char(t);
    tok->kind = CLR_TOKEN_WORD;
    tok->length = (size_t)(t->buffer + t->pos - tok->text);
    return CLR_SUCCESS;
  }
}

bool clr_token_is(const clr_token *tok, clr_token_kind kind, const char *text) {
  if (tok->kind != kind) return false;
  if (!text) return true;
  size_t n = strlen(text);
  return tok->length == n && memcmp(tok->text, text, n) == 0;
}

/* At most this many characters of a token are quoted in messages: a file that is not a scene
 * (an Include of an arbitrary file) must not have its contents echoed. */
#define CLR_TOKEN_EXCERPT 16

void clr_token_describe(const clr_token *tok, char *buf, size_t size) {
  int printable = 1;
  for (size_t i = 0; i < tok->length && printable; ++i) {
    unsigned char c = (unsigned char)tok->text[i];
    printable = c >= 0x20 && c < 0x7f;
  }
  int shown = tok->length > CLR_TOKEN_EXCERPT ? CLR_TOKEN_EXCERPT : (int)tok->length;
  const char *more = tok->length > CLR_TOKEN_EXCERPT ? "..." : "";
  if (!printable && (tok->kind == CLR_TOKEN_STRING || tok->kind == CLR_TOKEN_WORD)) {
    snprintf(buf, size, "%s (%zu bytes of binary data)",
             tok->kind == CLR_TOKEN_STRING ? "a string" : "a word", tok->length);
    return;
  }
  switch (tok->kind) {
    case CLR_TOKEN_EOF:
      snprintf(buf, size, "end of file");
      break;
    case CLR_TOKEN_LBRACKET:
      snprintf(buf, size, "'['");
      break;
    case CLR_TOKEN_RBRACKET:
      snprintf(buf, size, "']'");
      break;
    case CLR_TOKEN_STRING:
      snprintf(buf, size, "string \"%.*s%s\"", shown, tok->text, more);
      break;
    case CLR_TOKEN_WORD:
      snprintf(buf, size, "'%.*s%s'", shown, tok->text, more);
      break;
  }
}

char *clr_token_strdup(const clr_token *tok) {
  char *s = malloc(tok->length + 1);
  if (!s) return NULL;
  memcpy(s, tok->text, tok->length);
  s[tok->length] = 0;
  return s;
}
