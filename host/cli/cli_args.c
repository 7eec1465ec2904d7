/* Strict numeric parsing for CLI flags: the whole string must be a number in range. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "cli_args.h"

int cli_parse_int(const char *s, long min, long max, int32_t *out) {
  if (!s || !*s) return 0;
  char *end = NULL;
  errno = 0;
  long v = strtol(s, &end, 10);
  if (errno || *end || v < min || v > max) return 0;
  *out = (int32_t)v;
  return 1;
}

int cli_parse_float(const char *s, float *out) {
  if (!s || !*s) return 0;
  char *end = NULL;
  errno = 0;
  float v = strtof(s, &end);
  if (errno || *end || !isfinite(v)) return 0;
  *out = v;
  return 1;
}

int cli_parse_ints(const char *s, int n, int32_t *out) {
  if (!s) return 0;
  const char *p = s;
  for (int i = 0; i < n; ++i) {
    char *end = NULL;
    errno = 0;
    long v = strtol(p, &end, 10);
    if (end == p || errno || v < INT32_MIN || v > INT32_MAX) return 0;
    out[i] = (int32_t)v;
    if (i + 1 < n) {
      if (*end != ',') return 0;
      p = end + 1;
    } else if (*end) {
      return 0;
    }
  }
  return 1;
}

int cli_device_list_ok(const char *s) {
  if (!s || !*s || *s == ',') return 0;
  for (const char *p = s; *p; ++p)
    if (*p == ',' && (p[1] == ',' || p[1] == 0)) return 0;
  return 1;
}

int cli_parse_resolution(const char *s, int32_t *w, int32_t *h) {
  if (!s) return 0;
  const char *x = strchr(s, 'x');
  if (!x || x == s) return 0;
  char buf[32];
  size_t n = (size_t)(x - s);
  if (n >= sizeof buf) return 0;
  memcpy(buf, s, n);
  buf[n] = 0;
  return cli_parse_int(buf, 1, 1L << 30, w) && cli_parse_int(x + 1, 1, 1L << 30, h);
}
