/* A tiny raster canvas for the bench's figures: 8-bit sRGB pixels, thick lines, filled
 * rectangles and text in a 5x7 bitmap font, written as PNG through the library's writer. */
#ifndef CLR_PLOT_CANVAS_H
#define CLR_PLOT_CANVAS_H

#include <stdint.h>
#include "clrender/result.h"

typedef struct plot_color {
  uint8_t r, g, b; /* sRGB */
} plot_color;

typedef struct plot_canvas {
  int w, h;
  uint8_t *rgb; /* w * h * 3, top row first */
  int clip[4];  /* x0, y0, x1, y1 (half-open): drawing outside is dropped */
} plot_canvas;

/* A white canvas; returns 0 when out of memory or the size is not in 1..8192. */
int plot_canvas_create(plot_canvas *c, int w, int h);
void plot_canvas_free(plot_canvas *c);
void plot_clip(plot_canvas *c, int x0, int y0, int x1, int y1);
void plot_unclip(plot_canvas *c);

void plot_pixel(plot_canvas *c, int x, int y, plot_color color);
void plot_fill(plot_canvas *c, int x0, int y0, int x1, int y1, plot_color color); /* half-open */
/* A line of `width` pixels (a width x width square along Bresenham's line). */
void plot_line(plot_canvas *c, int x0, int y0, int x1, int y1, int width, plot_color color);

/* Text: each glyph 5x7 cells of `scale` pixels, advancing 6 * scale; lower case is drawn upper
 * case, characters without a glyph as '?'. (x, y) is the top left corner. */
void plot_text(plot_canvas *c, int x, int y, int scale, plot_color color, const char *s);
int plot_text_width(int scale, const char *s);
/* Text turned 90 degrees counter-clockwise (reads bottom to top), (x, y) its bottom left. */
void plot_text_up(plot_canvas *c, int x, int y, int scale, plot_color color, const char *s);

clr_result plot_canvas_write_png(const plot_canvas *c, const char *path);

#endif
