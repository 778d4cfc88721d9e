#version 450
// LBVH pass 1: bounds of the photon positions (atomic min/max on
// order-preserving uints) and the footprint areas summed per workgroup
// (a shared-memory tree, no subgroup assumption) into area_partial[tile].
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

shared float s_area[PB_GPU_WORKGROUP];

void main() {
  uint gid = pb_gid();
  uint tile = gid / PB_GPU_WORKGROUP; // uniform in the workgroup
  if (tile >= info.tiles) return;
  uint l = gl_LocalInvocationID.x;
  float a = 0.0;
  if (gid < info.count) {
    pb_gpu_photon p = photons_in[gid];
    // Areas of the scaled footprints (lbvh_reorder applies the scale).
    a = pb_footprint_area(p.axis_u, p.axis_v) * (info.footprint_scale * info.footprint_scale);
    if (isnan(a) || isinf(a)) a = 0.0;
    for (int k = 0; k < 3; ++k) {
      atomicMin(info.bmin[k], pb_float_to_ordered(p.position[k]));
      atomicMax(info.bmax[k], pb_float_to_ordered(p.position[k]));
    }
  }
  s_area[l] = a;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) s_area[l] += s_area[l + w];
    barrier();
  }
  if (l == 0u) area_partial[tile] = s_area[0];
}
