/* PLY mesh reader (ASCII, binary little and big endian) for pbrt-v3's "plymesh" shape. */
#include "ply_reader.h"

#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"
#include "render_input.h"

#define PLY_MAX_ELEMENTS 32
#define PLY_MAX_PROPERTIES 64
#define PLY_MAX_NAME 64
#define PLY_MAX_LIST_LENGTH 4096 /* longer lists in the face element are treated as corrupt */

typedef enum ply_type {
  PLY_NONE,
  PLY_I8,
  PLY_U8,
  PLY_I16,
  PLY_U16,
  PLY_I32,
  PLY_U32,
  PLY_F32,
  PLY_F64
} ply_type;
typedef enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE } ply_format;
/* What a property feeds: a component of the output mesh or nothing. */
typedef enum ply_role {
  ROLE_SKIP,
  ROLE_X,
  ROLE_Y,
  ROLE_Z,
  ROLE_NX,
  ROLE_NY,
  ROLE_NZ,
  ROLE_U,
  ROLE_V,
  ROLE_INDICES
} ply_role;

typedef struct ply_property {
  char name[PLY_MAX_NAME];
  ply_type type;       /* scalar type, or item type of a list */
  ply_type count_type; /* PLY_NONE for scalars */
  ply_role role;
} ply_property;

typedef struct ply_element {
  char name[PLY_MAX_NAME];
  long long count;
  int property_count;
  ply_property properties[PLY_MAX_PROPERTIES];
} ply_element;

typedef struct ply_file {
  const char *path;
  unsigned char *data;
  size_t size, pos;
  ply_format format;
  int swap;      /* binary data whose byte order differs from the host's */
  int truncated; /* a value was asked for past the end of the data */
  int bad_count; /* a list count was not a non-negative integer fitting its type */
  int element_count;
  ply_element elements[PLY_MAX_ELEMENTS];
} ply_file;

static const struct {
  const char *name;
  ply_type type;
  size_t size;
} ply_types[] = {{"char", PLY_I8, 1},    {"int8", PLY_I8, 1},     {"uchar", PLY_U8, 1},
                 {"uint8", PLY_U8, 1},   {"short", PLY_I16, 2},   {"int16", PLY_I16, 2},
                 {"ushort", PLY_U16, 2}, {"uint16", PLY_U16, 2},  {"int", PLY_I32, 4},
                 {"int32", PLY_I32, 4},  {"uint", PLY_U32, 4},    {"uint32", PLY_U32, 4},
                 {"float", PLY_F32, 4},  {"float32", PLY_F32, 4}, {"double", PLY_F64, 8},
                 {"float64", PLY_F64, 8}};

static ply_type type_from_name(const char *name) {
  for (size_t i = 0; i < sizeof ply_types / sizeof ply_types[0]; ++i)
    if (!strcmp(ply_types[i].name, name)) return ply_types[i].type;
  return PLY_NONE;
}

static size_t type_size(ply_type type) {
  for (size_t i = 0; i < sizeof ply_types / sizeof ply_types[0]; ++i)
    if (ply_types[i].type == type) return ply_types[i].size;
  return 0;
}

/* ---- whole-file loading ---- */

static clr_result load_file(ply_file *f) {
  char *data = NULL;
  CLR_CHECK(clr_read_input_file(f->path, "clr_ply_read", CLR_PLY_MAX_FILE_BYTES, &data, &f->size));
  f->data = (unsigned char *)data;
  return CLR_SUCCESS;
}

/* ---- header ---- */

/* CLR_ERROR_FILE_FORMAT for a malformed header line, naming the file and the line. */
static clr_result header_fail(const ply_file *f, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static clr_result header_fail(const ply_file *f, int line, const char *fmt, ...) {
  char detail[256];
  va_list args;
  va_start(args, fmt);
  vsnprintf(detail, sizeof detail, fmt, args);
  va_end(args);
  return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                            "clr_ply_read: \"%s\": malformed header, line %d: %s", f->path, line,
                            detail);
}

/* Splits the next header line into at most 8 whitespace-separated words (in `buf`); returns the
 * word count, or -1 at the end of the data. */
static int next_header_line(ply_file *f, char *buf, size_t buf_size, char *words[8]) {
  if (f->pos >= f->size) return -1;
  size_t len = 0;
  while (f->pos < f->size && f->data[f->pos] != '\n') {
    if (len + 1 < buf_size) buf[len++] = (char)f->data[f->pos];
    ++f->pos;
  }
  if (f->pos < f->size) ++f->pos; /* the '\n' */
  buf[len] = 0;
  int count = 0;
  char *s = buf;
  while (count < 8) {
    while (*s == ' ' || *s == '\t' || *s == '\r') *s++ = 0;
    if (!*s) break;
    words[count++] = s;
    while (*s && *s != ' ' && *s != '\t' && *s != '\r') ++s;
  }
  return count;
}

static int host_is_little_endian(void) {
  const uint16_t one = 1;
  unsigned char first;
  memcpy(&first, &one, 1);
  return first == 1;
}

static clr_result parse_format(ply_file *f, int line, char **words, int n) {
  if (n != 3 || strcmp(words[2], "1.0"))
    return header_fail(f, line, "expected \"format <type> 1.0\"");
  if (!strcmp(words[1], "ascii"))
    f->format = PLY_ASCII;
  else if (!strcmp(words[1], "binary_little_endian"))
    f->format = PLY_BINARY_LE;
  else if (!strcmp(words[1], "binary_big_endian"))
    f->format = PLY_BINARY_BE;
  else
    return header_fail(f, line, "unknown format \"%s\"", words[1]);
  f->swap = f->format != PLY_ASCII && (f->format == PLY_BINARY_LE) != host_is_little_endian();
  return CLR_SUCCESS;
}

static clr_result parse_element(ply_file *f, int line, char **words, int n) {
  if (n != 3) return header_fail(f, line, "expected \"element <name> <count>\"");
  if (f->element_count == PLY_MAX_ELEMENTS)
    return header_fail(f, line, "more than %d elements", PLY_MAX_ELEMENTS);
  char *end;
  errno = 0;
  long long count = strtoll(words[2], &end, 10);
  if (*end || errno || count < 0)
    return header_fail(f, line, "bad count \"%s\" for element \"%s\"", words[2], words[1]);
  ply_element *e = &f->elements[f->element_count++];
  memset(e, 0, sizeof *e);
  snprintf(e->name, sizeof e->name, "%s", words[1]);
  e->count = count;
  return CLR_SUCCESS;
}

static clr_result parse_property(ply_file *f, int line, char **words, int n) {
  if (f->element_count == 0) return header_fail(f, line, "property before any element");
  ply_element *e = &f->elements[f->element_count - 1];
  if (e->property_count == PLY_MAX_PROPERTIES)
    return header_fail(f, line, "element \"%s\" has more than %d properties", e->name,
                       PLY_MAX_PROPERTIES);
  ply_property *p = &e->properties[e->property_count];
  memset(p, 0, sizeof *p);
  int is_list = n >= 2 && !strcmp(words[1], "list");
  if (is_list ? n != 5 : n != 3)
    return header_fail(f, line,
                       "expected \"property <type> <name>\" or \"property list <count "
                       "type> <item type> <name>\"");
  const char *type_name = words[is_list ? 3 : 1];
  p->type = type_from_name(type_name);
  if (is_list) {
    p->count_type = type_from_name(words[2]);
    if (p->count_type == PLY_NONE || p->count_type == PLY_F32 || p->count_type == PLY_F64)
      return header_fail(f, line, "bad list count type \"%s\"", words[2]);
  }
  if (p->type == PLY_NONE) return header_fail(f, line, "unknown property type \"%s\"", type_name);
  snprintf(p->name, sizeof p->name, "%s", words[is_list ? 4 : 2]);
  ++e->property_count;
  return CLR_SUCCESS;
}

static clr_result parse_header(ply_file *f) {
  char buf[512], *words[8];
  int line = 1, n = next_header_line(f, buf, sizeof buf, words);
  if (n != 1 || strcmp(words[0], "ply"))
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\" is not a PLY file (no \"ply\" "
                              "magic line)",
                              f->path);
  int have_format = 0;
  for (;;) {
    ++line;
    n = next_header_line(f, buf, sizeof buf, words);
    if (n < 0) return header_fail(f, line, "end of file before \"end_header\"");
    if (n == 0 || !strcmp(words[0], "comment") || !strcmp(words[0], "obj_info")) continue;
    if (!strcmp(words[0], "end_header")) break;
    if (!strcmp(words[0], "format")) {
      CLR_CHECK(parse_format(f, line, words, n));
      have_format = 1;
    } else if (!strcmp(words[0], "element")) {
      CLR_CHECK(parse_element(f, line, words, n));
    } else if (!strcmp(words[0], "property")) {
      CLR_CHECK(parse_property(f, line, words, n));
    } else {
      return header_fail(f, line, "unknown keyword \"%s\"", words[0]);
    }
  }
  if (!have_format) return header_fail(f, line, "no \"format\" line");
  return CLR_SUCCESS;
}

/* ---- property roles ---- */

static ply_element *find_element(ply_file *f, const char *name) {
  for (int i = 0; i < f->element_count; ++i)
    if (!strcmp(f->elements[i].name, name)) return &f->elements[i];
  return NULL;
}

static ply_property *find_scalar(ply_element *e, const char *name) {
  for (int i = 0; i < e->property_count; ++i)
    if (e->properties[i].count_type == PLY_NONE && !strcmp(e->properties[i].name, name))
      return &e->properties[i];
  return NULL;
}

/* Gives each named property of `e` its role if all of them exist; returns whether they do. */
static int assign_roles(ply_element *e, const char *const *names, const ply_role *roles, int n) {
  ply_property *found[3];
  for (int i = 0; i < n; ++i)
    if (!(found[i] = find_scalar(e, names[i]))) return 0;
  for (int i = 0; i < n; ++i) found[i]->role = roles[i];
  return 1;
}

static clr_result assign_vertex_roles(ply_file *f, ply_element *v, int *has_normals, int *has_uv) {
  static const char *const xyz[3] = {"x", "y", "z"}, *const nxyz[3] = {"nx", "ny", "nz"};
  static const char *const uv_names[4][2] = {
      {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
  static const ply_role p_roles[3] = {ROLE_X, ROLE_Y, ROLE_Z},
                        n_roles[3] = {ROLE_NX, ROLE_NY, ROLE_NZ}, uv_roles[2] = {ROLE_U, ROLE_V};
  if (!assign_roles(v, xyz, p_roles, 3))
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\": element \"vertex\" lacks one of "
                              "the scalar properties x, y, z",
                              f->path);
  *has_normals = assign_roles(v, nxyz, n_roles, 3);
  *has_uv = 0;
  for (int i = 0; i < 4 && !*has_uv; ++i) *has_uv = assign_roles(v, uv_names[i], uv_roles, 2);
  return CLR_SUCCESS;
}

static clr_result assign_face_roles(ply_file *f, ply_element *face) {
  for (int i = 0; i < face->property_count; ++i) {
    ply_property *p = &face->properties[i];
    if (p->count_type != PLY_NONE &&
        (!strcmp(p->name, "vertex_indices") || !strcmp(p->name, "vertex_index"))) {
      p->role = ROLE_INDICES;
      return CLR_SUCCESS;
    }
  }
  return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                            "clr_ply_read: \"%s\": element \"face\" has no list "
                            "property \"vertex_indices\"",
                            f->path);
}

/* ---- data values ---- */

static double decode_binary(const unsigned char *src, ply_type type, int swap) {
  unsigned char b[8];
  size_t size = type_size(type);
  for (size_t i = 0; i < size; ++i) b[i] = src[swap ? size - 1 - i : i];
  switch (type) {
    case PLY_I8: {
      int8_t v;
      memcpy(&v, b, 1);
      return v;
    }
    case PLY_U8:
      return b[0];
    case PLY_I16: {
      int16_t v;
      memcpy(&v, b, 2);
      return v;
    }
    case PLY_U16: {
      uint16_t v;
      memcpy(&v, b, 2);
      return v;
    }
    case PLY_I32: {
      int32_t v;
      memcpy(&v, b, 4);
      return v;
    }
    case PLY_U32: {
      uint32_t v;
      memcpy(&v, b, 4);
      return v;
    }
    case PLY_F32: {
      float v;
      memcpy(&v, b, 4);
      return v;
    }
    case PLY_F64: {
      double v;
      memcpy(&v, b, 8);
      return v;
    }
    default:
      return 0.0;
  }
}

static int out_of_data(ply_file *f) {
  f->truncated = 1;
  return 0;
}

/* Reads one value of `type`; returns 0 when the data ends or (ASCII) is not a number. */
static int read_value(ply_file *f, ply_type type, double *out) {
  if (f->format != PLY_ASCII) {
    size_t size = type_size(type);
    if (f->size - f->pos < size) return out_of_data(f);
    *out = decode_binary(f->data + f->pos, type, f->swap);
    f->pos += size;
    return 1;
  }
  while (f->pos < f->size && (f->data[f->pos] == ' ' || f->data[f->pos] == '\t' ||
                              f->data[f->pos] == '\r' || f->data[f->pos] == '\n'))
    ++f->pos;
  if (f->pos >= f->size) return out_of_data(f);
  char *start = (char *)f->data + f->pos, *end; /* the buffer is NUL-terminated */
  *out = strtod(start, &end);
  if (end == start) return 0;
  f->pos += (size_t)(end - start);
  return 1;
}

/* Largest value of an integer PLY type (list counts must fit their declared type). */
static double type_max(ply_type type) {
  switch (type) {
    case PLY_I8:
      return 127.0;
    case PLY_U8:
      return 255.0;
    case PLY_I16:
      return 32767.0;
    case PLY_U16:
      return 65535.0;
    case PLY_I32:
      return 2147483647.0;
    case PLY_U32:
      return 4294967295.0;
    default:
      return 0.0;
  }
}

/* Reads a list's element count: a non-negative integer that fits the count type (ASCII counts
 * such as 1e30, inf, nan, -1 or 2.5 are refused before any conversion). */
static int read_list_count(ply_file *f, ply_type type, long long *count) {
  double value;
  if (!read_value(f, type, &value)) return 0;
  if (!(value >= 0 && value <= type_max(type)) || value != floor(value)) {
    f->bad_count = 1;
    return 0;
  }
  *count = (long long)value;
  return 1;
}

static clr_result data_error(ply_file *f, const ply_element *e, long long instance,
                             const ply_property *p) {
  const char *what = f->truncated ? "truncated data"
                     : f->bad_count
                         ? "bad list count (not a non-negative integer that fits its type)"
                         : "bad value";
  return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                            "clr_ply_read: \"%s\": %s in element \"%s\" instance %lld "
                            "of %lld, property \"%s\" (byte offset %zu)",
                            f->path, what, e->name, instance, e->count, p->name, f->pos);
}

/* Rejects header counts that cannot fit in the remaining bytes (so corrupt counts never drive a
 * huge allocation): binary instances need their fixed-size bytes, ASCII values two bytes each. */
static clr_result check_counts_fit(ply_file *f) {
  size_t remaining = f->size - f->pos + 1;
  for (int i = 0; i < f->element_count; ++i) {
    const ply_element *e = &f->elements[i];
    size_t per_instance = 0;
    for (int k = 0; k < e->property_count; ++k) {
      const ply_property *p = &e->properties[k];
      if (f->format == PLY_ASCII)
        per_instance += 2;
      else
        per_instance += type_size(p->count_type != PLY_NONE ? p->count_type : p->type);
    }
    if (per_instance && (unsigned long long)e->count > remaining / per_instance)
      return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                                "clr_ply_read: \"%s\": truncated data: element \"%s\" "
                                "declares %lld instances but only %zu bytes of data remain",
                                f->path, e->name, e->count, remaining - 1);
    remaining -= (size_t)e->count * per_instance;
  }
  return CLR_SUCCESS;
}

/* ---- element readers ---- */

static clr_result read_vertices(ply_file *f, const ply_element *e, clr_mesh *mesh) {
  for (long long i = 0; i < e->count; ++i) {
    for (int k = 0; k < e->property_count; ++k) {
      const ply_property *p = &e->properties[k];
      double value;
      if (p->count_type != PLY_NONE) {
        long long count;
        if (!read_list_count(f, p->count_type, &count)) return data_error(f, e, i, p);
        for (long long j = 0; j < count; ++j)
          if (!read_value(f, p->type, &value)) return data_error(f, e, i, p);
        continue;
      }
      if (!read_value(f, p->type, &value)) return data_error(f, e, i, p);
      float v = (float)value;
      switch (p->role) {
        case ROLE_X:
        case ROLE_Y:
        case ROLE_Z:
          mesh->p[3 * i + (p->role - ROLE_X)] = v;
          break;
        case ROLE_NX:
        case ROLE_NY:
        case ROLE_NZ:
          mesh->n[3 * i + (p->role - ROLE_NX)] = v;
          break;
        case ROLE_U:
        case ROLE_V:
          mesh->uv[2 * i + (p->role - ROLE_U)] = v;
          break;
        default:
          break;
      }
    }
  }
  return CLR_SUCCESS;
}

/* Reads one "vertex_indices" list, appending its 1 or 2 triangles (none for other lengths). */
static clr_result read_face_indices(ply_file *f, const ply_element *e, long long i,
                                    const ply_property *p, clr_mesh *mesh) {
  long long count;
  if (!read_list_count(f, p->count_type, &count)) return data_error(f, e, i, p);
  if (count > PLY_MAX_LIST_LENGTH)
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\": element \"face\" instance %lld "
                              "has %lld vertex indices (at most %d supported)",
                              f->path, i, count, PLY_MAX_LIST_LENGTH);
  uint32_t face[4];
  for (long long j = 0; j < count; ++j) {
    double value;
    if (!read_value(f, p->type, &value)) return data_error(f, e, i, p);
    if (!(value >= 0 && value < mesh->vertex_count) || value != floor(value))
      return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                                "clr_ply_read: \"%s\": element \"face\" instance %lld, "
                                "vertex_indices[%lld] = %g is outside [0, %ld)",
                                f->path, i, j, value, (long)mesh->vertex_count);
    if (j < 4) face[j] = (uint32_t)value;
  }
  if (count != 3 && count != 4) return CLR_SUCCESS; /* pbrt-v3 ignores such faces too */
  uint32_t *t = mesh->indices + 3 * (size_t)mesh->triangle_count;
  t[0] = face[0], t[1] = face[1], t[2] = face[2];
  ++mesh->triangle_count;
  if (count == 4) {
    t[3] = face[3], t[4] = face[0], t[5] = face[2];
    ++mesh->triangle_count;
  }
  return CLR_SUCCESS;
}

static clr_result read_faces(ply_file *f, const ply_element *e, clr_mesh *mesh) {
  for (long long i = 0; i < e->count; ++i) {
    for (int k = 0; k < e->property_count; ++k) {
      const ply_property *p = &e->properties[k];
      double value;
      if (p->role == ROLE_INDICES) {
        CLR_CHECK(read_face_indices(f, e, i, p, mesh));
      } else if (p->count_type != PLY_NONE) {
        long long count;
        if (!read_list_count(f, p->count_type, &count)) return data_error(f, e, i, p);
        for (long long j = 0; j < count; ++j)
          if (!read_value(f, p->type, &value)) return data_error(f, e, i, p);
      } else if (!read_value(f, p->type, &value)) {
        return data_error(f, e, i, p);
      }
    }
  }
  return CLR_SUCCESS;
}

static clr_result skip_element(ply_file *f, const ply_element *e) {
  if (e->property_count == 0) return CLR_SUCCESS; /* any count of empty instances */
  for (long long i = 0; i < e->count; ++i) {
    for (int k = 0; k < e->property_count; ++k) {
      const ply_property *p = &e->properties[k];
      double value;
      long long count = 1;
      if (p->count_type != PLY_NONE && !read_list_count(f, p->count_type, &count))
        return data_error(f, e, i, p);
      for (long long j = 0; j < count; ++j)
        if (!read_value(f, p->type, &value)) return data_error(f, e, i, p);
    }
  }
  return CLR_SUCCESS;
}

static clr_result read_body(ply_file *f, clr_mesh *mesh) {
  ply_element *vertex = find_element(f, "vertex"), *face = find_element(f, "face");
  if (!vertex || !face || vertex->count == 0 || face->count == 0)
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\": no \"vertex\" and \"face\" "
                              "elements with instances",
                              f->path);
  int has_normals = 0, has_uv = 0;
  CLR_CHECK(assign_vertex_roles(f, vertex, &has_normals, &has_uv));
  CLR_CHECK(assign_face_roles(f, face));
  CLR_CHECK(check_counts_fit(f));
  if (vertex->count > INT32_MAX / 3 || face->count > INT32_MAX / 6)
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\": too many vertices (%lld) or "
                              "faces (%lld)",
                              f->path, vertex->count, face->count);
  CLR_CHECK(clr_mesh_alloc(mesh, (int32_t)vertex->count, (int32_t)(2 * face->count), has_normals,
                           has_uv, f->path));
  mesh->triangle_count = 0; /* counts the triangles actually read */
  for (int i = 0; i < f->element_count; ++i) {
    ply_element *e = &f->elements[i];
    if (e == vertex)
      CLR_CHECK(read_vertices(f, e, mesh));
    else if (e == face)
      CLR_CHECK(read_faces(f, e, mesh));
    else
      CLR_CHECK(skip_element(f, e));
  }
  if (mesh->triangle_count == 0)
    return clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                              "clr_ply_read: \"%s\": no triangles (%lld faces, "
                              "none with 3 or 4 vertex indices)",
                              f->path, face->count);
  return clr_mesh_check(mesh, f->path, CLR_ERROR_FILE_FORMAT);
}

clr_result clr_ply_read(const char *path, clr_mesh *out) {
  if (!out) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_ply_read: out is NULL");
  memset(out, 0, sizeof *out);
  if (!path) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_ply_read: path is NULL");
  ply_file *f = calloc(1, sizeof *f);
  if (!f)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "clr_ply_read: no memory for \"%s\"", path);
  f->path = path;
  clr_result r = load_file(f);
  if (r == CLR_SUCCESS) r = parse_header(f);
  if (r == CLR_SUCCESS) r = read_body(f, out);
  if (r != CLR_SUCCESS) clr_mesh_free(out);
  free(f->data);
  free(f);
  return r;
}
