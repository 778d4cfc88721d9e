/* The temporal filter (temporal.h; shaders/filter/temporal.comp). */
#include "render/filter/temporal.h"

#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "shaders/temporal.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

/* Bindings: PB_TEMPORAL_BIND_* (shaders/shared/pb_contract.h). */

/* The host-array path's device buffers (pb_temporal_apply), made on its
 * first call: a sequence's frames never need them. */
typedef struct host_io {
  pb_gpu_buffer geo[2], albedo, indirect, motion, result, stats;
  float *host; /* 4 floats per pixel staging */
  int cur;
} host_io;

struct pb_temporal {
  uint32_t width, height;
  pb_temporal_desc desc;
  pb_gpu_buffer hist[2]; /* ping-pong: [cur] is written by this frame */
  pb_gpu_pipeline pipe;
  int cur, has_history;
  host_io *io;
};

static void host_io_destroy(pb_gpu *g, host_io *io) {
  if (!io) return;
  pb_gpu_buffer *bufs[] = {&io->geo[0], &io->geo[1], &io->albedo, &io->indirect, &io->motion, &io->result, &io->stats};
  for (size_t i = 0; i < sizeof bufs / sizeof *bufs; ++i) pb_gpu_buffer_destroy(g, bufs[i]);
  free(io->host);
  free(io);
}

void pb_temporal_destroy(pb_gpu *g, pb_temporal *t) {
  if (!t) return;
  pb_gpu_pipeline_destroy(g, &t->pipe);
  for (int i = 0; i < 2; ++i) pb_gpu_buffer_destroy(g, &t->hist[i]);
  host_io_destroy(g, t->io);
  free(t);
}

void pb_temporal_reset(pb_temporal *t) {
  if (t) t->has_history = 0;
}

pb_result pb_temporal_create(pb_gpu *g, uint32_t width, uint32_t height, const pb_temporal_desc *desc,
                             pb_temporal **out) {
  *out = NULL;
  if (!width || !height || (uint64_t)width * height > (1u << 28))
    return pb_fail(PB_ERR_USAGE, "temporal filter: image size %ux%u", width, height);
  pb_temporal *t = calloc(1, sizeof *t);
  if (!t) return pb_fail(PB_ERR_NOMEM, "temporal filter: out of memory");
  t->width = width;
  t->height = height;
  t->desc = desc ? *desc : (pb_temporal_desc){0};
  if (!(t->desc.alpha > 0.0f)) t->desc.alpha = 0.95f;
  if (!(t->desc.sigma_z > 0.0f)) t->desc.sigma_z = 1.0f;
  if (!(t->desc.sigma_n > 0.0f)) t->desc.sigma_n = 32.0f;
  if (!(t->desc.max_history > 0.0f)) t->desc.max_history = 4096.0f;
  uint64_t bytes = (uint64_t)width * height * 4 * sizeof(float);
  pb_result r = PB_OK;
  static const char *const names[] = {"temporal.history0", "temporal.history1"};
  for (int i = 0; i < 2; ++i) {
    pb_gpu_buffer_desc bd = {.name = names[i], .size = bytes};
    if ((r = pb_gpu_buffer_create(g, &bd, &t->hist[i])) != PB_OK) goto fail;
  }
  pb_gpu_pipeline_desc pd = {.name = "pass.temporal", .spirv = pb_spv_temporal, .spirv_bytes = sizeof pb_spv_temporal,
                             .binding_count = PB_TEMPORAL_BIND_COUNT, .push_bytes = sizeof(pb_gpu_temporal_push)};
  if ((r = pb_gpu_pipeline_create(g, &pd, &t->pipe)) != PB_OK) goto fail;
  *out = t;
  return PB_OK;
fail:
  pb_temporal_destroy(g, t);
  return r;
}

pb_result pb_temporal_bind(pb_gpu *g, pb_temporal *t, const pb_gpu_buffer *geo, const pb_gpu_buffer *geo_prev,
                           const pb_gpu_buffer *albedo, const pb_gpu_buffer *in, const pb_gpu_buffer *motion,
                           const pb_gpu_buffer *result, const pb_gpu_buffer *stats) {
  /* This frame's history goes to hist[cur]; the previous frame's is in
   * hist[prev]. */
  int cur = t->cur, prev = 1 - t->cur;
  const pb_gpu_buffer *bind[PB_TEMPORAL_BIND_COUNT] = {
      [PB_TEMPORAL_BIND_HIST_IN] = &t->hist[prev], [PB_TEMPORAL_BIND_GEO_PREV] = geo_prev,
      [PB_TEMPORAL_BIND_GEO] = geo,                [PB_TEMPORAL_BIND_INDIRECT] = in,
      [PB_TEMPORAL_BIND_ALBEDO] = albedo,          [PB_TEMPORAL_BIND_MOTION] = motion,
      [PB_TEMPORAL_BIND_HIST_OUT] = &t->hist[cur], [PB_TEMPORAL_BIND_RESULT] = result,
      [PB_TEMPORAL_BIND_STATS] = stats};
  return pb_gpu_pipeline_bind(g, &t->pipe, bind, PB_TEMPORAL_BIND_COUNT);
}

pb_result pb_temporal_record(pb_gpu *g, pb_temporal *t, int still) {
  pb_gpu_temporal_push p = {.width = t->width, .height = t->height, .has_history = (uint32_t)t->has_history,
                            .still = still ? 1u : 0u, .alpha = t->desc.alpha, .sigma_z = t->desc.sigma_z,
                            .sigma_n = t->desc.sigma_n, .max_history = t->desc.max_history,
                            .clamp_gamma = t->desc.clamp_gamma};
  pb_result r = pb_gpu_dispatch(g, &t->pipe, &p, (uint64_t)t->width * t->height);
  t->cur = 1 - t->cur;
  t->has_history = 1;
  return r;
}

void pb_temporal_stats_of(const void *gpu_stats, pb_temporal_stats *stats) {
  pb_gpu_temporal_stats s;
  memcpy(&s, gpu_stats, sizeof s);
  double lsum = ((double)s.len_hi * 4294967296.0 + (double)s.len_lo) / PB_TEMPORAL_LEN_SCALE;
  stats->surface_pixels = s.surface;
  stats->reset_pixels = s.reset;
  stats->mean_history = s.surface ? lsum / (double)s.surface : 0.0;
}

/* Packs 3 floats per pixel into the 4-float staging, w as given. */
static void pack3(float *dst, const float *src, size_t n, float w) {
  for (size_t i = 0; i < n; ++i) {
    dst[4 * i + 0] = src[3 * i + 0];
    dst[4 * i + 1] = src[3 * i + 1];
    dst[4 * i + 2] = src[3 * i + 2];
    dst[4 * i + 3] = w;
  }
}

static pb_result host_io_create(pb_gpu *g, pb_temporal *t) {
  if (t->io) return PB_OK;
  host_io *io = calloc(1, sizeof *io);
  uint64_t bytes = (uint64_t)t->width * t->height * 4 * sizeof(float);
  if (!io || !(io->host = malloc(bytes))) {
    free(io);
    return pb_fail(PB_ERR_NOMEM, "temporal filter: out of memory for %ux%u pixels", t->width, t->height);
  }
  static const char *const names[] = {"temporal.geometry0", "temporal.geometry1", "temporal.albedo",
                                      "temporal.indirect", "temporal.motion", "temporal.result", "temporal.stats"};
  pb_gpu_buffer *bufs[] = {&io->geo[0], &io->geo[1], &io->albedo, &io->indirect, &io->motion, &io->result, &io->stats};
  pb_result r = PB_OK;
  for (size_t i = 0; i < sizeof bufs / sizeof *bufs && r == PB_OK; ++i) {
    pb_gpu_buffer_desc bd = {.name = names[i], .size = i == 6 ? sizeof(pb_gpu_temporal_stats) : bytes,
                             .host_visible = i == 6};
    r = pb_gpu_buffer_create(g, &bd, bufs[i]);
  }
  if (r != PB_OK) {
    host_io_destroy(g, io);
    return r;
  }
  t->io = io;
  return PB_OK;
}

pb_result pb_temporal_apply(pb_gpu *g, pb_temporal *t, const float *normal, const float *depth,
                            const float *albedo, const float *motion, int still, float *indirect, float *history,
                            pb_temporal_stats *stats) {
  size_t n = (size_t)t->width * t->height;
  uint64_t bytes = (uint64_t)n * 4 * sizeof(float);
  if (!motion && !still)
    return pb_fail(PB_ERR_USAGE, "temporal filter: a moving frame needs motion vectors");
  pb_result r = host_io_create(g, t);
  if (r != PB_OK) return r;
  host_io *io = t->io;
  float *h = io->host;
  /* This frame's geometry goes to geo[cur]; the previous frame's is in
   * geo[1 - cur]. */
  int cur = io->cur;
  pack3(h, normal, n, 0.0f);
  for (size_t i = 0; i < n; ++i) h[4 * i + 3] = depth[i];
  if ((r = pb_gpu_buffer_upload(g, &io->geo[cur], 0, h, bytes)) != PB_OK) return r;
  pack3(h, albedo, n, 0.0f);
  if ((r = pb_gpu_buffer_upload(g, &io->albedo, 0, h, bytes)) != PB_OK) return r;
  pack3(h, indirect, n, 0.0f);
  if ((r = pb_gpu_buffer_upload(g, &io->indirect, 0, h, bytes)) != PB_OK) return r;
  if (motion && (r = pb_gpu_buffer_upload(g, &io->motion, 0, motion, bytes)) != PB_OK) return r;
  if ((r = pb_gpu_buffer_fill_zero(g, &io->stats)) != PB_OK) return r;
  /* Still: the pass reads no motion vectors (binding left as it is). */
  if ((r = pb_temporal_bind(g, t, &io->geo[cur], &io->geo[1 - cur], &io->albedo, &io->indirect, &io->motion,
                            &io->result, &io->stats)) != PB_OK)
    return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_temporal_record(g, t, still);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, 1);
  double w0 = pb_time_now();
  pb_result rs = pb_gpu_submit(g);
  double wall = (pb_time_now() - w0) * 1e3;
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  double ms = pb_gpu_elapsed_ms(g, 0, 1);
  io->cur = 1 - cur;
  /* The result: the filtered irradiance times the albedo (as the pass
   * demodulated it) where there is a surface, and in a still frame where
   * the sample missed every surface too (the running mean goes on); the
   * input elsewhere. */
  if ((r = pb_gpu_buffer_download(g, &io->result, 0, h, bytes)) != PB_OK) return r;
  uint64_t surf = 0, reset = 0;
  double lsum = 0;
  for (size_t i = 0; i < n; ++i) {
    float L = h[4 * i + 3];
    if (depth[i] > 0.0f || still)
      for (int k = 0; k < 3; ++k) indirect[3 * i + k] = h[4 * i + k];
    if (depth[i] > 0.0f) {
      ++surf;
      lsum += L;
      if (L < 1.0001f) ++reset;
    }
    if (history) history[i] = L;
  }
  if (stats) {
    stats->gpu_ms = ms >= 0 ? ms : wall;
    stats->surface_pixels = surf;
    stats->reset_pixels = reset;
    stats->mean_history = surf ? lsum / (double)surf : 0.0;
  }
  return PB_OK;
}
