/* One camera path of the reference renderer (pathtrace.c). */
#ifndef PB_REF_PATHTRACE_H
#define PB_REF_PATHTRACE_H

#include "ref/ctx.h"
#include "ref/photons.h"
#include "ref/vec.h"

/* One camera sample's outputs (pathtrace.c). */
typedef struct pb_sample_out {
  v3 direct, indirect;
  v3 albedo, normal;
  float depth;   /* camera-space z, 0 on a miss */
  int hit;
  uint64_t rays;
} pb_sample_out;

/* Traces one path from pixel (x, y) for sample index `sample`, with caustic
 * photon lookups when map is not NULL. */
void pb_trace_camera_sample(const pb_ref_ctx *ctx, const pb_ref_photon_map *map,
                            uint32_t x, uint32_t y, uint32_t sample,
                            pb_sample_out *out);

#endif
