#version 450
// Motion vectors (src/render/motion.h): per pixel, the pixel-centre camera
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

layout(std430, set = 0, binding = 0) readonly buffer Nodes { vec4 bvh_nodes4[]; }; // pb_gpu_bvh_node[], 2 each
layout(std430, set = 0, binding = 1) readonly buffer Tris { vec4 bvh_tris4[]; };   // pb_gpu_tri[], 3 each
layout(std430, set = 0, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = 3) readonly buffer PrevPos { float prev_positions[]; };
layout(std430, set = 0, binding = 4) readonly buffer Params { pb_gpu_motion_params mp; };
layout(std430, set = 0, binding = 5) writeonly buffer Motion { vec4 motion[]; };

#include "common/bvh.glsl"

vec3 pb_prev_vertex(uint i) {
  return vec3(prev_positions[3u * i], prev_positions[3u * i + 1u], prev_positions[3u * i + 2u]);
}

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (gid >= mp.width * mp.height) return;
  float fx = float(gid % mp.width) + 0.5, fy = float(gid / mp.width) + 0.5;
  float sx = (2.0 * fx / float(mp.width) - 1.0) * mp.tan_x;
  float sy = (1.0 - 2.0 * fy / float(mp.height)) * mp.tan_y;
  vec3 dir = normalize(mp.cam_forward.xyz + mp.cam_right.xyz * sx + mp.cam_up.xyz * sy);
  float t, u, v;
  uint prim = pb_trace(mp.cam_pos.xyz, dir, 0.0, uintBitsToFloat(0x7f800000u), false, t, u, v);
  vec4 result = vec4(0.0);
  if (prim != PB_GPU_MISS && prim < mp.triangle_count) {
    vec3 p = (1.0 - u - v) * pb_prev_vertex(indices[3u * prim]) + u * pb_prev_vertex(indices[3u * prim + 1u]) +
             v * pb_prev_vertex(indices[3u * prim + 2u]);
    // The inverse of the previous camera's ray: x = (sx / tan_x + 1) W / 2.
    vec3 d = p - mp.prev_pos.xyz;
    float z = dot(d, mp.prev_forward.xyz);
    if (z > 0.0) {
      float x = 0.5 * (dot(d, mp.prev_right.xyz) / z / mp.prev_tan_x + 1.0) * float(mp.width);
      float y = 0.5 * (1.0 - dot(d, mp.prev_up.xyz) / z / mp.prev_tan_y) * float(mp.height);
      if (!isinf(x) && !isinf(y) && !isnan(x) && !isnan(y)) result = vec4(x - fx, y - fy, z, 1.0);
    }
  }
  motion[gid] = result;
}
