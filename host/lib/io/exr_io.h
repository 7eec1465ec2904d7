/* OpenEXR image files through the OpenEXR 3 C API (OpenEXRCore): single-part scanline images. */
#ifndef CLR_EXR_IO_H
#define CLR_EXR_IO_H

#include <stdint.h>
#include "clrender/result.h"
#include "clrender/sampler.h" /* clr_bounds2i */

/* One channel to write: `data` holds data-window width * height floats, row-major; `half` != 0
 * stores it as 16-bit half (rounded to nearest even), else as 32-bit float. */
typedef struct clr_exr_channel {
  const char *name;
  const float *data;
  int32_t half;
} clr_exr_channel;

enum { CLR_EXR_ATTR_STRING = 0, CLR_EXR_ATTR_FLOAT = 1, CLR_EXR_ATTR_INT = 2 };

/* A header attribute: `kind` selects which of s, f, i holds the value. */
typedef struct clr_exr_attribute {
  const char *name;
  int32_t kind;
  const char *s;
  float f;
  int32_t i;
} clr_exr_attribute;

/* Writes a ZIP-compressed scanline EXR whose display window is [0,w) x [0,h) and whose data window
 * is `data_window` (half-open, inside the display window: a crop). Channels may come in any order
 * (the file stores them sorted by name). The file appears at `path` only when complete (written to
 * "path.tmp-XXXXXX" and renamed); on failure nothing is left behind. */
clr_result clr_exr_write(const char *path, int32_t display_width, int32_t display_height,
                         clr_bounds2i data_window, const clr_exr_channel *channels,
                         int32_t channel_count, const clr_exr_attribute *attrs, int32_t attr_count);

/* Fills rows[c] with `lines` rows (data-window width floats each, row-major) of channel c (the
 * caller's order) from data-window line y on; called once per chunk, from several threads at
 * once. */
typedef void (*clr_exr_rows_fn)(void *user, int32_t y, int32_t lines, float *const *rows);

/* clr_exr_write with the values computed chunk by chunk by `rows` (channels' data unused): no
 * whole-image planes, and the computing spread over the compressing threads. The same file. */
clr_result clr_exr_write_rows(const char *path, int32_t display_width, int32_t display_height,
                              clr_bounds2i data_window, const clr_exr_channel *channels,
                              int32_t channel_count, clr_exr_rows_fn rows, void *rows_user,
                              const clr_exr_attribute *attrs, int32_t attr_count);

/* An EXR file read into float planes (half and uint channels converted to float). */
typedef struct clr_exr_image {
  clr_bounds2i display_window; /* half-open */
  int32_t display_width, display_height;
  clr_bounds2i data_window; /* half-open */
  int32_t width, height;    /* data window size: each plane holds width * height floats */
  int32_t channel_count;
  char **channel_names;   /* in file order (sorted) */
  int32_t *channel_types; /* 0 uint, 1 half, 2 float as stored in the file */
  float **channels;
  int32_t attr_count;       /* string, float (and double, as float) and int header attributes */
  clr_exr_attribute *attrs; /* names and strings owned by the image */
} clr_exr_image;

/* Reads part 0 of a scanline EXR file. Missing/unreadable file: CLR_ERROR_IO; malformed,
 * truncated, tiled, deep or subsampled files: CLR_ERROR_FILE_FORMAT. The message names the
 * OpenEXR call, the file and OpenEXR's error. */
clr_result clr_exr_read(const char *path, clr_exr_image **out);
void clr_exr_image_free(clr_exr_image *image);

/* Plane of the named channel, NULL if absent. */
const float *clr_exr_image_channel(const clr_exr_image *image, const char *name);
/* Value of a string attribute, NULL if absent or of another type. */
const char *clr_exr_image_string_attr(const clr_exr_image *image, const char *name);
/* Store a float/int attribute's value in *value and return 1; return 0 if absent or of another
 * type (*value untouched). */
int clr_exr_image_float_attr(const clr_exr_image *image, const char *name, float *value);
int clr_exr_image_int_attr(const clr_exr_image *image, const char *name, int32_t *value);

/* IEEE half conversions used for half channels (round to nearest even; exact both ways). */
uint16_t clr_float_to_half(float f);
float clr_half_to_float(uint16_t h);

#endif
