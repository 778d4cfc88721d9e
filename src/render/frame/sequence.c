/* Frame sequences (sequence.h). */
#include "render/frame/sequence.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "core/mix.h"
#include "render/filter/filters.h"
#include "render/frame/plan.h"
#include "render/frame/targets.h"

struct pb_sequence {
  pb_scene *s;
  pb_gpu_scene *gs;
  int camera;
  uint32_t width, height;
  pb_sequence_desc desc;
  /* The temporal filters (indirect; caustics in scenes with caustic
   * photons), motion vectors and A-Trous, run by each frame on the GPU
   * (filters.h); NULL with neither filter. */
  pb_filter_chain *chain;
  int caustic_filtered;
  float (*prev_positions)[3];
  pb_light *prev_lights;
  pb_camera prev_cam, start_cam;
  int has_prev;
  uint32_t still_iterations; /* photon maps averaged by the still run so far */
  /* Still runs: running means of what the temporal filter does not see
   * (beauty minus indirect: emission, direct light, caustics; and the
   * direct and caustic AOVs) over the run's frames. */
  float *acc_rest, *acc_direct, *acc_caustic;
  uint32_t acc_frames;
  /* The same running means on the GPU (targets.h): every
   * frame in one band on the GPU path averages there, so the host arrays
   * above are only made for frames that do not (several bands, the host
   * resolve of the tests). */
  pb_still_sum still;
  int pend_gpu_acc; /* the frame in flight averaged on the GPU */
  pb_frame_context *frame_ctx; /* pipelines and buffers kept between frames */
  /* Frames in flight: the frame rendered by the last call, not returned
   * yet (its last submission maybe still on the GPU: pend.pending). */
  int in_flight, have_pend, pend_acc_still;
  pb_render_result pend;
  pb_sequence_frame_info pend_info;
  double last_out;             /* when the last frame came out (pb_time_now), 0: none yet */
  double pend_host_ms;         /* the sequence's own host time on it (pose, scene update) */
  uint64_t pend_scene_up, pend_scene_down; /* the scene update's transfers */
};

void pb_sequence_destroy(pb_gpu *g, pb_sequence *q) {
  if (!q) return;
  if (q->have_pend) (void)pb_gpu_wait(g);
  pb_render_result_destroy(&q->pend);
  pb_still_sum_destroy(g, &q->still);
  pb_filter_chain_destroy(g, q->chain);
  pb_frame_context_destroy(g, q->frame_ctx);
  free(q->prev_positions);
  free(q->prev_lights);
  free(q->acc_rest);
  free(q->acc_direct);
  free(q->acc_caustic);
  free(q);
}

pb_result pb_sequence_create(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera, uint32_t width,
                             uint32_t height, const pb_sequence_desc *desc, pb_sequence **out) {
  *out = NULL;
  if (camera < 0 || (uint32_t)camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "sequence: camera %d of %u", camera, s->camera_count);
  pb_sequence *q = calloc(1, sizeof *q);
  if (!q) return pb_fail(PB_ERR_NOMEM, "sequence: out of memory");
  q->s = s;
  q->gs = gs;
  q->camera = camera;
  q->width = width;
  q->height = height;
  q->desc = *desc;
  q->in_flight = desc->frames_in_flight >= 2;
  if (desc->frames_in_flight > 2) pb_log_info("sequence: %u frames in flight asked for; 2 are used (the readback ring's two slots)",
                                              desc->frames_in_flight);
  q->start_cam = s->cameras[camera];
  size_t n = (size_t)width * height;
  q->prev_positions = malloc((size_t)(s->vertex_count ? s->vertex_count : 1) * sizeof *q->prev_positions);
  q->prev_lights = malloc((size_t)(s->light_count ? s->light_count : 1) * sizeof *q->prev_lights);
  pb_result r = PB_OK;
  if (!q->prev_positions || !q->prev_lights) {
    r = pb_fail(PB_ERR_NOMEM, "sequence: out of memory for %ux%u pixels", width, height);
    goto fail;
  }
  if ((r = pb_frame_context_create(&q->frame_ctx)) != PB_OK) goto fail;
  pb_render_plan plan;
  pb_render_plan_of(s, desc->render.direct_only, &plan);
  pb_filter_chain_desc cd = {.atrous_iterations = desc->render.atrous_iterations,
                             .atrous_gamma = desc->render.atrous_gamma,
                             .temporal = desc->temporal,
                             .temporal_desc = desc->temporal_desc,
                             .vertex_count = s->vertex_count};
  if (desc->temporal && plan.caustic_photons) {
    /* Caustics move over still surfaces (a moving glass object, a moving
     * light): no motion vector says so, so their history is also clamped
     * to the frame's neighbourhood. gamma 0.5, from a sweep on
     * cornell_caustics_moving_sphere (96 px, frames 0-23, 2^15 paths,
     * against 512-spp references; caustics unfiltered: 26.35 dB, relMSE
     * 0.0569, excess flicker 0.0510): gamma 0.5 26.51 dB / 0.0571 / 0.0280,
     * 1: 26.43 / 0.0591 / 0.0249, 2.5: 26.40 / 0.0640 / 0.0229, no clamp:
     * 26.40 / 0.0812 / 0.0228 (the caustic lags behind the sphere). */
    cd.temporal_caustic = 1;
    cd.caustic_clamp_gamma = 0.5f;
    q->caustic_filtered = 1;
  }
  if ((cd.temporal || cd.atrous_iterations) && (r = pb_filter_chain_create(g, width, height, &cd, &q->chain)) != PB_OK)
    goto fail;
  if (!getenv("PB_STILL_ON_HOST") || getenv("PB_STILL_ON_HOST")[0] != '1') /* tests: the host path */
    if ((r = pb_still_sum_create(g, (uint32_t)n, q->caustic_filtered, &q->still)) != PB_OK) goto fail;
  *out = q;
  return PB_OK;
fail:
  pb_sequence_destroy(g, q);
  return r;
}

static void normalize3(float v[3]) {
  float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

void pb_sequence_orbit_camera(const pb_scene *s, const pb_camera *start, double t, double period, pb_camera *out) {
  *out = *start;
  double c[3], d[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
    d[k] = start->position[k] - c[k];
  }
  double r = sqrt(d[0] * d[0] + d[2] * d[2]);
  if (!(r > 1e-6)) { /* straight above or below the centre: orbit at the box's size */
    double e = 0;
    for (int k = 0; k < 3; ++k) e += ((double)s->bounds_max[k] - s->bounds_min[k]) * (s->bounds_max[k] - s->bounds_min[k]);
    r = sqrt(e) > 0 ? sqrt(e) : 1.0;
    d[0] = r, d[2] = 0;
  }
  double a = atan2(d[2], d[0]) + (period > 0 ? 2.0 * M_PI * t / period : 0.0);
  out->position[0] = (float)(c[0] + r * cos(a));
  out->position[1] = (float)(c[1] + d[1]);
  out->position[2] = (float)(c[2] + r * sin(a));
  float f[3] = {(float)c[0] - out->position[0], (float)c[1] - out->position[1], (float)c[2] - out->position[2]};
  normalize3(f);
  /* right = forward x (0, 1, 0), up = right x forward: the camera's -Z looks
   * at the centre, +Y stays as upright as the view allows. */
  float rt[3] = {-f[2], 0.0f, f[0]};
  if (!(rt[0] * rt[0] + rt[2] * rt[2] > 1e-12f)) rt[0] = 1.0f, rt[2] = 0.0f; /* looking straight down */
  normalize3(rt);
  float up[3] = {rt[1] * f[2] - rt[2] * f[1], rt[2] * f[0] - rt[0] * f[2], rt[0] * f[1] - rt[1] * f[0]};
  normalize3(up);
  memcpy(out->forward, f, sizeof f);
  memcpy(out->right, rt, sizeof rt);
  memcpy(out->up, up, sizeof up);
}

void pb_sequence_set_readback(pb_sequence *q, int readback) { q->desc.readback = readback; }
void pb_sequence_set_keep_planes(pb_sequence *q, uint64_t keep) { q->desc.keep_planes = keep; }

static int camera_equal(const pb_camera *a, const pb_camera *b) {
  return !memcmp(a->position, b->position, sizeof a->position) && !memcmp(a->forward, b->forward, sizeof a->forward) &&
         !memcmp(a->up, b->up, sizeof a->up) && !memcmp(a->right, b->right, sizeof a->right) && a->yfov == b->yfov &&
         a->orthographic == b->orthographic && a->fit == b->fit && a->ortho_size == b->ortho_size &&
         !memcmp(a->shift, b->shift, sizeof a->shift) && a->znear == b->znear && a->zfar == b->zfar &&
         a->aperture_radius == b->aperture_radius && a->focus_distance == b->focus_distance &&
         a->aperture_rotation == b->aperture_rotation && a->aperture_ratio == b->aperture_ratio &&
         a->aperture_blades == b->aperture_blades && a->panorama == b->panorama &&
         !memcmp(a->latitude, b->latitude, sizeof a->latitude) && !memcmp(a->longitude, b->longitude, sizeof a->longitude) &&
         a->fisheye_fov == b->fisheye_fov && a->fisheye_lens == b->fisheye_lens &&
         !memcmp(a->sensor, b->sensor, sizeof a->sensor);
}

/* Progressive rendering of a still run: the temporal filters already keep
 * the cumulative mean of the indirect light (and of the caustics when they
 * have their own); the rest of the frame (beauty minus those: emission,
 * direct light; the direct AOV, and unfiltered caustics) is averaged here,
 * so the whole picture converges. A frame that moved starts a new run. */
static pb_result accumulate(pb_sequence *q, pb_render_result *out, int still) {
  size_t n = (size_t)q->width * q->height;
  if (out->stats.readback_mode != PB_RENDER_READBACK_ALL) /* lean only with the means on the GPU (frame.c) */
    return pb_fail(PB_ERR_INTERNAL, "sequence: a frame read back without its AOVs to average on the host");
  if (!q->acc_rest) {
    q->acc_rest = malloc(n * 4 * sizeof *q->acc_rest);
    q->acc_direct = malloc(n * 3 * sizeof *q->acc_direct);
    q->acc_caustic = malloc(n * 3 * sizeof *q->acc_caustic);
    if (!q->acc_rest || !q->acc_direct || !q->acc_caustic)
      return pb_fail(PB_ERR_NOMEM, "sequence: out of memory for %ux%u pixels", q->width, q->height);
  }
  if (!still) q->acc_frames = 0;
  float k = (float)q->acc_frames, inv = 1.0f / (k + 1.0f);
  const float *filtered[2] = {out->indirect, q->caustic_filtered ? out->caustic : NULL};
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) {
      float kept = 0.0f; /* the temporally filtered parts */
      for (int f = 0; f < 2; ++f)
        if (c < 3 && filtered[f]) kept += filtered[f][3 * i + c];
      float rest = out->beauty[4 * i + c] - kept;
      float m = q->acc_frames ? (q->acc_rest[4 * i + c] * k + rest) * inv : rest;
      q->acc_rest[4 * i + c] = m;
      out->beauty[4 * i + c] = m + kept;
    }
    for (int c = 0; c < 3; ++c) {
      float d = out->direct[3 * i + c];
      out->direct[3 * i + c] = q->acc_direct[3 * i + c] = q->acc_frames ? (q->acc_direct[3 * i + c] * k + d) * inv : d;
      if (out->caustic && !q->caustic_filtered) {
        float e = out->caustic[3 * i + c];
        out->caustic[3 * i + c] = q->acc_caustic[3 * i + c] =
            q->acc_frames ? (q->acc_caustic[3 * i + c] * k + e) * inv : e;
      }
    }
  }
  q->acc_frames++;
  return PB_OK;
}

/* A frame comes out now: its interval since the last one. */
static void stamp_out(pb_sequence *q, pb_render_result *out) {
  double now = pb_time_now();
  out->stats.frame_interval_ms = q->last_out > 0 ? (now - q->last_out) * 1e3 : 0.0;
  q->last_out = now;
}

pb_result pb_sequence_frame(pb_gpu *g, pb_sequence *q, uint32_t index, double t, pb_render_result *out,
                            pb_sequence_frame_info *info) {
  memset(out, 0, sizeof *out);
  pb_sequence_frame_info fi;
  memset(&fi, 0, sizeof fi);
  fi.time = t;
  pb_scene *s = q->s;
  pb_result r;
  /* The scene still holds the previous frame's pose: keep it for motion. */
  if (q->has_prev) {
    memcpy(q->prev_positions, s->positions, (size_t)s->vertex_count * sizeof *q->prev_positions);
    memcpy(q->prev_lights, s->lights, (size_t)s->light_count * sizeof *q->prev_lights);
  }
  double t0 = pb_time_now(), c0 = pb_thread_cpu_now(), frame_t0 = t0;
  pb_gpu_transfers tr0 = pb_gpu_transfers_get(g);
  if (s->anim && (r = pb_scene_set_time(s, t)) != PB_OK) return r;
  if (q->desc.orbit)
    pb_sequence_orbit_camera(s, &q->start_cam, t, q->desc.orbit_period, &s->cameras[q->camera]);
  fi.pose_ms = (pb_time_now() - t0) * 1e3;
  fi.pose_cpu_ms = (pb_thread_cpu_now() - c0) * 1e3;
  const pb_camera *cam = &s->cameras[q->camera];
  fi.camera = *cam;
  if (q->has_prev) {
    fi.geometry_moved = memcmp(q->prev_positions, s->positions, (size_t)s->vertex_count * sizeof *q->prev_positions) != 0;
    fi.lights_moved = memcmp(q->prev_lights, s->lights, (size_t)s->light_count * sizeof *q->prev_lights) != 0;
    fi.camera_moved = !camera_equal(&q->prev_cam, cam);
  }
  fi.still = !fi.geometry_moved && !fi.lights_moved && !fi.camera_moved;
  /* Frames in flight: the previous frame's last submission may still run
   * while this frame is posed and recorded. What it reads stays as it was
   * on the GPU: a scene update's uploads wait for it (large) or follow it
   * in the queue (small, gpu.h pb_gpu_submit_async), the filter chain's
   * cameras are recorded, and pb_render_frame settles it before this
   * frame's last submission (render.h settle_first). Its pixels come later,
   * from the ring. */
  pb_gpu_transfers tr_scene0 = pb_gpu_transfers_get(g);
  if (fi.geometry_moved || fi.lights_moved || (!q->has_prev && s->anim)) {
    /* The GPU scene was made from the file's static pose: the first frame
     * of an animated scene updates it too. */
    if ((r = pb_gpu_scene_update(g, s, q->gs, q->desc.bvh_update, &fi.scene_update_ms)) != PB_OK) return r;
  }
  pb_gpu_transfers tr_scene1 = pb_gpu_transfers_get(g);
  pb_render_desc rd = q->desc.render;
  rd.seed = pb_mix64(q->desc.render.seed + 0x9e3779b97f4a7c15ull * index); /* frame i's own photons */
  rd.atrous_iterations = 0;     /* the chain's (q->chain), after the temporal filter */
  pb_render_io io = {.progress = q->desc.progress, .progress_user = q->desc.progress_user, .context = q->frame_ctx};
  /* A lean readback needs the still run's means on the GPU: the host's
   * (accumulate) work on the arrays. */
  rd.readback = q->still.pipe.pipeline ? q->desc.readback : PB_RENDER_READBACK_ALL;
  rd.keep_planes = q->desc.keep_planes;
  io.filters = q->chain;        /* recorded after the resolve, on the GPU; then
                                   eq. 20 on the filtered indirect, with this
                                   frame's mean photon direction (the chapter
                                   filters that direction too; here it is the
                                   frame's own) */
  uint32_t iters = rd.iterations ? rd.iterations : 1;
  if (!fi.still || !q->has_prev) q->still_iterations = 0;
  rd.iteration_base = rd.progressive ? q->still_iterations : 0;
  /* Still frames after the first sample new positions in the pixel, so the
   * run's mean is the box-filtered pixel (progressive anti-aliasing). */
  if (fi.still && q->has_prev) rd.jitter = 1;
  if (q->chain) {
    pb_filter_frame ff = {.moving = q->has_prev && !fi.still, .s = s, .gs = q->gs,
                          .prev_positions = fi.geometry_moved ? (const float(*)[3])q->prev_positions : NULL,
                          .cam = *cam, .prev_cam = q->prev_cam};
    pb_filter_chain_set_frame(q->chain, &ff);
  }
  /* The still run's means on the GPU: restart with a run (the host's
   * accumulate() counts the same way). */
  int acc_still = fi.still && q->has_prev;
  if (q->still.pipe.pipeline) {
    if (!acc_still) q->still.frames = 0;
    io.still_sum = &q->still;
  }
  if (q->in_flight) {
    rd.in_flight = 1;
    io.settle_first = q->have_pend && q->pend.pending == 1 ? &q->pend : NULL;
    fi.index = index;
    double pre_ms = (pb_time_now() - frame_t0) * 1e3;
    pb_render_result cur;
    if ((r = pb_render_frame_io(g, s, q->gs, q->camera, q->width, q->height, &rd, &io, &cur)) != PB_OK) return r;
    q->still_iterations += iters;
    int gpu_acc = cur.stats.still_on_gpu;
    if (gpu_acc) q->still.frames++;
    q->has_prev = 1;
    q->prev_cam = *cam;
    /* This frame runs on the GPU now; the previous one comes out. */
    r = PB_OK;
    if (q->have_pend) {
      double t1 = pb_time_now();
      r = pb_render_frame_complete(g, q->frame_ctx, &q->pend);
      if (r == PB_OK && !q->pend_gpu_acc) r = accumulate(q, &q->pend, q->pend_acc_still);
      if (r == PB_OK) {
        *out = q->pend;
        if (info) {
          *info = q->pend_info;
          info->ready = 1;
          info->motion_ms = out->stats.motion_ms;
        }
        /* Its host time: its pose and scene update, pb_render_frame up to
         * its last submission, the wait and the read (render.h), and the
         * accumulation just now. */
        out->stats.frame_wall_ms += q->pend_host_ms + (pb_time_now() - t1) * 1e3;
        out->stats.upload_bytes += q->pend_scene_up;
        out->stats.download_bytes += q->pend_scene_down;
        stamp_out(q, out);
      } else {
        pb_render_result_destroy(&q->pend);
      }
      memset(&q->pend, 0, sizeof q->pend);
    } else if (info) {
      memset(info, 0, sizeof *info); /* nothing out yet */
    }
    q->pend = cur;
    q->pend_info = fi;
    q->pend_info.camera = *cam;
    q->pend_acc_still = acc_still;
    q->pend_gpu_acc = gpu_acc;
    q->pend_host_ms = pre_ms;
    q->pend_scene_up = tr_scene1.upload_bytes - tr_scene0.upload_bytes;
    q->pend_scene_down = tr_scene1.download_bytes - tr_scene0.download_bytes;
    q->have_pend = 1;
    return r;
  }
  if ((r = pb_render_frame_io(g, s, q->gs, q->camera, q->width, q->height, &rd, &io, out)) != PB_OK) return r;
  q->still_iterations += iters;
  fi.motion_ms = out->stats.motion_ms;
  if (out->stats.still_on_gpu) {
    q->still.frames++;
  } else if ((r = accumulate(q, out, acc_still)) != PB_OK) {
    pb_render_result_destroy(out);
    return r;
  }
  q->has_prev = 1;
  out->stats.frame_wall_ms = (pb_time_now() - frame_t0) * 1e3;
  /* The frame's transfers, the scene update's included. */
  pb_gpu_transfers tr1 = pb_gpu_transfers_get(g);
  out->stats.upload_bytes = tr1.upload_bytes - tr0.upload_bytes;
  out->stats.download_bytes = tr1.download_bytes - tr0.download_bytes;
  out->stats.readback_bytes = tr1.readback_bytes - tr0.readback_bytes;
  /* The camera this frame used, kept here rather than read from the scene
   * at the next call: a caller may set the camera itself between frames
   * (photonbridge view), which is a move like any other. */
  q->prev_cam = *cam;
  fi.ready = 1;
  fi.index = index;
  stamp_out(q, out);
  if (info) *info = fi;
  return PB_OK;
}

pb_result pb_sequence_flush(pb_gpu *g, pb_sequence *q, pb_render_result *out, pb_sequence_frame_info *info) {
  memset(out, 0, sizeof *out);
  if (info) memset(info, 0, sizeof *info);
  if (!q->have_pend) return PB_OK;
  q->have_pend = 0;
  double t1 = pb_time_now();
  pb_result r = pb_render_frame_complete(g, q->frame_ctx, &q->pend);
  if (r != PB_OK) {
    pb_render_result_destroy(&q->pend);
    return r;
  }
  if (!q->pend_gpu_acc && (r = accumulate(q, &q->pend, q->pend_acc_still)) != PB_OK) {
    pb_render_result_destroy(&q->pend);
    memset(&q->pend, 0, sizeof q->pend);
    return r;
  }
  *out = q->pend;
  memset(&q->pend, 0, sizeof q->pend);
  out->stats.frame_wall_ms += q->pend_host_ms + (pb_time_now() - t1) * 1e3;
  out->stats.upload_bytes += q->pend_scene_up;
  out->stats.download_bytes += q->pend_scene_down;
  stamp_out(q, out);
  if (info) {
    *info = q->pend_info;
    info->ready = 1;
    info->motion_ms = out->stats.motion_ms;
  }
  return PB_OK;
}
