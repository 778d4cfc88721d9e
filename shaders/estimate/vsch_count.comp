// View-sample cluster hierarchy (seed 004 4.3), the count pass: one
// invocation per photon traverses the hierarchy (common/vsch_traverse.glsl)
// and counts its list insertions (the prefix sum over them, vsch_scan, says
// where vsch_fill writes them); the trivially accepted (4.6) and directional
// (4.7) flux goes into the nodes here, once.
//
// Lists: count, prefix sum over the photons, fill, then a stable radix sort
// of the (node, photon) pairs by node: the paper counts per node, scans the
// nodes and fills with atomic cursors, which puts each list in the order
// the atomics happened to run, so the float sum at shading changed in its
// last bits from run to run; pairs written in photon order and sorted
// stably keep every list in photon order and the image the same bit for
// bit (the paper's "jobs" list of (photon, node key) pairs grouped per
// cluster is the same structure).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
layout(std430, set = 0, binding = PB_VSCH_BIND_PHOTONS) readonly buffer Photons { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = PB_VSCH_BIND_COUNTS) readonly buffer Counts { pb_gpu_photon_counts mcounts; };
#define PB_VSCH_PHOTON_COUNT 1
#include "common/vsch.glsl"
uint g_count;
void pb_vsch_list(uint g) { g_count++; }
#include "common/vsch_traverse.glsl"
#define PB_VSCH_BEGIN g_count = 0u;
#define PB_VSCH_END vd[vp.photon_off + gid] = g_count;

void main() {
  uint gid = pb_gid();
  if (gid >= vd[PB_VSCH_H_PHOTONS]) return;
  pb_gpu_photon p = photons[gid];
  float r = pb_photon_radius(p);
  vec3 E = p.power / (PB_VSCH_PI * r * r);
  float emax = uintBitsToFloat(vd[PB_VSCH_H_EMAX]);
  PB_VSCH_BEGIN
  if (r > 0.0 && !isinf(r) && !any(isnan(E)) && !any(isinf(E)) && !any(isnan(p.position)) && !any(isnan(p.wi))) {
    vec3 vr, vu, vf;
    pb_view_frame(vr, vu, vf);
    vec3 wiv = vec3(dot(p.wi, vr), dot(p.wi, vu), dot(p.wi, vf));
    pb_vsch_traverse(pb_to_view(p.position), r, p.wi, p.normal, wiv, (p.flags & PB_PHOTON_CAUSTIC) != 0u, E, emax);
  }
  PB_VSCH_END
}
