/* A least-squares line seconds = fixed + per_unit * units over observations (e.g. one per
 * generated band of sample values): the marginal cost of a unit, without the per-call costs
 * that an average per unit would spread over the units. */
#ifndef CLR_RENDER_COST_FIT_H
#define CLR_RENDER_COST_FIT_H

typedef struct clr_cost_fit {
  double n, units, seconds, units2, units_seconds; /* sums over the observations */
} clr_cost_fit;

/* Adds one observation. */
void clr_cost_fit_add(clr_cost_fit *f, double units, double seconds);

/* The cost per unit: the fitted slope, kept within [average / 10, average] (the average: all
 * seconds over all units); the average when the units do not vary (relative spread below 1 %)
 * or fewer than 3 observations; 0 without units. */
double clr_cost_fit_per_unit(const clr_cost_fit *f);

#endif
