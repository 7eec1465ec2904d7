/* Axes, ticks, series and legends of plot_chart.h. */
#include "plot_chart.h"
#include <math.h>
#include <stdio.h>

enum { TEXT = 2, MARGIN_LEFT = 84, MARGIN_BOTTOM = 52, MARGIN_TOP = 30, MARGIN_RIGHT = 14 };
static const plot_color black = {0, 0, 0}, grid = {225, 225, 225}, white = {255, 255, 255};

plot_color plot_palette(int i) {
  static const plot_color colors[] = {{31, 119, 180},  {255, 127, 14},  {44, 160, 44},
                                      {214, 39, 40},   {148, 103, 189}, {140, 86, 75},
                                      {227, 119, 194}, {127, 127, 127}, {188, 189, 34},
                                      {23, 190, 207},  {0, 0, 0},       {110, 80, 0}};
  return colors[i % (int)(sizeof colors / sizeof colors[0])];
}

/* Position in [0,1] of v along the axis (outside for values out of range), NAN if unplottable. */
static double axis_t(const plot_axis *a, double v) {
  if (a->log_base) {
    if (!(v > 0) || !(a->lo > 0) || !(a->hi > a->lo)) return NAN;
    return log(v / a->lo) / log(a->hi / a->lo);
  }
  return a->hi > a->lo ? (v - a->lo) / (a->hi - a->lo) : NAN;
}

static double px_x(const plot_chart *ch, double v) {
  return ch->x0 + axis_t(&ch->x, v) * (ch->x1 - 1 - ch->x0);
}

static double px_y(const plot_chart *ch, double v) {
  return ch->y1 - 1 - axis_t(&ch->y, v) * (ch->y1 - 1 - ch->y0);
}

void plot_chart_begin(plot_chart *ch, plot_canvas *c, int left, int top, int width, int height,
                      plot_axis x, plot_axis y, const char *title, const char *x_name,
                      const char *y_name) {
  ch->canvas = c, ch->x = x, ch->y = y;
  ch->x0 = left + MARGIN_LEFT, ch->y0 = top + MARGIN_TOP;
  ch->x1 = left + width - MARGIN_RIGHT, ch->y1 = top + height - MARGIN_BOTTOM;
  int cx = (ch->x0 + ch->x1) / 2;
  plot_text(c, cx - plot_text_width(TEXT, title) / 2, top + 6, TEXT, black, title);
  plot_text(c, cx - plot_text_width(TEXT, x_name) / 2, ch->y1 + 30, TEXT, black, x_name);
  plot_text_up(c, left + 4, (ch->y0 + ch->y1) / 2 + plot_text_width(TEXT, y_name) / 2, TEXT, black,
               y_name);
}

static void tick_label(const plot_axis *a, double v, int power, char *buf, size_t size) {
  if (a->log_base == 10 && (power < -2 || power > 3))
    snprintf(buf, size, "1E%d", power);
  else
    snprintf(buf, size, "%g", v);
}

static void draw_tick(plot_chart *ch, int axis, double v, int label, int power) {
  plot_canvas *c = ch->canvas;
  char buf[32];
  tick_label(axis ? &ch->y : &ch->x, v, power, buf, sizeof buf);
  if (axis == 0) {
    int x = (int)lround(px_x(ch, v));
    plot_fill(c, x, ch->y0, x + 1, ch->y1, grid);
    plot_fill(c, x, ch->y1, x + 1, ch->y1 + 5, black);
    if (label) plot_text(c, x - plot_text_width(TEXT, buf) / 2, ch->y1 + 8, TEXT, black, buf);
  } else {
    int y = (int)lround(px_y(ch, v));
    plot_fill(c, ch->x0, y, ch->x1, y + 1, grid);
    plot_fill(c, ch->x0 - 5, y, ch->x0, y + 1, black);
    if (label) plot_text(c, ch->x0 - 8 - plot_text_width(TEXT, buf), y - 7, TEXT, black, buf);
  }
}

void plot_chart_ticks(plot_chart *ch, int axis, double step, int label_every) {
  const plot_axis *a = axis ? &ch->y : &ch->x;
  if (label_every < 1) label_every = 1;
  if (a->log_base) {
    if (!(a->lo > 0) || !(a->hi > a->lo)) return;
    double lb = log((double)a->log_base);
    int p0 = (int)ceil(log(a->lo) / lb - 1e-9), p1 = (int)floor(log(a->hi) / lb + 1e-9);
    for (int p = p0; p <= p1 && p - p0 < 200; ++p)
      draw_tick(ch, axis, pow(a->log_base, p), ((p % label_every) + label_every) % label_every == 0,
                p);
  } else if (step > 0) {
    for (int i = 0; i < 200; ++i) {
      double v = a->lo + i * step;
      if (v > a->hi + 1e-9 * step) break;
      draw_tick(ch, axis, v, i % label_every == 0, 0);
    }
  }
  plot_canvas *c = ch->canvas; /* the frame over the grid lines */
  plot_fill(c, ch->x0 - 1, ch->y0 - 1, ch->x1 + 1, ch->y0, black);
  plot_fill(c, ch->x0 - 1, ch->y1, ch->x1 + 1, ch->y1 + 1, black);
  plot_fill(c, ch->x0 - 1, ch->y0 - 1, ch->x0, ch->y1 + 1, black);
  plot_fill(c, ch->x1, ch->y0 - 1, ch->x1 + 1, ch->y1 + 1, black);
}

/* Pixel position of point i, or 0 when it can't be plotted; clamped far outside the area so
 * lines to it stay short. */
static int point_px(const plot_chart *ch, double x, double y, int *px, int *py) {
  double fx = px_x(ch, x), fy = px_y(ch, y);
  if (!isfinite(fx) || !isfinite(fy)) return 0;
  double m = 4096;
  *px = (int)lround(fx < -m ? -m : fx > m ? m : fx);
  *py = (int)lround(fy < -m ? -m : fy > m ? m : fy);
  return 1;
}

void plot_chart_series(plot_chart *ch, const double *x, const double *y, int n, plot_color color,
                       int markers) {
  plot_canvas *c = ch->canvas;
  plot_clip(c, ch->x0, ch->y0, ch->x1, ch->y1);
  int have = 0, lx = 0, ly = 0;
  for (int i = 0; i < n; ++i) {
    int px, py;
    if (!point_px(ch, x[i], y[i], &px, &py)) {
      have = 0;
      continue;
    }
    if (have) plot_line(c, lx, ly, px, py, 2, color);
    if (markers) plot_fill(c, px - 3, py - 3, px + 4, py + 4, color);
    have = 1, lx = px, ly = py;
  }
  plot_unclip(c);
}

void plot_chart_hline(plot_chart *ch, double y, plot_color color) {
  int px, py;
  if (!point_px(ch, ch->x.lo, y, &px, &py) || py < ch->y0 || py >= ch->y1) return;
  for (int x = ch->x0; x < ch->x1; x += 8) plot_fill(ch->canvas, x, py, x + 5, py + 1, color);
}

int plot_chart_legend_width(const char *const *labels, int n) {
  int widest = 0;
  for (int i = 0; i < n; ++i)
    if (plot_text_width(TEXT, labels[i]) > widest) widest = plot_text_width(TEXT, labels[i]);
  return widest + 44;
}

void plot_chart_legend(plot_chart *ch, const char *const *labels, const plot_color *colors, int n,
                       int corner) {
  int line = 9 * TEXT + 2, w = plot_chart_legend_width(labels, n), h = n * line + 10;
  int left = corner == 2 ? ch->x1 + 12 : corner ? ch->x1 - 8 - w : ch->x0 + 8;
  int top = corner ? ch->y0 + (corner == 2 ? 0 : 8) : ch->y1 - 8 - h;
  plot_fill(ch->canvas, left - 1, top - 1, left + w + 1, top + h + 1, black);
  plot_fill(ch->canvas, left, top, left + w, top + h, white);
  for (int i = 0; i < n; ++i) {
    int y = top + 6 + i * line;
    plot_fill(ch->canvas, left + 6, y + 6, left + 30, y + 9, colors[i]);
    plot_text(ch->canvas, left + 36, y, TEXT, black, labels[i]);
  }
}
