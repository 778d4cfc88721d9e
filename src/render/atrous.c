/* The A-Trous spatial filter (atrous.h; shaders/atrous.comp). */
#include "render/atrous.h"

#include <stdlib.h>
#include <string.h>

#include "shaders/atrous.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

enum { PB_ATROUS_MAX_ITERATIONS = 12 }; /* bindings: PB_ATROUS_BIND_* (pb_contract.h), b[] in that order */

pb_result pb_atrous_filter(pb_gpu *g, uint32_t width, uint32_t height, const float *normal, const float *depth,
                           const float *albedo, float *indirect, const pb_atrous_desc *desc_in, double *gpu_ms) {
  pb_atrous_desc d = desc_in ? *desc_in : (pb_atrous_desc){0};
  if (!d.iterations) d.iterations = 4;
  if (d.iterations > PB_ATROUS_MAX_ITERATIONS)
    return pb_fail(PB_ERR_USAGE, "filter: %u A-Trous iterations (at most %d)", d.iterations,
                   PB_ATROUS_MAX_ITERATIONS);
  if (d.sigma_z == 0.0f) d.sigma_z = 1.0f;
  if (d.sigma_n == 0.0f) d.sigma_n = 32.0f;
  if (d.gamma == 0.0f) d.gamma = PB_ATROUS_GAMMA_DEFAULT;
  if (d.gamma < 0.0f) d.gamma = 0.0f;
  if (gpu_ms) *gpu_ms = 0;
  size_t n = (size_t)width * height;
  if (!n) return PB_OK;
  pb_gpu_buffer b[PB_ATROUS_BIND_COUNT];
  memset(b, 0, sizeof b);
  pb_gpu_pipeline pipe;
  memset(&pipe, 0, sizeof pipe);
  float *geo = malloc(n * 4 * sizeof *geo), *ind = malloc(n * 4 * sizeof *ind), *alb = malloc(n * 4 * sizeof *alb);
  pb_result r = PB_OK;
  if (!geo || !ind || !alb) {
    r = pb_fail(PB_ERR_NOMEM, "filter: out of memory for %ux%u pixels", width, height);
    goto done;
  }
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      geo[4 * i + k] = normal[3 * i + k];
      ind[4 * i + k] = indirect[3 * i + k];
      alb[4 * i + k] = albedo[3 * i + k];
    }
    geo[4 * i + 3] = depth[i];
    ind[4 * i + 3] = 0.0f;
    alb[4 * i + 3] = d.history ? d.history[i] : 1.0f; /* L for the clip bound */
  }
  static const char *const names[PB_ATROUS_BIND_COUNT] = {"filter.irradiance", "filter.detail", "filter.geometry",
                                                          "filter.indirect", "filter.albedo"};
  for (int i = 0; i < PB_ATROUS_BIND_COUNT; ++i) {
    pb_gpu_buffer_desc bd = {.name = names[i], .size = (i == 0 ? 2 : 1) * n * 4 * sizeof(float),
                             .host_visible = i == 3};
    if ((r = pb_gpu_buffer_create(g, &bd, &b[i])) != PB_OK) goto done;
  }
  if ((r = pb_gpu_buffer_upload(g, &b[2], 0, geo, n * 4 * sizeof(float))) != PB_OK ||
      (r = pb_gpu_buffer_upload(g, &b[3], 0, ind, n * 4 * sizeof(float))) != PB_OK ||
      (r = pb_gpu_buffer_upload(g, &b[4], 0, alb, n * 4 * sizeof(float))) != PB_OK)
    goto done;
  pb_gpu_pipeline_desc pd = {.name = "pass.atrous", .spirv = pb_spv_atrous, .spirv_bytes = sizeof pb_spv_atrous,
                             .binding_count = PB_ATROUS_BIND_COUNT, .push_bytes = sizeof(pb_gpu_atrous_push)};
  if ((r = pb_gpu_pipeline_create(g, &pd, &pipe)) != PB_OK) goto done;
  const pb_gpu_buffer *bind[PB_ATROUS_BIND_COUNT] = {&b[0], &b[1], &b[2], &b[3], &b[4]};
  if ((r = pb_gpu_pipeline_bind(g, &pipe, bind, PB_ATROUS_BIND_COUNT)) != PB_OK) goto done;
  pb_gpu_atrous_push p = {.width = width, .height = height, .sigma_z = d.sigma_z, .sigma_n = d.sigma_n,
                          .gamma = d.gamma};
  if ((r = pb_gpu_begin(g)) != PB_OK) goto done;
  pb_gpu_timestamp(g, 0);
  p.mode = PB_ATROUS_INIT;
  r = pb_gpu_dispatch(g, &pipe, &p, n);
  pb_gpu_barrier(g);
  p.mode = PB_ATROUS_STEP;
  for (uint32_t i = 0; r == PB_OK && i < d.iterations; ++i) {
    p.step = 1u << i;
    p.src_half = i & 1u;
    r = pb_gpu_dispatch(g, &pipe, &p, n);
    pb_gpu_barrier(g);
  }
  p.mode = PB_ATROUS_FINISH;
  p.src_half = d.iterations & 1u;
  if (r == PB_OK) r = pb_gpu_dispatch(g, &pipe, &p, n);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, 1);
  if (r != PB_OK) {
    (void)pb_gpu_submit(g);
    goto done;
  }
  if ((r = pb_gpu_submit(g)) != PB_OK) goto done;
  if (gpu_ms) {
    double ms = pb_gpu_elapsed_ms(g, 0, 1);
    *gpu_ms = ms > 0 ? ms : 0;
  }
  if ((r = pb_gpu_buffer_download(g, &b[3], 0, ind, n * 4 * sizeof(float))) != PB_OK) goto done;
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) indirect[3 * i + k] = ind[4 * i + k];
done:
  pb_gpu_pipeline_destroy(g, &pipe);
  for (int i = 0; i < PB_ATROUS_BIND_COUNT; ++i) pb_gpu_buffer_destroy(g, &b[i]);
  free(geo);
  free(ind);
  free(alb);
  return r;
}
