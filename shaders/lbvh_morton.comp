#version 450
// LBVH pass 3: 30-bit Morton code of each photon position within the map's
// bounds; values = photon index (the sort's payload).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= info.count) return;
  keys[gid] = pb_morton30(photons_in[gid].position, info.lo, info.hi);
  vals[gid] = gid;
}
