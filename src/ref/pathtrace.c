/* One camera path of the reference renderer: unidirectional path tracing with
 * next-event estimation (Veach 1997, ch. 9-10).
 *
 * At every vertex with a smooth (non-delta) lobe:
 *  - every point, spot and directional light gets a shadow ray (they are
 *    delta lights: only next-event estimation can reach them);
 *  - every soft light (sphere, area, soft sun; soft_lights.c) gets one light
 *    sample, and the world one from its map (scene/world.h), each combined
 *    with the BSDF-sampled continuation that reaches it by the power
 *    heuristic (two strategies per light: Veach 1997, 9.2; a light with
 *    no_mis is reached by its light sample alone, weight 1, as Cycles'
 *    "Multiple Importance" off). A constant world has no light sample: the
 *    BSDF-sampled ray that leaves the scene sees it with weight 1;
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
 *    interaction, never by both. The photons also leave every soft light and
 *    the world (photons.c), so in SPPM mode a path that reaches one of those
 *    through a delta chain after a smooth vertex is the photon map's; the
 *    path tracer still counts it after a chain that started at the camera.
 *  - lights never stop rays (Cycles' lights are not surfaces): a ray adds the
 *    emission of every soft light it passes before its hit, and a ray that
 *    leaves the scene the world's and the soft suns'. Camera rays see no
 *    light (Cycles 3.4 shows lights only in reflections and refractions:
 *    scene.h), and the world only with an opaque film (pb_scene.film_opaque)
 *    when it is not hidden from the camera (mirrors still reflect it). A
 *    camera ray ends at the far clip plane and then sees the world, as a
 *    Cycles camera ray without a hit shades the background.
 * Along segments inside an absorbing medium (KHR_materials_volume, entered
 * by refraction) the throughput falls by the Beer-Lambert transmittance
 * exp(-sigma_a t); lights met inside one by their own distance, the world
 * beyond it entirely.
 * Bounce counting: a path of k scattering events between the emitter and the
 * eye has k bounces (direct lighting 1, an emitter seen directly 0); paths
 * over max_bounces are not counted. Russian roulette from the third bounce
 * ends paths without bias (survival q = min(0.95, max_c beta_c), the weight
 * divided by q): E[beta'] = q beta / q = beta. By default (ref.h,
 * PB_REF_BOUNCE_CAP) max_bounces is only a safety net: a truncation at 8
 * events lost sum_{k>8} rho^k / sum_k rho^k = rho^8 of the indirect light of
 * a closed room of albedo rho (10 % at 0.75; the furnace test
 * checks Le / (1 - rho) exactly), while the roulette's expected path length
 * is bounded by the 0.95 cap (at most 2 + 1 / 0.05 = 22 events, and about
 * 2 + 1 / (1 - rho) for albedo rho). */
#include <string.h>

#include "ref/bsdf.h"
#include "ref/lights.h"
#include "ref/pathtrace.h"

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

/* What a path vertex needs to weigh the emission its next ray meets. */
typedef struct path_state {
  uint32_t k;       /* the ray leaves vertex k - 1 (k == 1: the camera) */
  int prev_delta;   /* the last interaction was a delta lobe (or the camera) */
  float prev_pdf;   /* solid-angle pdf of the last smooth BSDF sample */
  int after_smooth; /* the path scattered off a smooth lobe before */
} path_state;

/* Emission the ray (o, d) meets before t_hit (INFINITY: it left the scene):
 * soft lights on the way, then the world and the soft suns, each through
 * the absorbing medium sigma the ray is in up to its distance. */
static void ray_emission(const pb_ref_ctx *ctx, const pb_ref_photon_map *map, const path_state *ps, v3 o, v3 d,
                         float t_hit, v3 beta, v3 sigma, pb_sample_out *out) {
  const pb_scene *s = ctx->scene;
  int camera = ps->k == 1;
  /* SPPM: the photons carry light -> delta chain -> smooth vertex. */
  if (map && ps->after_smooth && ps->prev_delta) return;
  for (uint32_t i = 0; i < s->light_count && ctx->lights.soft_count && !camera; ++i) {
    const pb_light *l = &s->lights[i];
    if (pb_light_is_delta(l) || l->no_mis) continue;
    float t, pl;
    v3 L;
    if (!pb_soft_light_hit(l, o, d, t_hit, &t, &L, &pl)) continue;
    float w = ps->prev_delta ? 1.0f : pb_mis_power(ps->prev_pdf, pl);
    if (!v3_is_zero(sigma)) L = v3_mul(L, pb_medium_transmittance(sigma, t));
    add_contrib(out, v3_scale(v3_mul(beta, L), w), ps->k - 1);
  }
  if (t_hit < INFINITY || !s->world.present) return;
  if (camera && (!s->film_opaque || s->world.hidden_from_camera)) return;
  float dir[3] = {d.x, d.y, d.z}, L[3];
  pb_world_radiance(&s->world, dir, L);
  float w = 1.0f;
  if (!ps->prev_delta && ctx->lights.world_nee)
    w = pb_mis_power(ps->prev_pdf, pb_world_pdf(&s->world, &ctx->lights.world_dist, dir));
  v3 Lw = v3_load(L);
  if (!v3_is_zero(sigma)) Lw = v3_mul(Lw, pb_medium_transmittance(sigma, INFINITY));
  add_contrib(out, v3_scale(v3_mul(beta, Lw), w), ps->k - 1);
}

/* One light sample of every soft light and of the world's map at a smooth
 * vertex, with shadow rays from o_front, or from o_back for a direction
 * below the geometric normal (transmitting lobes). */
static void soft_nee(const pb_ref_ctx *ctx, pb_rng *rng, const pb_bsdf *b, const pb_surface *surf, v3 wo,
                     v3 o_front, v3 o_back, v3 beta, uint32_t k, pb_sample_out *out, uint64_t *rays) {
  const pb_scene *s = ctx->scene;
  for (uint32_t i = 0; i < s->light_count && ctx->lights.soft_count; ++i) {
    const pb_light *l = &s->lights[i];
    if (pb_light_is_delta(l)) continue;
    float u1 = pb_rng_f(rng), u2 = pb_rng_f(rng);
    pb_light_sample ls;
    if (!pb_soft_light_sample(l, surf->p, u1, u2, &ls)) continue;
    float pdf_b;
    v3 f = pb_bsdf_eval(b, wo, ls.wi, &pdf_b);
    if (v3_is_zero(f)) continue;
    v3 vis = v3_make(1, 1, 1);
    if (!l->no_shadow) {
      float tmax = ls.dist < INFINITY ? ls.dist * (1.0f - PB_SHADOW_EPSILON) : INFINITY;
      vis = shadow(ctx, v3_dot(ls.wi, surf->ng) >= 0.0f ? o_front : o_back, ls.wi, tmax, rays);
      if (v3_is_zero(vis)) continue;
    }
    float w = l->no_mis ? 1.0f : pb_mis_power(ls.pdf, pdf_b);
    float c = fabsf(v3_dot(ls.wi, b->n));
    add_contrib(out, v3_mul(v3_mul(beta, vis), v3_scale(v3_mul(f, ls.L), c * w / ls.pdf)), k);
  }
  if (!ctx->lights.world_nee) return;
  float u1 = pb_rng_f(rng), u2 = pb_rng_f(rng), dir[3], pw;
  if (!pb_world_sample(&s->world, &ctx->lights.world_dist, u1, u2, dir, &pw)) return;
  v3 wi = v3_load(dir);
  float pdf_b;
  v3 f = pb_bsdf_eval(b, wo, wi, &pdf_b);
  if (v3_is_zero(f)) return;
  v3 vis = shadow(ctx, v3_dot(wi, surf->ng) >= 0.0f ? o_front : o_back, wi, INFINITY, rays);
  if (v3_is_zero(vis)) return;
  float L[3];
  pb_world_radiance(&s->world, dir, L);
  float c = fabsf(v3_dot(wi, b->n)) * pb_mis_power(pw, pdf_b) / pw;
  add_contrib(out, v3_mul(v3_mul(beta, vis), v3_scale(v3_mul(f, v3_load(L)), c)), k);
}

void pb_trace_camera_sample(const pb_ref_ctx *ctx, const pb_ref_photon_map *map,
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
  /* The lens point (depth of field) from its own stream, drawn only for a
   * camera with an aperture so that pinhole images keep their numbers. */
  float o3[3], d3[3], t0, tmax, lens[2] = {0.5f, 0.5f};
  if (ctx->view.aperture > 0.0f) {
    pb_rng lens_rng = pb_rng_make(ctx->seed, PB_RNG_LENS, pixel, sample);
    lens[0] = pb_rng_f(&lens_rng);
    lens[1] = pb_rng_f(&lens_rng);
  }
  /* No ray (outside a fisheye's circle): black and uncovered, as Cycles. */
  if (!pb_camera_ray_lens(&ctx->view, px, py, lens, o3, d3, &t0, &tmax)) return;
  v3 fwd = v3_load(cam->forward);
  v3 dir = v3_load(d3);
  v3 org = v3_load(o3);
  v3 beta = v3_make(1, 1, 1);
  v3 sigma = v3_make(0, 0, 0); /* absorption of the medium the path is in */
  int camera_path = 1;    /* only delta interactions so far (unlit surfaces) */
  int prev_delta = 1;     /* the camera is a delta "vertex" for MIS */
  float prev_pdf = 0.0f;  /* solid-angle pdf of the last smooth sample */
  int after_smooth = 0;
  uint64_t rays = 0;

  for (uint32_t k = 1;; ++k) {
    pb_ref_hit h;
    rays++;
    /* The camera segment ends at the far clip plane. */
    int hit = pb_ref_intersect(&ctx->accel, org, dir, k == 1 ? tmax : INFINITY, &h);
    path_state ps = {k, prev_delta, prev_pdf, after_smooth};
    ray_emission(ctx, map, &ps, org, dir, hit ? h.t : INFINITY, beta, sigma, out);
    if (!hit) break;
    if (!v3_is_zero(sigma)) beta = v3_mul(beta, pb_medium_transmittance(sigma, h.t));
    pb_surface surf;
    pb_surface_from_hit(s, &h, dir, &surf);
    v3 wo = v3_neg(dir);
    /* Holdout: the camera sees a hole (no coverage, black); any other ray
     * a black absorber (no closures: nothing below reflects). */
    if (k == 1 && surf.mat->blender.model == PB_MODEL_HOLDOUT) break;
    if (k == 1) {
      out->hit = 1;
      out->normal = surf.ns;
      /* camera depth; a panorama's the distance (Cycles' camera_z_depth) */
      out->depth = ctx->view.projection ? v3_len(v3_sub(v3_add(org, v3_scale(dir, h.t)), v3_load(cam->position)))
                                        : (t0 + h.t) * v3_dot(dir, fwd);
    }

    v3 le = pb_surface_emission(s, &surf, wo, camera_path);
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
        if (!pb_light_is_delta(&s->lights[i]) || !pb_delta_light_at(&s->lights[i], surf.p, &wi, &dist, &li)) continue;
        float pdf;
        v3 f = pb_bsdf_eval(&b, wo, wi, &pdf);
        if (v3_is_zero(f)) continue;
        v3 vis = v3_make(1, 1, 1);
        if (s->lights[i].no_shadow) rays++;
        else vis = shadow(ctx, v3_dot(wi, surf.ng) >= 0.0f ? o_front : o_back, wi, dist * (1.0f - PB_SHADOW_EPSILON), &rays);
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
            v3 le2 = pb_surface_emission(s, &es, v3_neg(wi), 0);
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
      /* After the emitter and photon terms: a scene without soft lights or
       * a world map draws the same random numbers as before they existed. */
      soft_nee(ctx, &rng, &b, &surf, wo, o_front, o_back, beta, k, out, &rays);
    }

    pb_bsdf_sample bs;
    float u0 = pb_rng_f(&rng), u1 = pb_rng_f(&rng), u2 = pb_rng_f(&rng);
    if (!pb_bsdf_sample_dir(&b, wo, u0, u1, u2, PB_RADIANCE, &bs)) break;
    beta = v3_mul(beta, bs.weight);
    if (v3_is_zero(beta)) break;
    prev_delta = bs.delta;
    if (!bs.delta) after_smooth = 1; /* a smooth scattering: chains after it are the photons' */
    prev_pdf = bs.pdf;
    camera_path &= bs.delta;
    sigma = pb_medium_after(sigma, &surf, &bs);
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
