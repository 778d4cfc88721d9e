/* Reflective shadow maps for the photon tracer's first bounce (seed 001
 * 24.2.1; shaders/photon/photon_rsm.comp, src/render/photon/photon_rsm.c). Included after
 * pb_gpu.h. One map per light entry of the tracer's light table: point
 * lights a cube map (6 faces of res x res), spots a perspective map over the
 * outer cone, directional lights an orthographic map over the scene's
 * bounding disc. */
#ifndef PB_RSM_SHARED_H
#define PB_RSM_SHARED_H

PB_CONST(PB_RSM_MODE_RENDER, 0u)  /* one invocation per texel */
PB_CONST(PB_RSM_MODE_PYRAMID, 1u) /* one invocation per node of level push.level */
PB_CONST(PB_RSM_MODE_TOTAL, 2u)   /* one workgroup per light: sum of its faces, coverage */
PB_CONST(PB_RSM_MODE_BOOST, 3u)   /* one workgroup per light: the specular texels' weights
                                     raised to push.caustic_share of the map (photon_rsm.comp) */

/* --first-bounce auto (PB_PHOTON_PARAM_RSM_AUTO): a light's photons start
 * from its map where the map's coverage is below this, else they are traced
 * (photon_trace.comp; the derivation is in photon_rsm.comp). */
#define PB_RSM_AUTO_COVERAGE 0.5

/* One light's map: texels first .. first + count - 1 (faces x res x res,
 * face-major, then rows); total: the sum of the texels' sampling weights;
 * coverage: the share of the light's flux that falls on texels with a
 * weight, i.e. the share of a traced first bounce's photons that hit the
 * scene (both written by PB_RSM_MODE_TOTAL; photon_rsm.comp). */
PB_STRUCT(pb_gpu_rsm_light) {
  uint first;
  uint count;
  uint res;               /* texels per side of a face, a power of two */
  uint light;             /* index into the scene's lights[] */
  float total;
  float tan_half;         /* spot: half-size of the image plane at distance 1 */
  uint faces;             /* 6 (point: cube map) or 1 */
  uint levels;            /* log2(res): pyramid levels above the texels */
  float coverage;         /* flux on weighted texels / the light's flux in
                             the traced emission's domain, 0 .. 1 */
  float boost;            /* the factor PB_RSM_MODE_BOOST multiplied the
                             specular texels' weights by (1: none) */
} PB_END(pb_gpu_rsm_light)

/* One texel, 64 bytes: the ray through its centre from the light (origin,
 * unit dir) and its first hit (prim, u, v at distance t; prim ==
 * PB_GPU_MISS when none), flux: the flux the texel receives, W (intensity x
 * texel solid angle, spot falloff included; irradiance x texel area for
 * directional lights); area: that solid angle (sr) or area (m^2); weight:
 * the luminance of the reflected power (sampling weight); pyramid: storage
 * for node k of the light's weight pyramid, not for this texel (a map has
 * fewer pyramid nodes than texels, see common/rsm_texel.glsl's
 * pb_rsm_node). */
PB_STRUCT(pb_gpu_rsm_texel) {
  PB_VEC3(origin);
  uint prim;
  PB_VEC3(dir);
  float t;
  PB_VEC3(flux);
  float pyramid;
  float u;
  float v;
  float area;
  float weight;
} PB_END(pb_gpu_rsm_texel)

/* Push constants of photon_rsm.comp. */
PB_STRUCT(pb_gpu_rsm_push) {
  PB_VEC3(scene_center);
  float scene_radius;
  uint mode;
  uint light_count;
  uint texels;            /* all maps together */
  uint level;             /* PB_RSM_MODE_PYRAMID: the level built, 1 .. levels */
  float caustic_share;    /* share of a map's photons aimed at its specular
                             texels (PB_RSM_MODE_BOOST); 0: by power alone */
  uint pad0, pad1, pad2;
} PB_END(pb_gpu_rsm_push)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_rsm_light) == 40, "pb_gpu_rsm_light size");
_Static_assert(offsetof(pb_gpu_rsm_light, coverage) == 32, "pb_gpu_rsm_light.coverage");
_Static_assert(sizeof(pb_gpu_rsm_texel) == 64, "pb_gpu_rsm_texel size");
_Static_assert(offsetof(pb_gpu_rsm_texel, dir) == 16, "pb_gpu_rsm_texel.dir");
_Static_assert(offsetof(pb_gpu_rsm_texel, flux) == 32, "pb_gpu_rsm_texel.flux");
_Static_assert(offsetof(pb_gpu_rsm_texel, u) == 48, "pb_gpu_rsm_texel.u");
_Static_assert(sizeof(pb_gpu_rsm_push) == 48, "pb_gpu_rsm_push size");
#endif

#endif
