#version 450
// LBVH pass 0 (one invocation): the build's state from the push constants
// and the map's photon count, read here on the GPU (never by the host), and
// the grids of the passes that follow (pb_gpu_dispatch_indirect).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = 1) in;
#include "common/lbvh.glsl"

uint[4] pb_grid(uint groups) {
  uint x = min(groups, pc.max_groups_x);
  return uint[4](x, x == 0u ? 1u : (groups + x - 1u) / x, 1u, 0u);
}

void main() {
  uint n = (pc.flags & PB_LBVH_COUNT_FROM_MAP) != 0u ? map_counts.stored : pc.host_count;
  n = min(n, pc.capacity);
  uint tiles = (n + PB_LBVH_BOUNDS_TILE - 1u) / PB_LBVH_BOUNDS_TILE;
  info.count = n;
  info.root = PB_LBVH_NONE;
  info.t_auto = 1u;
  info.leaves = 0u;
  info.bmin = uint[3](0xffffffffu, 0xffffffffu, 0xffffffffu);
  info.bmax = uint[3](0u, 0u, 0u);
  info.tiles = tiles;
  info.tiles_done = 0u;
  info.lo = vec3(0.0);
  info.hi = vec3(0.0);
  info.area_sum = 0.0;
  info.scene_area = pc.scene_area;
  info.stack_overflow = 0u;
  info.footprint_scale = pc.footprint_scale;
  info.t_fixed = pc.t_fixed;
  info.t_computed = 0u;
  info.photon_args = pb_grid((n + PB_GPU_WORKGROUP - 1u) / PB_GPU_WORKGROUP);
  info.tile_args = pb_grid(tiles);
}
