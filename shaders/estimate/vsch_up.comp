// View-sample cluster hierarchy (seed 004 4.1, 4.5; Fig. 3 right, Fig. 4),
// one dispatch per level L = 1 .. PB_VSCH_LEVELS: each node of level L from
// its children (the clusters of a tile, or 8 x 4 nodes of level L - 1): the
// occupancy mask (levels >= 2; a tile's is vsch_mark's), the union of the
// boxes, the samples, and the normal cone: the axis the sample-weighted
// mean of the children's axes, alpha the largest angle from it to a child's
// axis plus that child's alpha (4.5: "the maximum of the subnodes'
// deviation from that average plus the subnodes' normal-cone angle").
// The nearest edge of a sample below (word 15) is the children's minimum.
// Each node is written by one invocation: no atomics.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
#include "common/vsch.glsl"

void main() {
  uint gid = pb_gid();
  uint L = vp.level;
  uint nx = vd[PB_VSCH_H_NX + L], ny = vd[PB_VSCH_H_NY + L];
  if (gid >= nx * ny) return;
  uint x = gid % nx, y = gid / nx;
  uint g = pb_level_node(L, x, y);
  uint child[32];
  uint nc = 0u, mask = 0u;
  if (L == 1u) {
    mask = vd[pb_node_word(g, 6u)];
    uint base = vd[pb_node_word(g, 14u)];
    for (uint i = 0u; i < uint(bitCount(mask)); ++i) child[nc++] = base + i;
  } else {
    uint cnx = vd[PB_VSCH_H_NX + L - 1u], cny = vd[PB_VSCH_H_NY + L - 1u];
    for (uint i = 0u; i < 32u; ++i) {
      uint cx = x * PB_VSCH_BRANCH_X + (i % PB_VSCH_BRANCH_X), cy = y * PB_VSCH_BRANCH_Y + (i / PB_VSCH_BRANCH_X);
      if (cx >= cnx || cy >= cny) continue;
      uint cg = pb_level_node(L - 1u, cx, cy);
      if (vd[pb_node_word(cg, 7u)] == 0u) continue;
      mask |= 1u << i;
      child[nc++] = cg;
    }
    vd[pb_node_word(g, 6u)] = mask;
  }
  vec3 lo = vec3(uintBitsToFloat(0x7f800000u)), hi = -lo, a = vec3(0.0);
  uint samples = 0u, edge_min = 0x7f800000u;
  for (uint k = 0u; k < nc; ++k) {
    uint cg = child[k];
    edge_min = min(edge_min, vd[pb_node_word(cg, 15u)]);
    lo = min(lo, pb_node_lo(cg));
    hi = max(hi, pb_node_hi(cg));
    uint s = vd[pb_node_word(cg, 7u)];
    samples += s;
    a += pb_node_axis(cg, L - 1u) * float(s);
  }
  float la = length(a);
  vec3 axis = la > 1e-20 ? a / la : vec3(0.0, 0.0, 1.0);
  float alpha = la > 1e-20 ? 0.0 : PB_VSCH_PI;
  for (uint k = 0u; k < nc; ++k) {
    uint cg = child[k];
    float dev = acos(clamp(dot(pb_node_axis(cg, L - 1u), axis), -1.0, 1.0));
    alpha = max(alpha, dev + pb_node_alpha(cg));
  }
  alpha = min(alpha, PB_VSCH_PI);
  uint b = pb_node_word(g, 0u);
  vd[b] = pb_ord(lo.x), vd[b + 1u] = pb_ord(lo.y), vd[b + 2u] = pb_ord(lo.z);
  vd[b + 3u] = pb_ord(hi.x), vd[b + 4u] = pb_ord(hi.y), vd[b + 5u] = pb_ord(hi.z);
  vd[b + 7u] = samples;
  vd[b + 8u] = floatBitsToUint(axis.x), vd[b + 9u] = floatBitsToUint(axis.y), vd[b + 10u] = floatBitsToUint(axis.z);
  vd[b + 11u] = floatBitsToUint(alpha);
  vd[b + 15u] = edge_min; // the nearest edge of any sample below (non-negative float bits)
}
