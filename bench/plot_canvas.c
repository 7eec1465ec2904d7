/* Raster primitives of plot_canvas.h. */
#include "plot_canvas.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "clrender/image.h"
#include "plot_font.h"

int plot_canvas_create(plot_canvas *c, int w, int h) {
  memset(c, 0, sizeof *c);
  if (w <= 0 || h <= 0 || w > 8192 || h > 8192) return 0;
  c->rgb = malloc((size_t)w * h * 3);
  if (!c->rgb) return 0;
  memset(c->rgb, 255, (size_t)w * h * 3);
  c->w = w, c->h = h;
  plot_unclip(c);
  return 1;
}

void plot_canvas_free(plot_canvas *c) {
  free(c->rgb);
  memset(c, 0, sizeof *c);
}

void plot_clip(plot_canvas *c, int x0, int y0, int x1, int y1) {
  c->clip[0] = x0 < 0 ? 0 : x0, c->clip[1] = y0 < 0 ? 0 : y0;
  c->clip[2] = x1 > c->w ? c->w : x1, c->clip[3] = y1 > c->h ? c->h : y1;
}

void plot_unclip(plot_canvas *c) { plot_clip(c, 0, 0, c->w, c->h); }

void plot_pixel(plot_canvas *c, int x, int y, plot_color color) {
  if (x < c->clip[0] || y < c->clip[1] || x >= c->clip[2] || y >= c->clip[3]) return;
  uint8_t *p = c->rgb + 3 * ((size_t)y * c->w + x);
  p[0] = color.r, p[1] = color.g, p[2] = color.b;
}

void plot_fill(plot_canvas *c, int x0, int y0, int x1, int y1, plot_color color) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) plot_pixel(c, x, y, color);
}

void plot_line(plot_canvas *c, int x0, int y0, int x1, int y1, int width, plot_color color) {
  int dx = abs(x1 - x0), dy = -abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int err = dx + dy, lo = -(width - 1) / 2;
  for (int steps = 0; steps <= 32768; ++steps) { /* bounded: coordinates are clamped by callers */
    plot_fill(c, x0 + lo, y0 + lo, x0 + lo + width, y0 + lo + width, color);
    if (x0 == x1 && y0 == y1) break;
    int e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

/* Draws glyph cell (col, row) of character i at its place, upright or turned up. */
static void glyph_cell(plot_canvas *c, int x, int y, int scale, int up, int i, int col, int row,
                       plot_color color) {
  int gx = i * 6 + col;
  if (!up) {
    plot_fill(c, x + gx * scale, y + row * scale, x + (gx + 1) * scale, y + (row + 1) * scale,
              color);
  } else { /* text runs upward from (x, y): column gx -> y - gx, row -> x + row */
    plot_fill(c, x + row * scale, y - (gx + 1) * scale, x + (row + 1) * scale, y - gx * scale,
              color);
  }
}

static void text(plot_canvas *c, int x, int y, int scale, plot_color color, const char *s, int up) {
  for (int i = 0; s[i]; ++i) {
    const uint8_t *rows = plot_font_glyph(s[i]);
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col)
        if (rows[row] & (0x10 >> col)) glyph_cell(c, x, y, scale, up, i, col, row, color);
  }
}

void plot_text(plot_canvas *c, int x, int y, int scale, plot_color color, const char *s) {
  text(c, x, y, scale, color, s, 0);
}

void plot_text_up(plot_canvas *c, int x, int y, int scale, plot_color color, const char *s) {
  text(c, x, y, scale, color, s, 1);
}

int plot_text_width(int scale, const char *s) {
  int n = (int)strlen(s);
  return n ? (6 * n - 1) * scale : 0;
}

clr_result plot_canvas_write_png(const plot_canvas *c, const char *path) {
  size_t n = (size_t)c->w * c->h * 3;
  float *rgb = malloc(n * sizeof(float));
  if (!rgb) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "plot: out of memory");
  float linear[256]; /* the writer takes linear RGB and encodes sRGB: invert its curve */
  for (int v = 0; v < 256; ++v) {
    float s = (float)v / 255.0f;
    linear[v] = s <= 0.04045f ? s / 12.92f : powf((s + 0.055f) / 1.055f, 2.4f);
  }
  for (size_t i = 0; i < n; ++i) rgb[i] = linear[c->rgb[i]];
  clr_image image = {c->w, c->h, rgb};
  clr_result r = clr_image_write_png(path, &image);
  free(rgb);
  return r;
}
