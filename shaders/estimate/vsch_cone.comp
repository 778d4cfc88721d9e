// View-sample cluster hierarchy (seed 004 4.5, Fig. 4), pass 6: the normal
// cone of each cluster: its axis is the mean of its samples' normals (the
// integer sum vsch_leaf left), its half-angle alpha the largest angle
// between a sample's normal and the axis (atomic max of a non-negative
// float as uint bits).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
#include "common/vsch.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= vp.pixels) return;
  uint pw = vp.pixel_off + gid * PB_VSCH_PIXEL_WORDS;
  uint leaf = vd[pw];
  if (leaf == PB_VSCH_NONE) return;
  vec3 n = vec3(uintBitsToFloat(vd[pw + 2u]), uintBitsToFloat(vd[pw + 3u]), uintBitsToFloat(vd[pw + 4u]));
  float dev = acos(clamp(dot(n, pb_node_axis(leaf, 0u)), -1.0, 1.0));
  if (isnan(dev)) dev = PB_VSCH_PI;
  atomicMax(vd[pb_node_word(leaf, 11u)], floatBitsToUint(dev));
}
