#version 450
// Temporal filter of the indirect irradiance (seed 001 24.4.1, after Karis's
// TAA applied to irradiance), one invocation per pixel P:
//
//   E~_i(P) = (1 - alpha) E_i(P) + alpha E~_{i-1}(Q)              (eq. 12)
//   alpha   = 0.95 w_z(P,Q) w_n(P,Q)                              (eq. 13)
//
// E_i = indirect radiance / albedo, demodulated exactly as the A-Trous does
// (atrous.comp), so the two filters see the same signal. Q is where P's
// surface point was in the previous frame (the motion buffer, from the
// first hit of the pixel-centre ray: src/render/scene/motion.c). E~_{i-1} is read
// at Q bilinearly, and the edge-stopping weights are evaluated per tap
// against the previous frame's G-buffer (eq. 10 with P's depth gradient
// times the one-pixel reach of the bilinear footprint, against P's depth
// as seen from the previous camera; eq. 11 with sigma_n = 32): a tap whose
// surface is not P's surface drops out, and w = sum of bilinear x w_z x w_n
// over the taps is the w_z w_n of eq. 13. History taps off-screen or
// without a surface count as weight 0, so a disocclusion (w -> 0) resets
// the pixel to this frame's value: no ghosting.
//
// Two departures, both in the direction of the chapter's intent:
//  * A per-pixel history length L (the w channel; L = 1 / (1 - alpha), the
//    frames the average spans) caps alpha at L / (L + 1) while the history
//    is young, so the first frames after a reset average equally (a
//    cumulative mean) instead of starting at 95 % weight on one frame.
//  * With `still` (camera and scene unchanged since the previous frame)
//    alpha = w L / (L + 1) with no 0.95 cap: the cumulative mean of every
//    frame so far, i.e. progressive rendering, so a still view converges
//    (to the estimator's expectation) instead of plateauing at the
//    variance of a 0.95 moving average.
//  * A still run averages the radiance itself, not E times this frame's
//    albedo: its frames jitter their samples in the pixel, so where a pixel
//    straddles two materials the albedo a sample meets changes from frame
//    to frame, and the running mean of E re-modulated by one frame's albedo
//    would keep that frame's edge at full weight (a still view's edges, a
//    large share of a small viewport, never converged: 1/sqrt(2k) expected
//    between frames k and 2k, a third of that fall measured). Its history
//    is kept in radiance form, marked by a negative length; a moving frame
//    reading it divides by its pixel's albedo (the run's end, once).
// The history written for the next frame is E~_i itself, before the
// spatial filter: feeding the A-Trous output back would compound its blur
// frame after frame, and a still view would converge to the blurred image.
// The frame's result (binding 7) is E~_i times the albedo, demodulated as
// above (the radiance the A-Trous and the compose read, on the GPU), with L
// in w; each workgroup adds its counts and its sum of L to the statistics
// (binding 8, pb_gpu_temporal_stats), so no history leaves the GPU.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_HIST_IN) readonly buffer HistIn { vec4 hist_in[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_GEO_PREV) readonly buffer GeoPrev { vec4 geo_prev[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_GEO) readonly buffer GeoCur { vec4 geo[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_INDIRECT) readonly buffer Indirect { vec4 indirect[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_ALBEDO) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_MOTION) readonly buffer Motion { vec4 motion[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_HIST_OUT) writeonly buffer HistOut { vec4 hist_out[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_RESULT) writeonly buffer Result { vec4 result[]; };
layout(std430, set = 0, binding = PB_TEMPORAL_BIND_STATS) buffer Stats { pb_gpu_temporal_stats stats; };
layout(push_constant) uniform Push { pb_gpu_temporal_push push; };

const float PB_ALBEDO_MIN = 1e-3;

vec3 pb_demod(vec3 a) { return max(a, vec3(PB_ALBEDO_MIN)); }

float pb_depth(int x, int y) {
  x = clamp(x, 0, int(push.width) - 1);
  y = clamp(y, 0, int(push.height) - 1);
  return geo[uint(y) * push.width + uint(x)].w;
}

// The smaller one-sided difference (as atrous.comp): a depth step next to P
// reads as P's own slope.
float pb_grad(float z, float z0, float z1) {
  float b = z0 > 0.0 ? z - z0 : 1e30, f = z1 > 0.0 ? z1 - z : 1e30;
  float g = abs(b) < abs(f) ? b : f;
  return abs(g) < 1e29 ? g : 0.0;
}

// Filters pixel gid; returns its new history length L, or -1 without a surface.
float pb_filter_pixel(uint gid) {
  vec4 gp = geo[gid];
  vec3 a = pb_demod(albedo[gid].rgb);
  vec3 e = indirect[gid].rgb / a;
  bool surface = gp.w > 0.0;
  if (!surface && push.still == 0u) {  // no surface: nothing to filter, no history
    hist_out[gid] = vec4(e, 0.0);
    result[gid] = vec4(indirect[gid].rgb, 0.0);
    return -1.0;
  }
  vec3 hist = vec3(0.0);
  float len = 0.0, w = 0.0;
  vec4 mv = motion[gid];
  if (push.still != 0u) {
    // Nothing moved: the history is this pixel's own, in radiance form (a
    // history from a moving frame, in irradiance form, times this frame's
    // albedo). No edge-stopping: the still frames of a sequence jitter their
    // samples in the pixel, and the differences that makes in depth and
    // normal are anti-aliasing, not disocclusion. Nor is a sample that
    // missed every surface: at a silhouette against the world the pixel's
    // mean goes on with this frame's radiance (none), so it converges to
    // the box-filtered pixel; resetting it there (1.5 % of cornell_box's
    // pixels every frame at 64 px) kept those pixels at one frame's noise.
    // A pixel that never had a surface has no history (L = 0); a history
    // in irradiance form met where this frame has no surface is this
    // frame's alone.
    vec3 rad = indirect[gid].rgb;
    if (push.has_history != 0u) {
      vec4 h = hist_in[gid];
      len = abs(h.w);
      hist = h.w < 0.0 ? h.rgb : h.rgb * a;
      w = len > 0.0 && (surface || h.w < 0.0) ? 1.0 : 0.0;
    }
    float alpha_s = w * len / (len + 1.0);
    if (len >= push.max_history) alpha_s = w * push.max_history / (push.max_history + 1.0);
    vec3 filtered_s = max((1.0 - alpha_s) * rad + alpha_s * hist, vec3(0.0));  // eq. 12, radiance
    float len_s = 1.0 / (1.0 - alpha_s);
    hist_out[gid] = vec4(filtered_s, -len_s);
    result[gid] = vec4(filtered_s, len_s);
    return surface ? len_s : -1.0;  // the statistics count surface pixels
  } else if (push.has_history != 0u && mv.w > 0.0) {
    int x = int(gid % push.width), y = int(gid / push.width);
    float gx = pb_grad(gp.w, pb_depth(x - 1, y), pb_depth(x + 1, y));
    float gy = pb_grad(gp.w, pb_depth(x, y - 1), pb_depth(x, y + 1));
    float zq = mv.z;  // P's surface point's depth seen from the previous camera
    float tol = push.sigma_z * (abs(gx) + abs(gy)) + 1e-3 * zq;
    // Bilinear taps around Q in pixel-index space (centres at integers).
    vec2 q = vec2(float(x) + mv.x, float(y) + mv.y);
    vec2 qf = floor(q);
    vec2 f = q - qf;
    ivec2 q0 = ivec2(qf);
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 1; ++i) {
        float bil = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
        int tx = q0.x + i, ty = q0.y + j;
        if (bil <= 0.0 || tx < 0 || ty < 0 || tx >= int(push.width) || ty >= int(push.height)) continue;
        uint t = uint(ty) * push.width + uint(tx);
        vec4 gq = geo_prev[t];
        if (!(gq.w > 0.0)) continue;
        float wz = exp(-abs(zq - gq.w) / tol);
        float wn = pow(max(0.0, dot(gp.xyz, gq.xyz)), push.sigma_n);
        float wt = bil * wz * wn;
        vec4 h = hist_in[t];
        hist += wt * (h.w < 0.0 ? h.rgb / a : h.rgb);  // a still run's radiance form
        len += wt * abs(h.w);
        w += wt;
      }
    // A history worth less than 0.1 % of a frame is a disocclusion met at a
    // tap with a vanishing bilinear weight (motion a hair off an integer):
    // reset exactly rather than keep a trace of it.
    if (w > 1e-3) {
      hist /= w;
      len /= w;
    } else {
      w = 0.0;
    }
  }
  // Caustics (clamp_gamma > 0): light that moves over a still surface has no
  // motion vector, so the history is also clamped to this frame's 3x3
  // neighbourhood, mean +- clamp_gamma sigma (Salvi's variance clipping in
  // TAA; seed 001 24.4.1 finds colour clipping too loose for noisy
  // irradiance, which is why the indirect light does without it).
  if (push.clamp_gamma > 0.0 && w > 0.0 && push.still == 0u) {
    int x = int(gid % push.width), y = int(gid / push.width);
    vec3 m1 = vec3(0.0), m2 = vec3(0.0);
    float k = 0.0;
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        int qx = x + i, qy = y + j;
        if (qx < 0 || qy < 0 || qx >= int(push.width) || qy >= int(push.height)) continue;
        uint q = uint(qy) * push.width + uint(qx);
        if (!(geo[q].w > 0.0)) continue;
        vec3 c = indirect[q].rgb / pb_demod(albedo[q].rgb);
        m1 += c;
        m2 += c * c;
        k += 1.0;
      }
    vec3 mu = m1 / k, sd = sqrt(max(m2 / k - mu * mu, vec3(0.0)));
    hist = clamp(hist, mu - push.clamp_gamma * sd, mu + push.clamp_gamma * sd);
  }
  float young = len / (len + 1.0);
  float alpha = w * (push.still != 0u ? young : min(push.alpha, young));
  if (push.still != 0u && len >= push.max_history) alpha = w * push.max_history / (push.max_history + 1.0);
  vec3 filtered = max((1.0 - alpha) * e + alpha * hist, vec3(0.0));  // eq. 12
  float len_new = 1.0 / (1.0 - alpha);
  hist_out[gid] = vec4(filtered, len_new);
  result[gid] = vec4(filtered * a, len_new);
  return len_new;
}

shared uint s_surface[PB_GPU_WORKGROUP];
shared uint s_reset[PB_GPU_WORKGROUP];
shared float s_len[PB_GPU_WORKGROUP];

void main() {
  uint gid = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  uint n = push.width * push.height;
  float len = gid < n ? pb_filter_pixel(gid) : -1.0;
  // The statistics: a tree sum over the workgroup, one atomic per word.
  uint lid = gl_LocalInvocationIndex;
  s_surface[lid] = len >= 0.0 ? 1u : 0u;
  s_reset[lid] = len >= 0.0 && len < 1.0001 ? 1u : 0u;
  s_len[lid] = max(len, 0.0);
  barrier();
  for (uint k = PB_GPU_WORKGROUP / 2u; k > 0u; k >>= 1u) {
    if (lid < k) {
      s_surface[lid] += s_surface[lid + k];
      s_reset[lid] += s_reset[lid + k];
      s_len[lid] += s_len[lid + k];
    }
    barrier();
  }
  if (lid == 0u && s_surface[0] > 0u) {
    atomicAdd(stats.surface, s_surface[0]);
    atomicAdd(stats.reset, s_reset[0]);
    // At most 64 x 4097 x 256 < 2^32 per workgroup; the carry into len_hi
    // is exact: the old low word plus q wrapped past 2^32.
    uint q = uint(s_len[0] * float(PB_TEMPORAL_LEN_SCALE) + 0.5);
    uint old = atomicAdd(stats.len_lo, q);
    if (old > 0xffffffffu - q) atomicAdd(stats.len_hi, 1u);
  }
}
