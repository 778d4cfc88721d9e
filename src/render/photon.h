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

/* Statistics of the last pb_photon_tracer_run (photon_trace.c). */
typedef struct pb_photon_trace_stats {
  uint32_t guarded;    /* divisions guarded (grazing hits, cos_t -> 0,
                          degenerate footprints) + records dropped as
                          non-finite: nothing non-finite is ever stored */
  uint32_t absorbed;   /* paths ended by Russian roulette */
  uint32_t escaped;    /* paths that left the scene */
  uint32_t photons;    /* paths per iteration (the budget) */
  float delta;         /* global spacing Delta = 2 sqrt(pi / photons) */
} pb_photon_trace_stats;
void pb_photon_tracer_stats(const pb_photon_tracer *t, pb_photon_trace_stats *out);

/* The budget split (seed 001 24.2.1): photons[i] paths for light i, in
 * proportion to the luminance of pb_light_power (directional lights over the
 * disc of the scene's bounding radius), largest remainders, summing to
 * `total` when any light has power. first[i] is the light's first path. */
void pb_photon_split_budget(const pb_scene *s, uint32_t total, uint32_t *photons, uint32_t *first);

/* Tests only: trace paths in triples whose members 1 and 2 step the
 * (eq.-8-scaled) parameters of decision `depth` (0: emission, k: the k-th
 * interaction) by h (records' `path` is the invocation, 3 j + member); flags:
 * PB_PHOTON_PARAM_RAW_FOOTPRINT stores Delta dP (no -3/4 compression, s or
 * r_max), PB_PHOTON_PARAM_STORE_FIRST stores the first hit too. h = 0 and
 * flags = 0 turn it off. */
void pb_photon_tracer_debug(pb_photon_tracer *t, float h, uint32_t depth, uint32_t flags);
void pb_photon_map_destroy(pb_gpu *g, pb_photon_map *m);

#endif
