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
#include "render/estimate/estimator.h"
#include "render/scene/passes.h"
#include "render/photon/photon.h"
#include "render/photon/tracer.h"
#include "render/estimate/upsample.h"
#include "render/frame/plan.h"
#include "render/frame/noise.h"
#include "render/frame/readback.h"
#include "render/frame/resolve.h"
#include "render/frame/targets.h"
#include "render/filter/filters.h"
#include "render/estimate/shading_correction.h"
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

/* What a frame's last submission leaves to do once the GPU has run it
 * (frame_settle, frame_read): everything pb_render_frame knew at that
 * submission and its finish needs. The frame accumulates its statistics
 * here as it runs (frame_run.ft); a frame in flight keeps it in its
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

/* Every GPU resource a frame owns, made from its shape (plan.h
 * pb_frame_shape) alone and released by context_clear alone: kept by the
 * caller between the frames of a sequence (pb_render_io.context), or the
 * call's own for one frame. */
struct pb_frame_context {
  int valid;
  pb_frame_shape key;                /* what the resources were made from */
  frame_tail tail[PB_READBACK_RING]; /* frames in flight, by ring slot */
  uint32_t next_slot;                /* the ring slot of the next frame in flight */
  pb_frame_targets tg;
  pb_pass_setup ps;                  /* the scene passes' bindings (into tg) and constants */
  pb_gpu_pipeline gp, dp, rp, scp;   /* G-buffer, direct, resolve, eq. 20 */
  pb_tracer *tracer;
  pb_estimator *est;
  pb_upsample *ups;
  pb_photon_map map;
};

pb_result pb_frame_context_create(pb_frame_context **out) {
  *out = calloc(1, sizeof **out);
  return *out ? PB_OK : pb_fail(PB_ERR_NOMEM, "render: out of memory");
}

/* The one release of a context's resources (each destroy accepts what was
 * never made); leaves it zeroed, not valid. */
static void context_clear(pb_gpu *g, pb_frame_context *c) {
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

/* The scene passes' setup: the scene's buffers and the frame's targets,
 * the scene plan's specialization constants. */
static void pass_setup(const pb_gpu_scene *gs, const pb_render_plan *plan, pb_frame_targets *tg, pb_pass_setup *ps) {
  *ps = (pb_pass_setup){
      .bindings = {[PB_BIND_FRAME] = &tg->frame, [PB_BIND_NODES] = &gs->nodes, [PB_BIND_TRIS] = &gs->tris,
                   [PB_BIND_INDICES] = &gs->indices, [PB_BIND_NORMALS] = &gs->normals, [PB_BIND_UVS] = &gs->uvs,
                   [PB_BIND_TRI_MATERIAL] = &gs->tri_material, [PB_BIND_MATERIALS] = &gs->materials,
                   [PB_BIND_TEXTURES] = &gs->textures, [PB_BIND_TEXELS] = &gs->texels, [PB_BIND_LIGHTS] = &gs->lights,
                   [PB_BIND_GBUFFER] = &tg->gbuf, [PB_BIND_ACCUM] = &tg->accum, [PB_BIND_POSITIONS] = &gs->positions,
                   [PB_BIND_EMITTERS] = &gs->emitters, [PB_BIND_WORLD] = &gs->world},
      .spec = {[PB_SPEC_HAS_NORMALS] = plan->vertex_normals ? 1u : 0u, [PB_SPEC_TEXTURES] = plan->textures ? 1u : 0u,
               [PB_SPEC_SPECULAR] = plan->eye_chains ? 1u : 0u,
               [PB_SPEC_EMISSIVE] = plan->emitter_sampling || plan->unlit ? 1u : 0u,
               [PB_SPEC_SOFT_LIGHTS] = plan->soft_lights ? 1u : 0u, [PB_SPEC_WORLD] = plan->world ? 1u : 0u,
               [PB_SPEC_ALPHA] = plan->alpha ? 1u : 0u, [PB_SPEC_PRINCIPLED2] = plan->principled2 ? 1u : 0u,
               [PB_SPEC_CLOSURES] = plan->closures},
      .normal_maps = plan->normal_maps ? 1u : 0u,
      .blender = plan->blender_materials ? 1u : 0u,
      .accel = pb_gpu_scene_accel(gs),
  };
}

/* Makes every resource of shape `sh` in the zeroed context c (valid and
 * keyed first, so that a failure part-way leaves context_clear the rest). */
static pb_result context_build(pb_gpu *g, const pb_scene *s, const pb_frame_shape *sh, pb_frame_context *c) {
  c->valid = 1;
  c->key = *sh;
  pb_result r;
  if ((r = pb_frame_targets_create(g, sh->band_pixels, sh->photons, sh->scene.normal_maps, &c->tg)) != PB_OK ||
      (r = pb_resolve_create(g, &c->tg, &c->rp)) != PB_OK ||
      (c->tg.nmap && (r = pb_shading_correction_create(g, &c->tg, &c->scp)) != PB_OK))
    return r;
  pass_setup(sh->gs, &sh->scene, &c->tg, &c->ps);
  if ((r = pb_pass_gbuffer_create(g, &c->ps, &c->gp)) != PB_OK || (r = pb_pass_direct_create(g, &c->ps, &c->dp)) != PB_OK)
    return r;
  if (!sh->photons) return PB_OK;
  if (!sh->photon_map && (r = pb_tracer_create(g, s, sh->gs, &sh->tracer, &c->tracer)) != PB_OK) return r;
  if ((r = pb_estimator_create(g, s, &sh->estimator, &c->est)) != PB_OK) return r;
  /* Seed 003 sec. 6's up-sampling (upsample.h): the LBVH gather's; not
   * with normal maps (eq. 20's per-pixel photon directions). */
  if (sh->upsample_levels && !pb_estimator_can_upsample(c->est))
    return pb_fail(PB_ERR_USAGE, "render: --upsample-levels needs --estimator lbvh (not %s)", pb_estimator_name(c->est));
  if (sh->upsample_levels && sh->scene.normal_maps)
    pb_log_warn("render: --upsample-levels is off in scenes with normal maps (eq. 20 needs every pixel's photon "
                "directions); the estimate runs at full resolution");
  else if (sh->upsample_levels && (r = pb_upsample_create(g, sh->upsample_levels, sh->band_pixels, &c->ups)) != PB_OK)
    return r;
  return PB_OK;
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

double pb_render_image_miss_rate(const pb_render_stats *st) {
  double segments = -1, misses = -1;
  for (uint32_t i = 0; i < st->tracer_stat_count; ++i) {
    if (!strcmp(st->tracer_stats[i].name, "image_segments")) segments = st->tracer_stats[i].value;
    if (!strcmp(st->tracer_stats[i].name, "image_misses")) misses = st->tracer_stats[i].value;
  }
  return segments > 0 && misses >= 0 ? misses / segments : -1.0;
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

/* The preview's host copy of the mean beauty (iteration_done). */
typedef struct preview_state {
  float *beauty;
  double last_s;
  pb_noise_tracker noise;   /* the noise threshold's estimate */
  uint32_t noise_next;      /* the iteration count of its next check */
  int stop;                 /* PB_RENDER_STOP_* */
} preview_state;


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

/* ---- the frame: one call per stage ------------------------------------------ */

/* One call of pb_render_frame: its plan, its context, and what it owns
 * besides (released by run_end alone). */
typedef struct frame_run {
  pb_gpu *g;
  const pb_scene *s;
  const pb_render_desc *d;
  const pb_render_io *io;
  pb_render_result *out;
  pb_frame_plan p;
  pb_frame_context *c;         /* io's context, or `own` */
  pb_frame_context own;        /* the call's own context (no io.context) */
  int reuse;                   /* c was made by an earlier frame of this shape */
  pb_filter_chain *fc, *own_fc;/* the indirect light's filters; the call's own */
  preview_state preview;
  frame_tail ft;               /* the statistics as they accumulate; the tail */
  pb_render_result *prev;      /* the previous frame in flight, until settled */
  uint32_t kept_slot;          /* the context's next ring slot at the start */
  uint32_t ring_slot;          /* frames in flight: this frame's ring slot */
  uint64_t ring_kept;          /* ... and the planes it keeps there */
} frame_run;

/* The noise threshold after iteration `it` (samples [0, s_end) in band
 * 0's accumulators): a check when one is due (noise.h's schedule, and
 * after the last planned map), lowering *iters_run to it + 1 once the
 * estimate is at or below the threshold. */
static pb_result noise_check(frame_run *run, uint32_t it, uint32_t s_end) {
  preview_state *pv = &run->preview;
  uint32_t *iters_run = &run->ft.iters_run;
  if (!(run->d->noise_threshold > 0) || s_end == 0 || (it + 1 != pv->noise_next && it + 1 != *iters_run))
    return PB_OK;
  size_t n = (size_t)pv->noise.width * pv->noise.height;
  if (!pv->beauty && !(pv->beauty = malloc(4 * run->p.pixels * sizeof(float))))
    return pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u noise estimate", pv->noise.width,
                   pv->noise.height);
  pb_result r = pb_readback_preview(run->g, &run->c->tg, n, s_end, pv->beauty);
  if (r == PB_OK) r = pb_noise_tracker_check(&pv->noise, pv->beauty, s_end);
  if (r != PB_OK) return r;
  if (pv->noise.estimate >= 0 && pv->noise.estimate <= run->d->noise_threshold && it + 1 < *iters_run) {
    *iters_run = it + 1;
    pv->stop = PB_RENDER_STOP_NOISE;
  }
  pv->noise_next = pb_noise_tracker_next(&pv->noise, run->d->noise_threshold, it + 1, *iters_run);
  return PB_OK;
}

/* Progress, the time limit and the noise threshold, after iteration `it`
 * of band 0 finished (samples [0, s_end) of every pixel of the band are in
 * `accum`). Calls io->progress, with the mean beauty so far when
 * desc->preview_interval_s allows one (the whole image in one band, not the
 * last iteration: its beauty is the result, and at most one per interval);
 * lowers *iters_run to it + 1 once desc->time_limit_s has passed or the
 * noise estimate reached desc->noise_threshold. */
static pb_result iteration_done(frame_run *run, uint32_t it, uint32_t s_end) {
  const pb_render_desc *d = run->d;
  const pb_frame_plan *p = &run->p;
  preview_state *pv = &run->preview;
  uint32_t *iters_run = &run->ft.iters_run, width = p->shape.width, height = p->shape.height;
  double now = pb_time_now(), t0 = run->ft.wall0;
  if (d->time_limit_s > 0 && now - t0 >= d->time_limit_s && it + 1 < *iters_run) {
    *iters_run = it + 1;
    pv->stop = PB_RENDER_STOP_TIME_LIMIT;
  }
  pb_result r = noise_check(run, it, s_end);
  if (r != PB_OK || !run->io->progress) return r;
  pb_render_progress pr = {.iteration = it + 1, .iterations = *iters_run, .samples = s_end,
                           .spp = (uint32_t)((uint64_t)*iters_run * p->spp / p->iters), .elapsed_s = now - t0,
                           .width = width, .height = height, .noise = pv->noise.estimate};
  size_t n = p->pixels;
  if (d->preview_interval_s >= 0 && p->bands == 1 && it + 1 < *iters_run && s_end > 0 &&
      (pv->last_s == 0 || now - pv->last_s >= d->preview_interval_s)) {
    if (!pv->beauty && !(pv->beauty = malloc(4 * n * sizeof(float))))
      return pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u preview", width, height);
    if ((r = pb_readback_preview(run->g, &run->c->tg, n, s_end, pv->beauty)) != PB_OK) return r;
    pr.beauty = pv->beauty;
    pv->last_s = now;
  }
  return run->io->progress(run->io->progress_user, &pr);
}

static void run_begin(frame_run *run, pb_gpu *g, const pb_scene *s, const pb_render_desc *d, const pb_render_io *io,
                      pb_render_result *out) {
  run->g = g, run->s = s, run->d = d, run->io = io, run->out = out;
  /* A context from the previous frame of a sequence: reused when it
   * matches, cleared on a failure. */
  run->c = io->context ? io->context : &run->own;
  run->reuse = run->c->valid && !memcmp(&run->c->key, &run->p.shape, sizeof run->p.shape);
  run->kept_slot = run->c->next_slot;
  /* The previous frame in flight (pb_render_io.settle_first). */
  run->prev = io->settle_first && io->settle_first->pending && io->context ? io->settle_first : NULL;
  run->fc = io->filters;
  run->ring_kept = PB_RENDER_KEEP_ALL;
  frame_tail *ft = &run->ft;
  ft->wall0 = pb_time_now();
  ft->tr0 = pb_gpu_transfers_get(g);
  ft->ts = pb_gpu_get_limits(g)->timestamps;
  ft->iters_run = run->p.iters, ft->spp_run = run->p.spp;
  ft->gs = run->p.shape.gs;
  uint32_t rows0 = run->p.band_rows < run->p.shape.height ? run->p.band_rows : run->p.shape.height;
  pb_noise_tracker_init(&run->preview.noise, run->p.shape.width, rows0);
  run->preview.noise_next = 1;
}

/* The one clean-up path: what the call owns, and on a failure the context
 * and the result too. */
static pb_result run_end(frame_run *run, pb_result r) {
  free(run->preview.beauty);
  pb_noise_tracker_free(&run->preview.noise);
  pb_filter_chain_destroy(run->g, run->own_fc);
  if (r != PB_OK || run->c == &run->own) context_clear(run->g, run->c);
  if (r != PB_OK) pb_render_result_destroy(run->out);
  return r;
}

/* The context for this frame: reused (updated to the scene's new pose), or
 * made afresh, after the previous frame in flight finished with the old
 * one. */
static pb_result context_acquire(frame_run *run) {
  pb_gpu *g = run->g;
  pb_frame_context *c = run->c;
  pb_result r;
  if (run->reuse) { /* the scene may have moved since the context was made */
    if (c->tracer && (r = pb_tracer_update(g, c->tracer, run->s)) != PB_OK) return r;
    pb_estimator_update(c->est, run->s);
    return PB_OK;
  }
  if (run->prev) {
    double p0 = pb_time_now();
    if ((r = pb_render_frame_complete(g, c, run->prev)) != PB_OK) return r;
    run->ft.wall0 += pb_time_now() - p0; /* its time, not this frame's */
    run->ft.tr0 = pb_gpu_transfers_get(g);
    run->prev = NULL;
  }
  context_clear(g, c);
  return context_build(g, run->s, &run->p.shape, c);
}

/* The result's arrays: those the readback brings. */
static pb_result result_alloc(const pb_frame_plan *p, uint32_t width, uint32_t height, pb_render_result *out) {
  size_t n = p->pixels;
  int read_all = p->readback == PB_RENDER_READBACK_ALL;
  if (read_all || p->readback == PB_RENDER_READBACK_BEAUTY) out->beauty = calloc(4 * n, sizeof(float));
  if (read_all) {
    out->direct = calloc(3 * n, sizeof(float));
    out->albedo = calloc(3 * n, sizeof(float));
    out->normal = calloc(3 * n, sizeof(float));
    out->depth = calloc(n, sizeof(float));
    out->material = calloc(n, sizeof(float));
    out->emission = calloc(3 * n, sizeof(float));
    if (p->photons) {
      out->indirect = calloc(3 * n, sizeof(float));
      out->caustic = calloc(3 * n, sizeof(float));
    }
  }
  if ((p->readback != PB_RENDER_READBACK_STATS && !out->beauty) ||
      (read_all && (!out->direct || !out->albedo || !out->normal || !out->depth || !out->material || !out->emission ||
                    (p->photons && (!out->indirect || !out->caustic)))))
    return pb_fail(PB_ERR_NOMEM, "render: out of memory for a %ux%u image", width, height);
  return PB_OK;
}

/* Everything before the first band: the context, the result's arrays, the
 * call's own filter chain, the readback ring slot. */
static pb_result frame_prepare(frame_run *run) {
  const pb_frame_plan *p = &run->p;
  const pb_render_desc *d = run->d;
  pb_gpu *g = run->g;
  pb_result r;
  if ((r = context_acquire(run)) != PB_OK) return r;
  if ((r = result_alloc(p, p->shape.width, p->shape.height, run->out)) != PB_OK) return r;
  if (p->own_chain) {
    pb_filter_chain_desc cd = {.atrous_iterations = d->atrous_iterations, .atrous_gamma = d->atrous_gamma};
    if ((r = pb_filter_chain_create(g, p->shape.width, p->shape.height, &cd, &run->own_fc)) != PB_OK) return r;
    run->fc = run->own_fc;
  }
  frame_tail *ft = &run->ft;
  ft->chain_gpu = p->chain_gpu, ft->post_gpu = p->post_gpu, ft->photons_on = p->photons;
  ft->nmap_aovs = p->nmap_aovs, ft->opaque = run->s->film_opaque, ft->no_shading_correction = d->no_shading_correction;
  ft->readback = p->readback, ft->emitter_count = p->frame.emitter_count;
  ft->fc = run->fc, ft->est = run->c->est, ft->ups = run->c->ups;
  run->out->stats.still_on_gpu = p->still_gpu;
  /* kept_slot: read before the context was cleared (a rebuilt context
   * keeps the ring's order: the next frame's copy into a slot must not
   * race the read of the frame before). */
  run->ring_slot = p->defer ? run->kept_slot % PB_READBACK_RING : 0;
  if (p->defer && (r = pb_frame_targets_ring(g, &run->c->tg)) != PB_OK) return r;
  /* Frames in flight: the previous frame's last submission may still run
   * now, while this frame's first command buffer is recorded (gpu.h
   * PB_GPU_FRAMES; render.h pb_render_stats.record_overlapped). */
  if (run->prev && run->prev->pending_slot < PB_READBACK_RING) {
    run->out->stats.record_overlapped = pb_gpu_outstanding(g, run->c->tail[run->prev->pending_slot].gpu_sub);
    run->out->stats.record_running = pb_gpu_busy(g, run->c->tail[run->prev->pending_slot].gpu_sub);
  }
  return PB_OK;
}

/* Stage 1, iteration `it` of `band`: the photon map (seed, it), traced and
 * the estimator's build (the LBVH's), the estimator bound to the band's
 * buffers. Bands retrace the same maps. */
static pb_result record_photon_map(frame_run *run, uint32_t band, uint32_t it) {
  pb_gpu *g = run->g;
  pb_frame_context *c = run->c;
  const pb_render_desc *d = run->d;
  pb_render_stats *st = &run->out->stats;
  frame_tail *ft = &run->ft;
  pb_result r;
  const pb_photon_map *m = run->io->photon_map;
  double ms = 0, build_ms = 0;
  pb_estimator_map_info mi = {.footprint_scale = footprint_scale(d, it)};
  if (!m) {
    /* The tracer's r_max is set when it is made or updated (photon.h). */
    mi.r_max = pb_tracer_r_max(c->tracer);
    /* The trace and the estimator's build in one submission, no host round
     * trip between them: the build reads the stored count from the map's
     * counts on the GPU and sizes its passes from it (lbvh.c); the counts
     * come back once, after both. */
    if ((r = pb_tracer_prepare(g, c->tracer, d->seed, it, &c->map)) != PB_OK) return r;
    if ((r = pb_estimator_begin_map(g, c->est, &c->map, &mi)) != PB_OK) return r;
    if ((r = pb_gpu_begin(g)) != PB_OK) return r;
    double w0 = pb_time_now();
    r = pb_tracer_record(g, c->tracer, 0);
    if (r == PB_OK) r = pb_estimator_record_build(g, c->est, 2); /* slots 2..6 */
    pb_result rs = pb_gpu_submit(g);
    if (r == PB_OK) r = rs;
    if (r != PB_OK) return r;
    double wall_ms = (pb_time_now() - w0) * 1e3;
    if ((r = pb_tracer_finish(g, c->tracer, &c->map, 0, &ms)) != PB_OK) return r;
    pb_estimator_build_done(g, c->est, 2, &build_ms);
    if (ms < 0 || build_ms < 0) ms = wall_ms, build_ms = 0; /* no timestamps: all of it to the trace */
    if (band == 0) ft->trace_ms += ms;
    ft->photon_gpu_ms += ms;
    m = &c->map;
  }
  if (band == 0) {
    ft->stored_sum += m->stored, ft->caustic_sum += m->caustic;
    st->photons_emitted += m->emitted, st->photons_clamped += m->clamped;
  }
  if (!run->io->photon_map && band == 0) pb_tracer_stats_add(c->tracer, st);
  if (band == 0 && d->radius_histogram && !run->io->photon_map &&
      (r = pb_tracer_radius_histogram(g, c->tracer, m, st)) != PB_OK)
    return r;
  if (run->io->photon_map) { /* a map made by the host: the build in its own submission */
    if ((r = pb_estimator_begin_map(g, c->est, m, &mi)) != PB_OK) return r;
    double w0 = pb_time_now();
    if ((r = pb_gpu_begin(g)) != PB_OK) return r;
    r = pb_estimator_record_build(g, c->est, 0);
    pb_result rs = pb_gpu_submit(g);
    if (r == PB_OK) r = rs;
    if (r != PB_OK) return r;
    pb_estimator_build_done(g, c->est, 0, &build_ms);
    if (build_ms < 0) build_ms = (pb_time_now() - w0) * 1e3; /* no timestamps: the wall time */
  }
  ft->photon_gpu_ms += build_ms > 0 ? build_ms : 0;
  if (band == 0) {
    ft->est_build_ms += build_ms;
    pb_estimator_stats_add(g, c->est, st);
  }
  if ((r = pb_estimator_bind(g, c->est, &c->ps, &c->tg.paccum, c->tg.nmap ? &c->tg.pnmap : NULL)) != PB_OK) return r;
  if (c->ups && (r = pb_upsample_bind(g, c->ups, c->est, &c->ps, &c->tg.paccum, m->caustic > 0)) != PB_OK) return r;
  return PB_OK;
}

/* Stage 2: samples [s_begin, s_end) of every pixel of the band: G-buffer,
 * direct light and the photon estimate per sample, SAMPLES_PER_SUBMIT to a
 * submission, timed by timestamps (or the submission's wall time). */
static pb_result record_camera_samples(frame_run *run, uint32_t s_begin, uint32_t s_end, uint32_t pixels) {
  pb_gpu *g = run->g;
  pb_frame_context *c = run->c;
  frame_tail *ft = &run->ft;
  int photons_on = run->p.photons;
  pb_result r;
  for (uint32_t s0 = s_begin; s0 < s_end; s0 += SAMPLES_PER_SUBMIT) {
    uint32_t count = s_end - s0 < SAMPLES_PER_SUBMIT ? s_end - s0 : SAMPLES_PER_SUBMIT;
    if ((r = pb_gpu_begin(g)) != PB_OK) return r;
    pb_gpu_timestamp(g, 0);
    for (uint32_t k = 0; k < count && r == PB_OK; ++k) {
      r = pb_pass_record(g, &c->gp, s0 + k, pixels);
      pb_gpu_barrier(g);
      pb_gpu_timestamp(g, 3 * k + 1);
      if (r == PB_OK) r = pb_pass_record(g, &c->dp, s0 + k, pixels);
      pb_gpu_barrier(g);
      pb_gpu_timestamp(g, 3 * k + 2);
      if (photons_on && r == PB_OK)
        r = c->ups ? pb_upsample_record(g, c->ups, c->est, s0 + k, run->p.shape.width, pixels, 0)
                   : pb_estimator_record(g, c->est, s0 + k, pixels, 0);
      pb_gpu_barrier(g);
      pb_gpu_timestamp(g, 3 * k + 3);
    }
    double t0 = pb_time_now();
    pb_result rs = pb_gpu_submit(g);
    double wall = (pb_time_now() - t0) * 1e3;
    if (r == PB_OK) r = rs;
    if (r != PB_OK) return r;
    if (ft->ts) {
      for (uint32_t k = 0; k < count; ++k) {
        double a = pb_gpu_elapsed_ms(g, 3 * k, 3 * k + 1), b = pb_gpu_elapsed_ms(g, 3 * k + 1, 3 * k + 2);
        double cc = pb_gpu_elapsed_ms(g, 3 * k + 2, 3 * k + 3);
        if (a < 0 || b < 0 || cc < 0) ft->ts = 0;
        ft->gbuf_ms += a;
        ft->direct_ms += b;
        ft->gather_ms += cc;
      }
      double all = pb_gpu_elapsed_ms(g, 0, 3 * count);
      ft->gpu_ms += all > 0 ? all : 0;
    } else {
      ft->gpu_ms += wall;
    }
  }
  return PB_OK;
}

/* Band 0, before the tail's submission: the previous frame in flight is
 * settled before it overwrites what that settle reads (the guard, the k_PD
 * sums, the temporal counts; its timestamps are in its own context). */
static pb_result settle_previous(frame_run *run) {
  pb_gpu *g = run->g;
  pb_render_result *prev = run->prev;
  double p0 = pb_time_now();
  pb_gpu_transfers q0 = pb_gpu_transfers_get(g);
  if (prev->pending_slot >= PB_READBACK_RING) return pb_fail(PB_ERR_INTERNAL, "render: no frame in flight to settle");
  pb_result r = settle_tail(g, &run->c->tg, &run->c->tail[prev->pending_slot], prev);
  if (r != PB_OK) return r;
  pb_gpu_transfers q1 = pb_gpu_transfers_get(g);
  pb_gpu_transfers *tr0 = &run->ft.tr0;
  run->ft.wall0 += pb_time_now() - p0; /* its host time, not this frame's */
  tr0->upload_bytes += q1.upload_bytes - q0.upload_bytes;
  tr0->download_bytes += q1.download_bytes - q0.download_bytes;
  tr0->readback_bytes += q1.readback_bytes - q0.readback_bytes;
  return PB_OK;
}

/* Stage 3, the band's tail: the resolve (resolve.h), the filter chain and
 * eq. 20 on the GPU, a still run's means, and for a frame in flight the
 * copy into the readback ring, in one submission (not waited for in
 * flight). Timestamps: 0 start, 1 resolved, the chain's from 1
 * (filters.c), the last after eq. 20. */
static pb_result record_tail(frame_run *run, uint32_t band, uint32_t pixels) {
  pb_gpu *g = run->g;
  pb_frame_context *c = run->c;
  const pb_frame_plan *p = &run->p;
  frame_tail *ft = &run->ft;
  pb_result r;
  if (band == 0 && run->prev && (r = settle_previous(run)) != PB_OK) return r;
  /* The samples' statistics now, before the last submission: the next
   * frame's work follows it (render.h settle_first). */
  if (p->defer) estimator_final(g, ft, &run->out->stats);
  /* The resolve's counters, zeroed for the frame just before its first
   * band's resolve (only the resolve writes them). */
  if (band == 0 && ((r = pb_gpu_buffer_fill_zero(g, &c->tg.guard)) != PB_OK ||
                    (r = pb_gpu_buffer_fill_zero(g, &c->tg.kpd)) != PB_OK))
    return r;
  if (p->chain_gpu && (r = pb_filter_chain_bind(g, run->fc, &c->tg, p->nmap_aovs)) != PB_OK) return r;
  if (p->still_gpu && (r = pb_still_sum_bind(g, run->io->still_sum, &c->tg)) != PB_OK) return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_resolve_record(g, &c->rp, &c->tg, pixels, 1.0f / (float)ft->spp_run, run->s->film_opaque);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, 1);
  uint32_t slot = 1;
  if (p->chain_gpu && r == PB_OK) r = pb_filter_chain_record(g, run->fc, pixels, &slot);
  ft->sc_slot = slot;
  if (p->post_gpu && p->sc_on && r == PB_OK) { /* eq. 20 on the filtered indirect */
    r = pb_shading_correction_record(g, &c->scp, pixels, PB_SHADING_CORRECTION_S_MAX);
    pb_gpu_barrier(g);
  }
  if (p->still_gpu && r == PB_OK) { /* a still run's running means (targets.h pb_still_sum) */
    r = pb_still_sum_record(g, run->io->still_sum, &c->tg, pixels);
    pb_gpu_barrier(g);
  }
  pb_gpu_timestamp(g, ++slot);
  ft->slot = slot;
  if (p->defer) { /* after the last timestamp: the download is not a pass */
    pb_gpu_barrier(g);
    run->ring_kept = pb_readback_ring_record(g, &c->tg, run->ring_slot, pixels, p->readback, run->d->keep_planes,
                                             &run->out->stats.ring_bytes);
  }
  pb_result rs = p->defer ? pb_gpu_submit_async(g) : pb_gpu_submit(g);
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  ft->gpu_sub = pb_gpu_last_submission(g);
  return PB_OK;
}

/* One band of rows: its samples and photon maps, iteration by iteration,
 * then its tail; without frames in flight, its AOVs to the host (the
 * readback, readback.h, is where pixels leave the GPU). */
static pb_result frame_band(frame_run *run, uint32_t band) {
  pb_gpu *g = run->g;
  pb_frame_context *c = run->c;
  const pb_frame_plan *p = &run->p;
  frame_tail *ft = &run->ft;
  uint32_t width = p->shape.width, height = p->shape.height;
  uint32_t row0 = band * p->band_rows;
  uint32_t rows = height - row0 < p->band_rows ? height - row0 : p->band_rows;
  uint32_t pixels = rows * width;
  pb_gpu_frame fr = p->frame;
  fr.pixel_base = row0 * width;
  fr.pixel_count = pixels;
  pb_result r;
  if ((r = pb_gpu_buffer_upload(g, &c->tg.frame, 0, &fr, sizeof fr)) != PB_OK) return r;
  if ((r = pb_gpu_buffer_fill_zero(g, &c->tg.accum)) != PB_OK) return r;
  if (p->photons && (r = pb_gpu_buffer_fill_zero(g, &c->tg.paccum)) != PB_OK) return r;
  if (c->tg.nmap && (r = pb_gpu_buffer_fill_zero(g, &c->tg.pnmap)) != PB_OK) return r;
  if (c->ups && (r = pb_upsample_reset(g, c->ups)) != PB_OK) return r;
  for (uint32_t it = 0; it < ft->iters_run; ++it) {
    uint32_t s_begin = (uint32_t)((uint64_t)it * p->spp / p->iters);
    uint32_t s_end = (uint32_t)((uint64_t)(it + 1) * p->spp / p->iters);
    if (p->photons && s_end > s_begin && (r = record_photon_map(run, band, it)) != PB_OK) return r;
    if ((r = record_camera_samples(run, s_begin, s_end, pixels)) != PB_OK) return r;
    if (band == 0 && (r = iteration_done(run, it, s_end)) != PB_OK) return r;
  }
  ft->spp_run = (uint32_t)((uint64_t)ft->iters_run * p->spp / p->iters); /* all of spp without a time limit */
  if ((r = record_tail(run, band, pixels)) != PB_OK) return r;
  if (p->defer) return PB_OK; /* one band: frame_settle and frame_read finish it */
  if ((r = tail_band_times(g, ft, run->out)) != PB_OK) return r;
  return pb_readback_band(g, &c->tg, p->readback, pixels, fr.pixel_base, p->pixels, 1.0f / (float)ft->spp_run,
                          run->s->film_opaque, p->nmap_aovs, run->out, &ft->k_sum, &ft->hit_sum);
}

/* After the last band: the planes the caller may read on the GPU, then the
 * statistics now or, for a frame in flight, the tail kept in the context
 * for pb_render_frame_settle; the context's ring order for the next frame. */
static pb_result frame_finish(frame_run *run) {
  const pb_frame_plan *p = &run->p;
  pb_frame_context *c = run->c;
  pb_render_result *out = run->out;
  frame_tail *ft = &run->ft;
  out->width = p->shape.width;
  out->height = p->shape.height;
  out->stats.readback_mode = p->readback;
  out->stats.stop = run->preview.stop;
  out->stats.noise_estimate = run->preview.noise.estimate;
  out->stats.noise_psnr = run->preview.noise.psnr;
  out->stats.noise_checks = run->preview.noise.checks;
  if (c != &run->own && p->bands == 1 && !p->host_resolve) { /* the planes stay on the GPU (render.h pb_render_gpu_planes) */
    out->gpu.planes = p->defer ? &c->tg.ring[run->ring_slot][0] : &c->tg.planes;
    out->gpu.pplanes = !c->tg.photons ? NULL : p->defer ? &c->tg.ring[run->ring_slot][1] : &c->tg.pplanes;
    out->gpu.pixels = (uint32_t)p->pixels, out->gpu.channels = c->tg.channels;
    out->gpu.kept = p->defer ? run->ring_kept : PB_RENDER_KEEP_ALL;
    out->gpu.photons = c->tg.photons, out->gpu.nmap = c->tg.nmap, out->gpu.nmap_aovs = p->nmap_aovs;
  }
  ft->pixels = (uint32_t)p->pixels, ft->ring_slot = run->ring_slot, ft->pixel_base = 0, ft->n = p->pixels;
  ft->inv_spp = 1.0f / (float)ft->spp_run;
  c->next_slot = p->defer ? run->ring_slot + 1 : run->kept_slot;
  if (!p->defer) return tail_frame(run->g, &c->tg, ft, out);
  ft->host_ms = (pb_time_now() - ft->wall0) * 1e3;
  ft->tr_submit = pb_gpu_transfers_get(run->g);
  c->tail[run->ring_slot] = *ft;
  out->pending = 1;
  out->pending_slot = run->ring_slot;
  out->stats.in_flight = 1;
  return PB_OK;
}

/* The stages in order (render.h): the plan, the context, per band the
 * photon maps, camera samples and tail, then the frame's finish. */
pb_result pb_render_frame_io(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width,
                             uint32_t height, const pb_render_desc *desc, const pb_render_io *io,
                             pb_render_result *out) {
  static const pb_render_desc defaults;
  static const pb_render_io none;
  memset(out, 0, sizeof *out);
  frame_run run = {0};
  const pb_render_desc *d = desc ? desc : &defaults;
  if (!io) io = &none;
  pb_result r = pb_frame_plan_of(g, s, gs, camera, width, height, d, io, &run.p);
  if (r != PB_OK) return r;
  run_begin(&run, g, s, d, io, out);
  r = frame_prepare(&run);
  for (uint32_t band = 0; r == PB_OK && band < run.p.bands; ++band) r = frame_band(&run, band);
  if (r == PB_OK) r = frame_finish(&run);
  return run_end(&run, r);
}

pb_result pb_render_frame(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width,
                          uint32_t height, const pb_render_desc *desc, pb_render_result *out) {
  return pb_render_frame_io(g, s, gs, camera, width, height, desc, NULL, out);
}
