/* The renderable scene built from a parsed pbrt-v3 description: Embree geometry, camera,
 * materials with textures, and lights, with the queries the integrators make. This header is
 * the contract between scene building (camera.c, lights.c, materials.c, textures.c,
 * render_scene.c) and the integrators/render loop. All colours are linear RGB. */
#ifndef CLR_RENDER_SCENE_H
#define CLR_RENDER_SCENE_H

#include <stdint.h>
#include "clrender/result.h"
#include "bsdf_lobes.h"
#include "camera_sample.h"
#include "lights.h"
#include "ray_differential.h"
#include "scene_desc.h"
#include "tracer.h"

typedef struct clr_render_scene clr_render_scene;

/* Film and camera settings resolved from the scene file and CLI overrides. */
typedef struct clr_render_settings {
  int32_t x_resolution, y_resolution; /* Film "xresolution"/"yresolution" (1280x720) */
  float crop_window[4];               /* Film "cropwindow" x0 x1 y0 y1 (0 1 0 1) */
  float scale;                        /* Film "scale" (1) */
  float max_sample_luminance;         /* Film "maxsampleluminance" (inf) */
  char filename[1024];                /* Film "filename" ("pbrt.exr") */
} clr_render_settings;

/* Builds everything. `warn` gets one message per unsupported feature or fallback (with the
 * scene file and line). Errors (bad mesh index, missing PLY/texture file, ...) name the file and
 * line of the directive. */
clr_result clr_render_scene_build(const clr_scene_desc *desc, clr_warn_fn warn, void *warn_user,
                                  clr_render_scene **out);
void clr_render_scene_free(clr_render_scene *scene);

/* Film settings read from desc->film (before CLI overrides). */
void clr_render_settings_from_desc(const clr_scene_desc *desc, clr_render_settings *settings);

clr_tracer clr_render_scene_tracer(const clr_render_scene *scene);
/* The bounds of every shape (pbrt-v3 Scene::WorldBound). */
void clr_render_scene_world_bounds(const clr_render_scene *scene, float lo[3], float hi[3]);

/* --- camera (pbrt-v3 perspective/orthographic, thin lens) --- */
/* Must be called once the final film resolution / crop is known (before generating rays). */
clr_result clr_render_scene_set_film(clr_render_scene *scene, int32_t x_resolution,
                                     int32_t y_resolution);
/* pbrt-v3's ScaleDifferentials(1 / sqrt(spp)) of every camera ray (SamplerIntegrator::Render). */
void clr_render_scene_set_samples_per_pixel(clr_render_scene *scene, int32_t spp);
/* pbrt-v3 camera sample: pFilm in raster space (pixel + film offset), time in [0,1) mapped to
 * [shutteropen, shutterclose], lens in [0,1)^2. Returns the ray weight (1 or 0 if none). rd
 * (may be NULL) gets the ray's differentials when the scene has a surface that uses them (an
 * imagemap through its MIP map, a bump map), else rd->has = 0. */
float clr_render_scene_camera_ray(const clr_render_scene *scene, float film_x, float film_y,
                                  float time, float lens_u, float lens_v, clr_ray *ray,
                                  clr_ray_differential *rd);

/* clr_render_scene_camera_ray of n camera samples (structure of arrays): rays[k], rd[k] and
 * weights[k], the same bits; rd may be NULL. */
void clr_render_scene_camera_rays(const clr_render_scene *scene, const clr_camera_samples *samples,
                                  int n, clr_ray *rays, clr_ray_differential *rd, float *weights);

/* Which camera sample values the scene's rays depend on: *time when the camera or a shape or an
 * instance moves (a ray's time places them), *lens when the camera has a lens radius. Where 0,
 * any value gives the same rays, hits and shading. */
void clr_render_scene_camera_reads(const clr_render_scene *scene, int *time, int *lens);

/* --- surfaces --- */
typedef struct clr_surface {
  float p[3];  /* world position */
  float ng[3]; /* geometric normal, unit, facing the side the ray came from (-dir) */
  float ns[3]; /* shading normal, unit, same hemisphere as ng */
  float uv[2];
  float dpdu[3];    /* pbrt dpdu (world), for the AO frame */
  float n_geom[3];  /* pbrt isect.n: geometric normal oriented as the shape's (unit) */
  float kd[3];      /* diffuse reflectance (matte Kd, textures evaluated) */
  float on_a, on_b; /* matte "sigma": pbrt-v3 Oren-Nayar A and B (Lambertian: 1 and 0) */
  int32_t mirror;   /* 1: material "mirror", a perfect specular reflector with kr */
  int32_t plastic;  /* 1: material "plastic": kd Lambertian + ks TrowbridgeReitz lobe */
  int32_t glass;    /* 1: material "glass" with roughness 0: FresnelSpecular (kr, kt, eta) */
  int32_t metal;    /* 1: material "metal": TrowbridgeReitz lobe (alpha), conductor m_eta, m_k */
  float m_eta[3], m_k[3];
  float kt[3], eta;
  float ks[3], alpha;   /* plastic Ks and microfacet alpha (roughness remapped) */
  float kr[3];          /* mirror "Kr" (textures evaluated); kd is 0 for a mirror */
  float le[3];          /* emitted radiance toward -ray.dir if an area light, else 0 */
  int32_t has_material; /* 0 for material "none" (invisible: continue the ray) */
  int32_t area_light;   /* index of the area light (into the light list) or -1 */
  int32_t general;      /* 1: the material is the lobe list `bsdf` (uber, substrate, mix, ...) */
  float time;           /* the hitting ray's motion time, given to the rays spawned here */
  /* Set only at mirror, glass and lobe-BSDF hits of rays with differentials (pbrt-v3
   * SpecularReflect / SpecularTransmit): the hit's screen-space dpdx, dpdy and the change of ns
   * (as oriented here) dndx = dndu dudx + dndv dvdx, dndy. */
  int32_t has_differentials;
  float dpdx[3], dpdy[3], dndx[3], dndy[3];
  clr_bsdf bsdf; /* last: the fields every hit reads and writes share fewer cache lines */
} clr_surface;

/* Non-zero when some surface filters its textures (camera rays then carry differentials). */
int clr_render_scene_uses_differentials(const clr_render_scene *scene);

/* Fills `s` for a hit of `ray`. */
void clr_render_scene_surface(const clr_render_scene *scene, const clr_ray *ray, const clr_hit *hit,
                              clr_surface *s);
/* The same for a ray with differentials rd (NULL or rd->has 0: none): pbrt-v3's
 * SurfaceInteraction::ComputeDifferentials filters the hit's textures and sets its bump step. */
void clr_render_scene_surface_differential(const clr_render_scene *scene, const clr_ray *ray,
                                           const clr_ray_differential *rd, const clr_hit *hit,
                                           clr_surface *s);

/* What AO reads of the surface (pbrt-v3 AOIntegrator: p, ng, n_geom, dpdu, has_material, time),
 * equal to clr_render_scene_surface's; the other fields are left as they were. */
void clr_render_scene_surface_geometry(const clr_render_scene *scene, const clr_ray *ray,
                                       const clr_hit *hit, clr_surface *s);

/* --- lights --- */
int32_t clr_render_scene_light_count(const clr_render_scene *scene);

/* What the integrators choose lights by. */
typedef struct clr_light_info {
  float power;         /* pbrt-v3 Light::Power luminance */
  int32_t nsamples;    /* "nsamples" */
  int32_t is_delta;    /* point, spot, distant */
  int32_t is_infinite; /* lights escaped rays reach */
} clr_light_info;
void clr_render_scene_light_info(const clr_render_scene *scene, int32_t light,
                                 clr_light_info *info);
/* Solid-angle pdf that sampling light `light` from p gives direction wi, hitting the emitter at
 * distance t with geometric normal n_hit (NULL for lights without a surface). */
float clr_render_scene_light_pdf(const clr_render_scene *scene, int32_t light, const float p[3],
                                 const float wi[3], float t, const float n_hit[3]);
/* 0 when `ray` misses light `light`'s own shape (pbrt-v3 Light::Pdf_Li == 0: skip the scene ray). */
int clr_render_scene_light_may_hit(const clr_render_scene *scene, int32_t light,
                                   const clr_ray *ray);
/* Radiance that light `light` sends along an escaped ray of direction d. */
void clr_render_scene_light_le(const clr_render_scene *scene, int32_t light, const float d[3],
                               float le[3]);

/* One light sample (see clr_light_sample in lights.h). */
void clr_render_scene_sample_light(const clr_render_scene *scene, int32_t light, const float p[3],
                                   const float ng[3], const float u[2], clr_light_sample *ls);
/* The same sample's wi, li and pdf without its shadow ray. */
void clr_render_scene_sample_light_li(const clr_render_scene *scene, int32_t light,
                                      const float p[3], const float u[2], clr_light_sample *ls);
/* The point Sample_Li picks on light `light` for u when it does not depend on the reference
 * point (triangle, disk, cylinder area lights); 0 for other lights. */
int clr_render_scene_light_emitter_point(const clr_render_scene *scene, int32_t light,
                                         const float u[2], clr_emitter_point *e);
/* Light `light`'s triangle (lights.h) when it is a triangle area light without shading normals;
 * 0 for other lights. */
int clr_render_scene_light_triangle(const clr_render_scene *scene, int32_t light,
                                    clr_light_triangle *t);
/* Light `light` (lights.h) when it is a point light without a pattern; 0 for other lights. */
int clr_render_scene_light_point(const clr_render_scene *scene, int32_t light, clr_light_point *p);
/* Radiance arriving along a ray that escaped the scene (infinite lights), summed. */
void clr_render_scene_escaped(const clr_render_scene *scene, const clr_ray *ray, float le[3]);

/* Offset ray origin for leaving surface s in direction d (avoids self-intersection). */
void clr_render_scene_spawn_ray(const clr_surface *s, const float d[3], clr_ray *ray);

#endif
