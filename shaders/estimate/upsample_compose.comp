#version 450
// The end of the multi-level up-sampling (seed 003 sec. 6, Figure 9: "the
// irradiance is multiplied by the BRDF recorded for every pixel in
// screen-space to produce indirect illumination"): at every pixel of the
// band with a glTF material, the full-resolution irradiance per unit albedo
// (upsample_mark.comp, gather_upsample) times the diffuse term of its own
// BSDF, base kd(wo) / pi (bsdf.glsl pb_bsdf_eval's Lambert term; textures
// stay sharp: base is this pixel's), times the eye chain's throughput, is
// added to the indirect photon sum and the beauty, as the gather would add
// it. The glossy lobes and the caustic photons come from the full-resolution
// pass after this one (gather_upsample, PB_GATHER_UPS_REST). Also resets the
// queue counters of the levels for the next sample (gid 0; no pass reads them
// until the next sample's first mark, after a barrier).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_upsample.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"

layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
layout(std430, set = 0, binding = PB_UPS_BIND_IRR) readonly buffer UpsIrr { vec4 ups_irr[]; };
layout(std430, set = 0, binding = PB_UPS_BIND_LIST) buffer UpsList { uint ups_list[]; };
layout(std430, set = 0, binding = PB_UPS_BIND_PACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(push_constant) uniform UpsPush { pb_gpu_upsample_push up; };

void main() {
  uint gid = pb_gid();
  if (gid == 0u)
    for (uint l = 0u; l <= PB_UPS_MAX_LEVELS; ++l) ups_list[PB_UPS_H_QUEUED + l] = 0u;
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS || g.lobes != 0u) return;
  vec4 ir = ups_irr[gid];
  if (ir.w == float(PB_UPS_NONE)) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, vec3(0.0));
  float cos_o = dot(g.wo, b.n);
  if (cos_o <= 0.0) return;
  vec4 l = pb_lobes(b, cos_o);
  if (!(l.w > 0.0)) return;
  vec3 ind = b.base * (l.w * PB_INV_PI) * ir.xyz * g.throughput;
  if (any(isnan(ind)) || any(isinf(ind))) return;
  atomicAdd(ups_list[PB_UPS_H_DIFFUSE], 1u);
  pb_gpu_photon_accum pa = paccum[gid];
  pa.indirect.xyz += ind;
  paccum[gid] = pa;
  if ((up.flags & PB_GATHER_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += ind;
    accum[gid] = acc;
  }
}
