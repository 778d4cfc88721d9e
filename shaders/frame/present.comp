#version 450
// The viewer's display pass: one invocation per pixel
// scales the scene-linear AOV by 2^exposure, maps each channel through the
// shaper (node 0 at 0, linear to node 1 at 2^lo, log2-spaced to 2^hi) and
// interpolates the baked OCIO view tetrahedrally (color.h pb_color_lut;
// src/color/display_lut.c is the same arithmetic on the host), then
// encodes 8 bits as pb_png_write_display does (round to nearest, no
// dither: the host path has none), alpha 255. The output word is RGBA8
// with R in the low byte: VK_FORMAT_R8G8B8A8_UNORM's byte order when the
// presenter copies it into its image.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_contract.h"
#include "shared/pb_present.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_PRESENT_BIND_LUT) readonly buffer Lut { vec4 lut[]; };
layout(std430, set = 0, binding = PB_PRESENT_BIND_IN) readonly buffer Src { float src[]; };
layout(std430, set = 0, binding = PB_PRESENT_BIND_OUT) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform PresentPush { pb_gpu_present_push pp; };

float shape(float x) {
  float x0 = exp2(pp.lo), top = float(pp.size - 1u);
  if (!(x > 0.0)) return 0.0; // 0, negative, NaN
  if (x < x0) return x / x0;
  float u = 1.0 + float(pp.size - 2u) * ((log2(x) - pp.lo) / (pp.hi - pp.lo));
  return u < top ? u : top;
}

vec3 node(uint r, uint g, uint b) { return lut[(b * pp.size + g) * pp.size + r].rgb; }

uint to_u8(float x) {
  if (!(x > 0.0)) return 0u;
  if (x >= 1.0) return 255u;
  return uint(x * 255.0 + 0.5);
}

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
  if (i >= pp.pixels) return;
  uint base = pp.offset + i * pp.channels;
  vec3 x = vec3(src[base], src[base + 1u], src[base + 2u]);
  vec3 v;
  if ((pp.flags & PB_PRESENT_DATA) != 0u) {
    v = clamp(pp.data_scale * x + pp.data_bias, 0.0, 1.0);
  } else {
    uvec3 n;
    vec3 f;
    for (int k = 0; k < 3; ++k) {
      float u = shape(x[k] * pp.scale);
      uint c = uint(u);
      if (c > pp.size - 2u) c = pp.size - 2u;
      n[k] = c;
      f[k] = u - float(c);
    }
    float fr = f.x, fg = f.y, fb = f.z;
    uint r = n.x, g = n.y, b = n.z;
    vec3 c000 = node(r, g, b), c111 = node(r + 1u, g + 1u, b + 1u), ca, cb;
    float w0, wa, wb, w1;
    // Tetrahedral, the six cases of display_lut.c in the same order.
    if (fr > fg) {
      if (fg > fb) { ca = node(r + 1u, g, b); cb = node(r + 1u, g + 1u, b); w0 = 1.0 - fr; wa = fr - fg; wb = fg - fb; w1 = fb; }
      else if (fr > fb) { ca = node(r + 1u, g, b); cb = node(r + 1u, g, b + 1u); w0 = 1.0 - fr; wa = fr - fb; wb = fb - fg; w1 = fg; }
      else { ca = node(r, g, b + 1u); cb = node(r + 1u, g, b + 1u); w0 = 1.0 - fb; wa = fb - fr; wb = fr - fg; w1 = fg; }
    } else {
      if (fb > fg) { ca = node(r, g, b + 1u); cb = node(r, g + 1u, b + 1u); w0 = 1.0 - fb; wa = fb - fg; wb = fg - fr; w1 = fr; }
      else if (fb > fr) { ca = node(r, g + 1u, b); cb = node(r, g + 1u, b + 1u); w0 = 1.0 - fg; wa = fg - fb; wb = fb - fr; w1 = fr; }
      else { ca = node(r, g + 1u, b); cb = node(r + 1u, g + 1u, b); w0 = 1.0 - fg; wa = fg - fr; wb = fr - fb; w1 = fb; }
    }
    v = clamp(w0 * c000 + wa * ca + wb * cb + w1 * c111, 0.0, 1.0);
  }
  dst[i] = to_u8(v.x) | (to_u8(v.y) << 8) | (to_u8(v.z) << 16) | (255u << 24);
}
