#version 450
// Radix sort, step 1 of a pass: the digit histogram of each tile of
// PB_GPU_WORKGROUP keys (shared-memory atomics), digit-major into hist.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

shared uint s_hist[PB_LBVH_RADIX];

void main() {
  uint gid = pb_gid();
  uint tile = gid / PB_GPU_WORKGROUP; // uniform in the workgroup
  if (tile >= info.tiles) return;
  uint l = gl_LocalInvocationID.x;
  if (l < PB_LBVH_RADIX) s_hist[l] = 0u;
  barrier();
  if (gid < info.count) atomicAdd(s_hist[(keys[pc.src + gid] >> pc.shift) & (PB_LBVH_RADIX - 1u)], 1u);
  barrier();
  if (l < PB_LBVH_RADIX) hist[l * info.tiles + tile] = s_hist[l];
}
