// View-sample cluster hierarchy (seed 004 4.3), after the sort: each
// node's list is the run of its id in the sorted pairs; one invocation per
// pair marks where a run starts and ends (node words 12, 13).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
layout(std430, set = 0, binding = PB_VSCH_BIND_KEYS) readonly buffer Keys { uint keys[]; };
#include "common/vsch.glsl"

void main() {
  uint gid = pb_gid();
  uint n = vd[PB_VSCH_H_PAIRS];
  if (gid >= n) return;
  uint k = keys[vp.sorted + gid];
  if (gid == 0u || keys[vp.sorted + gid - 1u] != k) vd[pb_node_word(k, 12u)] = gid;
  if (gid + 1u == n || keys[vp.sorted + gid + 1u] != k) vd[pb_node_word(k, 13u)] = gid + 1u;
}
