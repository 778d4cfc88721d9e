#version 450
// LBVH pass 1, one workgroup per tile of PB_LBVH_BOUNDS_TILE photons: the
// bounds of the photon positions (the Morton codes' box; atomic min/max of
// order-preserving uints, one per workgroup and axis) and the sum of the
// scaled footprint areas per tile. The last workgroup to finish (an atomic
// count; it waits on no one, so no forward-progress assumption) adds the
// tiles' sums in tile order (the same float sum whatever the finishing
// order), sets T_auto (pb_t_auto below, from seed 000 section 5.3's ratio
// of the summed footprint areas to the scene's surface area and the
// traversal's cost) and converts the bounds to floats.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

// T_auto from the gather's traversal cost (seed 000 5.3: "proportional to
// the ratio" k of the summed footprint areas to the scene's surface area,
// the expected number of footprints over a surface point). Model: photons
// spread over the surfaces with density rho, footprints of radius r, so
// k = rho pi r^2. A node holding S photons covers their region, of area
// S / rho, widened by r on every side: of the N / S such nodes,
// (1 + 2 r sqrt(rho / S))^2 = (1 + 2 sqrt(k / (pi S)))^2 contain a query
// point. A query then tests the photons of the leaves that contain it,
// P = S_leaf (1 + 2 sqrt(k / (pi S_leaf)))^2, and opens the inner nodes that
// contain it, V = sum over the levels S = 2 S_leaf, 4 S_leaf, ... < N of
// min(N / S, (1 + 2 sqrt(k / (pi S)))^2); cost = c_node V + c_photon P.
// A threshold T gives leaves of T / (2 ln 2) photons on average (a leaf
// is a subtree of at most T whose parent has more: its size spread evenly
// in log2 between T / 2 and T; measured 0.68 T on cornell_box, 0.72 T
// derived). c_node / c_photon = 1: opening a node reads 4 uvec4 and tests
// two boxes, a photon 6 uvec4 and its ellipsoid (llvmpipe's cost follows the
// loads, common/lbvh_traverse.glsl); a least-squares fit of this model to
// the leaf sweeps of cornell_box and cornell_caustics together (20 points,
// bench/README.md) gives 0.98. T_auto is the T in [1, PB_LBVH_MAX_LEAF]
// of least modelled cost: about k^(1/3), not k (k 55 gives 7, k 400 gives
// 12), the order of the paper's T_auto (5-56 against k_PD 175-480).
#define PB_T_AUTO_NODE_COST 1.0
uint pb_t_auto(float k, uint n) {
  float kp = max(k, 0.0) / 3.14159265358979, nf = max(float(n), 1.0);
  float best = uintBitsToFloat(0x7f800000u);
  uint bt = 1u;
  for (uint t = 1u; t <= PB_LBVH_MAX_LEAF; ++t) {
    float sl = max(float(t) * 0.72134752, 1.0); // T / (2 ln 2)
    float sq = sqrt(sl) + 2.0 * sqrt(kp);
    float cost = sq * sq, v = 0.0;
    for (float sz = 2.0 * sl; sz < nf; sz *= 2.0) {
      float c = 1.0 + 2.0 * sqrt(kp / sz);
      v += min(nf / sz, c * c);
    }
    cost += PB_T_AUTO_NODE_COST * v;
    if (cost < best) best = cost, bt = t;
  }
  return bt;
}

shared vec3 s_lo[PB_GPU_WORKGROUP], s_hi[PB_GPU_WORKGROUP];
shared float s_area[PB_GPU_WORKGROUP];
shared bool s_last;

void main() {
  uint tile = pb_group();
  if (tile >= info.tiles) return; // uniform in the workgroup
  uint l = gl_LocalInvocationID.x, n = info.count;
  vec3 lo = vec3(uintBitsToFloat(0x7f800000u)), hi = -lo;
  float a = 0.0, k2 = info.footprint_scale * info.footprint_scale;
  for (uint r = 0u; r < PB_LBVH_BOUNDS_PPT; ++r) {
    uint i = tile * PB_LBVH_BOUNDS_TILE + r * PB_GPU_WORKGROUP + l;
    if (i >= n) break;
    pb_gpu_photon p = photons_in[i];
    lo = min(lo, p.position);
    hi = max(hi, p.position);
    // Areas of the scaled footprints (lbvh_climb applies the scale).
    float ai = pb_footprint_area(p.axis_u, p.axis_v) * k2;
    if (!isnan(ai) && !isinf(ai)) a += ai;
  }
  s_lo[l] = lo;
  s_hi[l] = hi;
  s_area[l] = a;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) {
      s_lo[l] = min(s_lo[l], s_lo[l + w]);
      s_hi[l] = max(s_hi[l], s_hi[l + w]);
      s_area[l] += s_area[l + w];
    }
    barrier();
  }
  if (l == 0u) {
    for (int k = 0; k < 3; ++k) {
      atomicMin(info.bmin[k], pb_float_to_ordered(s_lo[0][k]));
      atomicMax(info.bmax[k], pb_float_to_ordered(s_hi[0][k]));
    }
    area_partial[tile] = s_area[0];
    memoryBarrierBuffer(); // the bounds and the partial before the count (release)
    s_last = atomicAdd(info.tiles_done, 1u) == info.tiles - 1u;
  }
  barrier();
  if (!s_last) return;
  memoryBarrierBuffer(); // every tile's partial and bounds after the count (acquire)
  float sum = 0.0;
  for (uint t = l; t < info.tiles; t += PB_GPU_WORKGROUP) sum += area_partial[t];
  s_area[l] = sum;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) s_area[l] += s_area[l + w];
    barrier();
  }
  if (l != 0u) return;
  sum = s_area[0];
  info.area_sum = sum;
  float ratio = info.scene_area > 0.0 ? sum / info.scene_area : 1.0;
  if (isnan(ratio)) ratio = 1.0;
  uint t = pb_t_auto(ratio, n);
  info.t_computed = t;
  // A fixed threshold from the host (benchmark leaf-size sweeps) wins.
  info.t_auto = info.t_fixed != 0u ? info.t_fixed : t;
  info.lo = vec3(pb_ordered_to_float(info.bmin[0]), pb_ordered_to_float(info.bmin[1]),
                 pb_ordered_to_float(info.bmin[2]));
  info.hi = vec3(pb_ordered_to_float(info.bmax[0]), pb_ordered_to_float(info.bmax[1]),
                 pb_ordered_to_float(info.bmax[2]));
}
