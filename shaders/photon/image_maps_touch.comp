#version 450
// Which environment maps moved geometry touches (seed 003
// section 4's progressive update renders "only what changed"): one
// invocation per texel of maps first_map .. first_map + map_count - 1; the
// texel's ray from the map's centre through the texel's centre (the ray
// image_maps.comp cast), from 0 to its stored surface point (1e-4 of the
// distance beyond, for rounding) or to infinity where it saw nothing, is
// tested against the box of the triangles that moved (their old and new
// positions, touch.box_min/max). Only a texel whose ray crosses the box can
// have another first surface in the new pose (a moved triangle left it or
// entered it); a map with none keeps its texels exactly. Layout:
// shared/pb_image_maps.h.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_image_maps.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_IMAGE_BIND_MAPS) readonly buffer Maps {
  pb_gpu_image_maps_info im_info;
  pb_gpu_image_map im_maps[];
};
layout(std430, set = 0, binding = PB_IMAGE_BIND_TEXELS) readonly buffer Texels { pb_gpu_image_texel im_texels[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_COUNTS) buffer Touch { pb_gpu_image_touch touch; };
layout(push_constant) uniform Push { pb_gpu_image_maps_push pc; };

#define PB_INF uintBitsToFloat(0x7f800000u)
#include "common/image_maps.glsl"  // the cube layout (pb_cube_dir)

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  uint per_map = 6u * pc.resolution * pc.resolution;
  if (gid >= pc.map_count * per_map) return;
  uint m = pc.first_map + gid / per_map, idx = gid % per_map;
  if (touch.touched[m] != 0u) return;  // already known (a racy read: at worst a redundant test)
  vec3 c = im_maps[m].center;
  vec3 dir = pb_cube_dir(idx, pc.resolution);
  pb_gpu_image_texel tx = im_texels[im_maps[m].first + idx];
  float tmax = tx.prim == PB_GPU_MISS ? PB_INF : length(tx.position - c) * (1.0 + 1e-4) + 1e-6;
  // Slab test of the segment [0, tmax] (IEEE: 1 / 0 = inf keeps a ray
  // parallel to a slab inside or outside it).
  vec3 inv = 1.0 / dir;
  vec3 ta = (touch.box_min - c) * inv, tb = (touch.box_max - c) * inv;
  vec3 tn = min(ta, tb), tf = max(ta, tb);
  float t0 = max(max(max(tn.x, tn.y), tn.z), 0.0);
  float t1 = min(min(min(tf.x, tf.y), tf.z), tmax);
  if (t0 <= t1) touch.touched[m] = 1u;
}
