#version 450
// LBVH pass 6: node boxes, one invocation per inner node, as the union of
// the exact footprint-ellipsoid AABBs of the node's photon interval.
// O(n * depth) work and the root's invocation loops over every photon: a
// race-free stand-in for Karras' atomic bottom-up climb, which lost visits
// on lavapipe (nodes never reached; see the report of issue "photon LBVH").
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= pc.count) return; // count - 1 inner nodes
  uint f = nodes[gid].first, l = nodes[gid].last;
  vec3 lo = vec3(uintBitsToFloat(0x7f800000u)), hi = -lo;
  for (uint i = f; i <= l; ++i) {
    pb_gpu_photon p = photons[i];
    vec3 e = pb_footprint_extent(p.axis_u, p.axis_v, p.normal, p.normal_extent);
    lo = min(lo, p.position - e);
    hi = max(hi, p.position + e);
  }
  nodes[gid].lo = lo;
  nodes[gid].hi = hi;
}
