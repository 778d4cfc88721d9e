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

// Map samples of the world per pixel sample in the direct pass (one BSDF
// sample beside them; Veach 1997 9.2.2's multi-sample MIS, the power
// heuristic on n_i p_i). Four: the hdri sample's floor, lit mostly by a
// 3 x 3-texel sun, had 8.6 % median error in direct light at the render
// engine's 16 spp with one (stratified) map sample, which four cut by
// about half; each costs one shadow ray to infinity.
const uint PB_WORLD_MAP_SAMPLES = 4u;

// Point s of the 2D Sobol (0,2)-sequence (van der Corput's radical inverse
// and Sobol's second dimension, Kollig & Keller 2002), digitally scrambled by
// an XOR with a hash of (pixel, dim) that does not depend on s: each point
// is uniform on [0,1)^2 (so every estimator stays unbiased), and the first
// 2^k samples of a pixel keep the net's strata (one point in each of 2^k
// equal elementary boxes). A light sample drawn from it by inverting a CDF
// is stratified over the light's power: at the render engine's 16 spp the
// 3 x 3-texel sun of the hdri sample takes its share of the 16 map samples
// within one, where independent numbers leave a binomial count (relative
// noise sqrt((1 - P) / (16 P)) for a sun of power fraction P).
vec2 pb_ld2(uint pixel, uint s, uint dim) {
  uint x = bitfieldReverse(s), y = 0u;
  for (uint v = 0x80000000u, i = s; i != 0u; i >>= 1u, v ^= v >> 1u)
    if ((i & 1u) != 0u) y ^= v;
  uint hx = pb_hash(frame.seed_lo ^ pb_hash(pixel ^ pb_hash(dim ^ frame.seed_hi ^ 0x68e31da4u)));
  uint hy = pb_hash(hx ^ 0xb5297a4du);
  return vec2(float((x ^ hx) >> 8), float((y ^ hy) >> 8)) * (1.0 / 16777216.0);
}

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
    vec2 u = pb_ld2(pixel, s, PB_DIM_SOFT + 2u * i);
    if (!pb_soft_light_sample(l, surf.p, u.x, u.y, wi, dist, L, pdf)) continue;
    vec3 f = pb_bsdf_eval(b, wo, wi, rng);
    if (all(equal(f, vec3(0.0)))) continue;
    vec3 vis = (l.flags & PB_GPU_LIGHT_NO_SHADOW) != 0u
                   ? vec3(1.0)
                   : pb_shadow(pb_shadow_origin(surf, wi), wi, isinf(dist) ? dist : dist * (1.0 - 1e-4));
    sum += vis * f * L * (abs(dot(wi, b.n)) / pdf);
  }
  return sum;
}

// The density with which pb_blender_sample draws wi over b.mask's sampled
// closures (their smooth mixture over the sample weights it picks from;
// its delta and transparent shares have no density): the BSDF strategy's
// pdf in the MIS weights below, as the reference's pb_bsdf_eval pdf.
float pb_blender_sample_pdf(pb_bsdf b, vec3 wo, vec3 wi, inout uint rng, out vec3 f_cos) {
  float sum = 0.0, pdf;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i)
    if (pb_lobe_sampled(b.cl[i], b.mask)) sum += b.cl[i].sample_weight;
  f_cos = pb_blender_eval_cos(b, wo, wi, rng, pdf);
  return sum > 0.0 ? pdf * (b.sw_sum / sum) : 0.0;
}

// The world, two strategies combined by the power heuristic (Veach 1997,
// 9.2; the reference's soft_nee and ray_emission in src/ref/pathtrace.c):
//  - the BSDF's: a Blender material draws a direction from the closures of
//    b.mask (pb_blender_sample: GGX's visible normals for the glossy
//    layers, cosine for the diffuse ones), a glTF one a cosine-weighted
//    direction about b.n (density cos / pi); a delta closure drawn adds
//    nothing here (the eye path follows those, or at its end nobody does);
//  - the map's: a direction from its table (pb_world_sample).
// A constant world has the BSDF strategy alone, weight 1. Why the BSDF's and
// not a cosine lobe for glossy closures: a GGX lobe of roughness 0.3 (alpha
// 0.09) is about 1/(4 alpha^2) ~ 30 times denser than cos / pi at its peak,
// so a cosine direction that finds it carries a weight 30x the mean, and
// the map's strategy, which draws the sun most of the time, does not cover
// the sky the lobe reflects: fireflies over a rough metal (the hdri sample,
// relMSE 0.15 on its copper sphere with the cosine strategy).
vec3 pb_world_direct(pb_surface surf, pb_bsdf b, vec3 wo, uint pixel, uint s, inout uint rng) {
  if ((world.flags & PB_GPU_WORLD_PRESENT) == 0u) return vec3(0.0);
  bool sampled = (world.flags & PB_GPU_WORLD_SAMPLED) != 0u;
  bool blender = SC_BLENDER && b.model != PB_GPU_MODEL_GLTF;
  vec3 sum = vec3(0.0);
  vec2 ub = pb_ld2(pixel, s, PB_DIM_WORLD);
  float s1 = ub.x, s2 = ub.y;
  if (blender) {
    vec3 wi, wgt;
    float pdf;
    bool delta, transmit;
    if (pb_blender_sample(b, wo, pb_rand(pixel, s, PB_DIM_WORLD + 4u), s1, s2, false, rng, wi, wgt, pdf, delta,
                          transmit) &&
        !delta && pdf > 0.0 && any(notEqual(wgt, vec3(0.0)))) {
      vec3 vis = pb_shadow(pb_shadow_origin(surf, wi), wi, PB_INF);
      float w = sampled ? pb_mis_power(pdf, float(PB_WORLD_MAP_SAMPLES) * pb_world_pdf(wi)) : 1.0;
      sum += vis * wgt * pb_world_radiance(wi) * w;
    }
  } else {
    float c = sqrt(max(0.0, 1.0 - s1)), sn = sqrt(s1), phi = 2.0 * PB_PI * s2;
    vec3 wi = b.t * (sn * cos(phi)) + b.b * (sn * sin(phi)) + b.n * c;
    if (c > 0.0 && dot(wi, b.ng) > 0.0) {
      vec3 f = pb_bsdf_eval(b, wo, wi, rng);
      float pb = c * PB_INV_PI;
      if (any(notEqual(f, vec3(0.0)))) {
        vec3 vis = pb_shadow(pb_shadow_origin(surf, wi), wi, PB_INF);
        float w = sampled ? pb_mis_power(pb, float(PB_WORLD_MAP_SAMPLES) * pb_world_pdf(wi)) : 1.0;
        sum += vis * f * pb_world_radiance(wi) * (c * w / pb);
      }
    }
  }
  for (uint k = 0u; sampled && k < PB_WORLD_MAP_SAMPLES; ++k) {
    vec3 dir;
    float pw;
    // Point s K + k of the sequence: the pixel's K spp map samples stratified.
    vec2 um = pb_ld2(pixel, s * PB_WORLD_MAP_SAMPLES + k, PB_DIM_WORLD + 2u);
    if (pb_world_sample(um.x, um.y, dir, pw)) {
      vec3 fc; // f |cos|
      float pb;
      if (blender) {
        pb = pb_blender_sample_pdf(b, wo, dir, rng, fc);
      } else {
        float cd = dot(dir, b.n);
        fc = pb_bsdf_eval(b, wo, dir, rng) * abs(cd);
        pb = max(cd, 0.0) * PB_INV_PI;
      }
      if (any(notEqual(fc, vec3(0.0)))) {
        vec3 vis = pb_shadow(pb_shadow_origin(surf, dir), dir, PB_INF);
        float kp = float(PB_WORLD_MAP_SAMPLES) * pw;
        sum += vis * fc * pb_world_radiance(dir) * (pb_mis_power(kp, pb) / kp);
      }
    }
  }
  return sum;
}

// The soft lights and the world's map at a vertex that the eye path leaves
// through b.mask's closures (a Blender material's followed glossy closures,
// gbuffer.comp): one light sample of each, weighted by the power heuristic
// against that continuation's density (pb_blender_sample_pdf), which counts
// what it reaches with the complementary weight (gbuffer.comp's
// pb_segment_emission, from the pdf it was drawn with): the reference's
// soft_nee / ray_emission pair at a glossy vertex. A light with
// PB_GPU_LIGHT_NO_MIS is reached by this sample alone (weight 1), a
// constant world by the continuation alone. `dim` keys this vertex's random
// numbers apart from the direct pass's.
vec3 pb_lights_mis(pb_surface surf, pb_bsdf b, vec3 wo, uint pixel, uint s, uint dim, inout uint rng) {
  vec3 sum = vec3(0.0);
  if (SC_SOFT_LIGHTS)
    for (uint i = 0u; i < frame.light_count; ++i) {
      pb_gpu_light l = lights[i];
      if (!pb_light_is_soft(l)) continue;
      vec3 wi, L, fc;
      float dist, pdf;
      vec2 u = pb_ld2(pixel, s, dim + 2u * i);
      if (!pb_soft_light_sample(l, surf.p, u.x, u.y, wi, dist, L, pdf)) continue;
      float pb = pb_blender_sample_pdf(b, wo, wi, rng, fc);
      if (all(equal(fc, vec3(0.0)))) continue;
      vec3 vis = (l.flags & PB_GPU_LIGHT_NO_SHADOW) != 0u
                     ? vec3(1.0)
                     : pb_shadow(pb_shadow_origin(surf, wi), wi, isinf(dist) ? dist : dist * (1.0 - 1e-4));
      float w = (l.flags & PB_GPU_LIGHT_NO_MIS) != 0u ? 1.0 : pb_mis_power(pdf, pb);
      sum += vis * fc * L * (w / pdf);
    }
  if (SC_WORLD && (world.flags & PB_GPU_WORLD_PRESENT) != 0u && (world.flags & PB_GPU_WORLD_SAMPLED) != 0u) {
    vec3 dir, fc;
    float pw;
    uint dw = dim + 2u * frame.light_count;
    vec2 u = pb_ld2(pixel, s, dw);
    if (pb_world_sample(u.x, u.y, dir, pw)) {
      float pb = pb_blender_sample_pdf(b, wo, dir, rng, fc);
      if (any(notEqual(fc, vec3(0.0)))) {
        vec3 vis = pb_shadow(pb_shadow_origin(surf, dir), dir, PB_INF);
        sum += vis * fc * pb_world_radiance(dir) * (pb_mis_power(pw, pb) / pw);
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
  vec3 le = pb_emission_toward(es, -wi);
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
