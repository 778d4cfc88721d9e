/* kNN photon mapping behind the estimator interface (estimator.h): seed 000
 * section 3.1, the baseline of its Table 2. The photon LBVH of lbvh.c is
 * built for every map exactly as for the LBVH gather (the same passes,
 * timestamps and statistics; its boxes hold the hit points, so it serves a
 * nearest-neighbour search as well), then shaders/estimate/knn.comp finds, at every
 * G-buffer surface, the k nearest hits within r_max with a bounded max-heap
 * and evaluates eq. 1 with the k-th distance as the one bandwidth.
 *
 * k: desc.knn.k, default PB_KNN_K_DEFAULT = 64, the k_PD the LBVH gather
 * reaches at the default smoothing (photon.h: k_PD 50-85 on cornell_box and
 * spot_room at s = 2.5), where the paper finds equal quality (k_PM ~ k_PD;
 * bench/README.md "kNN against the LBVH gather" measures it here).
 * r_max: desc.knn.r_max, else the tracer's footprint clamp (18 photon
 * spacings, photon.h), else (maps made by the host) the scene's diagonal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/estimate/estimator.h"
#include "render/scene/passes.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_knn.h"
#include "shaders/knn.spv.h"
#include "shaders/knn_blender.spv.h"
#include "shaders/knn_rq.spv.h"
#include "shaders/knn_rq_blender.spv.h"

/* llvmpipe's loop limiter (Mesa gallivm, lp_bld_ir_common.c): 65535 back
 * edges per SIMD vector over ALL the shader's loops together, never reset;
 * past it every loop leaves after one iteration (knn.comp SC_BUDGET). The
 * search is one loop of one step per iteration, so it may take this many
 * less the others' share: the 4 edge rays' BVH traversals (PB_EDGES_MAX in
 * kernel_edges.glsl; a few hundred steps in these scenes, reserved 8192),
 * the k iterations of eq. 1's sum and the <= 16 sift steps a search may
 * finish past its bound. */
enum { PB_KNN_LLVMPIPE_LIMIT = 65535, PB_KNN_LLVMPIPE_RESERVE = 8192, PB_KNN_SIFT_PAST_BOUND = 16 };

typedef struct knn {
  pb_photon_estimator *lbvh; /* the build */
  uint32_t k;
  float r_max_desc, r_max_map, scene_diag, r_max; /* r_max: of the current map */
  int no_edge_correction;
  pb_gpu_pipeline pipe;
  uint32_t spec[PB_SPEC_KNN_COUNT];
  uint32_t build; /* pb_kernel_select's */
  int ready;
} knn;

static float diagonal(const pb_scene *s) {
  double e = 0;
  for (int k = 0; k < 3; ++k) {
    double d = (double)s->bounds_max[k] - s->bounds_min[k];
    if (isfinite(d)) e += d * d;
  }
  return e > 0 ? (float)sqrt(e) : 1.0f;
}

static void knn_destroy(pb_gpu *g, void *impl) {
  knn *e = impl;
  if (!e) return;
  pb_gpu_pipeline_destroy(g, &e->pipe);
  pb_photon_estimator_destroy(g, e->lbvh);
  free(e);
}

static pb_result knn_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, void **impl) {
  *impl = NULL;
  if (desc->knn.k > PB_KNN_K_MAX)
    return pb_fail(PB_ERR_USAGE, "render: kNN k = %u (1..%u)", desc->knn.k, (unsigned)PB_KNN_K_MAX);
  if (desc->knn.r_max < 0.0f || !isfinite(desc->knn.r_max))
    return pb_fail(PB_ERR_USAGE, "render: kNN r_max %g (a positive length, m)", desc->knn.r_max);
  knn *e = calloc(1, sizeof *e);
  if (!e) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the kNN estimator");
  e->k = desc->knn.k ? desc->knn.k : PB_KNN_K_DEFAULT;
  e->r_max_desc = desc->knn.r_max;
  e->no_edge_correction = desc->lbvh.no_edge_correction;
  e->scene_diag = diagonal(s);
  pb_photon_estimate_desc ld = desc->lbvh;
  pb_result r = pb_photon_estimator_create(g, s, &ld, &e->lbvh);
  if (r != PB_OK) {
    knn_destroy(g, e);
    return r;
  }
  *impl = e;
  return PB_OK;
}

static void knn_update(void *impl, const pb_scene *s) {
  knn *e = impl;
  pb_photon_estimator_update(e->lbvh, s);
  e->scene_diag = diagonal(s);
}

static pb_result knn_begin_map(pb_gpu *g, void *impl, const pb_photon_map *map, const pb_estimator_map_info *info) {
  knn *e = impl;
  /* The progressive footprint scale sizes the LBVH's boxes only: the kNN
   * bandwidth comes from k. */
  pb_photon_estimator_set_footprint_scale(e->lbvh, info->footprint_scale);
  e->r_max_map = info->r_max > 0.0f && isfinite(info->r_max) ? info->r_max : 0.0f;
  e->r_max = e->r_max_desc > 0.0f ? e->r_max_desc : e->r_max_map > 0.0f ? e->r_max_map : e->scene_diag;
  e->ready = 0;
  return pb_photon_estimator_prepare(g, e->lbvh, map);
}

static pb_result knn_record_build(pb_gpu *g, void *impl, uint32_t ts_slot) {
  return pb_photon_estimator_record_build(g, ((knn *)impl)->lbvh, ts_slot);
}

static void knn_build_done(pb_gpu *g, void *impl, uint32_t ts_slot, double *gpu_ms) {
  pb_photon_estimator_build_done(g, ((knn *)impl)->lbvh, ts_slot, gpu_ms);
}

static pb_result knn_bind(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                          const pb_gpu_buffer *photon_nmap) {
  knn *e = impl;
  pb_result r;
  uint32_t spec[PB_SPEC_KNN_COUNT] = {0};
  memcpy(spec, ps->spec, PB_SPEC_SHADING_COUNT * sizeof *spec); /* scene.glsl's ids 0-5, as the gather's */
  spec[PB_SPEC_NORMAL_MAPS] = ps->normal_maps ? 1u : 0u;
  spec[PB_SPEC_KNN_K] = e->k;
  /* llvmpipe's loop limiter (above; knn.comp SC_BUDGET). */
  spec[PB_SPEC_KNN_BUDGET] =
      pb_gpu_get_limits(g)->driver_id == VK_DRIVER_ID_MESA_LLVMPIPE
          ? (uint32_t)(PB_KNN_LLVMPIPE_LIMIT - PB_KNN_LLVMPIPE_RESERVE - PB_KNN_SIFT_PAST_BOUND) - e->k
          : 0u;
  static const pb_kernel_builds kb = PB_KERNEL_BUILDS(knn);
  pb_gpu_pipeline_desc d = {
      .name = "pass.knn",
      .binding_count = PB_KNN_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_knn_push),
      .spec = spec,
      .spec_count = PB_SPEC_KNN_COUNT,
  };
  uint32_t build = pb_kernel_select(&d, &kb, ps->blender, ps->accel != NULL, PB_BIND_NODES);
  if (e->pipe.pipeline && (memcmp(e->spec, spec, sizeof spec) != 0 || e->build != build))
    pb_gpu_pipeline_destroy(g, &e->pipe);
  if (!e->pipe.pipeline) {
    if ((r = pb_gpu_pipeline_create(g, &d, &e->pipe)) != PB_OK) return r;
    memcpy(e->spec, spec, sizeof spec);
    e->build = build;
  }
  pb_photon_lbvh_view v;
  pb_photon_estimator_lbvh(e->lbvh, &v);
  if (!v.photons->buffer) return pb_fail(PB_ERR_INTERNAL, "knn: bound before any LBVH build");
  const pb_gpu_buffer *b[PB_KNN_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i]; /* the scene's 15; not the world's */
  b[PB_KNN_BIND_PHOTONS] = v.photons;
  b[PB_KNN_BIND_NODES] = v.nodes;
  b[PB_KNN_BIND_INFO] = v.info;
  b[PB_KNN_BIND_ACCUM] = photon_accum;
  b[PB_KNN_BIND_NMAP] = photon_nmap ? photon_nmap : photon_accum; /* never read without normal maps */
  if ((r = pb_kernel_bind(g, &e->pipe, b, PB_KNN_BIND_COUNT, ps->accel)) != PB_OK) return r;
  e->ready = 1;
  return PB_OK;
}

static pb_result knn_record(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t pixels, uint32_t flags) {
  knn *e = impl;
  if (!e->ready) return pb_fail(PB_ERR_INTERNAL, "knn: recorded before it was bound to a built map");
  /* Edge renormalisation as far as the search reaches, where that is known
   * (the tracer's r_max or the description's; not the scene diagonal of a
   * host map, as the LBVH gather leaves it off there). */
  float reach = e->no_edge_correction ? 0.0f : (e->r_max_desc > 0.0f ? e->r_max_desc : e->r_max_map);
  pb_gpu_knn_push push = {.sample_index = sample_index, .flags = flags, .r_max = e->r_max, .edge_reach = reach};
  return pb_gpu_dispatch(g, &e->pipe, &push, pixels);
}

static uint32_t knn_stats(pb_gpu *g, void *impl, pb_tracer_stat *out, uint32_t max) {
  knn *e = impl;
  pb_photon_estimate_stats es;
  if (max < 3 || pb_photon_estimator_stats(g, e->lbvh, &es) != PB_OK) return 0;
  out[0] = (pb_tracer_stat){"k", e->k, 0};
  out[1] = (pb_tracer_stat){"r_max", e->r_max, 0};
  /* Queries whose search was cut short (the traversal stack, or the loop
   * budget on llvmpipe: knn.comp SC_BUDGET), of the last map's last sample
   * pass... summed over the passes since its build. */
  out[2] = (pb_tracer_stat){"queries_cut_short", es.stack_overflow, 1};
  return 3 + pb_estimator_lbvh_named_stats(&es, out + 3, max - 3);
}

const pb_estimator_ops pb_estimator_knn_ops = {
    .name = "knn",
    .create = knn_create,
    .update = knn_update,
    .begin_map = knn_begin_map,
    .record_build = knn_record_build,
    .build_done = knn_build_done,
    .bind = knn_bind,
    .record = knn_record,
    .stats = knn_stats,
    .destroy = knn_destroy,
};
