#version 450
// Renders the environment maps of the image-space photon tracer (seed 003
// section 3: "the surrounding objects are rendered to the six faces of a
// cube map ... [holding] the positions, normals and material indices"): one
// invocation per texel of maps first_map .. first_map + map_count - 1, the
// ray from the map's centre through the texel's centre cast against the
// scene BVH (common/bvh.glsl, the existing GPU ray casting in place of the
// paper's rasteriser). Layout: shared/pb_image_maps.h.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_image_maps.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#ifdef PB_RAY_QUERY
layout(set = 0, binding = PB_IMAGE_BIND_NODES) uniform accelerationStructureEXT pb_tlas; // the scene's (gpu/accel.c)
#else
layout(std430, set = 0, binding = PB_IMAGE_BIND_NODES) readonly buffer Nodes { vec4 bvh_nodes4[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_TRIS) readonly buffer Tris { vec4 bvh_tris4[]; };
#endif
layout(std430, set = 0, binding = PB_IMAGE_BIND_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_POSITIONS) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_TRI_MATERIAL) readonly buffer TriMat { uint tri_material[]; };
layout(std430, set = 0, binding = PB_IMAGE_BIND_MAPS) readonly buffer Maps {
  pb_gpu_image_maps_info im_info;
  pb_gpu_image_map im_maps[];
};
layout(std430, set = 0, binding = PB_IMAGE_BIND_TEXELS) buffer Texels { pb_gpu_image_texel im_texels[]; };
layout(push_constant) uniform Push { pb_gpu_image_maps_push pc; };

#include "common/bvh.glsl"
#include "common/image_maps.glsl"  // the cube layout (pb_cube_dir)

vec3 pb_vertex(uint i) { return vec3(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]); }

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  uint per_map = 6u * pc.resolution * pc.resolution;
  if (gid >= pc.map_count * per_map) return;
  uint m = pc.first_map + gid / per_map, idx = gid % per_map;
  vec3 c = im_maps[m].center;
  vec3 dir = pb_cube_dir(idx, pc.resolution);
  float t, u, v;
  uint prim = pb_trace(c, dir, 0.0, PB_INF, false, t, u, v);
  pb_gpu_image_texel tx;
  tx.prim = prim;
  tx.position = vec3(0.0);
  tx.normal = vec3(0.0, 0.0, 1.0);
  tx.material = 0u;
  if (prim != PB_GPU_MISS) {
    tx.position = c + t * dir;
    vec3 p0 = pb_vertex(indices[3u * prim]), p1 = pb_vertex(indices[3u * prim + 1u]),
         p2 = pb_vertex(indices[3u * prim + 2u]);
    vec3 n = cross(p1 - p0, p2 - p0);
    float l = length(n);
    tx.normal = l > 0.0 ? n / l : -dir;
    tx.material = tri_material[prim];
  }
  im_texels[im_maps[m].first + idx] = tx;
}
