#version 450
// Radix sort, step 3: stable scatter. Rank of a key among the keys of its
// tile with the same digit and a lower index, from per-digit bit masks of
// the tile (shared atomicOr, then bitCount below the invocation's bit).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

const uint WORDS = PB_GPU_WORKGROUP / 32u;
shared uint s_mask[PB_LBVH_RADIX * WORDS];

void main() {
  uint gid = pb_gid();
  uint tile = gid / PB_GPU_WORKGROUP; // uniform in the workgroup
  if (tile >= info.tiles) return;
  uint l = gl_LocalInvocationID.x;
  for (uint i = l; i < PB_LBVH_RADIX * WORDS; i += PB_GPU_WORKGROUP) s_mask[i] = 0u;
  barrier();
  bool valid = gid < info.count;
  uint key = 0u, d = 0u;
  if (valid) {
    key = keys[pc.src + gid];
    d = (key >> pc.shift) & (PB_LBVH_RADIX - 1u);
    atomicOr(s_mask[d * WORDS + l / 32u], 1u << (l % 32u));
  }
  barrier();
  if (!valid) return;
  uint rank = 0u;
  for (uint w = 0u; w < l / 32u; ++w) rank += bitCount(s_mask[d * WORDS + w]);
  uint below = (l % 32u) == 0u ? 0u : (s_mask[d * WORDS + l / 32u] & ((1u << (l % 32u)) - 1u));
  rank += bitCount(below);
  uint dst = hist[d * info.tiles + tile] + rank;
  keys[pc.dst + dst] = key;
  vals[pc.dst + dst] = vals[pc.src + gid];
}
