/* The resolve pass (shaders/frame/resolve.comp; shared/pb_resolve.h): the band's
 * accumulators into the AOV planes, non-finite values counted, on the GPU. */
#include "render/frame/resolve.h"

#include "shaders/resolve.spv.h"
#include "shared/pb_resolve.h"

pb_result pb_resolve_create(pb_gpu *g, const pb_frame_targets *t, pb_gpu_pipeline *out) {
  pb_gpu_pipeline_desc d = {.name = "pass.resolve", .spirv = pb_spv_resolve, .spirv_bytes = sizeof pb_spv_resolve,
                            .binding_count = PB_RESOLVE_BIND_COUNT, .push_bytes = sizeof(pb_gpu_resolve_push)};
  pb_result r = pb_gpu_pipeline_create(g, &d, out);
  if (r != PB_OK) return r;
  /* Accumulators a frame does not have: any buffer will do (never read). */
  const pb_gpu_buffer *b[PB_RESOLVE_BIND_COUNT] = {
      [PB_RESOLVE_BIND_ACCUM] = &t->accum,
      [PB_RESOLVE_BIND_PHOTON_ACCUM] = t->photons ? &t->paccum : &t->accum,
      [PB_RESOLVE_BIND_NMAP] = t->nmap ? &t->pnmap : &t->accum,
      [PB_RESOLVE_BIND_OUT] = &t->planes,
      [PB_RESOLVE_BIND_GUARD] = &t->guard,
      [PB_RESOLVE_BIND_OUT_PHOTONS] = t->photons ? &t->pplanes : &t->planes,
      [PB_RESOLVE_BIND_KPD_SUMS] = &t->kpd};
  if ((r = pb_gpu_pipeline_bind(g, out, b, PB_RESOLVE_BIND_COUNT)) != PB_OK) pb_gpu_pipeline_destroy(g, out);
  return r;
}

pb_result pb_resolve_record(pb_gpu *g, const pb_gpu_pipeline *p, const pb_frame_targets *t, uint32_t pixels,
                            float inv_spp, int opaque) {
  pb_gpu_resolve_push push = {.pixels = pixels, .inv_spp = inv_spp,
                              .flags = (t->photons ? PB_RESOLVE_PHOTONS : 0u) | (t->nmap ? PB_RESOLVE_NMAP : 0u) |
                                       (opaque ? PB_RESOLVE_OPAQUE : 0u)};
  return pb_gpu_dispatch(g, p, &push, pixels);
}
