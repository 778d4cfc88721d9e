#version 450
// Rays against the environment maps (tests, benchmark): one ray per
// invocation through the image-space search of common/image_maps.glsl, the
// same code the images build of photon_trace.comp runs. hits[i]: t the
// distance along the ray to the accepted point (PB_INF otherwise), prim its
// texel's triangle (PB_GPU_MISS otherwise), u the outcome (PB_IMAGE_TYPE_*,
// as a float), v the texel index (as a float, exact below 2^24).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_image_maps.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_IMAGE_BIND_MAPS) readonly buffer Maps {
  pb_gpu_image_maps_info im_info;
  pb_gpu_image_map im_maps[];
};
layout(std430, set = 0, binding = PB_IMAGE_BIND_TEXELS) readonly buffer Texels { pb_gpu_image_texel im_texels[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_RAYS) readonly buffer Rays { pb_gpu_ray rays[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_HITS) writeonly buffer Hits { pb_gpu_hit hits[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_COUNTS) buffer Counts { pb_gpu_image_counts counts; };
layout(push_constant) uniform Push { pb_gpu_image_maps_push pc; };

#define PB_INF uintBitsToFloat(0x7f800000u)
#include "common/image_maps.glsl"

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (gid >= pc.ray_count) return;
  pb_gpu_ray ray = rays[gid];
  float t;
  uint tex, nb, nc;
  uint ty = pb_image_intersect(ray.org, ray.dir, t, tex, nb, nc);
  atomicAdd(counts.segments, 1u);
  if (nb > 0u) atomicAdd(counts.type_b, nb);
  if (nc > 0u) atomicAdd(counts.type_c, nc);
  pb_gpu_hit h;
  h.t = PB_INF;
  h.prim = PB_GPU_MISS;
  h.u = float(ty);
  h.v = float(tex);
  if (ty == PB_IMAGE_TYPE_D) {
    atomicAdd(counts.hits, 1u);
    h.t = t;
    h.prim = im_texels[tex].prim;
  } else if (ty == PB_IMAGE_TYPE_B) {
    atomicAdd(counts.misses, 1u);
  } else {
    atomicAdd(counts.escapes, 1u);
  }
  hits[gid] = h;
}
