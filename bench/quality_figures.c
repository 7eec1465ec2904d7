/* Draws the figures of quality_figures.h with plot_chart. */
#include "quality_figures.h"
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include "plot_chart.h"

enum { CHART_W = 860, CHART_H = 460, ROW_H = 250, CELL = 210 };
static const plot_color black = {0, 0, 0}, gray = {120, 120, 120};

/* The decades spanning every positive value of the curves of one case. */
static plot_axis rmse_axis(const quality_curve *curves, int count) {
  double lo = INFINITY, hi = 0;
  for (int s = 0; s < count; ++s)
    for (int i = 0; i < curves[s].n; ++i) {
      double v = curves[s].rmse[i];
      if (v > 0 && v < lo) lo = v;
      if (v > hi) hi = v;
    }
  if (!(hi > 0)) return (plot_axis){1e-3, 1, 10};
  return (plot_axis){pow(10, floor(log10(lo))), pow(10, ceil(log10(hi))), 10};
}

static double max_spp(const quality_curve *curves, int count) {
  double hi = 1;
  for (int s = 0; s < count; ++s)
    for (int i = 0; i < curves[s].n; ++i)
      if (curves[s].spp[i] > hi) hi = curves[s].spp[i];
  return hi;
}

static void upper(char *s) {
  for (; *s; ++s) *s = (char)toupper((unsigned char)*s);
}

/* A log-log chart of one case with its legend (sampler and slope) on the right. */
static void convergence_chart(plot_canvas *c, int left, int top, const char *title,
                              const char *const *samplers, int count, const quality_curve *curves) {
  char labels[QUALITY_MAX_SAMPLERS][64];
  const char *label_ptr[QUALITY_MAX_SAMPLERS] = {0};
  plot_color colors[QUALITY_MAX_SAMPLERS];
  if (count > QUALITY_MAX_SAMPLERS) count = QUALITY_MAX_SAMPLERS;
  for (int s = 0; s < count; ++s) {
    colors[s] = plot_palette(s);
    if (curves[s].n > 1)
      snprintf(labels[s], sizeof labels[s], "%-10s %+.2f", samplers[s], curves[s].slope);
    else
      snprintf(labels[s], sizeof labels[s], "%-10s", samplers[s]);
    upper(labels[s]);
    label_ptr[s] = labels[s];
  }
  plot_chart ch;
  plot_axis x = {1, max_spp(curves, count), 2};
  plot_chart_begin(&ch, c, left, top, CHART_W - plot_chart_legend_width(label_ptr, count) - 24,
                   CHART_H, x, rmse_axis(curves, count), title, "SAMPLES PER PIXEL", "RMSE");
  plot_chart_ticks(&ch, 0, 0, 2);
  plot_chart_ticks(&ch, 1, 0, 1);
  for (int s = 0; s < count; ++s)
    plot_chart_series(&ch, curves[s].spp, curves[s].rmse, curves[s].n, colors[s], 1);
  plot_chart_legend(&ch, label_ptr, colors, count, 2);
}

clr_result quality_plot_convergence(const char *path, const char *const *cases, int case_count,
                                    const char *const *samplers, int sampler_count,
                                    const quality_curve *curves) {
  int cols = case_count < 2 ? 1 : 2, rows = (case_count + 1) / 2;
  plot_canvas c;
  if (!plot_canvas_create(&c, cols * CHART_W, rows * CHART_H + 30))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "plot: cannot allocate %s", path);
  plot_text(&c, 10, 8, 2, black, "RMSE VS SPP, LOG-LOG; LEGEND: SAMPLER, FITTED SLOPE");
  for (int k = 0; k < case_count; ++k) {
    char title[64];
    snprintf(title, sizeof title, "%s", cases[k]);
    upper(title);
    convergence_chart(&c, (k % 2) * CHART_W, 30 + (k / 2) * CHART_H, title, samplers, sampler_count,
                      curves + (size_t)k * sampler_count);
  }
  clr_result r = plot_canvas_write_png(&c, path);
  plot_canvas_free(&c);
  return r;
}

/* The unit square with the points as 3x3 dots, and 1/16 strata lines. */
static void points_cell(plot_canvas *c, int left, int top, const quality_spectrum *s) {
  const plot_color light = {225, 225, 225};
  for (int i = 0; i <= 16; ++i) {
    int v = i * (CELL - 1) / 16;
    plot_fill(c, left + v, top, left + v + 1, top + CELL, i % 16 ? light : black);
    plot_fill(c, left, top + v, left + CELL, top + v + 1, i % 16 ? light : black);
  }
  for (int i = 0; i < s->n; ++i) {
    int x = left + (int)(s->points[2 * i] * (CELL - 1));
    int y = top + CELL - 1 - (int)(s->points[2 * i + 1] * (CELL - 1));
    plot_fill(c, x - 1, y - 1, x + 2, y + 2, (plot_color){200, 30, 0});
  }
}

/* The periodogram, frequency (0,0) in the middle, gray = P / 2 clamped (white noise mid-gray). */
static void spectrum_cell(plot_canvas *c, int left, int top, const quality_spectrum *s) {
  int side = 2 * s->K + 1;
  for (int y = 0; y < CELL; ++y)
    for (int x = 0; x < CELL; ++x) {
      int kx = x * side / CELL, ky = side - 1 - y * side / CELL;
      double p = s->power[(size_t)ky * side + kx];
      if (kx == s->K && ky == s->K) p = 0; /* DC is n: not shown */
      double g = p / 2.0;
      uint8_t v = (uint8_t)(g >= 1 ? 255 : g <= 0 ? 0 : lround(g * 255));
      plot_pixel(c, left + x, top + y, (plot_color){v, v, v});
    }
}

static void radial_cell(plot_canvas *c, int left, int top, const quality_spectrum *s) {
  double x[512], y[512];
  int n = 0;
  for (int r = 1; r <= s->K && n < 512; ++r, ++n) x[n] = r, y[n] = s->radial[r];
  plot_chart ch;
  plot_chart_begin(&ch, c, left, top, 330, ROW_H, (plot_axis){0, s->K, 0}, (plot_axis){0, 3, 0}, "",
                   "FREQUENCY |K|", "POWER");
  plot_chart_ticks(&ch, 0, 8, 1);
  plot_chart_ticks(&ch, 1, 0.5, 2);
  plot_chart_hline(&ch, 1.0, gray);
  plot_chart_series(&ch, x, y, n, plot_palette(0), 0);
}

clr_result quality_plot_spectra(const char *path, const quality_spectrum *spectra, int count,
                                int pixels_averaged) {
  int w = 160 + 2 * (CELL + 20) + 340, h = 60 + count * ROW_H;
  plot_canvas c;
  if (count < 1 || !plot_canvas_create(&c, w, h))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "plot: cannot allocate %s", path);
  char head[160];
  snprintf(head, sizeof head, "%d POINTS OF ONE PIXEL (DIMS 0,1); PERIODOGRAM, K=-%d..%d,",
           spectra[0].n, spectra[0].K, spectra[0].K);
  plot_text(&c, 10, 8, 2, black, head);
  snprintf(head, sizeof head,
           "MEAN OF %d PIXELS (GRAY = POWER/2: WHITE NOISE MID-GRAY); RADIAL MEAN",
           pixels_averaged);
  plot_text(&c, 10, 30, 2, black, head);
  for (int i = 0; i < count; ++i) {
    int top = 60 + i * ROW_H;
    char name[64];
    snprintf(name, sizeof name, "%s", spectra[i].sampler);
    upper(name);
    plot_text(&c, 10, top + CELL / 2, 2, black, name);
    points_cell(&c, 160, top + 10, &spectra[i]);
    spectrum_cell(&c, 160 + CELL + 20, top + 10, &spectra[i]);
    radial_cell(&c, 160 + 2 * (CELL + 20), top - 10, &spectra[i]);
  }
  clr_result r = plot_canvas_write_png(&c, path);
  plot_canvas_free(&c);
  return r;
}
