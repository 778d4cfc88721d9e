/* The A-Trous spatial filter (atrous.h; shaders/filter/atrous.comp). */
#include "render/filter/atrous.h"

#include <stdlib.h>
#include <string.h>

#include "shaders/atrous.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

enum { PB_ATROUS_MAX_ITERATIONS = 12 }; /* bindings: PB_ATROUS_BIND_* (pb_contract.h), b[] in that order */

/* What one image size needs, made once (pb_atrous_pass_create) and reused
 * by every frame of a sequence: the pipeline (compiled once, not per call)
 * and the filter's own buffers (irradiance ping-pong, detail sum). The
 * host-array path (pb_atrous_pass_run) adds its input buffers and staging
 * on its first call. */
struct pb_atrous_pass {
  uint32_t width, height;
  pb_gpu_buffer b[PB_ATROUS_BIND_COUNT];
  pb_gpu_pipeline pipe;
  float *geo, *ind, *alb;
};

void pb_atrous_pass_destroy(pb_gpu *g, pb_atrous_pass *a) {
  if (!a) return;
  pb_gpu_pipeline_destroy(g, &a->pipe);
  for (int i = 0; i < PB_ATROUS_BIND_COUNT; ++i) pb_gpu_buffer_destroy(g, &a->b[i]);
  free(a->geo);
  free(a->ind);
  free(a->alb);
  free(a);
}

static const char *const names[PB_ATROUS_BIND_COUNT] = {
    [PB_ATROUS_BIND_S] = "filter.irradiance", [PB_ATROUS_BIND_DETAIL] = "filter.detail",
    [PB_ATROUS_BIND_GEO] = "filter.geometry", [PB_ATROUS_BIND_INDIRECT] = "filter.indirect",
    [PB_ATROUS_BIND_ALBEDO] = "filter.albedo"};

pb_result pb_atrous_pass_create(pb_gpu *g, uint32_t width, uint32_t height, pb_atrous_pass **out) {
  *out = NULL;
  size_t n = (size_t)width * height;
  pb_atrous_pass *a = calloc(1, sizeof *a);
  if (!a) return pb_fail(PB_ERR_NOMEM, "filter: out of memory");
  a->width = width, a->height = height;
  pb_result r = PB_OK;
  for (int i = PB_ATROUS_BIND_S; i <= PB_ATROUS_BIND_DETAIL; ++i) {
    pb_gpu_buffer_desc bd = {.name = names[i], .size = (i == PB_ATROUS_BIND_S ? 2 : 1) * (n ? n : 1) * 4 * sizeof(float)};
    if ((r = pb_gpu_buffer_create(g, &bd, &a->b[i])) != PB_OK) goto fail;
  }
  pb_gpu_pipeline_desc pd = {.name = "pass.atrous", .spirv = pb_spv_atrous, .spirv_bytes = sizeof pb_spv_atrous,
                             .binding_count = PB_ATROUS_BIND_COUNT, .push_bytes = sizeof(pb_gpu_atrous_push)};
  if ((r = pb_gpu_pipeline_create(g, &pd, &a->pipe)) != PB_OK) goto fail;
  *out = a;
  return PB_OK;
fail:
  pb_atrous_pass_destroy(g, a);
  return r;
}

pb_result pb_atrous_pass_bind(pb_gpu *g, pb_atrous_pass *a, const pb_gpu_buffer *geo, const pb_gpu_buffer *albedo,
                              const pb_gpu_buffer *indirect) {
  const pb_gpu_buffer *bind[PB_ATROUS_BIND_COUNT] = {
      [PB_ATROUS_BIND_S] = &a->b[PB_ATROUS_BIND_S], [PB_ATROUS_BIND_DETAIL] = &a->b[PB_ATROUS_BIND_DETAIL],
      [PB_ATROUS_BIND_GEO] = geo, [PB_ATROUS_BIND_INDIRECT] = indirect, [PB_ATROUS_BIND_ALBEDO] = albedo};
  return pb_gpu_pipeline_bind(g, &a->pipe, bind, PB_ATROUS_BIND_COUNT);
}

/* desc with its defaults, or a usage error. */
static pb_result defaults(const pb_atrous_desc *desc_in, pb_atrous_desc *d) {
  *d = desc_in ? *desc_in : (pb_atrous_desc){0};
  if (!d->iterations) d->iterations = 4;
  if (d->iterations > PB_ATROUS_MAX_ITERATIONS)
    return pb_fail(PB_ERR_USAGE, "filter: %u A-Trous iterations (at most %d)", d->iterations,
                   PB_ATROUS_MAX_ITERATIONS);
  if (d->sigma_z == 0.0f) d->sigma_z = 1.0f;
  if (d->sigma_n == 0.0f) d->sigma_n = 32.0f;
  if (d->gamma == 0.0f) d->gamma = PB_ATROUS_GAMMA_DEFAULT;
  if (d->gamma < 0.0f) d->gamma = 0.0f;
  return PB_OK;
}

pb_result pb_atrous_pass_record(pb_gpu *g, pb_atrous_pass *a, const pb_atrous_desc *desc) {
  pb_atrous_desc d;
  pb_result r = defaults(desc, &d);
  size_t n = (size_t)a->width * a->height;
  if (r != PB_OK || !n) return r;
  const pb_gpu_pipeline *pipe = &a->pipe;
  pb_gpu_atrous_push p = {.width = a->width, .height = a->height, .sigma_z = d.sigma_z, .sigma_n = d.sigma_n,
                          .gamma = d.gamma};
  p.mode = PB_ATROUS_INIT;
  r = pb_gpu_dispatch(g, pipe, &p, n);
  pb_gpu_barrier(g);
  p.mode = PB_ATROUS_STEP;
  for (uint32_t i = 0; r == PB_OK && i < d.iterations; ++i) {
    p.step = 1u << i;
    p.src_half = i & 1u;
    r = pb_gpu_dispatch(g, pipe, &p, n);
    pb_gpu_barrier(g);
  }
  p.mode = PB_ATROUS_FINISH;
  p.src_half = d.iterations & 1u;
  if (r == PB_OK) r = pb_gpu_dispatch(g, pipe, &p, n);
  pb_gpu_barrier(g);
  return r;
}

pb_result pb_atrous_pass_run(pb_gpu *g, pb_atrous_pass *a, const float *normal, const float *depth,
                             const float *albedo, float *indirect, const pb_atrous_desc *desc_in, double *gpu_ms) {
  pb_atrous_desc d;
  pb_result r = defaults(desc_in, &d);
  if (r != PB_OK) return r;
  if (gpu_ms) *gpu_ms = 0;
  uint32_t width = a->width, height = a->height;
  size_t n = (size_t)width * height;
  if (!n) return PB_OK;
  pb_gpu_buffer *b = a->b;
  if (!a->geo) { /* the host path's inputs, on first use */
    a->geo = malloc(n * 4 * sizeof(float));
    a->ind = malloc(n * 4 * sizeof(float));
    a->alb = malloc(n * 4 * sizeof(float));
    if (!a->geo || !a->ind || !a->alb)
      return pb_fail(PB_ERR_NOMEM, "filter: out of memory for %ux%u pixels", width, height);
    for (int i = PB_ATROUS_BIND_GEO; i <= PB_ATROUS_BIND_ALBEDO; ++i) {
      pb_gpu_buffer_desc bd = {.name = names[i], .size = n * 4 * sizeof(float),
                               .host_visible = i == PB_ATROUS_BIND_INDIRECT};
      if ((r = pb_gpu_buffer_create(g, &bd, &b[i])) != PB_OK) return r;
    }
  }
  float *geo = a->geo, *ind = a->ind, *alb = a->alb;
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      geo[4 * i + k] = normal[3 * i + k];
      ind[4 * i + k] = indirect[3 * i + k];
      alb[4 * i + k] = albedo[3 * i + k];
    }
    geo[4 * i + 3] = depth[i];
    ind[4 * i + 3] = d.history ? d.history[i] : 1.0f; /* L for the clip bound */
    alb[4 * i + 3] = 0.0f;
  }
  if ((r = pb_gpu_buffer_upload(g, &b[PB_ATROUS_BIND_GEO], 0, geo, n * 4 * sizeof(float))) != PB_OK ||
      (r = pb_gpu_buffer_upload(g, &b[PB_ATROUS_BIND_INDIRECT], 0, ind, n * 4 * sizeof(float))) != PB_OK ||
      (r = pb_gpu_buffer_upload(g, &b[PB_ATROUS_BIND_ALBEDO], 0, alb, n * 4 * sizeof(float))) != PB_OK)
    return r;
  if ((r = pb_atrous_pass_bind(g, a, &b[PB_ATROUS_BIND_GEO], &b[PB_ATROUS_BIND_ALBEDO], &b[PB_ATROUS_BIND_INDIRECT])) !=
      PB_OK)
    return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_atrous_pass_record(g, a, &d);
  pb_gpu_timestamp(g, 1);
  if (r != PB_OK) {
    (void)pb_gpu_submit(g);
    return r;
  }
  if ((r = pb_gpu_submit(g)) != PB_OK) return r;
  if (gpu_ms) {
    double ms = pb_gpu_elapsed_ms(g, 0, 1);
    *gpu_ms = ms > 0 ? ms : 0;
  }
  if ((r = pb_gpu_buffer_download(g, &b[PB_ATROUS_BIND_INDIRECT], 0, ind, n * 4 * sizeof(float))) != PB_OK) return r;
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) indirect[3 * i + k] = ind[4 * i + k];
  return PB_OK;
}

pb_result pb_atrous_filter(pb_gpu *g, uint32_t width, uint32_t height, const float *normal, const float *depth,
                           const float *albedo, float *indirect, const pb_atrous_desc *desc, double *gpu_ms) {
  if (gpu_ms) *gpu_ms = 0;
  if (desc && desc->iterations > PB_ATROUS_MAX_ITERATIONS)
    return pb_fail(PB_ERR_USAGE, "filter: %u A-Trous iterations (at most %d)", desc->iterations,
                   PB_ATROUS_MAX_ITERATIONS);
  if ((size_t)width * height == 0) return PB_OK;
  pb_atrous_pass *a;
  pb_result r = pb_atrous_pass_create(g, width, height, &a);
  if (r != PB_OK) return r;
  r = pb_atrous_pass_run(g, a, normal, depth, albedo, indirect, desc, gpu_ms);
  pb_atrous_pass_destroy(g, a);
  return r;
}
