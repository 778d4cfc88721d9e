#version 450
// Screen-space splatting, pass 1 of 3 (seed 001 24.2.1 and 24.3.1.1): one
// thread per stored photon. Photons whose surface normal faces away from
// the camera, or that lie behind the near plane (or past the far one), are
// culled; a photon whose position projects into the image adds one to the
// counter of its screen tile ("We apply the simple approximation of
// maintaining a counter for each screen-space tile. When a photon is
// deposited in a tile, the counter is atomically incremented"), n_p of
// eq. 5. The counters are zero on entry (splat_resolve.comp clears them
// after every sample; the host once when they are made).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_splat.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_BIND_FRAME) readonly buffer FrameBuf { pb_gpu_frame frame; };
#include "common/camera.glsl"
#include "common/splat.glsl"

void main() {
  uint i = pb_splat_gid();
  if (i >= pb_splat_stored()) return;
  pb_gpu_photon p = photons[i];
  vec2 px;
  float z;
  uint c = pb_splat_cull(p, px, z);
  if (c == 0u) atomicAdd(tiles[pb_splat_tile(px)], 1u);
  if ((sp.flags & PB_SPLAT_STATS) != 0u) {
    atomicAdd(stats.stored, 1u);
    if (c == 0u) atomicAdd(stats.counted, 1u);
    else if (c == 1u) atomicAdd(stats.off_screen, 1u);
    else if (c == 2u) atomicAdd(stats.back_facing, 1u);
    else atomicAdd(stats.outside, 1u);
  }
}
