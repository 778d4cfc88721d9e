#version 450
// The filters' input and output on the GPU (src/render/filter/filters.c), one
// invocation per pixel of the frame (one band: the filters need every
// neighbour). PACK reads the resolved planes (shared/pb_resolve.h) into
// the vec4 buffers the temporal filter and the A-Trous read: geometry (the
// edge-stopping normal, the geometric one where normal maps bend the
// shading one, seed 001 24.4.3; camera depth), albedo, indirect radiance
// with w = L = 1 (a single frame's history length, atrous.h) and, with
// PB_FILTER_IO_CAUSTIC, caustics. COMPOSE writes the filtered indirect and caustics back into
// their planes, each non-finite value as 0 and counted (the guard, as the
// resolve does), and moves the beauty by the change: beauty += filtered -
// raw, caustics first, then the indirect (the former host order, so the
// sums round as they did).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"
#include "shared/pb_resolve.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_PLANES) buffer Planes { float planes[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_PHOTON_PLANES) buffer PhotonPlanes { float pplanes[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_GEO) buffer Geo { vec4 geo[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_ALBEDO) buffer Albedo { vec4 albedo[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_INDIRECT_IN) buffer IndirectIn { vec4 indirect_in[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_INDIRECT) buffer Indirect { vec4 indirect[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_CAUSTIC_IN) buffer CausticIn { vec4 caustic_in[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_CAUSTIC) buffer Caustic { vec4 caustic[]; };
layout(std430, set = 0, binding = PB_FILTER_IO_BIND_GUARD) buffer Guard { uint guard_count; };
layout(push_constant) uniform Push { pb_gpu_filter_io_push push; };

float get(uint plane, uint ch, uint i, uint c) {
  if (plane < PB_RESOLVE_BASE_CHANNELS) return planes[plane * push.pixels + i * ch + c];
  return pplanes[(plane - PB_RESOLVE_BASE_CHANNELS) * push.pixels + i * ch + c];
}

void put(uint plane, uint ch, uint i, uint c, float v) {
  if (plane < PB_RESOLVE_BASE_CHANNELS)
    planes[plane * push.pixels + i * ch + c] = v;
  else
    pplanes[(plane - PB_RESOLVE_BASE_CHANNELS) * push.pixels + i * ch + c] = v;
}

vec3 get3(uint plane, uint i) { return vec3(get(plane, 3u, i, 0u), get(plane, 3u, i, 1u), get(plane, 3u, i, 2u)); }

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (i >= push.pixels) return;
  if (push.mode == PB_FILTER_IO_PACK) {
    uint np = (push.flags & PB_FILTER_IO_GEO_NORMAL) != 0u ? PB_RESOLVE_GEO_NORMAL : PB_RESOLVE_NORMAL;
    geo[i] = vec4(get3(np, i), get(PB_RESOLVE_DEPTH, 1u, i, 0u));
    albedo[i] = vec4(get3(PB_RESOLVE_ALBEDO, i), 0.0);
    indirect_in[i] = vec4(get3(PB_RESOLVE_INDIRECT, i), 1.0);
    if ((push.flags & PB_FILTER_IO_CAUSTIC) != 0u) caustic_in[i] = vec4(get3(PB_RESOLVE_CAUSTIC, i), 0.0);
    return;
  }
  uint bad = 0u;
  for (uint k = 0u; k < 3u; ++k) {
    precise float b = get(PB_RESOLVE_BEAUTY, 4u, i, k);
    if ((push.flags & PB_FILTER_IO_CAUSTIC) != 0u) {
      float c = caustic[i][k], raw = get(PB_RESOLVE_CAUSTIC, 3u, i, k);
      if (isnan(c) || isinf(c)) c = 0.0, bad++;
      put(PB_RESOLVE_CAUSTIC, 3u, i, k, c);
      b = b + (c - raw);
    }
    if ((push.flags & PB_FILTER_IO_INDIRECT) != 0u) {
      float v = indirect[i][k], raw = get(PB_RESOLVE_INDIRECT, 3u, i, k);
      if (isnan(v) || isinf(v)) v = 0.0, bad++;
      put(PB_RESOLVE_INDIRECT, 3u, i, k, v);
      b = b + (v - raw);
    }
    put(PB_RESOLVE_BEAUTY, 4u, i, k, b);
  }
  if (bad != 0u) atomicAdd(guard_count, bad);
}
