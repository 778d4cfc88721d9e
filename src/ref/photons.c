/* Caustic photons for the reference renderer's SPPM mode.
 *
 * The paths a path tracer cannot sample are those that leave a delta light
 * (point, spot, directional) and meet only delta interactions (mirror, glass)
 * before their first smooth vertex x: next-event estimation from x cannot
 * pass the specular chain, and BSDF sampling never hits a point. Photons
 * cover exactly these paths: each photon path starts at a delta light, follows
 * delta lobes only, and deposits its flux at every smooth vertex it reaches
 * after at least one delta interaction (pathtrace.c does the rest).
 *
 * Progressive photon mapping. Hachisuka & Jensen 2009 ("Stochastic
 * Progressive Photon Mapping", SIGGRAPH Asia) keep per visible point a radius
 * R, a photon count N and a flux tau, and after a pass that found M new
 * photons with flux Phi update
 *     N' = N + alpha M,   R'^2 = R^2 (N + alpha M) / (N + M),
 *     tau' = (tau + Phi) R'^2 / R^2,
 * radiance tau / (pi R^2 N_emitted), with alpha in (0,1) (2/3 here).
 * Knaus & Zwicker 2011 ("Progressive Photon Mapping: A Probabilistic
 * Approach", ACM TOG 30(3)) show the same convergence without per-point
 * statistics: pass i estimates with its own photons at a radius that shrinks
 * on a fixed schedule,
 *     r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1),
 * so that variance (~ 1 / r_i^2) grows like i^(1-alpha) while bias
 * (~ r_i^2) shrinks like i^(alpha-1), and the average of the N passes'
 * images converges (variance ~ N^-alpha, bias -> 0). That memoryless form is
 * the one used here, because it lets every smooth vertex of every eye path
 * (not only the first) gather caustics, keeps passes independent (the
 * even/odd halves of --estimate-noise), and makes the image independent of
 * the thread count. ref.c owns the schedule; this file traces one pass and
 * answers gathers at that pass's radius.
 *
 * Density estimate at x toward wo from the photons p within radius r:
 *     L(x, wo) = sum_p f(x, wo, wi_p) Phi_p (|wi_p . n_s| / |wi_p . n_g|) / (pi r^2)
 * (the ratio converts the photons' flux per geometric area to the shading
 * normal's cosine that pathtrace.c's estimators use; it is 1 for flat
 * shading). Photons on surfaces facing away (thin walls, corners) are
 * excluded by requiring n_p . n_x > 1/2.
 *
 * Photon emission is aimed at the bounding sphere of the triangles that may
 * have a delta lobe: a photon missing that sphere cannot start a specular
 * chain, so restricting emission to the sphere's cone (point/spot) or disc
 * (directional) and scaling the flux by its solid angle or area is exact.
 * Every light but emissive triangles emits, and the world:
 *  - point, spot, sphere lights: directions uniform in the cone from the
 *    centre over the target grown by the light's radius (every ray from a
 *    point within r of the centre that meets the target lies in it), from
 *    the sphere's point facing the direction (pb_sphere_light_origin);
 *  - directional lights and the soft sun: parallel rays over the target's
 *    disc, the sun's direction drawn from its disc (radiance / density = E:
 *    every photon carries E pi R^2 / n);
 *  - area lights: pb_area_light_emit over their whole spread (not aimed);
 *  - the world: a direction from its sampling table (scene/world.h), then
 *    parallel over the target's disc: flux L(w) pi R^2 / (pdf(w) n). */
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"
#include "ref/bsdf.h"
#include "ref/lights.h"
#include "ref/photons.h"

enum { CHUNK = 1024 }; /* photon paths per work item */

typedef struct photon_buf {
  pb_ref_photon *p;
  uint32_t count, cap;
} photon_buf;

enum { EMIT_WORLD = 0xffffffffu }; /* emit_light.light of the world */

typedef struct emit_light {
  uint32_t light;                  /* index into the scene's lights, or EMIT_WORLD */
  double cdf;
  /* Emission domain: a cone around `axis` with cos_max (solid angle omega)
   * for point/spot, or a disc of radius `disc_r` for directional lights. */
  v3 axis;
  float cos_max, omega;
  float disc_r;
  v3 disc_center;
  float back;  /* directional: distance to start behind the disc */
} emit_light;

typedef struct pass_ctx {
  pb_ref_ctx *ctx;
  uint32_t pass, paths, chunk_count;
  emit_light *emit;
  uint32_t emit_count;
  photon_buf *bufs;      /* one per chunk */
  uint64_t *rays;        /* per thread, padded */
  int oom;
} pass_ctx;

enum { RAY_STRIDE = 8 }; /* uint64 per thread slot: one cache line */

static int buf_push(photon_buf *b, const pb_ref_photon *ph) {
  if (b->count == b->cap) {
    uint32_t cap = b->cap ? b->cap * 2 : 256;
    pb_ref_photon *n = realloc(b->p, cap * sizeof *n);
    if (!n) return 0;
    b->p = n;
    b->cap = cap;
  }
  b->p[b->count++] = *ph;
  return 1;
}

/* Uniform direction in the cone of half-angle acos(cos_max) around axis. */
static v3 sample_cone(v3 axis, float cos_max, float u1, float u2) {
  float c = 1.0f - u1 * (1.0f - cos_max);
  float sn = sqrtf(fmaxf(0.0f, 1.0f - c * c));
  float phi = 2.0f * PB_PI_F * u2;
  v3 t, b;
  v3_basis(axis, &t, &b);
  return v3_norm(v3_add(v3_add(v3_scale(t, sn * cosf(phi)), v3_scale(b, sn * sinf(phi))),
                        v3_scale(axis, c)));
}

static void trace_photon(pass_ctx *pc, uint32_t path, photon_buf *buf, uint64_t *rays) {
  pb_ref_ctx *ctx = pc->ctx;
  const pb_scene *s = ctx->scene;
  pb_rng rng = pb_rng_make(ctx->seed, PB_RNG_PHOTON, pc->pass, path);

  /* Pick a light by its emission weight. */
  float ul = pb_rng_f(&rng);
  uint32_t li = 0;
  while (li + 1 < pc->emit_count && pc->emit[li + 1].cdf <= (double)ul) li++;
  const emit_light *e = &pc->emit[li];
  double p_light = (li + 1 < pc->emit_count ? pc->emit[li + 1].cdf : 1.0) - e->cdf;
  if (!(p_light > 0.0)) return;
  v3 o, d, power;
  float u1 = pb_rng_f(&rng), u2 = pb_rng_f(&rng);
  double per = 1.0 / (p_light * pc->paths);
  if (e->light == EMIT_WORLD || s->lights[e->light].type == PB_LIGHT_DIRECTIONAL) {
    v3 col;
    int delta = e->light != EMIT_WORLD && pb_light_is_delta(&s->lights[e->light]);
    if (e->light == EMIT_WORLD) {
      float w[3], pw, L[3];
      if (!pb_world_sample(&s->world, &ctx->lights.world_dist, u1, u2, w, &pw)) return;
      pb_world_radiance(&s->world, w, L);
      d = v3_neg(v3_load(w));
      col = v3_scale(v3_load(L), 1.0f / pw);
    } else {
      const pb_light *l = &s->lights[e->light];
      col = v3_scale(v3_load(l->color), l->intensity);
      d = v3_norm(v3_load(l->direction));
      if (!delta) {
        pb_light_sample ls;
        if (!pb_soft_light_sample(l, e->disc_center, u1, u2, &ls)) return;
        d = v3_neg(ls.wi); /* radiance / density = E, the colour above */
      }
    }
    v3 t, b;
    v3_basis(d, &t, &b);
    /* A delta light's disc point takes (u1, u2), as before soft lights; the
     * others used them for the direction. */
    float v1 = delta ? u1 : pb_rng_f(&rng), v2 = delta ? u2 : pb_rng_f(&rng);
    float r = e->disc_r * sqrtf(v1), phi = 2.0f * PB_PI_F * v2;
    v3 q = v3_add(e->disc_center, v3_add(v3_scale(t, r * cosf(phi)), v3_scale(b, r * sinf(phi))));
    o = v3_madd(q, d, -e->back);
    /* E [W/m^2] through a disc of area pi r^2. */
    power = v3_scale(col, (float)((double)PB_PI_F * e->disc_r * e->disc_r * per));
  } else if (s->lights[e->light].type == PB_LIGHT_AREA) {
    const pb_light *l = &s->lights[e->light];
    float wt;
    if (!pb_area_light_emit(l, u1, u2, pb_rng_f(&rng), pb_rng_f(&rng), &o, &d, &wt)) return;
    power = v3_scale(v3_load(l->color), (float)((double)l->intensity * wt * per));
  } else {
    const pb_light *l = &s->lights[e->light];
    d = sample_cone(e->axis, e->cos_max, u1, u2);
    float k = 1.0f;
    if (l->type == PB_LIGHT_SPOT)
      k = pb_spot_factor(l, v3_dot(v3_norm(v3_load(l->direction)), d));
    if (k <= 0.0f) return;
    o = v3_load(l->position);
    if (l->radius > 0.0f) o = pb_sphere_light_origin(l, d, pb_rng_f(&rng), pb_rng_f(&rng));
    /* I(w) [W/sr] over a cone of solid angle omega sampled uniformly. */
    v3 col = v3_scale(v3_load(l->color), l->intensity);
    power = v3_scale(col, (float)((double)k * e->omega * per));
  }
  if (v3_is_zero(power) || !v3_finite(power)) return;

  uint32_t chain = 0;
  v3 sigma = v3_make(0, 0, 0); /* absorbing medium the photon is in */
  for (;;) {
    pb_ref_hit h;
    (*rays)++;
    if (!pb_ref_intersect(&ctx->accel, o, d, INFINITY, &h)) return;
    if (!v3_is_zero(sigma)) power = v3_mul(power, pb_medium_transmittance(sigma, h.t));
    pb_surface surf;
    pb_surface_from_hit(s, &h, d, &surf);
    v3 wo = v3_neg(d);
    pb_bsdf b;
    pb_bsdf_setup(s, &surf, wo, &rng, &b);
    if (chain >= 1 && pb_bsdf_has_smooth(&b)) {
      pb_ref_photon ph;
      memcpy(ph.p, &surf.p, sizeof ph.p);
      ph.wi[0] = wo.x, ph.wi[1] = wo.y, ph.wi[2] = wo.z;
      ph.n[0] = surf.ng.x, ph.n[1] = surf.ng.y, ph.n[2] = surf.ng.z;
      ph.power[0] = power.x, ph.power[1] = power.y, ph.power[2] = power.z;
      ph.chain = chain;
      if (!buf_push(buf, &ph)) {
        pc->oom = 1;
        return;
      }
    }
    /* A further delta bounce makes a chain of chain + 1, stored at a vertex
     * the eye reaches after at least one bounce: worth it only within
     * max_bounces. */
    if ((uint64_t)chain + 2 > ctx->max_bounces) return;
    pb_bsdf_sample bs;
    float v0 = pb_rng_f(&rng), v1 = pb_rng_f(&rng), v2 = pb_rng_f(&rng);
    if (!pb_bsdf_sample_dir(&b, wo, v0, v1, v2, PB_IMPORTANCE, &bs)) return;
    if (!bs.delta) return; /* no longer a pure specular chain */
    power = v3_mul(power, bs.weight);
    if (v3_is_zero(power) || !v3_finite(power)) return;
    /* Russian roulette on long delta chains (a photon caught between
     * mirrors or inside glass by total internal reflection): from the 8th
     * delta event, where the old default truncated, survival
     * q = min(0.95, max_c w_c) and power / q (unbiased: E = q power / q), so
     * the default PB_REF_BOUNCE_CAP is never what ends a chain. Shorter
     * chains draw the same random numbers as before. */
    if (chain >= 7) {
      float q = fminf(0.95f, v3_max(bs.weight));
      if (!(pb_rng_f(&rng) < q)) return;
      power = v3_scale(power, 1.0f / q);
    }
    chain++;
    sigma = pb_medium_after(sigma, &surf, &bs);
    o = pb_offset_ray(surf.p, bs.transmit ? v3_neg(surf.ng) : surf.ng);
    d = bs.wi;
  }
}

static void chunk_work(void *user, uint32_t item, uint32_t thread) {
  pass_ctx *pc = user;
  uint32_t first = item * CHUNK;
  uint32_t last = first + CHUNK < pc->paths ? first + CHUNK : pc->paths;
  uint64_t *rays = &pc->rays[(size_t)thread * RAY_STRIDE];
  for (uint32_t i = first; i < last && !pc->oom; ++i)
    trace_photon(pc, i, &pc->bufs[item], rays);
}

/* Emission domains and light choice weights; 0 lights -> no photons. */
static uint32_t setup_emission(const pb_ref_ctx *ctx, emit_light *out) {
  const pb_scene *s = ctx->scene;
  const pb_ref_lights *L = &ctx->lights;
  uint32_t n = 0;
  double total = 0.0;
  if (!(L->spec_radius > 0.0f)) return 0;
  for (uint32_t i = 0; i <= s->light_count; ++i) {
    int world = i == s->light_count;
    if (world && !s->world.present) break;
    const pb_light *l = world ? NULL : &s->lights[i];
    emit_light e;
    memset(&e, 0, sizeof e);
    e.light = world ? EMIT_WORLD : i;
    double w;
    if (world) {
      w = v3_lum(v3_load(s->world.integral)); /* integral of L over the sphere [W/m^2] */
    } else {
      w = v3_lum(v3_make(fmaxf(l->color[0], 0), fmaxf(l->color[1], 0), fmaxf(l->color[2], 0))) *
          (double)fmaxf(l->intensity, 0.0f);
    }
    if (world || l->type == PB_LIGHT_DIRECTIONAL) {
      e.disc_r = L->spec_radius;
      e.disc_center = L->spec_center;
      /* Start outside the scene's bounding sphere. */
      e.back = v3_len(v3_sub(L->spec_center, L->center)) + L->radius + L->spec_radius;
      w *= M_PI * e.disc_r * e.disc_r;
    } else if (l->type == PB_LIGHT_AREA) {
      w *= M_PI * pb_light_area(l);
    } else {
      v3 to = v3_sub(L->spec_center, v3_load(l->position));
      float dist = v3_len(to), reach = L->spec_radius + l->radius;
      if (dist > reach * 1.0001f) {
        float sin_max = reach / dist;
        e.axis = v3_scale(to, 1.0f / dist);
        e.cos_max = sqrtf(fmaxf(0.0f, 1.0f - sin_max * sin_max));
      } else if (l->type == PB_LIGHT_SPOT) {
        /* Inside the target: the spot's own cone bounds the emission. */
        e.axis = v3_norm(v3_load(l->direction));
        e.cos_max = cosf(fminf(l->outer_cone, PB_PI_F));
      } else {
        e.axis = v3_make(0, 0, 1);
        e.cos_max = -1.0f;
      }
      e.omega = 2.0f * PB_PI_F * (1.0f - e.cos_max);
      w *= e.omega;
    }
    if (!(w > 0.0) || !isfinite(w)) continue;
    e.cdf = w; /* weight for now */
    total += w;
    out[n++] = e;
  }
  if (!(total > 0.0)) return 0;
  double acc = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    double w = out[i].cdf;
    out[i].cdf = acc / total;
    acc += w;
  }
  return n;
}

void pb_ref_photon_map_destroy(pb_ref_photon_map *m) {
  if (!m) return;
  free(m->photons);
  free(m->cell_start);
  memset(m, 0, sizeof *m);
}

static inline int64_t cell_of(float x, float inv_cell) {
  double c = floor((double)x * (double)inv_cell);
  /* Far-away photons share extreme cells; correct, just slower. */
  if (c < -1e15) c = -1e15;
  if (c > 1e15) c = 1e15;
  return (int64_t)c;
}

static inline uint32_t cell_hash(int64_t x, int64_t y, int64_t z, uint32_t mask) {
  uint64_t h = (uint64_t)x * 73856093ull ^ (uint64_t)y * 19349663ull ^
               (uint64_t)z * 83492791ull;
  return (uint32_t)(pb_mix64(h) & mask);
}

static pb_result build_grid(pb_ref_photon_map *m, pb_ref_photon *src, uint32_t count) {
  uint32_t buckets = 1;
  while (buckets < 2 * count && buckets < (1u << 30)) buckets <<= 1;
  m->bucket_count = buckets;
  m->cell_start = calloc((size_t)buckets + 1, sizeof *m->cell_start);
  m->photons = malloc((size_t)(count ? count : 1) * sizeof *m->photons);
  uint32_t *key = malloc((size_t)(count ? count : 1) * sizeof *key);
  if (!m->cell_start || !m->photons || !key) {
    free(key);
    return pb_fail(PB_ERR_NOMEM, "reference: out of memory for %u photons", count);
  }
  float inv = 1.0f / m->cell;
  for (uint32_t i = 0; i < count; ++i) {
    key[i] = cell_hash(cell_of(src[i].p[0], inv), cell_of(src[i].p[1], inv),
                       cell_of(src[i].p[2], inv), buckets - 1);
    m->cell_start[key[i] + 1]++;
  }
  for (uint32_t b = 0; b < buckets; ++b) m->cell_start[b + 1] += m->cell_start[b];
  /* Stable counting sort: photons keep their (deterministic) order within a
   * bucket, so gathers sum in the same order on every run. */
  uint32_t *fill = malloc((size_t)buckets * sizeof *fill);
  if (!fill) {
    free(key);
    return pb_fail(PB_ERR_NOMEM, "reference: out of memory for the photon grid");
  }
  memcpy(fill, m->cell_start, (size_t)buckets * sizeof *fill);
  for (uint32_t i = 0; i < count; ++i) m->photons[fill[key[i]]++] = src[i];
  free(fill);
  free(key);
  m->count = count;
  return PB_OK;
}

pb_result pb_photon_pass(pb_ref_ctx *ctx, uint32_t pass, uint32_t paths,
                         float radius, pb_ref_photon_map *map) {
  memset(map, 0, sizeof *map);
  map->radius = radius;
  map->cell = 2.0f * radius;
  emit_light *emit = malloc((ctx->scene->light_count + 2) * sizeof *emit); /* + the world */
  if (!emit) return pb_fail(PB_ERR_NOMEM, "reference: out of memory");
  pass_ctx pc;
  memset(&pc, 0, sizeof pc);
  pc.ctx = ctx;
  pc.pass = pass;
  pc.paths = paths;
  pc.emit = emit;
  pc.emit_count = setup_emission(ctx, emit);
  if (pc.emit_count == 0 || paths == 0 || !(radius > 0.0f)) {
    free(emit);
    return PB_OK; /* nothing can make a caustic */
  }
  pc.chunk_count = (paths + CHUNK - 1) / CHUNK;
  pc.bufs = calloc(pc.chunk_count, sizeof *pc.bufs);
  pc.rays = calloc((size_t)ctx->threads * RAY_STRIDE, sizeof *pc.rays);
  pb_result r = PB_OK;
  if (!pc.bufs || !pc.rays) {
    r = pb_fail(PB_ERR_NOMEM, "reference: out of memory");
    goto done;
  }
  r = pb_parallel_for(ctx->threads, pc.chunk_count, chunk_work, &pc, NULL, NULL);
  if (r != PB_OK) goto done;
  if (pc.oom) {
    r = pb_fail(PB_ERR_NOMEM, "reference: out of memory storing photons");
    goto done;
  }
  for (uint32_t t = 0; t < ctx->threads; ++t) map->rays += pc.rays[(size_t)t * RAY_STRIDE];

  /* Concatenate the chunks in chunk order (deterministic). */
  uint64_t total = 0;
  for (uint32_t c = 0; c < pc.chunk_count; ++c) total += pc.bufs[c].count;
  if (total > (1u << 30)) {
    r = pb_fail(PB_ERR_LIMIT, "reference: %llu photons in one pass exceed the limit",
                (unsigned long long)total);
    goto done;
  }
  pb_ref_photon *all = malloc((size_t)(total ? total : 1) * sizeof *all);
  if (!all) {
    r = pb_fail(PB_ERR_NOMEM, "reference: out of memory for %llu photons",
                (unsigned long long)total);
    goto done;
  }
  uint64_t at = 0;
  for (uint32_t c = 0; c < pc.chunk_count; ++c) {
    if (pc.bufs[c].count)
      memcpy(all + at, pc.bufs[c].p, pc.bufs[c].count * sizeof *all);
    at += pc.bufs[c].count;
  }
  r = build_grid(map, all, (uint32_t)total);
  free(all);

done:
  if (pc.bufs)
    for (uint32_t c = 0; c < pc.chunk_count; ++c) free(pc.bufs[c].p);
  free(pc.bufs);
  free(pc.rays);
  free(emit);
  if (r != PB_OK) {
    uint64_t rays = map->rays;
    pb_ref_photon_map_destroy(map);
    map->rays = rays;
  }
  return r;
}

v3 pb_photon_gather(const pb_ref_photon_map *m, const pb_bsdf *b, v3 p, v3 wo,
                    uint32_t depth, uint32_t max_bounces) {
  v3 sum = v3_make(0, 0, 0);
  if (!m->count) return sum;
  float r = m->radius, r2 = r * r, inv = 1.0f / m->cell;
  int64_t x0 = cell_of(p.x - r, inv), x1 = cell_of(p.x + r, inv);
  int64_t y0 = cell_of(p.y - r, inv), y1 = cell_of(p.y + r, inv);
  int64_t z0 = cell_of(p.z - r, inv), z1 = cell_of(p.z + r, inv);
  uint32_t mask = m->bucket_count - 1;
  for (int64_t cz = z0; cz <= z1; ++cz)
    for (int64_t cy = y0; cy <= y1; ++cy)
      for (int64_t cx = x0; cx <= x1; ++cx) {
        uint32_t bk = cell_hash(cx, cy, cz, mask);
        for (uint32_t i = m->cell_start[bk]; i < m->cell_start[bk + 1]; ++i) {
          const pb_ref_photon *ph = &m->photons[i];
          /* Two cells may share a bucket: take each photon from its own
           * cell only, or it would be counted twice. */
          if (cell_of(ph->p[0], inv) != cx || cell_of(ph->p[1], inv) != cy ||
              cell_of(ph->p[2], inv) != cz)
            continue;
          v3 d = v3_sub(v3_load(ph->p), p);
          if (v3_dot(d, d) >= r2) continue;
          if ((uint64_t)ph->chain + depth > max_bounces) continue;
          v3 n = v3_load(ph->n);
          if (v3_dot(n, b->ng) <= 0.5f) continue;
          v3 wi = v3_load(ph->wi);
          float cg = v3_dot(wi, b->ng);
          if (cg < 1e-4f) continue;
          float pdf;
          v3 f = pb_bsdf_eval(b, wo, wi, &pdf);
          if (v3_is_zero(f)) continue;
          float k = fabsf(v3_dot(wi, b->n)) / cg;
          sum = v3_add(sum, v3_scale(v3_mul(f, v3_load(ph->power)), k));
        }
      }
  return v3_scale(sum, 1.0f / (PB_PI_F * r2));
}
