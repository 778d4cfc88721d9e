#version 450
// LBVH pass 6a: node boxes of the nodes covering at most pc.src photons, one
// invocation per inner node, as the union of the exact footprint-ellipsoid
// AABBs of the node's photon interval (lbvh_boxes_top does the larger ones).
// A race-free stand-in for Karras' atomic bottom-up climb, which lost visits
// on lavapipe. The interval bound matters there too: llvmpipe ends every
// loop of an invocation after 65535 iterations in all (gallivm's
// LP_MAX_TGSI_LOOP_ITERATIONS, shared by all loops of the shader), so one
// invocation looping over the whole map left the root's box covering only
// the first 65535 photons, and the gather never entered the other half.
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
  if (l - f + 1u > pc.src) return; // lbvh_boxes_top
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
