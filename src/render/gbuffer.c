/* The G-buffer pass (shaders/gbuffer.comp): camera rays, specular eye
 * chains, emission along them and the first-hit AOVs. */
#include "render/passes.h"
#include "shaders/gbuffer.spv.h"
#include "shaders/gbuffer_blender.spv.h"

pb_result pb_pass_gbuffer_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out) {
  static const pb_pass_module m = {"pass.gbuffer", pb_spv_gbuffer, sizeof pb_spv_gbuffer, pb_spv_gbuffer_blender,
                                   sizeof pb_spv_gbuffer_blender};
  return pb_pass_create(g, s, &m, out);
}
