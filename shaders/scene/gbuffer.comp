#version 450
// Pass 1 of a sample: primary visibility and specular eye chains.
// One invocation per pixel of the band. The camera ray (pixel centre at
// spp 1, stratified/jittered otherwise) follows delta interactions (mirror,
// glass) up to max_specular_depth and stops at the first surface with a
// smooth lobe, which goes into the G-buffer for the direct pass (and later
// for photon gathering). Emission met along the way is accumulated here
// (unlit surfaces included: this is the camera path), and the chain's
// throughput falls by Beer-Lambert inside absorbing media.
// First-hit AOVs (albedo, normal, depth, material, coverage) are summed into
// accum. Mixed materials (smooth and delta lobes) pick one stochastically by
// the reference's lobe probabilities, so the estimate stays unbiased. Blender
// materials (the PB_BLENDER build) also continue through their smoother
// glossy closures, lit here by the delta lights and by one sample of each
// soft light and of the world's map (see the branch below).
// Lights do not stop rays (src/ref/pathtrace.c ray_emission): every segment
// after a delta (or followed glossy) interaction adds the soft lights it
// passes before its hit (but those with PB_GPU_LIGHT_NO_MIS), and a ray that
// leaves the scene the world and the soft suns' discs; the camera ray sees
// no light (Cycles 3.4, scene.h) and the world only when PB_GPU_WORLD_CAMERA
// says so (opaque film, visible). These paths start at the camera, so the
// reference counts them by path tracing too, with weight 1 after the camera
// or a delta interaction; after a followed glossy closure, whose vertex
// also sampled the soft lights and the world's map (pb_lights_mis), with
// the power heuristic's complementary weight, as the reference's
// ray_emission (emitters and the delta lights are each counted by one
// strategy only, so what the continuation meets is counted once).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_WORLD_BINDING PB_BIND_WORLD
// A Blender material's BSDF evaluated at one call site per lobe kind
// (principled.glsl pb_blender_eval_cos): this kernel evaluates it in four
// places, none of them a hot loop.
#define PB_EVAL_COMPACT 1
#include "common/scene.glsl"
#include "common/lights.glsl"
#include "common/camera.glsl"
#include "common/direct_light.glsl"

// Emission met by the segment (org, dir) before t_hit (inf: it left the
// scene), `chain` delta interactions after the camera, inside the absorbing
// medium sigma (each light attenuated to its own distance; the world beyond
// a medium of sigma > 0 is absorbed entirely). prev_pdf: the density the
// segment's direction was drawn with at a followed glossy closure, whose
// vertex also sampled the lights (pb_lights_mis): each light's share by the
// power heuristic; 0 after the camera or a delta closure (weight 1).
vec3 pb_segment_emission(vec3 org, vec3 dir, float t_hit, uint chain, vec3 sigma, float prev_pdf) {
  vec3 e = vec3(0.0);
  if (SC_SOFT_LIGHTS && chain > 0u)
    for (uint i = 0u; i < frame.light_count; ++i) {
      pb_gpu_light l = lights[i];
      if (!pb_light_is_soft(l) || (l.flags & PB_GPU_LIGHT_NO_MIS) != 0u) continue;
      float t, pdf;
      vec3 L;
      if (pb_soft_light_hit(l, org, dir, t_hit, t, L, pdf))
        e += L * (pb_medium_transmittance(sigma, t) * (prev_pdf > 0.0 ? pb_mis_power(prev_pdf, pdf) : 1.0));
    }
  if (SC_WORLD && isinf(t_hit) && (chain > 0u || (world.flags & PB_GPU_WORLD_CAMERA) != 0u)) {
    float w = prev_pdf > 0.0 && (world.flags & PB_GPU_WORLD_SAMPLED) != 0u ? pb_mis_power(prev_pdf, pb_world_pdf(dir))
                                                                           : 1.0;
    e += pb_world_radiance(dir) * (pb_medium_transmittance(sigma, t_hit) * w);
  }
  return e;
}

void main() {
  uint gid = pb_gid();
  if (gid >= frame.pixel_count) return;
  uint pixel = frame.pixel_base + gid;
  uint px = pixel % frame.width, py = pixel / frame.width;
  uint key = pb_pixel_key(pixel);
  uint s = pass.sample_index;

  // Sample position in the pixel: centre for one sample (unless the frame
  // asks for jitter: the still frames of a sequence, which accumulate into
  // a box-filtered pixel); for a square count of samples spp = m x m, the
  // sample's cell of the m x m grid, jittered. Any other count (2, 3, 5,
  // ... 128), and a frame whose sample count is open (a time limit or a
  // noise threshold ends it; spp is then only a bound), takes sample s from
  // the (0,2)-sequence in base 2 (van der Corput and Sobol's second
  // dimension; Kollig & Keller 2002), shifted per pixel (Cranley-Patterson):
  // every sample is uniform over the pixel and every prefix of 2^k samples
  // stratified, where a grid of ceil(sqrt(spp))^2 cells would leave its
  // last cells unsampled (2 samples: both in the pixel's upper half).
  vec2 jitter = vec2(0.5);
  uint grid_m = uint(ceil(sqrt(float(frame.spp))));
  bool grid = frame.spp > 1u && grid_m * grid_m == frame.spp;
  bool open_samples = (frame.flags & PB_GPU_FRAME_OPEN_SAMPLES) != 0u || (frame.spp > 1u && !grid);
  vec2 s02 = vec2(0.0);
  if (open_samples) {
    uint vdc = bitfieldReverse(s), sob = 0u;
    for (uint i = s, v = 1u << 31; i != 0u; i >>= 1, v ^= v >> 1)
      if ((i & 1u) != 0u) sob ^= v;
    s02 = vec2(float(vdc >> 8), float(sob >> 8)) * (1.0 / 16777216.0);
    jitter = fract(s02 + vec2(pb_rand(key, 0u, 0u), pb_rand(key, 0u, 1u)));
  } else if (grid || (frame.flags & PB_GPU_FRAME_JITTER) != 0u) {
    uint m = grid_m;
    uint cell = s % (m * m);
    jitter = (vec2(float(cell % m), float(cell / m)) +
              vec2(pb_rand(key, s, 0u), pb_rand(key, s, 1u))) / float(m);
  }
  float fx = float(px + frame.key_x0) + jitter.x, fy = float(py + frame.key_y0) + jitter.y;
  // The lens sample (depth of field): its own dimensions of the sample's
  // stream; with a square count the cell of the same m x m grid with the
  // pixel cell's axes swapped and rotated per pixel, so the lens points of
  // a pixel are stratified too and not tied to the pixel positions (other
  // and open sample counts: the same (0,2) point, axes swapped, its own
  // shift).
  vec2 lens = vec2(pb_rand(key, s, 0x4c454e00u), pb_rand(key, s, 0x4c454e01u));
  if (open_samples) {
    lens = fract(s02.yx + vec2(pb_rand(key, 0u, 0x4c454e00u), pb_rand(key, 0u, 0x4c454e01u)));
  } else if (grid) {
    uint m = grid_m;
    uint cell = s % (m * m), h = pb_hash(key ^ 0x4c454e53u);
    lens = (vec2(float((cell / m + h) % m), float((cell % m + (h >> 16)) % m)) + lens) / float(m);
  }
  vec3 org, dir;
  float t0, tmax;
  bool has_ray = pb_camera_ray_lens(frame.cam, vec2(fx, fy), lens, org, dir, t0, tmax);
  vec3 beta = vec3(1.0);
  vec3 sigma = vec3(0.0); // absorbing medium the chain is in (KHR_materials_volume)
  bool direct_only = (frame.flags & PB_GPU_FRAME_DIRECT_ONLY) != 0u;
  float prev_pdf = 0.0; // pb_segment_emission's

  pb_gpu_accum acc = accum[gid];
  pb_gpu_gbuffer g;
  g.prim = PB_GPU_MISS;
  g.position = vec3(0.0);
  g.wo = vec3(0.0);
  g.u = 0.0;
  g.v = 0.0;
  g.throughput = vec3(0.0);
  g.motion_x = 0.0;
  g.motion_y = 0.0;
  g.chain = 0u;
  g.lobes = 0u;

  // No ray (outside a fisheye's circle): black and uncovered, as in Cycles.
  for (uint chain = 0u; has_ray; ++chain) {
    float t, u, v;
    // The camera segment ends at the far clip plane (tmax), the others never.
    // A camera ray that ends there sees the world beyond it, as in Cycles
    // (a camera ray without a hit shades the background).
    uint prim = pb_trace(org, dir, 0.0, chain == 0u ? tmax : uintBitsToFloat(0x7f800000u), false, t, u, v);
    if (SC_SOFT_LIGHTS || SC_WORLD) {
      vec3 le = beta * pb_segment_emission(org, dir, prim == PB_GPU_MISS ? PB_INF : t, chain, sigma, prev_pdf);
      acc.beauty.rgb += le;
      if (chain <= 1u) acc.direct += le;
    }
    if (prim == PB_GPU_MISS) break;
    beta *= pb_medium_transmittance(sigma, t);
    pb_surface surf = pb_surface_from_hit(prim, u, v, dir);
    pb_apply_normal_map(surf, prim, u, v); // n_s for shading and the normal AOV
    vec3 wo = -dir;
    pb_bsdf b = pb_bsdf_setup_t(surf, wo, pb_surface_tangent(prim, u, v));
    bool blender = SC_BLENDER && b.model != PB_GPU_MODEL_GLTF;
    // Holdout: the camera sees a hole (no coverage, nothing behind).
    if (blender && chain == 0u && b.model == PB_GPU_MODEL_HOLDOUT) break;
    if (chain == 0u) {
      acc.beauty.w += 1.0;
      acc.normal += surf.ns;
      acc.depth += pb_camera_depth(frame.cam, org, dir, t0, t);
      acc.albedo += pb_bsdf_albedo(b);
      acc.material = float(surf.mat + 1u);
    }
    // Emission seen after `chain` delta interactions: a path of `chain`
    // scattering events (direct when at most one).
    vec3 le = pb_emission_toward(surf, wo);
    if (any(notEqual(le, vec3(0.0)))) {
      acc.beauty.rgb += beta * le;
      if (chain <= 1u) acc.direct += beta * le;
      if (chain == 0u) acc.emission += le;
    }
    if (direct_only && chain >= 1u) break;

    if (blender) {
      // A Blender material: stop here with probability sw_D / sw (the share
      // of the sample weights of the closures that stop: the diffuse ones
      // and the layers rougher than frame.glossy_path_alpha2, lit by the
      // direct pass and shaded by the photon map), else light the other
      // glossy closures here and follow one glossy, delta or transparent
      // closure (Cycles' eye path through glossy lobes). Each branch
      // divides by its probability, so the sum is the whole BSDF. Emitters
      // are reached through the followed closures by this continuation only
      // and through the stopping ones by the direct pass's light sample
      // only; the soft lights and the world through the followed closures
      // by a light sample here and by the continuation, MIS-weighted (Veach
      // 1997 9.2: without the light sample a rough copper reflecting a 3 x
      // 3-texel sun found it by its BSDF alone): no path is counted twice. At the depth limit everything is
      // left to the direct pass and the photon map.
      pb_blender_split(b, frame.glossy_path_alpha2);
      float sw_d = 0.0, sw_g = 0.0;
      for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) {
        if (pb_lobe_in(b.cl[i], PB_GPU_LOBES_DIFFUSE)) sw_d += b.cl[i].sample_weight;
        else sw_g += b.cl[i].sample_weight;
      }
      if (!(sw_d + sw_g > 0.0)) break;
      float uc = pb_rand(key, s, 2u + 4u * chain);
      float p_d = sw_d / (sw_d + sw_g);
      if (chain >= frame.max_specular_depth || !(sw_g > 0.0) || uc < p_d) {
        bool all_lobes = chain >= frame.max_specular_depth || !(sw_g > 0.0);
        g.lobes = all_lobes ? PB_GPU_LOBES_ALL : PB_GPU_LOBES_DIFFUSE;
        if (all_lobes && !pb_bsdf_has_smooth(b)) break;
        g.prim = prim;
        g.position = surf.p;
        g.wo = wo;
        g.u = u;
        g.v = v;
        g.throughput = all_lobes ? beta : beta / p_d;
        g.chain = chain;
        if (direct_only && chain > 0u) g.prim = PB_GPU_MISS;
        break;
      }
      float p_g = 1.0 - p_d;
      vec3 beta_g = beta / p_g;
      b.mask = PB_GPU_LOBES_GLOSSY;
      uint rng = pb_walk_seed(key, s, 16u + chain);
      vec3 dl = pb_delta_lights(surf, b, wo, rng);
      if (SC_SOFT_LIGHTS || SC_WORLD) dl += pb_lights_mis(surf, b, wo, key, s, 0x50000000u + (chain << 12u), rng);
      dl *= beta_g;
      acc.beauty.rgb += dl;
      if (chain == 0u) acc.direct += dl;
      vec3 wi, wgt;
      float pdf;
      bool delta, transmit;
      float u1 = pb_rand(key, s, 4u + 4u * chain), u2 = pb_rand(key, s, 5u + 4u * chain);
      if (!pb_blender_sample(b, wo, (uc - p_d) / p_g, u1, u2, false, rng, wi, wgt, pdf, delta, transmit)) break;
      beta = beta_g * wgt;
      prev_pdf = delta ? 0.0 : pdf;
      if (all(equal(beta, vec3(0.0))) || any(isnan(beta)) || any(isinf(beta))) break;
      if (chain >= 7u) { // Russian roulette as below (long chains)
        float q = min(0.95, max(beta.r, max(beta.g, beta.b)));
        if (!(pb_rand(key, s, 0x52520000u + chain) < q)) break;
        beta /= q;
      }
      sigma = pb_medium_after(sigma, surf, transmit);
      org = pb_offset_ray(surf.p, transmit ? -surf.ng : surf.ng);
      dir = wi;
      continue;
    }

    float cos_o = dot(pb_to_local(b, wo), vec3(0.0, 0.0, 1.0));
    if (cos_o <= 0.0) break;
    vec4 l = pb_lobes(b, cos_o);
    float p_smooth = l.x + (b.delta_spec ? 0.0 : l.y);
    float p_delta = (b.delta_spec ? l.y : 0.0) + l.z;
    if (!SC_SPECULAR) p_delta = 0.0;
    float p_sum = p_smooth + p_delta;
    if (!(p_sum > 0.0)) break;
    float uc = pb_rand(key, s, 2u + 4u * chain);
    if (uc * p_sum < p_smooth || chain >= frame.max_specular_depth) {
      // Stop here: the smooth lobes are lit by the direct pass. With a delta
      // lobe too, this choice had probability p_smooth / p_sum.
      if (p_smooth <= 0.0) break;
      g.prim = prim;
      g.position = surf.p;
      g.wo = wo;
      g.u = u;
      g.v = v;
      g.throughput = beta * (p_delta > 0.0 && chain < frame.max_specular_depth ? p_sum / p_smooth : 1.0);
      g.chain = chain;
      if (direct_only && chain > 0u) g.prim = PB_GPU_MISS;
      break;
    }
    // Follow a delta lobe: mirror (F / P) or smooth dielectric.
    prev_pdf = 0.0;
    float choose_delta = p_delta / p_sum;
    vec3 nl = vec3(0.0, 0.0, 1.0);
    vec3 lo = pb_to_local(b, wo);
    float ug = (uc * p_sum - p_smooth) / p_delta; // position inside the delta interval
    bool mirror = b.delta_spec && ug * p_delta < l.y;
    vec3 wi;
    bool transmit = false;
    if (mirror) {
      wi = b.t * -lo.x + b.b * -lo.y + b.n * lo.z;
      if (dot(wi, b.ng) <= 0.0) break;
      beta *= pb_spec_fresnel(b, lo.z) / (l.y / p_sum) / 1.0;
    } else {
      if (l.z <= 0.0) break;
      float eta_o = b.entering ? 1.0 : b.ior;
      float eta_t = b.entering ? b.ior : 1.0;
      float eta = eta_o / eta_t;
      float cos_t;
      float F = pb_fresnel_dielectric(lo.z, eta, cos_t);
      float kg = (1.0 - b.metallic) * b.transmission / (l.z / p_sum);
      float ug2 = pb_rand(key, s, 3u + 4u * chain);
      if (ug2 < F) {
        wi = b.t * -lo.x + b.b * -lo.y + b.n * lo.z;
        if (dot(wi, b.ng) <= 0.0) break;
        beta *= kg;
      } else {
        vec3 li = vec3(-eta * lo.x, -eta * lo.y, -cos_t);
        wi = normalize(b.t * li.x + b.b * li.y + b.n * li.z);
        if (dot(wi, b.ng) >= 0.0) break;
        beta *= b.base * (kg * eta * eta); // radiance scales by (eta_o/eta_t)^2
        transmit = true;
      }
    }
    if (all(equal(beta, vec3(0.0)))) break;
    // Russian roulette on long delta chains: from the 8th
    // interaction on (the old default depth) the chain survives with
    // q = min(0.95, max_c beta_c) and beta / q (unbiased: E = q beta / q),
    // so max_specular_depth (64 by default) is a safety net, not the end of
    // a mirror corridor or of light trapped in glass.
    if (chain >= 7u) {
      float q = min(0.95, max(beta.r, max(beta.g, beta.b)));
      if (!(pb_rand(key, s, 0x52520000u + chain) < q)) break;
      beta /= q;
    }
    sigma = pb_medium_after(sigma, surf, transmit);
    org = pb_offset_ray(surf.p, transmit ? -surf.ng : surf.ng);
    dir = wi;
  }
  gbuffer[gid] = g;
  accum[gid] = acc;
}
