/* Light sampling for the reference renderer (soft lights: soft_lights.c). Semantics follow scene.h:
 *  point: I = color * intensity [W/sr], irradiance I cos / d^2;
 *  spot:  the same, times the spot's falloff (pb_spot_factor: KHR's
 *         smoothstep(cos outer, cos inner, cos angle to `direction`),
 *         smoothstep(t) = t^2 (3 - 2 t), or Cycles 3.4's);
 *  directional: E = color * intensity [W/m^2] normal to `direction` (the
 *         direction light travels), irradiance E cos;
 *  emissive triangles: area lights of radiance `emissive` [W/(m^2 sr)], from
 *         the front (counter-clockwise) side only unless double-sided.
 * `range` is not applied: the reference keeps the physical inverse-square
 * law (Blender does not export range). */
#include <stdlib.h>
#include <string.h>

#include "ref/lights.h"

void pb_ref_lights_destroy(pb_ref_lights *l) {
  if (!l) return;
  free(l->emitters);
  free(l->emitter_cdf);
  free(l->tri_pick_pdf);
  pb_world_dist_destroy(&l->world_dist);
  memset(l, 0, sizeof *l);
}

pb_result pb_ref_lights_build(const pb_scene *s, pb_ref_lights *l) {
  memset(l, 0, sizeof *l);
  for (uint32_t i = 0; i < s->light_count; ++i) {
    if (pb_light_is_delta(&s->lights[i])) l->delta_count++;
    else l->soft_count++;
  }
  v3 bmin = v3_load(s->bounds_min), bmax = v3_load(s->bounds_max);
  l->center = v3_scale(v3_add(bmin, bmax), 0.5f);
  l->radius = fmaxf(0.5f * v3_len(v3_sub(bmax, bmin)), 1e-6f);

  pb_emitter_table et;
  pb_result r = pb_emitter_table_build(s, &et);
  if (r != PB_OK) return r;
  if (et.count) {
    l->tri_pick_pdf = calloc(s->triangle_count, sizeof *l->tri_pick_pdf);
    if (!l->tri_pick_pdf) {
      pb_emitter_table_destroy(&et);
      return pb_fail(PB_ERR_NOMEM, "reference: out of memory for %u emitters", et.count);
    }
    for (uint32_t i = 0; i < et.count; ++i) l->tri_pick_pdf[et.prim[i]] = (float)(et.cdf[i + 1] - et.cdf[i]);
    l->emitters = et.prim; /* the table's arrays are ours from here */
    l->emitter_cdf = et.cdf;
    l->emitter_count = et.count;
    free(et.area);
  }
  if (s->world.present) {
    if ((r = pb_world_dist_build(&s->world, &l->world_dist)) != PB_OK) {
      pb_ref_lights_destroy(l);
      return r;
    }
    l->world_nee = l->world_dist.width > 0;
  }

  /* Bounding sphere (of the box) of every triangle that may have a delta
   * lobe: photons aimed at it find every specular chain. */
  v3 smin = v3_make(INFINITY, INFINITY, INFINITY), smax = v3_scale(smin, -1.0f);
  int any = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (!pb_material_may_be_singular(&s->materials[s->triangle_material[t]])) continue;
    any = 1;
    for (int v = 0; v < 3; ++v) {
      v3 p = v3_load(s->positions[s->triangles[t][v]]);
      smin = v3_make(fminf(smin.x, p.x), fminf(smin.y, p.y), fminf(smin.z, p.z));
      smax = v3_make(fmaxf(smax.x, p.x), fmaxf(smax.y, p.y), fmaxf(smax.z, p.z));
    }
  }
  if (any) {
    l->spec_center = v3_scale(v3_add(smin, smax), 0.5f);
    /* A little margin so rays grazing the box's corners are kept. */
    l->spec_radius = 0.5f * v3_len(v3_sub(smax, smin)) * 1.001f + 1e-6f * l->radius;
  }
  return PB_OK;
}

static inline float smoothstep01(float t) {
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return t * t * (3.0f - 2.0f * t);
}

float pb_spot_factor(const pb_light *l, float cos_angle) {
  float co = cosf(l->outer_cone);
  if (l->spot_model == PB_SPOT_CYCLES || l->spot_model == PB_SPOT_CYCLES4) {
    if (cos_angle <= co) return 0.0f;
    float band = (1.0f - co) * l->spot_blend, t = cos_angle - co;
    float s = band > 0.0f && t < band ? smoothstep01(t / band) : 1.0f;
    return l->spot_model == PB_SPOT_CYCLES ? cos_angle * s : s; /* 3.4 keeps the cosine; 4.x does not */
  }
  float ci = cosf(l->inner_cone);
  if (ci - co <= 1e-7f) return cos_angle >= co ? 1.0f : 0.0f;
  return smoothstep01((cos_angle - co) / (ci - co));
}

int pb_delta_light_at(const pb_light *l, v3 p, v3 *wi, float *dist, v3 *Li) {
  v3 c = v3_scale(v3_make(l->color[0], l->color[1], l->color[2]), l->intensity);
  if (l->type == PB_LIGHT_DIRECTIONAL) {
    v3 d = v3_norm(v3_load(l->direction));
    if (v3_is_zero(d)) return 0;
    *wi = v3_neg(d);
    *dist = INFINITY;
    *Li = c;
    return !v3_is_zero(c);
  }
  v3 d = v3_sub(v3_load(l->position), p);
  float d2 = v3_dot(d, d);
  if (!(d2 > 0.0f)) return 0;
  float dl = sqrtf(d2);
  *wi = v3_scale(d, 1.0f / dl);
  *dist = dl;
  float k = 1.0f / d2;
  if (l->type == PB_LIGHT_SPOT) {
    v3 axis = v3_norm(v3_load(l->direction));
    k *= pb_spot_factor(l, -v3_dot(axis, *wi));
  }
  *Li = v3_scale(c, k);
  return k > 0.0f && !v3_is_zero(c);
}

int pb_emitter_sample(const pb_scene *s, const pb_ref_lights *l, float u0,
                      float u1, float u2, pb_ref_hit *hit, float *pdf_area) {
  if (!l->emitter_count) return 0;
  /* Largest i with cdf[i] <= u0. */
  uint32_t lo = 0, hi = l->emitter_count;
  while (hi - lo > 1) {
    uint32_t mid = (lo + hi) / 2;
    if (l->emitter_cdf[mid] <= (double)u0) lo = mid;
    else hi = mid;
  }
  uint32_t t = l->emitters[lo];
  float area = pb_triangle_area(s, t);
  if (!(area > 0.0f)) return 0;
  /* Uniform on the triangle (Shirley's square-to-triangle map). */
  float su = sqrtf(u1);
  hit->prim = t;
  hit->u = u2 * su;          /* weight of p1 */
  hit->v = 1.0f - su;        /* weight of p2 */
  hit->t = 0.0f;
  *pdf_area = l->tri_pick_pdf[t] / area;
  return 1;
}

float pb_emitter_pdf_area(const pb_scene *s, const pb_ref_lights *l, uint32_t t) {
  if (!l->tri_pick_pdf) return 0.0f;
  float p = l->tri_pick_pdf[t];
  if (p <= 0.0f) return 0.0f;
  float area = pb_triangle_area(s, t);
  return area > 0.0f ? p / area : 0.0f;
}
