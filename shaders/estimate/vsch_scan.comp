// View-sample cluster hierarchy (seed 004 4.3: "the prefix sum of that
// array"), one workgroup: the exclusive prefix sum of
//   level 0 (vp.level 0)  the tiles' occupied slices (popcount of their
//                        masks): the global id of each tile's first cluster
//                        (the compact cluster list), and their number;
//   level 1               the photons' list insertions (vsch_count): where
//                        each photon writes its pairs (vsch_fill), the pairs'
//                        number (capped at the sort's capacity) and the
//                        indirect dispatch over them.
// Each invocation sums a contiguous chunk, the 64 chunk sums are scanned,
// then each chunk is written: two reads of the input, two barriers.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
#include "common/vsch.glsl"

shared uint chunk_sum[PB_GPU_WORKGROUP];
shared uint total_sum;

uint count_of() {
  return vp.level == 0u ? vd[PB_VSCH_H_NX + 1u] * vd[PB_VSCH_H_NY + 1u] : vd[PB_VSCH_H_PHOTONS];
}
uint value(uint i) {
  return vp.level == 0u ? uint(bitCount(vd[pb_node_word(vp.level_base[1] + i, 6u)])) : vd[vp.photon_off + i];
}
void store(uint i, uint v) {
  if (vp.level == 0u)
    vd[pb_node_word(vp.level_base[1] + i, 14u)] = v;
  else
    vd[vp.photon_off + vp.capacity + i] = v;
}

void main() {
  uint t = gl_LocalInvocationID.x;
  uint n = count_of();
  uint chunk = (n + PB_GPU_WORKGROUP - 1u) / PB_GPU_WORKGROUP;
  uint b = min(t * chunk, n), e = min(b + chunk, n);
  uint s = 0u;
  for (uint i = b; i < e; ++i) s += value(i);
  chunk_sum[t] = s;
  barrier();
  if (t == 0u) {
    uint run = 0u;
    for (uint k = 0u; k < PB_GPU_WORKGROUP; ++k) {
      uint v = chunk_sum[k];
      chunk_sum[k] = run;
      run += v;
    }
    total_sum = run;
  }
  barrier();
  uint run = chunk_sum[t];
  for (uint i = b; i < e; ++i) {
    uint v = value(i);
    store(i, run);
    run += v;
  }
  if (t == 0u) {
    uint total = total_sum;
    if (vp.level == 0u) {
      vd[PB_VSCH_H_LEAVES] = total;
    } else {
      uint pairs = min(total, vp.pair_cap);
      vd[PB_VSCH_H_LISTED] = total;
      vd[PB_VSCH_H_PAIRS] = pairs;
      vd[PB_VSCH_H_PAIR_OVERFLOW] = total - pairs;
      uint groups = (pairs + PB_GPU_WORKGROUP - 1u) / PB_GPU_WORKGROUP;
      uint gx = min(groups, max(vp.max_groups_x, 1u));
      vd[PB_VSCH_H_ARGS] = gx;
      vd[PB_VSCH_H_ARGS + 1u] = gx > 0u ? (groups + gx - 1u) / gx : 0u;
      vd[PB_VSCH_H_ARGS + 2u] = 1u;
    }
  }
}
