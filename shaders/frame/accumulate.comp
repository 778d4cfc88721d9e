#version 450
// A still run's progressive accumulation, one invocation
// per pixel of the frame (one band), after the resolve, the filter chain
// and eq. 20, in the frame's last submission: what sequence.c's host
// accumulate() did on the read-back arrays, operation for operation (so the
// same pixels): the temporal filters keep the cumulative mean of the
// indirect light (and of the caustics when they have their own); the rest
// of the beauty (beauty minus those), the direct AOV and unfiltered
// caustics get a running mean m = (m * k + x) * inv over the run's frames,
// written back into the planes (the beauty as m + kept). `precise` keeps
// the compiler from fusing m * k + x into an FMA the host does not do.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_contract.h"
#include "shared/pb_resolve.h"
#include "shared/pb_accumulate.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_ACCUM_BIND_PLANES) buffer Planes { float planes[]; };
layout(std430, set = 0, binding = PB_ACCUM_BIND_PHOTON_PLANES) buffer PhotonPlanes { float pplanes[]; };
layout(std430, set = 0, binding = PB_ACCUM_BIND_SUM) buffer Sum { float sum[]; };
layout(push_constant) uniform AccumPush { pb_gpu_accumulate_push ap; };

float running(uint s, float x) {
  precise float m;
  if ((ap.flags & PB_ACCUM_FIRST) != 0u) {
    m = x;
  } else {
    precise float p = sum[s] * ap.k;
    precise float q = p + x;
    m = q * ap.inv;
  }
  sum[s] = m;
  return m;
}

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  uint n = ap.pixels;
  if (i >= n) return;
  bool photons = (ap.flags & PB_ACCUM_PHOTONS) != 0u;
  bool cfilt = (ap.flags & PB_ACCUM_CAUSTIC_FILTERED) != 0u;
  uint s = i * PB_ACCUM_FLOATS;
  uint ind = (PB_RESOLVE_INDIRECT - PB_RESOLVE_BASE_CHANNELS) * n + i * 3u;
  uint cau = (PB_RESOLVE_CAUSTIC - PB_RESOLVE_BASE_CHANNELS) * n + i * 3u;
  for (uint c = 0u; c < 4u; ++c) {
    precise float kept = 0.0; // the temporally filtered parts, added as the host does
    if (c < 3u && photons) kept = kept + pplanes[ind + c];
    if (c < 3u && photons && cfilt) kept = kept + pplanes[cau + c];
    uint b = PB_RESOLVE_BEAUTY * n + i * 4u + c;
    precise float rest = planes[b] - kept;
    precise float m = running(s + PB_ACCUM_REST + c, rest);
    planes[b] = m + kept;
  }
  for (uint c = 0u; c < 3u; ++c) {
    uint d = PB_RESOLVE_DIRECT * n + i * 3u + c;
    planes[d] = running(s + PB_ACCUM_DIRECT + c, planes[d]);
    if (photons && !cfilt) pplanes[cau + c] = running(s + PB_ACCUM_CAUSTIC + c, pplanes[cau + c]);
  }
}
