#version 450
// Photon gather (seed 000 eq. 1, section 6.3): at the G-buffer's surface
// (the first smooth vertex after the eye's specular chain) the photon LBVH is
// traversed (common/lbvh_traverse.glsl), opening every child whose box
// holds the point; each photon of a reached leaf whose footprint ellipsoid
// holds the point adds
//   K(q) / A_i * f(x, wi_i, wo) * Phi_i,
// q = a^2 + b^2 from x - x_i = a u_i + b v_i + c n_i e_i (the ellipsoid test
// is a^2 + b^2 + c^2 <= 1), A_i = pi |u_i x v_i| the ellipse's area, K the
// Epanechnikov kernel 2 (1 - q) (unit integral over the unit disc divided
// by pi, so K / A_i integrates to 1 over the ellipse) or the constant 1.
// f is the reference's smooth BSDF (Lambert + GGX layer, pb_bsdf_eval) with
// the material and textures at x; for a Blender material the closures the
// G-buffer pass left to the photon map (gbuffer.lobes), times the adjoint
// shading-normal weight |wi_i . n_s| / |wi_i . n_g,i| (Veach 1997 5.3; the
// reference's pb_photon_gather, src/ref/photons.c): the photon density on a
// face carries the geometric cosine |wi . n_g,i| of the face the photon hit
// (its stored normal), while the BSDF's cosine is the shading one at x, so
// each photon's cosine is swapped; photons with wi . n_g,i < 1e-4 (grazing or from below the
// face, where the ratio diverges) count nothing, as in the reference. On
// flat-shaded faces n_s = n_g and the weight is 1. Scenes with normal maps
// leave it to eq. 20 (shading_correction.c, from n_g to the mapped normal,
// which includes the interpolation), so it is not applied twice. Caustic photons go into their own sum;
// both are multiplied by the specular chain's throughput and added to the
// beauty (unless PB_GATHER_NO_BEAUTY).
//
// Built a second time with -DPB_UPSAMPLE=1 (gather_upsample): the multi-level
// up-sampling of seed 003 sec. 6 (Figure 9; src/render/estimate/upsample.c). With
// PB_GATHER_UPS_LIST it runs only at the pixels of the level's list and
// stores, per unit albedo, the diffuse irradiance of the non-caustic photons
// (for the glTF model f_d = base kd(wo) / pi at wi . n_g > 0, wi . n > 0,
// exactly the Lambert term of pb_bsdf_eval, so f_d / (base kd / pi) is the
// indicator of those two tests and the sum is sum_i K_i / A_i Phi_i times the
// adjoint weight): "it is not the final radiance, but the incoming
// irradiance on the diffuse surfaces, that is up-sampled";
// upsample_compose.comp multiplies it by base kd / pi and the throughput of
// every pixel. With PB_GATHER_UPS_REST it runs at full resolution for what is
// not up-sampled: f - f_d of the non-caustic photons where the surface has a
// glossy lobe ("for glossy surfaces, up-sampling is only performed for its
// diffuse component, while the glossy component is computed at full
// resolution"), the whole f of the caustic photons where the map has any
// (PB_GATHER_UPS_CAUSTICS), and everything at a Blender material's pixels
// (their closures are not split here); a pixel with none of these does not
// traverse the photon LBVH at all.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"
#include "common/photon_map.glsl"

layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
// The sorted photons (pb_gpu_photon) and the nodes (pb_gpu_lbvh_node) as
// uvec4, read through common/lbvh_traverse.glsl.
layout(std430, set = 0, binding = PB_GATHER_BIND_PHOTONS) readonly buffer Photons { uvec4 photons4[]; };
layout(std430, set = 0, binding = PB_GATHER_BIND_NODES) readonly buffer Nodes2 { uvec4 lnodes4[]; };
layout(std430, set = 0, binding = PB_GATHER_BIND_INFO) buffer InfoBuf { pb_gpu_lbvh_info info; };
layout(std430, set = 0, binding = PB_GATHER_BIND_ACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(std430, set = 0, binding = PB_GATHER_BIND_NMAP) buffer PhotonNmap { pb_gpu_photon_nmap pnmap[]; }; // normal maps only
layout(push_constant) uniform GatherPush { pb_gpu_gather_push gp; };
// Scenes with normal maps (eq. 20's sums below); compiled out for the rest.
layout(constant_id = PB_SPEC_NORMAL_MAPS) const bool SC_NORMAL_MAPS = true;
#ifdef PB_UPSAMPLE
#include "shared/pb_upsample.h"
layout(std430, set = 0, binding = PB_GATHER_BIND_UPS_IRR) buffer UpsIrr { vec4 ups_irr[]; };
layout(std430, set = 0, binding = PB_GATHER_BIND_UPS_LIST) buffer UpsList { uint ups_list[]; };

// The glTF model's Lambert term, as pb_bsdf_eval computes it (the same
// expressions, so f - f_d of a surface without a glossy lobe is exactly 0).
vec3 pb_ups_diffuse(pb_bsdf b, vec3 wo, vec3 wi) {
  if (dot(wi, b.ng) <= 0.0) return vec3(0.0);
  vec3 lo = pb_to_local(b, wo), li = pb_to_local(b, wi);
  if (lo.z <= 0.0 || li.z <= 0.0) return vec3(0.0);
  vec4 l = pb_lobes(b, lo.z);
  return l.w > 0.0 ? b.base * (l.w * PB_INV_PI) : vec3(0.0);
}
// A non-delta specular lobe with any weight (pb_spec_fresnel's two terms).
bool pb_ups_glossy(pb_bsdf b) {
  float kdiel = (1.0 - b.metallic) * (1.0 - b.transmission) * b.spec;
  return !b.delta_spec && (kdiel > 0.0 || (b.metallic > 0.0 && any(greaterThan(b.base, vec3(0.0)))));
}
#endif
#include "common/lbvh_traverse.glsl"

// Kernel renormalisation at the edges of a face (corners, creases; a
// boundary correction of kernel density estimation). A footprint that
// reaches past the line where this face meets a wall puts part of its
// kernel where there is no face, and the wall's photons never count here
// (the same-side test), so within one footprint radius of the edge the
// estimate falls, to half of the true density at the edge itself for a
// uniform one. Each photon's weight is divided by the share m_i of its
// kernel, centred at x, that lies on this side of every edge found: for an
// edge at distance d along the in-plane unit direction e, the kernel's
// support along e is h_i = sqrt((e . u_i)^2 + (e . v_i)^2) (the ellipse
// x + a u_i + b v_i, a^2 + b^2 <= 1, maps the line to one at t = d / h_i
// from the unit disc's centre), and the mass beyond it is
//   Epanechnikov (2 / pi)(1 - r^2): M(t) = 1/2 - (t (5 - 2 t^2) sqrt(1 - t^2)
//                                     + 3 asin t) / (3 pi),
//   constant 1 / pi:                 M(t) = (acos t - t sqrt(1 - t^2)) / pi,
// (integrals of the kernel over the disc's segment x > t; M(0) = 1/2). With
// several edges m_i = prod (1 - M_j): exact for one straight edge, and for
// two perpendicular ones at the corner point itself (1/4); bounded below by
// 1/4. For a uniform density the renormalised estimate is then exact up to a
// straight edge (sum over the photons of K(x - x_i) / m_i(x), the kernel
// symmetric in x and x_i). The edges are found by PB_EDGE_RAYS rays in the
// tangent plane, just above it, to sqrt(2) times the largest footprint
// radius (r_max; any straight edge within r_max is then hit by the nearest
// of four rays 90 degrees apart); each hit face whose normal is more than 60
// degrees from this face's (its photons fail the same-side and ellipsoid
// tests here) gives one edge, its in-plane distance from the hit point and
// the face's plane, so the rays need not meet it at right angles. Not
// corrected: a face that ends without a wall (an open edge: the light is
// then really lost off the face), walls shorter than the ray's height
// (1e-3 r_max), and creases of less than 60 degrees, whose neighbours'
// photons reach across within their ellipsoids.
#define PB_EDGE_RAYS 4
#define PB_GATHER_SAME_SIDE_COS 0.01
#define PB_EDGE_MIN_SHARE 0.25

float pb_kernel_mass_beyond(float t, bool box_kernel) {
  if (t >= 1.0) return 0.0;
  t = max(t, 0.0);
  float s = sqrt(max(1.0 - t * t, 0.0));
  return box_kernel ? (acos(t) - t * s) / PB_PI
                    : 0.5 - (t * (5.0 - 2.0 * t * t) * s + 3.0 * asin(t)) / (3.0 * PB_PI);
}

void main() {
  uint gid = pb_gid();
#ifdef PB_UPSAMPLE
  bool listed = (gp.flags & PB_GATHER_UPS_LIST) != 0u;
  if (listed) {
    if (gid >= ups_list[PB_UPS_H_QUEUED + gp.level]) return;
    gid = ups_list[PB_UPS_HEADER_WORDS + gid];
  }
#else
  const bool listed = false;
#endif
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS) return;
  if (info.root == PB_LBVH_NONE) {
#ifdef PB_UPSAMPLE
    if (listed) {
      ups_irr[gid] = vec4(0.0, 0.0, 0.0, float(PB_UPS_ESTIMATED));
      atomicAdd(ups_list[PB_UPS_H_ESTIMATED + gp.level], 1u);
    }
#endif
    return;
  }
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, pb_surface_tangent(g.prim, g.u, g.v));
  if (SC_BLENDER && g.lobes != 0u) { // a Blender material: the closures left to the photon map
    b.mask = g.lobes;
    pb_blender_split(b, frame.glossy_path_alpha2);
  }
#ifdef PB_UPSAMPLE
  // UPS_REST at a glTF pixel: only the glossy lobe of the non-caustic
  // photons (split), and the caustic ones where the map has any.
  bool blender_px = SC_BLENDER && g.lobes != 0u;
  bool glossy = !blender_px && pb_ups_glossy(b);
  bool caustics = (gp.flags & PB_GATHER_UPS_CAUSTICS) != 0u;
  bool split = !listed && !blender_px;
  if (!listed) {
    if (!blender_px && !glossy && !caustics) return;
    atomicAdd(ups_list[PB_UPS_H_FULL_RES], 1u);
  }
#endif
  uint rng = pb_walk_seed(pb_pixel_key(frame.pixel_base + gid), gp.sample_index, 2u);
  vec3 x = surf.p;
  bool box_kernel = (gp.flags & PB_GATHER_CONSTANT_KERNEL) != 0u;
  vec3 ind = vec3(0.0), cau = vec3(0.0);
  // Seed 001 24.4.3 (eq. 20): in scenes with normal maps, also the
  // power-weighted incoming direction of the non-caustic photons (dir) and
  // both normals of this surface. The BSDF above stays the one without the
  // normal map: the photon density carries the geometric cosine, which
  // shading_correction.c swaps for the shading one after the filter.
  bool nmap = SC_NORMAL_MAPS && frame.tangent_base != 0u;
  vec4 dir = vec4(0.0);
  uint hits = 0u;
  // The edges of this face within reach (above): in-plane unit direction
  // towards each and its distance.
  vec3 edge_dir[PB_EDGE_RAYS];
  float edge_dist[PB_EDGE_RAYS];
  uint edges = 0u;
  float reach = gp.edge_reach;
  if (reach > 0.0) {
    vec3 n = surf.ng, an = abs(n);
    // A frame from the world axis least aligned with n (axis-aligned rooms
    // get rays at right angles to their walls).
    vec3 a = an.x <= an.y && an.x <= an.z ? vec3(1, 0, 0) : (an.y <= an.z ? vec3(0, 1, 0) : vec3(0, 0, 1));
    vec3 t = normalize(cross(n, a)), bt = cross(n, t);
    vec3 o = x + n * (1e-3 * reach);
    for (int k = 0; k < PB_EDGE_RAYS; ++k) {
      float ang = float(k) * (2.0 * PB_PI / float(PB_EDGE_RAYS));
      vec3 e = cos(ang) * t + sin(ang) * bt;
      float th, uh, vh;
      uint prim = pb_trace(o, e, 0.0, 1.4143 * reach, false, th, uh, vh);
      if (prim == PB_GPU_MISS) continue;
      pb_surface ws = pb_surface_from_hit(prim, uh, vh, e); // ws.ng faces x
      float cn = dot(ws.ng, n);
      if (cn > 0.5) continue;
      vec3 ew = -(ws.ng - n * cn);
      float le = length(ew);
      if (!(le > 1e-4)) continue;
      ew /= le;
      float d = th * dot(e, ws.ng) / dot(ew, ws.ng);
      if (!(d >= 0.0) || isinf(d)) continue;
      bool merged = false;
      for (uint j = 0u; j < edges; ++j)
        if (dot(edge_dir[j], ew) > 0.99) {
          edge_dist[j] = min(edge_dist[j], d);
          merged = true;
        }
      if (!merged) {
        edge_dir[edges] = ew;
        edge_dist[edges] = d;
        edges++;
      }
    }
  }
  pb_lbvh_begin();
  uint first, count;
  while (pb_lbvh_next_leaf(x, first, count)) {
    for (uint i = first; i < first + count; ++i) {
      pb_gpu_photon p = pb_lbvh_photon(i);
      vec3 d = x - p.position;
      // Behind a wall: a photon of the same plane beyond an edge found may
      // lie on the far side of a thin wall standing on a floor that goes on
      // beyond it (ring's base). The renormalisation below takes the kernel
      // mass beyond every edge as lost, i.e. only this side's photons
      // counting at x; one from behind the wall counted too is light
      // leaking through it (ring: 0.031 against the reference's 0.0055 in
      // the ring's shadow at its base). The edges are the hit facets'
      // lines, which a round wall's oblique hits misplace, so a photon
      // beyond one is tested by a ray along the plane from x to it (rare:
      // only photons past an edge), and dropped when the ray meets the wall.
      if (edges > 0u) {
        bool beyond = false;
        for (uint j = 0u; j < edges; ++j) beyond = beyond || dot(-d, edge_dir[j]) > edge_dist[j];
        if (beyond) {
          vec3 o = x + surf.ng * (1e-3 * gp.edge_reach);
          vec3 w = -d - surf.ng * dot(-d, surf.ng);
          float lw = length(w);
          float th, uh, vh;
          if (lw > 0.0 && pb_trace(o, w / lw, 0.0, lw, true, th, uh, vh) != PB_GPU_MISS) continue;
        }
      }
      // Same side of the surface only (thin walls, corners), with a margin:
      // the packed record's normal is within 1e-4 of the photon's
      // (common/photon_pack.glsl), and a rotated mesh's perpendicular faces
      // come out at cosines of +-1e-8, so "> 0" let about half of the
      // photons on the outer face of a perpendicular wall through at its
      // edge (the camera inside the closed tall block of
      // tests/hard/hard_cases.py: mean 1.9e-4 with packed normals, limit
      // 1.6e-4; 0 with the margin). Faces within 0.6 degrees of
      // perpendicular are no surface this point's light is estimated on.
      if (dot(p.normal, surf.ng) > PB_GATHER_SAME_SIDE_COS) {
        float uu = dot(p.axis_u, p.axis_u), uv = dot(p.axis_u, p.axis_v), vv = dot(p.axis_v, p.axis_v);
        float det = uu * vv - uv * uv;
        float dn = dot(d, p.normal);
        float c = p.normal_extent > 0.0 ? dn / p.normal_extent : (dn == 0.0 ? 0.0 : 2.0);
        // Not a face behind or in front of this one (vsch_shade.comp's
        // test, derived there): the photon's height over this tangent plane
        // and this point's over the photon's have one sign on one surface
        // (convex, concave or flat) and opposite signs for a parallel face
        // behind (the back wall seen through the closed tall block's back
        // face from inside: mean 1.1e-4 there before) or in front; r / 1000
        // keeps coplanar photons.
        float ha = -dot(d, surf.ng), ht = 1e-3 * p.radius;
        bool other_face = (ha < -ht && dn > ht) || (ha > ht && dn < -ht);
        if (det > 0.0 && abs(c) <= 1.0 && !other_face) {
          float du = dot(d, p.axis_u), dv = dot(d, p.axis_v);
          float a = (vv * du - uv * dv) / det;
          float bb = (uu * dv - uv * du) / det;
          float q = a * a + bb * bb;
          if (q + c * c <= 1.0) {
            float area = PB_PI * sqrt(det);
            float k = (box_kernel ? 1.0 : 2.0 * (1.0 - q)) / area;
            if (edges > 0u) {
              float share = 1.0;
              for (uint j = 0u; j < edges; ++j) {
                float hu = dot(edge_dir[j], p.axis_u), hv = dot(edge_dir[j], p.axis_v);
                float h = sqrt(hu * hu + hv * hv);
                if (h > 0.0) share *= 1.0 - pb_kernel_mass_beyond(edge_dist[j] / h, box_kernel);
              }
              k /= max(share, PB_EDGE_MIN_SHARE);
            }
            bool caustic_photon = (p.flags & PB_PHOTON_CAUSTIC) != 0u;
#ifdef PB_UPSAMPLE
            vec3 f;
            if (listed) { // the diffuse irradiance of the non-caustic photons: f_d / (base kd / pi)
              if (caustic_photon) continue;
              f = dot(p.wi, b.ng) > 0.0 && dot(p.wi, b.n) > 0.0 ? vec3(1.0) : vec3(0.0);
            } else if (split && !caustic_photon) { // the glossy lobe only
              if (!glossy) continue;
              f = max(pb_bsdf_eval(b, g.wo, p.wi, rng) - pb_ups_diffuse(b, g.wo, p.wi), vec3(0.0));
            } else {
              f = pb_bsdf_eval(b, g.wo, p.wi, rng);
            }
#else
            vec3 f = pb_bsdf_eval(b, g.wo, p.wi, rng);
#endif
            if (SC_HAS_NORMALS && !nmap) {
              // The photon's own face: its density carries |wi . n_g| of the
              // face it hit (p.normal), which differs from this point's n_g
              // where a footprint reaches across an edge of a coarse mesh
              // (measured: with surf.ng here, +14 % on the smooth sphere of
              // test_gpu_smooth_shading, with p.normal within noise).
              float cg = dot(p.wi, p.normal);
              f *= cg >= 1e-4 ? abs(dot(p.wi, surf.ns)) / cg : 0.0;
            }
            vec3 contrib = k * f * p.power;
            if (!any(isnan(contrib)) && !any(isinf(contrib))) {
              if (caustic_photon) {
                cau += contrib;
              } else {
                ind += contrib;
                if (nmap) {
                  float wgt = k * pb_lum(p.power);
                  if (wgt > 0.0) dir += vec4(p.wi * wgt, wgt);
                }
              }
              hits++;
            }
          }
        }
      }
    }
  }
#ifdef PB_UPSAMPLE
  if (listed) { // per unit albedo, without the throughput: upsample_compose.comp applies both
    ups_irr[gid] = vec4(ind, float(PB_UPS_ESTIMATED));
    atomicAdd(ups_list[PB_UPS_H_ESTIMATED + gp.level], 1u);
    return;
  }
#endif
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
  if ((gp.flags & PB_GATHER_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += ind + cau;
    accum[gid] = acc;
  }
}
