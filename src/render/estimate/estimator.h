/* The photon density estimator, one interface over its implementations
 * (ARCHITECTURE.md: "replaceable stages behind small interfaces"):
 *
 *   lbvh   seed 000 sections 5-6: photon footprints in a linear BVH rebuilt
 *          per photon map, gathered by traversal at every G-buffer surface
 *          (lbvh.c, gather.c: pb_photon_estimator);
 *   knn    seed 000 section 3.1, its Table 2 baseline: the k nearest photons
 *          of each shading point, radius from the k-th;
 *   splat  seed 001 section 24.3 (eq. 2-9): photons splatted into screen
 *          space with a kernel sized by ray length and tile density;
 *   vsch   seed 004: photons traversed through a cluster hierarchy built
 *          over the view samples every frame, normal cones;
 *   auto   the frame picks one from the scene and the settings.
 *
 * Every implementation reads the photon records of a pb_photon_map (either
 * tracer, tracer.h) and adds its estimate of the reflected photon radiance
 * into the frame's per-pixel pb_gpu_photon_accum sums, so the resolve, the
 * filters and eq. 20 after it do not know which one ran.
 *
 * The frame's calls, per photon map (iteration) then per sample:
 *   begin_map    buffers for map->capacity, descriptors; no command buffer
 *                open. `info` carries what the tracer knows of the map.
 *   record_build into the open command buffer, after the tracer's record
 *                (same submission; the stored count is on the GPU in
 *                map->counts where the map has it, else map->stored),
 *                timestamp slots ts_slot .. ts_slot + PB_ESTIMATOR_TS_SLOTS-1;
 *   build_done   after that submission: the build's GPU time (-1: none);
 *   bind         to the frame's pass buffers and accumulators (after every
 *                build: buffers may have been reallocated);
 *   record       the estimate of one sample over `pixels` pixels into the
 *                open command buffer, after the G-buffer pass of that
 *                sample.
 * Statistics are named (pb_tracer_stat, render.h) so that `render --json`
 * reports each estimator's own under "estimator": {"name": ..., ...}. */
#ifndef PB_RENDER_ESTIMATOR_H
#define PB_RENDER_ESTIMATOR_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/estimate/estimator_desc.h" /* pb_estimator_kind, pb_estimator_desc */
#include "render/photon/photon.h"
#include "render/render.h"
#include "scene/scene.h"

struct pb_pass_setup;

/* Timestamp slots an estimator may use in record_build. */
enum { PB_ESTIMATOR_TS_SLOTS = 5, PB_ESTIMATOR_MAX_STATS = 24 };

/* What the tracer knows of the map about to be estimated. */
typedef struct pb_estimator_map_info {
  float r_max;           /* the tracer's largest footprint radius, m; 0: unknown
                            (maps made by the host) */
  float footprint_scale; /* progressive bandwidth of this iteration; 0: 1 */
} pb_estimator_map_info;

typedef struct pb_estimator_ops {
  const char *name; /* "lbvh", "knn", "splat", "vsch" */
  pb_result (*create)(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, void **impl);
  void (*update)(void *impl, const pb_scene *s); /* a new pose of the same scene */
  pb_result (*begin_map)(pb_gpu *g, void *impl, const pb_photon_map *map, const pb_estimator_map_info *info);
  pb_result (*record_build)(pb_gpu *g, void *impl, uint32_t ts_slot);
  void (*build_done)(pb_gpu *g, void *impl, uint32_t ts_slot, double *gpu_ms);
  pb_result (*bind)(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                    const pb_gpu_buffer *photon_nmap);
  pb_result (*record)(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t pixels, uint32_t flags);
  /* Named statistics of the last map (read back if needed): up to max
   * written, their number returned. */
  uint32_t (*stats)(pb_gpu *g, void *impl, pb_tracer_stat *out, uint32_t max);
  void (*destroy)(pb_gpu *g, void *impl);
  /* Optional: the estimate of seed 003's multi-level up-sampling
   * (render/estimate/upsample.h): bound to the frame's buffers plus the irradiance
   * plane and the pixel list (after bind), recorded over `invocations` work
   * items with PB_GATHER_UPS_LIST (level `level`'s list) or
   * PB_GATHER_UPS_REST (every pixel). NULL: this estimator cannot be
   * up-sampled (only the LBVH gather can). */
  pb_result (*bind_upsample)(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                             const pb_gpu_buffer *irradiance, const pb_gpu_buffer *list);
  pb_result (*record_upsample)(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t invocations, uint32_t flags,
                               uint32_t level);
} pb_estimator_ops;

typedef struct pb_estimator pb_estimator;

pb_result pb_estimator_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, pb_estimator **out);
void pb_estimator_update(pb_estimator *e, const pb_scene *s);
pb_result pb_estimator_begin_map(pb_gpu *g, pb_estimator *e, const pb_photon_map *map,
                                 const pb_estimator_map_info *info);
pb_result pb_estimator_record_build(pb_gpu *g, pb_estimator *e, uint32_t ts_slot);
void pb_estimator_build_done(pb_gpu *g, pb_estimator *e, uint32_t ts_slot, double *gpu_ms);
pb_result pb_estimator_bind(pb_gpu *g, pb_estimator *e, const struct pb_pass_setup *ps,
                            const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *photon_nmap);
pb_result pb_estimator_record(pb_gpu *g, pb_estimator *e, uint32_t sample_index, uint32_t pixels, uint32_t flags);
uint32_t pb_estimator_stats(pb_gpu *g, pb_estimator *e, pb_tracer_stat *out, uint32_t max);
/* The frame's hooks (frame.c): stats_add after each map's build adds that
 * map's statistics to the frame's (summed ones added, the others replaced;
 * the estimator's name); stats_final after the frame's last sample reads
 * the ones not summed again (an estimator whose work is per sample, vsch,
 * counts its last sample; the LBVH's per-map counts come back unchanged). */
void pb_estimator_stats_add(pb_gpu *g, pb_estimator *e, pb_render_stats *st);
void pb_estimator_stats_final(pb_gpu *g, pb_estimator *e, pb_render_stats *st);
const char *pb_estimator_name(const pb_estimator *e);
/* 1 where the estimator has the up-sampling's estimate (bind_upsample). */
int pb_estimator_can_upsample(const pb_estimator *e);
pb_result pb_estimator_bind_upsample(pb_gpu *g, pb_estimator *e, const struct pb_pass_setup *ps,
                                     const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *irradiance,
                                     const pb_gpu_buffer *list);
pb_result pb_estimator_record_upsample(pb_gpu *g, pb_estimator *e, uint32_t sample_index, uint32_t invocations,
                                       uint32_t flags, uint32_t level);
void pb_estimator_destroy(pb_gpu *g, pb_estimator *e);

/* The implementations (estimator.c dispatches through them). */
extern const pb_estimator_ops pb_estimator_lbvh_ops;
extern const pb_estimator_ops pb_estimator_knn_ops;
extern const pb_estimator_ops pb_estimator_splat_ops;
extern const pb_estimator_ops pb_estimator_vsch_ops;

/* For implementations that build the photon LBVH (lbvh, knn): its
 * statistics named (photons, t_auto, leaf_size, leaves, area_sum,
 * scene_area, stack_overflow of the last map; build_ms, bounds_ms,
 * morton_ms, sort_ms, climb_ms summed, each only with timestamps). */
uint32_t pb_estimator_lbvh_named_stats(const pb_photon_estimate_stats *es, pb_tracer_stat *out, uint32_t max);

/* The names of pb_estimator_kind, in order, NULL-terminated (the CLI's
 * --estimator choices). */
extern const char *const pb_estimator_names[];

/* Which implementations this binary has: 1 where the kind's
 * src/render/estimator_NAME.c was built (CMakeLists.txt defines
 * PB_ESTIMATOR_HAVE_NAME for estimator.c; lbvh and auto always). The
 * others' create fails with "estimator 'NAME' is not built in this binary". */
int pb_estimator_built(uint32_t kind);
/* The kind `auto` (or any kind) resolves to for scene s; the rule, in
 * words, for `info` and docs/cli.md. */
uint32_t pb_estimator_resolve(const pb_scene *s, const pb_estimator_desc *desc);
extern const char *const pb_estimator_auto_rule;

#endif
