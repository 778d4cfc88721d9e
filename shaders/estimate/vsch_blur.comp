// View-sample cluster hierarchy, directional variant (seed 004 4.7): "we
// store only the irradiance in a texture, and apply a depth- and
// normal-aware blur filter to that texture. The blurred irradiance is then
// multiplied by the diffuse BRDF in the final shading stage." The paper
// gives no kernel; derived here: a (2 R + 1)^2 box over the band's pixels,
// R = PB_VSCH_TILE / 2 (the clusters' blocks are a tile wide), weighted by
// max(0, n . n')^8 and exp(-(dz / (0.02 z))^2) with z the view depth, so
// that it stops at creases and depth edges; the result times the factor
// vsch_shade left (f(wo, n_s) times the throughput) is added to the
// indirect sum and the beauty.
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
layout(std430, set = 0, binding = PB_VSCH_SHADE_BIND_ACCUM) buffer PhotonAccum { pb_gpu_photon_accum paccum[]; };

vec3 word3(uint w) { return vec3(uintBitsToFloat(vd[w]), uintBitsToFloat(vd[w + 1u]), uintBitsToFloat(vd[w + 2u])); }

void main() {
  uint gid = pb_gid();
  if (gid >= vp.pixels) return;
  uint pw = vp.pixel_off + gid * PB_VSCH_PIXEL_WORDS;
  if (vd[pw] == PB_VSCH_NONE) return;
  int width = int(max(frame.width, 1u));
  int rows = int((vp.pixels + uint(width) - 1u) / uint(width));
  int x = int(gid) % width, y = int(gid) / width;
  vec3 n = word3(pw + 2u);
  float z = abs(uintBitsToFloat(vd[pw + 7u]));
  const int R = int(PB_VSCH_TILE) / 2;
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (int dy = -R; dy <= R; ++dy)
    for (int dx = -R; dx <= R; ++dx) {
      int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= width || yy >= rows) continue;
      uint j = uint(yy * width + xx);
      if (j >= vp.pixels) continue;
      uint qw = vp.pixel_off + j * PB_VSCH_PIXEL_WORDS;
      if (vd[qw] == PB_VSCH_NONE) continue;
      float cn = max(dot(n, word3(qw + 2u)), 0.0);
      float dz = (abs(uintBitsToFloat(vd[qw + 7u])) - z) / max(0.02 * z, 1e-12);
      float w = pow(cn, 8.0) * exp(-dz * dz);
      if (!(w > 0.0)) continue;
      sum += w * word3(qw + 8u);
      wsum += w;
    }
  if (!(wsum > 0.0)) return;
  vec3 l = sum / wsum * word3(pw + 11u);
  if (any(isnan(l)) || any(isinf(l))) return;
  pb_gpu_photon_accum pa = paccum[gid];
  pa.indirect.xyz += l;
  paccum[gid] = pa;
  if ((vp.flags & PB_VSCH_NO_BEAUTY) == 0u) {
    pb_gpu_accum acc = accum[gid];
    acc.beauty.rgb += l;
    accum[gid] = acc;
  }
}
