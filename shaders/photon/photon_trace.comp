#version 450
// The photon tracer: one invocation per photon path (gid < params.photons).
//
// Emission (seed 001 24.2.1): the host splits the budget over the lights
// (and the world) in proportion to their power (pb_light_power), so every
// photon starts with about the same flux; path gid belongs to the light whose
// range [first, first + count) holds it. Point: uniform sphere; spot:
// uniform in the outer cone, flux weighted by the spot's falloff; sphere
// lights: the same directions from the point of the sphere facing them
// (src/ref/soft_lights.c pb_sphere_light_origin); directional: parallel rays
// from a disc of the scene's bounding radius, for the soft sun in a
// direction from its disc; area lights: pb_area_light_emit (a point of the
// shape, a cosine-weighted direction in the spread's cone, flux x the
// spread profile); the world: a direction from its table (uniform for a
// constant world), parallel over the disc, flux x L / pdf. Soft lights and
// the world are traced also with the RSM first bounce (their maps are empty).
//
// First hit: traced from the light (equivalent to an RSM texel's surface
// point, see below). It is direct light and never stored (seed 001 24.2.2).
// Every later hit on a surface with a smooth lobe stores a photon (position,
// geometric normal facing the photon, incoming direction, flux, footprint,
// flags: caustic when every interaction since the light was specular; bits
// 8..15 the number of interactions before the hit, 1 for the first stored).
// Scattering: cosine-sampled smooth lobes weighted by the full smooth BSDF
// (f pi / P(smooth lobes), unbiased for the reference's diffuse + GGX mix),
// delta mirror weighted F / P(mirror), smooth dielectric reflect/refract with
// probability F / 1 - F (the reference's pb_bsdf_sample_dir, importance
// transport). Russian roulette on the max power ratio (seed 001 eq. 1,
// Jensen): p = min(1, max_c(Phi_c w_c) / max_c(Phi_c)); survivors carry
// Phi w / p, and their differentials grow by 1/sqrt(p) (seed 000 4.2).
//
// Differentials (seed 000 section 4; common/photon_diff.glsl). Emission
// spacing, derivation of the global Delta: a light given n_i of the n
// photons of the iteration emits them uniformly over its solid angle Omega
// (4 pi point, 2 pi (1 - cos_outer) spot), so each covers Omega / n_i and the
// expected distance to a neighbour in direction space is sqrt(Omega / n_i)
// (eq. 5 for Omega = 4 pi). Parameterised by (cos theta, phi), the raw
// differentials have lengths 1/sin theta and sin theta (eq. 6), so the
// spacings would be Delta_cos = sqrt(Omega/n_i) sin theta and
// Delta_phi = sqrt(Omega/n_i) / sin theta (eq. 7). Scaling dD_cos by
// sin theta and dD_phi by 1/sin theta (eq. 8) makes both unit vectors and
// both spacings sqrt(Omega / n_i); scaling them further by
// diff_scale = sqrt(Omega / n_i) / Delta with the global
// Delta = 2 sqrt(pi / n) (eq. 9, n the whole budget) leaves one spacing
// Delta for every photon of every light (footprints are invariant under
// "differential times k, spacing over k"). Directional lights: positions
// uniform on a disc of area A = pi R^2, dP = diff_scale (t, b) with
// diff_scale = sqrt(A / n_i) / Delta, dD = 0. Relation to an RSM: a texel of
// an RSM of solid angle Omega_texel is one sample of the light's emission;
// with n_i photons spread over N_texels texels by power, a photon stands for
// Omega / n_i steradians, i.e. the texel's footprint scaled by
// sqrt(N_texels / n_i) per axis -- the same Delta-scaled dD as here, with the
// texel's world footprint as Delta dP at the first hit.
//
// Footprint stored at a hit: a = Delta dPu, b = Delta dPv (in the tangent
// plane after the transfer), then for diffusely reflected photons the -3/4
// compression and smoothing factor of seed 000 4.3, a <- s Delta dPu
// |dPu|^(-3/4) (scale-free, see pb_store), for caustic photons only their
// own factor, a <- s_caustic Delta dPu (PB_PHOTON_PARAM_CAUSTIC_RAW, always
// set by the host); clamped so the semi-major is at most r_max (both axes
// scaled together; counts.clamped counts them). radius: the true semi-major
// of the skewed ellipse;
// normal_extent: its semi-minor length (a flat ellipsoid as thin as the
// footprint is narrow, so a query on another surface only cuts it where the
// two surfaces are within the footprint's smaller extent).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_rsm.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_SCENE_OWN_PASS_IO 1
layout(std430, set = 0, binding = PB_PHOTON_BIND_PHOTONS) buffer Photons { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = PB_PHOTON_BIND_COUNTS) buffer Counts { pb_gpu_photon_counts counts; };
layout(std430, set = 0, binding = PB_PHOTON_BIND_PARAMS) buffer Params {
  pb_gpu_photon_params params;
  pb_gpu_photon_light plights[];
};
// Reflective shadow maps (PB_PHOTON_PARAM_RSM; shaders/photon/photon_rsm.comp).
layout(std430, set = 0, binding = PB_PHOTON_BIND_RSM_LIGHTS) readonly buffer RsmLights { pb_gpu_rsm_light rlights[]; };
layout(std430, set = 0, binding = PB_PHOTON_BIND_RSM_TEXELS) readonly buffer RsmTexels { pb_gpu_rsm_texel rtexels[]; };

#define PB_WORLD_BINDING PB_PHOTON_BIND_WORLD
#include "common/scene.glsl"
#include "common/lights.glsl"

// Transmission (glass) code only for scenes that have it (SC_SPECULAR, from
// scene.glsl, compiles out mirror and glass altogether).
layout(constant_id = PB_SPEC_TRANSMISSION) const bool SC_TRANSMISSION = true;

#include "common/photon_diff.glsl"
#include "common/rsm_texel.glsl"

// The ray query of a photon segment. The BVH build: the closest hit in the
// scene BVH. The images build (-DPB_IMAGE_TRACER, photon_trace_images,
// seed 003): the nearest hit the environment maps accept
// (common/image_maps.glsl), the hit being the accepted texel's surface point
// (its triangle, the point's barycentrics on it: the map's position, normal
// and material, as the paper reads them) at t = its distance along the ray;
// a ray no map confirms (type B only) is lost like an escape, and counted.
#ifdef PB_IMAGE_TRACER
#include "shared/pb_image_maps.h"
layout(std430, set = 0, binding = PB_PHOTON_BIND_IMAGE_MAPS) readonly buffer ImageMaps {
  pb_gpu_image_maps_info im_info;
  pb_gpu_image_map im_maps[];
};
layout(std430, set = 0, binding = PB_PHOTON_BIND_IMAGE_TEXELS) readonly buffer ImageTexels {
  pb_gpu_image_texel im_texels[];
};
layout(std430, set = 0, binding = PB_PHOTON_BIND_IMAGE_COUNTS) buffer ImageCounts { pb_gpu_image_counts im_counts; };
#include "common/image_maps.glsl"

uint pb_photon_trace(vec3 o, vec3 d, out float t, out float u, out float v) {
  uint tex, nb, nc;
  u = v = 0.0;
  uint ty = pb_image_intersect(o, d, t, tex, nb, nc);
  atomicAdd(im_counts.segments, 1u);
  if (nb > 0u) atomicAdd(im_counts.type_b, nb);
  if (nc > 0u) atomicAdd(im_counts.type_c, nc);
  if (ty != PB_IMAGE_TYPE_D) {
    if (ty == PB_IMAGE_TYPE_B) atomicAdd(im_counts.misses, 1u);
    else atomicAdd(im_counts.escapes, 1u);
    return PB_GPU_MISS;
  }
  atomicAdd(im_counts.hits, 1u);
  pb_gpu_image_texel tx = im_texels[tex];
  uint prim = tx.prim;
  // Barycentrics of the texel's point on its triangle (it lies on it: the
  // map's ray hit it), clamped against rounding.
  uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
  vec3 p0 = pb_position(i0), e1 = pb_position(i1) - p0, e2 = pb_position(i2) - p0;
  vec3 ng = cross(e1, e2);
  float g = dot(ng, ng);
  vec3 dp = tx.position - p0;
  float b1 = g > 0.0 ? dot(cross(dp, e2), ng) / g : 0.0, b2 = g > 0.0 ? dot(cross(e1, dp), ng) / g : 0.0;
  b1 = clamp(b1, 0.0, 1.0);
  b2 = clamp(b2, 0.0, 1.0 - b1);
  u = b1;
  v = b2;
  t = max(t, 0.0);
  return prim;
}
#else
uint pb_photon_trace(vec3 o, vec3 d, out float t, out float u, out float v) {
  return pb_trace(o, d, 0.0, PB_INF, false, t, u, v);
}
#endif

float pb_prand(uint path, uint dim) { return pb_rand(path, params.iteration, dim); }
// Sequence dimensions: 0, 1 emission (RSM: 0 the stratum jitter), 2 + 4 k ..
// the k-th bounce; the RSM's per-iteration rotation lies far above any
// bounce (drawn for path 0); soft lights' and the world's second pair of
// emission numbers above that.
const uint PB_RSM_ROTATION_DIM = 1000u;
const uint PB_EMIT_DIM = 1002u;

// ray_length: the length of the segment that brought the photon here (seed 003's
// bandwidth).
void pb_store(vec3 p, vec3 n, vec3 wi, vec3 power, vec3 dPu, vec3 dPv, bool caustic, uint bounce,
              uint path, float ray_length) {
  float delta = params.delta;
  vec3 a = delta * dPu, b = delta * dPv;
  if ((params.flags & PB_PHOTON_PARAM_RAW_FOOTPRINT) == 0u && params.bandwidth_h0 > 0.0) {
    // Seed 003 section 6 (render --bandwidth-c0): "h = C sqrt(A / N) ...
    // C = C0 / sqrt(p) ... p is clamped to a certain range [P_min, P_max].
    // The PDF is approximated as p = cos(theta) / d^2 where d is the
    // traveled distance of the photon ray and theta is the incident angle."
    // p has units 1/m^2 there, C0 none, so that h would not be a length;
    // here p is made dimensionless by R^2 (R the scene's bounding radius:
    // p R^2 = 1 for a head-on hit after travelling R; derived, the paper is
    // silent) and clamped to [PB_PHOTON_BANDWIDTH_P_MIN, _MAX] (photon.h).
    // d: the last segment's length (the "photon ray" that stored it).
    // bandwidth_h0 = C0 sqrt(A / N) (host). A disc in the tangent plane, for
    // every photon (the paper splats caustic photons the same way); the
    // differentials still drive the paths, not the footprints.
    float R = params.scene_radius;
    float cos_t = abs(dot(wi, n));
    float pr = cos_t * R * R / max(ray_length * ray_length, 1e-12 * R * R);
    pr = clamp(pr, params.bandwidth_p_min, params.bandwidth_p_max);
    float h = params.bandwidth_h0 / sqrt(pr);
    vec3 tb, bb;
    pb_basis(n, tb, bb);
    a = h * tb;
    b = h * bb;
  } else if ((params.flags & PB_PHOTON_PARAM_RAW_FOOTPRINT) == 0u && caustic &&
      (params.flags & PB_PHOTON_PARAM_CAUSTIC_RAW) != 0u) {
    // Caustic photons: seed 000 4.3 rescales "the
    // footprints of all diffusely reflected photons"; a photon that has
    // undergone only specular interactions keeps its differential
    // footprint, times its own smoothing factor (the paper uses 5,
    // "ensuring very sharp caustics", against its diffuse s of 10-60):
    // a = s_c Delta dPu, b = s_c Delta dPv. Without
    // the compression s_c is dimensionless already (the footprint is a
    // length, Delta dP, scaling with the scene), and the footprint follows
    // the caustic's focus: where specular paths converge dP shrinks and so
    // does the kernel. Raw footprints (s_c = 1) overlap pi of their
    // neighbours (area pi (Delta |dP|)^2 against a spacing (Delta |dP|)^2),
    // s_c photons per axis more: k_PD ~ pi s_c^2 on a caustic. The host
    // always sets PB_PHOTON_PARAM_CAUSTIC_RAW; s_c defaults to 1 (k ~ 2.9
    // photons per gather on a caustic; src/render/photon/photon.h has the sweeps:
    // 0.5, k 0.72, was best only while a map held a few hundred caustic
    // records, 5 blurs ring's cardioid); the compressed branch below (the
    // old behaviour) stays for the flag's absence only.
    a = params.smoothing_caustic * a;
    b = params.smoothing_caustic * b;
  } else if ((params.flags & PB_PHOTON_PARAM_RAW_FOOTPRINT) == 0u) {
    float s = caustic ? params.smoothing_caustic : params.smoothing;
    // Scale-free -3/4 compression (seed 000 section 4.3). The paper's
    // r' = s Delta |dP|^(1/4) = s Delta^(3/4) r^(1/4), r = Delta |dP| the raw
    // footprint radius, leaves s with units length^(3/4) (s = 10-60 of its
    // Table 2 are for metre-sized scenes). With the reference length
    // r_ref = Delta R (R the scene's bounding radius: the photon spacing on
    // the bounding sphere, ~ the footprint of an unfocused photon),
    //   r' = s r_ref^(3/4) r^(1/4) = s (Delta R)^(3/4) (Delta |dP|)^(1/4)
    //      = [paper's r'] R^(3/4),
    // s is dimensionless: scaling the scene by c scales R, dP, r and r' by c
    // (the picture is unchanged), r' = s r where r = r_ref, and r' ~ Delta ~
    // N^(-1/2) keeps the photons per gather (k_PD ~ N r'^2) independent of
    // the budget N, as in the paper. For R = 1 m it is the paper's formula.
    // A zero differential stays zero (caught below).
    float la = length(dPu), lb = length(dPv);
    float rref34 = pow(delta * params.scene_radius, 0.75);
    a = la > 0.0 ? (s * rref34 * pow(delta * la, 0.25) / la) * dPu : vec3(0.0);
    b = lb > 0.0 ? (s * rref34 * pow(delta * lb, 0.25) / lb) * dPv : vec3(0.0);
  }
  vec2 ax = pb_ellipse_axes(a, b);
  if (!(ax.y > 1e-7 * params.r_max) || isinf(ax.x)) {
    // Degenerate (zero or non-finite) footprint: an isotropic disc in the
    // tangent plane, as large as the finite semi-major (at least 0.1 % of
    // r_max).
    pb_diff_guarded++;
    float r = (ax.x > 0.0 && !isinf(ax.x)) ? ax.x : 0.0;
    r = max(r, 1e-3 * params.r_max);
    vec3 t, bt;
    pb_basis(n, t, bt);
    a = r * t;
    b = r * bt;
    ax = vec2(r);
  }
  bool clamped = false;
  if ((params.flags & PB_PHOTON_PARAM_RAW_FOOTPRINT) == 0u && ax.x > params.r_max) {
    float k = params.r_max / ax.x;
    a *= k;
    b *= k;
    ax *= k;
    clamped = true;
  }
  if (!pb_finite3(p) || !pb_finite3(power) || !pb_finite3(a) || !pb_finite3(b) || !pb_finite3(wi) ||
      !pb_finite3(n) || isnan(ax.x) || isnan(ax.y)) {
    pb_diff_guarded++;
    return;
  }
  uint idx = atomicAdd(counts.stored, 1u);
  if (idx >= params.capacity) {
    // Keeps counts.stored == records written: every overflowing add is
    // undone, so the counter ends at exactly the capacity.
    atomicAdd(counts.stored, 0xffffffffu);
    atomicAdd(counts.overflow, 1u);
    return;
  }
  if (caustic) atomicAdd(counts.caustic, 1u);
  if (clamped) atomicAdd(counts.clamped, 1u);
  pb_gpu_photon ph;
  ph.position = p;
  ph.flags = (caustic ? PB_PHOTON_CAUSTIC : 0u) | (min(bounce, 255u) << PB_PHOTON_BOUNCE_SHIFT);
  ph.power = power;
  ph.radius = ax.x;
  ph.wi = wi;
  ph.normal_extent = ax.y;
  ph.normal = n;
  ph.path = path;
  ph.axis_u = a;
  ph.ray_length = isinf(ray_length) || isnan(ray_length) ? 0.0 : ray_length; // seed 001 eq. 2
  ph.axis_v = b;
  ph.pad1 = 0.0;
  photons[idx] = ph;
}

// Adjoint shading-normal correction of a photon's smooth scattering (Veach
// 1997, eq. 5.19): the BSDF sampled and weighted with the
// shading normal n_s carries flux as radiance would; importance (photons)
// needs f* = f |wo.n_s| |wi.n_g| / (|wo.n_g| |wi.n_s|), wo the direction the
// photon came from, wi the one it leaves in. Without it a smooth-shaded face
// sends its reflected flux by cos(wi, n_s) instead of cos(wi, n_g) (the
// projected area of the real face): measured, a floor whose normals lean
// 30 degrees toward a wall over-lit that wall and came back +17 % too bright
// (test_gpu_smooth_shading). 1 on flat faces; denominators guarded at 1e-4.
float pb_adjoint_shading(vec3 wo, vec3 wi, vec3 ns, vec3 ng) {
  float den = max(abs(dot(wo, ng)), 1e-4) * max(abs(dot(wi, ns)), 1e-4);
  return abs(dot(wo, ns)) * abs(dot(wi, ng)) / den;
}

// Steps (cos theta, phi) by h in the eq.-8-scaled parameters (tests'
// finite differences): cos theta += h sin theta, phi += h / sin theta.
void pb_stencil_step(uint member, float h, inout float c, inout float sn, inout float phi) {
  if (member == 1u) {
    c = clamp(c + h * sn, -1.0, 1.0);
    sn = sqrt(max(0.0, 1.0 - c * c));
  } else if (member == 2u) {
    phi += h / pb_guard_div(sn, 1e-6);
  }
}

// Derivative of the shading normal n (as the BSDF uses it: interpolated
// from the vertex normals, flipped to the photon's side) along the hit's
// positional differential dP (Igehy 1999 section 3.3): dP = db1 e1 + db2 e2
// in the triangle's plane gives the barycentric steps, the unnormalised
// m = n0 + b1 (n1 - n0) + b2 (n2 - n0) changes by dm, and
// dn = (dm - (dm.n) n) / |m|. Zero on flat-shaded triangles.
vec3 pb_diff_dn(uint prim, float u, float v, vec3 n, vec3 dP) {
  if (!SC_HAS_NORMALS) return vec3(0.0);
  uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
  vec3 p0 = pb_position(i0), e1 = pb_position(i1) - p0, e2 = pb_position(i2) - p0;
  vec3 ng = cross(e1, e2);
  float g = dot(ng, ng);
  if (!(g > 0.0) || isinf(g)) return vec3(0.0);
  float db1 = dot(cross(dP, e2), ng) / g, db2 = dot(cross(e1, dP), ng) / g;
  vec3 n0 = vec3(normals[3u * i0], normals[3u * i0 + 1u], normals[3u * i0 + 2u]);
  vec3 n1 = vec3(normals[3u * i1], normals[3u * i1 + 1u], normals[3u * i1 + 2u]);
  vec3 n2 = vec3(normals[3u * i2], normals[3u * i2 + 1u], normals[3u * i2 + 2u]);
  vec3 m = n0 * (1.0 - u - v) + n1 * u + n2 * v;
  float l = length(m);
  if (!(l > 1e-12) || isinf(l)) return vec3(0.0);
  vec3 mn = m / l, dm = (n1 - n0) * db1 + (n2 - n0) * db2;
  vec3 dn = (dm - dot(dm, mn) * mn) / l;
  dn = dot(mn, n) < 0.0 ? -dn : dn;
  return pb_finite3(dn) ? dn : vec3(0.0);
}

// RSM first bounce (seed 001 24.2.1): photon j of the n = pl.count photons
// of light entry li warps a stratified 2-D point down the light's pyramid of
// reflected power (hierarchical warp, common/rsm_texel.glsl pb_rsm_warp):
// texel i is picked with p_i = weight_i / total, receives n p_i photons in
// expectation (several when n exceeds the map), and the point's remainder is
// a uniform position within the texel. The photon traces the ray from the
// light through that position and carries the flux density there times the
// texel's measure over n p_i: unbiased (E[sum] = the texel's flux) wherever
// p_i > 0, with one texel's photons spread over its footprint. The path
// starts at that first hit (direct light, not stored) and continues by BRDF
// sampling like a traced one.
//
// Differentials. In the traced emission a photon stands for Omega / n_i of
// the light's solid angle (see the header: unit eq.-8 differentials scaled
// by sqrt(Omega / n_i) / Delta). Here texel i, of solid angle Omega_i
// (cube/perspective texel, exact), is covered by n p_i photons, so each one
// stands for Omega_i / (n p_i) steradians: its emission spacing is
// sqrt(Omega_i / (n p_i)) and, with the same global Delta, dDu, dDv are
// unit vectors orthogonal to the texel's direction scaled by
// k_i = sqrt(Omega_i / (n p_i)) / Delta (dP = 0 at the light; the transfer
// to the texel's hit gives the footprint there, the texel's world footprint
// divided by sqrt(n p_i) per axis). Directional maps: texel area A_i,
// dP = k_i (t, b) with k_i = sqrt(A_i / (n p_i)) / Delta and dD = 0. With
// uniform p_i = Omega_i / Omega this is the traced sqrt(Omega / n_i).
bool pb_rsm_emit(uint li, uint j, uint n, uint path, out vec3 o, out vec3 d, out vec3 power, out vec3 dPu,
                 out vec3 dPv, out vec3 dDu, out vec3 dDv, out uint prim, out float t, out float u,
                 out float v) {
  pb_gpu_rsm_light rl = rlights[li];
  o = d = power = dPu = dPv = dDu = dDv = vec3(0.0);
  prim = PB_GPU_MISS;
  t = u = v = 0.0;
  if (!(rl.total > 0.0) || rl.count == 0u) return false;
  // A stratified point of the unit square for photon j of n: (j + xi) / n
  // and the radical inverse of j turned by this iteration's offset
  // (Hammersley, Cranley-Patterson rotated), warped down the pyramid.
  float su = (float(j) + pb_prand(path, 0u)) / float(n);
  float sv = fract(float(bitfieldReverse(j)) * 2.3283064e-10 + pb_rand(0u, params.iteration, PB_RSM_ROTATION_DIM));
  uint lo = pb_rsm_warp(rl, su, sv);
  pb_gpu_rsm_texel tx = rtexels[rl.first + lo];
  if (!(tx.weight > 0.0)) return false;
  float np = float(n) * (tx.weight / rl.total);
  // The warp's remainder is a uniform point of the texel: the ray through it
  // and its first hit; the photon carries the flux density there times the
  // texel's measure, over n p_i.
  vec3 dens;
  float measure;
  pb_rsm_texel_point(rl, lo, vec2(su, sv), params.scene_center, params.scene_radius, o, d, dens, measure);
  power = dens * (measure / np);
  prim = pb_photon_trace(o, d, t, u, v);
  if (prim == PB_GPU_MISS || !(pb_max3(power) > 0.0)) return false;
  float k = sqrt(tx.area / np) / params.delta;
  vec3 tt, bb;
  pb_basis(d, tt, bb);
  if (lights[rl.light].type == PB_GPU_LIGHT_DIRECTIONAL) {
    dPu = k * tt;
    dPv = k * bb;
  } else {
    dDu = k * tt;
    dDv = k * bb;
  }
  return pb_finite3(power) && pb_finite3(dPu + dDu + dPv + dDv);
}

void pb_trace_path(uint gid) {
  uint path = gid, member = 0u;
  float h = params.stencil_h;
  if (h > 0.0) {
    path = gid / 3u;
    member = gid % 3u;
  }
  uint li = 0u;
  for (uint i = 1u; i < params.light_count; ++i)
    if (gid >= plights[i].first) li = i;
  pb_gpu_photon_light pl = plights[li];
  if (gid < pl.first || gid - pl.first >= pl.count) return;
  bool world_entry = pl.light == PB_GPU_WORLD_LIGHT;
  bool emitter_entry = pl.light == PB_GPU_EMITTER_LIGHT;
  // The world has no entry in lights[] (which may be empty): L is read only
  // for a light.
  pb_gpu_light L = pb_gpu_light(vec3(0.0), PB_GPU_LIGHT_DIRECTIONAL, vec3(0.0, -1.0, 0.0), 0.0, vec3(0.0), 0.0,
                                vec3(0.0), 0.0, vec3(0.0), 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 1.0, 0u, 0u);
  if (!world_entry && !emitter_entry) L = lights[pl.light];
  bool soft = (SC_WORLD && world_entry) || (SC_SOFT_LIGHTS && !world_entry && pb_light_is_soft(L));
  float k = pl.diff_scale;
  float u1 = pb_prand(path, 0u), u2 = pb_prand(path, 1u);
  vec3 power = pl.power;
  vec3 o, d, dPu = vec3(0.0), dPv = vec3(0.0), dDu = vec3(0.0), dDv = vec3(0.0);
  bool stencil_here = h > 0.0 && params.stencil_depth == 0u;
  bool rsm = (params.flags & PB_PHOTON_PARAM_RSM) != 0u && !soft && !emitter_entry;
  // --first-bounce auto: the map only for a light whose map covers less than
  // PB_RSM_AUTO_COVERAGE of its flux (photon_rsm.comp pb_rsm_total): there
  // a traced first bounce loses more than half of its photons to rays that
  // miss the scene and the map puts more than twice the photons on every
  // lit surface (1 / c: 20x on ring); where the map covers more (closed
  // rooms: c = 1) the gain is under 2x and the map's loss of geometry
  // thinner than a texel (photon_rsm.comp) is not worth it, so the light is
  // traced as by default. Both are unbiased per light; lights may differ.
  if (rsm && (params.flags & PB_PHOTON_PARAM_RSM_AUTO) != 0u && !(rlights[li].coverage < PB_RSM_AUTO_COVERAGE))
    rsm = false;
  uint first_prim = PB_GPU_MISS;
  float first_t = 0.0, first_u = 0.0, first_v = 0.0;
  if (rsm) {
    if (!pb_rsm_emit(li, gid - pl.first, pl.count, path, o, d, power, dPu, dPv, dDu, dDv, first_prim, first_t,
                     first_u, first_v))
      return;
  } else if (SC_EMISSIVE && emitter_entry) {
    // An emissive triangle as an area light (derived here; the seeds emit
    // from lights only): triangle i with the table's probability pick_i
    // (area x luminance x sides, scene/emitters.h), a uniform point, a side
    // it emits from (both with equal odds when double-sided), a cosine-
    // weighted direction: pdf = pick_i / A_i x cos / pi x 1 / sides, so the
    // photon carries L_e(x) cos / pdf / N = L_e(x) pi A_i sides / (pick_i N)
    // (pl.power = pi / N). The pick's remainder chooses the side.
    uint lo = 0u, hi = pl.emitters;
    if (hi == 0u) return;
    while (hi - lo > 1u) {
      uint mid = (lo + hi) / 2u;
      if (emitters[mid].cdf <= u1) lo = mid;
      else hi = mid;
    }
    pb_gpu_emitter e = emitters[lo];
    if (!(e.pick > 0.0) || !(e.area > 0.0)) return;
    pb_gpu_material em = materials[tri_material[e.prim]];
    bool two = (em.flags & PB_GPU_MAT_DOUBLE_SIDED) != 0u;
    bool back = two && clamp((u1 - e.cdf) / e.pick, 0.0, 1.0) >= 0.5;
    float su = sqrt(u2);
    float eu = pb_prand(path, PB_EMIT_DIM) * su, ev = 1.0 - su;
    uint i0 = indices[3u * e.prim], i1 = indices[3u * e.prim + 1u], i2 = indices[3u * e.prim + 2u];
    vec3 p0 = pb_position(i0), p1 = pb_position(i1), p2 = pb_position(i2);
    vec3 ng = normalize(cross(p1 - p0, p2 - p0));
    if (back) ng = -ng;
    pb_surface es = pb_surface_from_hit(e.prim, eu, ev, -ng);
    vec3 le = pb_emission(es);
    power *= le * (e.area * (two ? 2.0 : 1.0) / e.pick);
    vec3 t, b;
    pb_basis(ng, t, b);
    float v = pb_prand(path, PB_EMIT_DIM + 1u), phi = 2.0 * PB_PI * pb_prand(path, PB_EMIT_DIM + 2u);
    float sn = sqrt(v);
    d = t * (cos(phi) * sn) + b * (sin(phi) * sn) + ng * sqrt(max(0.0, 1.0 - v));
    o = pb_offset_ray(es.p, ng);
    dDu = k * t;
    dDv = k * b;
  } else if (world_entry || L.type == PB_GPU_LIGHT_DIRECTIONAL) {
    float v1 = u1, v2 = u2;
    if (world_entry) {
      vec3 w;
      float pw;
      if (!pb_world_sample(u1, u2, w, pw)) return;
      d = -w;
      power *= pb_world_radiance(w) / pw;
      v1 = pb_prand(path, PB_EMIT_DIM), v2 = pb_prand(path, PB_EMIT_DIM + 1u);
    } else if (soft) {
      vec3 wi, Ls;
      float dist, pdf;
      if (!pb_soft_light_sample(L, params.scene_center, u1, u2, wi, dist, Ls, pdf)) return;
      d = -wi; // radiance / density = E: pl.power holds it
      v1 = pb_prand(path, PB_EMIT_DIM), v2 = pb_prand(path, PB_EMIT_DIM + 1u);
    } else {
      d = normalize(L.direction);
    }
    vec3 t, b;
    pb_basis(d, t, b);
    float r = params.scene_radius * sqrt(v1), phi = 2.0 * PB_PI * v2;
    vec2 xy = r * vec2(cos(phi), sin(phi));
    if (stencil_here && member == 1u) xy.x += h * k;
    if (stencil_here && member == 2u) xy.y += h * k;
    o = params.scene_center + t * xy.x + b * xy.y - d * (1.01 * params.scene_radius);
    dPu = k * t;
    dPv = k * b;
  } else if (L.type == PB_GPU_LIGHT_AREA) {
    float wt;
    if (!pb_area_light_emit(L, u1, u2, pb_prand(path, PB_EMIT_DIM), pb_prand(path, PB_EMIT_DIM + 1u), o, d, wt))
      return;
    power *= pb_spread_factor(L, dot(d, L.direction)); // wt / (A pi cos^2 a): pl.power holds the rest
    // Directional differentials as from a point emitting into the cone
    // (the host's diff_scale counts its solid angle).
    vec3 t, b;
    pb_basis(d, t, b);
    dDu = k * t;
    dDv = k * b;
  } else {
    vec3 axis, t, b;
    if (L.type == PB_GPU_LIGHT_SPOT) {
      axis = normalize(L.direction);
      pb_basis(axis, t, b);
    } else {
      axis = vec3(0.0, 0.0, 1.0);
      t = vec3(1.0, 0.0, 0.0);
      b = vec3(0.0, 1.0, 0.0);
    }
    float c = 1.0 - u1 * (1.0 - pl.cos_max);
    float sn = sqrt(max(0.0, 1.0 - c * c));
    float phi = 2.0 * PB_PI * u2;
    if (stencil_here) pb_stencil_step(member, h * k, c, sn, phi);
    d = t * (cos(phi) * sn) + b * (sin(phi) * sn) + axis * c;
    pb_diff_emission_dirs(t, b, axis, c, sn, phi, dDu, dDv);
    dDu *= k;
    dDv *= k;
    if (L.type == PB_GPU_LIGHT_SPOT) power *= pb_spot_factor(L, c);
    o = L.position;
    if (soft) o = pb_sphere_light_origin(L, d, pb_prand(path, PB_EMIT_DIM), pb_prand(path, PB_EMIT_DIM + 1u));
  }
  if (!(pb_max3(power) > 0.0)) return;

  bool caustic = true; // only delta interactions so far
  uint stored = 0u;
  vec3 sigma = vec3(0.0); // absorbing medium the photon is in
  for (uint depth = 0u; depth < params.max_depth; ++depth) {
    float t, u, v;
    uint prim;
    if (rsm && depth == 0u) {
      prim = first_prim; // the texel's hit
      t = first_t;
      u = first_u;
      v = first_v;
    } else {
      prim = pb_photon_trace(o, d, t, u, v);
    }
    if (prim == PB_GPU_MISS) {
      atomicAdd(params.escaped, 1u);
      return;
    }
    power *= pb_medium_transmittance(sigma, t); // Beer-Lambert (KHR_materials_volume)
    // No normal map here (pb_apply_normal_map is not called): photons bounce
    // with the interpolated vertex normal as before. The density of photons
    // arriving on a surface already carries the geometric cosine (seed 001,
    // 24.4.3: "surfaces with their geometry normals pointing toward the
    // incoming light direction have a higher probability of being hit by
    // photons"); the normal map's effect on the gathered indirect light is
    // restored afterwards by eq. 20 (src/render/estimate/shading_correction.c).
    pb_surface surf = pb_surface_from_hit(prim, u, v, d);
    pb_diff_transfer(dPu, dPv, dDu, dDv, d, t, surf.ng);
    vec3 wo = -d;
    pb_bsdf b = pb_bsdf_setup_t(surf, wo, pb_surface_tangent(prim, u, v));
    if ((depth >= 1u || (params.flags & PB_PHOTON_PARAM_STORE_FIRST) != 0u) && pb_bsdf_has_smooth(b)) {
      pb_store(surf.p, surf.ng, wo, power, dPu, dPv, caustic, depth, gid, t);
      if (++stored >= params.max_bounces) return;
    }
    float cos_o = dot(wo, b.n);
    if (!(cos_o > 0.0)) return;
    uint dim = 2u + 4u * depth;
    float uc = pb_prand(path, dim), s1 = pb_prand(path, dim + 1u), s2 = pb_prand(path, dim + 2u);
    float ur = pb_prand(path, dim + 3u);
    bool stencil_now = h > 0.0 && params.stencil_depth == depth + 1u;
    vec4 l = pb_lobes(b, cos_o);
    float p_smooth = l.x + (b.delta_spec ? 0.0 : l.y);
    vec3 w, wi;
    bool transmit = false;
    if (SC_BLENDER && b.model != PB_GPU_MODEL_GLTF) {
      // A Blender material: its whole BSDF sampled (principled.glsl), the
      // adjoint of refraction for importance. Differentials: delta
      // reflections and refractions transfer as specular ones, a
      // transparent pass leaves them, any other lobe re-emits them as the
      // diffuse branch below does.
      uint rng = pb_walk_seed(path, params.iteration, 0x70000000u + depth);
      float pdf;
      bool delta;
      if (!pb_blender_sample(b, wo, uc, s1, s2, true, rng, wi, w, pdf, delta, transmit)) return;
      bool straight = dot(wi, d) > 0.99999;
      if (delta && straight) {
        // transparency: nothing bends
      } else if (delta && !transmit) {
        pb_diff_reflect(dDu, dDv, d, b.n, pb_diff_dn(prim, u, v, b.n, dPu), pb_diff_dn(prim, u, v, b.n, dPv));
      } else if (delta) {
        float ior_m = max(materials[surf.mat].in_value[PB_GPU_IN_IOR], 1e-5);
        float eta = surf.front ? 1.0 / ior_m : ior_m;
        pb_diff_refract(dDu, dDv, d, b.n, pb_diff_dn(prim, u, v, b.n, dPu), pb_diff_dn(prim, u, v, b.n, dPv), eta,
                        cos_o, abs(dot(wi, b.n)));
      } else {
        float c = clamp(dot(wi, b.n), -1.0, 1.0), sn = sqrt(max(0.0, 1.0 - c * c));
        float phi = atan(dot(wi, b.b), dot(wi, b.t));
        vec3 nu, nv;
        pb_diff_emission_dirs(b.t, b.b, b.n, abs(c), sn, phi, nu, nv);
        pb_diff_reemit(dPu, dPv, nu, nv);
        dDu = nu;
        dDv = nv;
        caustic = false;
        w *= pb_adjoint_shading(wo, wi, b.n, surf.ng);
      }
    } else if (uc < p_smooth) {
      float c = sqrt(max(0.0, 1.0 - s1)), sn = sqrt(s1), phi = 2.0 * PB_PI * s2;
      if (stencil_now) pb_stencil_step(member, h, c, sn, phi);
      vec3 lw = vec3(sn * cos(phi), sn * sin(phi), c);
      wi = b.t * lw.x + b.b * lw.y + b.n * lw.z;
      if (!(lw.z > 0.0) || dot(wi, b.ng) <= 0.0) return;
      uint no_rng = 0u; // glTF materials evaluate deterministically
      // The adjoint: light arrives from wo and leaves along wi, so wi is the
      // BSDF's outgoing ("view") direction and wo its light direction,
      // f(wi <- wo). The glTF model is not symmetric: its diffuse weight
      // kd = 1 - F(cos of the view direction) (pb_lobes), and with the
      // arguments the other way round a photon was weighted by the Fresnel
      // of its arrival, not of its departure: measured on a closed box of
      // albedo 0.6 around a point light (tests/estimator_check.py furnace),
      // +2.2 % indirect against the reference (light arriving near the
      // normal, F ~ F0, kept more than the cosine-weighted mean 1 - F it
      // leaves with), and +2.9 % at 4x the photons: a bias, not noise.
      w = pb_bsdf_eval(b, wi, wo, no_rng) * (PB_PI / p_smooth) * pb_adjoint_shading(wo, wi, b.n, surf.ng);
      vec3 nu, nv;
      pb_diff_emission_dirs(b.t, b.b, b.n, c, sn, phi, nu, nv);
      pb_diff_reemit(dPu, dPv, nu, nv);
      dDu = nu;
      dDv = nv;
      caustic = false;
    } else if (SC_SPECULAR && b.delta_spec && uc < l.x + l.y) {
      wi = reflect(d, b.n);
      if (dot(wi, b.ng) <= 0.0) return;
      w = pb_spec_fresnel(b, cos_o) / l.y;
      pb_diff_reflect(dDu, dDv, d, b.n, pb_diff_dn(prim, u, v, b.n, dPu), pb_diff_dn(prim, u, v, b.n, dPv));
    } else if (SC_SPECULAR && SC_TRANSMISSION && l.z > 0.0) {
      float eta = b.entering ? 1.0 / b.ior : b.ior;
      float cos_t;
      float F = pb_fresnel_dielectric(cos_o, eta, cos_t);
      float ug = (uc - l.x - l.y) / l.z;
      float kg = (1.0 - b.metallic) * b.transmission / l.z;
      if (ug < F) {
        wi = reflect(d, b.n);
        if (dot(wi, b.ng) <= 0.0) return;
        w = vec3(kg);
        pb_diff_reflect(dDu, dDv, d, b.n, pb_diff_dn(prim, u, v, b.n, dPu), pb_diff_dn(prim, u, v, b.n, dPv));
      } else {
        wi = normalize(eta * d + (eta * cos_o - cos_t) * b.n);
        if (dot(wi, b.ng) >= 0.0) return;
        w = b.base * kg;
        transmit = true;
        pb_diff_refract(dDu, dDv, d, b.n, pb_diff_dn(prim, u, v, b.n, dPu), pb_diff_dn(prim, u, v, b.n, dPv), eta,
                        cos_o, cos_t);
      }
    } else {
      return;
    }
    // Russian roulette on the max power ratio (seed 001 eq. 1). From the
    // 8th interaction on (depth 7: where the old default of 7 stored
    // bounces truncated) survival is capped at 0.95, so every path ends
    // geometrically even on white walls or between mirrors and the bounce
    // cap (params.max_bounces, 255 by default; src/render/photon/photon.h) is a
    // safety net, not a truncation: E[Phi'] = p Phi w / p = Phi w stays
    // unbiased. Shorter paths draw as before.
    float pmax = pb_max3(power);
    float q = pb_max3(power * w) / pmax;
    float p = min(depth >= 7u ? 0.95 : 1.0, q);
    if (!(p > 0.0) || ur >= p) {
      atomicAdd(params.absorbed, 1u);
      return;
    }
    power *= w / p;
    if (p < 1.0) {
      float g = inversesqrt(p);
      dPu *= g;
      dPv *= g;
      dDu *= g;
      dDv *= g;
    }
    if (!pb_finite3(power) || !pb_finite3(wi)) {
      pb_diff_guarded++;
      return;
    }
    sigma = pb_medium_after(sigma, surf, transmit);
    o = pb_offset_ray(surf.p, transmit ? -surf.ng : surf.ng);
    d = wi;
  }
}

void main() {
  uint gid = pb_gid();
  if (gid >= params.photons) return;
  atomicAdd(counts.emitted, 1u);
  pb_trace_path(gid);
  if (pb_diff_guarded > 0u) atomicAdd(params.guarded, pb_diff_guarded);
}
