#version 450
// kNN photon mapping (seed 000 section 3.1, the baseline of its Table 2): at
// the G-buffer's surface x (the first smooth vertex after the eye's specular
// chain, as gather.comp) the k nearest photon hits are found in the photon
// LBVH (the build of lbvh.c, reused: photons sorted in Morton order, nodes
// with both children's boxes), the bandwidth set to the distance r(x) of the
// k-th (the radius of their smallest sphere about x), and eq. 1 evaluated
// with that one bandwidth for all of them:
//   L(x, wo) ~ sum_{i<=k} 1 / r^2 K(|x - x_i|^2 / r^2) f(x, wi_i, wo) Phi_i,
// K the Epanechnikov kernel (2 / pi)(1 - t), unit integral over the unit
// disc, so K(.) / r^2 integrates to 1 over the disc of radius r. The search
// is bounded by r_max (3.1: "the bandwidth initially is only known to be
// bounded by a global r_max"): where fewer than k photons lie within r_max,
// r = r_max and those found count. The candidates are kept in a bounded
// max-heap of k entries keyed by squared distance (3.1: "a temporary set of
// k candidate hits ... updated as closer ones are found"), in each
// invocation's private memory; the traversal is depth first, nearer child
// first, and skips every child whose box lies farther than the heap's
// largest distance (or r_max while it is not full). The boxes bound the
// photons' footprint ellipsoids (lbvh_climb), so they contain the hit
// points: the box distance is a lower bound and the search exact. Only
// photons on the same side of the surface count (p.normal . n_g > 0, as in
// gather.comp: thin walls, and the other face at a corner), and none beyond
// an edge of the face where a wall stands; kernel mass past those edges is
// renormalised (common/kernel_edges.glsl),
// the BSDF, the adjoint shading-normal weight, the caustic / indirect split,
// eq. 20's sums and the beauty as in gather.comp.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_knn.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"

layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
layout(std430, set = 0, binding = PB_KNN_BIND_PHOTONS) readonly buffer Photons { uvec4 photons4[]; };
layout(std430, set = 0, binding = PB_KNN_BIND_NODES) readonly buffer Nodes2 { uvec4 lnodes4[]; };
layout(std430, set = 0, binding = PB_KNN_BIND_INFO) buffer InfoBuf { pb_gpu_lbvh_info info; };
layout(std430, set = 0, binding = PB_KNN_BIND_ACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(std430, set = 0, binding = PB_KNN_BIND_NMAP) buffer PhotonNmap { pb_gpu_photon_nmap pnmap[]; }; // normal maps only
layout(push_constant) uniform KnnPush { pb_gpu_knn_push kp; };
layout(constant_id = PB_SPEC_NORMAL_MAPS) const bool SC_NORMAL_MAPS = true;
layout(constant_id = PB_SPEC_KNN_K) const uint SC_K = PB_KNN_K_DEFAULT;
// Loop iterations the search may take per invocation (0: no bound), for
// llvmpipe (Mesa 22.3), whose gallivm loop limiter is ONE counter per
// shader function (main, everything inlined), per SIMD vector of 8 lanes,
// set to 65535 at entry and decremented at the back edge of EVERY loop,
// never reset (lp_bld_ir_common.c lp_exec_mask_function_init /
// lp_exec_endloop); at 0 every loop leaves after its current iteration,
// whatever its condition. The search was nested loops (the traversal, a
// leaf's photons, the heap's sift loops), and a SIMD vector runs a loop
// while any lane does, so a vector's back edges were sums over the outer
// iterations of the slowest lane's inner counts: on spot_room at k = 64
// (96 x 72, 65536 photons) 616 of 6912 pixels came out 0 while no query
// reached the per-lane bound of 50000 (queries_cut_short 0). How the cut
// loops left one photon in every slot was not traced; a cut sift loop
// skipping its final store would do it. Shown: in this one-loop search a
// dummy loop of 58000 back edges placed before it blacks 1176 pixels,
// 70000 all of them, with queries_cut_short still 0 (the limiter is
// silent and counts every loop); fixed-size heap arrays (PB_KNN_K_MAX
// instead of SC_K) changed nothing (616 again). Now the search is one
// loop, one step per iteration (a node, a photon or one level of a heap
// sift), so a vector's back edges are its slowest lane's steps and this
// bound (set by estimator_knn.c below 65535 less the other loops' share)
// holds for the vector too. Queries stopped by it are counted in
// info.stack_overflow.
layout(constant_id = PB_SPEC_KNN_BUDGET) const uint SC_BUDGET = 0u;
#include "common/lbvh_traverse.glsl"
#include "common/kernel_edges.glsl"

// The search sphere flattened into a disc along the surface normal (Jensen
// 1996's remedy for photons of a nearby parallel surface, a crate's top
// seen from the floor beside it; seed 000 3.1 says only "sphere"): the
// distance is |d|^2 + PB_KNN_FLATTEN (d . n)^2, a sphere squashed 5 times
// along n; coplanar photons keep their distance.
#define PB_KNN_FLATTEN 24.0
// Least cosine between a photon's normal and n_g at x for the same side
// (84 degrees: a ball's neighbours within r_max keep theirs).
#define PB_KNN_SAME_SIDE_COS 0.1

// The bounded max-heap: kh_d[0] the largest squared distance held.
float kh_d[SC_K];
uint kh_i[SC_K];

// Squared distance from x to the child's box (+inf for an empty child).
float pb_knn_box_d2(vec3 x, pb_lbvh_entry c) {
  vec3 lo = uintBitsToFloat(c.lo_ref.xyz), hi = uintBitsToFloat(c.hi_count.xyz);
  if (any(greaterThan(lo, hi))) return uintBitsToFloat(0x7f800000u); // +inf
  vec3 d = max(max(lo - x, x - hi), vec3(0.0));
  return dot(d, d);
}

void main() {
  uint gid = pb_gid();
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS || info.root == PB_LBVH_NONE) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, pb_surface_tangent(g.prim, g.u, g.v));
  if (SC_BLENDER && g.lobes != 0u) { // a Blender material: the closures left to the photon map
    b.mask = g.lobes;
    pb_blender_split(b, frame.glossy_path_alpha2);
  }
  uint rng = pb_walk_seed(pb_pixel_key(frame.pixel_base + gid), kp.sample_index, 2u);
  vec3 x = surf.p;
  // The edges of this face within reach (common/kernel_edges.glsl): the
  // kernel is renormalised for the share of its disc beyond them, and the
  // photons beyond them (in the tangent plane) are not this face's: a wall
  // stands there. Without this a search that finds few photons on this
  // side (the floor inside a closed block) grows to r_max and reaches
  // through the walls to the floor outside.
  vec3 edge_dir[PB_EDGES_MAX];
  float edge_dist[PB_EDGES_MAX];
  uint edges = pb_edges_find(x, surf.ng, kp.edge_reach, edge_dir, edge_dist);
  // ---- the k nearest hits within r_max ----
  float bound0 = kp.r_max * kp.r_max;
  uint n = 0u;
  uint st_code[PB_LBVH_STACK];
  float st_d2[PB_LBVH_STACK];
  uint sp = 0u;
  st_code[sp] = info.root, st_d2[sp] = 0.0, sp++;
  uint iters = 0u;
  bool cut = false;
  // One loop (SC_BUDGET): each iteration is one step of one of three
  // states, a heap sift in progress (one level), a leaf's next photon
  // (li < lend), or the next node off the stack.
  uint li = 0u, lend = 0u;
  uint hc = PB_LBVH_NONE; // the sift's slot, PB_LBVH_NONE: none in progress
  bool up = false;        // sift up (an insertion) or down (the top replaced)
  float hd = 0.0;         // the entry being placed
  uint hi = 0u;
  for (;;) {
    if (hc != PB_LBVH_NONE) { // one level of the sift (at most log2(k) steps)
      bool place;
      uint next = hc;
      if (up) {
        uint p = (hc - 1u) >> 1;
        place = hc == 0u || kh_d[p] >= hd;
        if (!place) next = p;
      } else {
        uint l = 2u * hc + 1u;
        uint m = l + 1u < SC_K && kh_d[l + 1u] > kh_d[l] ? l + 1u : l;
        place = l >= SC_K || kh_d[m] <= hd;
        if (!place) next = m;
      }
      if (place) {
        kh_d[hc] = hd, kh_i[hc] = hi;
        hc = PB_LBVH_NONE;
      } else {
        kh_d[hc] = kh_d[next], kh_i[hc] = kh_i[next];
        hc = next;
      }
      continue;
    }
    // The budget is tested between sifts only (the heap stays a heap).
    if (SC_BUDGET != 0u && ++iters > SC_BUDGET) {
      cut = true;
      break;
    }
    if (li < lend) { // the leaf's next photon
      uint i = li++;
      // position; wi and normal (the packed record's words 0 and 2)
      uvec4 w0 = photons4[PB_PHOTON_PACKED_WORDS4 * i], w2 = photons4[PB_PHOTON_PACKED_WORDS4 * i + 2u];
      vec3 d = uintBitsToFloat(w0.xyz) - x, pn = pb_photon_unpack_normal(w2);
      // Same side only, and only photons that count (as gather.comp's
      // weight: wi . n_g,i >= 1e-4, from above their own face): a photon
      // on the far face of a box (its stored normal the triangle's,
      // arriving from behind it) would fill the heap and count nothing.
      // The same side is a cosine above PB_KNN_SAME_SIDE_COS, not above 0:
      // photons on the outer face of a perpendicular wall at this face's
      // edge (the camera inside a closed block, tests/hard/hard_cases.py)
      // have cos ~ +1e-8 and lie exactly on the edge's plane, so neither
      // test below excluded them (mean 0.00183 inside, limit 1.6e-4).
      if (!(dot(pn, surf.ng) > PB_KNN_SAME_SIDE_COS) || !(dot(pb_photon_unpack_wi(w2), pn) >= 1e-4)) continue;
      float dn = dot(d, surf.ng);
      float d2 = dot(d, d) + PB_KNN_FLATTEN * dn * dn;
      if (edges > 0u) {
        vec3 dp = d - surf.ng * dot(d, surf.ng);
        bool beyond = false;
        for (uint j = 0u; j < PB_EDGES_MAX; ++j) // a constant count: unrolled, no back edge
          beyond = beyond || (j < edges && dot(dp, edge_dir[j]) > edge_dist[j]);
        if (beyond) continue;
      }
      if (n < SC_K) {
        if (d2 < bound0) hc = n++, up = true, hd = d2, hi = i;
      } else if (d2 < kh_d[0]) {
        hc = 0u, up = false, hd = d2, hi = i;
      }
      continue;
    }
    if (sp == 0u) break;
    --sp;
    uint code = st_code[sp];
    float bound = n == SC_K ? kh_d[0] : bound0;
    if (!(st_d2[sp] < bound)) continue;
    if ((code & PB_LBVH_LEAF) != 0u) {
      pb_lbvh_entry c = pb_lbvh_child((code & ~PB_LBVH_LEAF) >> 1, code & 1u);
      li = c.lo_ref.w & ~PB_LBVH_LEAF;
      lend = li + c.hi_count.w;
      continue;
    }
    pb_lbvh_entry c0 = pb_lbvh_child(code, 0u), c1 = pb_lbvh_child(code, 1u);
    float d0 = pb_knn_box_d2(x, c0), d1 = pb_knn_box_d2(x, c1);
    uint k0 = (c0.lo_ref.w & PB_LBVH_LEAF) != 0u ? (PB_LBVH_LEAF | (code << 1)) : c0.lo_ref.w;
    uint k1 = (c1.lo_ref.w & PB_LBVH_LEAF) != 0u ? (PB_LBVH_LEAF | (code << 1) | 1u) : c1.lo_ref.w;
    // Push the farther first, so that the nearer is opened next.
    bool swap = d1 < d0;
    uint ka = swap ? k0 : k1, kb = swap ? k1 : k0;
    float da = swap ? d0 : d1, db = swap ? d1 : d0;
    if (da < bound) {
      if (sp < PB_LBVH_STACK) st_code[sp] = ka, st_d2[sp] = da, sp++;
      else atomicAdd(info.stack_overflow, 1u);
    }
    if (db < bound) {
      if (sp < PB_LBVH_STACK) st_code[sp] = kb, st_d2[sp] = db, sp++;
      else atomicAdd(info.stack_overflow, 1u);
    }
  }
  if (cut) atomicAdd(info.stack_overflow, 1u);
  // ---- eq. 1 with the k-th distance as the bandwidth ----
  float r2 = n == SC_K ? kh_d[0] : bound0;
  if (!(r2 > 0.0)) n = 0u; // k photons at x itself: no bandwidth, no estimate
  float norm = n > 0u ? 1.0 / (PB_PI * r2 * pb_edges_share(edges, edge_dist, sqrt(r2))) : 0.0;
  bool nmap = SC_NORMAL_MAPS && frame.tangent_base != 0u;
  vec3 ind = vec3(0.0), cau = vec3(0.0);
  vec4 dir = vec4(0.0);
  for (uint j = 0u; j < n; ++j) {
    pb_gpu_photon p = pb_lbvh_photon(kh_i[j]);
    float k = 2.0 * max(1.0 - kh_d[j] / r2, 0.0) * norm;
    vec3 f = pb_bsdf_eval(b, g.wo, p.wi, rng);
    if (SC_HAS_NORMALS && !nmap) { // the adjoint shading-normal weight (gather.comp)
      float cg = dot(p.wi, p.normal);
      f *= cg >= 1e-4 ? abs(dot(p.wi, surf.ns)) / cg : 0.0;
    }
    vec3 contrib = k * f * p.power;
    if (any(isnan(contrib)) || any(isinf(contrib))) continue;
    if ((p.flags & PB_PHOTON_CAUSTIC) != 0u) {
      cau += contrib;
    } else {
      ind += contrib;
      if (nmap) {
        float wgt = k * pb_lum(p.power);
        if (wgt > 0.0) dir += vec4(p.wi * wgt, wgt);
      }
    }
  }
  ind *= g.throughput;
  cau *= g.throughput;
  pb_gpu_photon_accum pa = paccum[gid];
  pa.indirect += vec4(ind, float(n)); // k_PD: the photons in the estimate (k where r_max allows)
  pa.caustic.xyz += cau;
  paccum[gid] = pa;
  if (nmap) {
    pb_surface ms = surf;
    pb_apply_normal_map(ms, g.prim, g.u, g.v);
    pb_gpu_photon_nmap pn = pnmap[gid];
    if (materials[surf.mat].normal_tex != PB_GPU_NO_TEXTURE) pn.ns.w += 1.0;
    if (!any(isnan(dir)) && !any(isinf(dir))) pn.dir += dir;
    pn.geo.xyz += surf.ng;
    pn.ns.xyz += ms.ns;
    pnmap[gid] = pn;
  }
  if ((kp.flags & PB_GATHER_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += ind + cau;
    accum[gid] = acc;
  }
}
