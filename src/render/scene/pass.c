/* The one helper behind every scene pass (gbuffer.c, direct.c): a pipeline
 * of the pass's module (its PB_BLENDER and ray-query builds as the scene
 * asks) with the contract's 16
 * bindings (PB_BIND_*) and the scene's specialization constants (PB_SPEC_*,
 * shaders/shared/pb_contract.h), bound once; and the dispatch that records it
 * over a band's pixels for one sample. */
#include "render/scene/passes.h"

uint32_t pb_kernel_select(pb_gpu_pipeline_desc *d, const pb_kernel_builds *k, uint32_t blender, int ray_query,
                          uint32_t tlas) {
  uint32_t b = blender ? 1u : 0u, q = ray_query ? 1u : 0u;
  d->spirv = k->build[b][q].code;
  d->spirv_bytes = k->build[b][q].bytes;
  d->accel_bindings = q ? 1u << tlas : 0u;
  return b | q << 1;
}

pb_result pb_kernel_bind(pb_gpu *g, pb_gpu_pipeline *p, const pb_gpu_buffer *const *buffers, uint32_t count,
                         const pb_gpu_accel *accel) {
  pb_result r = pb_gpu_pipeline_bind(g, p, buffers, count);
  for (uint32_t i = 0; r == PB_OK && i < count && p->accel_bindings; ++i)
    if (p->accel_bindings >> i & 1u) {
      if (!accel) return pb_fail(PB_ERR_INTERNAL, "gpu: a ray-query pipeline bound without the scene's structure");
      r = pb_gpu_pipeline_bind_accel(g, p, i, accel);
    }
  return r;
}

pb_result pb_pass_create(pb_gpu *g, const pb_pass_setup *s, const pb_pass_module *m, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {
      .name = m->name,
      .binding_count = PB_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_pass_push),
      .spec = s->spec,
      .spec_count = PB_SPEC_COUNT,
  };
  pb_kernel_select(&d, &m->k, s->blender, s->accel != NULL, PB_BIND_NODES);
  pb_result r = pb_gpu_pipeline_create(g, &d, out);
  if (r != PB_OK) return r;
  r = pb_kernel_bind(g, out, s->bindings, PB_BIND_COUNT, s->accel);
  if (r != PB_OK) pb_gpu_pipeline_destroy(g, out);
  return r;
}

pb_result pb_pass_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t sample_index, uint32_t pixels) {
  pb_gpu_pass_push push = {.sample_index = sample_index};
  return pb_gpu_dispatch(g, p, &push, pixels);
}
