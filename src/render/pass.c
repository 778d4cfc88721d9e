/* The one helper behind every scene pass (gbuffer.c, direct.c): a pipeline
 * of the pass's module (or its PB_BLENDER build) with the contract's 16
 * bindings (PB_BIND_*) and the scene's specialization constants (PB_SPEC_*,
 * shaders/shared/pb_contract.h), bound once; and the dispatch that records it
 * over a band's pixels for one sample. */
#include "render/passes.h"

pb_result pb_pass_create(pb_gpu *g, const pb_pass_setup *s, const pb_pass_module *m, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {
      .name = m->name,
      .spirv = s->blender ? m->spirv_blender : m->spirv,
      .spirv_bytes = s->blender ? m->bytes_blender : m->bytes,
      .binding_count = PB_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_pass_push),
      .spec = s->spec,
      .spec_count = PB_SPEC_COUNT,
  };
  pb_result r = pb_gpu_pipeline_create(g, &d, out);
  if (r != PB_OK) return r;
  r = pb_gpu_pipeline_bind(g, out, s->bindings, PB_BIND_COUNT);
  if (r != PB_OK) pb_gpu_pipeline_destroy(g, out);
  return r;
}

pb_result pb_pass_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t sample_index, uint32_t pixels) {
  pb_gpu_pass_push push = {.sample_index = sample_index};
  return pb_gpu_dispatch(g, p, &push, pixels);
}
