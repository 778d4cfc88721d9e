/* Light sampling of the reference renderer: the light tables (lights.c),
 * point, spot, sun, area and sphere lights (soft_lights.c), emissive
 * triangles and MIS weights. */
#ifndef PB_REF_LIGHTS_H
#define PB_REF_LIGHTS_H

#include "ref/accel.h"
#include "ref/vec.h"
#include "scene/emitters.h"
#include "scene/scene.h"
#include "scene/world.h"

typedef struct pb_ref_lights {
  /* Emissive triangles, sampled by power from the scene's table
   * (scene/emitters.h). */
  uint32_t *emitters;     /* triangle indices */
  double *emitter_cdf;    /* emitter_count + 1 entries, cdf[last] = 1 */
  float *tri_pick_pdf;    /* per triangle: probability of picking it, or 0 */
  uint32_t emitter_count;
  /* Delta lights (point, spot and directional lights without size). */
  uint32_t delta_count;
  /* Soft lights (sphere, area, soft sun): every one sampled at every smooth
   * vertex, and hit by rays. */
  uint32_t soft_count;
  /* The world's sampling table (scene/world.h); world_nee: the world gets
   * a light sample at smooth vertices (a map). A constant world is reached
   * by BSDF sampling alone, as Cycles 3.4 does (scene/light.cpp disables a
   * spatially constant background's MIS), which is its best strategy. */
  pb_world_dist world_dist;
  int world_nee;
  /* Scene bounding sphere, for directional lights. */
  v3 center;
  float radius;
  /* Bounding sphere of triangles with a delta lobe (photon emission target),
   * radius 0 when there are none. */
  v3 spec_center;
  float spec_radius;
} pb_ref_lights;

pb_result pb_ref_lights_build(const pb_scene *s, pb_ref_lights *l);
void pb_ref_lights_destroy(pb_ref_lights *l);

/* Radiance-like contribution of delta light i at point p: the direction to
 * the light, the distance (INFINITY for directional), and Li such that the
 * reflected radiance is f |cos| Li. Returns 0 when it contributes nothing. */
int pb_delta_light_at(const pb_light *l, v3 p, v3 *wi, float *dist, v3 *Li);


/* Cycles 3.4's or 4.x's spot falloff or KHR's smooth step (scene.h pb_spot_model)
 * for the cosine of the angle between the spot's axis and the direction
 * light leaves in. */
float pb_spot_factor(const pb_light *l, float cos_angle);

/* A light sample toward a soft light (soft_lights.c). */
typedef struct pb_light_sample {
  v3 wi;      /* unit, from the lit point toward the light */
  float dist; /* to the sampled point (INFINITY for the sun) */
  v3 L;       /* radiance arriving along -wi */
  float pdf;  /* solid-angle density of wi */
} pb_light_sample;

/* Samples soft light l (pb_light_is_delta false) from point p with (u1, u2)
 * in [0, 1)^2, with Cycles 3.4's strategies: sphere light: uniform on the
 * disc facing p; area light: a rectangle by solid angle (Urena et al. 2013,
 * "An Area-Preserving Parametrization for Spherical Rectangles", on the part
 * of it that its spread lets reach p, as Cycles' light_spread_clamp_area_light;
 * by area below 1e-3 sr, where the solid angle loses float precision), an
 * ellipse by area; sun: uniform on its disc at unit distance. Returns 0 when
 * the light cannot reach p. */
int pb_soft_light_sample(const pb_light *l, v3 p, float u1, float u2, pb_light_sample *out);
/* The ray (o, d), d unit, meets soft light l at distance t in (0, tmax)
 * (the sun only when tmax is INFINITY, a ray that left the scene): its
 * radiance toward o and the density pb_soft_light_sample gives that
 * direction from o. Lights are one-sided where Cycles' are (area lights,
 * spots' discs). */
int pb_soft_light_hit(const pb_light *l, v3 o, v3 d, float tmax, float *t, v3 *L, float *pdf);

/* Photon emission from soft lights (photons.c; the GPU's photon_trace.comp
 * emits the same way):
 * area light: origin o uniform on the shape, direction d cosine-weighted in
 * the cone of half-angle pi/2 - a that the spread allows (sin^2 t = u3 cos^2
 * a); the photon's flux is the light's radiance L times *weight = A pi cos^2
 * a x the spread profile at t (radiance x cos / the two densities). 0 when
 * the sample carries nothing. */
int pb_area_light_emit(const pb_light *l, float u1, float u2, float u3, float u4, v3 *o, v3 *d, float *weight);
/* Sphere light: the point of the sphere of radius r about the light whose
 * projection along d is uniform on the disc of radius r (the hemisphere
 * facing d, weighted by its cosine to d): a photon leaving in direction d
 * starts there and carries I(d) / (its direction density), as from a point
 * light. The sphere of radius r and radiance I / (pi r^2) emits I per
 * steradian in every direction, the point light's flux; its irradiance at
 * distance D is I / D^2 where Cycles 3.4's disc facing the lit point gives
 * I / (D^2 + r^2), so photons differ from next-event estimation by at most
 * r^2 / D^2 at the first hit (1 % at 10 radii), only in indirect light and
 * caustics, where the sphere's blur is the disc's. */
v3 pb_sphere_light_origin(const pb_light *l, v3 d, float u1, float u2);

/* Picks an emissive triangle by power and a uniform point on it, as a hit
 * (prim and Embree barycentrics) for pb_surface_from_hit, with the pdf of
 * that point in area measure. Returns 0 when there are no emitters. */
int pb_emitter_sample(const pb_scene *s, const pb_ref_lights *l, float u0,
                      float u1, float u2, pb_ref_hit *hit, float *pdf_area);
/* pdf (area measure) of pb_emitter_sample returning a point on triangle t. */
float pb_emitter_pdf_area(const pb_scene *s, const pb_ref_lights *l, uint32_t t);

/* Power heuristic with beta = 2 (Veach 1997, ch. 9). */
static inline float pb_mis_power(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

#endif
