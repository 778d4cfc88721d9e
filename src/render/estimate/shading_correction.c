/* Seed 001's shading-normal correction (24.4.3, eq. 20); see
 * shading_correction.h. */
#include "render/estimate/shading_correction.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shaders/shading_correction.spv.h"
#include "shared/pb_filter.h"

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

float pb_shading_correction_factor(const float wi[3], const float ns[3], const float ng[3], float s_max) {
  float l = sqrtf(dot3(wi, wi));
  if (!(l > 0.0f) || !isfinite(l)) return 1.0f;
  float cs = dot3(wi, ns) / l, cg = dot3(wi, ng) / l;
  if (!isfinite(cs) || !isfinite(cg)) return 1.0f;
  /* Eq. 20 as min((w_i . w_ns) / (w_i . w_ng + eps), s_max) (derived in
   * shading_correction.h; not the garbled text's literal (w_i . w_ns)
   * min(1 / (w_i . w_ng + eps), s_max), which is never closer to the
   * unclamped ratio and measured further from the reference,
   * test_gpu_normal_map). */
  float f = fmaxf(cs, 0.0f) / (fmaxf(cg, 0.0f) + PB_SHADING_CORRECTION_EPS);
  return fminf(f, s_max);
}

size_t pb_shading_correction_apply(pb_render_result *out, size_t n, float s_max) {
  if (!out->indirect || !out->photon_dir || !out->geo_normal || !out->shading_normal) return 0;
  size_t changed = 0;
  for (size_t p = 0; p < n; ++p) {
    float frac = out->shading_normal[4 * p + 3];
    if (!(frac > 0.0f)) continue;
    float f = pb_shading_correction_factor(out->photon_dir + 3 * p, out->shading_normal + 4 * p,
                                           out->geo_normal + 3 * p, s_max);
    float k = 1.0f + frac * (f - 1.0f);
    if (k == 1.0f) continue;
    for (int c = 0; c < 3; ++c) {
      float before = out->indirect[3 * p + c], after = before * k;
      out->indirect[3 * p + c] = after;
      if (out->beauty) out->beauty[4 * p + c] += after - before;
    }
    changed++;
  }
  return changed;
}

pb_result pb_shading_correction_create(pb_gpu *g, const pb_frame_targets *t, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {.name = "pass.shading_correction", .spirv = pb_spv_shading_correction,
                            .spirv_bytes = sizeof pb_spv_shading_correction, .binding_count = PB_SHADING_BIND_COUNT,
                            .push_bytes = sizeof(pb_gpu_shading_push)};
  pb_result r = pb_gpu_pipeline_create(g, &d, out);
  if (r != PB_OK) return r;
  const pb_gpu_buffer *b[PB_SHADING_BIND_COUNT] = {[PB_SHADING_BIND_PLANES] = &t->planes,
                                                   [PB_SHADING_BIND_PHOTON_PLANES] = &t->pplanes};
  if ((r = pb_gpu_pipeline_bind(g, out, b, PB_SHADING_BIND_COUNT)) != PB_OK) pb_gpu_pipeline_destroy(g, out);
  return r;
}

pb_result pb_shading_correction_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t pixels, float s_max) {
  pb_gpu_shading_push push = {.pixels = pixels, .s_max = s_max};
  return pb_gpu_dispatch(g, p, &push, pixels);
}
