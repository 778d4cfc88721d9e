#version 450
// Edge-avoiding A-Trous filter of the indirect irradiance (seed 001 24.4.2,
// after Dammertz et al. 2010 and Schied et al. 2017), one pass per call:
//
// INIT: s_0 = indirect radiance / albedo (the irradiance-like signal the
//   paper filters; eq. 19 multiplies the BRDF back at the end), detail = 0.
// STEP (i = 0 .. n-1, taps 2^i pixels apart): the 5 x 5 cross-bilateral
//   filter of eq. 14-15,
//     s_{i+1}(P) = sum_Q h(Q) w(P,Q) s_i(Q) / sum_Q h(Q) w(P,Q),
//   h = (1/8, 1/4, 1/2, 1/4, 1/8) per axis (the chapter's kernel as printed;
//   the weights are normalised, so only their ratios matter),
//   w = w_z w_n with (eq. 10) w_z = exp(-|z(P) - z(Q)| /
//   (sigma_z |grad z(P) . (P - Q)| + eps)) and (eq. 11)
//   w_n = max(0, n(P) . n(Q))^sigma_n; and the detail coefficient
//   d_i = s_i - s_{i+1} (eq. 16) clipped to +-b_i, b_i = gamma sigma_i(P),
//   sigma_i the standard deviation of s_i over the same weighted taps
//   (variance clipping, eq. 18), added to the detail sum; after temporal
//   accumulation b_i = gamma sqrt(L) sigma_i (L: history length, atrous.h).
// FINISH: E = s_n + sum_i clamp(d_i, -b_i, b_i) (eq. 18), indirect =
//   E x albedo (eq. 19).
// Pixels without a surface (depth 0) pass through unchanged.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
layout(std430, set = 0, binding = PB_ATROUS_BIND_S) buffer S { vec4 s[]; };
layout(std430, set = 0, binding = PB_ATROUS_BIND_DETAIL) buffer Detail { vec4 detail[]; };
layout(std430, set = 0, binding = PB_ATROUS_BIND_GEO) readonly buffer Geo { vec4 geo[]; };
layout(std430, set = 0, binding = PB_ATROUS_BIND_INDIRECT) buffer Indirect { vec4 indirect[]; };
layout(std430, set = 0, binding = PB_ATROUS_BIND_ALBEDO) readonly buffer Albedo { vec4 albedo[]; };
layout(push_constant) uniform Push { pb_gpu_atrous_push push; };

const float PB_ALBEDO_MIN = 1e-3;

vec3 pb_demod(vec3 a) { return max(a, vec3(PB_ALBEDO_MIN)); }

float pb_depth(int x, int y) {
  x = clamp(x, 0, int(push.width) - 1);
  y = clamp(y, 0, int(push.height) - 1);
  return geo[uint(y) * push.width + uint(x)].w;
}

float pb_grad(float z, float z0, float z1) {
  float b = z0 > 0.0 ? z - z0 : 1e30, f = z1 > 0.0 ? z1 - z : 1e30;
  float g = abs(b) < abs(f) ? b : f;
  return abs(g) < 1e29 ? g : 0.0;
}

// w_n = max(0, n_P . n_Q)^sigma_n: sigma_n = 32 (the chapter's) by five
// squarings, far cheaper than pow() on CPU devices; other values by pow().
float pb_normal_weight(float c) {
  c = max(0.0, c);
  if (push.sigma_n == 32.0) {
    c *= c;
    c *= c;
    c *= c;
    c *= c;
    return c * c;
  }
  return pow(c, push.sigma_n);
}

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  uint n = push.width * push.height;
  if (gid >= n) return;
  vec4 gp = geo[gid];
  if (push.mode == PB_ATROUS_INIT) {
    s[gid] = vec4(indirect[gid].rgb / pb_demod(albedo[gid].rgb), 0.0);
    detail[gid] = vec4(0.0);
    return;
  }
  uint src = push.src_half * n, dst = (1u - push.src_half) * n;
  if (push.mode == PB_ATROUS_FINISH) {
    if (gp.w > 0.0) indirect[gid].rgb = max(s[src + gid].rgb + detail[gid].rgb, vec3(0.0)) * pb_demod(albedo[gid].rgb);
    return;
  }
  vec3 sp = s[src + gid].rgb;
  if (!(gp.w > 0.0)) {
    s[dst + gid] = vec4(sp, 0.0);
    return;
  }
  int x = int(gid % push.width), y = int(gid / push.width);
  // Screen-space depth gradient at P: per axis the smaller of the forward
  // and backward differences (a depth step next to P then reads as P's own
  // surface's slope, not as half the step, which would let the filter cross
  // it); neighbours without a surface are ignored.
  float gx = pb_grad(gp.w, pb_depth(x - 1, y), pb_depth(x + 1, y));
  float gy = pb_grad(gp.w, pb_depth(x, y - 1), pb_depth(x, y + 1));
  const float h[5] = float[5](0.125, 0.25, 0.5, 0.25, 0.125);
  vec3 sum = vec3(0.0), sum2 = vec3(0.0);
  float wsum = 0.0;
  int st = int(push.step);
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      int qx = x + i * st, qy = y + j * st;
      if (qx < 0 || qy < 0 || qx >= int(push.width) || qy >= int(push.height)) continue;
      uint q = uint(qy) * push.width + uint(qx);
      vec4 gq = geo[q];
      if (!(gq.w > 0.0)) continue;
      float wz = exp(-abs(gp.w - gq.w) / (push.sigma_z * abs(gx * float(i * st) + gy * float(j * st)) + 1e-4 * gp.w));
      float wn = pb_normal_weight(dot(gp.xyz, gq.xyz));
      float w = h[i + 2] * h[j + 2] * wz * wn;
      vec3 v = s[src + q].rgb;
      sum += w * v;
      sum2 += w * v * v;
      wsum += w;
    }
  vec3 next = wsum > 0.0 ? sum / wsum : sp;
  vec3 mean = next, var = wsum > 0.0 ? max(sum2 / wsum - mean * mean, vec3(0.0)) : vec3(0.0);
  // Clip bound gamma sqrt(L) sigma_i, L the temporal history length carried
  // in the indirect input's w (1 for a single frame; atrous.h; the temporal
  // filter's result writes it there).
  vec3 b = push.gamma * sqrt(max(indirect[gid].w, 1.0)) * sqrt(var);
  s[dst + gid] = vec4(next, 0.0);
  detail[gid].rgb += clamp(sp - next, -b, b);
}
