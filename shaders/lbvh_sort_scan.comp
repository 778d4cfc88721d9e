#version 450
// Radix sort, step 2: exclusive prefix sum over the digit-major histogram
// (one workgroup: each invocation scans a contiguous chunk serially, the
// chunk totals are scanned in shared memory).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

shared uint s_tot[PB_GPU_WORKGROUP];

void main() {
  uint gid = pb_gid();
  if (gid >= PB_GPU_WORKGROUP) return; // one workgroup
  uint l = gl_LocalInvocationID.x;
  uint m = PB_LBVH_RADIX * info.tiles;
  uint chunk = (m + PB_GPU_WORKGROUP - 1u) / PB_GPU_WORKGROUP;
  uint b = min(l * chunk, m), e = min(b + chunk, m);
  uint sum = 0u;
  for (uint i = b; i < e; ++i) sum += hist[i];
  s_tot[l] = sum;
  barrier();
  if (l == 0u) {
    uint run = 0u;
    for (uint i = 0u; i < PB_GPU_WORKGROUP; ++i) {
      uint t = s_tot[i];
      s_tot[i] = run;
      run += t;
    }
  }
  barrier();
  uint run = s_tot[l];
  for (uint i = b; i < e; ++i) {
    uint t = hist[i];
    hist[i] = run;
    run += t;
  }
}
