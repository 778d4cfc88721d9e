/* The LBVH gather behind the estimator interface (estimator.h): seed 000
 * sections 5-6, today's pb_photon_estimator (lbvh.c: the build; gather.c:
 * the gather pass) unchanged, its settings from pb_estimator_desc.lbvh and
 * its statistics named. */
#include <string.h>

#include "render/estimate/estimator.h"

static pb_result lbvh_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, void **impl) {
  pb_photon_estimator *e = NULL;
  pb_result r = pb_photon_estimator_create(g, s, &desc->lbvh, &e);
  *impl = e;
  return r;
}

static void lbvh_update(void *impl, const pb_scene *s) { pb_photon_estimator_update(impl, s); }

static pb_result lbvh_begin_map(pb_gpu *g, void *impl, const pb_photon_map *map, const pb_estimator_map_info *info) {
  pb_photon_estimator *e = impl;
  pb_photon_estimator_set_footprint_scale(e, info->footprint_scale);
  pb_photon_estimator_set_edge_reach(e, info->r_max); /* 0 (maps made by the host): off */
  return pb_photon_estimator_prepare(g, e, map);
}

static pb_result lbvh_record_build(pb_gpu *g, void *impl, uint32_t ts_slot) {
  return pb_photon_estimator_record_build(g, impl, ts_slot);
}

static void lbvh_build_done(pb_gpu *g, void *impl, uint32_t ts_slot, double *gpu_ms) {
  pb_photon_estimator_build_done(g, impl, ts_slot, gpu_ms);
}

static pb_result lbvh_bind(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                           const pb_gpu_buffer *photon_nmap) {
  return pb_photon_estimator_bind(g, impl, ps, photon_accum, photon_nmap);
}

static pb_result lbvh_record(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t pixels, uint32_t flags) {
  return pb_photon_estimator_record(g, impl, sample_index, pixels, flags);
}

uint32_t pb_estimator_lbvh_named_stats(const pb_photon_estimate_stats *es, pb_tracer_stat *out, uint32_t max) {
  /* Counts of the last map; timings summed over the frame's maps (each only
   * where the device has timestamps). */
  pb_tracer_stat all[16];
  uint32_t n = 0;
  all[n++] = (pb_tracer_stat){"photons", es->photons, 0};
  all[n++] = (pb_tracer_stat){"t_auto", es->t_auto, 0};
  all[n++] = (pb_tracer_stat){"leaf_size", es->leaf_size, 0};
  all[n++] = (pb_tracer_stat){"leaves", es->leaves, 0};
  all[n++] = (pb_tracer_stat){"area_sum", es->area_sum, 0};
  all[n++] = (pb_tracer_stat){"scene_area", es->scene_area, 0};
  all[n++] = (pb_tracer_stat){"stack_overflow", es->stack_overflow, 0};
  const struct {
    const char *name;
    double v;
  } ms[] = {{"build_ms", es->build_ms}, {"bounds_ms", es->bounds_ms}, {"morton_ms", es->morton_ms},
            {"sort_ms", es->sort_ms}, {"climb_ms", es->climb_ms}};
  for (size_t i = 0; i < sizeof ms / sizeof *ms; ++i)
    if (ms[i].v >= 0) all[n++] = (pb_tracer_stat){ms[i].name, ms[i].v, 1};
  if (n > max) n = max;
  memcpy(out, all, n * sizeof *out);
  return n;
}

static uint32_t lbvh_stats(pb_gpu *g, void *impl, pb_tracer_stat *out, uint32_t max) {
  pb_photon_estimate_stats es;
  /* A failed read-back (a lost device) reports nothing; the frame's next
   * submission fails with the device's error. */
  if (pb_photon_estimator_stats(g, impl, &es) != PB_OK) return 0;
  return pb_estimator_lbvh_named_stats(&es, out, max);
}

static void lbvh_destroy(pb_gpu *g, void *impl) { pb_photon_estimator_destroy(g, impl); }

static pb_result lbvh_bind_upsample(pb_gpu *g, void *impl, const struct pb_pass_setup *ps,
                                    const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *irradiance,
                                    const pb_gpu_buffer *list) {
  return pb_photon_estimator_bind_upsample(g, impl, ps, photon_accum, irradiance, list);
}

static pb_result lbvh_record_upsample(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t invocations,
                                      uint32_t flags, uint32_t level) {
  return pb_photon_estimator_record_upsample(g, impl, sample_index, invocations, flags, level);
}

const pb_estimator_ops pb_estimator_lbvh_ops = {
    .name = "lbvh",
    .create = lbvh_create,
    .update = lbvh_update,
    .begin_map = lbvh_begin_map,
    .record_build = lbvh_record_build,
    .build_done = lbvh_build_done,
    .bind = lbvh_bind,
    .record = lbvh_record,
    .stats = lbvh_stats,
    .destroy = lbvh_destroy,
    .bind_upsample = lbvh_bind_upsample,
    .record_upsample = lbvh_record_upsample,
};
