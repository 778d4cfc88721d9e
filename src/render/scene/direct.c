/* The direct-light pass (shaders/scene/direct.comp): one shadow ray per point,
 * spot and directional light at each G-buffer surface. */
#include "render/scene/passes.h"
#include "shaders/direct.spv.h"
#include "shaders/direct_blender.spv.h"
#include "shaders/direct_rq.spv.h"
#include "shaders/direct_rq_blender.spv.h"

pb_result pb_pass_direct_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out) {
  static const pb_pass_module m = {"pass.direct", PB_KERNEL_BUILDS(direct)};
  return pb_pass_create(g, s, &m, out);
}
