// View-sample cluster hierarchy (seed 004), pass 2: the ranges the later
// passes scale by: the nearest and farthest sample distance of the band
// (the depth slices of the grid) and the largest photon irradiance
// max_c Phi_c / (pi r^2) (the unit of the fixed-point flux sums), and the
// largest photon radius (the reach of vsch_leaf's edge search). One
// invocation per pixel and per photon (dispatch max(pixels, capacity)).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
layout(std430, set = 0, binding = PB_VSCH_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_VSCH_BIND_PHOTONS) readonly buffer Photons { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = PB_VSCH_BIND_COUNTS) readonly buffer Counts { pb_gpu_photon_counts mcounts; };
#define PB_VSCH_PHOTON_COUNT 1
#include "common/vsch.glsl"

void main() {
  uint gid = pb_gid();
  uint n = pb_vsch_photons();
  if (gid == 0u) vd[PB_VSCH_H_PHOTONS] = n;
  if (gid < vp.pixels) {
    pb_gpu_gbuffer g = gbuffer[gid];
    if (g.prim != PB_GPU_MISS) {
      float d = length(g.position - frame.cam.position);
      if (!isinf(d) && !isnan(d)) {
        atomicMin(vd[PB_VSCH_H_NEAR], pb_ord(d));
        atomicMax(vd[PB_VSCH_H_FAR], pb_ord(d));
      }
    }
  }
  if (gid < n) {
    pb_gpu_photon p = photons[gid];
    float r = pb_photon_radius(p);
    float e = max(p.power.x, max(p.power.y, p.power.z)) / (PB_VSCH_PI * r * r);
    if (r > 0.0 && e > 0.0 && !isinf(e) && !isnan(e)) atomicMax(vd[PB_VSCH_H_EMAX], floatBitsToUint(e));
    if (r > 0.0 && !isinf(r)) atomicMax(vd[PB_VSCH_H_RMAX], floatBitsToUint(r)); // r > 0: uint order
  }
}
