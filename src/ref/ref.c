/* Driver of the reference renderer: validates the desc, builds the Embree
 * scene and light tables, and renders progressive passes of one sample per
 * pixel over 16x16 tiles on the thread pool of core/parallel.h (tiles
 * handed out by an atomic counter). Each pixel's sum is accumulated in double in pass order, so the
 * image does not depend on the thread count; in SPPM mode each pass first
 * traces its own caustic photon map (photons.c). */
#include <errno.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/log.h"
#include "core/parallel.h"
#include "metrics/metrics.h"
#include "ref/pathtrace.h"

enum { TILE = 16, RAY_STRIDE = 8, MAX_BOUNCES_CAP = 4096 };

uint32_t pb_ref_default_threads(void) { return pb_cpu_count(); }

const char *pb_ref_mode_name(pb_ref_mode m) {
  switch (m) {
  case PB_REF_MODE_PT: return "pt";
  case PB_REF_MODE_SPPM: return "sppm";
  default: return "auto";
  }
}

pb_ref_mode pb_ref_auto_mode(const pb_scene *s) {
  /* Photons leave every light but emissive triangles, and the world. */
  if (s->light_count == 0 && !s->world.present) return PB_REF_MODE_PT;
  pb_ref_lights l;
  if (pb_ref_lights_build(s, &l) != PB_OK) {
    pb_error_clear();
    return PB_REF_MODE_SPPM; /* be safe: the caustic machinery is a superset */
  }
  int spec = l.spec_radius > 0.0f;
  pb_ref_lights_destroy(&l);
  return spec ? PB_REF_MODE_SPPM : PB_REF_MODE_PT;
}

static double cpu_now(void) {
  struct timespec ts;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- rendering ---------------------------------------------------------- */

typedef struct accum {
  double *rgb_direct, *rgb_indirect; /* 3 per pixel */
  double *half_a;                    /* beauty of even samples, or NULL */
  double *albedo, *normal;           /* 3 per pixel */
  double *depth;
  uint32_t *hits;
} accum;

typedef struct render_job {
  pb_ref_ctx *ctx;
  const pb_ref_photon_map *map;
  accum *acc;
  uint32_t pass;
  uint32_t tiles_x;
  uint64_t *rays;     /* per thread, padded */
  uint64_t *guarded;  /* per thread, padded */
  /* progress */
  const pb_ref_desc *desc;
  uint64_t done_before, total, tiles;
  double start, limit;
} render_job;

static void tile_work(void *user, uint32_t item, uint32_t thread) {
  render_job *j = user;
  const pb_ref_ctx *ctx = j->ctx;
  accum *a = j->acc;
  uint32_t x0 = (item % j->tiles_x) * TILE, y0 = (item / j->tiles_x) * TILE;
  uint32_t x1 = x0 + TILE < ctx->width ? x0 + TILE : ctx->width;
  uint32_t y1 = y0 + TILE < ctx->height ? y0 + TILE : ctx->height;
  uint64_t rays = 0, guarded = 0;
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = x0; x < x1; ++x) {
      pb_sample_out so;
      pb_trace_camera_sample(ctx, j->map, x, y, j->pass, &so);
      rays += so.rays;
      if (!v3_finite(so.direct) || !v3_finite(so.indirect) || !v3_finite(so.albedo) ||
          !v3_finite(so.normal) || !isfinite(so.depth)) {
        guarded++;
        continue; /* the sample counts as black: never NaN or Inf downstream */
      }
      size_t i = (size_t)y * ctx->width + x, i3 = 3 * i;
      for (int c = 0; c < 3; ++c) {
        a->rgb_direct[i3 + c] += v3_get(so.direct, c);
        a->rgb_indirect[i3 + c] += v3_get(so.indirect, c);
        a->albedo[i3 + c] += v3_get(so.albedo, c);
        a->normal[i3 + c] += v3_get(so.normal, c);
        if (a->half_a && (j->pass & 1u) == 0)
          a->half_a[i3 + c] += v3_get(so.direct, c) + v3_get(so.indirect, c);
      }
      if (so.hit) {
        a->hits[i]++;
        a->depth[i] += so.depth;
      }
    }
  j->rays[(size_t)thread * RAY_STRIDE] += rays;
  j->guarded[(size_t)thread * RAY_STRIDE] += guarded;
}

static void render_tick(void *user, uint32_t tiles_done) {
  render_job *j = user;
  if (!j->desc->progress) return;
  if (j->limit > 0) {
    double el = pb_time_now() - j->start;
    j->desc->progress(j->desc->progress_user, (uint64_t)(1000.0 * el),
                      (uint64_t)(1000.0 * j->limit));
  } else {
    uint64_t px = (uint64_t)j->ctx->width * j->ctx->height;
    uint64_t in_pass = j->tiles ? px * tiles_done / j->tiles : 0;
    j->desc->progress(j->desc->progress_user, j->done_before + in_pass, j->total);
  }
}

void pb_ref_result_destroy(pb_ref_result *r) {
  if (!r) return;
  free(r->beauty);
  free(r->direct);
  free(r->indirect);
  free(r->albedo);
  free(r->normal);
  free(r->depth);
  free(r->half_a);
  free(r->half_b);
  memset(r, 0, sizeof *r);
}

static void accum_free(accum *a) {
  free(a->rgb_direct);
  free(a->rgb_indirect);
  free(a->half_a);
  free(a->albedo);
  free(a->normal);
  free(a->depth);
  free(a->hits);
}

/* Float from a double sum, finite by construction; a value past FLT_MAX is
 * clamped and counted. */
static float to_float(double v, uint64_t *guarded) {
  if (!isfinite(v)) {
    (*guarded)++;
    return 0.0f;
  }
  if (v > FLT_MAX) {
    (*guarded)++;
    return FLT_MAX;
  }
  if (v < -FLT_MAX) {
    (*guarded)++;
    return -FLT_MAX;
  }
  return (float)v;
}

/* Every index the renderer follows is in range (a loaded scene guarantees
 * it; a scene built in code may not). */
static pb_result check_scene(const pb_scene *s, const char *name) {
  if (s->triangle_count == 0)
    return pb_fail(PB_ERR_SCENE_EMPTY, "%s: no triangles to render", name);
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k)
      if (s->triangles[t][k] >= s->vertex_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: triangle %u uses vertex %u of %u", name,
                       t, s->triangles[t][k], s->vertex_count);
    if (s->triangle_material[t] >= s->material_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: triangle %u uses material %u of %u", name,
                     t, s->triangle_material[t], s->material_count);
  }
  for (uint32_t m = 0; m < s->material_count; ++m) {
    const pb_material *mt = &s->materials[m];
    int32_t tex[3] = {mt->base_color_tex, mt->metallic_roughness_tex, mt->emissive_tex};
    for (int k = 0; k < 3; ++k)
      if (tex[k] >= 0 && (uint32_t)tex[k] >= s->texture_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: material %u uses texture %d of %u", name,
                       m, tex[k], s->texture_count);
  }
  return PB_OK;
}

static pb_result validate(const pb_scene *s, int camera, uint32_t w, uint32_t h,
                          const pb_ref_desc *d) {
  if (!s) return pb_fail(PB_ERR_USAGE, "reference: no scene");
  const char *name = s->path ? s->path : "scene";
  if (camera < 0 || (uint32_t)camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "%s: camera %d does not exist (%u cameras)", name,
                   camera, s->camera_count);
  if (w == 0 || h == 0 || w > 65536 || h > 65536 || (uint64_t)w * h > (1ull << 28))
    return pb_fail(PB_ERR_USAGE, "reference: image size %ux%u is out of range", w, h);
  const pb_camera *c = &s->cameras[camera];
  if (c->orthographic ? !(c->ortho_size > 0.0f && isfinite(c->ortho_size)) : !(c->yfov > 0.0f && c->yfov < 3.1f))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: camera '%s': %s %g is out of range", name, c->name,
                   c->orthographic ? "orthographic size" : "yfov",
                   (double)(c->orthographic ? c->ortho_size : c->yfov));
  if (!(d->time_limit_s >= 0.0) || !isfinite(d->time_limit_s))
    return pb_fail(PB_ERR_USAGE, "reference: time limit %g is not a duration",
                   d->time_limit_s);
  if (!(d->photon_radius >= 0.0f) || !isfinite(d->photon_radius))
    return pb_fail(PB_ERR_USAGE, "reference: photon radius %g is invalid",
                   (double)d->photon_radius);
  if (!(d->photon_alpha >= 0.0f && d->photon_alpha < 1.0f))
    return pb_fail(PB_ERR_USAGE, "reference: photon alpha %g is not in (0, 1)",
                   (double)d->photon_alpha);
  if (d->mode > PB_REF_MODE_SPPM)
    return pb_fail(PB_ERR_USAGE, "reference: unknown mode %d", (int)d->mode);
  return check_scene(s, name);
}

pb_result pb_ref_render(const pb_scene *scene, int camera, uint32_t width,
                        uint32_t height, const pb_ref_desc *desc_in,
                        pb_ref_result *out) {
  memset(out, 0, sizeof *out);
  pb_ref_desc desc;
  if (desc_in) desc = *desc_in;
  else memset(&desc, 0, sizeof desc);
  pb_result r = validate(scene, camera, width, height, &desc);
  if (r != PB_OK) return r;

  uint32_t spp = desc.spp ? desc.spp : (desc.time_limit_s > 0 ? (1u << 24) : 64u);
  if (desc.estimate_noise && (spp & 1u)) spp = spp == UINT32_MAX ? spp - 1 : spp + 1;
  uint32_t max_bounces = desc.max_bounces == PB_REF_BOUNCES_ZERO ? 0
                         : desc.max_bounces ? desc.max_bounces : (uint32_t)PB_REF_BOUNCE_CAP;
  if (max_bounces > MAX_BOUNCES_CAP) max_bounces = MAX_BOUNCES_CAP;
  float alpha = desc.photon_alpha > 0.0f ? desc.photon_alpha : 2.0f / 3.0f;

  pb_ref_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.scene = scene;
  ctx.cam = &scene->cameras[camera];
  ctx.width = width;
  ctx.height = height;
  ctx.max_bounces = max_bounces;
  ctx.threads = desc.threads ? desc.threads : pb_ref_default_threads();
  if (ctx.threads > 1024) ctx.threads = 1024;
  ctx.seed = desc.seed;
  ctx.mode = desc.mode == PB_REF_MODE_AUTO ? pb_ref_auto_mode(scene) : desc.mode;
  pb_camera_view(ctx.cam, width, height, &ctx.view);

  size_t n = (size_t)width * height;
  accum acc;
  memset(&acc, 0, sizeof acc);
  uint64_t *rays = NULL, *guarded = NULL;
  pb_ref_photon_map map;
  memset(&map, 0, sizeof map);

  double t0 = pb_time_now();
  r = pb_ref_accel_create(scene, &ctx.accel);
  if (r != PB_OK) return r;
  r = pb_ref_lights_build(scene, &ctx.lights);
  if (r != PB_OK) goto fail;
  out->stats.build_s = pb_time_now() - t0;

  acc.rgb_direct = calloc(3 * n, sizeof(double));
  acc.rgb_indirect = calloc(3 * n, sizeof(double));
  acc.albedo = calloc(3 * n, sizeof(double));
  acc.normal = calloc(3 * n, sizeof(double));
  acc.depth = calloc(n, sizeof(double));
  acc.hits = calloc(n, sizeof(uint32_t));
  if (desc.estimate_noise) acc.half_a = calloc(3 * n, sizeof(double));
  rays = calloc((size_t)ctx.threads * RAY_STRIDE, sizeof *rays);
  guarded = calloc((size_t)ctx.threads * RAY_STRIDE, sizeof *guarded);
  if (!acc.rgb_direct || !acc.rgb_indirect || !acc.albedo || !acc.normal ||
      !acc.depth || !acc.hits || (desc.estimate_noise && !acc.half_a) || !rays ||
      !guarded) {
    r = pb_fail(PB_ERR_NOMEM, "reference: out of memory for a %ux%u image", width,
                height);
    goto fail;
  }

  /* SPPM: photons per pass and the first radius. Default radius: twice the
   * footprint of a pixel at the distance of the scene's centre, i.e. caustics
   * start about as sharp as the image can show and sharpen from there. */
  uint32_t photons = desc.photons_per_pass;
  if (!photons) photons = n > 16384 ? (uint32_t)(n < (1u << 26) ? n : (1u << 26)) : 16384u;
  float radius = desc.photon_radius;
  if (!(radius > 0.0f)) {
    float dist = v3_len(v3_sub(ctx.lights.center, v3_load(ctx.cam->position)));
    if (!(dist > ctx.lights.radius * 1e-3f)) dist = ctx.lights.radius;
    radius = 2.0f * pb_camera_pixel_size(&ctx.view, dist);
  }
  out->stats.photon_radius_first = radius;

  uint32_t tiles_x = (width + TILE - 1) / TILE, tiles_y = (height + TILE - 1) / TILE;
  render_job job;
  memset(&job, 0, sizeof job);
  job.ctx = &ctx;
  job.acc = &acc;
  job.tiles_x = tiles_x;
  job.rays = rays;
  job.guarded = guarded;
  job.desc = &desc;
  job.tiles = (uint64_t)tiles_x * tiles_y;
  job.total = (uint64_t)spp * n;
  job.limit = desc.time_limit_s;

  double start = pb_time_now(), cpu_start = cpu_now();
  job.start = start;
  uint64_t photon_rays = 0;
  uint32_t pass = 0;
  double r2 = (double)radius * radius;
  for (; pass < spp; ++pass) {
    if (ctx.mode == PB_REF_MODE_SPPM) {
      /* Knaus & Zwicker's schedule: r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1)
       * with i = pass + 1 counting from 1. */
      if (pass > 0) r2 *= ((double)pass + alpha) / ((double)pass + 1.0);
      r = pb_photon_pass(&ctx, pass, photons, (float)sqrt(r2), &map);
      photon_rays += map.rays;
      if (r != PB_OK) goto fail;
      out->stats.photon_paths += photons;
      out->stats.photons_stored += map.count;
      out->stats.photon_radius_last = (float)sqrt(r2);
    }
    job.map = ctx.mode == PB_REF_MODE_SPPM ? &map : NULL;
    job.pass = pass;
    job.done_before = (uint64_t)pass * n;
    r = pb_parallel_for(ctx.threads, tiles_x * tiles_y, tile_work, &job, render_tick,
                        &job);
    pb_ref_photon_map_destroy(&map);
    if (r != PB_OK) goto fail;
    render_tick(&job, (uint32_t)job.tiles);
    if (desc.time_limit_s > 0 && pb_time_now() - start >= desc.time_limit_s &&
        (!desc.estimate_noise || (pass & 1u) == 1u)) {
      pass++;
      break;
    }
  }
  out->stats.time_s = pb_time_now() - start;
  out->stats.cpu_s = cpu_now() - cpu_start;
  out->stats.spp = pass;
  out->stats.passes = pass;
  out->stats.threads = ctx.threads;
  out->stats.mode = ctx.mode;
  out->stats.camera_samples = (uint64_t)pass * n;
  out->stats.rays = photon_rays;
  for (uint32_t t = 0; t < ctx.threads; ++t) {
    out->stats.rays += rays[(size_t)t * RAY_STRIDE];
    out->stats.guarded_samples += guarded[(size_t)t * RAY_STRIDE];
  }

  out->width = width;
  out->height = height;
  out->beauty = malloc(4 * n * sizeof(float));
  out->direct = malloc(3 * n * sizeof(float));
  out->indirect = malloc(3 * n * sizeof(float));
  out->albedo = malloc(3 * n * sizeof(float));
  out->normal = malloc(3 * n * sizeof(float));
  out->depth = malloc(n * sizeof(float));
  float *ha = NULL, *hb = NULL;
  if (desc.estimate_noise) {
    ha = out->half_a = malloc(3 * n * sizeof(float));
    hb = out->half_b = malloc(3 * n * sizeof(float));
  }
  if (!out->beauty || !out->direct || !out->indirect || !out->albedo ||
      !out->normal || !out->depth || (desc.estimate_noise && (!ha || !hb))) {
    r = pb_fail(PB_ERR_NOMEM, "reference: out of memory for the output images");
    goto fail;
  }
  double inv = pass ? 1.0 / pass : 0.0;
  uint64_t g = 0;
  uint32_t na = (pass + 1) / 2, nb = pass / 2;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      size_t k = 3 * i + (size_t)c;
      double d = acc.rgb_direct[k], id = acc.rgb_indirect[k];
      out->direct[k] = to_float(d * inv, &g);
      out->indirect[k] = to_float(id * inv, &g);
      out->beauty[4 * i + (size_t)c] = to_float((d + id) * inv, &g);
      out->albedo[k] = to_float(acc.albedo[k] * inv, &g);
      out->normal[k] = to_float(acc.normal[k] * inv, &g);
      if (ha) {
        ha[k] = to_float(na ? acc.half_a[k] / na : 0.0, &g);
        hb[k] = to_float(nb ? (d + id - acc.half_a[k]) / nb : 0.0, &g);
      }
    }
    /* Alpha: coverage, or 1 with an opaque film (pb_scene.film_opaque). */
    out->beauty[4 * i + 3] = scene->film_opaque ? 1.0f : to_float(acc.hits[i] * inv, &g);
    out->depth[i] = acc.hits[i] ? to_float(acc.depth[i] / acc.hits[i], &g) : 0.0f;
  }
  out->stats.guarded_samples += g;
  out->stats.noise_rmse = out->stats.noise_relmse = out->stats.noise_psnr = -1.0;
  if (ha) {
    pb_noise_estimate ne;
    r = pb_metrics_noise_from_halves(ha, hb, width, height, 3, NULL, &ne);
    if (r != PB_OK) goto fail;
    out->stats.noise_rmse = ne.rmse;
    out->stats.noise_relmse = ne.relmse;
    out->stats.noise_psnr = ne.psnr;
  }
  accum_free(&acc);
  free(rays);
  free(guarded);
  pb_ref_lights_destroy(&ctx.lights);
  pb_ref_accel_destroy(&ctx.accel);
  return PB_OK;

fail:
  accum_free(&acc);
  free(rays);
  free(guarded);
  pb_ref_photon_map_destroy(&map);
  pb_ref_lights_destroy(&ctx.lights);
  pb_ref_accel_destroy(&ctx.accel);
  pb_ref_result_destroy(out);
  return r;
}
