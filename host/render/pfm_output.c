/* Portable float map output (pbrt-v3 WritePFM): "PF", width height, -1 (little-endian), then
 * float RGB rows bottom to top. Written to a temporary name and renamed onto the path. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "clrender/result.h"
#include "pfm_output.h"

static int host_is_little_endian(void) {
  const uint16_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1;
}

clr_result clr_write_pfm(const char *path, const float *rgb, int width, int height) {
  if (!path || !rgb || width <= 0 || height <= 0)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "PFM output: bad image");
  size_t n = strlen(path) + 16;
  char *tmp = malloc(n);
  if (!tmp) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "PFM output");
  snprintf(tmp, n, "%s.tmp%ld", path, (long)getpid() % 1000000000L);
  FILE *f = fopen(tmp, "wb");
  if (!f) {
    free(tmp);
    return clr_set_last_error(CLR_ERROR_IO, "%s: cannot write", path);
  }
  int ok = fprintf(f, "PF\n%d %d\n%s\n", width, height, host_is_little_endian() ? "-1" : "1") > 0;
  for (int y = height - 1; ok && y >= 0; --y)
    ok = fwrite(rgb + (size_t)3 * (size_t)width * (size_t)y, sizeof(float),
                (size_t)3 * (size_t)width, f) == (size_t)3 * (size_t)width;
  ok = fclose(f) == 0 && ok;
  if (!ok || rename(tmp, path) != 0) {
    remove(tmp);
    free(tmp);
    return clr_set_last_error(CLR_ERROR_IO, "%s: cannot write", path);
  }
  free(tmp);
  return CLR_SUCCESS;
}
