/* Temporal then spatial filtering of the indirect AOV (filters.h): on host
 * arrays (pb_filter_indirect) and on the GPU inside the frame (the chain). */
#include "render/filter/filters.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/filter/atrous.h"
#include "render/scene/motion.h"
#include "render/frame/readback.h"
#include "shaders/filter_io.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

/* Caustics: their own temporal filter (filters.h), the beauty updated. */
static pb_result filter_caustic(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d, const float *normal) {
  size_t n = (size_t)res->width * res->height;
  float *raw = malloc(3 * n * sizeof *raw);
  if (!raw) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the filters");
  memcpy(raw, res->caustic, 3 * n * sizeof *raw);
  pb_temporal_stats ts;
  pb_result r = pb_temporal_apply(g, d->temporal_caustic, normal, res->depth, res->albedo, d->motion, d->still,
                                  res->caustic, NULL, &ts);
  if (r == PB_OK) {
    res->stats.temporal_ms += ts.gpu_ms;
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        float *c = &res->caustic[3 * i + k];
        if (!isfinite(*c)) *c = 0.0f, res->stats.nonfinite_values++;
        res->beauty[4 * i + k] += *c - raw[3 * i + k];
      }
  }
  free(raw);
  return r;
}

pb_result pb_filter_indirect(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d) {
  if (d->temporal_caustic && res->caustic) {
    pb_result r = filter_caustic(g, res, d, res->geo_normal ? res->geo_normal : res->normal);
    if (r != PB_OK) return r;
  }
  if (!res->indirect || (!d->temporal && !d->atrous_iterations)) return PB_OK;
  size_t n = (size_t)res->width * res->height;
  float *raw = malloc(3 * n * sizeof *raw);
  float *hist = d->temporal ? malloc(n * sizeof *hist) : NULL;
  if (!raw || (d->temporal && !hist)) {
    free(raw);
    free(hist);
    return pb_fail(PB_ERR_NOMEM, "render: out of memory for the filters");
  }
  memcpy(raw, res->indirect, 3 * n * sizeof *raw);
  pb_result r = PB_OK;
  pb_render_stats *st = &res->stats;
  /* Edge-stopping on the geometric normal where normal maps bend the
   * shading one (seed 001 24.4.3: the photon irradiance has no normal-map
   * detail to keep; eq. 20 puts it back after the filters). */
  const float *fn = res->geo_normal ? res->geo_normal : res->normal;
  if (d->temporal) {
    pb_temporal_stats ts;
    r = pb_temporal_apply(g, d->temporal, fn, res->depth, res->albedo, d->motion, d->still,
                          res->indirect, hist, &ts);
    if (r == PB_OK) {
      st->temporal_ms += ts.gpu_ms;
      st->temporal_reset_pixels = ts.reset_pixels;
      st->temporal_surface_pixels = ts.surface_pixels;
      st->temporal_mean_history = ts.mean_history;
    }
  }
  if (r == PB_OK && d->atrous_iterations) {
    pb_atrous_desc fd = {.iterations = d->atrous_iterations, .gamma = d->atrous_gamma, .history = hist};
    double ms = 0;
    r = d->atrous ? pb_atrous_pass_run(g, d->atrous, fn, res->depth, res->albedo, res->indirect, &fd, &ms)
                  : pb_atrous_filter(g, res->width, res->height, fn, res->depth, res->albedo, res->indirect, &fd, &ms);
    st->filter_ms += ms;
  }
  if (r == PB_OK) {
    for (size_t i = 0; i < 3 * n; ++i)
      if (!isfinite(res->indirect[i])) res->indirect[i] = 0.0f, st->nonfinite_values++;
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) res->beauty[4 * i + k] += res->indirect[3 * i + k] - raw[3 * i + k];
  }
  free(raw);
  free(hist);
  return r;
}

/* ---- the filter chain (filters.h) ------------------------------------------ */

struct pb_filter_chain {
  uint32_t width, height;
  pb_filter_chain_desc desc;
  pb_temporal *temporal, *temporal_caustic;
  pb_atrous_pass *atrous;
  pb_motion_pass *motion;        /* with a temporal filter */
  pb_gpu_pipeline io;            /* filter_io.comp */
  /* vec4 per pixel: geometry (ping-pong for the temporal filters: [cur] is
   * this frame's), albedo, indirect and caustics before (in) and after the
   * temporal filters (the same buffer without one). */
  pb_gpu_buffer geo[2], albedo, ind_in, ind, cau_in, cau;
  pb_gpu_buffer stats, stats_caustic; /* pb_gpu_temporal_stats */
  int cur;
  pb_filter_frame frame;
  int has_frame, has_prev, moving_now, caustic_now, geo_normal;
  uint32_t slot0, pixels;
  float *motion_host;            /* pb_filter_chain_host's */
};

void pb_filter_chain_destroy(pb_gpu *g, pb_filter_chain *c) {
  if (!c) return;
  pb_temporal_destroy(g, c->temporal);
  pb_temporal_destroy(g, c->temporal_caustic);
  pb_atrous_pass_destroy(g, c->atrous);
  pb_motion_pass_destroy(g, c->motion);
  pb_gpu_pipeline_destroy(g, &c->io);
  pb_gpu_buffer *bufs[] = {&c->geo[0], &c->geo[1], &c->albedo, &c->ind_in, &c->ind,
                           &c->cau_in, &c->cau,    &c->stats,  &c->stats_caustic};
  for (size_t i = 0; i < sizeof bufs / sizeof *bufs; ++i) pb_gpu_buffer_destroy(g, bufs[i]);
  free(c->motion_host);
  free(c);
}

pb_result pb_filter_chain_create(pb_gpu *g, uint32_t width, uint32_t height, const pb_filter_chain_desc *d,
                                 pb_filter_chain **out) {
  *out = NULL;
  if (!width || !height || (uint64_t)width * height > (1u << 28))
    return pb_fail(PB_ERR_USAGE, "filters: image size %ux%u", width, height);
  pb_filter_chain *c = calloc(1, sizeof *c);
  if (!c) return pb_fail(PB_ERR_NOMEM, "filters: out of memory");
  c->width = width, c->height = height, c->desc = *d;
  uint64_t bytes = (uint64_t)width * height * 4 * sizeof(float);
  pb_result r = PB_OK;
  int tc = d->temporal && d->temporal_caustic;
  struct { pb_gpu_buffer *b; const char *name; int on; uint64_t size; int mapped; } bufs[] = {
      {&c->geo[0], "filters.geometry0", 1, bytes, 0},
      {&c->geo[1], "filters.geometry1", d->temporal, bytes, 0},
      {&c->albedo, "filters.albedo", 1, bytes, 0},
      {&c->ind_in, "filters.indirect_in", d->temporal, bytes, 0},
      {&c->ind, "filters.indirect", 1, bytes, 0},
      {&c->cau_in, "filters.caustic_in", tc, bytes, 0},
      {&c->cau, "filters.caustic", tc, bytes, 0},
      {&c->stats, "filters.temporal_stats", d->temporal, sizeof(pb_gpu_temporal_stats), 1},
      {&c->stats_caustic, "filters.temporal_caustic_stats", tc, sizeof(pb_gpu_temporal_stats), 1}};
  for (size_t i = 0; i < sizeof bufs / sizeof *bufs && r == PB_OK; ++i)
    if (bufs[i].on) {
      pb_gpu_buffer_desc bd = {.name = bufs[i].name, .size = bufs[i].size, .host_visible = bufs[i].mapped,
                               .readback = bufs[i].mapped};
      r = pb_gpu_buffer_create(g, &bd, bufs[i].b);
    }
  if (r != PB_OK) goto fail;
  if (d->temporal && (r = pb_temporal_create(g, width, height, &d->temporal_desc, &c->temporal)) != PB_OK) goto fail;
  if (tc) {
    pb_temporal_desc cd = d->temporal_desc;
    cd.clamp_gamma = d->caustic_clamp_gamma;
    if ((r = pb_temporal_create(g, width, height, &cd, &c->temporal_caustic)) != PB_OK) goto fail;
  }
  if (d->atrous_iterations && (r = pb_atrous_pass_create(g, width, height, &c->atrous)) != PB_OK) goto fail;
  /* Made now, not by the first moving frame: a live view's first move must
   * not wait for a pipeline compilation. */
  if (d->temporal && (r = pb_motion_pass_create(g, width, height, d->vertex_count, &c->motion)) != PB_OK) goto fail;
  pb_gpu_pipeline_desc pd = {.name = "pass.filter_io", .spirv = pb_spv_filter_io, .spirv_bytes = sizeof pb_spv_filter_io,
                             .binding_count = PB_FILTER_IO_BIND_COUNT, .push_bytes = sizeof(pb_gpu_filter_io_push)};
  if ((r = pb_gpu_pipeline_create(g, &pd, &c->io)) != PB_OK) goto fail;
  *out = c;
  return PB_OK;
fail:
  pb_filter_chain_destroy(g, c);
  return r;
}

void pb_filter_chain_set_frame(pb_filter_chain *c, const pb_filter_frame *f) {
  c->frame = *f;
  c->has_frame = 1;
}

/* Moving frames after the first need motion vectors. */
static int chain_moving(const pb_filter_chain *c) {
  return c->temporal && c->has_frame && c->frame.moving && c->has_prev;
}
/* (has_prev: the chain filtered a frame before; the sequence says moving
 * only from its second frame on, so this is a second guard.) */

pb_result pb_filter_chain_bind(pb_gpu *g, pb_filter_chain *c, const pb_frame_targets *t, int geo_normal) {
  pb_result r = PB_OK;
  c->geo_normal = geo_normal;
  c->moving_now = chain_moving(c);
  c->caustic_now = c->temporal_caustic != NULL;
  const pb_filter_frame *f = &c->frame;
  if (c->moving_now) {
    if (!c->motion && (r = pb_motion_pass_create(g, c->width, c->height, c->desc.vertex_count, &c->motion)) != PB_OK)
      return r;
    if ((r = pb_motion_pass_prepare(g, c->motion, f->s, f->gs, f->prev_positions, &f->cam, &f->prev_cam)) != PB_OK)
      return r;
  }
  const pb_gpu_buffer *geo = &c->geo[c->temporal ? c->cur : 0], *geo_prev = &c->geo[c->temporal ? 1 - c->cur : 0];
  const pb_gpu_buffer *ind_in = c->temporal ? &c->ind_in : &c->ind;
  /* Without caustics' own filter their bindings are never read or written. */
  const pb_gpu_buffer *cau_in = c->caustic_now ? &c->cau_in : &c->albedo, *cau = c->caustic_now ? &c->cau : &c->albedo;
  const pb_gpu_buffer *io[PB_FILTER_IO_BIND_COUNT] = {
      [PB_FILTER_IO_BIND_PLANES] = &t->planes,  [PB_FILTER_IO_BIND_PHOTON_PLANES] = &t->pplanes,
      [PB_FILTER_IO_BIND_GEO] = geo,            [PB_FILTER_IO_BIND_ALBEDO] = &c->albedo,
      [PB_FILTER_IO_BIND_INDIRECT_IN] = ind_in, [PB_FILTER_IO_BIND_INDIRECT] = &c->ind,
      [PB_FILTER_IO_BIND_CAUSTIC_IN] = cau_in,  [PB_FILTER_IO_BIND_CAUSTIC] = cau,
      [PB_FILTER_IO_BIND_GUARD] = &t->guard};
  if ((r = pb_gpu_pipeline_bind(g, &c->io, io, PB_FILTER_IO_BIND_COUNT)) != PB_OK) return r;
  /* Still frames: the temporal pass reads no motion (any buffer will do). */
  const pb_gpu_buffer *mv = c->moving_now ? pb_motion_pass_output(c->motion) : &c->albedo;
  if (c->temporal) {
    if ((r = pb_gpu_buffer_fill_zero(g, &c->stats)) != PB_OK ||
        (r = pb_temporal_bind(g, c->temporal, geo, geo_prev, &c->albedo, &c->ind_in, mv, &c->ind, &c->stats)) != PB_OK)
      return r;
  }
  if (c->caustic_now) {
    if ((r = pb_gpu_buffer_fill_zero(g, &c->stats_caustic)) != PB_OK ||
        (r = pb_temporal_bind(g, c->temporal_caustic, geo, geo_prev, &c->albedo, &c->cau_in, mv, &c->cau,
                              &c->stats_caustic)) != PB_OK)
      return r;
  }
  if (c->atrous && (r = pb_atrous_pass_bind(g, c->atrous, geo, &c->albedo, &c->ind)) != PB_OK) return r;
  return PB_OK;
}

pb_result pb_filter_chain_record(pb_gpu *g, pb_filter_chain *c, uint32_t pixels, uint32_t *slot) {
  /* Slots: s0 start, +1 packed, +2 motion, +3 temporal, +4 A-Trous, +5 composed. */
  uint32_t s0 = c->slot0 = *slot;
  c->pixels = pixels;
  *slot += 5;
  int still = !c->moving_now;
  pb_gpu_filter_io_push p = {.pixels = pixels, .mode = PB_FILTER_IO_PACK,
                             .flags = (c->geo_normal ? PB_FILTER_IO_GEO_NORMAL : 0u) |
                                      (c->caustic_now ? PB_FILTER_IO_CAUSTIC : 0u)};
  pb_result r = pb_gpu_dispatch(g, &c->io, &p, pixels);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, s0 + 1);
  if (r == PB_OK && c->moving_now) r = pb_motion_pass_record(g, c->motion);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, s0 + 2);
  if (r == PB_OK && c->caustic_now) r = pb_temporal_record(g, c->temporal_caustic, still);
  if (r == PB_OK && c->temporal) r = pb_temporal_record(g, c->temporal, still);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, s0 + 3);
  if (r == PB_OK && c->atrous) {
    pb_atrous_desc ad = {.iterations = c->desc.atrous_iterations, .gamma = c->desc.atrous_gamma};
    r = pb_atrous_pass_record(g, c->atrous, &ad);
  }
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, s0 + 4);
  p.mode = PB_FILTER_IO_COMPOSE;
  p.flags = (c->temporal || c->atrous ? PB_FILTER_IO_INDIRECT : 0u) | (c->caustic_now ? PB_FILTER_IO_CAUSTIC : 0u);
  if (r == PB_OK && p.flags) r = pb_gpu_dispatch(g, &c->io, &p, pixels);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, s0 + 5);
  if (c->temporal) c->cur = 1 - c->cur;
  c->has_prev = 1;
  return r;
}

pb_result pb_filter_chain_finish(pb_gpu *g, pb_filter_chain *c, int timestamps, pb_render_stats *st) {
  uint32_t s0 = c->slot0;
  if (timestamps) {
    double ms[5];
    for (int i = 0; i < 5; ++i) {
      ms[i] = pb_gpu_elapsed_ms(g, s0 + i, s0 + i + 1);
      if (ms[i] < 0) ms[i] = 0;
    }
    st->motion_ms += ms[1];
    st->temporal_ms += ms[2];
    st->filter_ms += ms[0] + ms[3] + ms[4]; /* the A-Trous and the moves in and out */
  }
  if (c->temporal) {
    pb_temporal_stats ts;
    pb_result r = pb_readback_temporal_stats(g, &c->stats, &ts);
    if (r != PB_OK) return r;
    st->temporal_reset_pixels = ts.reset_pixels;
    st->temporal_surface_pixels = ts.surface_pixels;
    st->temporal_mean_history = ts.mean_history;
  }
  return PB_OK;
}

pb_result pb_filter_chain_host(pb_gpu *g, pb_filter_chain *c, pb_render_result *res) {
  if (!res->indirect) return PB_OK;
  int moving = chain_moving(c);
  pb_result r = PB_OK;
  if (moving) {
    const pb_filter_frame *f = &c->frame;
    double t0 = pb_time_now(), ms = 0;
    if (!c->motion_host && !(c->motion_host = malloc((size_t)c->width * c->height * 4 * sizeof(float))))
      return pb_fail(PB_ERR_NOMEM, "filters: out of memory for %ux%u motion vectors", c->width, c->height);
    if (!c->motion && (r = pb_motion_pass_create(g, c->width, c->height, c->desc.vertex_count, &c->motion)) != PB_OK)
      return r;
    if ((r = pb_motion_pass_run(g, c->motion, f->s, f->gs, f->prev_positions, &f->cam, &f->prev_cam, c->motion_host,
                                &ms)) != PB_OK)
      return r;
    res->stats.motion_ms += ms > 0 ? ms : (pb_time_now() - t0) * 1e3;
  }
  pb_filter_desc fd = {.atrous_iterations = c->desc.atrous_iterations,
                       .atrous_gamma = c->desc.atrous_gamma,
                       .temporal = c->temporal,
                       .temporal_caustic = c->temporal_caustic,
                       .motion = moving ? c->motion_host : NULL,
                       .still = !moving,
                       .atrous = c->atrous};
  c->has_prev = 1;
  return pb_filter_indirect(g, res, &fd);
}
