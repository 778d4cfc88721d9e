/* The spatial filter of the indirect light (seed 001 24.4.2; the pass is
 * shaders/filter/atrous.comp): edge-avoiding A-Trous over the irradiance (indirect
 * radiance / albedo) with depth and normal edge-stopping (eq. 10-11) and
 * variance clipping of the detail coefficients (eq. 16-18), then the
 * albedo multiplied back (eq. 19). A density-estimator post-process: it
 * reads only per-pixel buffers (G-buffer AOVs and the indirect AOV). */
#ifndef PB_RENDER_ATROUS_H
#define PB_RENDER_ATROUS_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"

/* Zero means default for every field. */
typedef struct pb_atrous_desc {
  uint32_t iterations;  /* 5x5 passes, taps 1, 2, 4, ... apart; 0: 4 */
  float sigma_z;        /* eq. 10; 0: 1 */
  float sigma_n;        /* eq. 11; 0: 32 */
  float gamma;          /* detail clipping at gamma standard deviations; 0:
                           PB_ATROUS_GAMMA_DEFAULT; < 0: no detail kept
                           (plain A-Trous, s_n) */
  /* Per-pixel temporal history length L (the frames the temporal filter's
   * average spans, temporal.h) or NULL (single frames: L = 1). The clip
   * bound becomes gamma sqrt(L) sigma_i: the noise left after temporal
   * accumulation is about 1/sqrt(L) of one frame's, so the same gamma keeps
   * detail in proportion (seed 001 24.6.2 proposes scaling the clipping
   * constant by the temporal weights). As L grows the clipping opens and a
   * still view converges to the temporally accumulated value. */
  const float *history;
} pb_atrous_desc;

/* gamma = 0.25, measured (lavapipe, 128 px, 16 spp, 8 maps of 2^16 paths,
 * 4 passes, against 1024-spp references): cornell_box beauty 26.77 dB
 * unfiltered, 27.94 / 28.03 / 27.41 / 26.78 dB at gamma 0 / 0.25 / 0.5 / 1;
 * spot_room 32.72 dB, 33.42 / 33.21 / 32.90 / 32.72. The chapter clips
 * temporally filtered irradiance, whose noise is far lower; on a single
 * frame gamma = 1 keeps nearly all of the noise. */
#define PB_ATROUS_GAMMA_DEFAULT 0.25f

/* Filters `indirect` (RGB, width x height, top row first) in place, guided
 * by the shading `normal` (XYZ), camera `depth` (0: no surface) and
 * `albedo` (RGB) of the same pixels. gpu_ms (may be NULL): the passes' time.
 * Makes and frees a pass (below) for the one call. */
pb_result pb_atrous_filter(pb_gpu *g, uint32_t width, uint32_t height, const float *normal, const float *depth,
                           const float *albedo, float *indirect, const pb_atrous_desc *desc, double *gpu_ms);

/* The filter's pipeline and buffers for one image size, made once and
 * reused (sequences: one per sequence, so no frame compiles the pipeline or
 * allocates); pb_atrous_pass_run filters as pb_atrous_filter does. */
typedef struct pb_atrous_pass pb_atrous_pass;
pb_result pb_atrous_pass_create(pb_gpu *g, uint32_t width, uint32_t height, pb_atrous_pass **out);
void pb_atrous_pass_destroy(pb_gpu *g, pb_atrous_pass *a);
pb_result pb_atrous_pass_run(pb_gpu *g, pb_atrous_pass *a, const float *normal, const float *depth,
                             const float *albedo, float *indirect, const pb_atrous_desc *desc, double *gpu_ms);

/* The device-side filter, recorded into a frame's command buffer (the
 * filter chain, filters.h): geo (vec4: edge-stopping normal, depth),
 * albedo (vec4) and indirect (vec4: radiance, w = the history length L,
 * desc->history is not read; filtered in place) are the frame's buffers of
 * width x height. Bind before pb_gpu_begin, record inside. */
pb_result pb_atrous_pass_bind(pb_gpu *g, pb_atrous_pass *a, const pb_gpu_buffer *geo, const pb_gpu_buffer *albedo,
                              const pb_gpu_buffer *indirect);
pb_result pb_atrous_pass_record(pb_gpu *g, pb_atrous_pass *a, const pb_atrous_desc *desc);

#endif
