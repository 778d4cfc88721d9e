#version 450
// Screen-space splatting, pass 3 of 3 (seed 001 24.3): one thread per
// pixel. "We use photons to reconstruct irradiance ... We then approximate
// the light reflected from a surface by the product of the photon's
// irradiance and the surface's BRDF using a mean incoming direction": the
// splatted irradiance E (splat_splat.comp, eq. 9) times f(x, w_mean, wo),
// w_mean the normalised power-weighted direction of the kernels that
// covered the pixel, f the same BSDF as the LBVH gather's (gather.comp:
// the material and textures at x, the closures a Blender material left to
// the photon map, the adjoint shading-normal weight |w . n_s| / |w . n_g|
// where the scene has no normal maps; with normal maps eq. 20 is applied
// later by shading_correction.c from the direction sums written here).
// Exact for diffuse surfaces, as the chapter says; glossy ones see the
// directional distribution only through w_mean. The result is added into
// the pixel's pb_gpu_photon_accum (indirect, caustic; indirect.w the
// kernels that covered it), times the eye chain's throughput, and into the
// beauty unless PB_GATHER_NO_BEAUTY, as the gather does: the resolve,
// temporal and A-Trous passes after it do not know which estimator ran.
// The splat target of the pixel is cleared for the next sample, and
// threads below push.tiles clear the tile counters (splat_count.comp).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_splat.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"

layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_TILES) buffer Tiles { uint tiles[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_TARGET) buffer Target { uint target[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_ACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_NMAP) buffer PhotonNmap { pb_gpu_photon_nmap pnmap[]; }; // normal maps only
layout(push_constant) uniform SplatPush { pb_gpu_splat_push sp; };
layout(constant_id = PB_SPEC_NORMAL_MAPS) const bool SC_NORMAL_MAPS = true;

void main() {
  uint gid = pb_gid();
  if (gid < sp.tiles) tiles[gid] = 0u;
  if (gid >= frame.pixel_count) return;
  uint base = gid * PB_SPLAT_PIXEL_WORDS;
  vec3 e_ind = vec3(uintBitsToFloat(target[base + PB_SPLAT_W_IND]), uintBitsToFloat(target[base + PB_SPLAT_W_IND + 1u]),
                    uintBitsToFloat(target[base + PB_SPLAT_W_IND + 2u]));
  vec3 e_cau = vec3(uintBitsToFloat(target[base + PB_SPLAT_W_CAU]), uintBitsToFloat(target[base + PB_SPLAT_W_CAU + 1u]),
                    uintBitsToFloat(target[base + PB_SPLAT_W_CAU + 2u]));
  vec4 dir = vec4(uintBitsToFloat(target[base + PB_SPLAT_W_DIR]), uintBitsToFloat(target[base + PB_SPLAT_W_DIR + 1u]),
                  uintBitsToFloat(target[base + PB_SPLAT_W_DIR + 2u]), uintBitsToFloat(target[base + PB_SPLAT_W_WSUM]));
  uint hits = target[base + PB_SPLAT_W_HITS];
  for (uint k = 0u; k < PB_SPLAT_PIXEL_WORDS; ++k) target[base + k] = 0u;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  bool nmap = SC_NORMAL_MAPS && frame.tangent_base != 0u;
  vec3 ind = vec3(0.0), cau = vec3(0.0);
  if (hits > 0u) {
    pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, pb_surface_tangent(g.prim, g.u, g.v));
    if (SC_BLENDER && g.lobes != 0u) { // a Blender material: the closures left to the photon map
      b.mask = g.lobes;
      pb_blender_split(b, frame.glossy_path_alpha2);
    }
    uint rng = pb_walk_seed(pb_pixel_key(frame.pixel_base + gid), sp.sample_index, 2u);
    float ld = length(dir.xyz);
    // The mean direction; kernels of zero power leave the normal.
    vec3 wm = ld > 0.0 && !isinf(ld) ? dir.xyz / ld : surf.ng;
    vec3 f = pb_bsdf_eval(b, g.wo, wm, rng);
    if (SC_HAS_NORMALS && !nmap) {
      float cg = dot(wm, surf.ng);
      f *= cg >= 1e-4 ? abs(dot(wm, surf.ns)) / cg : 0.0;
    }
    ind = f * e_ind * g.throughput;
    cau = f * e_cau * g.throughput;
    if (any(isnan(ind)) || any(isinf(ind))) ind = vec3(0.0);
    if (any(isnan(cau)) || any(isinf(cau))) cau = vec3(0.0);
  }
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
  if ((sp.flags & PB_GATHER_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += ind + cau;
    accum[gid] = acc;
  }
}
