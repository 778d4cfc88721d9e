/* A live session's frame loop, shared by `photonbridge view` (viewer.c) and
 * `photonbridge serve` (src/serve/serve.c): one pb_sequence (render/
 * sequence.h, as `render --frames` drives it) whose frames take the camera
 * and the time the client gives. A frame where nothing moved refines the
 * previous ones (the still run); one where the camera, the time or a light
 * moved restarts the run and reprojects the indirect light's history.
 *
 * Frame i of the session uses the seed mixed with i, so the frame after N
 * still frames from the start (index 0) is the last frame of `render
 * --frames 0:N-1` with the same camera and settings. pb_view_session_reset
 * (a new size, new settings, a reloaded scene) starts again at index 0. */
#ifndef PB_VIEW_SESSION_H
#define PB_VIEW_SESSION_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/frame/noise.h"
#include "render/render.h"
#include "render/frame/sequence.h"
#include "scene/scene.h"

typedef struct pb_view_session {
  pb_gpu *g;
  pb_scene *s;
  pb_gpu_scene *gs;
  pb_sequence *seq;
  pb_sequence_desc desc;
  int camera;                   /* the slot in s->cameras the view's camera is written to */
  uint32_t width, height;
  uint32_t frame;               /* frames rendered since the start or the last reset */
  uint32_t run_frames;          /* frames refined by the current still run (1: the first) */
  double t_posed;               /* the time the scene is posed at */
  pb_render_result res;         /* the last frame */
  pb_sequence_frame_info info;  /* and what happened in it */
  /* The noise threshold (view --noise-threshold, serve's stream): the still
   * run's own noise estimate (render/frame/noise.h), the run's frames as its
   * blocks (the beauty a still run shows is their mean). */
  pb_noise_tracker noise;
  uint32_t noise_next;          /* the run frame of its next check */
} pb_view_session;

/* s and gs stay the caller's; the session poses s and updates gs. */
pb_result pb_view_session_create(pb_view_session *v, pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera,
                                 uint32_t width, uint32_t height, const pb_sequence_desc *desc);
/* A new sequence (size, settings, or scene: s and gs may be new ones);
 * the next frame is index 0 again. On failure the session has no sequence
 * and pb_view_session_frame fails until a reset succeeds. */
pb_result pb_view_session_reset(pb_view_session *v, pb_scene *s, pb_gpu_scene *gs, uint32_t width,
                                uint32_t height, const pb_sequence_desc *desc);
void pb_view_session_destroy(pb_view_session *v);

/* Renders the next frame with camera `cam` (written into the session's
 * camera slot; NULL: the slot as the file, or its animation, poses it) at
 * time t into v->res and v->info. With desc.frames_in_flight 2 (view
 * --frames-in-flight 2) v->res and v->info are the frame before
 * (v->info.ready 0 and v->res empty after the first call); `serve` keeps 1:
 * each reply is the frame its request asked for. When t is the time the scene already
 * holds, the scene is not posed again, so that an animated scene camera
 * does not replace `cam`. */
pb_result pb_view_session_frame(pb_view_session *v, const pb_camera *cam, double t);

/* After a frame, with a noise threshold T > 0: checks the still run's
 * estimate on noise.h's schedule (needs v->res.beauty: a readback of at
 * least the beauty); a new run (anything moved, a new size) starts it
 * afresh. No-op for T <= 0 or a frame without a beauty. */
pb_result pb_view_session_noise_update(pb_view_session *v, double threshold);
/* Whether the still run's estimate has reached T (the view rests, a
 * stream stops until asked again). */
int pb_view_session_noise_reached(const pb_view_session *v, double threshold);
/* The still run's estimate (RMS display noise), or -1 before it has one. */
double pb_view_session_noise(const pb_view_session *v);

#endif
