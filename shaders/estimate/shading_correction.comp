#version 450
// Eq. 20 of seed 001 (24.4.3) on the resolved planes (shared/pb_resolve.h),
// after the filters: each pixel's indirect radiance is scaled by
// k = 1 + frac (f - 1), f = min(max(w_i . n_s, 0) / (max(w_i . n_g, 0) +
// eps), s_max), frac the fraction of its samples on a normal-mapped
// material, and the beauty takes the same change; the arithmetic of
// src/render/estimate/shading_correction.c (pb_shading_correction_factor and _apply),
// operation for operation and without fused multiply-adds (`precise`).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"
#include "shared/pb_resolve.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
layout(std430, set = 0, binding = PB_SHADING_BIND_PLANES) buffer Planes { float planes[]; };
layout(std430, set = 0, binding = PB_SHADING_BIND_PHOTON_PLANES) buffer PhotonPlanes { float pplanes[]; };
layout(push_constant) uniform Push { pb_gpu_shading_push push; };

// eps of eq. 20 (PB_SHADING_CORRECTION_EPS, shading_correction.h).
const float PB_EPS = 1e-3;

uint at(uint plane, uint ch, uint i, uint c) {  // photon planes only (plane >= BASE)
  return (plane - PB_RESOLVE_BASE_CHANNELS) * push.pixels + i * ch + c;
}

vec3 get3(uint plane, uint ch, uint i) {
  return vec3(pplanes[at(plane, ch, i, 0u)], pplanes[at(plane, ch, i, 1u)], pplanes[at(plane, ch, i, 2u)]);
}

bool finite(float v) { return !isnan(v) && !isinf(v); }

float dot3(vec3 a, vec3 b) {
  precise float d = a.x * b.x + a.y * b.y;
  d = d + a.z * b.z;
  return d;
}

float factor(vec3 wi, vec3 ns, vec3 ng) {
  float l = sqrt(dot3(wi, wi));
  if (!(l > 0.0) || !finite(l)) return 1.0;
  float cs = dot3(wi, ns) / l, cg = dot3(wi, ng) / l;
  if (!finite(cs) || !finite(cg)) return 1.0;
  precise float den = max(cg, 0.0) + PB_EPS;
  float f = max(cs, 0.0) / den;
  return min(f, push.s_max);
}

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (i >= push.pixels) return;
  float frac = pplanes[at(PB_RESOLVE_SHADING_NORMAL, 4u, i, 3u)];
  if (!(frac > 0.0)) return;
  float f = factor(get3(PB_RESOLVE_PHOTON_DIR, 3u, i), get3(PB_RESOLVE_SHADING_NORMAL, 4u, i),
                   get3(PB_RESOLVE_GEO_NORMAL, 3u, i));
  precise float k = 1.0 + frac * (f - 1.0);
  if (k == 1.0) return;
  for (uint c = 0u; c < 3u; ++c) {
    uint ip = at(PB_RESOLVE_INDIRECT, 3u, i, c), bp = PB_RESOLVE_BEAUTY * push.pixels + i * 4u + c;
    precise float before = pplanes[ip], after = before * k;
    pplanes[ip] = after;
    planes[bp] = planes[bp] + (after - before);
  }
}
