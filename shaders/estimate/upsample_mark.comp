#version 450
// One level of the multi-level up-sampling of the diffuse photon irradiance
// (seed 003 sec. 6, Figure 9: "incident irradiance is first rendered to a
// small image. Then it is up-sampled to a higher resolution ... like the
// reverse of a mip-map generation process"; src/render/estimate/upsample.c orders the
// levels). Level l holds the pixels at x, y multiples of s = 2^l. At the
// coarse level L every such pixel with a diffuse surface is queued for the
// estimate (gather_upsample, PB_GATHER_UPS_LIST). At a finer level each new
// pixel (a multiple of s, not of 2s in both axes) takes the corners of its
// cell of the level above (x0 = x - x mod 2s, x1 = x0 + 2s where x is not a
// multiple of 2s; y alike: 1, 2 or 4 samples at the bilinear weights 1, 1/2,
// 1/4), and
//   interpolates  E = sum_c w_c E_c / sum_c w_c   where every corner agrees
//                 with the pixel's own surface (geometry-aware: the normal and
//                 the plane test below gate the bilinear weights);
//   is queued     for the estimate at this level otherwise ("places with
//                 high-frequency illumination such as corners are recomputed
//                 at higher resolution"), and so is one whose corner had no
//                 diffuse estimate (a miss, a Blender material). Its estimate
//                 is then a corner for the level below, so the recomputation
//                 follows edges and corners down to full resolution.
// Corners outside the band are left out (clamp to the edge): the last row and
// column of a grid that does not divide the image take the samples they have.
//
// Thresholds (G-buffer n_s facing the eye, p the surface point):
//   normal  n_p . n_c >= PB_UPS_COS_NORMAL = cos 18.2 deg. Irradiance under
//           one dominant direction a goes as E0 cos(theta - a) along the normal
//           angle theta; linear interpolation between normals dtheta apart
//           errs by at most max|E''| dtheta^2 / 8 <= E0 dtheta^2 / 8, 1.2 % at
//           dtheta = 0.318 rad, inside the 2 % the tests allow. Walls meeting
//           at a corner (90 deg) and creases over 18 deg are recomputed.
//   plane   |n_c . (p - p_c)| <= PB_UPS_PLANE |p - p_c|, PB_UPS_PLANE = 0.31:
//           a smooth surface of radius R between points d apart bends its
//           normal by d / R <= 0.318 (the normal test) and leaves its tangent
//           plane by d^2 / (2R), a share (d / R) / 2 <= 0.16 of d, so any
//           share over 0.31 (twice that) is a depth step or a fold the
//           normals do not show: a surface in front of another, an occluder's
//           silhouette. Both are relative, so they hold at any scene scale.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_upsample.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
#include "common/scene.glsl"

layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_UPS_BIND_IRR) buffer UpsIrr { vec4 ups_irr[]; };
layout(std430, set = 0, binding = PB_UPS_BIND_LIST) buffer UpsList { uint ups_list[]; };
layout(push_constant) uniform UpsPush { pb_gpu_upsample_push up; };

const float PB_UPS_COS_NORMAL = 0.95;
const float PB_UPS_PLANE = 0.31;

void pb_ups_queue(uint pix) {
  ups_irr[pix] = vec4(0.0, 0.0, 0.0, float(PB_UPS_NONE));
  uint i = atomicAdd(ups_list[PB_UPS_H_QUEUED + up.level], 1u);
  ups_list[PB_UPS_HEADER_WORDS + i] = pix;
}

void main() {
  uint gid = pb_gid();
  uint w = frame.width, rows = frame.pixel_count / max(frame.width, 1u);
  uint s = 1u << up.level;
  uint gw = (w + s - 1u) / s, gh = (rows + s - 1u) / s;
  if (gid >= gw * gh) return;
  uint x = (gid % gw) * s, y = (gid / gw) * s;
  bool coarse = up.level >= up.levels;
  uint s2 = 2u * s;
  if (!coarse && x % s2 == 0u && y % s2 == 0u) return; // a pixel of the level above
  uint pix = y * w + x;
  pb_gpu_gbuffer g = gbuffer[pix];
  // No diffuse irradiance here: a miss, or a Blender material (its closures
  // are estimated at full resolution, PB_GATHER_UPS_REST).
  if (g.prim == PB_GPU_MISS || g.lobes != 0u) {
    ups_irr[pix] = vec4(0.0, 0.0, 0.0, float(PB_UPS_NONE));
    return;
  }
  if (coarse) {
    pb_ups_queue(pix);
    return;
  }
  uint x0 = x - x % s2, y0 = y - y % s2;
  bool xs = x % s2 != 0u, ys = y % s2 != 0u; // x (y) between two columns (rows) of the level above
  pb_surface sp = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  vec3 e = vec3(0.0);
  float wsum = 0.0;
  bool agree = true;
  for (uint k = 0u; k < 4u && agree; ++k) {
    bool kx = (k & 1u) != 0u, ky = (k & 2u) != 0u;
    if ((kx && !xs) || (ky && !ys)) continue;
    uint cx = kx ? x0 + s2 : x0, cy = ky ? y0 + s2 : y0;
    if (cx >= w || cy >= rows) continue; // outside the band: clamp to the edge
    uint c = cy * w + cx;
    vec4 ir = ups_irr[c];
    if (ir.w == float(PB_UPS_NONE)) {
      agree = false;
      break;
    }
    pb_gpu_gbuffer gc = gbuffer[c];
    pb_surface sc = pb_surface_from_hit(gc.prim, gc.u, gc.v, -gc.wo);
    vec3 d = sp.p - sc.p;
    if (dot(sp.ns, sc.ns) < PB_UPS_COS_NORMAL || abs(dot(sc.ns, d)) > PB_UPS_PLANE * length(d)) {
      agree = false;
      break;
    }
    float wk = (xs ? 0.5 : 1.0) * (ys ? 0.5 : 1.0);
    e += wk * ir.xyz;
    wsum += wk;
  }
  if (agree && wsum > 0.0) {
    ups_irr[pix] = vec4(e / wsum, float(PB_UPS_INTERPOLATED));
    atomicAdd(ups_list[PB_UPS_H_INTERPOLATED + up.level], 1u);
  } else {
    pb_ups_queue(pix);
  }
}
