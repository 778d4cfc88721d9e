/* Frame sequences: the scene posed at each frame's time (glTF
 * animation, pb_scene_set_time), the GPU scene updated (BVH refit or
 * rebuild, pb_gpu_scene_update), the frame rendered with new photon seeds,
 * motion vectors (motion.h), then temporal and spatial filtering of the
 * indirect light (filters.h), history carried from frame to frame.
 *
 * A frame in which nothing moved (camera, geometry and lights as in the
 * previous frame) is "still": the temporal filter then keeps a cumulative
 * mean (progressive rendering), and with render.progressive the photon
 * footprints keep shrinking from frame to frame as they do between the
 * iterations of one frame (frame.c), so a still view converges. */
#ifndef PB_RENDER_SEQUENCE_H
#define PB_RENDER_SEQUENCE_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "render/filter/temporal.h"
#include "scene/scene.h"

typedef struct pb_sequence_desc {
  pb_render_desc render;   /* every frame's settings; frame i uses the seed
                              render.seed mixed with i; atrous_iterations
                              run after the temporal filter */
  int temporal;            /* 1: temporal filter (seed 001 24.4.1) */
  pb_temporal_desc temporal_desc;
  int bvh_update;          /* PB_BVH_UPDATE_* for moving geometry */
  int orbit;               /* 1: replace the camera by an orbit around the
                              scene: one turn per orbit_period seconds */
  double orbit_period;
  /* Frames in flight: 0 or 1, each pb_sequence_frame returns
   * the frame it rendered; 2, it returns the frame before (the first call
   * returns none, pb_sequence_flush the last), and the GPU runs a frame's
   * last submission (resolve, filters, the readback's copy into its ring)
   * while the caller works on the frame before and the next frame is
   * posed, set up and recorded (its first submissions queued behind it:
   * gpu.h PB_GPU_FRAMES). The same pixels (tests/frame_same_pixels.py in_flight: 2 against
   * 1, bit-identical on lavapipe, within float rounding wherever the photon
   * store's order varies); only when frames come out changes. */
  uint32_t frames_in_flight;
  /* What each frame reads back to the host (render.h
   * pb_render_desc.readback): PB_RENDER_READBACK_ALL (0: `render --frames`,
   * every AOV), _BEAUTY (`serve`: the beauty it sends), _STATS (`view`
   * with the GPU display: no pixels, the picture is made from the planes
   * on the GPU, out->gpu). The statistics are the same in every mode.
   * Frames that cannot (the host path: several bands, the still run
   * averaged on the host) read everything; out->stats.readback_mode says. */
  int readback;
  /* With frames in flight and a lean readback: the planes the caller reads
   * from out->gpu after the frame (render.h pb_render_desc.keep_planes;
   * 0: none but what the readback reads). */
  uint64_t keep_planes;
  /* Called after each photon iteration of every frame (render.h
   * pb_render_io.progress); NULL: none. */
  pb_render_progress_fn progress;
  void *progress_user;
} pb_sequence_desc;

/* What happened in one frame. */
typedef struct pb_sequence_frame_info {
  double time;                 /* seconds */
  int still;                   /* nothing moved since the previous frame */
  int geometry_moved, lights_moved, camera_moved;
  double pose_ms, scene_update_ms, motion_ms;
  double pose_cpu_ms;          /* the pose's CPU time (skinning, morphing) */
  pb_camera camera;            /* the camera used */
  int ready;                   /* 1: a frame came out (out and this info are
                                  it); 0: none yet (frames in flight, the
                                  first call; pb_sequence_flush with none left) */
  uint32_t index;              /* the frame's index (pb_sequence_frame's) */
} pb_sequence_frame_info;

typedef struct pb_sequence pb_sequence;

/* s and gs stay owned by the caller and are posed/updated in place by
 * every frame; `camera` indexes s->cameras. */
pb_result pb_sequence_create(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera, uint32_t width,
                             uint32_t height, const pb_sequence_desc *desc, pb_sequence **out);
void pb_sequence_destroy(pb_gpu *g, pb_sequence *q);

/* Renders the frame at time t (seconds); index numbers the frame for its
 * photon seeds. out: as pb_render_frame's, filtered. With frames in flight
 * (desc.frames_in_flight 2) out and info are the previous call's frame,
 * info->ready 0 (out empty) on the first call: frames come out one late. */
pb_result pb_sequence_frame(pb_gpu *g, pb_sequence *q, uint32_t index, double t, pb_render_result *out,
                            pb_sequence_frame_info *info);
/* Changes desc.readback from the next frame on (the viewer, when what it
 * shows needs the host's arrays or no longer does). */
void pb_sequence_set_readback(pb_sequence *q, int readback);
/* Changes desc.keep_planes from the next frame on. */
void pb_sequence_set_keep_planes(pb_sequence *q, uint64_t keep);
/* Frames in flight: waits for the last frame still in flight and returns
 * it (info->ready 1), or none (info->ready 0, out empty). Without frames
 * in flight: always none. */
pb_result pb_sequence_flush(pb_gpu *g, pb_sequence *q, pb_render_result *out, pb_sequence_frame_info *info);

/* The orbit camera at time t: around the centre of the scene's bounds at
 * the original camera's height and horizontal distance, starting where the
 * original camera stands, looking at the centre, world +Y up (glTF). */
void pb_sequence_orbit_camera(const pb_scene *s, const pb_camera *start, double t, double period, pb_camera *out);

#endif
