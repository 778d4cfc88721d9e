#version 450
// Pass 2 of a sample: direct light at the G-buffer's surface from every
// point, spot and directional light, one shadow ray (any hit) each, with the
// reference's BSDF (smooth lobes). Added to beauty, and to the direct AOV
// when the surface is the first hit (one scattering event).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#include "common/scene.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  pb_bsdf b = pb_bsdf_setup(surf, g.wo);
  vec3 o_shadow = pb_offset_ray(surf.p, surf.ng);
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < frame.light_count; ++i) {
    vec3 wi, Li;
    float dist;
    if (!pb_delta_light_at(lights[i], surf.p, wi, dist, Li)) continue;
    vec3 f = pb_bsdf_eval(b, g.wo, wi);
    if (all(equal(f, vec3(0.0)))) continue;
    float t, u, v;
    if (pb_trace(o_shadow, wi, 0.0, dist, true, t, u, v) != PB_GPU_MISS) continue;
    sum += f * Li * abs(dot(wi, b.n));
  }
  vec3 c = g.throughput * sum;
  pb_gpu_accum acc = accum[gid];
  acc.beauty.rgb += c;
  if (g.chain == 0u) acc.direct += c;
  accum[gid] = acc;
}
