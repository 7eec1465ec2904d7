/* Small strict parsers for CLI flag values: each returns 0 and prints nothing on bad input. */
#ifndef CLR_CLI_ARGS_H
#define CLR_CLI_ARGS_H

#include <stdint.h>

int cli_parse_int(const char *s, long min, long max, int32_t *out);
int cli_parse_float(const char *s, float *out);
/* "a,b,c" with exactly n integers. */
int cli_parse_ints(const char *s, int n, int32_t *out);
/* A device or a comma list of devices without an empty entry ("0,,1", ",0", "0," or ""). */
int cli_device_list_ok(const char *s);
/* "WxH" */
int cli_parse_resolution(const char *s, int32_t *w, int32_t *h);

#endif
