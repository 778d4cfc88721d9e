/* The per-pixel targets of a frame: every buffer a band of
 * pixels needs on the GPU, created once per band size and feature set and
 * kept by the frame context (render.h) for the frames of a sequence:
 *   frame   pb_gpu_frame, the passes' constants
 *   gbuf    pb_gpu_gbuffer per pixel (gbuffer.comp -> direct.comp, gather.comp)
 *   accum   pb_gpu_accum per pixel: sums over samples
 *   paccum  pb_gpu_photon_accum per pixel (photon stages on)
 *   pnmap   pb_gpu_photon_nmap per pixel (scenes with normal maps)
 *   planes  the resolved AOVs (shared/pb_resolve.h): what the readback
 *           (readback.h) brings to the host, host-visible; pplanes those
 *           of the photon stages
 *   guard   the resolve's count of non-finite values replaced
 *   kpd     the resolve's sums for k_PD over the frame (pb_gpu_resolve_kpd)
 * Sizes never exceed the device's storage-buffer range: frame.c picks the
 * band so that the largest per-pixel target fits. */
#ifndef PB_RENDER_TARGETS_H
#define PB_RENDER_TARGETS_H

#include "gpu/gpu.h"

typedef struct pb_frame_targets {
  uint32_t band_pixels;
  int photons, nmap;
  uint32_t channels; /* floats per pixel in planes (PB_RESOLVE_*_CHANNELS) */
  pb_gpu_buffer frame, gbuf, accum, paccum, pnmap, planes, pplanes, guard, kpd;
  /* Frames in flight (render.h pb_render_desc.in_flight): the readback's
   * staging ring, PB_READBACK_RING copies of planes and pplanes in
   * host-cached memory, made on first use (pb_frame_targets_ring). A frame's
   * last submission copies its planes into slot i; the host reads slot i
   * while the next frame's submission writes the planes and slot i + 1. */
  pb_gpu_buffer ring[2][2]; /* [slot][0: planes, 1: pplanes] */
  int ring_made;
} pb_frame_targets;

enum { PB_READBACK_RING = 2 };

pb_result pb_frame_targets_ring(pb_gpu *g, pb_frame_targets *t);

/* Bytes per pixel of the largest target (the band's limit). */
uint64_t pb_frame_targets_max_pixel_bytes(void);
pb_result pb_frame_targets_create(pb_gpu *g, uint32_t band_pixels, int photons, int nmap, pb_frame_targets *out);
void pb_frame_targets_destroy(pb_gpu *g, pb_frame_targets *t);

/* A still run's running means on the GPU (shaders/
 * accumulate.comp, shared/pb_accumulate.h): the sequence's target, made
 * once per size, PB_ACCUM_FLOATS floats a pixel; frame.c records the pass
 * after eq. 20 in a frame's last submission when the frame is one band on
 * the GPU path (pb_render_io.still_sum), so a still camera's refinement
 * keeps nothing on the host. */
typedef struct pb_still_sum {
  pb_gpu_buffer sum;
  pb_gpu_pipeline pipe;
  uint32_t pixels;
  uint32_t frames;       /* in the means (the sequence sets it: 0 restarts the run) */
  int caustic_filtered;  /* caustics have their own temporal filter: kept out of the mean */
} pb_still_sum;

pb_result pb_still_sum_create(pb_gpu *g, uint32_t pixels, int caustic_filtered, pb_still_sum *out);
void pb_still_sum_destroy(pb_gpu *g, pb_still_sum *a); /* accepts a zeroed one */
/* Points the pass at the frame's planes (before pb_gpu_begin). */
pb_result pb_still_sum_bind(pb_gpu *g, pb_still_sum *a, const pb_frame_targets *t);
/* Records the pass over the band (pixels == a->pixels) with a->frames
 * frames in the means. */
pb_result pb_still_sum_record(pb_gpu *g, pb_still_sum *a, const pb_frame_targets *t, uint32_t pixels);

#endif
