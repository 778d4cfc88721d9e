/* One frame of the GPU renderer: orders the passes (see render.h), renders
 * the image in bands of rows when its per-pixel targets (targets.h) would
 * exceed the device's maxStorageBufferRange, times each pass with
 * timestamps, resolves the accumulators into AOVs on the GPU (resolve.h),
 * filters the indirect light there (the filter chain, filters.h; eq. 20,
 * shading_correction.h) in the resolve's command buffer, and brings the
 * AOVs to the host through the readback (readback.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/estimator.h"
#include "render/passes.h"
#include "render/photon.h"
#include "render/tracer.h"
#include "render/upsample.h"
#include "render/plan.h"
#include "render/readback.h"
#include "render/resolve.h"
#include "render/targets.h"
#include "render/filters.h"
#include "render/shading_correction.h"
#include "shared/pb_photon.h"
#include "shared/pb_resolve.h"
#include "render/render.h"
#include "scene/camera.h"

/* Samples recorded per submission: three timestamps each (gbuffer, direct,
 * gather), plus the start. */
enum { SAMPLES_PER_SUBMIT = 64, TIMESTAMP_SLOTS = 3 * SAMPLES_PER_SUBMIT + 1 };

/* ---- frames in flight: what the host writes while a frame still runs --------
 *
 * With pb_render_desc.in_flight a frame's last submission (the resolve, the
 * filter chain, eq. 20, the still run's means, the copy into the readback
 * ring: "tail N") is not waited for; the next frame N+1 is posed, set up and
 * recorded, and its first submissions queued, while tail N may still run
 * (gpu.h PB_GPU_FRAMES: its own command buffer, fence and timestamps). Every
 * host write between tail N's submission and N+1's last submission, and why
 * tail N cannot see it:
 *   sequence.c  pb_gpu_scene_update (geometry or lights moved): uploads of
 *               positions, BVH, lights: over 64 KiB they wait for tail N,
 *               under it they are deferred (recorded after tail N, gpu.h
 *               pb_gpu_submit_async). pb_filter_chain_set_frame: host state
 *               only, read when N+1's chain is recorded.
 *   frame.c     tg.frame (pb_gpu_frame, the camera and constants): deferred.
 *               tg.accum, tg.paccum, tg.pnmap zeroed (tail N's resolve reads
 *               them): deferred fills. tg.guard, tg.kpd (tail N's resolve
 *               writes them, its settle reads them): zeroed after the settle
 *               below, right before N+1's resolve.
 *   upsample.c  pb_upsample_reset's list fill: deferred.
 *   photon_trace.c (pb_tracer_prepare) image counts fill, frame, params,
 *               lights and map counts uploads: deferred (params and lights
 *               over 64 KiB wait).
 *   pipeline binds (tracer, estimator, up-sampling, filter chain, temporal,
 *               A-Trous, still sum): the same buffers as the set holds skip
 *               (gpu.h); the others wait for tail N (the temporal filter's
 *               ping-pong history rebinds every frame: after the settle).
 *   filters.c   the temporal statistics' fills (tail N wrote them, its settle
 *               reads them): after the settle, nothing pending.
 *   motion.c    the motion pass's params and previous positions: uploaded
 *               while N+1's tail records, after the settle.
 *   targets.c   the still run's means (pb_still_sum): GPU-only; the frame
 *               count is a push constant of the recording.
 *   readback    tail N writes ring slot i, N+1's tail slot i + 1; the host
 *               reads slot i after tail N's fence (pb_render_frame_read).
 *   estimator   statistics read from the GPU after the samples (vsch's pair
 *               counts, kNN's cut queries): read before tail N's submission
 *               (estimator_final), not at its settle, where N+1's build
 *               would have replaced them.
 * No code outside src/gpu writes a buffer's `mapped` pointer. Checked with
 * PB_SYNC_VALIDATION=1 (tests/frame_in_flight.py): zero messages. */

/* ---- the frame context (render.h) ------------------------------------------ */

/* What a reusable context must match: everything its contents depend on.
 * Zeroed before filling, so memcmp compares no padding garbage. */
typedef struct ctx_key {
  const pb_gpu_scene *gs;
  const void *photon_map;
  uint32_t width, height, photons, bounces, first_bounce, tracer, image_maps, image_map_resolution, upsample_levels;
  float smoothing, r_max, smoothing_caustic, bandwidth_c0, caustic_share;
  int direct_only, photons_on;
  pb_estimator_desc estimator; /* 4-byte fields only: no padding */
} ctx_key;

/* What a frame's last submission leaves to do once the GPU has run it
 * (frame_settle, frame_read): everything pb_render_frame knew at that
 * submission and its finish needs. A frame in flight keeps it in its
 * context, one per readback ring slot (targets.h). */
typedef struct frame_tail {
  int ts, chain_gpu, post_gpu, photons_on, nmap_aovs, opaque, no_shading_correction;
  int readback; /* PB_RENDER_READBACK_*: what the readback brings */
  int est_final; /* the estimator's final statistics are in the result already */
  uint64_t gpu_sub; /* the last submission (gpu.h): its timestamps */
  uint32_t sc_slot, slot, pixels, spp_run, iters_run, emitter_count, ring_slot;
  size_t pixel_base, n;
  float inv_spp;
  double gpu_ms, gbuf_ms, direct_ms, gather_ms, photon_gpu_ms, trace_ms, est_build_ms, k_sum, hit_sum, wall0;
  double host_ms; /* frames in flight: the wall time of pb_render_frame up to the last submission */
  uint64_t stored_sum, caustic_sum;
  pb_gpu_transfers tr0, tr_submit; /* at the frame's start and its last submission */
  pb_filter_chain *fc;
  pb_estimator *est;
  pb_upsample *ups;
  const pb_gpu_scene *gs;
} frame_tail;

struct pb_frame_context {
  int valid;
  ctx_key key;
  frame_tail tail[PB_READBACK_RING]; /* frames in flight, by ring slot */
  uint32_t next_slot;                /* the ring slot of the next frame in flight */
  pb_frame_targets tg;
  pb_gpu_pipeline gp, dp, rp, scp;
  pb_tracer *tracer;
  pb_estimator *est;
  pb_upsample *ups;
  pb_photon_map map;
};

pb_result pb_frame_context_create(pb_frame_context **out) {
  *out = calloc(1, sizeof **out);
  return *out ? PB_OK : pb_fail(PB_ERR_NOMEM, "render: out of memory");
}

static void context_clear(pb_gpu *g, pb_frame_context *c) {
  if (!c->valid) return;
  pb_photon_map_destroy(g, &c->map);
  pb_estimator_destroy(g, c->est);
  pb_upsample_destroy(g, c->ups);
  pb_tracer_destroy(g, c->tracer);
  pb_gpu_pipeline_destroy(g, &c->gp);
  pb_gpu_pipeline_destroy(g, &c->dp);
  pb_gpu_pipeline_destroy(g, &c->rp);
  pb_gpu_pipeline_destroy(g, &c->scp);
  pb_frame_targets_destroy(g, &c->tg);
  memset(c, 0, sizeof *c);
}

void pb_frame_context_destroy(pb_gpu *g, pb_frame_context *c) {
  if (!c) return;
  context_clear(g, c);
  free(c);
}

void pb_render_result_destroy(pb_render_result *r) {
  if (!r) return;
  free(r->beauty);
  free(r->direct);
  free(r->albedo);
  free(r->normal);
  free(r->depth);
  free(r->material);
  free(r->emission);
  free(r->indirect);
  free(r->caustic);
  free(r->geo_normal);
  free(r->photon_dir);
  free(r->shading_normal);
  memset(r, 0, sizeof *r);
}

static pb_result validate(const pb_scene *s, int camera, uint32_t w, uint32_t h, const pb_render_desc *d) {
  if (camera < 0 || (uint32_t)camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "render: camera %d of %u", camera, s->camera_count);
  if (w == 0 || h == 0 || w > 16384 || h > 16384)
    return pb_fail(PB_ERR_USAGE, "render: image size %ux%u (1..16384 per side)", w, h);
  if (d->spp > (1u << 20)) return pb_fail(PB_ERR_USAGE, "render: %u samples per pixel (at most 2^20)", d->spp);
  if (d->alpha < 0.0f || !(d->alpha < 1.0f))
    return pb_fail(PB_ERR_USAGE, "render: progressive alpha %g (in (0, 1))", d->alpha);
  if (!(d->glossy_path_roughness <= 1.0f))
    return pb_fail(PB_ERR_USAGE, "render: glossy path roughness %g (at most 1)", d->glossy_path_roughness);
  if (d->full_width && ((uint64_t)d->crop_x + w > d->full_width || (uint64_t)d->crop_y + h > d->full_height ||
                        d->full_width > 65536 || d->full_height > 65536))
    return pb_fail(PB_ERR_USAGE, "render: crop %ux%u at (%u, %u) does not fit in the %ux%u frame", w, h, d->crop_x,
                   d->crop_y, d->full_width, d->full_height);
  if (!(d->time_limit_s >= 0) || !isfinite(d->time_limit_s))
    return pb_fail(PB_ERR_USAGE, "render: time limit %g s is not a duration", d->time_limit_s);
  if (d->max_specular_depth > PB_RENDER_MAX_SPECULAR_DEPTH)
    return pb_fail(PB_ERR_USAGE, "render: --max-specular-depth %u (at most %d)", d->max_specular_depth,
                   PB_RENDER_MAX_SPECULAR_DEPTH);
  return PB_OK;
}

double pb_render_estimator_stat(const pb_render_stats *st, const char *name, double missing) {
  for (uint32_t i = 0; i < st->estimator_stat_count; ++i)
    if (!strcmp(st->estimator_stats[i].name, name)) return st->estimator_stats[i].value;
  return missing;
}

/* Progressive mode: Hachisuka & Jensen's SPPM radius reduction in Knaus &
 * Zwicker's probabilistic form (2011): iteration i = 1, 2, ... uses an
 * independent map with every footprint scaled by k_i,
 *   r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1),
 *   k_i^2 = prod_{j=1}^{i-1} (j + alpha) / (j + 1)  (k_1 = 1),
 * and the frame averages the K estimates (each with its own radius), so
 * variance ~ 1 / (K r_K^2) -> 0 and bias ~ r_K^2 -> 0 together (r_K^2 ~
 * K^(alpha - 1)). Without it k_i = 1 (a plain average, whose bias stays).
 * The estimator applies k_i (pb_estimator_map_info.footprint_scale; the
 * LBVH's in lbvh_climb) to iteration `it`'s map. */
static float footprint_scale(const pb_render_desc *d, uint32_t it) {
  if (!d->progressive) return 1.0f;
  double k2 = 1.0, alpha = d->alpha > 0.0f ? d->alpha : 2.0 / 3.0;
  for (uint32_t j = 1; j <= d->iteration_base + it; ++j) k2 *= (j + alpha) / (j + 1.0);
  return (float)sqrt(k2);
}

/* Progress and the time limit, after iteration `it` of band 0 finished
 * (samples [0, s_end) of every pixel of the band are in `accum`). Calls
 * desc->progress, with the mean beauty so far when desc->preview_interval_s
 * allows one (the whole image in one band, not the last iteration: its
 * beauty is the result, and at most one per interval); lowers *iters_run to
 * it + 1 once desc->time_limit_s has passed. */
typedef struct preview_state {
  float *beauty;
  double last_s;
} preview_state;

static pb_result iteration_done(pb_gpu *g, const pb_render_desc *d, const pb_frame_targets *tg, preview_state *pv, uint32_t it, uint32_t iters, uint32_t s_end, uint32_t spp,
                                uint32_t width, uint32_t height, uint32_t bands, double t0, uint32_t *iters_run) {
  double now = pb_time_now();
  if (d->time_limit_s > 0 && now - t0 >= d->time_limit_s && it + 1 < *iters_run) *iters_run = it + 1;
  if (!d->progress) return PB_OK;
  pb_render_progress p = {.iteration = it + 1, .iterations = *iters_run, .samples = s_end,
                          .spp = (uint32_t)((uint64_t)*iters_run * spp / iters), .elapsed_s = now - t0,
                          .width = width, .height = height};
  size_t n = (size_t)width * height;
  if (d->preview_interval_s >= 0 && bands == 1 && it + 1 < *iters_run && s_end > 0 &&
      (pv->last_s == 0 || now - pv->last_s >= d->preview_interval_s)) {
    if (!pv->beauty && !(pv->beauty = malloc(4 * n * sizeof(float))))
      return pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u preview", width, height);
    pb_result r = pb_readback_preview(g, tg, n, s_end, pv->beauty);
    if (r != PB_OK) return r;
    p.beauty = pv->beauty;
    pv->last_s = now;
  }
  return d->progress(d->progress_user, &p);
}

/* After the band's last submission finished: its GPU times and the filter
 * chain's statistics (timestamps of the last submission: before the next
 * pb_gpu_begin). */
static pb_result tail_band_times(pb_gpu *g, frame_tail *ft, pb_render_result *out) {
  /* A frame in flight's submission may not be the last one any more: its
   * context keeps its timestamps until released (gpu.h pb_gpu_release). */
  int ts = ft->ts && pb_gpu_timestamps_of(g, ft->gpu_sub);
  if (ts) { /* the resolve and eq. 20; the chain's passes in their own stats */
    double ms = pb_gpu_elapsed_ms(g, 0, 1), ms2 = pb_gpu_elapsed_ms(g, ft->sc_slot, ft->slot);
    ft->gpu_ms += (ms > 0 ? ms : 0) + (ms2 > 0 ? ms2 : 0);
  }
  pb_result r = ft->chain_gpu ? pb_filter_chain_finish(g, ft->fc, ts, &out->stats) : PB_OK;
  pb_gpu_release(g, ft->gpu_sub);
  (void)pb_gpu_timestamps_of(g, 0);
  return r;
}

/* The estimator's and the up-sampling's statistics after the frame's
 * samples (a frame in flight: before its last submission, which the next
 * frame's work follows). */
static void estimator_final(pb_gpu *g, frame_tail *ft, pb_render_stats *st) {
  if (ft->photons_on && ft->est) pb_estimator_stats_final(g, ft->est, st);
  if (ft->photons_on && ft->ups) pb_upsample_stats_add(g, ft->ups, st); /* under "estimator" too */
  ft->est_final = 1;
}

/* The frame's statistics once every band is read back (or, for a frame in
 * flight, once its last submission finished: all but k_pd, which the
 * readback completes), the guard's count and the host path's filters. */
static pb_result tail_frame(pb_gpu *g, const pb_frame_targets *tg, frame_tail *ft, pb_render_result *out) {
  pb_render_stats *st = &out->stats;
  pb_result r;
  const pb_gpu_scene *gs = ft->gs;
  size_t n = ft->n;
  /* Statistics that are not summed over maps (vsch's pair counts, kNN's cut
   * queries) are read here, after the frame's samples; a deferred tail (frames
   * in flight) reads them after the next frame was recorded, so they may
   * describe that frame's work. */
  if (!ft->est_final) estimator_final(g, ft, st);
  if ((r = pb_readback_guard(g, tg, &st->nonfinite_values)) != PB_OK) return r;
  /* A lean readback reads no k_PD plane: the resolve's sums (16 bytes),
   * here, before the next frame zeroes them (a frame in flight: settled). */
  if (ft->photons_on && ft->readback != PB_RENDER_READBACK_ALL &&
      (r = pb_readback_kpd(g, tg, &ft->k_sum, &ft->hit_sum)) != PB_OK)
    return r;
  st->readback_mode = ft->readback;
  if (!ft->post_gpu && ft->readback == PB_RENDER_READBACK_ALL) {
    /* The host path (several bands, the host reference): the same filters
     * on the read-back AOVs, then eq. 20. With normal maps the filters'
     * edge-stopping uses the geometric normal (filters.c). */
    if (ft->fc && ft->photons_on && (r = pb_filter_chain_host(g, ft->fc, out)) != PB_OK) return r;
    if (!ft->no_shading_correction) pb_shading_correction_apply(out, n, PB_SHADING_CORRECTION_S_MAX);
  }
  int ts = ft->ts;
  st->spp = ft->spp_run;
  st->timestamps = ts;
  st->gbuffer_ms = ts ? ft->gbuf_ms : -1;
  st->direct_ms = ts ? ft->direct_ms : -1;
  st->total_gpu_ms = ft->gpu_ms;
  st->upload_ms = gs->upload_s * 1e3;
  st->bvh_build_ms = gs->bvh.build_s * 1e3;
  st->bvh_nodes = gs->bvh.node_count;
  st->bvh_depth = gs->bvh.depth;
  st->primary_rays = (uint64_t)n * ft->spp_run;
  st->shadow_rays_max = (uint64_t)n * ft->spp_run * (gs->light_count + (ft->emitter_count ? 1u : 0u));
  if (ft->photons_on) {
    st->photon_trace_ms = ft->trace_ms;
    st->estimator_build_ms = ft->est_build_ms;
    st->gather_ms = ts ? ft->gather_ms : -1;
    st->photons_stored = ft->stored_sum;
    st->photons_caustic = ft->caustic_sum;
    st->iterations = ft->iters_run;
    st->k_pd = ft->hit_sum > 0 ? ft->k_sum / ft->hit_sum : 0.0;
  }
  st->wall_ms = (pb_time_now() - ft->wall0) * 1e3;
  st->frame_wall_ms = st->wall_ms;
  st->frame_gpu_ms = ts ? ft->gpu_ms + ft->photon_gpu_ms + st->filter_ms + st->temporal_ms + st->motion_ms : -1;
  pb_gpu_transfers tr1 = pb_gpu_transfers_get(g);
  st->upload_bytes = tr1.upload_bytes - ft->tr0.upload_bytes;
  st->download_bytes = tr1.download_bytes - ft->tr0.download_bytes;
  st->readback_bytes = tr1.readback_bytes - ft->tr0.readback_bytes;
  return PB_OK;
}

static pb_result settle_tail(pb_gpu *g, const pb_frame_targets *tg, frame_tail *ft, pb_render_result *out) {
  double t0 = pb_time_now();
  pb_gpu_transfers s0 = pb_gpu_transfers_get(g);
  pb_result r = pb_gpu_wait(g);
  if (r == PB_OK) r = tail_band_times(g, ft, out);
  if (r == PB_OK) r = tail_frame(g, tg, ft, out);
  /* Not this frame's: what moved between its last submission and now (the
   * previous frame's readback from the ring). */
  out->stats.upload_bytes -= s0.upload_bytes - ft->tr_submit.upload_bytes;
  out->stats.download_bytes -= s0.download_bytes - ft->tr_submit.download_bytes;
  out->stats.readback_bytes -= s0.readback_bytes - ft->tr_submit.readback_bytes;
  /* Frames in flight: the host's time on this frame, not the GPU's that
   * ran while the host did something else (render.h). */
  out->stats.frame_wall_ms = ft->host_ms + (pb_time_now() - t0) * 1e3;
  out->pending = 2; /* settled, pixels not read */
  return r;
}

pb_result pb_render_frame_settle(pb_gpu *g, pb_frame_context *c, pb_render_result *out) {
  if (out->pending != 1 || !c || !c->valid || out->pending_slot >= PB_READBACK_RING)
    return pb_fail(PB_ERR_INTERNAL, "render: no frame in flight to settle");
  return settle_tail(g, &c->tg, &c->tail[out->pending_slot], out);
}

pb_result pb_render_frame_read(pb_gpu *g, pb_frame_context *c, pb_render_result *out) {
  if (out->pending != 2 || !c || !c->valid || out->pending_slot >= PB_READBACK_RING)
    return pb_fail(PB_ERR_INTERNAL, "render: no settled frame to read back");
  frame_tail *ft = &c->tail[out->pending_slot];
  double t0 = pb_time_now();
  pb_gpu_transfers tr0 = pb_gpu_transfers_get(g);
  pb_result r = pb_readback_ring(g, &c->tg, ft->readback, ft->ring_slot, ft->pixels, ft->nmap_aovs, out, &ft->k_sum,
                                 &ft->hit_sum);
  if (r != PB_OK) return r;
  pb_render_stats *st = &out->stats;
  if (ft->photons_on) st->k_pd = ft->hit_sum > 0 ? ft->k_sum / ft->hit_sum : 0.0;
  st->readback_bytes += pb_gpu_transfers_get(g).readback_bytes - tr0.readback_bytes;
  st->frame_wall_ms += (pb_time_now() - t0) * 1e3;
  out->pending = 0;
  return PB_OK;
}

pb_result pb_render_result_read_gpu(pb_gpu *g, pb_render_result *r) {
  if (r->stats.readback_mode == PB_RENDER_READBACK_ALL) return PB_OK; /* all on the host already */
  if (r->pending || !r->gpu.planes)
    return pb_fail(PB_ERR_INTERNAL, "render: the frame's planes are not on the GPU to read");
  /* A frame in flight's ring slot holds what its lean readback read and
   * pb_render_desc.keep_planes: every AOV needs every plane. */
  uint64_t need = PB_RENDER_KEEP(PB_RESOLVE_BEAUTY) | PB_RENDER_KEEP(PB_RESOLVE_DIRECT) |
                  PB_RENDER_KEEP(PB_RESOLVE_ALBEDO) | PB_RENDER_KEEP(PB_RESOLVE_NORMAL) |
                  PB_RENDER_KEEP(PB_RESOLVE_DEPTH) | PB_RENDER_KEEP(PB_RESOLVE_MATERIAL) |
                  PB_RENDER_KEEP(PB_RESOLVE_EMISSION);
  if (r->gpu.photons) need |= PB_RENDER_KEEP(PB_RESOLVE_INDIRECT) | PB_RENDER_KEEP(PB_RESOLVE_CAUSTIC);
  if (r->gpu.nmap && r->gpu.nmap_aovs)
    need |= PB_RENDER_KEEP(PB_RESOLVE_GEO_NORMAL) | PB_RENDER_KEEP(PB_RESOLVE_PHOTON_DIR) |
            PB_RENDER_KEEP(PB_RESOLVE_SHADING_NORMAL);
  if ((r->gpu.kept & need) != need)
    return pb_fail(PB_ERR_INTERNAL, "render: a frame in flight with a lean readback kept only some planes "
                                    "(pb_render_desc.keep_planes): its AOVs cannot be read");
  size_t n = r->gpu.pixels;
  float **arr[] = {&r->beauty, &r->direct, &r->albedo, &r->normal, &r->depth, &r->material, &r->emission,
                   &r->indirect, &r->caustic};
  const size_t ch[] = {4, 3, 3, 3, 1, 1, 3, 3, 3};
  for (size_t a = 0; a < sizeof arr / sizeof *arr; ++a) {
    if (a >= 7 && !r->gpu.photons) break;
    if (!*arr[a] && !(*arr[a] = calloc(ch[a] * n, sizeof(float))))
      return pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u image", r->width, r->height);
  }
  pb_gpu_transfers t0 = pb_gpu_transfers_get(g);
  pb_result rr = pb_readback_planes(g, &r->gpu, r);
  r->stats.readback_bytes += pb_gpu_transfers_get(g).readback_bytes - t0.readback_bytes;
  if (rr == PB_OK) r->stats.readback_mode = PB_RENDER_READBACK_ALL;
  return rr;
}

pb_result pb_render_frame_complete(pb_gpu *g, pb_frame_context *c, pb_render_result *out) {
  pb_result r = out->pending == 1 ? pb_render_frame_settle(g, c, out) : PB_OK;
  if (r == PB_OK && out->pending == 2) r = pb_render_frame_read(g, c, out);
  return r;
}

pb_result pb_render_frame(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width,
                          uint32_t height, const pb_render_desc *desc_in, pb_render_result *out) {
  memset(out, 0, sizeof *out);
  pb_render_desc desc = {0};
  if (desc_in) desc = *desc_in;
  pb_result r = validate(s, camera, width, height, &desc);
  if (r != PB_OK) return r;
  uint32_t spp = desc.spp ? desc.spp : 1;
  int photons_on = !desc.direct_only && (desc.photon_map || gs->light_count > 0 || s->world.present || gs->emitter_count > 0);
  uint32_t iters = photons_on ? (desc.iterations ? desc.iterations : 1) : 1;
  if (photons_on && spp < iters) spp = iters;
  uint32_t max_spec = desc.max_specular_depth ? desc.max_specular_depth : PB_RENDER_MAX_SPECULAR_DEPTH; /* RR from 8: gbuffer.comp */
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  double wall0 = pb_time_now();
  pb_gpu_transfers tr0 = pb_gpu_transfers_get(g);

  /* Band: whole rows whose per-pixel targets each fit one storage buffer
   * (the largest: the accumulators, 80 bytes per pixel; targets.h).
   * Never truncated: a row that does not fit is refused. */
  uint64_t per_pixel = pb_frame_targets_max_pixel_bytes();
  uint64_t max_pixels = lim->max_storage_buffer_range / per_pixel;
  if (max_pixels > lim->max_allocation / per_pixel) max_pixels = lim->max_allocation / per_pixel;
  if (max_pixels < width)
    return pb_fail(PB_ERR_LIMIT, "render: one row of %u pixels needs %llu bytes of G-buffer, over the device's "
                   "storage-buffer limit of %llu bytes; render a narrower image",
                   width, (unsigned long long)(width * per_pixel),
                   (unsigned long long)lim->max_storage_buffer_range);
  uint32_t band_rows = (uint32_t)(max_pixels / width);
  if (band_rows > height) band_rows = height;
  uint32_t band_pixels = band_rows * width;
  uint32_t bands = (height + band_rows - 1) / band_rows;

  size_t n = (size_t)width * height;
  pb_frame_targets tg;
  memset(&tg, 0, sizeof tg);
  pb_gpu_pipeline gp = {0}, dp = {0}, rp = {0}, scp = {0};
  /* The filters of the indirect light: the sequence's chain, or one made
   * for this call's A-Trous (filters.h). */
  pb_filter_chain *fc = desc.filters, *own_fc = NULL;
  int nmap_on = 0;
  pb_tracer *tracer = NULL;
  pb_estimator *est = NULL;
  pb_upsample *ups = NULL;
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  double trace_ms = 0, est_build_ms = 0, gather_ms = 0, k_sum = 0, hit_sum = 0;
  double photon_gpu_ms = 0; /* tracing and LBVH builds of every band (timing.frame_gpu_ms) */
  uint64_t stored_sum = 0, caustic_sum = 0;
  /* Iterations run (fewer than iters when the time limit stops the
   * refinement in band 0; later bands run as many) and their samples. */
  uint32_t iters_run = iters, spp_run = spp;
  preview_state preview = {0};
  /* A context from the previous frame of a sequence: reused when it matches,
   * its contents owned by this call until the end (a failure destroys them). */
  pb_frame_context *ctx = desc.context;
  ctx_key key;
  memset(&key, 0, sizeof key);
  key.gs = gs;
  key.photon_map = desc.photon_map;
  key.width = width, key.height = height, key.photons = desc.photons, key.bounces = desc.photon_bounces;
  key.first_bounce = desc.first_bounce;
  key.tracer = desc.tracer, key.image_maps = desc.image_maps, key.image_map_resolution = desc.image_map_resolution;
  key.upsample_levels = desc.upsample_levels;
  key.smoothing = desc.smoothing, key.r_max = desc.r_max, key.smoothing_caustic = desc.smoothing_caustic;
  memcpy(&key.estimator, &desc.estimator, sizeof key.estimator);
  key.bandwidth_c0 = desc.bandwidth_c0;
  key.caustic_share = desc.caustic_share;
  key.direct_only = desc.direct_only, key.photons_on = photons_on;
  int reuse = ctx && ctx->valid && !memcmp(&ctx->key, &key, sizeof key);
  /* The previous frame in flight (pb_render_desc.settle_first): finished
   * here before its context goes, with its pixels. */
  pb_render_result *prev = desc.settle_first && desc.settle_first->pending && ctx ? desc.settle_first : NULL;
  if (prev && !reuse) {
    double p0 = pb_time_now();
    if ((r = pb_render_frame_complete(g, ctx, prev)) != PB_OK) return r;
    wall0 += pb_time_now() - p0; /* its time, not this frame's */
    tr0 = pb_gpu_transfers_get(g);
    prev = NULL;
  }
  if (ctx && !reuse) context_clear(g, ctx);
  /* A frame in flight's tails (read after this frame's last submission)
   * and the ring's next slot survive the hand-over below. */
  frame_tail kept_tails[PB_READBACK_RING];
  uint32_t kept_slot = ctx ? ctx->next_slot : 0;
  if (ctx) memcpy(kept_tails, ctx->tail, sizeof kept_tails);
  if (reuse) {
    tg = ctx->tg;
    gp = ctx->gp, dp = ctx->dp, rp = ctx->rp, scp = ctx->scp;
    tracer = ctx->tracer, est = ctx->est, ups = ctx->ups, map = ctx->map;
    memset(ctx, 0, sizeof *ctx);
  }
  /* A lean readback (render.h pb_render_desc.readback): where nothing on
   * the host needs the AOVs. The GPU path in one band (the host path's
   * filters and eq. 20 work on the read-back arrays), a context to keep
   * the planes in, and a still run's means on the GPU when there is one
   * (else the caller averages the arrays). Everything else reads all. */
  const char *host_env0 = getenv("PB_RESOLVE_ON_HOST");
  int host_resolve = host_env0 && host_env0[0] == '1';
  int readback = PB_RENDER_READBACK_ALL;
  if ((desc.readback == PB_RENDER_READBACK_BEAUTY || desc.readback == PB_RENDER_READBACK_STATS) && ctx &&
      bands == 1 && !host_resolve && (!desc.still_sum || desc.still_sum->pixels == band_pixels))
    readback = desc.readback;
  int read_all = readback == PB_RENDER_READBACK_ALL;
  if (read_all || readback == PB_RENDER_READBACK_BEAUTY) out->beauty = calloc(4 * n, sizeof(float));
  if (read_all) {
    out->direct = calloc(3 * n, sizeof(float));
    out->albedo = calloc(3 * n, sizeof(float));
    out->normal = calloc(3 * n, sizeof(float));
    out->depth = calloc(n, sizeof(float));
    out->material = calloc(n, sizeof(float));
    out->emission = calloc(3 * n, sizeof(float));
    if (photons_on) {
      out->indirect = calloc(3 * n, sizeof(float));
      out->caustic = calloc(3 * n, sizeof(float));
    }
  }
  if ((readback != PB_RENDER_READBACK_STATS && !out->beauty) ||
      (read_all && (!out->direct || !out->albedo || !out->normal || !out->depth || !out->material || !out->emission ||
               (photons_on && (!out->indirect || !out->caustic))))) {
    r = pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u image", width, height);
    goto fail;
  }
  pb_render_plan plan;
  pb_render_plan_of(s, desc.direct_only, &plan);
  if (!reuse && ((r = pb_frame_targets_create(g, band_pixels, photons_on, plan.normal_maps, &tg)) != PB_OK ||
                 (r = pb_resolve_create(g, &tg, &rp)) != PB_OK ||
                 (tg.nmap && (r = pb_shading_correction_create(g, &tg, &scp)) != PB_OK)))
    goto fail;
  if (!fc && photons_on && desc.atrous_iterations) {
    pb_filter_chain_desc cd = {.atrous_iterations = desc.atrous_iterations, .atrous_gamma = desc.atrous_gamma};
    if ((r = pb_filter_chain_create(g, width, height, &cd, &own_fc)) != PB_OK) goto fail;
    fc = own_fc;
  }
  pb_pass_setup ps = {
      .bindings = {[PB_BIND_FRAME] = &tg.frame, [PB_BIND_NODES] = &gs->nodes, [PB_BIND_TRIS] = &gs->tris,
                   [PB_BIND_INDICES] = &gs->indices, [PB_BIND_NORMALS] = &gs->normals, [PB_BIND_UVS] = &gs->uvs,
                   [PB_BIND_TRI_MATERIAL] = &gs->tri_material, [PB_BIND_MATERIALS] = &gs->materials,
                   [PB_BIND_TEXTURES] = &gs->textures, [PB_BIND_TEXELS] = &gs->texels, [PB_BIND_LIGHTS] = &gs->lights,
                   [PB_BIND_GBUFFER] = &tg.gbuf, [PB_BIND_ACCUM] = &tg.accum, [PB_BIND_POSITIONS] = &gs->positions,
                   [PB_BIND_EMITTERS] = &gs->emitters, [PB_BIND_WORLD] = &gs->world},
      .spec = {[PB_SPEC_HAS_NORMALS] = plan.vertex_normals ? 1u : 0u, [PB_SPEC_TEXTURES] = plan.textures ? 1u : 0u,
               [PB_SPEC_SPECULAR] = plan.eye_chains ? 1u : 0u,
               [PB_SPEC_EMISSIVE] = plan.emitter_sampling || plan.unlit ? 1u : 0u,
               [PB_SPEC_SOFT_LIGHTS] = plan.soft_lights ? 1u : 0u, [PB_SPEC_WORLD] = plan.world ? 1u : 0u,
               [PB_SPEC_ALPHA] = plan.alpha ? 1u : 0u, [PB_SPEC_PRINCIPLED2] = plan.principled2 ? 1u : 0u},
      .normal_maps = plan.normal_maps ? 1u : 0u,
      .blender = plan.blender_materials ? 1u : 0u,
  };
  if (!reuse && ((r = pb_pass_gbuffer_create(g, &ps, &gp)) != PB_OK || (r = pb_pass_direct_create(g, &ps, &dp)) != PB_OK))
    goto fail;
  if (reuse) {
    /* The scene may have moved since the context was made. */
    if (tracer && (r = pb_tracer_update(g, tracer, s)) != PB_OK) goto fail;
    pb_estimator_update(est, s);
  } else if (photons_on) {
    if (!desc.photon_map) {
      pb_photon_trace_desc td = {.photons = desc.photons, .max_bounces = desc.photon_bounces, .smoothing = desc.smoothing > 0.0f ? desc.smoothing : PB_PHOTON_SMOOTHING_DEFAULT, .r_max = desc.r_max,
                                 .smoothing_caustic = desc.smoothing_caustic, .first_bounce = desc.first_bounce,
                                 .bandwidth_c0 = desc.bandwidth_c0, .caustic_share = desc.caustic_share};
      pb_tracer_desc trd = {.kind = desc.tracer, .photon = td,
                            .images = {.count = desc.image_maps, .resolution = desc.image_map_resolution}};
      if ((r = pb_tracer_create(g, s, gs, &trd, &tracer)) != PB_OK) goto fail;
    }
    if ((r = pb_estimator_create(g, s, &desc.estimator, &est)) != PB_OK) goto fail;
    /* Seed 003 sec. 6's up-sampling (upsample.h): the LBVH gather's; not
     * with normal maps (eq. 20's per-pixel photon directions). */
    if (desc.upsample_levels && !pb_estimator_can_upsample(est)) {
      r = pb_fail(PB_ERR_USAGE, "render: --upsample-levels needs --estimator lbvh (not %s)", pb_estimator_name(est));
      goto fail;
    }
    if (desc.upsample_levels && plan.normal_maps)
      pb_log_warn("render: --upsample-levels is off in scenes with normal maps (eq. 20 needs every pixel's photon "
                  "directions); the estimate runs at full resolution");
    else if (desc.upsample_levels && (r = pb_upsample_create(g, desc.upsample_levels, band_pixels, &ups)) != PB_OK)
      goto fail;
  }

  nmap_on = tg.nmap;
  /* The shading-correction AOVs leave the GPU where eq. 20 can use them. */
  int nmap_aovs = nmap_on && (s->features & PB_FEATURE_NORMAL_MAPS) && s->tangents && s->uvs;
  const pb_camera *cam = &s->cameras[camera];
  pb_gpu_frame fr;
  memset(&fr, 0, sizeof fr);
  if (desc.full_width) {
    pb_camera_view(cam, desc.full_width, desc.full_height, &fr.cam);
    fr.key_x0 = desc.crop_x, fr.key_y0 = desc.crop_y, fr.key_width = desc.full_width;
  } else {
    pb_camera_view(cam, width, height, &fr.cam);
  }
  fr.width = width;
  fr.height = height;
  fr.spp = spp;
  fr.light_count = gs->light_count;
  fr.emitter_count = (gs->features & PB_FEATURE_EMISSIVE) ? gs->emitter_count : 0;
  fr.max_specular_depth = max_spec;
  fr.seed_lo = (uint32_t)desc.seed;
  fr.seed_hi = (uint32_t)(desc.seed >> 32);
  fr.flags = (desc.direct_only ? PB_GPU_FRAME_DIRECT_ONLY : 0u) | (desc.jitter ? PB_GPU_FRAME_JITTER : 0u);
  float gr = desc.glossy_path_roughness == 0.0f ? PB_RENDER_GLOSSY_PATH_ROUGHNESS : fmaxf(desc.glossy_path_roughness, 0.0f);
  fr.glossy_path_alpha2 = gr * gr * gr * gr; /* alpha = roughness^2 */
  fr.tangent_base = gs->tangent_base;
  fr.uv1_base = gs->uv1_base;
  fr.color_base = gs->color_base;
  fr.principled2_base = gs->principled2_base;

  int ts = lim->timestamps;
  double gbuf_ms = 0, direct_ms = 0, gpu_ms = 0;
  /* After the resolve, on the GPU: the filter chain and eq. 20, for an image
   * in one band (the filters read neighbours). Several bands, and the host
   * resolve of the tests (PB_RESOLVE_ON_HOST=1, readback.h), filter the
   * read-back AOVs on the host instead: the former path, the reference. */
  const char *host_env = getenv("PB_RESOLVE_ON_HOST");
  int post_gpu = photons_on && bands == 1 && !(host_env && host_env[0] == '1');
  int chain_gpu = post_gpu && fc, sc_on = !desc.no_shading_correction && nmap_aovs;
  /* A still run's means on the GPU: after eq. 20, on the final planes of a
   * frame in one band (the host resolve of the tests: on the host). */
  int still_gpu = desc.still_sum && bands == 1 && !(host_env && host_env[0] == '1') &&
                  desc.still_sum->pixels == band_pixels;
  out->stats.still_on_gpu = still_gpu;
  /* Frames in flight (render.h): one band on the GPU path, with a context
   * to keep the tail in. The last submission then also copies the planes
   * into the readback ring and is not waited for. */
  int defer = desc.in_flight && ctx && bands == 1 && post_gpu && !own_fc;
  /* kept_slot: the context was zeroed above when reused (ctx->next_slot
   * then reads 0, and every frame took slot 0: the next frame's copy into
   * the slot raced the read of the frame before). */
  uint32_t ring_slot = defer ? kept_slot % PB_READBACK_RING : 0;
  if (defer && (r = pb_frame_targets_ring(g, &tg)) != PB_OK) goto fail;
  frame_tail ft;
  memset(&ft, 0, sizeof ft);
  uint64_t ring_kept = PB_RENDER_KEEP_ALL;
  /* Frames in flight: the previous frame's last submission may still run
   * now, while this frame's first command buffer is recorded (gpu.h
   * PB_GPU_FRAMES; render.h pb_render_stats.record_overlapped). */
  if (prev && prev->pending_slot < PB_READBACK_RING) {
    out->stats.record_overlapped = pb_gpu_outstanding(g, kept_tails[prev->pending_slot].gpu_sub);
    out->stats.record_running = pb_gpu_busy(g, kept_tails[prev->pending_slot].gpu_sub);
  }

  for (uint32_t band = 0; band < bands; ++band) {
    uint32_t row0 = band * band_rows;
    uint32_t rows = height - row0 < band_rows ? height - row0 : band_rows;
    uint32_t pixels = rows * width;
    fr.pixel_base = row0 * width;
    fr.pixel_count = pixels;
    if ((r = pb_gpu_buffer_upload(g, &tg.frame, 0, &fr, sizeof fr)) != PB_OK) goto fail;
    if ((r = pb_gpu_buffer_fill_zero(g, &tg.accum)) != PB_OK) goto fail;
    if (photons_on && (r = pb_gpu_buffer_fill_zero(g, &tg.paccum)) != PB_OK) goto fail;
    if (nmap_on && (r = pb_gpu_buffer_fill_zero(g, &tg.pnmap)) != PB_OK) goto fail;
    if (ups && (r = pb_upsample_reset(g, ups)) != PB_OK) goto fail;
    for (uint32_t it = 0; it < iters_run; ++it) {
    uint32_t s_begin = (uint32_t)((uint64_t)it * spp / iters), s_end = (uint32_t)((uint64_t)(it + 1) * spp / iters);
    if (photons_on && s_end > s_begin) {
      /* One photon map per iteration (seed, it): traced, the estimator's
       * build (the LBVH's), the estimator bound to this band's buffers.
       * Bands retrace the same maps. */
      const pb_photon_map *m = desc.photon_map;
      double ms = 0, build_ms = 0;
      pb_estimator_map_info mi = {.footprint_scale = footprint_scale(&desc, it)};
      if (!m) {
        /* The tracer's r_max is set when it is made or updated (photon.h). */
        mi.r_max = pb_tracer_r_max(tracer);
        /* The trace and the estimator's build in one submission, no host
         * round trip between them: the build reads the stored count from
         * the map's counts on the GPU and sizes its passes from it (lbvh.c);
         * the counts come back once, after both. */
        if ((r = pb_tracer_prepare(g, tracer, desc.seed, it, &map)) != PB_OK) goto fail;
        if ((r = pb_estimator_begin_map(g, est, &map, &mi)) != PB_OK) goto fail;
        if ((r = pb_gpu_begin(g)) != PB_OK) goto fail;
        double w0 = pb_time_now();
        r = pb_tracer_record(g, tracer, 0);
        if (r == PB_OK) r = pb_estimator_record_build(g, est, 2); /* slots 2..6 */
        pb_result rs = pb_gpu_submit(g);
        if (r == PB_OK) r = rs;
        if (r != PB_OK) goto fail;
        double wall_ms = (pb_time_now() - w0) * 1e3;
        if ((r = pb_tracer_finish(g, tracer, &map, 0, &ms)) != PB_OK) goto fail;
        pb_estimator_build_done(g, est, 2, &build_ms);
        if (ms < 0 || build_ms < 0) ms = wall_ms, build_ms = 0; /* no timestamps: all of it to the trace */
        if (band == 0) trace_ms += ms;
        photon_gpu_ms += ms;
        m = &map;
      }
      if (band == 0) stored_sum += m->stored, caustic_sum += m->caustic, out->stats.photons_emitted += m->emitted,
                     out->stats.photons_clamped += m->clamped;
      if (!desc.photon_map && band == 0) pb_tracer_stats_add(tracer, &out->stats);
      if (band == 0 && desc.radius_histogram && !desc.photon_map &&
          (r = pb_tracer_radius_histogram(g, tracer, m, &out->stats)) != PB_OK)
        goto fail;
      if (desc.photon_map) { /* a map made by the host: the build in its own submission */
        if ((r = pb_estimator_begin_map(g, est, m, &mi)) != PB_OK) goto fail;
        double w0 = pb_time_now();
        if ((r = pb_gpu_begin(g)) != PB_OK) goto fail;
        r = pb_estimator_record_build(g, est, 0);
        pb_result rs = pb_gpu_submit(g);
        if (r == PB_OK) r = rs;
        if (r != PB_OK) goto fail;
        pb_estimator_build_done(g, est, 0, &build_ms);
        if (build_ms < 0) build_ms = (pb_time_now() - w0) * 1e3; /* no timestamps: the wall time */
      }
      photon_gpu_ms += build_ms > 0 ? build_ms : 0;
      if (band == 0) {
        est_build_ms += build_ms;
        pb_estimator_stats_add(g, est, &out->stats);
      }
      if ((r = pb_estimator_bind(g, est, &ps, &tg.paccum, nmap_on ? &tg.pnmap : NULL)) != PB_OK) goto fail;
      if (ups && (r = pb_upsample_bind(g, ups, est, &ps, &tg.paccum, m->caustic > 0)) != PB_OK) goto fail;
    }
    for (uint32_t s0 = s_begin; s0 < s_end; s0 += SAMPLES_PER_SUBMIT) {
      uint32_t count = s_end - s0 < SAMPLES_PER_SUBMIT ? s_end - s0 : SAMPLES_PER_SUBMIT;
      if ((r = pb_gpu_begin(g)) != PB_OK) goto fail;
      pb_gpu_timestamp(g, 0);
      for (uint32_t k = 0; k < count && r == PB_OK; ++k) {
        r = pb_pass_record(g, &gp, s0 + k, pixels);
        pb_gpu_barrier(g);
        pb_gpu_timestamp(g, 3 * k + 1);
        if (r == PB_OK) r = pb_pass_record(g, &dp, s0 + k, pixels);
        pb_gpu_barrier(g);
        pb_gpu_timestamp(g, 3 * k + 2);
        if (photons_on && r == PB_OK)
          r = ups ? pb_upsample_record(g, ups, est, s0 + k, width, pixels, 0) : pb_estimator_record(g, est, s0 + k, pixels, 0);
        pb_gpu_barrier(g);
        pb_gpu_timestamp(g, 3 * k + 3);
      }
      double t0 = pb_time_now();
      pb_result rs = pb_gpu_submit(g);
      double wall = (pb_time_now() - t0) * 1e3;
      if (r == PB_OK) r = rs;
      if (r != PB_OK) goto fail;
      if (ts) {
        for (uint32_t k = 0; k < count; ++k) {
          double a = pb_gpu_elapsed_ms(g, 3 * k, 3 * k + 1), b = pb_gpu_elapsed_ms(g, 3 * k + 1, 3 * k + 2);
          double c = pb_gpu_elapsed_ms(g, 3 * k + 2, 3 * k + 3);
          if (a < 0 || b < 0 || c < 0) ts = 0;
          gbuf_ms += a;
          direct_ms += b;
          gather_ms += c;
        }
        double all = pb_gpu_elapsed_ms(g, 0, 3 * count);
        gpu_ms += all > 0 ? all : 0;
      } else {
        gpu_ms += wall;
      }
    }
    if (band == 0 && (r = iteration_done(g, &desc, &tg, &preview, it, iters, s_end, spp, width, height,
                                         bands, wall0, &iters_run)) != PB_OK)
      goto fail;
    }
    spp_run = (uint32_t)((uint64_t)iters_run * spp / iters); /* all of spp without a time limit */
    /* The resolve (resolve.h), the filter chain and eq. 20 on the GPU in one
     * submission, then the band's AOVs to the host: the readback
     * (readback.h) is where pixels leave the GPU. Timestamps: 0 start, 1
     * resolved, the chain's from 1 (filters.c), the last after eq. 20. */
    if (band == 0 && prev) {
      /* The previous frame in flight is settled before this submission
       * overwrites what its settle reads (the guard, the k_PD sums, the
       * temporal counts; its timestamps are in its own context). */
      double p0 = pb_time_now();
      pb_gpu_transfers q0 = pb_gpu_transfers_get(g);
      if (prev->pending_slot >= PB_READBACK_RING) {
        r = pb_fail(PB_ERR_INTERNAL, "render: no frame in flight to settle");
        goto fail;
      }
      if ((r = settle_tail(g, &tg, &kept_tails[prev->pending_slot], prev)) != PB_OK) goto fail;
      pb_gpu_transfers q1 = pb_gpu_transfers_get(g);
      wall0 += pb_time_now() - p0; /* its host time, not this frame's */
      tr0.upload_bytes += q1.upload_bytes - q0.upload_bytes;
      tr0.download_bytes += q1.download_bytes - q0.download_bytes;
      tr0.readback_bytes += q1.readback_bytes - q0.readback_bytes;
    }
    if (defer) {
      /* The samples' statistics now, before the last submission: the next
       * frame's work follows it (render.h settle_first). */
      ft.photons_on = photons_on, ft.est = est, ft.ups = ups;
      estimator_final(g, &ft, &out->stats);
    }
    /* The resolve's counters, zeroed for the frame just before its first
     * band's resolve (only the resolve writes them). */
    if (band == 0 && ((r = pb_gpu_buffer_fill_zero(g, &tg.guard)) != PB_OK ||
                      (r = pb_gpu_buffer_fill_zero(g, &tg.kpd)) != PB_OK))
      goto fail;
    if (chain_gpu && (r = pb_filter_chain_bind(g, fc, &tg, nmap_aovs)) != PB_OK) goto fail;
    if (still_gpu && (r = pb_still_sum_bind(g, desc.still_sum, &tg)) != PB_OK) goto fail;
    if ((r = pb_gpu_begin(g)) != PB_OK) goto fail;
    pb_gpu_timestamp(g, 0);
    float inv_spp = 1.0f / (float)spp_run;
    r = pb_resolve_record(g, &rp, &tg, pixels, inv_spp, s->film_opaque);
    pb_gpu_barrier(g);
    pb_gpu_timestamp(g, 1);
    uint32_t slot = 1, sc_slot;
    if (chain_gpu && r == PB_OK) r = pb_filter_chain_record(g, fc, pixels, &slot);
    sc_slot = slot;
    if (post_gpu && sc_on && r == PB_OK) { /* eq. 20 on the filtered indirect */
      r = pb_shading_correction_record(g, &scp, pixels, PB_SHADING_CORRECTION_S_MAX);
      pb_gpu_barrier(g);
    }
    if (still_gpu && r == PB_OK) { /* a still run's running means (targets.h pb_still_sum) */
      r = pb_still_sum_record(g, desc.still_sum, &tg, pixels);
      pb_gpu_barrier(g);
    }
    pb_gpu_timestamp(g, ++slot);
    if (defer) { /* after the last timestamp: the download is not a pass */
      pb_gpu_barrier(g);
      ring_kept = pb_readback_ring_record(g, &tg, ring_slot, pixels, readback, desc.keep_planes,
                                          &out->stats.ring_bytes);
    }
    pb_result rs = defer ? pb_gpu_submit_async(g) : pb_gpu_submit(g);
    if (r == PB_OK) r = rs;
    if (r != PB_OK) goto fail;
    ft.gpu_sub = pb_gpu_last_submission(g);
    ft.ts = ts, ft.chain_gpu = chain_gpu, ft.fc = fc, ft.sc_slot = sc_slot, ft.slot = slot;
    ft.gpu_ms = gpu_ms;
    if (defer) break; /* one band: frame_settle and frame_read finish it */
    if ((r = tail_band_times(g, &ft, out)) != PB_OK) goto fail;
    gpu_ms = ft.gpu_ms;
    if ((r = pb_readback_band(g, &tg, readback, pixels, fr.pixel_base, n, inv_spp, s->film_opaque, nmap_aovs, out, &k_sum,
                              &hit_sum)) != PB_OK) goto fail;
  }
  out->width = width;
  out->height = height;
  ft.ts = ts, ft.chain_gpu = chain_gpu, ft.post_gpu = post_gpu, ft.photons_on = photons_on;
  ft.nmap_aovs = nmap_aovs, ft.opaque = s->film_opaque, ft.no_shading_correction = desc.no_shading_correction;
  ft.readback = readback;
  out->stats.readback_mode = readback;
  if (ctx && bands == 1 && !host_resolve) { /* the planes stay on the GPU (render.h pb_render_gpu_planes) */
    out->gpu.planes = defer ? &ctx->tg.ring[ring_slot][0] : &ctx->tg.planes;
    out->gpu.pplanes = !tg.photons ? NULL : defer ? &ctx->tg.ring[ring_slot][1] : &ctx->tg.pplanes;
    out->gpu.pixels = (uint32_t)n, out->gpu.channels = tg.channels;
    out->gpu.kept = defer ? ring_kept : PB_RENDER_KEEP_ALL;
    out->gpu.photons = tg.photons, out->gpu.nmap = tg.nmap, out->gpu.nmap_aovs = nmap_aovs;
  }
  ft.pixels = (uint32_t)n, ft.spp_run = spp_run, ft.iters_run = iters_run, ft.emitter_count = fr.emitter_count;
  ft.ring_slot = ring_slot, ft.pixel_base = 0, ft.n = n, ft.inv_spp = 1.0f / (float)spp_run;
  ft.gpu_ms = gpu_ms, ft.gbuf_ms = gbuf_ms, ft.direct_ms = direct_ms, ft.gather_ms = gather_ms;
  ft.photon_gpu_ms = photon_gpu_ms, ft.trace_ms = trace_ms, ft.est_build_ms = est_build_ms;
  ft.k_sum = k_sum, ft.hit_sum = hit_sum, ft.wall0 = wall0, ft.stored_sum = stored_sum, ft.caustic_sum = caustic_sum;
  ft.tr0 = tr0, ft.fc = fc, ft.est = est, ft.ups = ups, ft.gs = gs;
  if (defer) {
    ft.host_ms = (pb_time_now() - wall0) * 1e3;
    ft.tr_submit = pb_gpu_transfers_get(g);
    ctx->tail[ring_slot] = ft;
    out->pending = 1;
    out->pending_slot = ring_slot;
    out->stats.in_flight = 1;
  } else if ((r = tail_frame(g, &tg, &ft, out)) != PB_OK) {
    goto fail;
  }
  free(preview.beauty);
  pb_filter_chain_destroy(g, own_fc);
  if (ctx) { /* kept for the next frame */
    for (uint32_t i = 0; i < PB_READBACK_RING; ++i)
      if (!defer || i != ring_slot) ctx->tail[i] = kept_tails[i];
    ctx->next_slot = defer ? ring_slot + 1 : kept_slot;
    ctx->tg = tg;
    ctx->gp = gp, ctx->dp = dp, ctx->rp = rp, ctx->scp = scp;
    ctx->tracer = tracer, ctx->est = est, ctx->ups = ups, ctx->map = map;
    ctx->key = key;
    ctx->valid = 1;
    return PB_OK;
  }
  pb_photon_map_destroy(g, &map);
  pb_estimator_destroy(g, est);
  pb_upsample_destroy(g, ups);
  pb_tracer_destroy(g, tracer);
  pb_gpu_pipeline_destroy(g, &gp);
  pb_gpu_pipeline_destroy(g, &dp);
  pb_gpu_pipeline_destroy(g, &rp);
  pb_gpu_pipeline_destroy(g, &scp);
  pb_frame_targets_destroy(g, &tg);
  return PB_OK;
fail:
  free(preview.beauty);
  pb_filter_chain_destroy(g, own_fc);
  pb_gpu_pipeline_destroy(g, &scp);
  pb_photon_map_destroy(g, &map);
  pb_estimator_destroy(g, est);
  pb_upsample_destroy(g, ups);
  pb_tracer_destroy(g, tracer);
  pb_gpu_pipeline_destroy(g, &gp);
  pb_gpu_pipeline_destroy(g, &dp);
  pb_gpu_pipeline_destroy(g, &rp);
  pb_frame_targets_destroy(g, &tg);
  pb_render_result_destroy(out);
  return r;
}
