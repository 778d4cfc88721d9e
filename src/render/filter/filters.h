/* The post-filters of the indirect light, in the chapter's order (seed 001
 * 24.4): temporal (temporal.h, eq. 12-13) then spatial (atrous.h, eq.
 * 14-19), on a resolved frame's AOVs; the beauty takes the filtered
 * indirect in place of the raw one. Caustics get at most a temporal filter
 * (no blur across them). */
#ifndef PB_RENDER_FILTERS_H
#define PB_RENDER_FILTERS_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "render/frame/targets.h"
#include "render/filter/temporal.h"
#include "scene/scene.h"

typedef struct pb_filter_desc {
  uint32_t atrous_iterations; /* 0: no spatial filter */
  float atrous_gamma;         /* as pb_render_desc.atrous_gamma */
  pb_temporal *temporal;      /* NULL: no temporal filter */
  pb_temporal *temporal_caustic; /* NULL: caustics unfiltered; else their own
                                 temporal filter (history clamped to the
                                 frame's neighbourhood; no spatial filter,
                                 so they stay sharp) */
  const float *motion;        /* motion.h vectors (NULL with still) */
  int still;                  /* camera and scene unchanged since the
                                 previous frame */
  struct pb_atrous_pass *atrous; /* the A-Trous pass of this image size, kept
                                 by the caller (sequences); NULL: made for
                                 the call */
} pb_filter_desc;

/* Filters res->indirect in place and updates res->beauty; adds the
 * passes' times and the temporal statistics to res->stats. A result
 * without an indirect AOV is left alone. The host-array path: tests, and
 * the chain's reference (pb_filter_chain_host). */
pb_result pb_filter_indirect(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d);

/* ---- the filter chain: the same filters on the GPU, inside the frame -----
 *
 * One object per image size and sequence (or per call for a single frame's
 * A-Trous), holding the temporal filters (indirect; caustics when asked),
 * the A-Trous, the motion-vector pass and the vec4 buffers they share. A
 * frame (frame.c) records it after the resolve, in the resolve's command
 * buffer, on the resolved planes of the frame's targets (targets.h):
 *   pack (planes -> geometry, albedo, indirect, caustics; filter_io.comp)
 *   -> motion vectors (moving frames) -> temporal (indirect, caustics)
 *   -> A-Trous (indirect) -> compose (filtered values into the planes,
 *   non-finite values counted in the guard, beauty += filtered - raw)
 * so no pixel leaves the GPU before the readback. The image must be one
 * band; several bands (images past the storage-buffer limit) and the host
 * reference (PB_RESOLVE_ON_HOST=1) run pb_filter_chain_host on the read-back
 * AOVs instead, the same filters through host arrays. */
typedef struct pb_filter_chain pb_filter_chain;

typedef struct pb_filter_chain_desc {
  uint32_t atrous_iterations;    /* 0: no spatial filter */
  float atrous_gamma;            /* as pb_render_desc.atrous_gamma */
  int temporal;                  /* 1: temporal filter of the indirect */
  pb_temporal_desc temporal_desc;
  int temporal_caustic;          /* 1: caustics get their own temporal filter
                                    (history clamped, clamp_gamma) */
  float caustic_clamp_gamma;
  uint32_t vertex_count;         /* the scene's, for the motion vectors */
} pb_filter_chain_desc;

/* This frame against the previous one (set before each pb_render_frame). */
typedef struct pb_filter_frame {
  int moving;                    /* camera, geometry or lights moved since
                                    the previous frame: motion vectors; 0:
                                    still (the temporal filters keep a
                                    cumulative mean) */
  const pb_scene *s;             /* moving: the scene as posed, */
  const pb_gpu_scene *gs;        /* its GPU copy, */
  const float (*prev_positions)[3]; /* the previous positions (NULL: the
                                    geometry did not move), */
  pb_camera cam, prev_cam;       /* and both cameras */
} pb_filter_frame;

pb_result pb_filter_chain_create(pb_gpu *g, uint32_t width, uint32_t height, const pb_filter_chain_desc *d,
                                 pb_filter_chain **out);
void pb_filter_chain_destroy(pb_gpu *g, pb_filter_chain *c);
void pb_filter_chain_set_frame(pb_filter_chain *c, const pb_filter_frame *f);
/* frame.c, for a frame of one band with the photon stages on: bind before
 * the resolve's pb_gpu_begin (uploads the motion pass's constants, binds
 * every pass to the targets), record after the resolve (timestamps from
 * *slot on, *slot advanced), finish after the submission (times and the
 * temporal statistics into st). geo_normal: edge-stop on the geometric
 * normal plane (normal maps). */
pb_result pb_filter_chain_bind(pb_gpu *g, pb_filter_chain *c, const pb_frame_targets *t, int geo_normal);
pb_result pb_filter_chain_record(pb_gpu *g, pb_filter_chain *c, uint32_t pixels, uint32_t *slot);
pb_result pb_filter_chain_finish(pb_gpu *g, pb_filter_chain *c, int timestamps, pb_render_stats *st);
/* The chain on host arrays (several bands, the host reference): motion
 * vectors read back, pb_filter_indirect. */
pb_result pb_filter_chain_host(pb_gpu *g, pb_filter_chain *c, pb_render_result *res);

#endif
