/* Light sampling for the reference renderer. Semantics follow scene.h:
 *  point: I = color * intensity [W/sr], irradiance I cos / d^2;
 *  spot:  the same, times smoothstep(cos outer, cos inner, cos angle to
 *         `direction`), smoothstep(t) = t^2 (3 - 2 t);
 *  directional: E = color * intensity [W/m^2] normal to `direction` (the
 *         direction light travels), irradiance E cos;
 *  emissive triangles: area lights of radiance `emissive` [W/(m^2 sr)], from
 *         the front (counter-clockwise) side only unless double-sided.
 * `range` is not applied: the reference keeps the physical inverse-square
 * law (Blender does not export range). */
#include <stdlib.h>
#include <string.h>

#include "ref/ref_internal.h"

float pb_triangle_area(const pb_scene *s, uint32_t t) {
  const uint32_t *tri = s->triangles[t];
  v3 p0 = v3_load(s->positions[tri[0]]), p1 = v3_load(s->positions[tri[1]]),
     p2 = v3_load(s->positions[tri[2]]);
  return 0.5f * v3_len(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
}

void pb_ref_lights_destroy(pb_ref_lights *l) {
  if (!l) return;
  free(l->emitters);
  free(l->emitter_cdf);
  free(l->tri_pick_pdf);
  memset(l, 0, sizeof *l);
}

pb_result pb_ref_lights_build(const pb_scene *s, pb_ref_lights *l) {
  memset(l, 0, sizeof *l);
  l->delta_count = s->light_count;
  v3 bmin = v3_load(s->bounds_min), bmax = v3_load(s->bounds_max);
  l->center = v3_scale(v3_add(bmin, bmax), 0.5f);
  l->radius = fmaxf(0.5f * v3_len(v3_sub(bmax, bmin)), 1e-6f);

  uint32_t n = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    if (pb_material_is_emissive(&s->materials[s->triangle_material[t]])) n++;
  if (n) {
    l->emitters = malloc(n * sizeof *l->emitters);
    l->emitter_cdf = malloc((n + 1) * sizeof *l->emitter_cdf);
    l->tri_pick_pdf = calloc(s->triangle_count, sizeof *l->tri_pick_pdf);
    if (!l->emitters || !l->emitter_cdf || !l->tri_pick_pdf) {
      pb_ref_lights_destroy(l);
      return pb_fail(PB_ERR_NOMEM, "reference: out of memory for %u emitters", n);
    }
    double total = 0.0;
    uint32_t k = 0;
    for (uint32_t t = 0; t < s->triangle_count; ++t) {
      const pb_material *m = &s->materials[s->triangle_material[t]];
      if (!pb_material_is_emissive(m)) continue;
      v3 e = v3_make(fmaxf(m->emissive[0], 0), fmaxf(m->emissive[1], 0),
                     fmaxf(m->emissive[2], 0));
      /* Power up to a constant: area x radiance x sides (pi dropped). Use
       * the maximum channel so a saturated emitter never gets weight 0. */
      double w = (double)pb_triangle_area(s, t) * fmax(v3_lum(e), 1e-3 * v3_max(e)) *
                 (m->double_sided ? 2.0 : 1.0);
      if (!(w > 0.0) || !isfinite(w)) continue;
      l->emitters[k] = t;
      l->emitter_cdf[k] = total;
      total += w;
      k++;
    }
    l->emitter_count = k;
    if (k == 0 || !(total > 0.0)) {
      free(l->emitters);
      free(l->emitter_cdf);
      free(l->tri_pick_pdf);
      l->emitters = NULL;
      l->emitter_cdf = NULL;
      l->tri_pick_pdf = NULL;
      l->emitter_count = 0;
    } else {
      for (uint32_t i = 0; i < k; ++i) {
        double next = i + 1 < k ? l->emitter_cdf[i + 1] : total;
        l->tri_pick_pdf[l->emitters[i]] = (float)((next - l->emitter_cdf[i]) / total);
        l->emitter_cdf[i] /= total;
      }
      l->emitter_cdf[k] = 1.0;
    }
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

float pb_spot_falloff(const pb_light *l, float cos_angle) {
  float co = cosf(l->outer_cone), ci = cosf(l->inner_cone);
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
    k *= pb_spot_falloff(l, -v3_dot(axis, *wi));
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
