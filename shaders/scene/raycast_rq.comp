#version 460
// Ray queries through VK_KHR_ray_query (GL_EXT_ray_query) against the scene's
// acceleration structure (src/gpu/accel.c): one ray per invocation, closest
// hit or any hit (occlusion), the same rays and hits as raycast.comp's GLSL
// BVH, for the tests that compare the two. Compiled apart from shaders/*.comp
// (SPIR-V 1.4, shaders/shaders.cmake) and loaded only on a device created
// with the ray-query extensions (pb_gpu_limits.ray_query).
//
// Hits: prim is the scene's triangle index (the BLAS holds the scene's
// triangles in order, one geometry, opaque, no culling: back faces count, as
// in the GLSL BVH and Embree); u, v the barycentrics of p1 and p2. Any hit
// sets prim 0 and t to tmax when occluded. The query's interval is
// [tmin, tmax], the BVH's (tmin, tmax): a hit exactly at an end is noise.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(set = 0, binding = PB_RAYCAST_RQ_BIND_TLAS) uniform accelerationStructureEXT Tlas;
layout(std430, set = 0, binding = PB_RAYCAST_RQ_BIND_RAYS) readonly buffer Rays { pb_gpu_ray rays[]; };
layout(std430, set = 0, binding = PB_RAYCAST_RQ_BIND_HITS) writeonly buffer Hits { pb_gpu_hit hits[]; };
layout(push_constant) uniform Push { pb_gpu_raycast_push pc; };

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (gid >= pc.ray_count) return;
  pb_gpu_ray ray = rays[gid];
  bool any_hit = pc.any_hit != 0u;
  uint flags = gl_RayFlagsOpaqueEXT | (any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : 0u);
  rayQueryEXT q;
  rayQueryInitializeEXT(q, Tlas, flags, 0xffu, ray.org, ray.tmin, ray.dir, ray.tmax);
  while (rayQueryProceedEXT(q)) {
  }
  pb_gpu_hit h;
  h.t = ray.tmax;
  h.prim = PB_GPU_MISS;
  h.u = 0.0;
  h.v = 0.0;
  if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    if (any_hit) {
      h.prim = 0u;
    } else {
      vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, true);
      h.t = rayQueryGetIntersectionTEXT(q, true);
      h.prim = uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
      h.u = b.x;
      h.v = b.y;
    }
  }
  hits[gid] = h;
}
