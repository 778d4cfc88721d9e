/* The viewer's picture made on the render device: an AOV
 * through the baked OCIO view (color.h pb_color_lut; shaders/frame/present.comp)
 * into an RGBA8 buffer on the GPU that the presenter (present.h) copies
 * into the swapchain when it shares the render device. Needs no window:
 * tests run it on any device. */
#ifndef PB_VIEW_PRESENT_PASS_H
#define PB_VIEW_PRESENT_PASS_H

#include <stdint.h>

#include "color/color.h"
#include "core/result.h"
#include "gpu/gpu.h"

typedef struct pb_present_pass {
  pb_gpu_pipeline pipe;
  pb_gpu_buffer lut;   /* the baked view's nodes */
  pb_gpu_buffer in;    /* the AOV uploaded from the host (pb_present_pass_upload) */
  pb_gpu_buffer out;   /* RGBA8, R in the low byte, pixels_cap words */
  uint32_t pixels_cap, in_floats;
  uint32_t size;
  float lo, hi;
  const pb_gpu_buffer *bound_src; /* the input the descriptor set points at */
} pb_present_pass;

/* Uploads the LUT; buffers for `pixels` pixels (RGBA floats in). */
pb_result pb_present_pass_create(pb_gpu *g, const pb_color_lut *lut, uint32_t pixels, pb_present_pass *out);
void pb_present_pass_destroy(pb_gpu *g, pb_present_pass *p); /* accepts a zeroed one */
/* A new bake (a new view); the buffers stay. */
pb_result pb_present_pass_set_lut(pb_gpu *g, pb_present_pass *p, const pb_color_lut *lut);

typedef struct pb_present_job {
  const pb_gpu_buffer *src; /* the AOV on the device; NULL: p->in (upload first) */
  uint32_t offset;          /* its float offset in src (a plane of the planes buffer) */
  uint32_t channels;        /* 3 or 4 */
  uint32_t pixels;          /* <= pixels_cap */
  float scale;              /* 2^exposure */
  int data;                 /* 1: no view, data_scale * x + data_bias (normals: 0.5, 0.5) */
  float data_scale, data_bias;
} pb_present_job;

/* Copies `pixels` x `channels` host floats into p->in (RGBA or RGB). */
pb_result pb_present_pass_upload(pb_gpu *g, pb_present_pass *p, const float *pixels, uint32_t count,
                                 uint32_t channels);
/* Records the pass into the recording command buffer (pb_gpu_begin first;
 * a pb_gpu_barrier after whatever wrote src is the caller's). */
pb_result pb_present_pass_record(pb_gpu *g, pb_present_pass *p, const pb_present_job *job);
/* Begin, record, submit and wait: p->out holds the picture. */
pb_result pb_present_pass_run(pb_gpu *g, pb_present_pass *p, const pb_present_job *job);
/* The picture on the host (tests, screenshots): 4 x pixels bytes. */
pb_result pb_present_pass_download(pb_gpu *g, const pb_present_pass *p, uint8_t *rgba, uint32_t pixels);

#endif
