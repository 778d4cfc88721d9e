#version 450
// Pass 2 of a sample: direct light at the G-buffer's surface, with the
// reference's BSDF (smooth lobes):
//  - every point, spot and directional light: one shadow ray (any hit) each;
//  - emissive triangles (SC_EMISSIVE, frame.emitter_count > 0): one emitter
//    picked by power from the host's table (pb_gpu_emitter), a uniform point
//    on it (Shirley's map, as the reference), the solid-angle pdf
//    pick / area * d^2 / cos_l and one shadow ray between the two points,
//    both moved off their surfaces (the reference's segment).
//  - soft lights (SC_SOFT_LIGHTS): one light sample each (common/lights.glsl,
//    the reference's strategies), a shadow ray unless the light casts none;
//  - the world (SC_WORLD): a cosine-weighted direction over the smooth lobes
//    and, for a map, a direction from its table, combined by the power
//    heuristic (a constant world: the cosine direction alone, weight 1),
//    each with a shadow ray to infinity.
// Added to beauty, and to the direct AOV when the surface is the first hit
// (one scattering event).
//
// Soft lights and the reference: the reference also reaches them by its
// BSDF-sampled continuation, MIS-weighted; light sampling alone has the same
// expectation wherever the light's pdf is positive where it emits, which
// holds for every strategy here (the emitter argument below). The world's two
// strategies are combined here as there, with other BSDF pdfs.
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

#define PB_WORLD_BINDING 15
#include "common/scene.glsl"
#include "common/lights.glsl"

// Random dimensions of the emitter sample (the G-buffer pass uses 0..3+4k
// for small k), of soft light i (2 each) and of the world's two samples.
const uint PB_DIM_EMITTER = 0x40000000u;
const uint PB_DIM_SOFT = 0x40000010u;
const uint PB_DIM_WORLD = 0x20000000u;

float pb_mis_power(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

bool pb_unoccluded(vec3 o, vec3 wi, float dist) {
  float t, u, v;
  return pb_trace(o, wi, 0.0, dist, true, t, u, v) == PB_GPU_MISS;
}

// One light sample of every soft light.
vec3 pb_soft_direct(pb_surface surf, pb_bsdf b, vec3 wo, vec3 o_shadow, uint pixel, uint s) {
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < frame.light_count; ++i) {
    pb_gpu_light l = lights[i];
    if (!pb_light_is_soft(l)) continue;
    vec3 wi, L;
    float dist, pdf;
    if (!pb_soft_light_sample(l, surf.p, pb_rand(pixel, s, PB_DIM_SOFT + 2u * i),
                              pb_rand(pixel, s, PB_DIM_SOFT + 2u * i + 1u), wi, dist, L, pdf))
      continue;
    vec3 f = pb_bsdf_eval(b, wo, wi);
    if (all(equal(f, vec3(0.0)))) continue;
    if ((l.flags & PB_GPU_LIGHT_NO_SHADOW) == 0u &&
        !pb_unoccluded(o_shadow, wi, isinf(dist) ? dist : dist * (1.0 - 1e-4)))
      continue;
    sum += f * L * (abs(dot(wi, b.n)) / pdf);
  }
  return sum;
}

// The world: a cosine-weighted direction (density cos / pi about b.n) and a
// map sample, MIS.
vec3 pb_world_direct(pb_bsdf b, vec3 wo, vec3 o_shadow, uint pixel, uint s) {
  if ((world.flags & PB_GPU_WORLD_PRESENT) == 0u) return vec3(0.0);
  bool sampled = (world.flags & PB_GPU_WORLD_SAMPLED) != 0u;
  vec3 sum = vec3(0.0);
  float s1 = pb_rand(pixel, s, PB_DIM_WORLD), s2 = pb_rand(pixel, s, PB_DIM_WORLD + 1u);
  float c = sqrt(max(0.0, 1.0 - s1)), sn = sqrt(s1), phi = 2.0 * PB_PI * s2;
  vec3 wi = b.t * (sn * cos(phi)) + b.b * (sn * sin(phi)) + b.n * c;
  if (c > 0.0 && dot(wi, b.ng) > 0.0) {
    vec3 f = pb_bsdf_eval(b, wo, wi);
    float pb = c * PB_INV_PI;
    if (any(notEqual(f, vec3(0.0))) && pb_unoccluded(o_shadow, wi, PB_INF)) {
      float w = sampled ? pb_mis_power(pb, pb_world_pdf(wi)) : 1.0;
      sum += f * pb_world_radiance(wi) * (c * w / pb);
    }
  }
  if (sampled) {
    vec3 dir;
    float pw;
    if (pb_world_sample(pb_rand(pixel, s, PB_DIM_WORLD + 2u), pb_rand(pixel, s, PB_DIM_WORLD + 3u), dir, pw)) {
      vec3 f = pb_bsdf_eval(b, wo, dir);
      float cd = dot(dir, b.n);
      if (any(notEqual(f, vec3(0.0))) && pb_unoccluded(o_shadow, dir, PB_INF))
        sum += f * pb_world_radiance(dir) * (abs(cd) * pb_mis_power(pw, max(cd, 0.0) * PB_INV_PI) / pw);
    }
  }
  return sum;
}

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
    if (SC_SOFT_LIGHTS && pb_light_is_soft(lights[i])) continue;
    vec3 wi, Li;
    float dist;
    if (!pb_delta_light_at(lights[i], surf.p, wi, dist, Li)) continue;
    vec3 f = pb_bsdf_eval(b, g.wo, wi);
    if (all(equal(f, vec3(0.0)))) continue;
    // Stop short of the light by pbrt's ShadowEpsilon (as src/ref does,
    // PB_SHADOW_EPSILON): a light exactly on a surface stays visible.
    if ((lights[i].flags & PB_GPU_LIGHT_NO_SHADOW) == 0u && !pb_unoccluded(o_shadow, wi, dist * (1.0 - 1e-4)))
      continue;
    sum += f * Li * abs(dot(wi, b.n));
  }
  // Random numbers keyed by the pixel's index in the full frame (a crop
  // draws the full frame's samples).
  uint key = pb_pixel_key(frame.pixel_base + gid);
  if (SC_EMISSIVE && frame.emitter_count > 0u) sum += pb_emitter_light(surf, b, g.wo, o_shadow, key, pass.sample_index);
  if (SC_SOFT_LIGHTS) sum += pb_soft_direct(surf, b, g.wo, o_shadow, key, pass.sample_index);
  if (SC_WORLD) sum += pb_world_direct(b, g.wo, o_shadow, key, pass.sample_index);
  vec3 c = g.throughput * sum;
  pb_gpu_accum acc = accum[gid];
  acc.beauty.rgb += c;
  if (g.chain == 0u) acc.direct += c;
  accum[gid] = acc;
}
