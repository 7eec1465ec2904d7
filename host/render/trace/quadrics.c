/* pbrt-v3's Cylinder, Cone, Paraboloid and Hyperboloid (its shapes directory) re-implemented from their
 * definitions, in double precision without pbrt-v3's error bounds. */
#include <math.h>
#include "quadrics.h"

#define PI_D 3.14159265358979323846

int clr_quadric_init(clr_quadric *q, const char **why) {
  *why = "";
  if (!(q->phimax > 0.0) || !(q->phimax <= 2.0 * PI_D + 1e-9)) {
    *why = "\"phimax\" must be in (0, 360]";
    return 0;
  }
  switch (q->type) {
    case CLR_QUADRIC_CYLINDER:
    case CLR_QUADRIC_PARABOLOID: {
      double z0 = fmin(q->zmin, q->zmax), z1 = fmax(q->zmin, q->zmax);
      q->zmin = z0;
      q->zmax = z1;
      if (!(q->radius > 0.0) || !isfinite(q->radius) || !isfinite(z0) || !isfinite(z1) ||
          !(z1 > z0) || (q->type == CLR_QUADRIC_PARABOLOID && !(z0 >= 0.0))) {
        *why = q->type == CLR_QUADRIC_CYLINDER
                   ? "needs \"radius\" > 0 and \"zmin\" != \"zmax\""
                   : "needs \"radius\" > 0 and 0 <= \"zmin\" < \"zmax\"";
        return 0;
      }
      return 1;
    }
    case CLR_QUADRIC_CONE:
      if (!(q->radius > 0.0) || !isfinite(q->radius) || !(q->height > 0.0) ||
          !isfinite(q->height)) {
        *why = "needs \"radius\" > 0 and \"height\" > 0";
        return 0;
      }
      return 1;
    case CLR_QUADRIC_HYPERBOLOID: {
      double *p1 = q->p1, *p2 = q->p2;
      for (int k = 0; k < 3; ++k)
        if (!isfinite(p1[k]) || !isfinite(p2[k])) {
          *why = "\"p1\" and \"p2\" must be finite";
          return 0;
        }
      q->zmin = fmin(p1[2], p2[2]);
      q->zmax = fmax(p1[2], p2[2]);
      q->rmax = fmax(sqrt(p1[0] * p1[0] + p1[1] * p1[1]), sqrt(p2[0] * p2[0] + p2[1] * p2[1]));
      if (p2[2] == 0.0)
        for (int k = 0; k < 3; ++k) {
          double s = p1[k];
          p1[k] = p2[k];
          p2[k] = s;
        }
      double pp[3] = {p1[0], p1[1], p1[2]};
      for (int iter = 0; iter < 64; ++iter) { /* pbrt-v3's loop, bounded */
        for (int k = 0; k < 3; ++k) pp[k] += 2.0 * (p2[k] - p1[k]);
        double xy1 = pp[0] * pp[0] + pp[1] * pp[1], xy2 = p2[0] * p2[0] + p2[1] * p2[1];
        double z2 = p2[2] * p2[2];
        q->ah =
            (1.0 / xy1 - (pp[2] * pp[2]) / (xy1 * z2)) / (1.0 - (xy2 * pp[2] * pp[2]) / (xy1 * z2));
        q->ch = (q->ah * xy2 - 1.0) / z2;
        if (isfinite(q->ah) && isfinite(q->ch) && q->zmax > q->zmin) return 1;
      }
      *why = "\"p1\" and \"p2\" describe no hyperboloid (need distinct z)";
      return 0;
    }
  }
  return 0;
}

void clr_quadric_bounds(const clr_quadric *q, double *r, double *z0, double *z1) {
  *r = q->type == CLR_QUADRIC_HYPERBOLOID ? q->rmax : q->radius;
  *z0 = q->type == CLR_QUADRIC_CONE ? 0.0 : q->zmin;
  *z1 = q->type == CLR_QUADRIC_CONE ? q->height : q->zmax;
}

static double phi_of(const clr_quadric *q, const double p[3]) {
  double phi;
  if (q->type == CLR_QUADRIC_HYPERBOLOID) {
    double v = (p[2] - q->p1[2]) / (q->p2[2] - q->p1[2]);
    double pr[2] = {(1 - v) * q->p1[0] + v * q->p2[0], (1 - v) * q->p1[1] + v * q->p2[1]};
    phi = atan2(p[1] * pr[0] - pr[1] * p[0], p[0] * pr[0] + p[1] * pr[1]);
  } else {
    phi = atan2(p[1], p[0]);
  }
  return phi < 0.0 ? phi + 2.0 * PI_D : phi;
}

/* The hit point at t (the cylinder's refined onto its radius) if inside the clipping. */
static int accept(const clr_quadric *q, const double o[3], const double d[3], double t) {
  double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
  if (q->type == CLR_QUADRIC_CYLINDER) {
    double r = sqrt(p[0] * p[0] + p[1] * p[1]);
    if (r > 0.0) {
      p[0] *= q->radius / r;
      p[1] *= q->radius / r;
    }
  }
  double z0, z1, r;
  clr_quadric_bounds(q, &r, &z0, &z1);
  return !(p[2] < z0 || p[2] > z1 || phi_of(q, p) > q->phimax);
}

int clr_quadric_intersect(const clr_quadric *q, const double o[3], const double d[3], double tmax,
                          double *t) {
  double a, b, c;
  switch (q->type) {
    case CLR_QUADRIC_CYLINDER:
      a = d[0] * d[0] + d[1] * d[1];
      b = 2.0 * (d[0] * o[0] + d[1] * o[1]);
      c = o[0] * o[0] + o[1] * o[1] - q->radius * q->radius;
      break;
    case CLR_QUADRIC_CONE: {
      double k = (q->radius / q->height) * (q->radius / q->height), oz = o[2] - q->height;
      a = d[0] * d[0] + d[1] * d[1] - k * d[2] * d[2];
      b = 2.0 * (d[0] * o[0] + d[1] * o[1] - k * d[2] * oz);
      c = o[0] * o[0] + o[1] * o[1] - k * oz * oz;
      break;
    }
    case CLR_QUADRIC_PARABOLOID: {
      double k = q->zmax / (q->radius * q->radius);
      a = k * (d[0] * d[0] + d[1] * d[1]);
      b = 2.0 * k * (d[0] * o[0] + d[1] * o[1]) - d[2];
      c = k * (o[0] * o[0] + o[1] * o[1]) - o[2];
      break;
    }
    default:
      a = q->ah * (d[0] * d[0] + d[1] * d[1]) - q->ch * d[2] * d[2];
      b = 2.0 * (q->ah * (d[0] * o[0] + d[1] * o[1]) - q->ch * d[2] * o[2]);
      c = q->ah * (o[0] * o[0] + o[1] * o[1]) - q->ch * o[2] * o[2] - 1.0;
  }
  double t0, t1;
  if (a == 0.0) { /* one root (a ray along the cone's or cylinder's degenerate direction) */
    if (b == 0.0) return 0;
    t0 = t1 = -c / b;
  } else {
    double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return 0;
    double root = sqrt(disc), qq = b < 0.0 ? -0.5 * (b - root) : -0.5 * (b + root);
    t0 = qq / a;
    t1 = qq != 0.0 ? c / qq : t0;
    if (t0 > t1) {
      double s = t0;
      t0 = t1;
      t1 = s;
    }
  }
  if (t0 > tmax || t1 <= 0.0) return 0;
  if (t0 > 0.0 && accept(q, o, d, t0)) {
    *t = t0;
    return 1;
  }
  if (t1 > tmax || t1 == t0 || !accept(q, o, d, t1)) return 0;
  *t = t1;
  return 1;
}

void clr_quadric_param(const clr_quadric *q, const double p[3], double uv[2], double dpdu[3],
                       double dpdv[3]) {
  double phi = phi_of(q, p);
  uv[0] = phi / q->phimax;
  dpdu[0] = -q->phimax * p[1];
  dpdu[1] = q->phimax * p[0];
  dpdu[2] = 0.0;
  switch (q->type) {
    case CLR_QUADRIC_CYLINDER:
      uv[1] = (p[2] - q->zmin) / (q->zmax - q->zmin);
      dpdv[0] = dpdv[1] = 0.0;
      dpdv[2] = q->zmax - q->zmin;
      return;
    case CLR_QUADRIC_CONE: {
      uv[1] = p[2] / q->height;
      double w = 1.0 - uv[1];
      dpdv[0] = w > 0.0 ? -p[0] / w : 0.0;
      dpdv[1] = w > 0.0 ? -p[1] / w : 0.0;
      dpdv[2] = q->height;
      return;
    }
    case CLR_QUADRIC_PARABOLOID: {
      double dz = q->zmax - q->zmin;
      uv[1] = (p[2] - q->zmin) / dz;
      dpdv[0] = p[2] > 0.0 ? dz * p[0] / (2.0 * p[2]) : 0.0;
      dpdv[1] = p[2] > 0.0 ? dz * p[1] / (2.0 * p[2]) : 0.0;
      dpdv[2] = dz;
      return;
    }
    default: {
      uv[1] = (p[2] - q->p1[2]) / (q->p2[2] - q->p1[2]);
      double c = cos(phi), s = sin(phi), ex = q->p2[0] - q->p1[0], ey = q->p2[1] - q->p1[1];
      dpdv[0] = ex * c - ey * s;
      dpdv[1] = ex * s + ey * c;
      dpdv[2] = q->p2[2] - q->p1[2];
    }
  }
}

void clr_quadric_point(const clr_quadric *q, double u, double v, double p[3]) {
  double phi = u * q->phimax, c = cos(phi), s = sin(phi);
  switch (q->type) {
    case CLR_QUADRIC_CYLINDER:
      p[0] = q->radius * c;
      p[1] = q->radius * s;
      p[2] = q->zmin + v * (q->zmax - q->zmin);
      return;
    case CLR_QUADRIC_CONE:
      p[0] = q->radius * (1.0 - v) * c;
      p[1] = q->radius * (1.0 - v) * s;
      p[2] = v * q->height;
      return;
    case CLR_QUADRIC_PARABOLOID: {
      double z = q->zmin + v * (q->zmax - q->zmin), r = q->radius * sqrt(z / q->zmax);
      p[0] = r * c;
      p[1] = r * s;
      p[2] = z;
      return;
    }
    default: {
      double pr[3];
      for (int k = 0; k < 3; ++k) pr[k] = (1 - v) * q->p1[k] + v * q->p2[k];
      p[0] = pr[0] * c - pr[1] * s;
      p[1] = pr[0] * s + pr[1] * c;
      p[2] = pr[2];
    }
  }
}

static double dot_d(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* pbrt-v3's second partials of each quadric at object-space p (uv and dpdv from
 * clr_quadric_param). */
static void second_partials(const clr_quadric *q, const double p[3], const double uv[2],
                            const double dpdv[3], double duu[3], double duv[3], double dvv[3]) {
  double f = q->phimax * q->phimax;
  duu[0] = -f * p[0], duu[1] = -f * p[1], duu[2] = 0.0;
  duv[0] = duv[1] = duv[2] = dvv[0] = dvv[1] = dvv[2] = 0.0;
  switch (q->type) {
    case CLR_QUADRIC_CYLINDER:
      return;
    case CLR_QUADRIC_CONE: {
      double w = 1.0 - uv[1], k = w > 0.0 ? q->phimax / w : 0.0;
      duv[0] = k * p[1], duv[1] = -k * p[0];
      return;
    }
    case CLR_QUADRIC_PARABOLOID: {
      double dz = q->zmax - q->zmin, z = p[2];
      if (!(z > 0.0)) return;
      duv[0] = -dz * q->phimax * p[1] / (2.0 * z), duv[1] = dz * q->phimax * p[0] / (2.0 * z);
      dvv[0] = -dz * dz * p[0] / (4.0 * z * z), dvv[1] = -dz * dz * p[1] / (4.0 * z * z);
      return;
    }
    default:
      duv[0] = -q->phimax * dpdv[1], duv[1] = q->phimax * dpdv[0];
  }
}

void clr_quadric_normal_partials(const clr_quadric *q, const double p[3], double dndu[3],
                                 double dndv[3]) {
  double uv[2], du[3], dv[3], duu[3], duv[3], dvv[3];
  clr_quadric_param(q, p, uv, du, dv);
  second_partials(q, p, uv, dv, duu, duv, dvv);
  double n[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
                 du[0] * dv[1] - du[1] * dv[0]};
  double len = sqrt(dot_d(n, n));
  double E = dot_d(du, du), F = dot_d(du, dv), G = dot_d(dv, dv), det = E * G - F * F;
  for (int i = 0; i < 3; ++i) dndu[i] = dndv[i] = 0.0;
  if (!(len > 0.0) || !(det > 0.0) || !isfinite(det)) return; /* apex, pole: pbrt-v3's inf/NaN */
  for (int i = 0; i < 3; ++i) n[i] /= len;
  double e = dot_d(n, duu), f = dot_d(n, duv), g = dot_d(n, dvv);
  for (int i = 0; i < 3; ++i) { /* Weingarten equations */
    dndu[i] = ((f * F - e * G) * du[i] + (e * F - f * E) * dv[i]) / det;
    dndv[i] = ((g * F - f * G) * du[i] + (f * F - g * E) * dv[i]) / det;
  }
}
