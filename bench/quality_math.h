/* The math of the bench's quality section, kept apart so tests/test_quality_math.c can check it:
 * analytic integrands over the unit square with exact integrals, the least-squares convergence
 * slope, and the periodogram (power spectrum) of a 2D point set. */
#ifndef CLR_QUALITY_MATH_H
#define CLR_QUALITY_MATH_H

typedef struct qm_integrand {
  const char *name;
  double (*f)(double x, double y); /* over [0,1)^2 */
  double exact;                    /* its integral over [0,1]^2 */
} qm_integrand;

/* The integrands: "disk" (indicator of a disk, discontinuous along a curve), "gaussian"
 * (smooth), "bilinear step" (x*y cut by an oblique line: discontinuous along a line). */
int qm_integrand_count(void);
const qm_integrand *qm_integrand_get(int i);

/* Slope of the least-squares line through (log spp[i], log rmse[i]) over the points with both
 * values positive; 0 when fewer than two such points. */
double qm_loglog_slope(const double *spp, const double *rmse, int n);

/* Adds the periodogram of n points (xy[2i], xy[2i+1]) in [0,1)^2 to power[(ky+K)(2K+1)+(kx+K)]
 * for integer frequencies -K <= kx, ky <= K: P(k) = |sum_i exp(-2 pi i k.x_i)|^2 / n, that is
 * n |(1/n) sum_i exp(-2 pi i k.x_i)|^2, whose expectation is 1 for k != 0 for uniform random
 * points (P(0) = n). Returns 0 when out of memory (power unchanged), else 1. */
int qm_periodogram_add(const float *xy, int n, int K, double *power);

/* Mean of power (as above) over the frequencies with round(|k|) == r, into radial[r] for
 * 1 <= r <= K (radial[0] = 0: only the DC term lies there). */
void qm_radial_average(const double *power, int K, double *radial);

#endif
