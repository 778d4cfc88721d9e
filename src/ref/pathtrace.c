/* One camera path of the reference renderer: unidirectional path tracing with
 * next-event estimation (Veach 1997, ch. 9-10).
 *
 * At every vertex with a smooth (non-delta) lobe:
 *  - every point, spot and directional light gets a shadow ray (they are
 *    delta lights: only next-event estimation can reach them);
 *  - one emissive triangle, picked by power, gets a shadow ray, and the
 *    BSDF-sampled continuation that hits an emitter counts too; the two are
 *    combined with the power heuristic. After a delta lobe (or from the
 *    camera) an emitter hit counts with weight 1, since next-event estimation
 *    cannot produce that path;
 *  - with a caustic photon map (SPPM mode), the photons' flux density gives
 *    the paths delta light -> specular chain -> this vertex, which neither
 *    strategy above can sample. The partition is exact: a path ending at a
 *    delta light is counted by next-event estimation when the vertex before
 *    the light is smooth and by the photon map when it is a delta
 *    interaction, never by both.
 * Bounce counting: a path of k scattering events between the emitter and the
 * eye has k bounces (direct lighting 1, an emitter seen directly 0); paths
 * over max_bounces are not counted. Russian roulette from the third bounce
 * keeps the estimator unbiased. */
#include <string.h>

#include "ref/ref_internal.h"

/* Fraction of light reaching o + tmax d from o: 0 or 1, or through
 * surfaces with Alpha < 1 (Cycles' transparent shadows) the product of
 * their transparencies. */
static v3 shadow(const pb_ref_ctx *ctx, v3 o, v3 d, float tmax, uint64_t *rays) {
  const pb_scene *s = ctx->scene;
  if (!(s->features & PB_FEATURE_ALPHA) || !(s->features & PB_FEATURE_BLENDER)) {
    (*rays)++;
    return pb_ref_occluded(&ctx->accel, o, d, tmax) ? v3_make(0, 0, 0) : v3_make(1, 1, 1);
  }
  v3 T = v3_make(1, 1, 1);
  for (int n = 0; n < 64 && tmax > 0.0f; ++n) {
    pb_ref_hit h;
    (*rays)++;
    if (!pb_ref_intersect(&ctx->accel, o, d, tmax, &h)) return T;
    pb_surface surf;
    pb_surface_from_hit(s, &h, d, &surf);
    float t = surf.mat->blender.model == PB_MODEL_PRINCIPLED ? 1.0f - pb_blender_alpha(s, &surf) : 0.0f;
    if (!(t > 0.0f)) return v3_make(0, 0, 0);
    T = v3_scale(T, t);
    o = pb_offset_ray(surf.p, v3_neg(surf.ng));
    tmax -= h.t;
  }
  return v3_make(0, 0, 0);
}

static inline void add_contrib(pb_sample_out *o, v3 c, uint32_t bounces) {
  if (bounces <= 1) o->direct = v3_add(o->direct, c);
  else o->indirect = v3_add(o->indirect, c);
}

void pb_trace_camera_sample(const pb_ref_ctx *ctx, const pb_photon_map *map,
                            uint32_t x, uint32_t y, uint32_t sample,
                            pb_sample_out *out) {
  const pb_scene *s = ctx->scene;
  const pb_camera *cam = ctx->cam;
  memset(out, 0, sizeof *out);
  uint64_t pixel = (uint64_t)y * ctx->width + x;
  pb_rng rng = pb_rng_make(ctx->seed, PB_RNG_CAMERA, pixel, sample);

  /* Position in the pixel: the R2 low-discrepancy sequence (Roberts 2018,
   * generalised golden ratio), randomised by a Cranley-Patterson shift, so
   * anti-aliasing noise falls faster than 1/sqrt(spp) while the estimate
   * stays unbiased. Even and odd samples form two sequences with
   * independent shifts: the halves of --estimate-noise stay independent. */
  pb_rng shift_rng = pb_rng_make(ctx->seed, PB_RNG_PIXEL, pixel, sample & 1u);
  double n = (double)(sample >> 1);
  double jx = (double)pb_rng_f(&shift_rng) + n * 0.75487766624669276;
  double jy = (double)pb_rng_f(&shift_rng) + n * 0.56984029099805327;
  jx -= floor(jx);
  jy -= floor(jy);
  float px = (float)x + (float)jx, py = (float)y + (float)jy;
  float sx = (2.0f * px / (float)ctx->width - 1.0f) * ctx->tan_x;
  float sy = (1.0f - 2.0f * py / (float)ctx->height) * ctx->tan_y;
  v3 fwd = v3_load(cam->forward);
  v3 dir = v3_norm(v3_add(v3_add(fwd, v3_scale(v3_load(cam->right), sx)),
                          v3_scale(v3_load(cam->up), sy)));
  v3 org = v3_load(cam->position);
  v3 beta = v3_make(1, 1, 1);
  int prev_delta = 1;     /* the camera is a delta "vertex" for MIS */
  float prev_pdf = 0.0f;  /* solid-angle pdf of the last smooth sample */
  uint64_t rays = 0;

  for (uint32_t k = 1;; ++k) {
    pb_ref_hit h;
    rays++;
    if (!pb_ref_intersect(&ctx->accel, org, dir, INFINITY, &h)) break;
    pb_surface surf;
    pb_surface_from_hit(s, &h, dir, &surf);
    v3 wo = v3_neg(dir);
    /* Holdout: the camera sees a hole (no coverage, black); any other ray
     * a black absorber (no closures: nothing below reflects). */
    if (k == 1 && surf.mat->blender.model == PB_MODEL_HOLDOUT) break;
    if (k == 1) {
      out->hit = 1;
      out->normal = surf.ns;
      out->depth = h.t * v3_dot(dir, fwd);
    }

    v3 le = pb_surface_emission(s, &surf);
    if (!v3_is_zero(le)) {
      float w = 1.0f;
      if (!prev_delta) {
        float pa = pb_emitter_pdf_area(s, &ctx->lights, surf.prim);
        float cos_l = v3_dot(surf.ng, wo);
        float pl = cos_l > 0.0f ? pa * h.t * h.t / cos_l : 0.0f;
        w = pb_mis_power(prev_pdf, pl);
      }
      add_contrib(out, v3_scale(v3_mul(beta, le), w), k - 1);
    }
    if (k > ctx->max_bounces) break;

    pb_bsdf b;
    pb_bsdf_setup(s, &surf, wo, &rng, &b);
    if (k == 1) out->albedo = pb_bsdf_albedo(&b);

    if (pb_bsdf_has_smooth(&b)) {
      /* Shadow rays leave on the side their light lies on: transmitting
       * lobes (a Principled glass) see lights through the surface. */
      v3 o_front = pb_offset_ray(surf.p, surf.ng), o_back = o_front;
      if (b.model != PB_MODEL_GLTF) o_back = pb_offset_ray(surf.p, v3_neg(surf.ng));
      for (uint32_t i = 0; i < s->light_count; ++i) {
        v3 wi, li;
        float dist;
        if (!pb_delta_light_at(&s->lights[i], surf.p, &wi, &dist, &li)) continue;
        float pdf;
        v3 f = pb_bsdf_eval(&b, wo, wi, &pdf);
        if (v3_is_zero(f)) continue;
        v3 vis = shadow(ctx, v3_dot(wi, surf.ng) >= 0.0f ? o_front : o_back, wi,
                        dist * (1.0f - PB_SHADOW_EPSILON), &rays);
        if (v3_is_zero(vis)) continue;
        float c = fabsf(v3_dot(wi, b.n));
        add_contrib(out, v3_mul(v3_mul(beta, vis), v3_scale(v3_mul(f, li), c)), k);
      }
      if (ctx->lights.emitter_count) {
        float u0 = pb_rng_f(&rng), u1 = pb_rng_f(&rng), u2 = pb_rng_f(&rng);
        pb_ref_hit eh;
        float pa;
        if (pb_emitter_sample(s, &ctx->lights, u0, u1, u2, &eh, &pa)) {
          pb_surface es;
          /* Where the sampled point is, seen from surf.p. */
          const uint32_t *tri = s->triangles[eh.prim];
          float w0 = 1.0f - eh.u - eh.v;
          v3 q = v3_add(v3_add(v3_scale(v3_load(s->positions[tri[0]]), w0),
                               v3_scale(v3_load(s->positions[tri[1]]), eh.u)),
                        v3_scale(v3_load(s->positions[tri[2]]), eh.v));
          v3 d = v3_sub(q, surf.p);
          float d2 = v3_dot(d, d);
          if (d2 > 0.0f) {
            float dl = sqrtf(d2);
            v3 wi = v3_scale(d, 1.0f / dl);
            pb_surface_from_hit(s, &eh, wi, &es);
            v3 le2 = pb_surface_emission(s, &es);
            float cos_l = v3_dot(es.ng, v3_neg(wi));
            float pdf_b;
            v3 f = v3_is_zero(le2) || cos_l <= 0.0f ? v3_make(0, 0, 0)
                                                    : pb_bsdf_eval(&b, wo, wi, &pdf_b);
            if (!v3_is_zero(f)) {
              float pl = pa * d2 / cos_l;
              /* Both ends moved off their surfaces (Waechter & Binder), so
               * the segment between them touches neither. */
              v3 tgt = pb_offset_ray(es.p, es.ng);
              v3 o_shadow = v3_dot(wi, surf.ng) >= 0.0f ? o_front : o_back;
              v3 seg = v3_sub(tgt, o_shadow);
              float sl = v3_len(seg);
              v3 vis = sl > 0.0f ? shadow(ctx, o_shadow, v3_scale(seg, 1.0f / sl), sl, &rays) : v3_make(0, 0, 0);
              if (!v3_is_zero(vis)) {
                float w = pb_mis_power(pl, pdf_b);
                float c = fabsf(v3_dot(wi, b.n));
                add_contrib(out, v3_mul(v3_mul(beta, vis), v3_scale(v3_mul(f, le2), c * w / pl)), k);
              }
            }
          }
        }
      }
      if (map && map->count)
        add_contrib(out, v3_mul(beta, pb_photon_gather(map, &b, surf.p, wo, k,
                                                       ctx->max_bounces)),
                    2);
    }

    pb_bsdf_sample bs;
    float u0 = pb_rng_f(&rng), u1 = pb_rng_f(&rng), u2 = pb_rng_f(&rng);
    if (!pb_bsdf_sample_dir(&b, wo, u0, u1, u2, PB_RADIANCE, &bs)) break;
    beta = v3_mul(beta, bs.weight);
    if (v3_is_zero(beta)) break;
    prev_delta = bs.delta;
    prev_pdf = bs.pdf;
    org = pb_offset_ray(surf.p, bs.transmit ? v3_neg(surf.ng) : surf.ng);
    dir = bs.wi;
    if (k >= 3) {
      float q = fminf(0.95f, v3_max(beta));
      if (!(pb_rng_f(&rng) < q)) break;
      beta = v3_scale(beta, 1.0f / q);
    }
  }
  out->rays = rays;
}
