/* The G-buffer pass (shaders/gbuffer.comp): camera rays, specular eye
 * chains, emission along them and the first-hit AOVs. */
#include "render/passes.h"
#include "shaders/gbuffer.spv.h"
#include "shaders/gbuffer_blender.spv.h"

pb_result pb_pass_gbuffer_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {
      .name = "pass.gbuffer",
      .spirv = s->blender ? pb_spv_gbuffer_blender : pb_spv_gbuffer,
      .spirv_bytes = s->blender ? sizeof pb_spv_gbuffer_blender : sizeof pb_spv_gbuffer,
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
