/* The G-buffer pass (shaders/scene/gbuffer.comp): camera rays, specular eye
 * chains, emission along them and the first-hit AOVs. */
#include "render/scene/passes.h"
#include "shaders/gbuffer.spv.h"
#include "shaders/gbuffer_blender.spv.h"
#include "shaders/gbuffer_rq.spv.h"
#include "shaders/gbuffer_rq_blender.spv.h"

pb_result pb_pass_gbuffer_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out) {
  static const pb_pass_module m = {"pass.gbuffer", PB_KERNEL_BUILDS(gbuffer)};
  return pb_pass_create(g, s, &m, out);
}
