#version 450
// LBVH pass 6b: boxes of the nodes covering more than pc.src photons (the
// top of the tree, about 2 count / pc.src nodes), one invocation per inner
// node: the union of the boxes lbvh_boxes wrote for the first nodes of at
// most pc.src photons below it (and of single photons hanging off the top),
// found by a traversal of the top part only. The host picks pc.src so that
// both passes stay far below llvmpipe's 65535 loop iterations per invocation.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

bool pb_small(uint i) { return nodes[i].last - nodes[i].first + 1u <= pc.src; }

void main() {
  uint gid = pb_gid();
  if (gid >= pc.count) return; // count - 1 inner nodes
  if (pb_small(gid)) return;   // lbvh_boxes
  vec3 lo = vec3(uintBitsToFloat(0x7f800000u)), hi = -lo;
  uint stack[PB_LBVH_STACK];
  uint sp = 0u;
  stack[sp++] = nodes[gid].left;
  stack[sp++] = nodes[gid].right;
  while (sp > 0u) {
    uint ref = stack[--sp];
    if ((ref & PB_LBVH_LEAF) != 0u) {
      pb_gpu_photon p = photons[ref & ~PB_LBVH_LEAF];
      vec3 e = pb_footprint_extent(p.axis_u, p.axis_v, p.normal, p.normal_extent);
      lo = min(lo, p.position - e);
      hi = max(hi, p.position + e);
    } else if (pb_small(ref)) {
      lo = min(lo, nodes[ref].lo);
      hi = max(hi, nodes[ref].hi);
    } else if (sp + 2u <= PB_LBVH_STACK) { // the tree is at most 62 deep
      stack[sp++] = nodes[ref].left;
      stack[sp++] = nodes[ref].right;
    }
  }
  nodes[gid].lo = lo;
  nodes[gid].hi = hi;
}
