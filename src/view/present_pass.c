/* The viewer's display pass (present_pass.h). */
#include "view/present_pass.h"

#include <stdlib.h>
#include <string.h>

#include "shaders/present.spv.h"
#include "shared/pb_contract.h"
#include "shared/pb_present.h"

static pb_result bind(pb_gpu *g, pb_present_pass *p, const pb_gpu_buffer *src) {
  const pb_gpu_buffer *b[PB_PRESENT_BIND_COUNT] = {
      [PB_PRESENT_BIND_LUT] = &p->lut, [PB_PRESENT_BIND_IN] = src, [PB_PRESENT_BIND_OUT] = &p->out};
  pb_result r = pb_gpu_pipeline_bind(g, &p->pipe, b, PB_PRESENT_BIND_COUNT);
  if (r == PB_OK) p->bound_src = src;
  return r;
}

pb_result pb_present_pass_set_lut(pb_gpu *g, pb_present_pass *p, const pb_color_lut *lut) {
  uint64_t bytes = (uint64_t)lut->size * lut->size * lut->size * 4 * sizeof(float);
  if (!p->lut.buffer || p->lut.size != bytes) {
    pb_gpu_buffer_destroy(g, &p->lut);
    pb_gpu_buffer_desc bd = {.name = "present.lut", .size = bytes};
    pb_result r = pb_gpu_buffer_create(g, &bd, &p->lut);
    if (r != PB_OK) return r;
    p->bound_src = NULL; /* rebind: the LUT buffer is new */
  }
  p->size = lut->size, p->lo = lut->lo, p->hi = lut->hi;
  return pb_gpu_buffer_upload(g, &p->lut, 0, lut->rgba, bytes);
}

pb_result pb_present_pass_create(pb_gpu *g, const pb_color_lut *lut, uint32_t pixels, pb_present_pass *out) {
  memset(out, 0, sizeof *out);
  if (!pixels) pixels = 1;
  pb_gpu_pipeline_desc d = {.name = "pass.present", .spirv = pb_spv_present, .spirv_bytes = sizeof pb_spv_present,
                            .binding_count = PB_PRESENT_BIND_COUNT, .push_bytes = sizeof(pb_gpu_present_push)};
  pb_result r = pb_gpu_pipeline_create(g, &d, &out->pipe);
  pb_gpu_buffer_desc in = {.name = "present.in", .size = (uint64_t)pixels * 4 * sizeof(float)};
  pb_gpu_buffer_desc o = {.name = "present.out", .size = (uint64_t)pixels * 4, .readback = 1};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &in, &out->in);
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &o, &out->out);
  if (r == PB_OK) r = pb_present_pass_set_lut(g, out, lut);
  if (r == PB_OK) r = bind(g, out, &out->in);
  if (r != PB_OK) {
    pb_present_pass_destroy(g, out);
    return r;
  }
  out->pixels_cap = pixels;
  out->in_floats = pixels * 4;
  return PB_OK;
}

void pb_present_pass_destroy(pb_gpu *g, pb_present_pass *p) {
  if (!p) return;
  if (p->pipe.pipeline) pb_gpu_pipeline_destroy(g, &p->pipe);
  pb_gpu_buffer_destroy(g, &p->lut);
  pb_gpu_buffer_destroy(g, &p->in);
  pb_gpu_buffer_destroy(g, &p->out);
  memset(p, 0, sizeof *p);
}

pb_result pb_present_pass_upload(pb_gpu *g, pb_present_pass *p, const float *pixels, uint32_t count,
                                 uint32_t channels) {
  if ((uint64_t)count * channels > p->in_floats)
    return pb_fail(PB_ERR_USAGE, "present pass: %u pixels x %u channels, made for %u floats", count, channels,
                   p->in_floats);
  return pb_gpu_buffer_upload(g, &p->in, 0, pixels, (uint64_t)count * channels * sizeof(float));
}

pb_result pb_present_pass_record(pb_gpu *g, pb_present_pass *p, const pb_present_job *job) {
  const pb_gpu_buffer *src = job->src ? job->src : &p->in;
  if (job->pixels > p->pixels_cap || (job->channels != 3 && job->channels != 4) ||
      (uint64_t)job->offset * 4 + (uint64_t)job->pixels * job->channels * 4 > src->size)
    return pb_fail(PB_ERR_USAGE, "present pass: %u pixels x %u channels at float %u do not fit (%u pixels, %llu bytes)",
                   job->pixels, job->channels, job->offset, p->pixels_cap, (unsigned long long)src->size);
  pb_result r;
  if (p->bound_src != src && (r = bind(g, p, src)) != PB_OK) return r;
  pb_gpu_present_push push = {.pixels = job->pixels, .size = p->size, .offset = job->offset,
                              .channels = job->channels, .lo = p->lo, .hi = p->hi, .scale = job->scale,
                              .flags = job->data ? PB_PRESENT_DATA : 0u, .data_scale = job->data_scale,
                              .data_bias = job->data_bias};
  return pb_gpu_dispatch(g, &p->pipe, &push, job->pixels);
}

pb_result pb_present_pass_run(pb_gpu *g, pb_present_pass *p, const pb_present_job *job) {
  /* Binding patches the descriptor set: before recording. */
  const pb_gpu_buffer *src = job->src ? job->src : &p->in;
  pb_result r;
  if (p->bound_src != src && (r = bind(g, p, src)) != PB_OK) return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  if ((r = pb_present_pass_record(g, p, job)) != PB_OK) {
    (void)pb_gpu_submit(g);
    return r;
  }
  return pb_gpu_submit(g);
}

pb_result pb_present_pass_download(pb_gpu *g, const pb_present_pass *p, uint8_t *rgba, uint32_t pixels) {
  return pb_gpu_buffer_read_back(g, &p->out, 0, rgba, (uint64_t)pixels * 4);
}
