/* Multi-level up-sampling of the diffuse photon irradiance (seed 003 sec. 6
 * "Rendering", Figure 9): the photon estimate's diffuse part runs at every
 * 2^L-th pixel in x and y and is up-sampled level by level (2^L -> 2^(L-1)
 * -> ... -> 1) by a geometry-aware interpolation of the 4 nearest samples of
 * the level above; where those disagree with the pixel in normal or depth
 * the estimate runs again at that level's pixel (shaders/estimate/upsample_mark.comp
 * states and derives the thresholds). It is the irradiance per unit albedo
 * that is up-sampled, multiplied at every pixel by that pixel's diffuse
 * BSDF (upsample_compose.comp); glossy lobes, caustic photons and Blender
 * materials are estimated at full resolution (gather.comp built with
 * -DPB_UPSAMPLE=1, PB_GATHER_UPS_REST). Only the LBVH gather has it
 * (pb_estimator_can_upsample); off in scenes with normal maps (eq. 20's
 * per-pixel photon direction sums are not up-sampled).
 *
 * Per frame: create for the band's pixels (or keep it in the frame
 * context), reset at the start of each band, bind after the estimator's
 * bind (per photon map), record per sample in place of the estimator's
 * record, stats after the frame. */
#ifndef PB_RENDER_UPSAMPLE_H
#define PB_RENDER_UPSAMPLE_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/estimate/estimator.h"
#include "render/scene/passes.h"
#include "render/render.h"

typedef struct pb_upsample pb_upsample;

/* levels 1 .. PB_UPS_MAX_LEVELS (shared/pb_upsample.h); band_pixels: the
 * largest band. */
pb_result pb_upsample_create(pb_gpu *g, uint32_t levels, uint32_t band_pixels, pb_upsample **out);
/* Zeroes the counters (the statistics sum over a frame's bands and samples). */
pb_result pb_upsample_reset(pb_gpu *g, pb_upsample *u);
/* caustics: the map has caustic photons (the full-resolution pass then
 * traverses at every pixel). */
pb_result pb_upsample_bind(pb_gpu *g, pb_upsample *u, pb_estimator *est, const pb_pass_setup *ps,
                           const pb_gpu_buffer *photon_accum, int caustics);
/* The estimate of sample `sample_index` over the band (width x pixels /
 * width) into the open command buffer: the levels, the compose, the
 * full-resolution rest; barriers between them. flags: PB_GATHER_NO_BEAUTY. */
pb_result pb_upsample_record(pb_gpu *g, pb_upsample *u, pb_estimator *est, uint32_t sample_index, uint32_t width,
                             uint32_t pixels, uint32_t flags);
/* Named statistics since the last reset (read back): upsample_levels,
 * upsample_coarse (estimates at level L), upsample_recomputed (estimates at
 * the finer levels), upsample_interpolated, upsample_full_res (pixels the
 * full-resolution pass traversed at), upsample_estimates (their sum: the
 * estimate's invocations that traversed the photon LBVH), upsample_diffuse
 * (pixels shaded from the irradiance), per sample summed. */
uint32_t pb_upsample_stats(pb_gpu *g, pb_upsample *u, pb_tracer_stat *out, uint32_t max);
/* The frame's hook after its last sample: those statistics appended to the
 * estimator's (pb_render_stats.estimator_stats, while there is room). */
void pb_upsample_stats_add(pb_gpu *g, pb_upsample *u, pb_render_stats *st);
void pb_upsample_destroy(pb_gpu *g, pb_upsample *u);

#endif
