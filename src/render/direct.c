/* The direct-light pass (shaders/direct.comp): one shadow ray per point,
 * spot and directional light at each G-buffer surface. */
#include "render/passes.h"
#include "shaders/direct.spv.h"
#include "shaders/direct_blender.spv.h"

pb_result pb_pass_direct_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {
      .name = "pass.direct",
      .spirv = s->blender ? pb_spv_direct_blender : pb_spv_direct,
      .spirv_bytes = s->blender ? sizeof pb_spv_direct_blender : sizeof pb_spv_direct,
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
