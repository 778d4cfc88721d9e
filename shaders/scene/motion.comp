#version 450
// Motion vectors (src/render/scene/motion.h): per pixel, the pixel-centre camera
// ray (gbuffer.comp's ray at one sample) traced to its first hit; the hit's
// triangle and barycentrics give the same point on the triangle's previous
// vertex positions (triangle i is the same triangle at every pose), which
// the previous camera projects. Output (dx, dy, z, valid): previous screen
// position minus this pixel's centre in pixels, the point's camera depth in
// the previous frame, 1 when it was in front of the previous camera.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#ifdef PB_RAY_QUERY
layout(set = 0, binding = PB_MOTION_BIND_NODES) uniform accelerationStructureEXT pb_tlas; // the scene's (gpu/accel.c)
#else
layout(std430, set = 0, binding = PB_MOTION_BIND_NODES) readonly buffer Nodes { vec4 bvh_nodes4[]; }; // pb_gpu_bvh_node[], 2 each
layout(std430, set = 0, binding = PB_MOTION_BIND_TRIS) readonly buffer Tris { vec4 bvh_tris4[]; };   // pb_gpu_tri[], 3 each
#endif
layout(std430, set = 0, binding = PB_MOTION_BIND_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = PB_MOTION_BIND_PREV_POSITIONS) readonly buffer PrevPos { float prev_positions[]; };
layout(std430, set = 0, binding = PB_MOTION_BIND_PARAMS) readonly buffer Params { pb_gpu_motion_params mp; };
layout(std430, set = 0, binding = PB_MOTION_BIND_MOTION) writeonly buffer Motion { vec4 motion[]; };

#include "common/bvh.glsl"
#include "common/camera.glsl"

vec3 pb_prev_vertex(uint i) {
  return vec3(prev_positions[3u * i], prev_positions[3u * i + 1u], prev_positions[3u * i + 2u]);
}

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (gid >= mp.width * mp.height) return;
  float fx = float(gid % mp.width) + 0.5, fy = float(gid / mp.width) + 0.5;
  vec3 org, dir;
  float t0, tmax;
  // The pinhole ray (the lens centre's, with depth of field): the vectors
  // follow the surface seen through the pixel centre, not a lens sample.
  pb_camera_ray(mp.cam, vec2(fx, fy), org, dir, t0, tmax);
  float t, u, v;
  uint prim = pb_trace(org, dir, 0.0, tmax, false, t, u, v);
  vec4 result = vec4(0.0);
  if (prim != PB_GPU_MISS && prim < mp.triangle_count) {
    vec3 p = (1.0 - u - v) * pb_prev_vertex(indices[3u * prim]) + u * pb_prev_vertex(indices[3u * prim + 1u]) +
             v * pb_prev_vertex(indices[3u * prim + 2u]);
    vec2 q;
    float z;
    if (pb_camera_project(mp.prev, p, q, z)) result = vec4(q.x - fx, q.y - fy, z, 1.0);
  }
  motion[gid] = result;
}
