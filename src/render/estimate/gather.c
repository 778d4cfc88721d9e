/* The gather pass (shaders/estimate/gather.comp): eq. 1 of seed 000 at every
 * G-buffer surface, by traversal of the photon LBVH (lbvh.c). Bound to the
 * frame's scene buffers plus the sorted photons, the nodes, the build info
 * and the per-pixel photon accumulators. */
#include <math.h>
#include <string.h>

#include "render/estimate/estimator_internal.h"
#include "shaders/gather.spv.h"
#include "shaders/gather_blender.spv.h"
#include "shaders/gather_upsample.spv.h"
#include "shaders/gather_upsample_blender.spv.h"
#include "shaders/gather_rq.spv.h"
#include "shaders/gather_rq_blender.spv.h"
#include "shaders/gather_upsample_rq.spv.h"
#include "shaders/gather_upsample_rq_blender.spv.h"

pb_result pb_photon_estimator_bind(pb_gpu *g, pb_photon_estimator *e, const struct pb_pass_setup *ps,
                                   const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *photon_nmap) {
  pb_result r;
  uint32_t spec[PB_SPEC_COUNT] = {0};
  memcpy(spec, ps->spec, PB_SPEC_SHADING_COUNT * sizeof *spec); /* scene.glsl's ids 0-5; no lights here */
  spec[PB_SPEC_NORMAL_MAPS] = ps->normal_maps ? 1u : 0u;
  static const pb_kernel_builds k = PB_KERNEL_BUILDS(gather);
  pb_gpu_pipeline_desc d = {
      .name = "pass.gather",
      .binding_count = PB_GATHER_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_gather_push),
      .spec = spec,
      .spec_count = PB_SPEC_COUNT,
  };
  uint32_t build = pb_kernel_select(&d, &k, ps->blender, ps->accel != NULL, PB_BIND_NODES);
  if (e->gather.pipeline && (memcmp(e->gather_spec, spec, sizeof e->gather_spec) != 0 || e->gather_build != build))
    pb_gpu_pipeline_destroy(g, &e->gather);
  if (!e->gather.pipeline) {
    if ((r = pb_gpu_pipeline_create(g, &d, &e->gather)) != PB_OK) return r;
    memcpy(e->gather_spec, spec, sizeof e->gather_spec);
    e->gather_build = build;
  }
  if (!e->sorted.buffer) return pb_fail(PB_ERR_INTERNAL, "gather: bound before any LBVH build");
  const pb_gpu_buffer *b[PB_GATHER_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i]; /* the scene's 15; not the world's */
  b[PB_GATHER_BIND_PHOTONS] = &e->sorted;
  b[PB_GATHER_BIND_NODES] = &e->nodes;
  b[PB_GATHER_BIND_INFO] = &e->info;
  b[PB_GATHER_BIND_ACCUM] = photon_accum;
  /* Without normal maps the shader never reads it: any buffer will do. */
  b[PB_GATHER_BIND_NMAP] = photon_nmap ? photon_nmap : photon_accum;
  if ((r = pb_kernel_bind(g, &e->gather, b, PB_GATHER_BIND_COUNT, ps->accel)) != PB_OK) return r;
  e->gather_ready = 1;
  return PB_OK;
}

void pb_photon_estimator_set_edge_reach(pb_photon_estimator *e, float r_max) {
  e->edge_reach = r_max > 0.0f && isfinite(r_max) ? r_max : 0.0f;
}

pb_result pb_photon_estimator_record(pb_gpu *g, pb_photon_estimator *e, uint32_t sample_index,
                                     uint32_t pixels, uint32_t flags) {
  if (!e->gather_ready) return pb_fail(PB_ERR_INTERNAL, "gather: recorded before pb_photon_estimator_bind");
  pb_gpu_gather_push push = {.sample_index = sample_index,
                             .flags = flags | (e->desc.constant_kernel ? PB_GATHER_CONSTANT_KERNEL : 0u),
                             .edge_reach = e->desc.no_edge_correction ? 0.0f : e->edge_reach};
  return pb_gpu_dispatch(g, &e->gather, &push, pixels);
}

/* gather_upsample: the same bindings as the gather's (the accumulators at
 * 12 and 18, the normal-map sums unused: up-sampling is off in scenes with
 * normal maps), then the irradiance plane and the list (pb_contract.h). */
pb_result pb_photon_estimator_bind_upsample(pb_gpu *g, pb_photon_estimator *e, const struct pb_pass_setup *ps,
                                            const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *irradiance,
                                            const pb_gpu_buffer *list) {
  pb_result r;
  uint32_t spec[PB_SPEC_COUNT] = {0};
  memcpy(spec, ps->spec, PB_SPEC_SHADING_COUNT * sizeof *spec);
  spec[PB_SPEC_NORMAL_MAPS] = 0u;
  static const pb_kernel_builds k = PB_KERNEL_BUILDS(gather_upsample);
  pb_gpu_pipeline_desc d = {
      .name = "pass.gather_upsample",
      .binding_count = PB_GATHER_UPS_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_gather_push),
      .spec = spec,
      .spec_count = PB_SPEC_COUNT,
  };
  uint32_t build = pb_kernel_select(&d, &k, ps->blender, ps->accel != NULL, PB_BIND_NODES);
  if (e->gather_ups.pipeline &&
      (memcmp(e->gather_ups_spec, spec, sizeof e->gather_ups_spec) != 0 || e->gather_ups_build != build))
    pb_gpu_pipeline_destroy(g, &e->gather_ups);
  if (!e->gather_ups.pipeline) {
    if ((r = pb_gpu_pipeline_create(g, &d, &e->gather_ups)) != PB_OK) return r;
    memcpy(e->gather_ups_spec, spec, sizeof e->gather_ups_spec);
    e->gather_ups_build = build;
  }
  if (!e->sorted.buffer) return pb_fail(PB_ERR_INTERNAL, "gather: bound before any LBVH build");
  const pb_gpu_buffer *b[PB_GATHER_UPS_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i];
  b[PB_GATHER_BIND_PHOTONS] = &e->sorted;
  b[PB_GATHER_BIND_NODES] = &e->nodes;
  b[PB_GATHER_BIND_INFO] = &e->info;
  b[PB_GATHER_BIND_ACCUM] = photon_accum;
  b[PB_GATHER_BIND_NMAP] = photon_accum; /* never read (SC_NORMAL_MAPS 0) */
  b[PB_GATHER_BIND_UPS_IRR] = irradiance;
  b[PB_GATHER_BIND_UPS_LIST] = list;
  if ((r = pb_kernel_bind(g, &e->gather_ups, b, PB_GATHER_UPS_BIND_COUNT, ps->accel)) != PB_OK) return r;
  e->gather_ups_ready = 1;
  return PB_OK;
}

pb_result pb_photon_estimator_record_upsample(pb_gpu *g, pb_photon_estimator *e, uint32_t sample_index,
                                              uint32_t invocations, uint32_t flags, uint32_t level) {
  if (!e->gather_ups_ready)
    return pb_fail(PB_ERR_INTERNAL, "gather: up-sampling recorded before pb_photon_estimator_bind_upsample");
  pb_gpu_gather_push push = {.sample_index = sample_index,
                             .flags = flags | (e->desc.constant_kernel ? PB_GATHER_CONSTANT_KERNEL : 0u),
                             .edge_reach = e->desc.no_edge_correction ? 0.0f : e->edge_reach,
                             .level = level};
  return pb_gpu_dispatch(g, &e->gather_ups, &push, invocations);
}
