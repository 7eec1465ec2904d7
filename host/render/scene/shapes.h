/* The scene's shapes as the renderer keeps them: meshes and spheres with their material colour
 * and the index of their first area light. */
#ifndef CLR_RENDER_SHAPES_H
#define CLR_RENDER_SHAPES_H

#include "materials.h"
#include "mesh.h"
#include "quadrics.h"
#include "textures.h"
#include "transform.h"
#include "vec3.h"

typedef enum { RS_SHAPE_MESH, RS_SHAPE_SPHERE, RS_SHAPE_DISK, RS_SHAPE_QUADRIC } rs_shape_type;

typedef struct rs_shape {
  rs_shape_type type;
  clr_mesh mesh;     /* world space, or object space for shapes of an object */
  float *tri_frames; /* mesh: each triangle's unit normal and dpdu (6 floats), mesh_surface's */
  float radius;
  float height, inner_radius, phimax; /* disk (phimax in radians); sphere: phimax too */
  float zmin, zmax;                   /* sphere: pbrt-v3's clipping (object space), with phimax */
  int partial;                        /* sphere clipped by zmin/zmax/phimax */
  clr_quadric quadric;                /* cylinder, cone, paraboloid, hyperboloid */
  clr_transform object_to_world;      /* sphere: object to world (or to instance) */
  int flip_normal;                    /* pbrt reverseOrientation ^ transformSwapsHandedness */
  int has_material;
  rs_colour kd;
  float on_a, on_b; /* Oren-Nayar A, B from matte "sigma" (1, 0: Lambertian) */
  int mirror;       /* material "mirror": specular reflection with kr */
  rs_colour kr;
  int plastic; /* material "plastic": kd + ks microfacet lobe of alpha */
  int glass;   /* material "glass" (smooth): kr, kt, eta */
  int metal;   /* material "metal": m_eta, m_k (rgb), alpha */
  float m_eta[3], m_k[3];
  rs_colour kt;
  float eta;
  rs_colour ks;
  float alpha;
  rs_colour bump;          /* material "bumpmap" (float texture; texture -1: none); a mix: its first
                   * material's, as pbrt-v3's MixMaterial keeps that one's shading frame */
  int needs_differentials; /* its material reads a texture differentials filter, or a bump map */
  int general;             /* material built as lobes at each hit (materials.h) */
  rs_material gmat;
  int first_light; /* light index of triangle 0 / the sphere, -1 when not emitting */
  int in_object;
  clr_transform object_to_world_end; /* moving shapes: for the world bounds */
  int moving; /* kept in object space in a moving instance (ActiveTransform EndTime) */
} rs_shape;

/* pbrt-v3 Triangle's orientation of mesh triangle ix's geometric normal n at barycentrics (b0, b1,
 * b2): toward the interpolated vertex normal ns where the mesh has normals (then 1, ns written),
 * else flipped with flip_normal (0). */
static inline int rs_orient_triangle_normal(const rs_shape *sh, const uint32_t *ix, float b0,
                                            float b1, float b2, float n[3], float ns[3]) {
  if (!sh->mesh.n) {
    if (sh->flip_normal) rs_negate(n);
    return 0;
  }
  for (int i = 0; i < 3; ++i)
    ns[i] = b0 * sh->mesh.n[3 * ix[0] + i] + b1 * sh->mesh.n[3 * ix[1] + i] +
            b2 * sh->mesh.n[3 * ix[2] + i];
  if (rs_dot(n, ns) < 0.0f) rs_negate(n);
  return 1;
}

#endif
