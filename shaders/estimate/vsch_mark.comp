// View-sample cluster hierarchy (seed 004 4.1, Fig. 3 left), pass 3: each
// sample finds its cell of the view-space grid, its screen tile and depth
// slice, and marks the slice occupied in the tile's mask. The slices are
// log-spaced in the distance from the camera from the band's nearest
// sample: ratio 1 + (the tile's angular size), so that a cell is about as
// deep as it is wide ("roughly cubical boxes"), coarser where the band's
// depth range needs more than PB_VSCH_SLICES of those (derived: the paper
// leaves the grid to Sintorn et al. 2014).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
#define PB_VSCH_DATA_BINDING PB_VSCH_BIND_DATA
layout(std430, set = 0, binding = PB_VSCH_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
#include "common/vsch.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= vp.pixels) return;
  uint pw = vp.pixel_off + gid * PB_VSCH_PIXEL_WORDS;
  pb_gpu_gbuffer g = gbuffer[gid];
  float d = length(g.position - frame.cam.position);
  if (g.prim == PB_GPU_MISS || isinf(d) || isnan(d)) {
    vd[pw] = PB_VSCH_NONE;
    vd[pw + 1u] = PB_VSCH_NONE;
    return;
  }
  float near = max(pb_unord(vd[PB_VSCH_H_NEAR]), 1e-9), far = max(pb_unord(vd[PB_VSCH_H_FAR]), near);
  float tile_angle = frame.cam.orthographic != 0u
                         ? 0.0
                         : float(PB_VSCH_TILE) * abs(frame.cam.dx) * length(frame.cam.right) / max(length(frame.cam.forward), 1e-30);
  float range = log(far / near);
  float step = max(log(1.0 + tile_angle), range / float(PB_VSCH_SLICES) * 1.0001);
  uint slice = step > 0.0 ? min(uint(max(log(max(d, near) / near) / step, 0.0)), PB_VSCH_SLICES - 1u) : 0u;
  uint width = max(frame.width, 1u);
  uint x = gid % width, y = gid / width;
  uint tile = (y / PB_VSCH_TILE) * vd[PB_VSCH_H_NX + 1u] + x / PB_VSCH_TILE;
  atomicOr(vd[pb_node_word(vp.level_base[1] + tile, 6u)], 1u << slice);
  vd[pw + 1u] = tile * PB_VSCH_SLICES + slice;
}
