// View-sample cluster hierarchy (seed 004 4.4, 4.6, 4.7), the radiance
// estimate: one invocation per view sample walks the nodes that contain it
// (its cluster, its tile, the tile's ancestors) and
//   - loops over each node's photon list: a photon whose sphere holds the
//     sample (|x - x_p| <= r) and whose direction is above the sample's
//     tangent plane adds f(wo, wi_p) Phi_p / (pi r^2), f the smooth BSDF at
//     the sample (as the gather's, with its adjoint shading-normal weight
//     |wi . n_s| / (wi . n_p)); 4.4: I = sum f Phi, L = I / (pi r^2), no
//     smoothing kernel. Photons of varying radii (the default: each
//     photon's own footprint radius) divide by their own pi r^2, which
//     keeps every photon's flux once over the surface;
//   - adds the node's trivially accepted irradiance (4.6) times f: the
//     paper's diffuse f is constant; for our BSDFs (Lambert + a GGX layer) f
//     is evaluated at the irradiance-weighted mean direction of those
//     photons (derived, exact for Lambertian surfaces);
//   - directional (4.7): sums the nodes' octant buckets, each weighted by
//     2 cos(n, d) for the octant's centre d (view space), clamped to [0, 1]
//     (the paper's heuristic; the clamp is derived: unclamped, an octant
//     whose centre lies along n counted its flux twice, and one fully above
//     the plane 1.15 times), and leaves that irradiance with the factor
//     f(wo, n_s) x throughput to vsch_blur, which blurs it and adds it.
// A listed photon counts only on the sample's side (its face's normal
// within 90 degrees of the sample's n_g, as the gather's) and not beyond an
// edge of the sample's face where a wall stands (common/kernel_edges.glsl,
// found again here where vsch_leaf found one within reach): the sphere of
// 4.3 reaches through thin walls. Where the photon's disc of radius r
// reaches past such an edge its flux is divided by the share of the disc
// on this side (the uniform disc's segment mass; gather.comp renormalises
// its kernel the same way), so that the flux is kept once at corners.
// Caustic photons (always listed) go into their own sum. Sums are
// multiplied by the specular chain's throughput and added to the frame's
// pb_gpu_photon_accum (and the beauty, unless PB_VSCH_NO_BEAUTY), as the
// gather's.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"
layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
#define PB_VSCH_DATA_BINDING PB_VSCH_SHADE_BIND_DATA
#include "common/vsch.glsl"
#include "common/kernel_edges.glsl"
layout(std430, set = 0, binding = PB_VSCH_SHADE_BIND_PHOTONS) readonly buffer Photons { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = PB_VSCH_SHADE_BIND_VALS) readonly buffer Vals { uint vals[]; };
layout(std430, set = 0, binding = PB_VSCH_SHADE_BIND_ACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(std430, set = 0, binding = PB_VSCH_SHADE_BIND_NMAP) buffer PhotonNmap { pb_gpu_photon_nmap pnmap[]; };
layout(constant_id = PB_SPEC_NORMAL_MAPS) const bool SC_NORMAL_MAPS = true;

// The list photons' sums in fixed point (64 bits, units of emax / 2^28 per
// unit of f): the photon map's records are written by the tracer's atomics,
// so their order (and each list's, sorted by record index) changes from run
// to run; integer sums do not depend on it, and the image is the same bit
// for bit for a fixed seed.
const float PB_VSCH_SUM_ONE = 268435456.0;
void pb_sum_add(inout uvec2 a, float q) {
  if (!(q > 0.0)) return;
  q = min(q, 1.8e19);
  uint hi = uint(q * (1.0 / 4294967296.0));
  uint lo = uint(q - float(hi) * 4294967296.0);
  uint carry;
  a.x = uaddCarry(a.x, lo, carry);
  a.y += hi + carry;
}
float pb_sum_value(uvec2 a) { return float(a.y) * 4294967296.0 + float(a.x); }

// The mass of the uniform unit disc beyond a chord at distance t from its
// centre (t >= 0): (acos t - t sqrt(1 - t^2)) / pi.
float pb_disc_mass_beyond(float t) {
  if (t >= 1.0) return 0.0;
  t = max(t, 0.0);
  return (acos(t) - t * sqrt(max(1.0 - t * t, 0.0))) / PB_VSCH_PI;
}

void main() {
  uint gid = pb_gid();
  if (gid >= vp.pixels) return;
  uint pw = vp.pixel_off + gid * PB_VSCH_PIXEL_WORDS;
  uint leaf = vd[pw];
  if (leaf == PB_VSCH_NONE) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, pb_surface_tangent(g.prim, g.u, g.v));
  if (SC_BLENDER && g.lobes != 0u) {
    b.mask = g.lobes;
    pb_blender_split(b, frame.glossy_path_alpha2);
  }
  uint rng = pb_walk_seed(pb_pixel_key(frame.pixel_base + gid), vp.sample_index, 2u);
  vec3 x = surf.p;
  // The edges of this face (vsch_leaf found the nearest within reach; the
  // same call finds the same ones).
  vec3 edge_dir[PB_EDGES_MAX];
  float edge_dist[PB_EDGES_MAX];
  uint edges = 0u;
  if (!isinf(uintBitsToFloat(vd[pw + 14u]))) edges = pb_edges_find(x, surf.ng, pb_vsch_edge_reach(), edge_dir, edge_dist);
  bool nmap = SC_NORMAL_MAPS && frame.tangent_base != 0u;
  bool directional = (vp.flags & PB_VSCH_DIRECTIONAL) != 0u;
  float emax = uintBitsToFloat(vd[PB_VSCH_H_EMAX]) / float(PB_VSCH_FIXED_ONE);
  vec3 vr, vu, vf;
  pb_view_frame(vr, vu, vf);
  vec3 ind = vec3(0.0), cau = vec3(0.0), edir = vec3(0.0);
  uvec2 si[3] = uvec2[3](uvec2(0u), uvec2(0u), uvec2(0u)), sc[3] = uvec2[3](uvec2(0u), uvec2(0u), uvec2(0u));
  float qscale = emax > 0.0 ? PB_VSCH_SUM_ONE / (emax * float(PB_VSCH_FIXED_ONE)) : 0.0;
  vec4 dir = vec4(0.0);
  uint hits = 0u;
  uint tile = vd[pw + 1u] / PB_VSCH_SLICES;
  uint tx = tile % vd[PB_VSCH_H_NX + 1u], ty = tile / vd[PB_VSCH_H_NX + 1u];
  for (uint L = 0u; L <= PB_VSCH_LEVELS; ++L) {
    uint node;
    if (L == 0u) {
      node = leaf;
    } else {
      if (L >= 2u) tx /= PB_VSCH_BRANCH_X, ty /= PB_VSCH_BRANCH_Y;
      node = pb_level_node(L, tx, ty);
    }
    uint first = vd[pb_node_word(node, 12u)], end = vd[pb_node_word(node, 13u)];
    for (uint j = first; j < end; ++j) {
      pb_gpu_photon p = photons[vals[vp.sorted + j]];
      float r = pb_photon_radius(p);
      vec3 d = x - p.position;
      if (dot(d, d) > r * r || dot(p.wi, surf.ng) <= 0.0 || !(dot(p.normal, surf.ng) > 0.0)) continue;
      // Not a face behind this one (derived; the paper's scenes have no
      // thin walls): with a the photon's height over the sample's tangent
      // plane and b the sample's over the photon's, two points of one
      // surface have a and b of one sign (convex: both below, concave: both
      // above, flat: 0; to second order both are -k s^2 / 2 with k the
      // normal curvature along the path between them), while a face behind
      // this one facing the same way gives a < 0 < b (the inside of
      // cornell_box's closed block, 0.1-0.5 m in front of the back wall,
      // lit by the back wall's photons once r_max reached 30 Delta R) and
      // one in front of it (a shelf over a floor) a > 0 > b. The sphere of
      // 4.3 reaches both; a tolerance of r / 1000 keeps coplanar photons.
      float ha = dot(-d, surf.ng), hb = dot(d, p.normal), ht = 1e-3 * r;
      if ((ha < -ht && hb > ht) || (ha > ht && hb < -ht)) continue;
      float share = 1.0;
      if (edges > 0u) {
        vec3 dp = -d - surf.ng * dot(-d, surf.ng); // the photon's in-plane offset from x
        bool beyond = false;
        for (uint k = 0u; k < edges; ++k) {
          float e = edge_dist[k] - dot(dp, edge_dir[k]); // the photon's distance to the edge
          beyond = beyond || e < 0.0;
          share *= 1.0 - pb_disc_mass_beyond(e / r);
        }
        if (beyond) continue;
        share = max(share, PB_EDGES_MIN_SHARE);
      }
      vec3 f = pb_bsdf_eval(b, g.wo, p.wi, rng);
      if (SC_HAS_NORMALS && !nmap) {
        float cg = dot(p.wi, p.normal);
        f *= cg >= 1e-4 ? abs(dot(p.wi, surf.ns)) / cg : 0.0;
      }
      float inv_area = 1.0 / (PB_VSCH_PI * r * r * share);
      vec3 contrib = f * p.power * inv_area;
      if (any(isnan(contrib)) || any(isinf(contrib))) continue;
      if ((p.flags & PB_PHOTON_CAUSTIC) != 0u) {
        for (int k = 0; k < 3; ++k) pb_sum_add(sc[k], contrib[k] * qscale);
      } else {
        for (int k = 0; k < 3; ++k) pb_sum_add(si[k], contrib[k] * qscale);
        if (nmap) {
          float wgt = inv_area * pb_lum(p.power);
          if (wgt > 0.0) dir += vec4(p.wi * wgt, wgt);
        }
      }
      hits++;
    }
    if (directional) {
      uint db = vp.dir_off + node * PB_VSCH_DIR_WORDS;
      for (uint o = 0u; o < 8u; ++o) {
        vec3 e = vec3(pb_read64(db + 6u * o), pb_read64(db + 6u * o + 2u), pb_read64(db + 6u * o + 4u)) * emax;
        if (e == vec3(0.0)) continue;
        vec3 dv = pb_octant_dir(o);
        vec3 dw = vr * dv.x + vu * dv.y + vf * dv.z;
        edir += e * clamp(2.0 * dot(surf.ng, dw), 0.0, 1.0);
      }
    } else {
      uint tb = vp.triv_off + node * PB_VSCH_TRIVIAL_WORDS;
      float lsum = pb_read64(tb + 12u);
      if (lsum > 0.0) {
        vec3 e = vec3(pb_read64(tb), pb_read64(tb + 2u), pb_read64(tb + 4u)) * emax;
        vec3 wm = 2.0 * vec3(pb_read64(tb + 6u), pb_read64(tb + 8u), pb_read64(tb + 10u)) / lsum - 1.0;
        float lw = length(wm);
        wm = lw > 1e-6 ? wm / lw : surf.ng;
        if (dot(wm, surf.ng) <= 1e-4) wm = surf.ng;
        vec3 f = pb_bsdf_eval(b, g.wo, wm, rng);
        if (SC_HAS_NORMALS && !nmap) f *= abs(dot(wm, surf.ns)) / dot(wm, surf.ng);
        vec3 contrib = f * e;
        if (!any(isnan(contrib)) && !any(isinf(contrib))) {
          ind += contrib;
          if (nmap) {
            float wgt = pb_lum(e);
            if (wgt > 0.0) dir += vec4(wm * wgt, wgt);
          }
        }
      }
    }
  }
  if (directional) {
    vec3 fac = pb_bsdf_eval(b, g.wo, surf.ns, rng) * g.throughput;
    if (any(isnan(edir)) || any(isinf(edir))) edir = vec3(0.0);
    if (any(isnan(fac)) || any(isinf(fac))) fac = vec3(0.0);
    vd[pw + 8u] = floatBitsToUint(edir.x), vd[pw + 9u] = floatBitsToUint(edir.y), vd[pw + 10u] = floatBitsToUint(edir.z);
    vd[pw + 11u] = floatBitsToUint(fac.x), vd[pw + 12u] = floatBitsToUint(fac.y), vd[pw + 13u] = floatBitsToUint(fac.z);
  }
  if (qscale > 0.0)
    for (int k = 0; k < 3; ++k) {
      ind[k] += pb_sum_value(si[k]) / qscale;
      cau[k] += pb_sum_value(sc[k]) / qscale;
    }
  ind *= g.throughput;
  cau *= g.throughput;
  pb_gpu_photon_accum pa = paccum[gid];
  pa.indirect += vec4(ind, float(hits));
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
  if ((vp.flags & PB_VSCH_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += ind + cau;
    accum[gid] = acc;
  }
}
