/* The temporal filter (temporal.h; shaders/temporal.comp). */
#include "render/temporal.h"

#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "shaders/temporal.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

/* Bindings: PB_TEMPORAL_BIND_* (shaders/shared/pb_contract.h). */
/* The demodulation floor of temporal.comp and atrous.comp. */
static const float PB_ALBEDO_MIN = 1e-3f;

struct pb_temporal {
  uint32_t width, height;
  pb_temporal_desc desc;
  pb_gpu_buffer hist[2], geo[2]; /* ping-pong: [cur] is this frame's input */
  pb_gpu_buffer indirect, albedo, motion;
  pb_gpu_pipeline pipe;
  float *host;                   /* 4 floats per pixel staging */
  int cur, has_history;
};

void pb_temporal_destroy(pb_gpu *g, pb_temporal *t) {
  if (!t) return;
  pb_gpu_pipeline_destroy(g, &t->pipe);
  for (int i = 0; i < 2; ++i) {
    pb_gpu_buffer_destroy(g, &t->hist[i]);
    pb_gpu_buffer_destroy(g, &t->geo[i]);
  }
  pb_gpu_buffer_destroy(g, &t->indirect);
  pb_gpu_buffer_destroy(g, &t->albedo);
  pb_gpu_buffer_destroy(g, &t->motion);
  free(t->host);
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
  size_t n = (size_t)width * height;
  uint64_t bytes = (uint64_t)n * 4 * sizeof(float);
  pb_result r = PB_OK;
  t->host = malloc(bytes);
  if (!t->host) {
    r = pb_fail(PB_ERR_NOMEM, "temporal filter: out of memory for %ux%u pixels", width, height);
    goto fail;
  }
  static const char *const names[] = {"temporal.history0", "temporal.history1", "temporal.geometry0",
                                      "temporal.geometry1", "temporal.indirect", "temporal.albedo",
                                      "temporal.motion"};
  pb_gpu_buffer *bufs[] = {&t->hist[0], &t->hist[1], &t->geo[0], &t->geo[1], &t->indirect, &t->albedo, &t->motion};
  for (size_t i = 0; i < sizeof bufs / sizeof *bufs; ++i) {
    pb_gpu_buffer_desc bd = {.name = names[i], .size = bytes};
    if ((r = pb_gpu_buffer_create(g, &bd, bufs[i])) != PB_OK) goto fail;
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

/* Packs 3 (or 1, into w) floats per pixel into the 4-float staging. */
static void pack3(float *dst, const float *src, size_t n, float w) {
  for (size_t i = 0; i < n; ++i) {
    dst[4 * i + 0] = src[3 * i + 0];
    dst[4 * i + 1] = src[3 * i + 1];
    dst[4 * i + 2] = src[3 * i + 2];
    dst[4 * i + 3] = w;
  }
}

pb_result pb_temporal_apply(pb_gpu *g, pb_temporal *t, const float *normal, const float *depth,
                            const float *albedo, const float *motion, int still, float *indirect, float *history,
                            pb_temporal_stats *stats) {
  size_t n = (size_t)t->width * t->height;
  uint64_t bytes = (uint64_t)n * 4 * sizeof(float);
  if (!motion && !still)
    return pb_fail(PB_ERR_USAGE, "temporal filter: a moving frame needs motion vectors");
  int cur = t->cur, prev = 1 - t->cur;
  pb_result r;
  /* This frame's geometry goes to geo[cur]; the previous frame's is in
   * geo[prev] and its history in hist[prev]. */
  pack3(t->host, normal, n, 0.0f);
  for (size_t i = 0; i < n; ++i) t->host[4 * i + 3] = depth[i];
  if ((r = pb_gpu_buffer_upload(g, &t->geo[cur], 0, t->host, bytes)) != PB_OK) return r;
  pack3(t->host, albedo, n, 0.0f);
  if ((r = pb_gpu_buffer_upload(g, &t->albedo, 0, t->host, bytes)) != PB_OK) return r;
  pack3(t->host, indirect, n, 0.0f);
  if ((r = pb_gpu_buffer_upload(g, &t->indirect, 0, t->host, bytes)) != PB_OK) return r;
  if (motion) {
    r = pb_gpu_buffer_upload(g, &t->motion, 0, motion, bytes);
  } else {
    /* Still: every pixel's point is where it was, at the same depth. */
    for (size_t i = 0; i < n; ++i) {
      t->host[4 * i + 0] = t->host[4 * i + 1] = 0.0f;
      t->host[4 * i + 2] = depth[i];
      t->host[4 * i + 3] = depth[i] > 0.0f ? 1.0f : 0.0f;
    }
    r = pb_gpu_buffer_upload(g, &t->motion, 0, t->host, bytes);
  }
  if (r != PB_OK) return r;
  const pb_gpu_buffer *bind[PB_TEMPORAL_BIND_COUNT] = {
      [PB_TEMPORAL_BIND_HIST_IN] = &t->hist[prev], [PB_TEMPORAL_BIND_GEO_PREV] = &t->geo[prev],
      [PB_TEMPORAL_BIND_GEO] = &t->geo[cur],       [PB_TEMPORAL_BIND_INDIRECT] = &t->indirect,
      [PB_TEMPORAL_BIND_ALBEDO] = &t->albedo,      [PB_TEMPORAL_BIND_MOTION] = &t->motion,
      [PB_TEMPORAL_BIND_HIST_OUT] = &t->hist[cur]};
  if ((r = pb_gpu_pipeline_bind(g, &t->pipe, bind, PB_TEMPORAL_BIND_COUNT)) != PB_OK) return r;
  pb_gpu_temporal_push p = {.width = t->width, .height = t->height, .has_history = (uint32_t)t->has_history,
                            .still = still ? 1u : 0u, .alpha = t->desc.alpha, .sigma_z = t->desc.sigma_z,
                            .sigma_n = t->desc.sigma_n, .max_history = t->desc.max_history,
                            .clamp_gamma = t->desc.clamp_gamma};
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_gpu_dispatch(g, &t->pipe, &p, n);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, 1);
  double w0 = pb_time_now();
  pb_result rs = pb_gpu_submit(g);
  double wall = (pb_time_now() - w0) * 1e3;
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  double ms = pb_gpu_elapsed_ms(g, 0, 1);
  /* The new history is the filtered irradiance: times the albedo (as the
   * pass demodulated it) it is the result. */
  if ((r = pb_gpu_buffer_download(g, &t->hist[cur], 0, t->host, bytes)) != PB_OK) return r;
  uint64_t surf = 0, reset = 0;
  double lsum = 0;
  for (size_t i = 0; i < n; ++i) {
    float L = t->host[4 * i + 3];
    if (depth[i] > 0.0f) {
      for (int k = 0; k < 3; ++k)
        indirect[3 * i + k] = t->host[4 * i + k] * (albedo[3 * i + k] > PB_ALBEDO_MIN ? albedo[3 * i + k] : PB_ALBEDO_MIN);
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
  t->cur = prev;
  t->has_history = 1;
  return PB_OK;
}
