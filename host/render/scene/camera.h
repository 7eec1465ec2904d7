/* pbrt-v3 perspective and orthographic cameras with a thin lens. */
#ifndef CLR_RENDER_CAMERA_H
#define CLR_RENDER_CAMERA_H

#include <stdint.h>
#include "clrender/result.h"
#include "animated_transform.h"
#include "camera_sample.h"
#include "ray_differential.h"
#include "scene_desc.h"
#include "tracer.h"

typedef enum { RS_CAMERA_PERSPECTIVE, RS_CAMERA_ORTHOGRAPHIC } rs_camera_type;

typedef struct rs_camera {
  rs_camera_type type;
  float fov, lens_radius, focal_distance, shutter_open, shutter_close;
  float frame_aspect; /* <= 0: from the film resolution */
  float screen[4];    /* x0 x1 y0 y1; given when screen_given */
  int screen_given;
  clr_transform camera_to_world;
  rs_animated_transform motion; /* ActiveTransform EndTime moved the camera: used per ray time */
  clr_transform raster_to_camera;
  float dx_camera[3], dy_camera[3]; /* pbrt-v3 dxCamera, dyCamera: one pixel in camera space */
  float differential_scale;         /* pbrt-v3 ScaleDifferentials: 1 / sqrt(spp) */
  int fixed_origin;                 /* every ray starts at origin_world (pinhole, not moving) */
  float origin_world[3];            /* camera_to_world of the camera-space origin */
} rs_camera;

/* The Camera directive's parameters. */
clr_result rs_camera_build(rs_camera *cam, const clr_scene_desc *d, clr_warn_fn warn, void *wu);
/* Raster-to-camera for the final film resolution (call before rs_camera_ray). */
clr_result rs_camera_set_film(rs_camera *cam, int32_t x_resolution, int32_t y_resolution);
/* pbrt-v3 GenerateRay for raster position (film_x, film_y), lens sample (lens_u, lens_v);
 * returns the ray weight. With rd: GenerateRayDifferential, the offset rays scaled by
 * differential_scale (the orthographic thin lens focuses them as its main ray). */
float rs_camera_ray(const rs_camera *cam, float film_x, float film_y, float time, float lens_u,
                    float lens_v, clr_ray *ray, clr_ray_differential *rd);

/* The rays of n camera samples (structure of arrays): rays[k], rd[k] (when rd) and weights[k]
 * as rs_camera_ray makes them for sample k, the same bits; the pinhole's in waves of
 * RS_CAMERA_WAVE without a call per ray. */
#define RS_CAMERA_WAVE 64
void rs_camera_rays(const rs_camera *cam, const clr_camera_samples *samples, int n, clr_ray *rays,
                    clr_ray_differential *rd, float *weights);

#endif
