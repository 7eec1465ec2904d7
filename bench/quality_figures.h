/* The quality section's figures: convergence curves (log-log RMSE vs spp, one line per sampler
 * and one chart per case) and each sampler's points and power spectrum, as PNG files. */
#ifndef CLR_QUALITY_FIGURES_H
#define CLR_QUALITY_FIGURES_H

#include "clrender/result.h"

enum { QUALITY_MAX_LEVELS = 13, QUALITY_MAX_SAMPLERS = 32 };

typedef struct quality_curve {
  int n; /* levels measured (0: none) */
  double spp[QUALITY_MAX_LEVELS], rmse[QUALITY_MAX_LEVELS];
  double slope; /* least-squares slope of log rmse vs log spp */
} quality_curve;

/* One chart per case in a grid of two columns; curves[case * samplers + s]. */
clr_result quality_plot_convergence(const char *path, const char *const *cases, int case_count,
                                    const char *const *samplers, int sampler_count,
                                    const quality_curve *curves);

typedef struct quality_spectrum {
  const char *sampler;
  const float *points; /* n points (x, y) of one pixel */
  int n;
  const double *power;  /* (2K+1)^2 periodogram, kx fastest, as qm_periodogram_add */
  const double *radial; /* K+1 radial averages */
  int K;
} quality_spectrum;

/* One row per sampler: its points, the periodogram and its radial average. */
clr_result quality_plot_spectra(const char *path, const quality_spectrum *spectra, int count,
                                int pixels_averaged);

#endif
