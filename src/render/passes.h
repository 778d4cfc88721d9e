/* The render passes of a frame (one file each, ordered by frame.c). Every
 * pass reads the same 16 storage buffers, at the bindings PB_BIND_* of the
 * shader contract (shaders/shared/pb_contract.h, included by pb_gpu.h), as
 * are the specialization-constant ids PB_SPEC_*. */
#ifndef PB_RENDER_PASSES_H
#define PB_RENDER_PASSES_H

#include "gpu/gpu.h"
#include "shared/pb_gpu.h"

typedef struct pb_pass_setup {
  const pb_gpu_buffer *bindings[PB_BIND_COUNT];
  uint32_t spec[PB_SPEC_COUNT];
  uint32_t normal_maps; /* the gather's SC_NORMAL_MAPS (constant_id 5): eq. 20's
                           extra sums, compiled out for scenes without */
  uint32_t blender;     /* 1: the passes' PB_BLENDER builds (Blender materials) */
} pb_pass_setup;

/* A scene pass's SPIR-V: the glTF build and the PB_BLENDER build. */
typedef struct pb_pass_module {
  const char *name;
  const uint32_t *spirv;
  size_t bytes;
  const uint32_t *spirv_blender;
  size_t bytes_blender;
} pb_pass_module;

/* pass.c: a pipeline of module `m` with s's bindings and constants. */
pb_result pb_pass_create(pb_gpu *g, const pb_pass_setup *s, const pb_pass_module *m, pb_gpu_pipeline *out);

/* gbuffer.c: primary visibility + specular eye chains + emission + AOVs. */
pb_result pb_pass_gbuffer_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out);
/* direct.c: shadow rays to the delta lights, one light sample per soft
 * light, one emissive triangle (picked by power) and the world (a BSDF
 * sample and a map sample, MIS) at the G-buffer's surfaces. */
pb_result pb_pass_direct_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out);
/* Records one pass over `pixels` pixels for sample `sample_index`. */
pb_result pb_pass_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t sample_index, uint32_t pixels);

#endif
