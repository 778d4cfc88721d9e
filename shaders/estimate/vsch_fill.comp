// View-sample cluster hierarchy (seed 004 4.3), the fill pass: the same
// traversal as vsch_count (common/vsch_traverse.glsl, PB_VSCH_FILL: no flux
// added), each list insertion written as the pair (node id, photon id) at
// the photon's offset from vsch_scan, into the radix sort's input (pairs
// past its capacity are dropped and counted, PB_VSCH_H_PAIR_OVERFLOW).
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
layout(std430, set = 0, binding = PB_VSCH_BIND_KEYS) writeonly buffer Keys { uint keys[]; };
layout(std430, set = 0, binding = PB_VSCH_BIND_VALS) writeonly buffer Vals { uint vals[]; };
#define PB_VSCH_FILL 1
uint g_slot, g_end, g_pid;
void pb_vsch_list(uint g) {
  if (g_slot < g_end) { // within the slots vsch_count reserved, and the sort's capacity
    keys[g_slot] = g;
    vals[g_slot] = g_pid;
  }
  g_slot++;
}
#include "common/vsch_traverse.glsl"
#define PB_VSCH_BEGIN g_slot = vd[vp.photon_off + vp.capacity + gid]; g_pid = gid; \
  g_end = min(g_slot + vd[vp.photon_off + gid], vp.pair_cap);
#define PB_VSCH_END

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
