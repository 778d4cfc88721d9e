// Direct light at a surface, shared by the direct pass (the G-buffer's
// vertex) and the G-buffer pass (the glossy vertices a Blender material's
// eye path passes through): shadow rays to the delta lights, one emitter
// sample, one sample of each soft light and the world's (after
// common/lights.glsl). See direct.comp for how they combine with the
// reference's MIS.
#ifndef PB_DIRECT_LIGHT_GLSL
#define PB_DIRECT_LIGHT_GLSL

// Random dimensions of the emitter sample (the G-buffer pass uses 0..3+4k
// for small k), of soft light i (2 each) and of the world's two samples.
const uint PB_DIM_EMITTER = 0x40000000u;
const uint PB_DIM_SOFT = 0x40000010u;
const uint PB_DIM_WORLD = 0x20000000u;

float pb_mis_power(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
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

// Fraction of light that reaches o + tmax d from o: 0 or 1, or with
// SC_ALPHA the product of 1 - Alpha of the Principled surfaces in between
// (Cycles' transparent shadows; the reference's shadow() in pathtrace.c).
vec3 pb_shadow(vec3 o, vec3 d, float tmax) {
  float t, u, v;
  if (!SC_ALPHA) return pb_trace(o, d, 0.0, tmax, true, t, u, v) == PB_GPU_MISS ? vec3(1.0) : vec3(0.0);
  vec3 tr = vec3(1.0);
  for (uint n = 0u; n < 64u && tmax > 0.0; ++n) {
    uint prim = pb_trace(o, d, 0.0, tmax, false, t, u, v);
    if (prim == PB_GPU_MISS) return tr;
    pb_surface s = pb_surface_from_hit(prim, u, v, d);
    float k = materials[s.mat].model == PB_GPU_MODEL_PRINCIPLED ? 1.0 - pb_blender_alpha(s) : 0.0;
    if (!(k > 0.0)) return vec3(0.0);
    tr *= k;
    o = pb_offset_ray(s.p, -s.ng);
    tmax -= t;
  }
  return vec3(0.0);
}

// Where shadow rays toward wi start: off the surface on wi's side (a
// Blender glass sees lights through it; glTF's smooth lobes only reflect).
vec3 pb_shadow_origin(pb_surface surf, vec3 wi) {
  return pb_offset_ray(surf.p, dot(wi, surf.ng) >= 0.0 ? surf.ng : -surf.ng);
}

// Every point, spot and directional light (soft ones are pb_soft_direct's):
// f Li |cos| summed, one shadow ray each (stopped pbrt's ShadowEpsilon
// short of the light, as src/ref; none for a light that casts no shadow).
vec3 pb_delta_lights(pb_surface surf, pb_bsdf b, vec3 wo, inout uint rng) {
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < frame.light_count; ++i) {
    if (SC_SOFT_LIGHTS && pb_light_is_soft(lights[i])) continue;
    vec3 wi, Li;
    float dist;
    if (!pb_delta_light_at(lights[i], surf.p, wi, dist, Li)) continue;
    vec3 f = pb_bsdf_eval(b, wo, wi, rng);
    if (all(equal(f, vec3(0.0)))) continue;
    vec3 vis = (lights[i].flags & PB_GPU_LIGHT_NO_SHADOW) != 0u
                   ? vec3(1.0)
                   : pb_shadow(pb_shadow_origin(surf, wi), wi, dist * (1.0 - 1e-4));
    sum += vis * f * Li * abs(dot(wi, b.n));
  }
  return sum;
}

// One light sample of every soft light: f L |cos| / pdf summed.
vec3 pb_soft_direct(pb_surface surf, pb_bsdf b, vec3 wo, uint pixel, uint s, inout uint rng) {
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < frame.light_count; ++i) {
    pb_gpu_light l = lights[i];
    if (!pb_light_is_soft(l)) continue;
    vec3 wi, L;
    float dist, pdf;
    if (!pb_soft_light_sample(l, surf.p, pb_rand(pixel, s, PB_DIM_SOFT + 2u * i),
                              pb_rand(pixel, s, PB_DIM_SOFT + 2u * i + 1u), wi, dist, L, pdf))
      continue;
    vec3 f = pb_bsdf_eval(b, wo, wi, rng);
    if (all(equal(f, vec3(0.0)))) continue;
    vec3 vis = (l.flags & PB_GPU_LIGHT_NO_SHADOW) != 0u
                   ? vec3(1.0)
                   : pb_shadow(pb_shadow_origin(surf, wi), wi, isinf(dist) ? dist : dist * (1.0 - 1e-4));
    sum += vis * f * L * (abs(dot(wi, b.n)) / pdf);
  }
  return sum;
}

// The world: a cosine-weighted direction (density cos / pi about b.n) and a
// map sample, MIS.
vec3 pb_world_direct(pb_surface surf, pb_bsdf b, vec3 wo, uint pixel, uint s, inout uint rng) {
  if ((world.flags & PB_GPU_WORLD_PRESENT) == 0u) return vec3(0.0);
  bool sampled = (world.flags & PB_GPU_WORLD_SAMPLED) != 0u;
  vec3 sum = vec3(0.0);
  float s1 = pb_rand(pixel, s, PB_DIM_WORLD), s2 = pb_rand(pixel, s, PB_DIM_WORLD + 1u);
  float c = sqrt(max(0.0, 1.0 - s1)), sn = sqrt(s1), phi = 2.0 * PB_PI * s2;
  vec3 wi = b.t * (sn * cos(phi)) + b.b * (sn * sin(phi)) + b.n * c;
  if (c > 0.0 && dot(wi, b.ng) > 0.0) {
    vec3 f = pb_bsdf_eval(b, wo, wi, rng);
    float pb = c * PB_INV_PI;
    if (any(notEqual(f, vec3(0.0)))) {
      vec3 vis = pb_shadow(pb_shadow_origin(surf, wi), wi, PB_INF);
      float w = sampled ? pb_mis_power(pb, pb_world_pdf(wi)) : 1.0;
      sum += vis * f * pb_world_radiance(wi) * (c * w / pb);
    }
  }
  if (sampled) {
    vec3 dir;
    float pw;
    if (pb_world_sample(pb_rand(pixel, s, PB_DIM_WORLD + 2u), pb_rand(pixel, s, PB_DIM_WORLD + 3u), dir, pw)) {
      vec3 f = pb_bsdf_eval(b, wo, dir, rng);
      float cd = dot(dir, b.n);
      if (any(notEqual(f, vec3(0.0)))) {
        vec3 vis = pb_shadow(pb_shadow_origin(surf, dir), dir, PB_INF);
        sum += vis * f * pb_world_radiance(dir) * (abs(cd) * pb_mis_power(pw, max(cd, 0.0) * PB_INV_PI) / pw);
      }
    }
  }
  return sum;
}

// One emitter sample at surface `surf` (bsdf b, toward the eye wo). Returns
// f Le |cos| / pdf, or 0.
vec3 pb_emitter_light(pb_surface surf, pb_bsdf b, vec3 wo, uint pixel, uint s, inout uint rng) {
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
  vec3 f = pb_bsdf_eval(b, wo, wi, rng);
  if (all(equal(f, vec3(0.0)))) return vec3(0.0);
  float pl = e.pick / e.area * d2 / cos_l;
  vec3 o_shadow = pb_shadow_origin(surf, wi);
  vec3 seg = pb_offset_ray(es.p, es.ng) - o_shadow;
  float sl = length(seg);
  if (!(sl > 0.0)) return vec3(0.0);
  vec3 vis = pb_shadow(o_shadow, seg / sl, sl);
  return vis * f * le * (abs(dot(wi, b.n)) / pl);
}

#endif
