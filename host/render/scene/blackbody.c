/* Normalized blackbody emission to RGB (see blackbody.h). */
#include <math.h>
#include "blackbody.h"

/* Wyman, Sloan, Shirley: "Simple Analytic Approximations to the CIE XYZ Color Matching
 * Functions", JCGT 2(2), 2013, the multi-lobe fit of the CIE 1931 2-degree observer. */
static double lobe(double l, double mu, double s1, double s2) {
  double t = (l - mu) / (l < mu ? s1 : s2);
  return exp(-0.5 * t * t);
}
static double cie_x(double l) {
  return 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) -
         0.065 * lobe(l, 501.1, 20.4, 26.2);
}
static double cie_y(double l) {
  return 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
}
static double cie_z(double l) {
  return 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
}

/* pbrt-v3 Blackbody: Planck's law at wavelength lambda (nm) and temperature t (K). */
static double planck(double lambda_nm, double t) {
  const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
  double l = lambda_nm * 1e-9;
  return (2.0 * h * c * c) / (pow(l, 5.0) * (exp((h * c) / (l * kb * t)) - 1.0));
}

void rs_blackbody_rgb(float t, float rgb[3]) {
  rgb[0] = rgb[1] = rgb[2] = 0.0f;
  if (!(t > 0.0f) || !isfinite(t)) return;
  double peak = planck(2.8977721e-3 / t * 1e9, t), xyz[3] = {0, 0, 0}, y_integral = 0.0;
  const int n = 471; /* 360..830 nm, pbrt-v3's CIE sampling */
  for (int i = 0; i < n; ++i) {
    double l = 360.0 + i, v = planck(l, t) / peak;
    xyz[0] += v * cie_x(l);
    xyz[1] += v * cie_y(l);
    xyz[2] += v * cie_z(l);
    y_integral += cie_y(l);
  }
  double scale = (830.0 - 360.0) / (y_integral * n);
  for (int k = 0; k < 3; ++k) xyz[k] *= scale;
  /* pbrt-v3 XYZToRGB */
  rgb[0] = (float)(3.240479 * xyz[0] - 1.537150 * xyz[1] - 0.498535 * xyz[2]);
  rgb[1] = (float)(-0.969256 * xyz[0] + 1.875991 * xyz[1] + 0.041556 * xyz[2]);
  rgb[2] = (float)(0.055648 * xyz[0] - 0.204043 * xyz[1] + 1.057311 * xyz[2]);
}
