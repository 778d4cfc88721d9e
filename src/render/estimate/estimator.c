/* The density-estimator interface (estimator.h): the dispatch over each
 * kind's pb_estimator_ops, and `auto`.
 *
 * Which implementations are in the binary: each src/render/estimator_NAME.c
 * defines pb_estimator_NAME_ops, and CMakeLists.txt compiles this file with
 * PB_ESTIMATOR_HAVE_NAME=1 for every such file it globbed (lbvh is always
 * in). A kind without its file gets a table here whose create fails with
 * "estimator 'NAME' is not built in this binary". (Weak definitions here,
 * overridden by the implementation's strong one, do not work: pb is a static
 * archive, and the linker never extracts an archive member for a symbol that
 * a weak definition it already has satisfies, so the implementation would
 * silently never be linked.) */
#include "render/estimate/estimator.h"

#include <stdlib.h>
#include <string.h>

const char *const pb_estimator_names[] = {"lbvh", "knn", "splat", "vsch", "auto", NULL};

struct pb_estimator {
  const pb_estimator_ops *ops;
  void *impl;
  uint32_t kind; /* resolved: never PB_ESTIMATOR_AUTO */
};

/* ---- kinds not in this binary ---------------------------------------------- */

#if !PB_ESTIMATOR_HAVE_KNN || !PB_ESTIMATOR_HAVE_SPLAT || !PB_ESTIMATOR_HAVE_VSCH
static pb_result unbuilt(const char *name) {
  return pb_fail(PB_ERR_USAGE, "render: estimator '%s' is not built in this binary (no src/render/estimator_%s.c)",
                 name, name);
}
#endif
#define UNBUILT_OPS(NAME)                                                                                          \
  static pb_result unbuilt_create_##NAME(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *d, void **impl) { \
    (void)g, (void)s, (void)d;                                                                                     \
    *impl = NULL;                                                                                                  \
    return unbuilt(#NAME);                                                                                         \
  }                                                                                                                \
  static const pb_estimator_ops unbuilt_##NAME##_ops = {.name = #NAME, .create = unbuilt_create_##NAME};
#if !PB_ESTIMATOR_HAVE_KNN
UNBUILT_OPS(knn)
#define KNN_OPS (&unbuilt_knn_ops)
#else
#define KNN_OPS (&pb_estimator_knn_ops)
#endif
#if !PB_ESTIMATOR_HAVE_SPLAT
UNBUILT_OPS(splat)
#define SPLAT_OPS (&unbuilt_splat_ops)
#else
#define SPLAT_OPS (&pb_estimator_splat_ops)
#endif
#if !PB_ESTIMATOR_HAVE_VSCH
UNBUILT_OPS(vsch)
#define VSCH_OPS (&unbuilt_vsch_ops)
#else
#define VSCH_OPS (&pb_estimator_vsch_ops)
#endif

static const pb_estimator_ops *ops_of(uint32_t kind) {
  switch (kind) {
  case PB_ESTIMATOR_LBVH: return &pb_estimator_lbvh_ops;
  case PB_ESTIMATOR_KNN: return KNN_OPS;
  case PB_ESTIMATOR_SPLAT: return SPLAT_OPS;
  case PB_ESTIMATOR_VSCH: return VSCH_OPS;
  default: return NULL;
  }
}

int pb_estimator_built(uint32_t kind) {
  if (kind == PB_ESTIMATOR_AUTO) return 1;
  const pb_estimator_ops *o = ops_of(kind);
  return o && o->create && o->begin_map; /* the unbuilt tables have no begin_map */
}

/* ---- auto ------------------------------------------------------------------ */

/* The rule as measured (bench/run_bench.py --mode estimators, `make
 * bench-estimators`: the four estimators on the same photon maps of every
 * sample, 96 px, 2^16 paths a map, 1 / 4 / 16 maps, lavapipe; results in
 * bench/results/lavapipe/estimators/, BENCHMARKS.md "Density estimators
 * side by side"): the LBVH gather reaches each PSNR first on cornell_box,
 * cornell_caustics and spot_room; kNN is 2.1-3.4x slower at equal error;
 * splatting is as fast on spot_room but stays at 18-19 dB on
 * cornell_caustics whatever the photon count (a bias); the view-sample
 * hierarchy is 2.8-4.5x slower on lavapipe and ahead only on ring (25.0 dB
 * where the gather stays at 22.4 dB, 214-3124 photons stored: a sparse
 * caustic map), too few scenes to found a scene-dependent rule on. So auto
 * is the gather everywhere. */
const char *const pb_estimator_auto_rule =
    "lbvh on every scene: first to each PSNR on 3 of the 4 samples (knn 2-3.5x slower at equal error, "
    "splat biased on cornell_caustics, vsch ahead only on the sparse caustic map of ring; BENCHMARKS.md, "
    "density estimators side by side)";

uint32_t pb_estimator_resolve(const pb_scene *s, const pb_estimator_desc *desc) {
  uint32_t kind = desc ? desc->kind : PB_ESTIMATOR_LBVH;
  if (kind != PB_ESTIMATOR_AUTO) return kind;
  (void)s;
  return PB_ESTIMATOR_LBVH;
}

/* ---- the dispatch ---------------------------------------------------------- */

pb_result pb_estimator_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, pb_estimator **out) {
  *out = NULL;
  pb_estimator_desc d = desc ? *desc : (pb_estimator_desc){0};
  if (d.kind >= PB_ESTIMATOR_KIND_COUNT)
    return pb_fail(PB_ERR_USAGE, "render: estimator %u (lbvh, knn, splat, vsch or auto)", d.kind);
  d.kind = pb_estimator_resolve(s, &d);
  /* The screen-space estimators project photons through a planar camera
   * (splat_splat.comp's z^2 footprint, vsch's view tiles); depth of field
   * is their pinhole's (the indirect light they splat stays sharp). */
  if ((d.kind == PB_ESTIMATOR_SPLAT || d.kind == PB_ESTIMATOR_VSCH) && s)
    for (uint32_t i = 0; i < s->camera_count; ++i)
      if (s->cameras[i].panorama != PB_CAMERA_PANO_NONE)
        return pb_fail(PB_ERR_USAGE, "render: estimator %s needs a perspective or orthographic camera; camera '%s' "
                       "is panoramic (use lbvh or knn)", pb_estimator_names[d.kind], s->cameras[i].name);
  const pb_estimator_ops *ops = ops_of(d.kind);
  pb_estimator *e = calloc(1, sizeof *e);
  if (!e) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the estimator");
  e->ops = ops;
  e->kind = d.kind;
  pb_result r = ops->create(g, s, &d, &e->impl);
  if (r != PB_OK) {
    free(e);
    return r;
  }
  *out = e;
  return PB_OK;
}

void pb_estimator_update(pb_estimator *e, const pb_scene *s) {
  if (e && e->ops->update) e->ops->update(e->impl, s);
}

pb_result pb_estimator_begin_map(pb_gpu *g, pb_estimator *e, const pb_photon_map *map,
                                 const pb_estimator_map_info *info) {
  pb_estimator_map_info i = info ? *info : (pb_estimator_map_info){0};
  return e->ops->begin_map(g, e->impl, map, &i);
}

pb_result pb_estimator_record_build(pb_gpu *g, pb_estimator *e, uint32_t ts_slot) {
  return e->ops->record_build ? e->ops->record_build(g, e->impl, ts_slot) : PB_OK;
}

void pb_estimator_build_done(pb_gpu *g, pb_estimator *e, uint32_t ts_slot, double *gpu_ms) {
  if (gpu_ms) *gpu_ms = 0;
  if (e->ops->build_done) e->ops->build_done(g, e->impl, ts_slot, gpu_ms);
}

pb_result pb_estimator_bind(pb_gpu *g, pb_estimator *e, const struct pb_pass_setup *ps,
                            const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *photon_nmap) {
  return e->ops->bind(g, e->impl, ps, photon_accum, photon_nmap);
}

pb_result pb_estimator_record(pb_gpu *g, pb_estimator *e, uint32_t sample_index, uint32_t pixels, uint32_t flags) {
  return e->ops->record(g, e->impl, sample_index, pixels, flags);
}

uint32_t pb_estimator_stats(pb_gpu *g, pb_estimator *e, pb_tracer_stat *out, uint32_t max) {
  if (!e || !e->ops->stats) return 0;
  uint32_t n = e->ops->stats(g, e->impl, out, max);
  return n < max ? n : max;
}

void pb_estimator_stats_add(pb_gpu *g, pb_estimator *e, pb_render_stats *st) {
  pb_tracer_stat now[PB_TRACER_MAX_STATS];
  uint32_t n = pb_estimator_stats(g, e, now, PB_TRACER_MAX_STATS);
  st->estimator = pb_estimator_name(e);
  pb_tracer_stats_merge(st->estimator_stats, &st->estimator_stat_count, now, n, 0);
}

void pb_estimator_stats_final(pb_gpu *g, pb_estimator *e, pb_render_stats *st) {
  pb_tracer_stat now[PB_TRACER_MAX_STATS];
  uint32_t n = pb_estimator_stats(g, e, now, PB_TRACER_MAX_STATS);
  pb_tracer_stats_merge(st->estimator_stats, &st->estimator_stat_count, now, n, 1);
}

const char *pb_estimator_name(const pb_estimator *e) { return e ? e->ops->name : "none"; }

int pb_estimator_can_upsample(const pb_estimator *e) {
  return e && e->ops->bind_upsample && e->ops->record_upsample;
}

pb_result pb_estimator_bind_upsample(pb_gpu *g, pb_estimator *e, const struct pb_pass_setup *ps,
                                     const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *irradiance,
                                     const pb_gpu_buffer *list) {
  if (!pb_estimator_can_upsample(e))
    return pb_fail(PB_ERR_USAGE, "render: --upsample-levels needs --estimator lbvh (not %s)", pb_estimator_name(e));
  return e->ops->bind_upsample(g, e->impl, ps, photon_accum, irradiance, list);
}

pb_result pb_estimator_record_upsample(pb_gpu *g, pb_estimator *e, uint32_t sample_index, uint32_t invocations,
                                       uint32_t flags, uint32_t level) {
  if (!pb_estimator_can_upsample(e))
    return pb_fail(PB_ERR_INTERNAL, "render: estimator %s has no up-sampling", pb_estimator_name(e));
  return e->ops->record_upsample(g, e->impl, sample_index, invocations, flags, level);
}

void pb_estimator_destroy(pb_gpu *g, pb_estimator *e) {
  if (!e) return;
  if (e->ops->destroy) e->ops->destroy(g, e->impl);
  free(e);
}
