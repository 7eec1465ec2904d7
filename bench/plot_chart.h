/* Line charts on a plot_canvas: linear or logarithmic axes, ticks with labels, series with
 * markers, a legend. */
#ifndef CLR_PLOT_CHART_H
#define CLR_PLOT_CHART_H

#include "plot_canvas.h"

typedef struct plot_axis {
  double lo, hi; /* the range shown; positive on a log axis */
  int log_base;  /* 0: linear; 2 or 10: logarithmic */
} plot_axis;

typedef struct plot_chart {
  plot_canvas *canvas;
  int x0, y0, x1, y1; /* plotting area (inside the frame), half-open */
  plot_axis x, y;
} plot_chart;

/* The chart in the canvas rectangle (left, top, width, height): margins for labels, frame,
 * title and axis names. */
void plot_chart_begin(plot_chart *ch, plot_canvas *c, int left, int top, int width, int height,
                      plot_axis x, plot_axis y, const char *title, const char *x_name,
                      const char *y_name);
/* Grid lines and labels: on a log axis at each power of the base (labelled every
 * label_every-th), on a linear axis every `step` from lo. axis: 0 x, 1 y. */
void plot_chart_ticks(plot_chart *ch, int axis, double step, int label_every);
/* Points with a positive value on each log axis are joined; others break the line. */
void plot_chart_series(plot_chart *ch, const double *x, const double *y, int n, plot_color color,
                       int markers);
void plot_chart_hline(plot_chart *ch, double y, plot_color color);
/* The legend boxed in the bottom-left (corner 0) or top-right (corner 1) of the area, or
 * (corner 2) beside it on the right, top-aligned (leave room: plot_chart_legend_width). */
void plot_chart_legend(plot_chart *ch, const char *const *labels, const plot_color *colors, int n,
                       int corner);

int plot_chart_legend_width(const char *const *labels, int n);

/* A palette of distinct colours for series i (cycles). */
plot_color plot_palette(int i);

#endif
