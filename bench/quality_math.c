/* Integrands with exact integrals, the log-log slope fit and the point-set periodogram. The
 * integrands are not symmetric about x = 1/2, y = 1/2 or x = y: unscrambled digital nets (sobol,
 * maxmindist) reflect and swap coordinates between sample blocks, so a symmetric integrand would
 * show their error on it only, not their convergence. */
#include "quality_math.h"
#include <math.h>
#include <stdlib.h>

#define QM_PI 3.14159265358979323846

static const double disk_center[2] = {0.45, 0.55}, disk_radius = 0.35;
static const double gauss_center[2] = {0.4, 0.55}, gauss_sigma = 0.2;
/* The bilinear step is x*y below the line y = a + b x, which crosses the square from side to
 * side (a, a + b in [0,1]). */
static const double step_a = 0.2, step_b = 0.7;

static double disk(double x, double y) {
  double dx = x - disk_center[0], dy = y - disk_center[1];
  return dx * dx + dy * dy < disk_radius * disk_radius ? 1.0 : 0.0;
}

static double gaussian(double x, double y) {
  double dx = x - gauss_center[0], dy = y - gauss_center[1];
  return exp(-(dx * dx + dy * dy) / (2.0 * gauss_sigma * gauss_sigma));
}

static double bilinear_step(double x, double y) { return y < step_a + step_b * x ? x * y : 0.0; }

/* Integral over [0,1] of exp(-(t - c)^2 / (2 sigma^2)). */
static double gaussian_factor(double c) {
  double s = gauss_sigma * sqrt(2.0);
  return gauss_sigma * sqrt(QM_PI / 2.0) * (erf((1.0 - c) / s) + erf(c / s));
}

/* The Gaussian is separable: the product of its factors' integrals. */
static double gaussian_exact(void) {
  return gaussian_factor(gauss_center[0]) * gaussian_factor(gauss_center[1]);
}

/* Integral of x * (a + b x)^2 / 2 over [0,1]. */
static double bilinear_step_exact(void) {
  double a = step_a, b = step_b;
  return 0.5 * (a * a / 2.0 + 2.0 * a * b / 3.0 + b * b / 4.0);
}

static qm_integrand integrands[3];

static void fill_integrands(void) {
  if (integrands[0].f) return;
  integrands[0] = (qm_integrand){"disk", disk, QM_PI * disk_radius * disk_radius};
  integrands[1] = (qm_integrand){"gaussian", gaussian, gaussian_exact()};
  integrands[2] = (qm_integrand){"bilinear step", bilinear_step, bilinear_step_exact()};
}

int qm_integrand_count(void) { return (int)(sizeof integrands / sizeof integrands[0]); }

const qm_integrand *qm_integrand_get(int i) {
  fill_integrands();
  return i >= 0 && i < qm_integrand_count() ? &integrands[i] : 0;
}

double qm_loglog_slope(const double *spp, const double *rmse, int n) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    if (!(spp[i] > 0) || !(rmse[i] > 0)) continue;
    double x = log(spp[i]), y = log(rmse[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++m;
  }
  double d = m * sxx - sx * sx;
  return m < 2 || d <= 0 ? 0.0 : (m * sxy - sx * sy) / d;
}

/* Phasors exp(-2 pi i k v) for k = -K..K into ph[2 (k + K)] (re), ph[2 (k + K) + 1] (im). */
static void phasors(double v, int K, double *ph) {
  for (int k = -K; k <= K; ++k) {
    double phase = -2.0 * QM_PI * k * v;
    ph[2 * (k + K)] = cos(phase), ph[2 * (k + K) + 1] = sin(phase);
  }
}

int qm_periodogram_add(const float *xy, int n, int K, double *power) {
  int side = 2 * K + 1;
  double *px = malloc((size_t)n * side * 2 * sizeof(double));
  double *py = malloc((size_t)n * side * 2 * sizeof(double));
  if (!px || !py) {
    free(px), free(py);
    return 0;
  }
  for (int i = 0; i < n; ++i) {
    phasors(xy[2 * i], K, px + (size_t)i * side * 2);
    phasors(xy[2 * i + 1], K, py + (size_t)i * side * 2);
  }
  for (int ky = 0; ky < side; ++ky)
    for (int kx = 0; kx < side; ++kx) {
      double sr = 0, si = 0;
      for (int i = 0; i < n; ++i) { /* exp(-2 pi i (kx x + ky y)) = product of the phasors */
        const double *a = px + ((size_t)i * side + kx) * 2, *b = py + ((size_t)i * side + ky) * 2;
        sr += a[0] * b[0] - a[1] * b[1], si += a[0] * b[1] + a[1] * b[0];
      }
      power[ky * side + kx] += (sr * sr + si * si) / n;
    }
  free(px), free(py);
  return 1;
}

void qm_radial_average(const double *power, int K, double *radial) {
  int side = 2 * K + 1;
  for (int r = 0; r <= K; ++r) radial[r] = 0;
  for (int r = 1; r <= K; ++r) { /* the ring of frequencies with round(|k|) == r */
    int count = 0;
    for (int ky = -K; ky <= K; ++ky)
      for (int kx = -K; kx <= K; ++kx) {
        if (lround(sqrt((double)(kx * kx + ky * ky))) != r) continue;
        radial[r] += power[(ky + K) * side + (kx + K)], ++count;
      }
    radial[r] = count ? radial[r] / count : 0;
  }
}
