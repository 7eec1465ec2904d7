/* pbrt-v3 scene parser: directives -> clr_scene_desc, with the graphics state of pbrt-v3's
 * api.cpp (CTM, material, area light, reverse orientation, scoped named materials/textures). */
#include "scene_parser.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"
#include "scene_tokenizer.h"

typedef struct location {
  const char *file;
  int line;
  int col;
} location;

/* What AttributeBegin saves (pbrt-v3 GraphicsState plus the CTM). */
typedef struct graphics_state {
  clr_transform ctm;          /* at the start time */
  clr_transform ctm_end;      /* at the end time (pbrt-v3's second TransformSet entry) */
  bool transform_active;      /* the start CTM takes edits ("ActiveTransform All/StartTime") */
  bool end_active;            /* the end CTM takes edits ("ActiveTransform All/EndTime") */
  int material;               /* index of the current Material */
  const char *named_material; /* from NamedMaterial (parser pool), NULL after Material */
  int area_light;             /* -1 when none */
  bool reverse_orientation;
} graphics_state;

typedef enum block_kind { BLOCK_ATTRIBUTE, BLOCK_TRANSFORM, BLOCK_OBJECT } block_kind;

typedef struct block {
  block_kind kind;
  graphics_state saved;
  int binding_count; /* named materials/textures visible when the block opened */
  location at;
} block;

typedef enum binding_kind { BIND_MATERIAL, BIND_FLOAT_TEXTURE, BIND_SPECTRUM_TEXTURE } binding_kind;

/* Name visible in the current attribute scope; later bindings hide earlier ones. */
typedef struct binding {
  binding_kind kind;
  const char *name; /* owned by the scene description */
  int index;
} binding;

typedef struct coord_system {
  char *name;
  clr_transform transform;
} coord_system;

typedef struct include_frame {
  clr_tokenizer tokenizer;
  char *dir; /* directory of the file, "" or ending in '/' */
} include_frame;

typedef struct parser {
  clr_scene_desc *desc;
  clr_warn_fn warn;
  void *warn_user;
  include_frame frames[CLR_SCENE_MAX_INCLUDE_DEPTH + 1];
  int frame_count;
  clr_token peeked;
  bool has_peeked;
  graphics_state gs;
  block *blocks;
  int block_count, block_capacity;
  binding *bindings;
  int binding_count, binding_capacity;
  coord_system *coords;
  int coord_count, coord_capacity;
  char **pool;
  int pool_count, pool_capacity;
  bool in_world;
  bool done; /* after WorldEnd */
  int current_object;
} parser;

typedef struct directive directive;
typedef clr_result (*directive_fn)(parser *p, const directive *d, location at);
typedef enum phase { PHASE_ANY, PHASE_OPTIONS, PHASE_WORLD } phase;
/* Builds the transform of a numeric transform directive; false when it fell back to identity. */
typedef bool (*transform_builder)(const float *v, clr_transform *t);
struct directive {
  const char *name;
  directive_fn handler;
  phase allowed;
  int32_t numbers;         /* numeric transform directives: how many numbers they take */
  transform_builder build; /* and how they become a transform */
};

/* ---- messages ---------------------------------------------------------------------------- */

static void warnf(parser *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warnf(parser *p, const char *fmt, ...) {
  char message[1024];
  va_list args;
  va_start(args, fmt);
  vsnprintf(message, sizeof message, fmt, args);
  va_end(args);
  p->warn(p->warn_user, message);
}

static clr_result expected(const clr_token *got, const char *what) {
  char description[96];
  clr_token_describe(got, description, sizeof description);
  return clr_set_last_error(CLR_ERROR_PARSE, "%s:%d:%d: expected %s, got %s", got->file, got->line,
                            got->col, what, description);
}

static clr_result out_of_memory(location at) {
  return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s:%d: out of memory while parsing the scene",
                            at.file, at.line);
}

/* ---- small helpers ----------------------------------------------------------------------- */

static char *copy_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *c = malloc(n);
  if (c) memcpy(c, s, n);
  return c;
}

static const char *pool_add(parser *p, const char *s) {
  if (clr_grow_array((void **)&p->pool, &p->pool_capacity, p->pool_count + 1, sizeof *p->pool) !=
      CLR_SUCCESS)
    return NULL;
  char *copy = copy_string(s);
  if (copy) p->pool[p->pool_count++] = copy;
  return copy;
}

static char *directory_of(const char *path) {
  const char *slash = strrchr(path, '/');
  size_t n = slash ? (size_t)(slash - path) + 1 : 0;
  char *dir = malloc(n + 1);
  if (!dir) return NULL;
  memcpy(dir, path, n);
  dir[n] = 0;
  return dir;
}

/* Parses a float token as strtof does (pbrt-v3 parseNumber); false unless fully numeric. */
static bool parse_float(const clr_token *tok, float *out) {
  char small[64];
  if (tok->kind != CLR_TOKEN_WORD || tok->length == 0) return false;
  char c = tok->text[0];
  if (!(isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.')) return false;
  char *buf = tok->length < sizeof small ? small : malloc(tok->length + 1);
  if (!buf) return false;
  memcpy(buf, tok->text, tok->length);
  buf[tok->length] = 0;
  char *end = NULL;
  float value = strtof(buf, &end);
  bool ok = end == buf + tok->length && isfinite(value);
  if (buf != small) free(buf);
  if (ok) *out = value;
  return ok;
}

static bool parse_int(const clr_token *tok, int *out) {
  float f;
  if (!parse_float(tok, &f)) return false;
  char buf[32];
  if (tok->length < sizeof buf) {
    memcpy(buf, tok->text, tok->length);
    buf[tok->length] = 0;
    char *end = NULL;
    errno = 0;
    long v = strtol(buf, &end, 10);
    if (end == buf + tok->length) {
      if (errno == ERANGE || v < INT_MIN || v > INT_MAX) return false;
      *out = (int)v;
      return true;
    }
  }
  /* Integral values written as floats ("2.0", "1e3") are accepted. */
  if (f != floorf(f) || f < (float)INT_MIN || f >= (float)INT_MAX) return false;
  *out = (int)f;
  return true;
}

/* ---- tokens across Include files ----------------------------------------------------------- */

static void pop_frame(parser *p) {
  include_frame *f = &p->frames[--p->frame_count];
  clr_tokenizer_close(&f->tokenizer);
  free(f->dir);
  f->dir = NULL;
}

static clr_result next_token(parser *p, clr_token *tok) {
  if (p->has_peeked) {
    *tok = p->peeked;
    p->has_peeked = false;
    return CLR_SUCCESS;
  }
  for (;;) {
    CLR_CHECK(clr_tokenizer_next(&p->frames[p->frame_count - 1].tokenizer, tok));
    if (tok->kind != CLR_TOKEN_EOF || p->frame_count == 1) return CLR_SUCCESS;
    pop_frame(p);
  }
}

static clr_result peek_token(parser *p, clr_token *tok) {
  if (!p->has_peeked) {
    CLR_CHECK(next_token(p, &p->peeked));
    p->has_peeked = true;
  }
  *tok = p->peeked;
  return CLR_SUCCESS;
}

/* Opens `path` (already resolved) as a new innermost file. context names the caller. */
static clr_result push_file(parser *p, const char *path, const char *context, location at) {
  const char *stored = clr_scene_desc_add_file(p->desc, path);
  if (!stored) return out_of_memory(at);
  include_frame *f = &p->frames[p->frame_count];
  f->dir = directory_of(stored);
  if (!f->dir) return out_of_memory(at);
  clr_result r = clr_tokenizer_open_file(&f->tokenizer, stored, context);
  if (r != CLR_SUCCESS) {
    free(f->dir);
    f->dir = NULL;
    return r;
  }
  ++p->frame_count;
  return CLR_SUCCESS;
}

/* ---- directive arguments ----------------------------------------------------------------- */

static clr_result expect_string(parser *p, const char *what, char **out) {
  clr_token tok;
  CLR_CHECK(next_token(p, &tok));
  if (tok.kind != CLR_TOKEN_STRING) return expected(&tok, what);
  *out = clr_token_strdup(&tok);
  if (!*out) return out_of_memory((location){tok.file, tok.line, tok.col});
  return CLR_SUCCESS;
}

static clr_result expect_numbers(parser *p, int n, float *out) {
  for (int i = 0; i < n; ++i) {
    clr_token tok;
    CLR_CHECK(next_token(p, &tok));
    if (!parse_float(&tok, &out[i])) return expected(&tok, "a number");
  }
  return CLR_SUCCESS;
}

/* 16 numbers, optionally in brackets (pbrt-v3 requires them for Transform/ConcatTransform). */
static clr_result expect_matrix(parser *p, float out[16]) {
  clr_token tok;
  CLR_CHECK(peek_token(p, &tok));
  bool bracketed = tok.kind == CLR_TOKEN_LBRACKET;
  if (bracketed) CLR_CHECK(next_token(p, &tok));
  CLR_CHECK(expect_numbers(p, 16, out));
  if (!bracketed) return CLR_SUCCESS;
  CLR_CHECK(next_token(p, &tok));
  return tok.kind == CLR_TOKEN_RBRACKET ? CLR_SUCCESS : expected(&tok, "']' after 16 numbers");
}

/* ---- parameter lists --------------------------------------------------------------------- */

/* Values being collected for one parameter. */
typedef struct value_builder {
  clr_param *param;
  int capacity;
  bool bracketed;
  int bracket_line, bracket_col;
} value_builder;

static clr_result reserve_value(value_builder *b, location at) {
  clr_param *q = b->param;
  if (q->count < b->capacity) return CLR_SUCCESS;
  int capacity = b->capacity;
  void **array = q->ints      ? (void **)&q->ints
                 : q->strings ? (void **)&q->strings
                              : (void **)&q->floats;
  size_t size = q->ints ? sizeof(int) : q->strings ? sizeof(char *) : sizeof(float);
  if (clr_grow_array(array, &capacity, q->count + 1, size) != CLR_SUCCESS) return out_of_memory(at);
  b->capacity = capacity;
  return CLR_SUCCESS;
}

static clr_result value_error(const value_builder *b, const clr_token *tok, const char *what) {
  if (!b->bracketed) return expected(tok, what);
  char message[160];
  snprintf(message, sizeof message, "%s or ']' closing the '[' at %d:%d", what, b->bracket_line,
           b->bracket_col);
  return expected(tok, message);
}

static clr_result add_string_value(value_builder *b, const clr_token *tok, const char *text,
                                   location at) {
  clr_param *q = b->param;
  if (!q->strings && q->count == 0) {
    q->strings = malloc(4 * sizeof *q->strings);
    if (!q->strings) return out_of_memory(at);
    b->capacity = 4;
  }
  CLR_CHECK(reserve_value(b, at));
  char *s = text ? copy_string(text) : clr_token_strdup(tok);
  if (!s) return out_of_memory(at);
  q->strings[q->count++] = s;
  return CLR_SUCCESS;
}

static clr_result add_value(value_builder *b, const clr_token *tok) {
  clr_param *q = b->param;
  location at = {tok->file, tok->line, tok->col};
  clr_param_type t = q->type;
  if (t == CLR_PARAM_STRING || t == CLR_PARAM_TEXTURE ||
      (t == CLR_PARAM_SPECTRUM && tok->kind == CLR_TOKEN_STRING && !q->floats)) {
    if (tok->kind != CLR_TOKEN_STRING) return value_error(b, tok, "a quoted string");
    return add_string_value(b, tok, NULL, at);
  }
  if (t == CLR_PARAM_BOOL) {
    bool is_true = clr_token_is(tok, tok->kind, "true"),
         is_false = clr_token_is(tok, tok->kind, "false");
    if ((tok->kind != CLR_TOKEN_STRING && tok->kind != CLR_TOKEN_WORD) || (!is_true && !is_false))
      return value_error(b, tok, "true or false");
    if (!q->ints && !(q->ints = malloc(4 * sizeof *q->ints))) return out_of_memory(at);
    if (b->capacity == 0) b->capacity = 4;
    CLR_CHECK(reserve_value(b, at));
    q->ints[q->count++] = is_true ? 1 : 0;
    return CLR_SUCCESS;
  }
  if (t == CLR_PARAM_INT) {
    int v;
    if (!parse_int(tok, &v)) return value_error(b, tok, "an integer");
    if (!q->ints && !(q->ints = malloc(4 * sizeof *q->ints))) return out_of_memory(at);
    if (b->capacity == 0) b->capacity = 4;
    CLR_CHECK(reserve_value(b, at));
    q->ints[q->count++] = v;
    return CLR_SUCCESS;
  }
  float v;
  if (!parse_float(tok, &v)) return value_error(b, tok, "a number");
  if (q->strings) return value_error(b, tok, "a quoted string"); /* spectrum file names */
  if (!q->floats && !(q->floats = malloc(4 * sizeof *q->floats))) return out_of_memory(at);
  if (b->capacity == 0) b->capacity = 4;
  CLR_CHECK(reserve_value(b, at));
  q->floats[q->count++] = v;
  return CLR_SUCCESS;
}

/* "type name" -> type and heap name. */
static clr_result parse_declaration(const clr_token *decl, clr_param *q) {
  const char *s = decl->text, *end = decl->text + decl->length;
  while (s < end && isspace((unsigned char)*s)) ++s;
  const char *type_start = s;
  while (s < end && !isspace((unsigned char)*s)) ++s;
  size_t type_length = (size_t)(s - type_start);
  if (!clr_param_type_from_name(type_start, type_length, &q->type)) {
    char message[320];
    snprintf(message, sizeof message,
             "a parameter type (integer, float, bool, string, texture, point2, vector2, point3, "
             "vector3, normal, rgb, color, spectrum, blackbody, xyz) in \"%.*s\"",
             (int)(decl->length > 60 ? 60 : decl->length), decl->text);
    return expected(decl, message);
  }
  while (s < end && isspace((unsigned char)*s)) ++s;
  const char *name_start = s;
  while (s < end && !isspace((unsigned char)*s)) ++s;
  const char *name_end = s;
  while (s < end && isspace((unsigned char)*s)) ++s;
  if (name_start == name_end || s != end) {
    char message[160];
    snprintf(message, sizeof message, "\"%s NAME\" (one parameter name after the type)",
             clr_param_type_name(q->type));
    return expected(decl, message);
  }
  size_t n = (size_t)(name_end - name_start);
  q->name = malloc(n + 1);
  if (!q->name) return out_of_memory((location){decl->file, decl->line, decl->col});
  memcpy(q->name, name_start, n);
  q->name[n] = 0;
  return CLR_SUCCESS;
}

static clr_result parse_values(parser *p, value_builder *b, const clr_token *decl) {
  clr_token tok;
  CLR_CHECK(next_token(p, &tok));
  if (tok.kind == CLR_TOKEN_STRING || tok.kind == CLR_TOKEN_WORD) return add_value(b, &tok);
  if (tok.kind != CLR_TOKEN_LBRACKET) {
    char message[160];
    snprintf(message, sizeof message, "a value or '[' for parameter \"%.*s\"",
             (int)(decl->length > 60 ? 60 : decl->length), decl->text);
    return expected(&tok, message);
  }
  b->bracketed = true;
  b->bracket_line = tok.line;
  b->bracket_col = tok.col;
  for (;;) {
    CLR_CHECK(next_token(p, &tok));
    if (tok.kind == CLR_TOKEN_RBRACKET) return CLR_SUCCESS;
    if (tok.kind == CLR_TOKEN_EOF || tok.kind == CLR_TOKEN_LBRACKET) {
      char message[96];
      snprintf(message, sizeof message, "']' closing the '[' at %d:%d", b->bracket_line,
               b->bracket_col);
      return expected(&tok, message);
    }
    CLR_CHECK(add_value(b, &tok));
  }
}

static clr_result check_value_count(parser *p, const clr_param *q, const location *decl) {
  int arity = clr_param_type_arity(q->type);
  if (q->type == CLR_PARAM_SPECTRUM && q->strings) arity = 1;
  const char *type = clr_param_type_name(q->type);
  if (q->type == CLR_PARAM_TEXTURE && q->count != 1)
    return clr_set_last_error(
        CLR_ERROR_PARSE, "%s:%d:%d: expected one texture name for parameter '%s', got %d values",
        decl->file, decl->line, decl->col, q->name, q->count);
  if (q->count % arity != 0)
    return clr_set_last_error(
        CLR_ERROR_PARSE, "%s:%d:%d: expected a multiple of %d values for %s parameter '%s', got %d",
        decl->file, decl->line, decl->col, arity, type, q->name, q->count);
  if (q->type == CLR_PARAM_XYZ || q->type == CLR_PARAM_SPECTRUM) /* blackbody: converted */
    warnf(p,
          "%s:%d: parameter '%s' has spectral type '%s', which clrender keeps unconverted "
          "(use rgb)",
          decl->file, decl->line, q->name, type);
  return CLR_SUCCESS;
}

static clr_result parse_one_param(parser *p, clr_param_list *list) {
  clr_token decl;
  CLR_CHECK(next_token(p, &decl));
  location at = {decl.file, decl.line, decl.col};
  clr_param q;
  memset(&q, 0, sizeof q);
  q.line = decl.line;
  q.float_texture = q.spectrum_texture = -1;
  value_builder b = {&q, 0, false, 0, 0};
  clr_result r = parse_declaration(&decl, &q);
  /* The declaration token may live in an Include buffer freed while reading values. */
  char decl_text[96];
  snprintf(decl_text, sizeof decl_text, "%.*s", (int)(decl.length > 80 ? 80 : decl.length),
           decl.text);
  clr_token decl_copy = decl;
  decl_copy.text = decl_text;
  decl_copy.length = strlen(decl_text);
  if (r == CLR_SUCCESS) r = parse_values(p, &b, &decl_copy);
  if (r == CLR_SUCCESS) r = check_value_count(p, &q, &at);
  if (r != CLR_SUCCESS) {
    clr_param_free(&q);
    return r;
  }
  if (clr_params_add(list, &q) != CLR_SUCCESS) return out_of_memory(at);
  return CLR_SUCCESS;
}

/* Quoted "type name" declarations with values until the next non-string token. */
static clr_result parse_param_list(parser *p, clr_param_list *list) {
  for (;;) {
    clr_token tok;
    CLR_CHECK(peek_token(p, &tok));
    if (tok.kind != CLR_TOKEN_STRING) return CLR_SUCCESS;
    CLR_CHECK(parse_one_param(p, list));
  }
}

/* `"type" params...` as Shape, Material, Camera, ... take. */
static clr_result parse_typed_params(parser *p, const directive *d, location at, char **type,
                                     clr_param_list *params) {
  char what[96];
  snprintf(what, sizeof what, "a quoted type name after %s", d->name);
  *type = NULL;
  clr_params_init(params, d->name, NULL, at.file, at.line);
  CLR_CHECK(expect_string(p, what, type));
  params->type = *type;
  clr_result r = parse_param_list(p, params);
  if (r != CLR_SUCCESS) {
    free(*type);
    *type = NULL;
    clr_params_free(params);
  }
  return r;
}

/* ---- graphics state ---------------------------------------------------------------------- */

static bool phase_allows(parser *p, const directive *d, location at) {
  if (d->allowed == PHASE_OPTIONS && p->in_world) {
    warnf(p, "%s:%d: %s is not allowed inside the world block; ignored", at.file, at.line, d->name);
    return false;
  }
  if (d->allowed == PHASE_WORLD && !p->in_world) {
    warnf(p, "%s:%d: %s is only allowed after WorldBegin; ignored", at.file, at.line, d->name);
    return false;
  }
  return true;
}

/* Frees what parse_typed_params gave. */
static void discard_typed(char *type, clr_param_list *params) {
  free(type);
  clr_params_free(params);
}

/* parse_typed_params, then the phase check: *kept is false (nothing left to free) where the
 * directive is ignored here. */
static clr_result parse_typed_directive(parser *p, const directive *d, location at, char **type,
                                        clr_param_list *params, bool *kept) {
  CLR_CHECK(parse_typed_params(p, d, at, type, params));
  *kept = phase_allows(p, d, at);
  if (!*kept) discard_typed(*type, params);
  return CLR_SUCCESS;
}

static int find_binding(const parser *p, binding_kind kind, const char *name) {
  for (int i = p->binding_count - 1; i >= 0; --i)
    if (p->bindings[i].kind == kind && strcmp(p->bindings[i].name, name) == 0)
      return p->bindings[i].index;
  return -1;
}

static clr_result add_binding(parser *p, binding_kind kind, const char *name, int index,
                              location at) {
  if (clr_grow_array((void **)&p->bindings, &p->binding_capacity, p->binding_count + 1,
                     sizeof *p->bindings) != CLR_SUCCESS)
    return out_of_memory(at);
  p->bindings[p->binding_count++] = (binding){kind, name, index};
  return CLR_SUCCESS;
}

/* Resolves "texture" parameters against the textures visible now. */
static void resolve_textures(parser *p, clr_param_list *list) {
  for (int i = 0; i < list->count; ++i) {
    clr_param *q = &list->items[i];
    if (q->type != CLR_PARAM_TEXTURE) continue;
    q->float_texture = find_binding(p, BIND_FLOAT_TEXTURE, q->strings[0]);
    q->spectrum_texture = find_binding(p, BIND_SPECTRUM_TEXTURE, q->strings[0]);
    if (q->float_texture < 0 && q->spectrum_texture < 0)
      warnf(p, "%s:%d: parameter '%s' of %s '%s' names undefined texture '%s'", list->file, q->line,
            q->name, list->directive, list->type, q->strings[0]);
  }
}

static void apply_transform(parser *p, const clr_transform *t) {
  if (p->gs.transform_active) p->gs.ctm = clr_transform_compose(&p->gs.ctm, t);
  if (p->gs.end_active) p->gs.ctm_end = clr_transform_compose(&p->gs.ctm_end, t);
}

/* Sets the active CTMs to t. */
static void set_transform(parser *p, const clr_transform *t) {
  if (p->gs.transform_active) p->gs.ctm = *t;
  if (p->gs.end_active) p->gs.ctm_end = *t;
}

static clr_result push_block(parser *p, block_kind kind, location at) {
  if (clr_grow_array((void **)&p->blocks, &p->block_capacity, p->block_count + 1,
                     sizeof *p->blocks) != CLR_SUCCESS)
    return out_of_memory(at);
  p->blocks[p->block_count++] = (block){kind, p->gs, p->binding_count, at};
  return CLR_SUCCESS;
}

static const char *block_begin_name(block_kind kind) {
  return kind == BLOCK_ATTRIBUTE   ? "AttributeBegin"
         : kind == BLOCK_TRANSFORM ? "TransformBegin"
                                   : "ObjectBegin";
}

static const char *block_end_name(block_kind kind) {
  return kind == BLOCK_ATTRIBUTE   ? "AttributeEnd"
         : kind == BLOCK_TRANSFORM ? "TransformEnd"
                                   : "ObjectEnd";
}

static clr_result pop_block(parser *p, block_kind kind, location at) {
  if (p->block_count == 0)
    return clr_set_last_error(CLR_ERROR_PARSE, "%s:%d:%d: expected a %s before %s, got none",
                              at.file, at.line, at.col, block_begin_name(kind),
                              block_end_name(kind));
  const block *b = &p->blocks[p->block_count - 1];
  if (b->kind != kind)
    return clr_set_last_error(CLR_ERROR_PARSE,
                              "%s:%d:%d: expected %s (for the %s at %s:%d), got %s", at.file,
                              at.line, at.col, block_end_name(b->kind), block_begin_name(b->kind),
                              b->at.file, b->at.line, block_end_name(kind));
  if (kind == BLOCK_TRANSFORM) {
    p->gs.ctm = b->saved.ctm;
    p->gs.ctm_end = b->saved.ctm_end;
    p->gs.transform_active = b->saved.transform_active;
    p->gs.end_active = b->saved.end_active;
  } else {
    p->gs = b->saved;
    p->binding_count = b->binding_count;
  }
  --p->block_count;
  return CLR_SUCCESS;
}

static void warn_unclosed_blocks(parser *p) {
  for (int i = p->block_count - 1; i >= 0; --i)
    warnf(p, "%s:%d: missing %s for this %s", p->blocks[i].at.file, p->blocks[i].at.line,
          block_end_name(p->blocks[i].kind), block_begin_name(p->blocks[i].kind));
  p->block_count = 0;
}

/* ---- transform directives ---------------------------------------------------------------- */

static bool build_translate(const float *v, clr_transform *t) {
  *t = clr_transform_translate(v[0], v[1], v[2]);
  return true;
}

static bool build_scale(const float *v, clr_transform *t) {
  *t = clr_transform_scale(v[0], v[1], v[2]);
  return true;
}

static bool build_rotate(const float *v, clr_transform *t) {
  *t = clr_transform_rotate(v[0], v[1], v[2], v[3]);
  return true;
}

static bool build_look_at(const float *v, clr_transform *t) {
  return clr_transform_look_at(v, v + 3, v + 6, t);
}

/* Translate, Scale, Rotate, LookAt: d->numbers numbers, then d->build. */
static clr_result d_numeric_transform(parser *p, const directive *d, location at) {
  float v[9];
  CLR_CHECK(expect_numbers(p, d->numbers, v));
  if (d->build == build_scale && (v[0] == 0.0f || v[1] == 0.0f || v[2] == 0.0f))
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s:%d:%d: expected non-zero Scale factors, got %g %g %g (the "
                              "transform would be singular)",
                              at.file, at.line, at.col, (double)v[0], (double)v[1], (double)v[2]);
  clr_transform t;
  if (!d->build(v, &t))
    warnf(p, "%s:%d: %s 'up' vector is parallel to the viewing direction; using the identity",
          at.file, at.line, d->name);
  apply_transform(p, &t);
  return CLR_SUCCESS;
}

/* pbrt-v3 reads the 16 numbers column by column (the file lists the matrix transposed). */
static clr_result read_file_matrix(parser *p, const directive *d, location at, clr_transform *t) {
  float v[16], m[4][4];
  CLR_CHECK(expect_matrix(p, v));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = v[j * 4 + i];
  if (!clr_transform_from_matrix(m, t))
    warnf(p, "%s:%d: %s matrix is singular; its inverse is set to zero", at.file, at.line, d->name);
  return CLR_SUCCESS;
}

static clr_result d_transform(parser *p, const directive *d, location at) {
  clr_transform t;
  CLR_CHECK(read_file_matrix(p, d, at, &t));
  set_transform(p, &t);
  return CLR_SUCCESS;
}

static clr_result d_concat_transform(parser *p, const directive *d, location at) {
  clr_transform t;
  CLR_CHECK(read_file_matrix(p, d, at, &t));
  apply_transform(p, &t);
  return CLR_SUCCESS;
}

static clr_result d_identity(parser *p, const directive *d, location at) {
  (void)at;
  (void)d;
  clr_transform identity = clr_transform_identity();
  set_transform(p, &identity);
  return CLR_SUCCESS;
}

static clr_result set_coord_system(parser *p, const char *name, const clr_transform *t,
                                   location at) {
  for (int i = 0; i < p->coord_count; ++i) {
    if (strcmp(p->coords[i].name, name) == 0) {
      p->coords[i].transform = *t;
      return CLR_SUCCESS;
    }
  }
  if (clr_grow_array((void **)&p->coords, &p->coord_capacity, p->coord_count + 1,
                     sizeof *p->coords) != CLR_SUCCESS)
    return out_of_memory(at);
  char *copy = copy_string(name);
  if (!copy) return out_of_memory(at);
  p->coords[p->coord_count++] = (coord_system){copy, *t};
  return CLR_SUCCESS;
}

static clr_result d_coordinate_system(parser *p, const directive *d, location at) {
  (void)d;
  char *name = NULL;
  CLR_CHECK(expect_string(p, "a quoted coordinate system name", &name));
  clr_result r = set_coord_system(p, name, &p->gs.ctm, at);
  free(name);
  return r;
}

static clr_result d_coord_sys_transform(parser *p, const directive *d, location at) {
  (void)d;
  char *name = NULL;
  CLR_CHECK(expect_string(p, "a quoted coordinate system name", &name));
  int found = -1;
  for (int i = 0; i < p->coord_count && found < 0; ++i)
    if (strcmp(p->coords[i].name, name) == 0) found = i;
  if (found >= 0)
    p->gs.ctm = p->gs.ctm_end = p->coords[found].transform; /* pbrt-v3 sets both */
  else
    warnf(p, "%s:%d: unknown coordinate system '%s' in CoordSysTransform; ignored", at.file,
          at.line, name);
  free(name);
  return CLR_SUCCESS;
}

/* ---- Include ----------------------------------------------------------------------------- */

static clr_result d_include(parser *p, const directive *d, location at) {
  (void)d;
  clr_token tok;
  CLR_CHECK(next_token(p, &tok));
  if (tok.kind != CLR_TOKEN_STRING) return expected(&tok, "a quoted file name after Include");
  if (p->frame_count > CLR_SCENE_MAX_INCLUDE_DEPTH)
    return clr_set_last_error(CLR_ERROR_PARSE,
                              "%s:%d:%d: expected Include files nested at most %d deep, got deeper "
                              "(recursive Include?)",
                              at.file, at.line, at.col, CLR_SCENE_MAX_INCLUDE_DEPTH);
  const char *dir = tok.text[0] == '/' ? "" : p->frames[p->frame_count - 1].dir;
  size_t n = strlen(dir) + tok.length + 1;
  char *path = malloc(n);
  if (!path) return out_of_memory(at);
  snprintf(path, n, "%s%.*s", dir, (int)tok.length, tok.text);
  char context[512];
  snprintf(context, sizeof context, "%s:%d:%d: Include", at.file, at.line, at.col);
  clr_result r = push_file(p, path, context, at);
  free(path);
  return r;
}

/* ---- options block ----------------------------------------------------------------------- */

static clr_result set_option(parser *p, const directive *d, location at, clr_scene_option *o) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  free(o->type);
  clr_params_free(&o->params);
  o->type = type;
  o->params = params;
  o->given = true;
  return CLR_SUCCESS;
}

static clr_result d_sampler(parser *p, const directive *d, location at) {
  return set_option(p, d, at, &p->desc->sampler);
}
static clr_result d_film(parser *p, const directive *d, location at) {
  return set_option(p, d, at, &p->desc->film);
}
static clr_result d_pixel_filter(parser *p, const directive *d, location at) {
  return set_option(p, d, at, &p->desc->filter);
}
static clr_result d_integrator(parser *p, const directive *d, location at) {
  return set_option(p, d, at, &p->desc->integrator);
}

static clr_result d_camera(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  clr_camera_desc *c = &p->desc->camera;
  free(c->type);
  clr_params_free(&c->params);
  c->type = type;
  c->params = params;
  c->given = true;
  c->camera_to_world = clr_transform_inverse(&p->gs.ctm);
  c->camera_to_world_end = clr_transform_inverse(&p->gs.ctm_end);
  return set_coord_system(p, "camera", &c->camera_to_world, at);
}

static clr_result d_world_begin(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  p->in_world = true;
  p->gs.ctm = p->gs.ctm_end = clr_transform_identity();
  p->gs.transform_active = p->gs.end_active = true;
  clr_transform identity = clr_transform_identity();
  return set_coord_system(p, "world", &identity, at);
}

static clr_result d_world_end(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  warn_unclosed_blocks(p);
  p->done = true;
  return CLR_SUCCESS;
}

/* ---- world block: attributes ------------------------------------------------------------- */

static clr_result d_attribute_begin(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  return push_block(p, BLOCK_ATTRIBUTE, at);
}

static clr_result d_attribute_end(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  return pop_block(p, BLOCK_ATTRIBUTE, at);
}

static clr_result d_transform_begin(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  return push_block(p, BLOCK_TRANSFORM, at);
}

static clr_result d_transform_end(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  return pop_block(p, BLOCK_TRANSFORM, at);
}

static clr_result d_reverse_orientation(parser *p, const directive *d, location at) {
  if (phase_allows(p, d, at)) p->gs.reverse_orientation = !p->gs.reverse_orientation;
  return CLR_SUCCESS;
}

/* ---- world block: materials and textures -------------------------------------------------- */

/* Appends a material, taking ownership of name, type and params. */
static clr_result add_material(parser *p, char *name, char *type, clr_param_list *params,
                               location at, int *index) {
  clr_scene_desc *s = p->desc;
  if (clr_grow_array((void **)&s->materials, &s->material_capacity, s->material_count + 1,
                     sizeof *s->materials) != CLR_SUCCESS) {
    free(name);
    discard_typed(type, params);
    return out_of_memory(at);
  }
  resolve_textures(p, params);
  *index = s->material_count;
  s->materials[s->material_count++] = (clr_material_desc){name, type, *params};
  return CLR_SUCCESS;
}

static clr_result d_material(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  int index;
  CLR_CHECK(add_material(p, NULL, type, &params, at, &index));
  p->gs.material = index;
  p->gs.named_material = NULL;
  return CLR_SUCCESS;
}

static clr_result d_make_named_material(parser *p, const directive *d, location at) {
  char *name;
  clr_param_list params;
  CLR_CHECK(parse_typed_params(p, d, at, &name, &params));
  const char *type = clr_params_find_string(&params, "type", NULL);
  char *type_copy = type ? copy_string(type) : NULL;
  bool allowed = phase_allows(p, d, at);
  if (!allowed || !type_copy) {
    if (allowed && !type)
      warnf(p, "%s:%d: MakeNamedMaterial '%s' has no \"string type\" parameter; ignored", at.file,
            at.line, name);
    free(name);
    free(type_copy);
    clr_params_free(&params);
    return allowed && type ? out_of_memory(at) : CLR_SUCCESS;
  }
  params.type = type_copy;
  int index;
  CLR_CHECK(add_material(p, name, type_copy, &params, at, &index));
  return add_binding(p, BIND_MATERIAL, p->desc->materials[index].name, index, at);
}

static clr_result d_named_material(parser *p, const directive *d, location at) {
  char *name = NULL;
  CLR_CHECK(expect_string(p, "a quoted material name after NamedMaterial", &name));
  if (!phase_allows(p, d, at)) {
    free(name);
    return CLR_SUCCESS;
  }
  const char *pooled = pool_add(p, name);
  free(name);
  if (!pooled) return out_of_memory(at);
  p->gs.named_material = pooled;
  return CLR_SUCCESS;
}

static clr_result d_texture(parser *p, const directive *d, location at) {
  char *name = NULL, *kind = NULL, *type = NULL;
  clr_param_list params;
  clr_result r = expect_string(p, "a quoted texture name after Texture", &name);
  if (r == CLR_SUCCESS)
    r = expect_string(p, "a quoted texture type (\"float\" or \"spectrum\")", &kind);
  if (r == CLR_SUCCESS) r = parse_typed_params(p, d, at, &type, &params);
  bool is_float = kind && strcmp(kind, "float") == 0;
  bool is_spectrum = kind && (strcmp(kind, "spectrum") == 0 || strcmp(kind, "color") == 0);
  bool keep = r == CLR_SUCCESS && phase_allows(p, d, at);
  if (keep && !is_float && !is_spectrum) {
    warnf(p,
          "%s:%d: Texture '%s' has unknown type '%s' (expected \"float\" or \"spectrum\"); "
          "ignored",
          at.file, at.line, name, kind);
    keep = false;
  }
  free(kind);
  if (!keep) {
    free(name);
    if (r == CLR_SUCCESS) discard_typed(type, &params);
    return r;
  }
  clr_scene_desc *s = p->desc;
  if (clr_grow_array((void **)&s->textures, &s->texture_capacity, s->texture_count + 1,
                     sizeof *s->textures) != CLR_SUCCESS) {
    free(name);
    discard_typed(type, &params);
    return out_of_memory(at);
  }
  resolve_textures(p, &params);
  int index = s->texture_count++;
  s->textures[index] = (clr_texture_desc){name, is_float ? CLR_TEXTURE_FLOAT : CLR_TEXTURE_SPECTRUM,
                                          type, params, p->gs.ctm};
  return add_binding(p, is_float ? BIND_FLOAT_TEXTURE : BIND_SPECTRUM_TEXTURE, name, index, at);
}

/* ---- world block: lights and shapes ------------------------------------------------------ */

static clr_result d_light_source(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  clr_scene_desc *s = p->desc;
  if (clr_grow_array((void **)&s->lights, &s->light_capacity, s->light_count + 1,
                     sizeof *s->lights) != CLR_SUCCESS) {
    discard_typed(type, &params);
    return out_of_memory(at);
  }
  s->lights[s->light_count++] = (clr_light_desc){type, params, p->gs.ctm};
  return CLR_SUCCESS;
}

static clr_result d_area_light_source(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  clr_scene_desc *s = p->desc;
  if (clr_grow_array((void **)&s->area_lights, &s->area_light_capacity, s->area_light_count + 1,
                     sizeof *s->area_lights) != CLR_SUCCESS) {
    discard_typed(type, &params);
    return out_of_memory(at);
  }
  p->gs.area_light = s->area_light_count;
  s->area_lights[s->area_light_count++] = (clr_area_light_desc){type, params};
  return CLR_SUCCESS;
}

static int shape_material(parser *p, location at) {
  if (!p->gs.named_material) return p->gs.material;
  int index = find_binding(p, BIND_MATERIAL, p->gs.named_material);
  if (index >= 0) return index;
  warnf(p, "%s:%d: undefined named material '%s'; using the current Material", at.file, at.line,
        p->gs.named_material);
  return p->gs.material;
}

static clr_result d_shape(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  bool kept;
  CLR_CHECK(parse_typed_directive(p, d, at, &type, &params, &kept));
  if (!kept) return CLR_SUCCESS;
  clr_scene_desc *s = p->desc;
  clr_object_desc *object = p->current_object >= 0 ? &s->objects[p->current_object] : NULL;
  if (clr_grow_array((void **)&s->shapes, &s->shape_capacity, s->shape_count + 1,
                     sizeof *s->shapes) != CLR_SUCCESS ||
      (object && clr_grow_array((void **)&object->shapes, &object->shape_capacity,
                                object->shape_count + 1, sizeof *object->shapes) != CLR_SUCCESS)) {
    discard_typed(type, &params);
    return out_of_memory(at);
  }
  int area_light = p->gs.area_light;
  if (object && area_light >= 0) {
    warnf(p,
          "%s:%d: area lights are not supported with object instancing; shape in object '%s' "
          "does not emit",
          at.file, at.line, object->name);
    area_light = -1;
  }
  resolve_textures(p, &params);
  bool moving = memcmp(&p->gs.ctm.m, &p->gs.ctm_end.m, sizeof p->gs.ctm.m) != 0;
  static const char *const movable[] = {"trianglemesh", "plymesh",    "loopsubdiv",
                                        "sphere",       "disk",       "cylinder",
                                        "cone",         "paraboloid", "hyperboloid"};
  bool known = false;
  for (size_t k = 0; k < sizeof movable / sizeof movable[0]; ++k)
    known |= strcmp(type, movable[k]) == 0;
  moving = moving && known; /* the others are not rendered (warned about when built) */
  if (moving && object) {
    clr_result r = clr_set_last_error(
        CLR_ERROR_PARSE,
        "%s:%d:%d: moving Shape \"%s\" (ActiveTransform) inside ObjectBegin '%s' is not "
        "supported: Embree's single instance level cannot move it within its instances",
        at.file, at.line, at.col, type, object->name);
    discard_typed(type, &params);
    return r;
  }
  if (moving && area_light >= 0) { /* pbrt-v3's pbrtShape: "Ignoring currently set area light" */
    warnf(p,
          "%s:%d: moving Shape \"%s\" does not emit: the area light of a moving shape is "
          "ignored, as pbrt-v3 does",
          at.file, at.line, type);
    area_light = -1;
  }
  int index = s->shape_count++;
  s->shapes[index] = (clr_shape_desc){type,
                                      params,
                                      p->gs.ctm,
                                      moving ? p->gs.ctm_end : p->gs.ctm,
                                      p->gs.reverse_orientation,
                                      shape_material(p, at),
                                      area_light,
                                      p->current_object};
  if (object) object->shapes[object->shape_count++] = index;
  return CLR_SUCCESS;
}

/* ---- world block: object instancing ------------------------------------------------------ */

static clr_result d_object_begin(parser *p, const directive *d, location at) {
  char *name = NULL;
  CLR_CHECK(expect_string(p, "a quoted object name after ObjectBegin", &name));
  if (!phase_allows(p, d, at)) {
    free(name);
    return CLR_SUCCESS;
  }
  if (p->current_object >= 0) {
    clr_result r = clr_set_last_error(
        CLR_ERROR_PARSE, "%s:%d:%d: expected ObjectEnd for object '%s', got ObjectBegin '%s'",
        at.file, at.line, at.col, p->desc->objects[p->current_object].name, name);
    free(name);
    return r;
  }
  clr_scene_desc *s = p->desc;
  if (clr_grow_array((void **)&s->objects, &s->object_capacity, s->object_count + 1,
                     sizeof *s->objects) != CLR_SUCCESS) {
    free(name);
    return out_of_memory(at);
  }
  s->objects[s->object_count] = (clr_object_desc){name, NULL, 0, 0};
  p->current_object = s->object_count++;
  return push_block(p, BLOCK_OBJECT, at);
}

static clr_result d_object_end(parser *p, const directive *d, location at) {
  if (!phase_allows(p, d, at)) return CLR_SUCCESS;
  CLR_CHECK(pop_block(p, BLOCK_OBJECT, at));
  p->current_object = -1;
  return CLR_SUCCESS;
}

static clr_result d_object_instance(parser *p, const directive *d, location at) {
  char *name = NULL;
  CLR_CHECK(expect_string(p, "a quoted object name after ObjectInstance", &name));
  clr_scene_desc *s = p->desc;
  int object = clr_scene_desc_find_object(s, name);
  if (!phase_allows(p, d, at)) {
    free(name);
    return CLR_SUCCESS;
  }
  if (p->current_object >= 0)
    warnf(p, "%s:%d: ObjectInstance '%s' inside an object definition; ignored", at.file, at.line,
          name);
  else if (object < 0)
    warnf(p, "%s:%d: ObjectInstance of undefined object '%s'; ignored", at.file, at.line, name);
  free(name);
  if (p->current_object >= 0 || object < 0) return CLR_SUCCESS;
  if (clr_grow_array((void **)&s->instances, &s->instance_capacity, s->instance_count + 1,
                     sizeof *s->instances) != CLR_SUCCESS)
    return out_of_memory(at);
  s->instances[s->instance_count++] =
      (clr_instance_desc){object, p->gs.ctm, p->gs.ctm_end, at.file, at.line};
  return CLR_SUCCESS;
}

/* ---- pbrt-v3 directives outside clrender's subset: parsed, warned about, ignored ----------- */

static void warn_unsupported(parser *p, const directive *d, location at) {
  warnf(p, "%s:%d: %s is not supported by clrender; ignored", at.file, at.line, d->name);
}

static clr_result d_unsupported_typed(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  CLR_CHECK(parse_typed_params(p, d, at, &type, &params));
  discard_typed(type, &params);
  warn_unsupported(p, d, at);
  return CLR_SUCCESS;
}

/* Accelerator: pbrt-v3 accepts it silently when built without that accelerator choice; Embree
 * always builds its own BVH, so the directive and its parameters are parsed and dropped. */
static clr_result d_accelerator(parser *p, const directive *d, location at) {
  char *type;
  clr_param_list params;
  CLR_CHECK(parse_typed_params(p, d, at, &type, &params));
  discard_typed(type, &params);
  return CLR_SUCCESS;
}

static clr_result d_medium_interface(parser *p, const directive *d, location at) {
  char *inside = NULL;
  CLR_CHECK(expect_string(p, "a quoted medium name after MediumInterface", &inside));
  free(inside);
  clr_token tok;
  CLR_CHECK(peek_token(p, &tok));
  if (tok.kind == CLR_TOKEN_STRING) CLR_CHECK(next_token(p, &tok));
  warn_unsupported(p, d, at);
  return CLR_SUCCESS;
}

static clr_result d_transform_times(parser *p, const directive *d, location at) {
  (void)d;
  float v[2];
  CLR_CHECK(expect_numbers(p, 2, v));
  if (!(isfinite(v[0]) && isfinite(v[1]) && v[0] <= v[1]))
    return clr_set_last_error(CLR_ERROR_PARSE,
                              "%s:%d:%d: TransformTimes needs finite start <= end, got %g %g",
                              at.file, at.line, at.col, (double)v[0], (double)v[1]);
  p->desc->transform_start_time = v[0];
  p->desc->transform_end_time = v[1];
  return CLR_SUCCESS;
}

/* pbrt-v3 ActiveTransform: which of the start and end CTMs later edits change. */
static clr_result d_active_transform(parser *p, const directive *d, location at) {
  (void)d;
  (void)at;
  clr_token tok;
  CLR_CHECK(next_token(p, &tok));
  if (clr_token_is(&tok, CLR_TOKEN_WORD, "All"))
    p->gs.transform_active = p->gs.end_active = true;
  else if (clr_token_is(&tok, CLR_TOKEN_WORD, "StartTime"))
    p->gs.transform_active = true, p->gs.end_active = false;
  else if (clr_token_is(&tok, CLR_TOKEN_WORD, "EndTime"))
    p->gs.transform_active = false, p->gs.end_active = true;
  else
    return expected(&tok, "All, StartTime or EndTime after ActiveTransform");
  return CLR_SUCCESS;
}

/* ---- dispatch ---------------------------------------------------------------------------- */

static const directive directives[] = {
    {"AttributeBegin", d_attribute_begin, PHASE_WORLD, 0, NULL},
    {"AttributeEnd", d_attribute_end, PHASE_WORLD, 0, NULL},
    {"AreaLightSource", d_area_light_source, PHASE_WORLD, 0, NULL},
    {"Camera", d_camera, PHASE_OPTIONS, 0, NULL},
    {"ConcatTransform", d_concat_transform, PHASE_ANY, 0, NULL},
    {"CoordinateSystem", d_coordinate_system, PHASE_ANY, 0, NULL},
    {"CoordSysTransform", d_coord_sys_transform, PHASE_ANY, 0, NULL},
    {"Film", d_film, PHASE_OPTIONS, 0, NULL},
    {"Identity", d_identity, PHASE_ANY, 0, NULL},
    {"Include", d_include, PHASE_ANY, 0, NULL},
    {"Integrator", d_integrator, PHASE_OPTIONS, 0, NULL},
    {"LightSource", d_light_source, PHASE_WORLD, 0, NULL},
    {"LookAt", d_numeric_transform, PHASE_ANY, 9, build_look_at},
    {"MakeNamedMaterial", d_make_named_material, PHASE_WORLD, 0, NULL},
    {"Material", d_material, PHASE_WORLD, 0, NULL},
    {"NamedMaterial", d_named_material, PHASE_WORLD, 0, NULL},
    {"ObjectBegin", d_object_begin, PHASE_WORLD, 0, NULL},
    {"ObjectEnd", d_object_end, PHASE_WORLD, 0, NULL},
    {"ObjectInstance", d_object_instance, PHASE_WORLD, 0, NULL},
    {"PixelFilter", d_pixel_filter, PHASE_OPTIONS, 0, NULL},
    {"ReverseOrientation", d_reverse_orientation, PHASE_WORLD, 0, NULL},
    {"Rotate", d_numeric_transform, PHASE_ANY, 4, build_rotate},
    {"Sampler", d_sampler, PHASE_OPTIONS, 0, NULL},
    {"Scale", d_numeric_transform, PHASE_ANY, 3, build_scale},
    {"Shape", d_shape, PHASE_WORLD, 0, NULL},
    {"Texture", d_texture, PHASE_WORLD, 0, NULL},
    {"Transform", d_transform, PHASE_ANY, 0, NULL},
    {"TransformBegin", d_transform_begin, PHASE_WORLD, 0, NULL},
    {"TransformEnd", d_transform_end, PHASE_WORLD, 0, NULL},
    {"Translate", d_numeric_transform, PHASE_ANY, 3, build_translate},
    {"WorldBegin", d_world_begin, PHASE_OPTIONS, 0, NULL},
    {"WorldEnd", d_world_end, PHASE_WORLD, 0, NULL},
    /* pbrt-v3 directives outside the subset. */
    {"Accelerator", d_accelerator, PHASE_ANY, 0, NULL},
    {"ActiveTransform", d_active_transform, PHASE_ANY, 0, NULL},
    {"MakeNamedMedium", d_unsupported_typed, PHASE_ANY, 0, NULL},
    {"MediumInterface", d_medium_interface, PHASE_ANY, 0, NULL},
    {"TransformTimes", d_transform_times, PHASE_ANY, 0, NULL},
};

static const directive *find_directive(const clr_token *tok) {
  for (size_t i = 0; i < sizeof directives / sizeof directives[0]; ++i)
    if (clr_token_is(tok, CLR_TOKEN_WORD, directives[i].name)) return &directives[i];
  return NULL;
}

static clr_result parse_directives(parser *p) {
  for (;;) {
    clr_token tok;
    CLR_CHECK(next_token(p, &tok));
    if (tok.kind == CLR_TOKEN_EOF) break;
    if (p->done) {
      warnf(p, "%s:%d: ignoring everything after WorldEnd", tok.file, tok.line);
      return CLR_SUCCESS;
    }
    const directive *d = find_directive(&tok);
    if (!d) return expected(&tok, "a directive");
    CLR_CHECK(d->handler(p, d, (location){tok.file, tok.line, tok.col}));
  }
  warn_unclosed_blocks(p);
  return CLR_SUCCESS;
}

/* ---- entry points ------------------------------------------------------------------------ */

void clr_parse_options_init(clr_parse_options *opts) {
  if (!opts) return;
  opts->warn = clr_warn_stderr;
  opts->warn_user = NULL;
}

static clr_result parser_init(parser *p, const clr_parse_options *opts) {
  memset(p, 0, sizeof *p);
  p->warn = opts && opts->warn ? opts->warn : clr_warn_stderr;
  p->warn_user = opts ? opts->warn_user : NULL;
  p->desc = clr_scene_desc_create();
  if (!p->desc)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_scene_parse: out of memory creating the scene");
  p->gs.ctm = p->gs.ctm_end = clr_transform_identity();
  p->gs.transform_active = p->gs.end_active = true;
  p->gs.material = 0;
  p->gs.area_light = -1;
  p->current_object = -1;
  return CLR_SUCCESS;
}

/* Frees everything but the description, which goes to *out on success. */
static clr_result parser_finish(parser *p, clr_result r, clr_scene_desc **out) {
  while (p->frame_count > 0) pop_frame(p);
  for (int i = 0; i < p->coord_count; ++i) free(p->coords[i].name);
  free(p->coords);
  for (int i = 0; i < p->pool_count; ++i) free(p->pool[i]);
  free(p->pool);
  free(p->blocks);
  free(p->bindings);
  if (r != CLR_SUCCESS) {
    clr_scene_desc_free(p->desc);
    return r;
  }
  *out = p->desc;
  return CLR_SUCCESS;
}

clr_result clr_scene_parse_file(const char *path, const clr_parse_options *opts,
                                clr_scene_desc **out) {
  if (out) *out = NULL;
  if (!path || !out)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_scene_parse_file: %s is NULL",
                              !path ? "path" : "out");
  parser p;
  clr_result r = parser_init(&p, opts);
  if (r != CLR_SUCCESS) return r;
  r = push_file(&p, path, "clr_scene_parse_file", (location){path, 0, 0});
  if (r == CLR_SUCCESS) r = parse_directives(&p);
  if (r == CLR_SUCCESS && !p.in_world) /* empty, or not a scene file at all */
    r = clr_set_last_error(CLR_ERROR_PARSE,
                           "%s: not a pbrt scene: expected WorldBegin, got none (empty file or "
                           "no world block)",
                           path);
  return parser_finish(&p, r, out);
}

clr_result clr_scene_parse_string(const char *text, const char *virtual_path,
                                  const clr_parse_options *opts, clr_scene_desc **out) {
  if (out) *out = NULL;
  if (!text || !out)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_scene_parse_string: %s is NULL",
                              !text ? "text" : "out");
  parser p;
  clr_result r = parser_init(&p, opts);
  if (r != CLR_SUCCESS) return r;
  const char *path = virtual_path ? virtual_path : "<string>";
  location at = {path, 0, 0};
  const char *stored = clr_scene_desc_add_file(p.desc, path);
  include_frame *f = &p.frames[0];
  if (!stored || !(f->dir = directory_of(stored))) {
    r = out_of_memory(at);
  } else {
    r = clr_tokenizer_open_string(&f->tokenizer, text, strlen(text), stored);
    if (r == CLR_SUCCESS)
      p.frame_count = 1;
    else {
      free(f->dir);
      f->dir = NULL;
    }
  }
  if (r == CLR_SUCCESS) r = parse_directives(&p);
  return parser_finish(&p, r, out);
}
