/* The live session's frame loop (session.h), factored out of viewer.c so
 * that `view` and `serve` drive pb_sequence the same way. */
#include "view/session.h"

#include <string.h>

pb_result pb_view_session_create(pb_view_session *v, pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera,
                                 uint32_t width, uint32_t height, const pb_sequence_desc *desc) {
  memset(v, 0, sizeof *v);
  v->g = g;
  v->camera = camera;
  return pb_view_session_reset(v, s, gs, width, height, desc);
}

pb_result pb_view_session_reset(pb_view_session *v, pb_scene *s, pb_gpu_scene *gs, uint32_t width,
                                uint32_t height, const pb_sequence_desc *desc) {
  pb_sequence_destroy(v->g, v->seq);
  v->seq = NULL;
  pb_render_result_destroy(&v->res);
  memset(&v->info, 0, sizeof v->info);
  v->s = s, v->gs = gs, v->width = width, v->height = height, v->desc = *desc;
  v->frame = 0, v->run_frames = 0;
  v->t_posed = s->anim ? s->anim_start : 0.0;
  if (v->camera < 0 || (uint32_t)v->camera >= s->camera_count) v->camera = 0;
  return pb_sequence_create(v->g, s, gs, v->camera, width, height, desc, &v->seq);
}

void pb_view_session_destroy(pb_view_session *v) {
  pb_noise_tracker_free(&v->noise);
  pb_sequence_destroy(v->g, v->seq);
  v->seq = NULL;
  pb_render_result_destroy(&v->res);
}

pb_result pb_view_session_frame(pb_view_session *v, const pb_camera *cam, double t) {
  if (!v->seq) return pb_fail(PB_ERR_USAGE, "session: no sequence (the last reset failed)");
  pb_scene *s = v->s;
  if (cam) s->cameras[v->camera] = *cam;
  /* Nothing to pose when the time has not changed since the last pose: the
   * scene holds it already, and a second pose would put an animated scene
   * camera back over the view's. */
  struct pb_scene_anim *anim = s->anim;
  int hide = anim && v->frame > 0 && t == v->t_posed;
  if (hide) s->anim = NULL;
  pb_render_result_destroy(&v->res);
  pb_result r = pb_sequence_frame(v->g, v->seq, v->frame, t, &v->res, &v->info);
  s->anim = anim;
  if (r != PB_OK) return r;
  v->t_posed = t;
  /* info is the frame that came out: this one, or with frames in flight
   * the one before (none after the first call). */
  if (v->info.ready) v->run_frames = v->info.still && v->info.index > 0 ? v->run_frames + 1 : 1;
  v->frame++;
  return PB_OK;
}

pb_result pb_view_session_noise_update(pb_view_session *v, double threshold) {
  const pb_render_result *res = &v->res;
  uint32_t k = v->run_frames;
  if (!(threshold > 0) || !res->beauty || k == 0) return PB_OK;
  if (k == 1 || v->noise.width != res->width || v->noise.height != res->height || k < v->noise.prev_samples) {
    pb_noise_tracker_free(&v->noise);
    pb_noise_tracker_init(&v->noise, res->width, res->height);
    v->noise_next = 1;
  }
  if (k < v->noise_next) return PB_OK;
  pb_result r = pb_noise_tracker_check(&v->noise, res->beauty, k);
  v->noise_next = pb_noise_tracker_next(&v->noise, threshold, k, UINT32_MAX);
  return r;
}

int pb_view_session_noise_reached(const pb_view_session *v, double threshold) {
  return threshold > 0 && v->noise.samples_a && v->noise.samples_b && v->noise.estimate >= 0 &&
         v->noise.estimate <= threshold && v->run_frames >= v->noise.prev_samples && v->run_frames > 0;
}

double pb_view_session_noise(const pb_view_session *v) {
  return v->noise.samples_a && v->noise.samples_b ? v->noise.estimate : -1.0;
}
