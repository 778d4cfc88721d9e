#version 450
// LBVH pass 3 (after the sort), one invocation per sorted photon: the
// photon copied into Morton order, as the 48-byte record
// (common/photon_pack.glsl), with its footprint scaled by info.footprint_scale (the estimator's
// per-build bandwidth, e.g. SPPM's shrinking radius: the boxes and the
// gather's kernel and normalisation all read these copies), then the
// hierarchy, the boxes and the leaf merge in one bottom-up climb from it
// (Apetrei 2014, "Fast and simple agglomerative LBVH construction", Alg. 1):
// a subtree covering sorted photons l..r has its parent at the split on the
// side whose neighbouring keys share the longer prefix (delta, Karras 2012:
// the (code, index) keys' common prefix length), at split r (it is the left
// child) or at split l - 1 (the right child). Each child writes its entry
// into the parent and counts its arrival; the second to arrive (an atomic
// count: the first stops, no one waits, so no forward-progress assumption)
// knows the
// parent's range, box and count, merges it into a leaf when it covers at
// most T_auto photons or one Morton code (seed 000 5.3 / 6.2), and climbs
// on. The finisher of the root writes info.root.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"
#include "common/photon_pack.glsl"

// The fences around the visit count (lbvh.c turns them off on llvmpipe, see
// there).
layout(constant_id = PB_SPEC_FENCES) const bool SC_FENCES = true;

// Common prefix length of the sorted (code, index) keys i and i + 1.
int pb_delta(uint i) {
  uint a = keys[pc.sorted + i], b = keys[pc.sorted + i + 1u];
  return a != b ? 31 - findMSB(a ^ b) : 32 + 31 - findMSB(i ^ (i + 1u));
}

// A child entry (pb_gpu_lbvh_child) as its two 4-word halves.
struct pb_entry {
  uvec4 lo_ref, hi_count;
};
vec3 pb_lo(pb_entry c) { return uintBitsToFloat(c.lo_ref.xyz); }
vec3 pb_hi(pb_entry c) { return uintBitsToFloat(c.hi_count.xyz); }

// Photon i: copied, then climbed from; true when this climb finished the
// root (its entry in c). `leaves` counts the leaves this climb made children
// of inner nodes.
bool pb_climb(uint i, uint n, uint t_auto, out pb_entry c, inout uint leaves) {
  uint src = vals[pc.sorted + i] * 6u, dst = i * PB_PHOTON_PACKED_WORDS4;
  float k = info.footprint_scale;
  uvec4 w0 = photons_in4[src], w1 = photons_in4[src + 1u], w2 = photons_in4[src + 2u];
  uvec4 w3 = photons_in4[src + 3u], w4 = photons_in4[src + 4u], w5 = photons_in4[src + 5u];
  w1.w = floatBitsToUint(uintBitsToFloat(w1.w) * k);                    // radius
  w2.w = floatBitsToUint(uintBitsToFloat(w2.w) * k);                    // normal_extent
  w4.xyz = floatBitsToUint(uintBitsToFloat(w4.xyz) * k);                // axis_u
  w5.xyz = floatBitsToUint(uintBitsToFloat(w5.xyz) * k);                // axis_v
  // Stored as the 48-byte record (common/photon_pack.glsl); the box is the
  // decoded footprint's, the one the gather tests against.
  pb_gpu_photon p = pb_gpu_photon(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), uintBitsToFloat(w1.w),
                                  uintBitsToFloat(w2.xyz), uintBitsToFloat(w2.w), uintBitsToFloat(w3.xyz), w3.w,
                                  uintBitsToFloat(w4.xyz), uintBitsToFloat(w4.w), uintBitsToFloat(w5.xyz),
                                  uintBitsToFloat(w5.w));
  uvec4 q0, q1, q2;
  pb_photon_pack(p, q0, q1, q2);
  photons4[dst] = q0;
  photons4[dst + 1u] = q1;
  photons4[dst + 2u] = q2;
  pb_gpu_photon d = pb_photon_unpack(q0, q1, q2);
  vec3 pos = d.position;
  vec3 e = pb_footprint_extent(d.axis_u, d.axis_v, d.normal, d.normal_extent);
  c = pb_entry(uvec4(floatBitsToUint(pos - e), PB_LBVH_LEAF | i), uvec4(floatBitsToUint(pos + e), 1u));
  uint l = i, r = i;
  while (l != 0u || r != n - 1u) {
    int dl = l == 0u ? -1 : pb_delta(l - 1u), dr = r == n - 1u ? -1 : pb_delta(r);
    uint parent = dr > dl ? r : l - 1u, side = dr > dl ? 0u : 1u;
    uint at = parent * 4u + side * 2u;
    nodes4[at] = c.lo_ref;
    nodes4[at + 1u] = c.hi_count;
    if (SC_FENCES) memoryBarrierBuffer(); // the entry before the count (release)
    if (atomicAdd(visit[parent], 1u) == 0u) return false; // the sibling goes on
    if (SC_FENCES) memoryBarrierBuffer(); // the sibling's entry after the count (acquire)
    at ^= 2u; // the sibling's entry
    pb_entry o = pb_entry(nodes4[at], nodes4[at + 1u]);
    if (side == 0u) r = parent + o.hi_count.w;
    else l = parent + 1u - o.hi_count.w;
    uint count = r - l + 1u;
    // The parent's split has the smallest delta in its range: 32 and more
    // when all its codes are equal (the index part alone differs).
    bool leaf = count <= t_auto || max(dl, dr) >= 32;
    if (!leaf) leaves += ((c.lo_ref.w & PB_LBVH_LEAF) != 0u ? 1u : 0u) + ((o.lo_ref.w & PB_LBVH_LEAF) != 0u ? 1u : 0u);
    c = pb_entry(uvec4(floatBitsToUint(min(pb_lo(c), pb_lo(o))), leaf ? (PB_LBVH_LEAF | l) : parent),
                 uvec4(floatBitsToUint(max(pb_hi(c), pb_hi(o))), count));
  }
  return true;
}

void main() {
  uint i = pb_gid(), n = info.count, leaves = 0u;
  if (i >= n) return;
  pb_entry c;
  bool root = pb_climb(i, n, info.t_auto, c, leaves);
  if (leaves != 0u) atomicAdd(info.leaves, leaves);
  if (!root) return;
  // The root. A map that is one leaf gets a node of its own (child 1 empty).
  if ((c.lo_ref.w & PB_LBVH_LEAF) == 0u) {
    info.root = c.lo_ref.w;
    return;
  }
  uvec3 inf = uvec3(0x7f800000u);
  nodes4[(n - 1u) * 4u] = c.lo_ref;
  nodes4[(n - 1u) * 4u + 1u] = c.hi_count;
  nodes4[(n - 1u) * 4u + 2u] = uvec4(inf, PB_LBVH_NONE);
  nodes4[(n - 1u) * 4u + 3u] = uvec4(inf | 0x80000000u, 0u); // -inf, count 0
  info.root = n - 1u;
  info.leaves = 1u;
}
