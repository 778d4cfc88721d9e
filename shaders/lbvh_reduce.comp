#version 450
// LBVH pass 2 (one workgroup): sums the partial footprint areas, sets
// T_auto (seed 000 section 5.3: proportional to the ratio of the summed
// footprint areas to the scene's surface area, i.e. the expected number of
// footprints over a surface point; factor 1) and converts the bounds.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

shared float s_sum[PB_GPU_WORKGROUP];

void main() {
  uint gid = pb_gid();
  if (gid >= PB_GPU_WORKGROUP) return; // one workgroup
  uint l = gl_LocalInvocationID.x;
  float a = 0.0;
  for (uint i = l; i < info.tiles; i += PB_GPU_WORKGROUP) a += area_partial[i];
  s_sum[l] = a;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) s_sum[l] += s_sum[l + w];
    barrier();
  }
  if (l == 0u) {
    float sum = s_sum[0];
    info.area_sum = sum;
    float ratio = info.scene_area > 0.0 ? sum / info.scene_area : 1.0;
    if (isnan(ratio)) ratio = 1.0;
    uint t = uint(clamp(round(ratio), 1.0, float(PB_LBVH_MAX_LEAF)));
    info.t_computed = t;
    // A fixed threshold from the host (benchmark leaf-size sweeps) wins.
    info.t_auto = info.t_fixed != 0u ? info.t_fixed : t;
    if (info.count > 0u) {
      info.lo = vec3(pb_ordered_to_float(info.bmin[0]), pb_ordered_to_float(info.bmin[1]),
                     pb_ordered_to_float(info.bmin[2]));
      info.hi = vec3(pb_ordered_to_float(info.bmax[0]), pb_ordered_to_float(info.bmax[1]),
                     pb_ordered_to_float(info.bmax[2]));
    }
  }
}
