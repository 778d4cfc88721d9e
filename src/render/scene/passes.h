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
  const pb_gpu_accel *accel; /* the scene's acceleration structure when its rays
                                are cast as ray queries (pb_gpu_scene.ray_query),
                                else NULL: the GLSL BVH at PB_BIND_NODES */
} pb_pass_setup;

/* A kernel's SPIR-V builds (shaders.cmake), [PB_BLENDER][PB_RAY_QUERY]:
 * NAME, NAME_rq, NAME_blender, NAME_rq_blender. A kernel without Blender
 * materials lists its two builds twice. */
typedef struct pb_spirv {
  const uint32_t *code;
  size_t bytes;
} pb_spirv;
typedef struct pb_kernel_builds {
  pb_spirv build[2][2];
} pb_kernel_builds;
#define PB_SPIRV(n) {pb_spv_##n, sizeof pb_spv_##n}
#define PB_KERNEL_BUILDS(n) {{{PB_SPIRV(n), PB_SPIRV(n##_rq)}, {PB_SPIRV(n##_blender), PB_SPIRV(n##_rq_blender)}}}
#define PB_KERNEL_BUILDS_GLTF(n) {{{PB_SPIRV(n), PB_SPIRV(n##_rq)}, {PB_SPIRV(n), PB_SPIRV(n##_rq)}}}

/* pass.c: points d at k's build for `blender` and, with ray_query, at the
 * ray-query build whose binding `tlas` is the acceleration structure
 * (d->accel_bindings). Which build: 0..3, for the callers that keep a
 * pipeline until its build changes. */
uint32_t pb_kernel_select(pb_gpu_pipeline_desc *d, const pb_kernel_builds *k, uint32_t blender, int ray_query,
                          uint32_t tlas);
/* Binds the buffers (pb_gpu_pipeline_bind) and, on a pipeline of a
 * ray-query build, accel at its acceleration-structure binding. */
pb_result pb_kernel_bind(pb_gpu *g, pb_gpu_pipeline *p, const pb_gpu_buffer *const *buffers, uint32_t count,
                         const pb_gpu_accel *accel);

/* A scene pass's builds (its 16 bindings PB_BIND_*, the TLAS at
 * PB_BIND_NODES in the ray-query builds). */
typedef struct pb_pass_module {
  const char *name;
  pb_kernel_builds k;
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
