// View-sample cluster hierarchy (seed 004 4.1, 4.5), pass 5: each sample
// joins its cluster (the rank of its slice in its tile's mask, after the
// tile's first cluster from vsch_scan): the box grows to its view-space
// position, the samples and the normal sum (integers, x 2^16) by its
// geometric normal (facing the eye, as the gather's same-side test uses).
// The sample's cluster, normal and view position are kept per pixel.
// Also the edges of the sample's face within pb_vsch_edge_reach() (where a wall
// stands: common/kernel_edges.glsl, as knn.comp and the gather find them):
// the nearest one's in-plane distance per pixel (vsch_shade looks for the
// edges again only where there is one) and its minimum over the cluster
// (node word 15, propagated up by vsch_up), which the traversal's
// cluster-trivial acceptance needs: a photon whose sphere of radius r
// encloses a node may lie beyond an edge of a sample's face (the floor
// outside a closed block seen from the floor inside it: a thin wall between
// them), and its flux is only the node's where no sample has an edge within
// 2 r (derived: the paper's scenes have no such walls).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"
layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
#define PB_VSCH_DATA_BINDING PB_VSCH_SHADE_BIND_DATA
#include "common/vsch.glsl"
#include "common/kernel_edges.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= vp.pixels) return;
  uint pw = vp.pixel_off + gid * PB_VSCH_PIXEL_WORDS;
  uint ts = vd[pw + 1u];
  if (ts == PB_VSCH_NONE) {
    vd[pw] = PB_VSCH_NONE;
    return;
  }
  pb_gpu_gbuffer g = gbuffer[gid];
  uint tile = ts / PB_VSCH_SLICES, slice = ts % PB_VSCH_SLICES;
  uint tg = vp.level_base[1] + tile;
  uint mask = vd[pb_node_word(tg, 6u)];
  uint leaf = vd[pb_node_word(tg, 14u)] + uint(bitCount(mask & ((1u << slice) - 1u)));
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  vec3 n = surf.ng;
  vec3 v = pb_to_view(g.position);
  vd[pw] = leaf;
  vd[pw + 2u] = floatBitsToUint(n.x), vd[pw + 3u] = floatBitsToUint(n.y), vd[pw + 4u] = floatBitsToUint(n.z);
  vd[pw + 5u] = floatBitsToUint(v.x), vd[pw + 6u] = floatBitsToUint(v.y), vd[pw + 7u] = floatBitsToUint(v.z);
  uint b = pb_node_word(leaf, 0u);
  for (uint k = 0u; k < 3u; ++k) {
    atomicMin(vd[b + k], pb_ord(v[k]));
    atomicMax(vd[b + 3u + k], pb_ord(v[k]));
  }
  atomicAdd(vd[b + 7u], 1u);
  vec3 edge_dir[PB_EDGES_MAX];
  float edge_dist[PB_EDGES_MAX];
  uint edges = pb_edges_find(surf.p, n, pb_vsch_edge_reach(), edge_dir, edge_dist);
  float dmin = uintBitsToFloat(0x7f800000u);
  for (uint j = 0u; j < edges; ++j) dmin = min(dmin, max(edge_dist[j], 0.0));
  vd[pw + 14u] = floatBitsToUint(dmin);
  atomicMin(vd[b + 15u], floatBitsToUint(dmin)); // non-negative floats: uint order
  ivec3 q = ivec3(round(n * 65536.0));
  atomicAdd(vd[b + 8u], uint(q.x));
  atomicAdd(vd[b + 9u], uint(q.y));
  atomicAdd(vd[b + 10u], uint(q.z));
}
