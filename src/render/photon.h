/* The photon stages of a frame, as two replaceable parts behind small
 * interfaces (ARCHITECTURE.md: later work adds kNN, screen-space splatting,
 * the view-sample hierarchy and an image-space tracer):
 *
 *   tracer:    scene -> photon map (pb_gpu_photon records on the device)
 *              (RSM first bounce, power-proportional budget, differentials,
 *               Russian roulette; seeds 000 section 4, 001 section 24.2)
 *   estimator: photon map + shading points -> indirect and caustic radiance
 *              (LBVH over footprints + gather, seed 000 sections 5-6)
 *
 * frame.c orders them after `direct`. Both allocate from the photon budget
 * and the scene, never from fixed maxima. */
#ifndef PB_RENDER_PHOTON_H
#define PB_RENDER_PHOTON_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "scene/scene.h"

/* The photon map one tracer iteration produced, resident on the device. */
typedef struct pb_photon_map {
  pb_gpu_buffer photons;      /* pb_gpu_photon[capacity] */
  pb_gpu_buffer counts;       /* pb_gpu_photon_counts */
  uint32_t capacity;
  /* Host copies of the counters, read back after the trace. */
  uint32_t stored, caustic, emitted, overflow;
} pb_photon_map;

/* Zero means default for every field. */
typedef struct pb_photon_trace_desc {
  uint32_t photons;           /* paths emitted per iteration; 0: 2^18 */
  uint32_t max_bounces;       /* stored diffuse bounces per path; 0: 3 */
  float smoothing;            /* s for diffuse photons; 0: 1 */
  float smoothing_caustic;    /* s for caustic photons; 0: 5 (seed 000) */
  float r_max;                /* footprint radius clamp, metres; 0: 5 % of the
                                 scene's bounding radius */
} pb_photon_trace_desc;

typedef struct pb_photon_tracer pb_photon_tracer;

pb_result pb_photon_tracer_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs,
                                  const pb_photon_trace_desc *desc, pb_photon_tracer **out);
/* Traces one iteration with seed (seed, iteration) into `map` (created on the
 * first call, reused after). gpu_ms gets per-pass times (may be NULL). */
pb_result pb_photon_tracer_run(pb_gpu *g, pb_photon_tracer *t, uint64_t seed, uint32_t iteration,
                               pb_photon_map *map, double *gpu_ms);
void pb_photon_tracer_destroy(pb_gpu *g, pb_photon_tracer *t);
void pb_photon_map_destroy(pb_gpu *g, pb_photon_map *m);

#endif
