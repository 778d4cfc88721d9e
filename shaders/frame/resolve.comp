#version 450
// The resolve pass: one invocation per pixel of a band turns the
// sums over samples (pb_gpu_accum from the G-buffer and direct passes,
// pb_gpu_photon_accum and pb_gpu_photon_nmap from the gather) into the AOVs
// of pb_render_result, in the planes of shared/pb_resolve.h, on the GPU:
// means (sum x inv_spp, the host's float), the mean normal normalised, depth
// over coverage, the material index as written, and for eq. 20 (seed 001
// 24.4.3) the unit mean geometric normal, photon direction and shading
// normal with the normal-mapped fraction of samples. Every value of the
// guarded AOVs (beauty, direct, albedo, normal, depth, material, emission,
// indirect, caustic) that is not finite is written as 0 and counted
// (atomicAdd on guard.count; a correct render has none).
// k_PD's two sums (the KPD plane's channels) are reduced here too, per
// workgroup in shared memory, then added with atomics into KpdSums as 64-bit
// fixed point (shared/pb_resolve.h pb_gpu_resolve_kpd), so a lean readback
// brings 16 bytes instead of the plane.
// The arithmetic is the former host resolve's (frame.c, shading_correction.c
// pb_shading_correction_resolve), operation for operation.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_resolve.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_RESOLVE_BIND_ACCUM) readonly buffer Accum { pb_gpu_accum accum[]; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_PHOTON_ACCUM) readonly buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_NMAP) readonly buffer PhotonNmap { pb_gpu_photon_nmap pnmap[]; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_OUT) writeonly buffer Planes { float planes[]; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_GUARD) buffer Guard { uint guard_count; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_OUT_PHOTONS) writeonly buffer PhotonPlanes { float pplanes[]; };
layout(std430, set = 0, binding = PB_RESOLVE_BIND_KPD_SUMS) buffer KpdSums { pb_gpu_resolve_kpd kpd; };
layout(push_constant) uniform ResolvePush { pb_gpu_resolve_push rp; };

// Per workgroup: [0] photons, [1] hits, each as (lo, hi) words.
shared uint s_lo[2][PB_GPU_WORKGROUP], s_hi[2][PB_GPU_WORKGROUP];

uint g_bad = 0u;

float guarded(float v) {
  if (isnan(v) || isinf(v)) {
    g_bad += 1u;
    return 0.0;
  }
  return v;
}

void put(uint plane, uint ch, uint i, uint c, float v) {
  if (plane < PB_RESOLVE_BASE_CHANNELS)
    planes[plane * rp.pixels + i * ch + c] = v;
  else
    pplanes[(plane - PB_RESOLVE_BASE_CHANNELS) * rp.pixels + i * ch + c] = v;
}

vec3 unit3(vec3 v) { // shading_correction.c unit(): 0 unless the length is finite and > 0
  float l = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  bool ok = l > 0.0 && !isinf(l) && !isnan(l);
  return ok ? v / l : vec3(0.0);
}

// A count as 64-bit unsigned fixed point (pb_resolve.h): v x 2^FRAC_BITS,
// exact for v < 2^40 (a float's 24 bits, shifted); the high word is
// floor(w / 2^32), the low word the exact rest.
uvec2 fixed64(float v) {
  if (isnan(v) || isinf(v) || v <= 0.0) return uvec2(0u);
  float w = min(v, exp2(float(PB_RESOLVE_KPD_MAX_LOG2))) * exp2(float(PB_RESOLVE_KPD_FRAC_BITS));
  float h = floor(w * exp2(-32.0));
  return uvec2(uint(w - h * exp2(32.0)), uint(h));
}

// Adds the 64-bit (lo, hi) b to a, the carry out of the low word into the high.
uvec2 add64(uvec2 a, uvec2 b) {
  uint lo = a.x + b.x;
  return uvec2(lo, a.y + b.y + (lo < a.x ? 1u : 0u));
}

void resolve_pixel(uint i, out float k_photons, out float k_hits) {
  pb_gpu_accum a = accum[i];
  k_photons = 0.0;
  k_hits = 0.0;
  float inv = rp.inv_spp;
  for (uint k = 0u; k < 4u; ++k) {
    float v = a.beauty[k] * inv;
    if (k == 3u && (rp.flags & PB_RESOLVE_OPAQUE) != 0u) v = 1.0;
    put(PB_RESOLVE_BEAUTY, 4u, i, k, guarded(v));
  }
  for (uint k = 0u; k < 3u; ++k) {
    put(PB_RESOLVE_DIRECT, 3u, i, k, guarded(a.direct[k] * inv));
    put(PB_RESOLVE_ALBEDO, 3u, i, k, guarded(a.albedo[k] * inv));
    put(PB_RESOLVE_EMISSION, 3u, i, k, guarded(a.emission[k] * inv));
  }
  vec3 n = a.normal;
  float nl = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  for (uint k = 0u; k < 3u; ++k) put(PB_RESOLVE_NORMAL, 3u, i, k, guarded(nl > 0.0 ? n[k] / nl : 0.0));
  put(PB_RESOLVE_DEPTH, 1u, i, 0u, guarded(a.beauty[3] > 0.0 ? a.depth / a.beauty[3] : 0.0));
  put(PB_RESOLVE_MATERIAL, 1u, i, 0u, guarded(a.material));
  if ((rp.flags & PB_RESOLVE_PHOTONS) != 0u) {
    pb_gpu_photon_accum p = paccum[i];
    for (uint k = 0u; k < 3u; ++k) {
      put(PB_RESOLVE_INDIRECT, 3u, i, k, guarded(p.indirect[k] * inv));
      put(PB_RESOLVE_CAUSTIC, 3u, i, k, guarded(p.caustic[k] * inv));
    }
    put(PB_RESOLVE_KPD, 2u, i, 0u, p.indirect.w); // raw sums: stats only
    put(PB_RESOLVE_KPD, 2u, i, 1u, a.beauty[3]);
    k_photons = p.indirect.w;
    k_hits = a.beauty[3];
    if ((rp.flags & PB_RESOLVE_NMAP) != 0u) {
      pb_gpu_photon_nmap m = pnmap[i];
      vec3 gn = unit3(m.geo.xyz), pd = unit3(m.dir.xyz), ns = unit3(m.ns.xyz);
      float frac = m.ns.w * inv;
      frac = (isnan(frac) || isinf(frac)) ? 0.0 : min(max(frac, 0.0), 1.0);
      for (uint k = 0u; k < 3u; ++k) {
        put(PB_RESOLVE_GEO_NORMAL, 3u, i, k, gn[k]);
        put(PB_RESOLVE_PHOTON_DIR, 3u, i, k, pd[k]);
        put(PB_RESOLVE_SHADING_NORMAL, 4u, i, k, ns[k]);
      }
      put(PB_RESOLVE_SHADING_NORMAL, 4u, i, 3u, frac);
    }
  }
  if (g_bad != 0u) atomicAdd(guard_count, g_bad);
}

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  float kp = 0.0, kh = 0.0;
  if (i < rp.pixels) resolve_pixel(i, kp, kh);
  // k_PD's sums: the flag is the dispatch's (uniform), so every invocation
  // of the workgroup reaches the barriers; pixels past the band add 0.
  if ((rp.flags & PB_RESOLVE_PHOTONS) == 0u) return;
  uint l = gl_LocalInvocationID.x;
  uvec2 p = fixed64(kp), h = fixed64(kh);
  s_lo[0][l] = p.x, s_hi[0][l] = p.y, s_lo[1][l] = h.x, s_hi[1][l] = h.y;
  barrier();
  for (uint s = PB_GPU_WORKGROUP / 2u; s > 0u; s >>= 1u) {
    if (l < s)
      for (uint c = 0u; c < 2u; ++c) {
        uvec2 v = add64(uvec2(s_lo[c][l], s_hi[c][l]), uvec2(s_lo[c][l + s], s_hi[c][l + s]));
        s_lo[c][l] = v.x, s_hi[c][l] = v.y;
      }
    barrier();
  }
  if (l == 0u) {
    // 64-bit atomic add from two 32-bit ones: atomicAdd returns the low
    // word before this add, so the carry out of it is exact under any order.
    uint old = atomicAdd(kpd.photons_lo, s_lo[0][0]);
    uint carry = old + s_lo[0][0] < old ? 1u : 0u;
    if (s_hi[0][0] + carry != 0u) atomicAdd(kpd.photons_hi, s_hi[0][0] + carry);
    old = atomicAdd(kpd.hits_lo, s_lo[1][0]);
    carry = old + s_lo[1][0] < old ? 1u : 0u;
    if (s_hi[1][0] + carry != 0u) atomicAdd(kpd.hits_hi, s_hi[1][0] + carry);
  }
}
