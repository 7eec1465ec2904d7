#include "cost_fit.h"

void clr_cost_fit_add(clr_cost_fit *f, double units, double seconds) {
  f->n += 1.0;
  f->units += units;
  f->seconds += seconds;
  f->units2 += units * units;
  f->units_seconds += units * seconds;
}

double clr_cost_fit_per_unit(const clr_cost_fit *f) {
  if (!(f->units > 0.0)) return 0.0;
  double average = f->seconds / f->units;
  double spread = f->n * f->units2 - f->units * f->units; /* n^2 variance of the units */
  if (f->n < 3.0 || !(spread > 1e-4 * f->units * f->units)) return average;
  double slope = (f->n * f->units_seconds - f->units * f->seconds) / spread;
  if (!(slope > 0.1 * average)) return 0.1 * average; /* a negative or noisy slope */
  return slope < average ? slope : average;
}
