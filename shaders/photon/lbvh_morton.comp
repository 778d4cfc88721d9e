#version 450
// LBVH pass 2: the 30-bit Morton code of each photon position within the
// map's bounds (the sort's key) and the photon's index (its value); clears
// the climb's visit counters.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

void main() {
  uint gid = pb_gid(), n = info.count;
  if (gid >= n) return;
  keys[gid] = pb_morton30(photons_in[gid].position, info.lo, info.hi);
  vals[gid] = gid;
  if (gid + 1u < n) visit[gid] = 0u;
}
