/* The photon tracer, one interface over its implementations (ARCHITECTURE.md:
 * "photon tracer behind one interface too"):
 *
 *   bvh     photon_trace.c as it is: every segment traced in the scene BVH
 *           (exact closest hits; seeds 000, 001);
 *   images  seed 003 (Yao et al. 2010): the same emission, scattering,
 *           differentials and records, every segment searched in k cube
 *           environment maps of the scene (image_maps.h) instead; the maps
 *           follow the scene's pose (rendered again per update, a swap of
 *           their centres every few updates).
 *
 * Both write pb_gpu_photon records into a pb_photon_map, so every density
 * estimator works with either. Statistics are named (pb_tracer_stat) so that
 * `render --json` and `info` report whatever a tracer counts. */
#ifndef PB_RENDER_TRACER_H
#define PB_RENDER_TRACER_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/photon/image_maps.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "scene/scene.h"

typedef enum pb_tracer_kind {
  PB_TRACER_BVH = 0,
  PB_TRACER_IMAGES = 1,
} pb_tracer_kind;

/* Zero means default for every field. */
typedef struct pb_tracer_desc {
  uint32_t kind;                 /* pb_tracer_kind; 0: BVH */
  pb_photon_trace_desc photon;   /* emission, scattering, footprints (both) */
  pb_image_maps_desc images;     /* PB_TRACER_IMAGES only */
} pb_tracer_desc;

typedef struct pb_tracer pb_tracer;

pb_result pb_tracer_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_tracer_desc *desc,
                           pb_tracer **out);
/* A new pose of the same scene (gs already updated). */
pb_result pb_tracer_update(pb_gpu *g, pb_tracer *t, const pb_scene *s);
/* One photon map for (seed, iteration) into `map` (pb_photon_tracer_run). */
pb_result pb_tracer_trace(pb_gpu *g, pb_tracer *t, uint64_t seed, uint32_t iteration, pb_photon_map *map,
                          double *gpu_ms);
/* The same in three steps, so the frame can record the trace and the LBVH
 * build into one submission (frame.c): prepare (bindings, constants, zeroed
 * counts), record (into the open command buffer, timestamps ts_slot and
 * ts_slot + 1), finish (after the submit: the counts and statistics). */
pb_result pb_tracer_prepare(pb_gpu *g, pb_tracer *t, uint64_t seed, uint32_t iteration, pb_photon_map *map);
pb_result pb_tracer_record(pb_gpu *g, pb_tracer *t, uint32_t ts_slot);
pb_result pb_tracer_finish(pb_gpu *g, pb_tracer *t, pb_photon_map *map, uint32_t ts_slot, double *gpu_ms);
/* "bvh" or "images". */
const char *pb_tracer_name(const pb_tracer *t);
/* The named statistics of the last trace (and of the maps): up to max
 * entries written, their number returned. */
uint32_t pb_tracer_stats(const pb_tracer *t, pb_tracer_stat *out, uint32_t max);
/* The frame's hooks (frame.c), so that it never reaches inside a tracer:
 * r_max is the footprint clamp in use, metres (set when the tracer is made
 * or updated: pb_estimator_map_info.r_max); stats_add adds the statistics
 * of the map just traced to the frame's (the guarded divisions, the named
 * statistics: summed ones added, the others replaced; the tracer's name);
 * radius_histogram bins the footprint radii of `map` (just traced) into
 * st->radius_hist (pb_render_desc.radius_histogram: a download per map;
 * the host copy is the tracer's, kept for the next map). */
float pb_tracer_r_max(const pb_tracer *t);
void pb_tracer_stats_add(const pb_tracer *t, pb_render_stats *st);
pb_result pb_tracer_radius_histogram(pb_gpu *g, pb_tracer *t, const pb_photon_map *map, pb_render_stats *st);
/* The maps of an images tracer (NULL for bvh). */
pb_image_maps *pb_tracer_image_maps(const pb_tracer *t);
void pb_tracer_destroy(pb_gpu *g, pb_tracer *t);

/* The names of pb_tracer_kind, in order, NULL-terminated (the CLI's
 * --tracer choices). */
extern const char *const pb_tracer_names[];

#endif
