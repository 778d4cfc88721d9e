#version 450
// LBVH pass 5: Karras (2012) binary radix tree over the sorted codes, one
// invocation per inner node (count - 1 of them). Equal codes are told apart
// by their sorted index (the split list of seed 000 6.2, built in parallel).
// Also clears the bottom-up visit counters.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

// Length of the common prefix of the (code, index) keys i and j; -1 when j
// is outside 0 .. n-1.
int pb_delta(int i, int j, int n) {
  if (j < 0 || j >= n) return -1;
  uint ci = keys[i], cj = keys[j];
  if (ci == cj) return 32 + (31 - findMSB(uint(i) ^ uint(j)));
  return 31 - findMSB(ci ^ cj);
}

void main() {
  uint gid = pb_gid();
  if (gid >= pc.count) return; // count - 1 inner nodes
  int n = int(info.count);
  int i = int(gid);
  int d = pb_delta(i, i + 1, n) - pb_delta(i, i - 1, n) >= 0 ? 1 : -1;
  int dmin = pb_delta(i, i - d, n);
  int lmax = 2;
  while (pb_delta(i, i + lmax * d, n) > dmin) lmax *= 2;
  int len = 0;
  for (int t = lmax / 2; t >= 1; t /= 2)
    if (pb_delta(i, i + (len + t) * d, n) > dmin) len += t;
  int j = i + len * d;
  int dnode = pb_delta(i, j, n);
  int s = 0;
  for (int t = (len + 1) / 2;; t = (t + 1) / 2) {
    if (pb_delta(i, i + (s + t) * d, n) > dnode) s += t;
    if (t <= 1) break;
  }
  int gamma = i + s * d + min(d, 0);
  uint first = uint(min(i, j)), last = uint(max(i, j));
  uint left = first == uint(gamma) ? (PB_LBVH_LEAF | uint(gamma)) : uint(gamma);
  uint right = last == uint(gamma + 1) ? (PB_LBVH_LEAF | uint(gamma + 1)) : uint(gamma + 1);
  nodes[i].left = left;
  nodes[i].right = right;
  nodes[i].first = first;
  nodes[i].last = last;
  nodes[i].flags = 0u;
  if (i == 0) nodes[0].parent = PB_LBVH_NONE;
  if ((left & PB_LBVH_LEAF) != 0u) leaf_parent[left & ~PB_LBVH_LEAF] = uint(i);
  else nodes[left].parent = uint(i);
  if ((right & PB_LBVH_LEAF) != 0u) leaf_parent[right & ~PB_LBVH_LEAF] = uint(i);
  else nodes[right].parent = uint(i);
  visit[i] = 0u;
}
