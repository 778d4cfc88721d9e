// Bindings shared by every LBVH pass (src/render/lbvh.c binds them in this
// order; one layout for all passes keeps the host side to one list).
#ifndef PB_LBVH_GLSL
#define PB_LBVH_GLSL

layout(std430, set = 0, binding = 0) coherent buffer InfoBuf { pb_gpu_lbvh_info info; };
layout(std430, set = 0, binding = 1) readonly buffer PhotonsIn { pb_gpu_photon photons_in[]; };
layout(std430, set = 0, binding = 2) buffer PhotonsSorted { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = 3) buffer Keys { uint keys[]; };        // 2 x capacity (ping-pong)
layout(std430, set = 0, binding = 4) buffer Vals { uint vals[]; };        // 2 x capacity
layout(std430, set = 0, binding = 5) buffer Hist { uint hist[]; };        // PB_LBVH_RADIX x tiles, digit-major
layout(std430, set = 0, binding = 6) coherent buffer Nodes { pb_gpu_lbvh_node nodes[]; };
layout(std430, set = 0, binding = 7) buffer LeafParent { uint leaf_parent[]; };
layout(std430, set = 0, binding = 8) coherent buffer Visit { uint visit[]; };
layout(std430, set = 0, binding = 9) buffer Partial { float area_partial[]; };
layout(push_constant) uniform LbvhPush { pb_gpu_lbvh_push pc; };

uint pb_gid() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
}

#include "common/photon_map.glsl"

#endif
