#version 450
// LBVH pass 7: leaf merge by T_auto (seed 000 5.3 / 6.2). An inner node is
// collapsed when it covers at most T_auto photons or photons that all share
// one Morton code (they cannot be split). Children that are collapsed become
// leaf references; the last photon of every leaf gets PB_PHOTON_LEAF_END.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

bool pb_collapsed(uint i) {
  uint f = nodes[i].first, l = nodes[i].last;
  return l - f + 1u <= info.t_auto || keys[f] == keys[l];
}

void main() {
  uint gid = pb_gid();
  if (gid >= pc.count) return; // count - 1 inner nodes
  uint i = gid;
  bool c = pb_collapsed(i);
  bool parent_c = i != 0u && pb_collapsed(nodes[i].parent);
  if (c) {
    nodes[i].flags = PB_LBVH_NODE_COLLAPSED;
    if (!parent_c) { // the top of a merged leaf
      uint last = nodes[i].last;
      photons[last].flags |= PB_PHOTON_LEAF_END;
      atomicAdd(info.leaves, 1u);
      if (i == 0u) info.root = PB_LBVH_LEAF | nodes[0].first;
    }
    return;
  }
  // An inner node that stays: its children become leaf references when
  // collapsed; single photons are leaves of one.
  uint refs[2] = uint[2](nodes[i].left, nodes[i].right);
  for (int k = 0; k < 2; ++k) {
    uint r = refs[k];
    if ((r & PB_LBVH_LEAF) != 0u) {
      photons[r & ~PB_LBVH_LEAF].flags |= PB_PHOTON_LEAF_END;
      atomicAdd(info.leaves, 1u);
    } else if (pb_collapsed(r)) {
      refs[k] = PB_LBVH_LEAF | nodes[r].first;
    }
  }
  nodes[i].left = refs[0];
  nodes[i].right = refs[1];
}
