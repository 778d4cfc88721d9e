#version 450
// Reflective shadow maps for the photon tracer's first bounce (seed 001
// 24.2.1). Two modes of one pass (push.mode):
//
// PB_RSM_MODE_RENDER, one invocation per texel of every light's map: the ray
// from the light through the texel centre, its first hit (prim, u, v, t),
// and the flux the texel receives:
//   point: cube map, face f looks along +-axis f/2; a texel is the rectangle
//     [x0, x1] x [y0, y1] of the face plane at distance 1, of solid angle
//     Omega = F(x1,y1) - F(x0,y1) - F(x1,y0) + F(x0,y0),
//     F(x, y) = atan(x y / sqrt(1 + x^2 + y^2)) (exact; the six faces sum
//     to 4 pi), flux = I Omega;
//   spot: one perspective face over the outer cone (plane half-size
//     tan(outer), outer clamped to 1.5 rad), flux = I Omega smoothstep at the
//     texel centre's cos theta (0 outside the cone);
//   directional: orthographic map over the square around the scene's
//     bounding disc (radius R), texel area A = (2R / res)^2, flux = E A
//     (texels beyond the scene miss, as the traced disc's rays do).
// The first hit is direct light and is not stored (seed 001 24.2.2): the
// tracer starts the path at the texel's hit and continues by BRDF sampling.
// The sampling weight is the luminance of the reflected power, flux x
// albedo (base colour; at least 5 % of the flux so that every lit texel can
// be chosen and the estimator stays unbiased for non-diffuse lobes), with
// the flux taken at the largest density over the texel's centre and corners
// (photons are jittered over the whole texel, common/rsm_texel.glsl); 5 % of
// that flux for a texel whose centre misses or sees a back face while a
// corner sees a front face; 0 for the rest.
// Not unbiased for geometry thinner than a texel seen against nothing: a
// texel is weighted from its five points (centre, corners), so one whose
// five rays all miss (or see back faces) is never sampled, while a wire, a
// thin slat or the rim of an object may cross it between the points; the
// light of that part is lost. Everything else is unbiased: a texel with any
// weight is sampled over its whole area, and a thin object in front of
// other geometry sits in texels whose rays hit that geometry. For a feature
// of width w against empty space, in texels of width W (at the feature's
// distance: 2 d / res for a point light's face centre, 2 R / res for a
// directional light; res 64), the share of its direct light lost is about
// 1 - min(1, 2 w / W) for a long one (the points are W / 2 apart across
// it). Measured (bench/scenes/thin_slats.py: 24 slats 1.5 m from a point
// light, W = 4.7 cm; 48 px, 4 maps of 2^17): with 1 cm slats the floor's
// indirect light is 0.00019 against 0.00044 traced (-57 %, predicted -57 %);
// with 20 cm slats 0.01129 both. The traced first bounce (the default) has
// no such loss.
//
// PB_RSM_MODE_PYRAMID, dispatched once per level l = 1 .. log2(res), one
// invocation per node: the sum of its 2 x 2 children at level l - 1 (the
// texels' weights at level 0), stored as common/rsm_texel.glsl's
// pb_rsm_node describes. PB_RSM_MODE_TOTAL, one workgroup per light: the
// sum of its faces' tops (rlights.total) and the map's coverage
// (rlights.coverage, see pb_rsm_total). The tracer warps stratified points
// down the pyramid (hierarchical warp, seed 001 24.2.1).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_rsm.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
layout(std430, set = 0, binding = PB_RSM_BIND_LIGHTS) buffer RsmLights { pb_gpu_rsm_light rlights[]; };
layout(std430, set = 0, binding = PB_RSM_BIND_TEXELS) buffer RsmTexels { pb_gpu_rsm_texel rtexels[]; };
layout(push_constant) uniform Push { pb_gpu_rsm_push push; };

#include "common/scene.glsl"
#include "common/rsm_texel.glsl"

float pb_rsm_lum(vec3 c) { return dot(max(c, vec3(0.0)), vec3(0.2126, 0.7152, 0.0722)); }

float pb_rsm_F(float x, float y) { return atan(x * y / sqrt(1.0 + x * x + y * y)); }

// Solid angle of [x0, x1] x [y0, y1] on the plane at distance 1.
float pb_rsm_omega(float x0, float x1, float y0, float y1) {
  return (pb_rsm_F(x1, y1) - pb_rsm_F(x0, y1)) - (pb_rsm_F(x1, y0) - pb_rsm_F(x0, y0));
}

void pb_rsm_render(uint gid) {
  uint li = 0u;
  for (uint i = 1u; i < push.light_count; ++i)
    if (gid >= rlights[i].first) li = i;
  pb_gpu_rsm_light rl = rlights[li];
  if (gid < rl.first || gid - rl.first >= rl.count) return;
  uint local = gid - rl.first, res = rl.res;
  float inv = 1.0 / float(res);
  uint pix = local % (res * res);
  uint ix = pix % res, iy = pix / res;
  // Texel edges in [-1, 1]: the exact solid angle (point, spot).
  float x0 = 2.0 * float(ix) * inv - 1.0, x1 = 2.0 * float(ix + 1u) * inv - 1.0;
  float y0 = 2.0 * float(iy) * inv - 1.0, y1 = 2.0 * float(iy + 1u) * inv - 1.0;
  pb_gpu_light L = lights[rl.light];
  vec3 o, d, dens, flux;
  float area, measure;
  pb_rsm_texel_point(rl, local, vec2(0.5), push.scene_center, push.scene_radius, o, d, dens, measure);
  if (L.type == PB_GPU_LIGHT_DIRECTIONAL) {
    area = measure;
    flux = dens * area;
  } else {
    float s = L.type == PB_GPU_LIGHT_SPOT ? rl.tan_half : 1.0;
    area = pb_rsm_omega(s * x0, s * x1, s * y0, s * y1);
    // I f(centre) Omega: the centre's falloff (dens / the centre's
    // dOmega/dA), times the exact solid angle.
    float X = s * 0.5 * (x0 + x1), Y = s * 0.5 * (y0 + y1), q = 1.0 + X * X + Y * Y;
    flux = dens * (q * sqrt(q)) * area;
  }
  pb_gpu_rsm_texel tx;
  tx.origin = o;
  tx.dir = d;
  tx.flux = flux;
  tx.area = area;
  tx.pyramid = 0.0;
  float th, u, v;
  tx.prim = pb_trace(o, d, 0.0, PB_INF, false, th, u, v);
  tx.t = th;
  tx.u = u;
  tx.v = v;
  tx.weight = 0.0;
  // The largest flux density over the centre and the corners: a texel
  // straddling a spot's cone edge keeps a weight though its centre is
  // outside (photons are jittered over the whole texel).
  float dmax = pb_rsm_lum(dens);
  bool corner_front = false, corner_specular = false;
  for (uint c = 0u; c < 4u; ++c) {
    vec3 oc, dc, dn;
    float mc, tc, uc, vc;
    pb_rsm_texel_point(rl, local, vec2(float(c & 1u), float(c >> 1u)), push.scene_center, push.scene_radius, oc, dc,
                       dn, mc);
    dmax = max(dmax, pb_rsm_lum(dn));
    uint pc = pb_trace(oc, dc, 0.0, PB_INF, false, tc, uc, vc);
    if (pc != PB_GPU_MISS) {
      pb_surface sc = pb_surface_from_hit(pc, uc, vc, dc);
      bool front = dot(-dc, sc.ng) > 0.0;
      corner_front = corner_front || front;
      if (front && push.caustic_share > 0.0) corner_specular = corner_specular || !pb_bsdf_has_smooth(pb_bsdf_setup(sc, -dc));
    }
  }
  float lf = dmax * measure;
  bool centre_front = false;
  if (tx.prim != PB_GPU_MISS) {
    pb_surface surf = pb_surface_from_hit(tx.prim, u, v, d);
    pb_bsdf bs = pb_bsdf_setup(surf, -d);
    centre_front = dot(-d, bs.n) > 0.0;
    if (centre_front) tx.weight = lf * max(pb_rsm_lum(bs.base), 0.05);
    corner_specular = corner_specular || (centre_front && !pb_bsdf_has_smooth(bs));
  } else {
    tx.t = 0.0;
    tx.u = tx.v = 0.0;
  }
  // A texel whose centre misses (or sees a back face) while a corner sees a
  // lit front face: the smallest weight, so that the part of it that sees
  // the scene still gets photons (silhouettes at least a texel wide; thinner
  // features seen against nothing can fall between the points, see above).
  if (!centre_front && corner_front) tx.weight = 0.05 * lf;
  if (!(tx.weight > 0.0) || isinf(tx.weight)) tx.weight = 0.0;
  // PB_RSM_MODE_BOOST's mark (the pyramid field is free until
  // PB_RSM_MODE_PYRAMID, which runs after it): a texel one of whose five
  // points sees a front face with only delta lobes (a mirror, glass), where
  // the photons start caustic paths.
  if (push.caustic_share > 0.0 && corner_specular && tx.weight > 0.0) tx.pyramid = 1.0;
  rtexels[gid] = tx;
}

void pb_rsm_pyramid(uint gid) {
  uint li = 0u;
  for (uint i = 1u; i < push.light_count; ++i)
    if (gid >= rlights[i].first) li = i;
  pb_gpu_rsm_light rl = rlights[li];
  if (gid < rl.first || push.level > rl.levels) return;
  uint side = rl.res >> push.level, local = gid - rl.first;
  if (local >= rl.faces * side * side) return;
  uint face = local / (side * side), p = local % (side * side);
  uint x = p % side, y = p / side, l = push.level - 1u;
  float w = pb_rsm_weight(rl, l, face, 2u * x, 2u * y) + pb_rsm_weight(rl, l, face, 2u * x + 1u, 2u * y) +
            pb_rsm_weight(rl, l, face, 2u * x, 2u * y + 1u) + pb_rsm_weight(rl, l, face, 2u * x + 1u, 2u * y + 1u);
  rtexels[rl.first + pb_rsm_node(rl, push.level, face, x, y)].pyramid = w;
}

// Coverage c of a light's map: the share of the light's flux (luminance)
// that falls on texels with a weight, i.e. on the scene's front faces; the
// rest leaves the scene. A traced first bounce spends the same share 1 - c
// of the light's photons on rays that miss (each of them costs a trace and
// carries the flux the estimate then lacks elsewhere), while the map spends
// every photon on the scene: at equal paths the map puts 1 / c times the
// traced photons on every lit surface (the flux is the same, each photon
// carries c times less of it). On ring, point light 3 m from a 4 x 4 m
// floor and a 1 m ring, c is about 0.05 (the floor covers 4.9 % of the
// light's sphere, the ring 0.2 %), which is the 20-some times more caustic
// records the RSM stores there at equal paths (bench/README.md, "ring and
// 35 dB"), not a difference in the flagging or weighting of caustic
// photons. Directional maps are the square of side 2 R around the scene's
// bounding disc, the traced emission that disc: hits lie inside the disc, so
// c is the square's share times 4 / pi.
shared float s_cov_all[PB_GPU_WORKGROUP], s_cov_hit[PB_GPU_WORKGROUP];
void pb_rsm_total(uint li, uint l) {
  pb_gpu_rsm_light rl = rlights[li];
  float all = 0.0, hit = 0.0;
  for (uint i = l; i < rl.count; i += PB_GPU_WORKGROUP) {
    pb_gpu_rsm_texel tx = rtexels[rl.first + i];
    float f = pb_rsm_lum(tx.flux);
    all += f;
    if (tx.weight > 0.0) hit += f;
  }
  s_cov_all[l] = all;
  s_cov_hit[l] = hit;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) {
      s_cov_all[l] += s_cov_all[l + w];
      s_cov_hit[l] += s_cov_hit[l + w];
    }
    barrier();
  }
  if (l != 0u) return;
  float t = 0.0;
  for (uint f = 0u; f < rl.faces; ++f) t += pb_rsm_weight(rl, rl.levels, f, 0u, 0u);
  rlights[li].total = t;
  float c = s_cov_all[0] > 0.0 ? s_cov_hit[0] / s_cov_all[0] : 1.0;
  if (lights[rl.light].type == PB_GPU_LIGHT_DIRECTIONAL) c *= 4.0 / 3.14159265358979;
  rlights[li].coverage = clamp(c, 0.0, 1.0);
}

// The caustic share (render --caustic-share F; Jensen's separate caustic
// map, 1996, "Global illumination using photon maps" 3.1, which spends its
// own photon budget on the specular objects through projection maps). A
// map sampled by reflected power alone spends the photons of a small mirror
// in the proportion of its power: on ring (a 1 m mirror ring 3 m from a
// point light, on a 4 x 4 m floor) 9 % of them, so 91 % of the paths start
// on the floor, where they are direct light (not stored) and their diffuse
// bounce upward leaves the scene or meets the ring's vertical mirror walls,
// which keep it going up: they store nothing, while the caustic, every
// record ring stores, gets the rest. Any positive texel weights keep the map
// unbiased: a photon of texel i carries its flux density times the texel's
// measure over n p_i, p_i = w_i / sum w (pb_rsm_emit in photon_trace.comp),
// whatever w_i is. So the specular texels S (marked by the render mode)
// are multiplied by
//   beta = F W_D / ((1 - F) W_S),   W_S = sum over S of w, W_D over the rest,
// which gives them the share beta W_S / (beta W_S + W_D) = F of the
// photons, and by 1 where that would lower them (beta < 1: a map whose
// mirrors already reflect more than F of its power keeps its weights).
// rlights[li].boost keeps beta. Then the pyramid and the totals are built
// from the new weights (the coverage counts flux, not weights: unchanged).
shared float s_ws[PB_GPU_WORKGROUP], s_wa[PB_GPU_WORKGROUP];
void pb_rsm_boost(uint li, uint l) {
  pb_gpu_rsm_light rl = rlights[li];
  float ws = 0.0, wa = 0.0;
  for (uint i = l; i < rl.count; i += PB_GPU_WORKGROUP) {
    pb_gpu_rsm_texel tx = rtexels[rl.first + i];
    wa += tx.weight;
    if (tx.pyramid > 0.0) ws += tx.weight;
  }
  s_ws[l] = ws;
  s_wa[l] = wa;
  barrier();
  for (uint w = PB_GPU_WORKGROUP / 2u; w > 0u; w >>= 1u) {
    if (l < w) {
      s_ws[l] += s_ws[l + w];
      s_wa[l] += s_wa[l + w];
    }
    barrier();
  }
  float F = clamp(push.caustic_share, 0.0, 0.999);
  float WS = s_ws[0], WD = s_wa[0] - s_ws[0];
  float beta = WS > 0.0 ? F * WD / ((1.0 - F) * WS) : 1.0;
  if (!(beta > 1.0) || isinf(beta)) beta = 1.0;
  for (uint i = l; i < rl.count; i += PB_GPU_WORKGROUP) {
    uint k = rl.first + i;
    if (rtexels[k].pyramid > 0.0) {
      rtexels[k].weight *= beta;
      rtexels[k].pyramid = 0.0;
    }
  }
  if (l == 0u) rlights[li].boost = beta;
}

void main() {
  uint gid = pb_gid();
  if (push.mode == PB_RSM_MODE_BOOST) {
    uint li = gid / PB_GPU_WORKGROUP;
    if (li < push.light_count) pb_rsm_boost(li, gid % PB_GPU_WORKGROUP);
    return;
  }
  if (push.mode == PB_RSM_MODE_TOTAL) {
    // One workgroup per light (uniform in the workgroup: the barriers).
    uint li = gid / PB_GPU_WORKGROUP;
    if (li < push.light_count) pb_rsm_total(li, gid % PB_GPU_WORKGROUP);
    return;
  }
  if (gid >= push.texels) return;
  if (push.mode == PB_RSM_MODE_PYRAMID) pb_rsm_pyramid(gid);
  else pb_rsm_render(gid);
}
