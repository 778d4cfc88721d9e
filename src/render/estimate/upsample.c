/* Multi-level up-sampling of the diffuse photon irradiance (upsample.h; seed
 * 003 sec. 6, Figure 9): the irradiance plane and the pixel list, the mark
 * and compose passes, and the order of the levels. The estimate itself is
 * the estimator's (pb_estimator_record_upsample: the LBVH gather built with
 * -DPB_UPSAMPLE=1). */
#include "render/estimate/upsample.h"

#include <stdlib.h>
#include <string.h>

#include "shared/pb_lbvh.h"
#include "shared/pb_upsample.h"
#include "shaders/upsample_compose.spv.h"
#include "shaders/upsample_mark.spv.h"

enum { UPS_MARK = 0, UPS_COMPOSE, UPS_N };

struct pb_upsample {
  uint32_t levels, capacity;
  pb_gpu_buffer irr, list;
  pb_gpu_pipeline pass[UPS_N];
  uint32_t spec[PB_SPEC_COUNT];
  int caustics, ready;
};

pb_result pb_upsample_create(pb_gpu *g, uint32_t levels, uint32_t band_pixels, pb_upsample **out) {
  *out = NULL;
  if (levels < 1 || levels > PB_UPS_MAX_LEVELS)
    return pb_fail(PB_ERR_USAGE, "render: --upsample-levels %u (0: off, 1 .. %u)", levels, (unsigned)PB_UPS_MAX_LEVELS);
  pb_upsample *u = calloc(1, sizeof *u);
  if (!u) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the up-sampling");
  u->levels = levels;
  u->capacity = band_pixels;
  pb_gpu_buffer_desc id = {.name = "upsample.irradiance", .size = (uint64_t)band_pixels * 16};
  pb_gpu_buffer_desc ld = {.name = "upsample.list", .size = ((uint64_t)PB_UPS_HEADER_WORDS + band_pixels) * 4};
  pb_result r = pb_gpu_buffer_create(g, &id, &u->irr);
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &ld, &u->list);
  if (r == PB_OK) r = pb_gpu_buffer_fill_zero(g, &u->irr);
  if (r == PB_OK) r = pb_gpu_buffer_fill_zero(g, &u->list);
  if (r != PB_OK) {
    pb_upsample_destroy(g, u);
    return r;
  }
  *out = u;
  return PB_OK;
}

pb_result pb_upsample_reset(pb_gpu *g, pb_upsample *u) { return pb_gpu_buffer_fill_zero(g, &u->list); }

pb_result pb_upsample_bind(pb_gpu *g, pb_upsample *u, pb_estimator *est, const pb_pass_setup *ps,
                           const pb_gpu_buffer *photon_accum, int caustics) {
  pb_result r;
  uint32_t spec[PB_SPEC_COUNT];
  memcpy(spec, ps->spec, sizeof spec);
  if (u->pass[UPS_MARK].pipeline && memcmp(spec, u->spec, sizeof spec) != 0)
    for (int i = 0; i < UPS_N; ++i) pb_gpu_pipeline_destroy(g, &u->pass[i]);
  static const struct {
    const char *name;
    const uint32_t *spirv;
    size_t bytes;
  } mods[UPS_N] = {{"pass.upsample_mark", pb_spv_upsample_mark, sizeof pb_spv_upsample_mark},
                   {"pass.upsample_compose", pb_spv_upsample_compose, sizeof pb_spv_upsample_compose}};
  const pb_gpu_buffer *b[PB_UPS_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i]; /* the scene's 0-14 */
  b[PB_UPS_BIND_IRR] = &u->irr;
  b[PB_UPS_BIND_LIST] = &u->list;
  b[PB_UPS_BIND_PACCUM] = photon_accum;
  for (int i = 0; i < UPS_N; ++i) {
    if (!u->pass[i].pipeline) {
      pb_gpu_pipeline_desc d = {.name = mods[i].name, .spirv = mods[i].spirv, .spirv_bytes = mods[i].bytes,
                                .binding_count = PB_UPS_BIND_COUNT, .push_bytes = sizeof(pb_gpu_upsample_push),
                                .spec = spec, .spec_count = PB_SPEC_COUNT};
      if ((r = pb_gpu_pipeline_create(g, &d, &u->pass[i])) != PB_OK) return r;
    }
    if ((r = pb_gpu_pipeline_bind(g, &u->pass[i], b, PB_UPS_BIND_COUNT)) != PB_OK) return r;
  }
  memcpy(u->spec, spec, sizeof spec);
  if ((r = pb_estimator_bind_upsample(g, est, ps, photon_accum, &u->irr, &u->list)) != PB_OK) return r;
  u->caustics = caustics;
  u->ready = 1;
  return PB_OK;
}

pb_result pb_upsample_record(pb_gpu *g, pb_upsample *u, pb_estimator *est, uint32_t sample_index, uint32_t width,
                             uint32_t pixels, uint32_t flags) {
  if (!u->ready) return pb_fail(PB_ERR_INTERNAL, "upsample: recorded before pb_upsample_bind");
  if (pixels > u->capacity || width == 0 || pixels % width)
    return pb_fail(PB_ERR_INTERNAL, "upsample: a band of %u pixels (width %u) for %u", pixels, width, u->capacity);
  uint32_t rows = pixels / width;
  pb_result r = PB_OK;
  /* Figure 9: the coarse level L, then each finer level from the one above
   * (mark: interpolate or queue; the gather at the queued pixels). */
  for (uint32_t l = u->levels;; --l) {
    uint32_t s = 1u << l;
    uint64_t grid = (uint64_t)((width + s - 1) / s) * ((rows + s - 1) / s);
    pb_gpu_upsample_push push = {.sample_index = sample_index, .level = l, .levels = u->levels};
    if ((r = pb_gpu_dispatch(g, &u->pass[UPS_MARK], &push, grid)) != PB_OK) return r;
    pb_gpu_barrier(g);
    if ((r = pb_estimator_record_upsample(g, est, sample_index, (uint32_t)grid, PB_GATHER_UPS_LIST | flags, l)) !=
        PB_OK)
      return r;
    pb_gpu_barrier(g);
    if (l == 0) break;
  }
  pb_gpu_upsample_push push = {.sample_index = sample_index, .levels = u->levels, .flags = flags};
  if ((r = pb_gpu_dispatch(g, &u->pass[UPS_COMPOSE], &push, pixels)) != PB_OK) return r;
  pb_gpu_barrier(g);
  /* Glossy lobes, caustic photons, Blender materials: full resolution. */
  return pb_estimator_record_upsample(g, est, sample_index, pixels,
                                      PB_GATHER_UPS_REST | flags | (u->caustics ? PB_GATHER_UPS_CAUSTICS : 0u), 0);
}

uint32_t pb_upsample_stats(pb_gpu *g, pb_upsample *u, pb_tracer_stat *out, uint32_t max) {
  uint32_t h[PB_UPS_HEADER_WORDS];
  if (!u || pb_gpu_buffer_download(g, &u->list, 0, h, sizeof h) != PB_OK) return 0;
  double coarse = h[PB_UPS_H_ESTIMATED + u->levels], recomputed = 0, interpolated = 0;
  for (uint32_t l = 0; l < u->levels; ++l) recomputed += h[PB_UPS_H_ESTIMATED + l];
  for (uint32_t l = 0; l < u->levels; ++l) interpolated += h[PB_UPS_H_INTERPOLATED + l];
  double full = h[PB_UPS_H_FULL_RES];
  pb_tracer_stat all[] = {
      {"upsample_levels", u->levels, 0},          {"upsample_coarse", coarse, 1},
      {"upsample_recomputed", recomputed, 1},     {"upsample_interpolated", interpolated, 1},
      {"upsample_full_res", full, 1},             {"upsample_estimates", coarse + recomputed + full, 1},
      {"upsample_diffuse", h[PB_UPS_H_DIFFUSE], 1},
  };
  uint32_t n = sizeof all / sizeof *all;
  if (n > max) n = max;
  memcpy(out, all, n * sizeof *out);
  return n;
}

void pb_upsample_stats_add(pb_gpu *g, pb_upsample *u, pb_render_stats *st) {
  pb_tracer_stat us[PB_TRACER_MAX_STATS];
  uint32_t m = pb_upsample_stats(g, u, us, PB_TRACER_MAX_STATS);
  for (uint32_t i = 0; i < m && st->estimator_stat_count < PB_TRACER_MAX_STATS; ++i)
    st->estimator_stats[st->estimator_stat_count++] = us[i];
}

void pb_upsample_destroy(pb_gpu *g, pb_upsample *u) {
  if (!u) return;
  for (int i = 0; i < UPS_N; ++i) pb_gpu_pipeline_destroy(g, &u->pass[i]);
  pb_gpu_buffer_destroy(g, &u->irr);
  pb_gpu_buffer_destroy(g, &u->list);
  free(u);
}
