/* pbrt-v3 projective cameras (perspective, orthographic) with a thin lens. */
#include <math.h>
#include <string.h>
#include "render_error.h"
#include "camera.h"
#include "vec3.h"
#include "float_minmax.h"

clr_result rs_camera_build(rs_camera *cam, const clr_scene_desc *d, clr_warn_fn warn, void *wu) {
  const clr_param_list *p = &d->camera.params;
  memset(cam, 0, sizeof *cam);
  const char *type = d->camera.type ? d->camera.type : "perspective";
  if (strcmp(type, "perspective") == 0) {
    cam->type = RS_CAMERA_PERSPECTIVE;
  } else if (strcmp(type, "orthographic") == 0) {
    cam->type = RS_CAMERA_ORTHOGRAPHIC;
  } else {
    return clr_set_last_error(CLR_ERROR_SCENE, "%s:%d: unsupported camera \"%s\"",
                              p->file ? p->file : "?", p->line, type);
  }
  cam->differential_scale = 1.0f;
  cam->lens_radius = clr_params_find_float(p, "lensradius", 0.0f);
  cam->focal_distance = clr_params_find_float(p, "focaldistance", 1e6f);
  cam->frame_aspect = clr_params_find_float(p, "frameaspectratio", -1.0f);
  cam->shutter_open = clr_params_find_float(p, "shutteropen", 0.0f);
  cam->shutter_close = clr_params_find_float(p, "shutterclose", 1.0f);
  if (cam->shutter_close < cam->shutter_open) {
    float t = cam->shutter_open;
    cam->shutter_open = cam->shutter_close;
    cam->shutter_close = t;
  }
  int n = 0;
  const float *sw = clr_params_find_floats(p, "screenwindow", &n);
  if (sw && n == 4) {
    memcpy(cam->screen, sw, sizeof cam->screen);
    cam->screen_given = 1;
  } else if (sw && warn) {
    warn(wu, "Camera \"screenwindow\" needs four values: ignored");
  }
  if (cam->type == RS_CAMERA_PERSPECTIVE) {
    cam->fov = clr_params_find_float(p, "fov", 90.0f);
    float half = clr_params_find_float(p, "halffov", -1.0f);
    if (half > 0.0f) cam->fov = 2.0f * half;
  }
  cam->camera_to_world = d->camera.camera_to_world;
  rs_animated_transform_init(&cam->motion, &d->camera.camera_to_world,
                             &d->camera.camera_to_world_end, d->transform_start_time,
                             d->transform_end_time);
  return CLR_SUCCESS;
}

static clr_transform perspective(float fov_deg, float n, float f) {
  float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, f / (f - n), -f * n / (f - n)}, {0, 0, 1, 0}};
  clr_transform persp;
  clr_transform_from_matrix(m, &persp);
  float inv_tan = 1.0f / tanf(fov_deg * (RS_PI / 180.0f) * 0.5f);
  clr_transform s = clr_transform_scale(inv_tan, inv_tan, 1.0f);
  return clr_transform_compose(&s, &persp);
}

clr_result rs_camera_set_film(rs_camera *cam, int32_t xres, int32_t yres) {
  float frame = cam->frame_aspect > 0.0f ? cam->frame_aspect : (float)xres / (float)yres;
  float sw[4];
  if (cam->screen_given) {
    memcpy(sw, cam->screen, sizeof sw);
  } else if (frame > 1.0f) {
    sw[0] = -frame;
    sw[1] = frame;
    sw[2] = -1.0f;
    sw[3] = 1.0f;
  } else {
    sw[0] = -1.0f;
    sw[1] = 1.0f;
    sw[2] = -1.0f / frame;
    sw[3] = 1.0f / frame;
  }
  clr_transform camera_to_screen = cam->type == RS_CAMERA_PERSPECTIVE
                                       ? perspective(cam->fov, 1e-2f, 1000.0f)
                                       : clr_transform_identity();
  clr_transform a = clr_transform_scale((float)xres, (float)yres, 1.0f);
  clr_transform b = clr_transform_scale(1.0f / (sw[1] - sw[0]), 1.0f / (sw[2] - sw[3]), 1.0f);
  clr_transform c = clr_transform_translate(-sw[0], -sw[3], 0.0f);
  clr_transform ab = clr_transform_compose(&a, &b);
  clr_transform screen_to_raster = clr_transform_compose(&ab, &c);
  clr_transform raster_to_screen = clr_transform_inverse(&screen_to_raster);
  clr_transform screen_to_camera = clr_transform_inverse(&camera_to_screen);
  cam->raster_to_camera = clr_transform_compose(&screen_to_camera, &raster_to_screen);
  float p0[3] = {0, 0, 0}, px[3] = {1, 0, 0}, py[3] = {0, 1, 0}, c0[3], cx[3], cy[3];
  clr_transform_point(&cam->raster_to_camera, p0, c0);
  clr_transform_point(&cam->raster_to_camera, px, cx);
  clr_transform_point(&cam->raster_to_camera, py, cy);
  for (int i = 0; i < 3; ++i) {
    cam->dx_camera[i] = cx[i] - c0[i];
    cam->dy_camera[i] = cy[i] - c0[i];
  }
  /* a pinhole's rays all leave the camera-space origin: its world point, mapped once */
  const float origin[3] = {0.0f, 0.0f, 0.0f};
  cam->fixed_origin =
      cam->type == RS_CAMERA_PERSPECTIVE && !(cam->lens_radius > 0.0f) && !cam->motion.animated;
  clr_transform_point(&cam->camera_to_world, origin, cam->origin_world);
  return CLR_SUCCESS;
}

/* The camera-space ray through camera point pc (on the near plane or the ortho plane) for lens
 * point (lx, ly) (both 0 without a lens). */
static void camera_space_ray(const rs_camera *cam, const float pc[3], float lx, float ly,
                             float o[3], float d[3]) {
  if (cam->type == RS_CAMERA_PERSPECTIVE) {
    o[0] = o[1] = o[2] = 0.0f;
    memcpy(d, pc, 3 * sizeof(float));
    rs_normalize(d);
  } else {
    memcpy(o, pc, 3 * sizeof(float));
    d[0] = d[1] = 0.0f;
    d[2] = 1.0f;
  }
  if (cam->lens_radius > 0.0f) {
    float ft = cam->focal_distance / d[2];
    float focus[3] = {o[0] + ft * d[0], o[1] + ft * d[1], o[2] + ft * d[2]};
    o[0] += lx;
    o[1] += ly;
    if (cam->type == RS_CAMERA_PERSPECTIVE) o[0] = lx, o[1] = ly;
    for (int i = 0; i < 3; ++i) d[i] = focus[i] - o[i];
    rs_normalize(d);
  }
}

/* pbrt-v3 GenerateRayDifferential's offset rays (camera space) moved to world space by c2w and
 * scaled toward the main world ray (ow, dw) by the camera's differential scale. */
static void differential(const rs_camera *cam, const float pc[3], float lx, float ly,
                         const clr_transform *c2w, const float ow[3], const float dw[3],
                         clr_ray_differential *rd) {
  const float *step[2] = {cam->dx_camera, cam->dy_camera};
  float *outo[2] = {rd->rx_o, rd->ry_o}, *outd[2] = {rd->rx_d, rd->ry_d};
  float sc = cam->differential_scale;
  for (int k = 0; k < 2; ++k) {
    float q[3] = {pc[0] + step[k][0], pc[1] + step[k][1], pc[2] + step[k][2]}, o[3], d[3];
    camera_space_ray(cam, q, lx, ly, o, d);
    clr_transform_point(c2w, o, outo[k]);
    clr_transform_vector(c2w, d, outd[k]);
    rs_normalize(outd[k]);
    for (int i = 0; i < 3; ++i) {
      outo[k][i] = ow[i] + (outo[k][i] - ow[i]) * sc;
      outd[k][i] = dw[i] + (outd[k][i] - dw[i]) * sc;
    }
  }
  rd->has = 1;
}

float rs_camera_ray(const rs_camera *cam, float film_x, float film_y, float time, float lens_u,
                    float lens_v, clr_ray *ray, clr_ray_differential *rd) {
  float pf[3] = {film_x, film_y, 0.0f}, pc[3];
  clr_transform_point(&cam->raster_to_camera, pf, pc);
  float o[3], d[3], lx = 0.0f, ly = 0.0f;
  if (cam->lens_radius > 0.0f) {
    rs_concentric_disk(lens_u, lens_v, &lx, &ly);
    lx *= cam->lens_radius;
    ly *= cam->lens_radius;
  }
  camera_space_ray(cam, pc, lx, ly, o, d);
  float ow[3], dw[3];
  const clr_transform *c2w = &cam->camera_to_world;
  clr_transform moved;
  if (cam->motion.animated) { /* pbrt-v3: ray time Lerp(sample, shutter open, close) */
    float t = (1.0f - time) * cam->shutter_open + time * cam->shutter_close;
    rs_animated_transform_at(&cam->motion, t, &moved);
    c2w = &moved;
  }
  if (cam->fixed_origin)
    memcpy(ow, cam->origin_world, sizeof ow);
  else
    clr_transform_point(c2w, o, ow);
  clr_transform_vector(c2w, d, dw);
  rs_normalize(dw);
  if (rd) differential(cam, pc, lx, ly, c2w, ow, dw, rd);
  ray->ox = ow[0];
  ray->oy = ow[1];
  ray->oz = ow[2];
  ray->dx = dw[0];
  ray->dy = dw[1];
  ray->dz = dw[2];
  ray->tnear = 0.0f;
  ray->tfar = INFINITY;
  /* moving shapes: the shutter time mapped onto TransformTimes, clamped (Embree's [0, 1]) */
  float shutter_t = (1.0f - time) * cam->shutter_open + time * cam->shutter_close;
  float span = cam->motion.end_time - cam->motion.start_time;
  ray->time = span > 0.0f
                  ? rs_fminf(rs_fmaxf((shutter_t - cam->motion.start_time) / span, 0.0f), 1.0f)
                  : 0.0f;
  return 1.0f;
}
