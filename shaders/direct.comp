#version 450
// Pass 2 of a sample: direct light at the G-buffer's surface, with the
// reference's BSDF (smooth lobes):
//  - every point, spot and directional light: one shadow ray (any hit) each;
//  - emissive triangles (SC_EMISSIVE, frame.emitter_count > 0): one emitter
//    picked by power from the host's table (pb_gpu_emitter), a uniform point
//    on it (Shirley's map, as the reference), the solid-angle pdf
//    pick / area * d^2 / cos_l and one shadow ray between the two points,
//    both moved off their surfaces (the reference's segment).
// Added to beauty, and to the direct AOV when the surface is the first hit
// (one scattering event).
//
// Emitters and the reference: src/ref/pathtrace.c combines this light sample
// with the BSDF-sampled continuation that hits an emitter (power heuristic).
// The MIS weights of the two strategies sum to 1 wherever both pdfs are
// positive, and where the BSDF pdf is 0 the light sample's weight is 1, so
// the reference's expectation of once-scattered emitter light is the plain
// integral of f Le |cos| over the emitters' solid angle: exactly what pure
// light sampling estimates here (weight 1, every emitter point with
// Le > 0 has a positive pdf). Only the variance differs. The BSDF-sampled
// continuation is not traced on the GPU, so an emitter hit after a smooth
// bounce is never counted twice (the G-buffer pass counts emission only along
// delta chains, where the reference's weight is 1 too).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#include "common/scene.glsl"

// Random dimensions of the emitter sample (the G-buffer pass uses 0..3+4k
// for small k).
const uint PB_DIM_EMITTER = 0x40000000u;

// Largest i with emitters[i].cdf <= u (emitters[0].cdf == 0).
uint pb_pick_emitter(float u) {
  uint lo = 0u, hi = frame.emitter_count;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1u;
    if (emitters[mid].cdf <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

// One emitter sample at surface `surf` (bsdf b, toward the eye wo), shadow
// ray from o_shadow. Returns f Le |cos| / pdf, or 0.
vec3 pb_emitter_light(pb_surface surf, pb_bsdf b, vec3 wo, vec3 o_shadow, uint pixel, uint s) {
  float u0 = pb_rand(pixel, s, PB_DIM_EMITTER);
  float u1 = pb_rand(pixel, s, PB_DIM_EMITTER + 1u);
  float u2 = pb_rand(pixel, s, PB_DIM_EMITTER + 2u);
  pb_gpu_emitter e = emitters[pb_pick_emitter(u0)];
  if (!(e.pick > 0.0) || !(e.area > 0.0)) return vec3(0.0);
  float su = sqrt(u1);
  float eu = u2 * su, ev = 1.0 - su; // weights of p1, p2
  uint i0 = indices[3u * e.prim], i1 = indices[3u * e.prim + 1u], i2 = indices[3u * e.prim + 2u];
  vec3 q = pb_position(i0) * (1.0 - eu - ev) + pb_position(i1) * eu + pb_position(i2) * ev;
  vec3 d = q - surf.p;
  float d2 = dot(d, d);
  if (!(d2 > 0.0)) return vec3(0.0);
  vec3 wi = d / sqrt(d2);
  pb_surface es = pb_surface_from_hit(e.prim, eu, ev, wi);
  vec3 le = pb_emission(es);
  float cos_l = dot(es.ng, -wi);
  if (all(equal(le, vec3(0.0))) || !(cos_l > 0.0)) return vec3(0.0);
  vec3 f = pb_bsdf_eval(b, wo, wi);
  if (all(equal(f, vec3(0.0)))) return vec3(0.0);
  float pl = e.pick / e.area * d2 / cos_l;
  vec3 seg = pb_offset_ray(es.p, es.ng) - o_shadow;
  float sl = length(seg);
  if (!(sl > 0.0)) return vec3(0.0);
  float t, u, v;
  if (pb_trace(o_shadow, seg / sl, 0.0, sl, true, t, u, v) != PB_GPU_MISS) return vec3(0.0);
  return f * le * (abs(dot(wi, b.n)) / pl);
}

void main() {
  uint gid = pb_gid();
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  // Normal map: the BSDF (and its |cos| below) use n_s; shadow-ray offsets
  // and side tests keep surf.ng.
  pb_apply_normal_map(surf, g.prim, g.u, g.v);
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
    // Stop short of the light by pbrt's ShadowEpsilon (as src/ref does,
    // PB_SHADOW_EPSILON): a light exactly on a surface stays visible.
    if (pb_trace(o_shadow, wi, 0.0, dist * (1.0 - 1e-4), true, t, u, v) != PB_GPU_MISS) continue;
    sum += f * Li * abs(dot(wi, b.n));
  }
  if (SC_EMISSIVE && frame.emitter_count > 0u)
    sum += pb_emitter_light(surf, b, g.wo, o_shadow, pb_pixel_key(frame.pixel_base + gid), pass.sample_index);
  vec3 c = g.throughput * sum;
  pb_gpu_accum acc = accum[gid];
  acc.beauty.rgb += c;
  if (g.chain == 0u) acc.direct += c;
  accum[gid] = acc;
}
