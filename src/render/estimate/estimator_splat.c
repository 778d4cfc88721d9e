/* The screen-space splatting estimator (seed 001, Smal &
 * Aizenshtein, Ray Tracing Gems ch. 24, section 24.3, eq. 2-9): every
 * stored photon facing the camera and in front of it is splatted into the
 * pixels its kernel covers, a tri-axial ellipsoid on the photon's surface
 * whose size comes from the photon's ray length (s_l, eq. 2) and the photon
 * count of its screen tile (s_d, eq. 3-6), stretched along the incident
 * direction (s_u, eq. 7), depth-tested against the frame's G-buffer, its
 * irradiance Phi / a (eq. 9) summed per pixel and turned into reflected
 * radiance with the BSDF at the power-weighted mean direction. The result
 * goes into the same pb_gpu_photon_accum sums the LBVH gather adds to, so
 * the resolve, the temporal filter and A-Trous follow unchanged.
 *
 * Three passes per sample (shaders/estimate/splat_count.comp, splat_splat.comp,
 * splat_resolve.comp; shared/pb_splat.h), recorded by `record` after the
 * sample's G-buffer pass: there is no per-map build (record_build records
 * nothing): the tile counts depend on the camera, which the frame gives at
 * bind time. Where the chapter's text is garbled (eq. 3, 5, 6) the shaders
 * say what was derived. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/estimate/estimator.h"
#include "render/scene/passes.h"
#include "shaders/splat_count.spv.h"
#include "shaders/splat_resolve.spv.h"
#include "shaders/splat_resolve_blender.spv.h"
#include "shaders/splat_splat.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"
#include "shared/pb_splat.h"

/* Defaults of the kernel's constants. The chapter names them
 * (MAX_RAY_LENGTH, n_tile, MAX_SCALING_CONSTANT, KernelCompress,
 * DYNAMIC_KERNEL_SCALE_MIN/MAX) but gives no values; these are ours:
 *  l_max   eq. 2: "related to the overall scale of the scene and can be
 *          derived from its bounding box": the scene's bounding radius
 *          (PB_SPLAT_L_MAX_DEFAULT times it);
 *  n_tile  eq. 6: photons expected per point (see splat_splat.comp for the
 *          square root): 128. Measured on cornell_box (64 px, 4 spp, 2 maps
 *          of 2^16 paths, lavapipe): 32 covers a pixel with 9 kernels on
 *          average (s_l^2 ~ 0.3 of n_tile), 20.2 dB against the reference;
 *          128: 37 kernels, 22.5 dB, the photon light's mean -0.6 % from the
 *          LBVH gather's; 512: 142 kernels, 24.4 dB but -3 % (the kernels
 *          lose their mass past the box's edges) at 4.5x the time;
 *  s_max   eq. 7: 4, the stretch of a photon arriving 75.5 degrees from the
 *          normal;
 *  s_n     the compression along the normal (and the depth test): 1/4;
 *  tile    16 pixels;
 *  r_max   eq. 6's upper clamp: the tracer's r_max (its largest footprint),
 *          else 5 % of the scene's bounding radius; r_min 0. */
#define PB_SPLAT_L_MAX_DEFAULT 1.0f
#define PB_SPLAT_N_TILE_DEFAULT 128.0f
#define PB_SPLAT_S_MAX_DEFAULT 4.0f
#define PB_SPLAT_S_N_DEFAULT 0.25f
#define PB_SPLAT_TILE_DEFAULT 16u
/* A kernel's screen rectangle is clipped to this many pixels either side of
 * its centre (a photon next to the camera; counted in the statistics). */
#define PB_SPLAT_MAX_EXTENT 256u

enum { PASS_COUNT = 0, PASS_SPLAT, PASS_RESOLVE, PASS_N };

typedef struct splat {
  pb_estimator_desc desc;
  float l_max_factor, n_tile, s_max, s_n;
  uint32_t tile;
  float scene_radius;
  /* The map being estimated (handles copied at begin_map). */
  pb_gpu_buffer photons, counts;
  int has_counts;
  const pb_photon_map *map;
  uint32_t capacity;
  float r_max, footprint_scale;
  /* Passes and buffers. */
  pb_gpu_pipeline pass[PASS_N];
  uint32_t resolve_spec[PB_SPEC_COUNT];
  uint32_t resolve_blender;
  pb_gpu_buffer tiles, target, stats, dummy;
  uint64_t tiles_bytes, target_bytes;
  uint32_t tiles_x, tiles_y, frame_width, frame_height;
  int bound, first_sample;
  pb_gpu_splat_stats last;
} splat;

static float scene_radius(const pb_scene *s) {
  float d2 = 0;
  for (int k = 0; k < 3; ++k) {
    float e = s->bounds_max[k] - s->bounds_min[k];
    if (isfinite(e) && e > 0) d2 += e * e;
  }
  float r = 0.5f * sqrtf(d2);
  return r > 0 && isfinite(r) ? r : 1.0f;
}

static float pick(float v, float def) { return v > 0 && isfinite(v) ? v : def; }

static pb_result splat_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, void **impl) {
  splat *e = calloc(1, sizeof *e);
  if (!e) return pb_fail(PB_ERR_NOMEM, "estimator splat: out of memory");
  e->desc = *desc;
  /* pb_estimator_desc.splat: s_l holds eq. 2's l_max as a multiple of the
   * scene's bounding radius, s_d eq. 6's n_tile, s_u eq. 7's s_max (the
   * constants each scale is made from). */
  e->l_max_factor = pick(desc->splat.s_l, PB_SPLAT_L_MAX_DEFAULT);
  e->n_tile = pick(desc->splat.s_d, PB_SPLAT_N_TILE_DEFAULT);
  e->s_max = pick(desc->splat.s_u, PB_SPLAT_S_MAX_DEFAULT);
  if (e->s_max < 1.0f) e->s_max = 1.0f;
  e->s_n = PB_SPLAT_S_N_DEFAULT;
  e->tile = desc->splat.tile ? desc->splat.tile : PB_SPLAT_TILE_DEFAULT;
  e->scene_radius = scene_radius(s);
  e->footprint_scale = 1.0f;
  static const struct {
    const char *name;
    const uint32_t *spv;
    size_t bytes;
  } k[2] = {{"splat.count", pb_spv_splat_count, sizeof pb_spv_splat_count},
            {"splat.splat", pb_spv_splat_splat, sizeof pb_spv_splat_splat}};
  pb_result r = PB_OK;
  for (int i = 0; i < 2 && r == PB_OK; ++i) {
    pb_gpu_pipeline_desc pd = {.name = k[i].name,
                               .spirv = k[i].spv,
                               .spirv_bytes = k[i].bytes,
                               .binding_count = PB_SPLAT_BIND_COUNT,
                               .push_bytes = sizeof(pb_gpu_splat_push)};
    r = pb_gpu_pipeline_create(g, &pd, &e->pass[i]);
  }
  pb_gpu_buffer_desc sd = {.name = "splat.stats", .size = sizeof(pb_gpu_splat_stats), .readback = 1};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &sd, &e->stats);
  if (r == PB_OK) r = pb_gpu_buffer_fill_zero(g, &e->stats);
  pb_gpu_buffer_desc dd = {.name = "splat.dummy", .size = 256};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &dd, &e->dummy);
  if (r == PB_OK) r = pb_gpu_buffer_fill_zero(g, &e->dummy);
  if (r != PB_OK) {
    pb_estimator_splat_ops.destroy(g, e);
    return r;
  }
  *impl = e;
  return PB_OK;
}

static void splat_update(void *impl, const pb_scene *s) {
  splat *e = impl;
  e->scene_radius = scene_radius(s);
}

static pb_result splat_begin_map(pb_gpu *g, void *impl, const pb_photon_map *map, const pb_estimator_map_info *info) {
  (void)g;
  splat *e = impl;
  if (!map || !map->photons.buffer) return pb_fail(PB_ERR_INTERNAL, "estimator splat: a photon map without photons");
  e->map = map;
  e->photons = map->photons;
  e->counts = map->counts;
  e->has_counts = map->counts.buffer != VK_NULL_HANDLE;
  e->capacity = map->capacity;
  e->r_max = info && info->r_max > 0 && isfinite(info->r_max) ? info->r_max : 0.05f * e->scene_radius;
  e->footprint_scale = info && info->footprint_scale > 0 && isfinite(info->footprint_scale) ? info->footprint_scale : 1.0f;
  e->bound = 0;
  return PB_OK;
}

static pb_result splat_record_build(pb_gpu *g, void *impl, uint32_t ts_slot) {
  (void)g, (void)impl, (void)ts_slot; /* nothing per map: the kernels need the camera */
  return PB_OK;
}

static void splat_build_done(pb_gpu *g, void *impl, uint32_t ts_slot, double *gpu_ms) {
  (void)g, (void)impl, (void)ts_slot;
  if (gpu_ms) *gpu_ms = 0.0;
}

static pb_result ensure(pb_gpu *g, pb_gpu_buffer *b, uint64_t *have, uint64_t bytes, const char *name) {
  if (bytes < 16) bytes = 16;
  if (b->buffer && *have >= bytes) return PB_OK;
  pb_gpu_buffer_destroy(g, b);
  *have = 0;
  pb_gpu_buffer_desc d = {.name = name, .size = bytes};
  pb_result r = pb_gpu_buffer_create(g, &d, b);
  if (r != PB_OK) return r;
  *have = bytes;
  return PB_OK;
}

static pb_result splat_bind(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                            const pb_gpu_buffer *photon_nmap) {
  splat *e = impl;
  pb_result r;
  if (!e->photons.buffer) return pb_fail(PB_ERR_INTERNAL, "estimator splat: bound before any photon map");
  /* The image size (tiles over the whole image, every band) from the
   * frame's constants: a 160-byte read, once per map. */
  pb_gpu_frame fr;
  if ((r = pb_gpu_buffer_download(g, ps->bindings[PB_BIND_FRAME], 0, &fr, sizeof fr)) != PB_OK) return r;
  if (fr.width == 0 || fr.height == 0) return pb_fail(PB_ERR_INTERNAL, "estimator splat: an empty frame");
  e->frame_width = fr.width;
  e->frame_height = fr.height;
  e->tiles_x = (fr.width + e->tile - 1) / e->tile;
  e->tiles_y = (fr.height + e->tile - 1) / e->tile;
  uint64_t pixels = ps->bindings[PB_BIND_GBUFFER]->size / sizeof(pb_gpu_gbuffer);
  uint64_t tb = (uint64_t)e->tiles_x * e->tiles_y * sizeof(uint32_t);
  uint64_t pb = pixels * PB_SPLAT_PIXEL_WORDS * sizeof(uint32_t);
  int fresh = !e->tiles.buffer || e->tiles_bytes < tb || !e->target.buffer || e->target_bytes < pb;
  if ((r = ensure(g, &e->tiles, &e->tiles_bytes, tb, "splat.tiles")) != PB_OK) return r;
  if ((r = ensure(g, &e->target, &e->target_bytes, pb, "splat.target")) != PB_OK) return r;
  /* The passes leave both zero behind them (splat_resolve.comp); a new
   * buffer starts zero here. */
  if (fresh && ((r = pb_gpu_buffer_fill_zero(g, &e->tiles)) != PB_OK || (r = pb_gpu_buffer_fill_zero(g, &e->target)) != PB_OK))
    return r;
  if ((r = pb_gpu_buffer_fill_zero(g, &e->stats)) != PB_OK) return r;

  uint32_t spec[PB_SPEC_COUNT] = {0};
  memcpy(spec, ps->spec, PB_SPEC_SHADING_COUNT * sizeof *spec); /* scene.glsl's ids 0-5, as the gather */
  spec[PB_SPEC_NORMAL_MAPS] = ps->normal_maps ? 1u : 0u;
  if (e->pass[PASS_RESOLVE].pipeline &&
      (memcmp(e->resolve_spec, spec, sizeof e->resolve_spec) != 0 || e->resolve_blender != ps->blender))
    pb_gpu_pipeline_destroy(g, &e->pass[PASS_RESOLVE]);
  if (!e->pass[PASS_RESOLVE].pipeline) {
    pb_gpu_pipeline_desc d = {
        .name = "splat.resolve",
        .spirv = ps->blender ? pb_spv_splat_resolve_blender : pb_spv_splat_resolve,
        .spirv_bytes = ps->blender ? sizeof pb_spv_splat_resolve_blender : sizeof pb_spv_splat_resolve,
        .binding_count = PB_SPLAT_BIND_COUNT,
        .push_bytes = sizeof(pb_gpu_splat_push),
        .spec = spec,
        .spec_count = PB_SPEC_COUNT,
    };
    if ((r = pb_gpu_pipeline_create(g, &d, &e->pass[PASS_RESOLVE])) != PB_OK) return r;
    memcpy(e->resolve_spec, spec, sizeof e->resolve_spec);
    e->resolve_blender = ps->blender;
  }
  const pb_gpu_buffer *b[PB_SPLAT_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i]; /* the scene's 15; not the world's */
  b[PB_SPLAT_BIND_PHOTONS] = &e->photons;
  b[PB_SPLAT_BIND_COUNTS] = e->has_counts ? &e->counts : &e->dummy;
  b[PB_SPLAT_BIND_TILES] = &e->tiles;
  b[PB_SPLAT_BIND_TARGET] = &e->target;
  b[PB_SPLAT_BIND_ACCUM] = photon_accum;
  b[PB_SPLAT_BIND_NMAP] = photon_nmap ? photon_nmap : photon_accum; /* never read without normal maps */
  b[PB_SPLAT_BIND_STATS] = &e->stats;
  for (int i = 0; i < PASS_N; ++i)
    if ((r = pb_gpu_pipeline_bind(g, &e->pass[i], b, PB_SPLAT_BIND_COUNT)) != PB_OK) return r;
  e->bound = 1;
  e->first_sample = 1;
  return PB_OK;
}

static pb_result splat_record(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t pixels, uint32_t flags) {
  splat *e = impl;
  if (!e->bound) return pb_fail(PB_ERR_INTERNAL, "estimator splat: recorded before bind");
  uint32_t stored = e->map ? e->map->stored : 0;
  pb_gpu_splat_push push = {
      .sample_index = sample_index,
      .flags = (flags & PB_GATHER_NO_BEAUTY) | (e->has_counts ? PB_SPLAT_USE_COUNTS : 0u) |
               (e->first_sample ? PB_SPLAT_STATS : 0u),
      .stored = stored < e->capacity ? stored : e->capacity,
      .capacity = e->capacity,
      .tile = e->tile,
      .tiles_x = e->tiles_x,
      .tiles_y = e->tiles_y,
      .tiles = e->tiles_x * e->tiles_y,
      .l_max = e->l_max_factor * e->scene_radius,
      .n_tile = e->n_tile,
      .s_max = e->s_max,
      .s_n = e->s_n,
      .r_min = 0.0f,
      .r_max = e->r_max,
      .footprint_scale = e->footprint_scale,
      .max_extent = PB_SPLAT_MAX_EXTENT,
  };
  e->first_sample = 0;
  /* The map's host count is current here (the frame binds and records
   * after the tracer's counts came back); the passes also bound it by the
   * GPU's count where the map has one. */
  uint64_t photons = push.stored;
  pb_result r = PB_OK;
  if (photons > 0) {
    r = pb_gpu_dispatch(g, &e->pass[PASS_COUNT], &push, photons);
    pb_gpu_barrier(g);
    if (r == PB_OK) r = pb_gpu_dispatch(g, &e->pass[PASS_SPLAT], &push, photons);
    pb_gpu_barrier(g);
  }
  uint64_t n = pixels > push.tiles ? pixels : push.tiles;
  if (r == PB_OK) r = pb_gpu_dispatch(g, &e->pass[PASS_RESOLVE], &push, n);
  return r;
}

/* The counters come from the first sample after a bind (PB_SPLAT_STATS),
 * and the frame reads statistics after a map's build, before its samples
 * (frame.c): they describe the first sample of the map before, so they are
 * reported as last values (not summed over the maps), zero before any map
 * was splatted. */
static uint32_t splat_stats(pb_gpu *g, void *impl, pb_tracer_stat *out, uint32_t max) {
  splat *e = impl;
  if (e->stats.buffer && pb_gpu_buffer_download(g, &e->stats, 0, &e->last, sizeof e->last) != PB_OK)
    memset(&e->last, 0, sizeof e->last);
  const pb_gpu_splat_stats *s = &e->last;
  pb_tracer_stat all[] = {
      {"photons", s->stored, 0},        {"back_facing", s->back_facing, 0}, {"outside", s->outside, 0},
      {"off_screen", s->off_screen, 0}, {"counted", s->counted, 0},         {"pairs_tested", s->tested, 0},
      {"pairs_splatted", s->splatted, 0}, {"kernels_clipped", s->clipped, 0}, {"tile", e->tile, 0},
      {"n_tile", e->n_tile, 0},         {"l_max", e->l_max_factor * e->scene_radius, 0},
      {"s_max", e->s_max, 0},           {"s_n", e->s_n, 0},                 {"r_max", e->r_max, 0},
  };
  uint32_t n = (uint32_t)(sizeof all / sizeof *all);
  if (n > max) n = max;
  memcpy(out, all, n * sizeof *out);
  return n;
}

static void splat_destroy(pb_gpu *g, void *impl) {
  splat *e = impl;
  if (!e) return;
  for (int i = 0; i < PASS_N; ++i) pb_gpu_pipeline_destroy(g, &e->pass[i]);
  pb_gpu_buffer_destroy(g, &e->tiles);
  pb_gpu_buffer_destroy(g, &e->target);
  pb_gpu_buffer_destroy(g, &e->stats);
  pb_gpu_buffer_destroy(g, &e->dummy);
  free(e);
}

const pb_estimator_ops pb_estimator_splat_ops = {
    .name = "splat",
    .create = splat_create,
    .update = splat_update,
    .begin_map = splat_begin_map,
    .record_build = splat_record_build,
    .build_done = splat_build_done,
    .bind = splat_bind,
    .record = splat_record,
    .stats = splat_stats,
    .destroy = splat_destroy,
};
