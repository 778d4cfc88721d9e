// Bindings shared by every LBVH build pass (src/render/photon/lbvh.c binds them in
// this order; one layout for all passes keeps the host side to one list).
#ifndef PB_LBVH_GLSL
#define PB_LBVH_GLSL

layout(std430, set = 0, binding = PB_LBVH_BIND_INFO) coherent buffer InfoBuf { pb_gpu_lbvh_info info; };
layout(std430, set = 0, binding = PB_LBVH_BIND_PHOTONS_IN) readonly buffer PhotonsIn { pb_gpu_photon photons_in[]; };
layout(std430, set = 0, binding = PB_LBVH_BIND_MAP_COUNTS) readonly buffer MapCounts { pb_gpu_photon_counts map_counts; };
layout(std430, set = 0, binding = PB_LBVH_BIND_SORTED) buffer PhotonsSorted { pb_gpu_photon_packed photons[]; };
layout(std430, set = 0, binding = PB_LBVH_BIND_KEYS) buffer Keys { uint keys[]; };        // the sort's, 2 x capacity
layout(std430, set = 0, binding = PB_LBVH_BIND_VALS) buffer Vals { uint vals[]; };        // the sort's, 2 x capacity
layout(std430, set = 0, binding = PB_LBVH_BIND_NODES) coherent buffer Nodes { pb_gpu_lbvh_node nodes[]; };
layout(std430, set = 0, binding = PB_LBVH_BIND_VISIT) coherent buffer Visit { uint visit[]; };
layout(std430, set = 0, binding = PB_LBVH_BIND_PARTIAL) coherent buffer Partial { float area_partial[]; };
// Bindings 1 and 3 again, the tracer's record as 6 uvec4 (pb_photon.h's
// offsets), the sorted (packed) one as 3: one 4-word access where llvmpipe
// pays a loop over the lanes for each member.
layout(std430, set = 0, binding = PB_LBVH_BIND_PHOTONS_IN4) readonly buffer PhotonsIn4 { uvec4 photons_in4[]; };
layout(std430, set = 0, binding = PB_LBVH_BIND_SORTED4) buffer PhotonsSorted4 { uvec4 photons4[]; };
// Binding 6 again: a child entry as 2 uvec4 (lo, ref; hi, count).
layout(std430, set = 0, binding = PB_LBVH_BIND_NODES4) coherent buffer Nodes4 { uvec4 nodes4[]; };
layout(push_constant) uniform LbvhPush { pb_gpu_lbvh_push pc; };

// Invocation index in a grid folded into x and y (pb_gpu_dispatch_indirect).
uint pb_gid() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
}
uint pb_group() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

#include "common/photon_map.glsl"

#endif
