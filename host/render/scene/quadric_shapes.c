/* pbrt-v3 CreateCylinderShape, CreateConeShape, CreateParaboloidShape, CreateHyperboloidShape
 * parameters, and the surface of a quadric hit. */
#include <math.h>
#include <string.h>
#include "render_error.h"
#include "quadric_shapes.h"
#include "vec3.h"
#include "float_minmax.h"

int rs_is_quadric(const char *type) {
  return strcmp(type, "cylinder") == 0 || strcmp(type, "cone") == 0 ||
         strcmp(type, "paraboloid") == 0 || strcmp(type, "hyperboloid") == 0;
}

clr_result rs_quadric_from_params(const char *type, const clr_param_list *p, clr_quadric *q) {
  memset(q, 0, sizeof *q);
  q->phimax = clr_params_find_float(p, "phimax", 360.0f) * 3.14159265358979323846 / 180.0;
  if (strcmp(type, "cylinder") == 0) {
    q->type = CLR_QUADRIC_CYLINDER;
    q->radius = clr_params_find_float(p, "radius", 1.0f);
    q->zmin = clr_params_find_float(p, "zmin", -1.0f);
    q->zmax = clr_params_find_float(p, "zmax", 1.0f);
  } else if (strcmp(type, "cone") == 0) {
    q->type = CLR_QUADRIC_CONE;
    q->radius = clr_params_find_float(p, "radius", 1.0f);
    q->height = clr_params_find_float(p, "height", 1.0f);
  } else if (strcmp(type, "paraboloid") == 0) {
    q->type = CLR_QUADRIC_PARABOLOID;
    q->radius = clr_params_find_float(p, "radius", 1.0f);
    q->zmin = clr_params_find_float(p, "zmin", 0.0f);
    q->zmax = clr_params_find_float(p, "zmax", 1.0f);
  } else {
    static const float origin[3] = {0, 0, 0}, one[3] = {1, 1, 1};
    float a[3], b[3];
    q->type = CLR_QUADRIC_HYPERBOLOID;
    clr_params_find_point3(p, "p1", origin, a);
    clr_params_find_point3(p, "p2", one, b);
    for (int k = 0; k < 3; ++k) {
      q->p1[k] = a[k];
      q->p2[k] = b[k];
    }
  }
  const char *why;
  if (!clr_quadric_init(q, &why)) /* q keeps the derived values the surface needs */
    return clr_set_last_error(CLR_ERROR_SCENE, "%s:%d: Shape \"%s\": %s", p->file ? p->file : "?",
                              p->line, type, why);
  return CLR_SUCCESS;
}

void rs_quadric_surface(const clr_quadric *q, const clr_transform *o2w, const float pw[3],
                        float p[3], float n[3], float uv[2], float dpdu[3]) {
  const clr_quadric qi = *q;
  clr_transform w2o = clr_transform_inverse(o2w);
  float po[3];
  clr_transform_point(&w2o, pw, po);
  if (qi.type == CLR_QUADRIC_CYLINDER) { /* pbrt-v3 refines the hit onto the radius */
    float r = sqrtf(po[0] * po[0] + po[1] * po[1]);
    if (r > 0.0f) {
      po[0] *= (float)qi.radius / r;
      po[1] *= (float)qi.radius / r;
    }
  }
  double pd[3] = {po[0], po[1], po[2]}, uvd[2], du[3], dv[3];
  clr_quadric_param(&qi, pd, uvd, du, dv);
  float duf[3] = {(float)du[0], (float)du[1], (float)du[2]};
  float dvf[3] = {(float)dv[0], (float)dv[1], (float)dv[2]}, no[3];
  rs_cross(duf, dvf, no);
  clr_transform_point(o2w, po, p);
  clr_transform_normal(o2w, no, n);
  rs_normalize(n);
  clr_transform_vector(o2w, duf, dpdu);
  uv[0] = (float)uvd[0];
  uv[1] = (float)uvd[1];
}

void rs_quadric_bounds(const clr_quadric *q, const clr_transform *o2w, float lo[3], float hi[3]) {
  double r, z0, z1;
  clr_quadric_bounds(q, &r, &z0, &z1);
  for (int i = 0; i < 3; ++i) {
    lo[i] = INFINITY;
    hi[i] = -INFINITY;
  }
  for (int c = 0; c < 8; ++c) {
    float o[3] = {(float)((c & 1) ? r : -r), (float)((c & 2) ? r : -r), (float)((c & 4) ? z1 : z0)},
          w[3];
    clr_transform_point(o2w, o, w);
    for (int i = 0; i < 3; ++i) {
      lo[i] = rs_fminf(lo[i], w[i]);
      hi[i] = rs_fmaxf(hi[i], w[i]);
    }
  }
}
