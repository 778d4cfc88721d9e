// View-sample cluster hierarchy (seed 004), pass 1 of a sample: every node
// record back to empty (boxes inverted, masks, counts, cones, lists, the
// trivial and directional sums), the header, and the level dimensions of
// this band (clusters of PB_VSCH_TILE^2 pixels, 8 x 4 nodes per node above).
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
  if (gid == 0u) {
    for (uint w = 0u; w < PB_VSCH_HEADER_WORDS; ++w) vd[w] = 0u;
    vd[PB_VSCH_H_NEAR] = pb_ord(uintBitsToFloat(0x7f800000u));
    vd[PB_VSCH_H_FAR] = pb_ord(-uintBitsToFloat(0x7f800000u));
    uint width = max(frame.width, 1u);
    uint rows = (vp.pixels + width - 1u) / width;
    uint nx = (width + PB_VSCH_TILE - 1u) / PB_VSCH_TILE, ny = (rows + PB_VSCH_TILE - 1u) / PB_VSCH_TILE;
    for (uint L = 1u; L <= PB_VSCH_LEVELS; ++L) {
      vd[PB_VSCH_H_NX + L] = nx;
      vd[PB_VSCH_H_NY + L] = ny;
      nx = (nx + PB_VSCH_BRANCH_X - 1u) / PB_VSCH_BRANCH_X;
      ny = (ny + PB_VSCH_BRANCH_Y - 1u) / PB_VSCH_BRANCH_Y;
    }
  }
  if (gid >= vp.nodes) return;
  uint b = vp.node_off + gid * PB_VSCH_NODE_WORDS;
  uint inf = pb_ord(uintBitsToFloat(0x7f800000u)), ninf = pb_ord(-uintBitsToFloat(0x7f800000u));
  for (uint k = 0u; k < 3u; ++k) {
    vd[b + k] = inf;
    vd[b + 3u + k] = ninf;
  }
  for (uint k = 6u; k < PB_VSCH_NODE_WORDS; ++k) vd[b + k] = 0u;
  vd[b + 15u] = 0x7f800000u; // no edge near any sample (yet): +inf
  uint t = vp.triv_off + gid * PB_VSCH_TRIVIAL_WORDS;
  for (uint k = 0u; k < PB_VSCH_TRIVIAL_WORDS; ++k) vd[t + k] = 0u;
  if (vp.dir_off != 0u) {
    uint d = vp.dir_off + gid * PB_VSCH_DIR_WORDS;
    for (uint k = 0u; k < PB_VSCH_DIR_WORDS; ++k) vd[d + k] = 0u;
  }
}
