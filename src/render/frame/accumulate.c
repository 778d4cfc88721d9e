/* A still run's progressive accumulation on the GPU (targets.h
 * pb_still_sum; shaders/frame/accumulate.comp). */
#include <string.h>

#include "render/frame/targets.h"
#include "shaders/accumulate.spv.h"
#include "shared/pb_accumulate.h"
#include "shared/pb_contract.h"

pb_result pb_still_sum_create(pb_gpu *g, uint32_t pixels, int caustic_filtered, pb_still_sum *out) {
  memset(out, 0, sizeof *out);
  pb_gpu_pipeline_desc d = {.name = "pass.accumulate", .spirv = pb_spv_accumulate,
                            .spirv_bytes = sizeof pb_spv_accumulate, .binding_count = PB_ACCUM_BIND_COUNT,
                            .push_bytes = sizeof(pb_gpu_accumulate_push)};
  pb_gpu_buffer_desc bd = {.name = "still_sum", .size = (uint64_t)(pixels ? pixels : 1) * PB_ACCUM_FLOATS * sizeof(float)};
  pb_result r = pb_gpu_pipeline_create(g, &d, &out->pipe);
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &bd, &out->sum);
  if (r != PB_OK) {
    pb_still_sum_destroy(g, out);
    return r;
  }
  out->pixels = pixels;
  out->caustic_filtered = caustic_filtered;
  return PB_OK;
}

void pb_still_sum_destroy(pb_gpu *g, pb_still_sum *a) {
  if (!a) return;
  if (a->pipe.pipeline) pb_gpu_pipeline_destroy(g, &a->pipe);
  pb_gpu_buffer_destroy(g, &a->sum);
  memset(a, 0, sizeof *a);
}

pb_result pb_still_sum_bind(pb_gpu *g, pb_still_sum *a, const pb_frame_targets *t) {
  const pb_gpu_buffer *b[PB_ACCUM_BIND_COUNT] = {
      [PB_ACCUM_BIND_PLANES] = &t->planes,
      [PB_ACCUM_BIND_PHOTON_PLANES] = t->photons ? &t->pplanes : &t->planes, /* never read without */
      [PB_ACCUM_BIND_SUM] = &a->sum};
  return pb_gpu_pipeline_bind(g, &a->pipe, b, PB_ACCUM_BIND_COUNT);
}

pb_result pb_still_sum_record(pb_gpu *g, pb_still_sum *a, const pb_frame_targets *t, uint32_t pixels) {
  if (pixels != a->pixels)
    return pb_fail(PB_ERR_USAGE, "accumulate: a band of %u pixels, the running means hold %u", pixels, a->pixels);
  float k = (float)a->frames, inv = 1.0f / (k + 1.0f); /* sequence.c's floats */
  pb_gpu_accumulate_push push = {.pixels = pixels, .k = k, .inv = inv,
                                 .flags = (a->frames ? 0u : PB_ACCUM_FIRST) | (t->photons ? PB_ACCUM_PHOTONS : 0u) |
                                          (a->caustic_filtered ? PB_ACCUM_CAUSTIC_FILTERED : 0u)};
  return pb_gpu_dispatch(g, &a->pipe, &push, pixels);
}
