/* The render passes of a frame (one file each, ordered by frame.c). Every
 * pass reads the same 16 storage buffers, in the binding order of
 * shaders/common/scene.glsl (the world's, PB_BIND_WORLD, is
 * shaders/common/lights.glsl's). */
#ifndef PB_RENDER_PASSES_H
#define PB_RENDER_PASSES_H

#include "gpu/gpu.h"
#include "shared/pb_gpu.h"

enum {
  PB_BIND_FRAME = 0, PB_BIND_NODES, PB_BIND_TRIS, PB_BIND_INDICES, PB_BIND_NORMALS, PB_BIND_UVS,
  PB_BIND_TRI_MATERIAL, PB_BIND_MATERIALS, PB_BIND_TEXTURES, PB_BIND_TEXELS, PB_BIND_LIGHTS,
  PB_BIND_GBUFFER, PB_BIND_ACCUM, PB_BIND_POSITIONS, PB_BIND_EMITTERS, PB_BIND_WORLD, PB_BIND_COUNT
};

/* Specialization constants, constant_id order of scene.glsl; ids 4 and 5
 * are the photon tracer's and the gather's own (0 here). */
enum {
  PB_SPEC_HAS_NORMALS = 0, PB_SPEC_TEXTURES, PB_SPEC_SPECULAR, PB_SPEC_EMISSIVE, PB_SPEC_PASS_4, PB_SPEC_PASS_5,
  PB_SPEC_SOFT_LIGHTS = 6, PB_SPEC_WORLD = 7, PB_SPEC_ALPHA = 8, PB_SPEC_COUNT
};

typedef struct pb_pass_setup {
  const pb_gpu_buffer *bindings[PB_BIND_COUNT];
  uint32_t spec[PB_SPEC_COUNT];
  uint32_t normal_maps; /* the gather's SC_NORMAL_MAPS (constant_id 5): eq. 20's
                           extra sums, compiled out for scenes without */
  uint32_t blender;     /* 1: the passes' PB_BLENDER builds (Blender materials) */
} pb_pass_setup;

/* gbuffer.c: primary visibility + specular eye chains + emission + AOVs. */
pb_result pb_pass_gbuffer_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out);
/* direct.c: shadow rays to the delta lights, one light sample per soft
 * light, one emissive triangle (picked by power) and the world (a BSDF
 * sample and a map sample, MIS) at the G-buffer's surfaces. */
pb_result pb_pass_direct_create(pb_gpu *g, const pb_pass_setup *s, pb_gpu_pipeline *out);
/* Records one pass over `pixels` pixels for sample `sample_index`. */
pb_result pb_pass_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t sample_index, uint32_t pixels);

#endif
