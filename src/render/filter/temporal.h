/* The temporal filter of the indirect light (seed 001 24.4.1, eq. 12-13; the
 * pass is shaders/filter/temporal.comp): the previous frame's temporally filtered
 * irradiance, reprojected through the motion vectors (motion.h), blended
 * with this frame's by an exponential moving average whose weight alpha =
 * 0.95 w_z w_n drops where depth or normal disagree (disocclusion, moving
 * geometry), so history resets there instead of ghosting. A still view
 * (nothing moved since the previous frame) accumulates a cumulative mean:
 * progressive rendering. Like the A-Trous (atrous.h) it reads only
 * per-pixel buffers: a post-process of any density estimator.
 *
 * It keeps its history (irradiance, history length) in device buffers
 * between frames; one object per image size and sequence. A frame records
 * the pass into its own command buffer (pb_temporal_bind, then
 * pb_temporal_record: the inputs are device buffers the frame's filter
 * chain fills, filters.h); pb_temporal_apply does the same for host
 * arrays (tests, benchmarks). */
#ifndef PB_RENDER_TEMPORAL_H
#define PB_RENDER_TEMPORAL_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"

/* Zero means default for every field. */
typedef struct pb_temporal_desc {
  float alpha;        /* eq. 13's constant; 0: 0.95 */
  float sigma_z;      /* eq. 10; 0: 1 */
  float sigma_n;      /* eq. 11; 0: 32 */
  float max_history;  /* still views: frames averaged at most; 0: 4096 */
  float clamp_gamma;  /* > 0: history also clamped to this frame's 3x3 mean
                         +- clamp_gamma sigma (for caustics, which move over
                         still surfaces); 0: off */
} pb_temporal_desc;

typedef struct pb_temporal pb_temporal;

/* What one frame's pass did. */
typedef struct pb_temporal_stats {
  double gpu_ms;           /* the pass (timestamps; wall time without) */
  uint64_t surface_pixels; /* pixels with a surface */
  uint64_t reset_pixels;   /* of those, with no usable history (L = 1):
                              disoccluded, off-screen before, or the first
                              frame */
  double mean_history;     /* mean L over surface pixels */
} pb_temporal_stats;

pb_result pb_temporal_create(pb_gpu *g, uint32_t width, uint32_t height, const pb_temporal_desc *desc,
                             pb_temporal **out);
void pb_temporal_destroy(pb_gpu *g, pb_temporal *t);
/* Forgets the history (a cut): the next frame starts afresh. */
void pb_temporal_reset(pb_temporal *t);

/* Filters one frame in place. normal (XYZ), depth (camera z, 0: no
 * surface), albedo (RGB) and indirect (RGB radiance, filtered on return)
 * are the frame's AOVs (render.h); motion: 4 floats per pixel as motion.h
 * writes them, or NULL when nothing moved and the camera is the previous
 * frame's (then `still` must be 1). still = 1: camera and scene unchanged
 * since the previous frame, so the history becomes a cumulative mean.
 * history (may be NULL): each pixel's history length L afterwards (0 on
 * pixels without a surface), for the A-Trous clipping (atrous.h). */
pb_result pb_temporal_apply(pb_gpu *g, pb_temporal *t, const float *normal, const float *depth,
                            const float *albedo, const float *motion, int still, float *indirect, float *history,
                            pb_temporal_stats *stats);

/* The device-side pass. Buffers of width x height vec4 (pb_filter.h's
 * temporal layout): geo and geo_prev this and the previous frame's
 * geometry (the caller keeps the ping-pong), albedo, the radiance to filter
 * `in`, motion (any buffer when still: not read), `result` (the filtered
 * radiance with L in w, on return of the submission) and `stats`
 * (pb_gpu_temporal_stats, zeroed by the caller). Bind before pb_gpu_begin
 * (it rewrites the pass's descriptor set), record inside; the record flips
 * the history, so call each once per frame. */
pb_result pb_temporal_bind(pb_gpu *g, pb_temporal *t, const pb_gpu_buffer *geo, const pb_gpu_buffer *geo_prev,
                           const pb_gpu_buffer *albedo, const pb_gpu_buffer *in, const pb_gpu_buffer *motion,
                           const pb_gpu_buffer *result, const pb_gpu_buffer *stats);
pb_result pb_temporal_record(pb_gpu *g, pb_temporal *t, int still);
/* stats as pb_temporal_apply's from a pb_gpu_temporal_stats read back
 * (readback.h); gpu_ms stays the caller's. */
void pb_temporal_stats_of(const void *gpu_stats, pb_temporal_stats *stats);

#endif
