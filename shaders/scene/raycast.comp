#version 450
// Ray queries for tests and the benchmark: one ray per invocation, closest
// hit or any hit (occlusion), against the scene BVH.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_RAYCAST_BIND_NODES) readonly buffer Nodes { vec4 bvh_nodes4[]; }; // pb_gpu_bvh_node[], 2 each
layout(std430, set = 0, binding = PB_RAYCAST_BIND_TRIS) readonly buffer Tris { vec4 bvh_tris4[]; };   // pb_gpu_tri[], 3 each
layout(std430, set = 0, binding = PB_RAYCAST_BIND_RAYS) readonly buffer Rays { pb_gpu_ray rays[]; };
layout(std430, set = 0, binding = PB_RAYCAST_BIND_HITS) writeonly buffer Hits { pb_gpu_hit hits[]; };
layout(push_constant) uniform Push { pb_gpu_raycast_push pc; };

#include "common/bvh.glsl"

void main() {
  uint gid = gl_GlobalInvocationID.x;
  if (gid >= pc.ray_count) return;
  pb_gpu_ray ray = rays[gid];
  float t, u, v;
  uint prim = pb_trace(ray.org, ray.dir, ray.tmin, ray.tmax, pc.any_hit != 0u, t, u, v);
  pb_gpu_hit h;
  h.t = t;
  h.prim = prim;
  h.u = u;
  h.v = v;
  hits[gid] = h;
}
