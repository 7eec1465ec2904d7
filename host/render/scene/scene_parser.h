/* pbrt-v3 scene file parser: builds a clr_scene_desc following pbrt-v3's api.cpp semantics
 * (graphics state stack, named materials/textures, object instancing, camera transform). */
#ifndef CLR_SCENE_PARSER_H
#define CLR_SCENE_PARSER_H

#include "clrender/result.h"
#include "scene_desc.h"

/* Deepest allowed nesting of Include files below the main file. */
#define CLR_SCENE_MAX_INCLUDE_DEPTH 32

typedef struct clr_parse_options {
  /* Receives warnings ("FILE:LINE: ..."): unsupported directives, spectral parameter types,
   * undefined names, unclosed blocks. NULL prints them to stderr. */
  clr_warn_fn warn;
  void *warn_user;
} clr_parse_options;

void clr_parse_options_init(clr_parse_options *opts);

/* Parses a scene file (Include paths are relative to the including file's directory). On
 * success *out owns a new description (free with clr_scene_desc_free); on failure *out is NULL
 * and clr_last_error_message() holds "FILE:LINE:COL: expected X, got Y":
 *   CLR_ERROR_PARSE  syntax errors: unterminated string or bracket, unknown directive, unknown
 *                    parameter type, value count not a multiple of the type's arity,
 *                    non-numeric value where numbers are expected, AttributeEnd/TransformEnd/
 *                    ObjectEnd without its Begin, Include nested deeper than 32;
 *   CLR_ERROR_IO     the file or an Include file cannot be read (names the file and the
 *                    including FILE:LINE);
 *   CLR_ERROR_NULL_POINTER, CLR_ERROR_OUT_OF_MEMORY.
 *   CLR_ERROR_SCENE  a zero Scale factor.
 * A missing WorldEnd is fine; a file without WorldBegin (empty, or not a scene) is
 * CLR_ERROR_PARSE. opts may be NULL. */
clr_result clr_scene_parse_file(const char *path, const clr_parse_options *opts,
                                clr_scene_desc **out);
/* Same for text in memory; virtual_path (may be NULL: "<string>") names it in messages and its
 * directory is the base of relative Include paths. */
clr_result clr_scene_parse_string(const char *text, const char *virtual_path,
                                  const clr_parse_options *opts, clr_scene_desc **out);

#endif
