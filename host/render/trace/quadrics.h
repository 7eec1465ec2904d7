/* pbrt-v3's quadrics in object space: cylinder, cone, paraboloid, hyperboloid (with phimax), their
 * exact ray intersection (the nearer of the two roots inside the clipping, else the farther) and
 * their (u, v) parametrization. The tracer wraps them as Embree user geometry. */
#ifndef CLR_RENDER_QUADRICS_H
#define CLR_RENDER_QUADRICS_H

typedef enum {
  CLR_QUADRIC_CYLINDER,
  CLR_QUADRIC_CONE,
  CLR_QUADRIC_PARABOLOID,
  CLR_QUADRIC_HYPERBOLOID
} clr_quadric_type;

typedef struct clr_quadric {
  clr_quadric_type type;
  double radius, zmin, zmax, height, phimax; /* phimax in radians */
  double p1[3], p2[3];                       /* hyperboloid: the line swept about z */
  double ah, ch, rmax;                       /* hyperboloid: a x^2 + a y^2 - c z^2 = 1 */
} clr_quadric;

/* Completes the derived values (pbrt-v3's constructors: z range sorted, hyperboloid
 * coefficients); 0 when the parameters describe no surface (the message is in *why). */
int clr_quadric_init(clr_quadric *q, const char **why);
/* An object-space box: |x|, |y| <= *r, z in [*z0, *z1]. */
void clr_quadric_bounds(const clr_quadric *q, double *r, double *z0, double *z1);
/* Ray o + t d (object space) against the quadric: 1 with *t in (0, tmax] when hit. */
int clr_quadric_intersect(const clr_quadric *q, const double o[3], const double d[3], double tmax,
                          double *t);
/* At an object-space point on the surface: pbrt-v3's (u, v), dpdu and dpdv. */
void clr_quadric_param(const clr_quadric *q, const double p[3], double uv[2], double dpdu[3],
                       double dpdv[3]);
/* pbrt-v3's dndu, dndv (Weingarten equations) of the unit normal along dpdu x dpdv at an
 * object-space surface point; 0 where the partials are degenerate (cone apex, paraboloid tip). */
void clr_quadric_normal_partials(const clr_quadric *q, const double p[3], double dndu[3],
                                 double dndv[3]);
/* The surface point at (u, v). */
void clr_quadric_point(const clr_quadric *q, double u, double v, double p[3]);

#endif
