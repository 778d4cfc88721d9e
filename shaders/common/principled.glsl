// The Blender materials on the GPU: the same functions as the reference's
// src/ref/principled.c (read that file's header for what Cycles 3.4 does
// and where we sample differently), in the same order and with the same
// names. Included by bsdf.glsl after the pb_closure / pb_bsdf structs; all of
// it is behind SC_BLENDER (scene.glsl), so glTF scenes compile it out.
#ifndef PB_PRINCIPLED_GLSL
#define PB_PRINCIPLED_GLSL

#include "shared/pb_principled2_tables.h"
#include "shared/pb_thin_film.h"

// The input loops below are kept as loops ([[dont_unroll]]): each of their
// iterations may read a texture, and a driver that unrolls them (Mesa's NIR
// does, for a loop that indexes a local array) inlines one bilinear lookup
// per input, which made pipeline creation of a textured Principled v2 scene
// take minutes on lavapipe.
#extension GL_EXT_control_flow_attributes : require

const float PB_CUTOFF = 1e-5;           // CLOSURE_WEIGHT_CUTOFF
const float PB_SINGULAR_ALPHA2 = 1e-7;  // alpha_x alpha_y at or below: a delta lobe

// A small per-evaluation random stream (PCG, O'Neill 2014) for the
// Multiscatter GGX walk; seeded from pb_rand's hash by the caller.
float pb_walk_rand(inout uint st) {
  st = st * 747796405u + 2891336453u;
  uint w = ((st >> ((st >> 28u) + 4u)) ^ st) * 277803737u;
  w = (w >> 22u) ^ w;
  return float(w >> 8) * (1.0 / 16777216.0);
}

float pb_avg3(vec3 c) { return (c.x + c.y + c.z) * (1.0 / 3.0); }
float pb_luma709(vec3 c) { return dot(c, vec3(0.2126729, 0.7151522, 0.0721750)); }
float pb_schlick_w(float u) {
  float m = clamp(1.0 - u, 0.0, 1.0), m2 = m * m;
  return m2 * m2 * m;
}

float pb_fresnel_diel(float cos_i, float eta) {
  float c = abs(cos_i);
  float g = eta * eta - 1.0 + c * c;
  if (g <= 0.0) return 1.0;
  g = sqrt(g);
  float a = (g - c) / (g + c);
  float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

vec3 pb_fresnel_v1(vec3 l, vec3 h, float ior, float f0, vec3 cspec0) {
  float t = (pb_fresnel_diel(dot(l, h), ior) - f0) / (1.0 - f0);
  return cspec0 * (1.0 - t) + vec3(t);
}

// Cycles' ensure_valid_reflection; see principled.c. Written with one
// exit: glslc 2023.2's optimizer (spirv-opt's block merging) crashes on the
// early-return form once it is inlined into the eye-path loops.
vec3 pb_valid_reflection_normal(vec3 ng, vec3 i, vec3 n) {
  vec3 r = n * (2.0 * dot(n, i)) - i;
  float t = min(0.9 * dot(ng, i), 0.01);
  vec3 res = n;
  if (dot(ng, r) < t) {
    vec3 x = normalize(n - ng * dot(n, ng));
    float ix = dot(i, x), iz = dot(i, ng);
    float a = ix * ix + iz * iz;
    float b = sqrt(max(0.0, ix * ix * (a - t * t)));
    float c = iz * t + a;
    float z1 = 0.5 / a * (b + c), z2 = 0.5 / a * (c - b);
    bool ok1 = z1 > 1e-5 && z1 <= 1.0 + 1e-5, ok2 = z2 > 1e-5 && z2 <= 1.0 + 1e-5;
    float n1x = sqrt(max(0.0, 1.0 - z1)), n1z = sqrt(max(0.0, z1));
    float n2x = sqrt(max(0.0, 1.0 - z2)), n2z = sqrt(max(0.0, z2));
    float r1 = 2.0 * (n1x * ix + n1z * iz) * n1z - iz, r2 = 2.0 * (n2x * ix + n2z * iz) * n2z - iz;
    bool v1 = r1 >= 1e-5, v2 = r2 >= 1e-5;
    float both = (v1 && v2) ? (r1 < r2 ? z1 : z2) : (r1 > r2 ? z1 : z2);
    float nz2 = ok1 && ok2 ? both : (ok1 ? z1 : z2);
    res = ok1 || ok2 ? x * sqrt(max(0.0, 1.0 - nz2)) + ng * sqrt(max(0.0, nz2)) : ng;
  }
  return res;
}

// Cycles' bump shadowing by Blender version (PB_GPU_BUMP_*; the
// reference's bump_shadowing has the sources): Chiang et al. 2019 up to
// 4.4, Conty Estevez et al. 2019 GGX shadowing from 4.5, only the
// wrong-side test with Bump Map Correction off.
float pb_bump_shadowing(uint model, vec3 ns, vec3 n, vec3 wi) {
  float cgi = dot(ns, wi), cgn = dot(ns, n), cni = dot(n, wi);
  if (model == PB_GPU_BUMP_CONTY) {
    if (cgi * cgn * cni < 0.0) return 0.0;
    float ci = abs(cgi), cd = abs(cgn);
    if (cd >= 1.0 || ci >= 1.0) return 1.0;
    if (ci < 1e-6) return 0.0;
    float a2 = clamp(0.125 * (1.0 / (cd * cd) - 1.0), 0.0, 1.0);
    float lambda = 0.5 * (sqrt(1.0 + a2 * max(1.0 / (ci * ci) - 1.0, 0.0)) - 1.0);
    return 1.0 / (1.0 + lambda);
  }
  vec3 g = cni < 0.0 ? -ns : ns;
  float den = cni * dot(g, n);
  float x = den != 0.0 ? dot(g, wi) / den : 0.0;
  if (x >= 1.0) return 1.0;
  if (x < 0.0) return 0.0;
  if (model == PB_GPU_BUMP_NONE) return 1.0;
  float x2 = x * x;
  return -x2 * x + x2 + x;
}

void pb_lobe_frame(inout pb_closure c, vec3 n, vec3 t) {
  c.n = n;
  vec3 y = cross(n, t);
  float l = length(y);
  if (l > 1e-6 && !isinf(l) && !isnan(l)) {
    c.y = y / l;
    c.x = cross(c.y, n);
  } else {
    pb_basis(n, c.x, c.y);
  }
}
// Cycles' rotate_around_axis: tangent t turned about axis n by `turns`
// full turns (Rodrigues), as the Anisotropic Rotation inputs turn it.
vec3 pb_turn_tangent(vec3 t, vec3 n, float turns) {
  if (turns == 0.0) return t;
  float th = turns * 2.0 * PB_PI, cs = cos(th), sn = sin(th);
  return t * cs + cross(n, t) * sn + n * (dot(n, t) * (1.0 - cs));
}
vec3 pb_to_lobe(pb_closure c, vec3 w) { return vec3(dot(w, c.x), dot(w, c.y), dot(w, c.n)); }
vec3 pb_from_lobe(pb_closure c, vec3 l) { return c.x * l.x + c.y * l.y + c.n * l.z; }

// ---- GGX --------------------------------------------------------------------

float pb_ggx_d_aniso(vec3 m, float ax, float ay) {
  if (m.z <= 0.0) return 0.0;
  float sx = m.x / ax, sy = m.y / ay;
  float k = sx * sx + sy * sy + m.z * m.z;
  return 1.0 / (PB_PI * ax * ay * k * k);
}
float pb_ggx_g1(vec3 w, float ax, float ay) {
  float c2 = w.z * w.z;
  if (c2 <= 0.0) return 0.0;
  float s2 = w.x * w.x + w.y * w.y;
  float a2 = s2 > 0.0 ? (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / s2 : ax * ay;
  return 2.0 / (1.0 + sqrt(max(0.0, 1.0 + a2 * (1.0 - c2) / c2)));
}
float pb_gtr1_d(float c, float a) {
  if (a >= 1.0) return PB_INV_PI;
  float a2 = a * a;
  return (a2 - 1.0) / (PB_PI * log(a2) * (1.0 + (a2 - 1.0) * c * c));
}
vec3 pb_ggx_vndf(vec3 v, float ax, float ay, float u1, float u2) {
  vec3 vh = normalize(vec3(ax * v.x, ay * v.y, v.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
  vec3 t2 = cross(vh, t1);
  float r = sqrt(u1), phi = 2.0 * PB_PI * u2;
  float p1 = r * cos(phi), p2 = r * sin(phi);
  float s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
  vec3 nh = t1 * p1 + t2 * p2 + vh * sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2));
  return normalize(vec3(ax * nh.x, ay * nh.y, max(1e-7, nh.z)));
}
vec3 pb_cosine_dir(float u1, float u2) {
  float r = sqrt(u1), phi = 2.0 * PB_PI * u2;
  return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
}

// ---- Multiscatter GGX random walk (principled.c multi_ggx_eval) -------------

float pb_mf_lambda(vec3 w, float ax, float ay) {
  if (w.z > 0.9999) return 0.0;
  if (w.z < -0.9999) return -0.9999;
  float inv = 1.0 / max(w.z * w.z, 1e-7);
  float wx = w.x * ax, wy = w.y * ay;
  float v = sqrt(1.0 + (wx * wx + wy * wy) * inv);
  if (w.z <= 0.0) v = -v;
  return 0.5 * (v - 1.0);
}
float pb_mf_c1(float h) { return clamp(0.5 * (h + 1.0), 0.0, 1.0); }
float pb_mf_inv_c1(float c) { return 2.0 * clamp(c, 0.0, 1.0) - 1.0; }
float pb_mf_g1(vec3 w, float c1, float lambda) {
  if (w.z > 0.9999) return 1.0;
  if (w.z < 1e-5) return 0.0;
  return pow(c1, lambda);
}
bool pb_mf_next_height(vec3 w, inout float h, inout float c1, inout float g1, float lambda, float u) {
  if (w.z > 0.9999) return false;
  if (w.z < -0.9999) {
    c1 *= u;
    h = pb_mf_inv_c1(c1);
    g1 = pb_mf_g1(w, c1, lambda);
  } else if (abs(w.z) >= 1e-4) {
    if (u > 1.0 - g1) return false;
    c1 = lambda >= 0.0 ? 1.0 : c1 * pow(1.0 - u, -1.0 / lambda);
    h = pb_mf_inv_c1(c1);
    g1 = pb_mf_g1(w, c1, lambda);
  }
  return true;
}
vec3 pb_walk_vndf(vec3 v, float ax, float ay, float u1, float u2) {
  vec3 s = normalize(vec3(ax * v.x, ay * v.y, v.z));
  float sx, sy;
  if (s.z > 0.9999 || abs(s.z) < 1e-6) {
    float r = sqrt(u1 / max(1.0 - u1, 1e-7)), phi = 2.0 * PB_PI * u2;
    sx = r * cos(phi);
    sy = r * sin(phi);
  } else {
    float sin_t = sqrt(max(0.0, 1.0 - s.z * s.z)), tan_t = sin_t / s.z;
    float proj = 0.5 * (s.z + 1.0);
    if (proj < 1e-4) return vec3(0.0, 0.0, 1.0);
    float a = 2.0 * u1 * proj / s.z - 1.0;
    float q = a * a - 1.0;
    if (abs(q) < 1e-7) return vec3(0.0, 0.0, 1.0);
    q = 1.0 / q;
    float d = sqrt(max(0.0, tan_t * tan_t * q * q - (a * a - tan_t * tan_t) * q));
    float x2 = tan_t * q + d;
    sx = (a < 0.0 || x2 > 1.0 / tan_t) ? tan_t * q - d : x2;
    float sgn = u2 >= 0.5 ? 1.0 : -1.0, w = 2.0 * abs(u2 - 0.5);
    float z = (w * (w * (w * 0.27385 - 0.73369) + 0.46341)) / (w * (w * (w * 0.093073 + 0.309420) - 1.0) + 0.597999);
    sy = sgn * z * sqrt(1.0 + sx * sx);
  }
  float pl = sqrt(s.x * s.x + s.y * s.y);
  float cp = pl > 0.0 ? s.x / pl : 1.0, sp = pl > 0.0 ? s.y / pl : 0.0;
  float mx = ax * (cp * sx - sp * sy), my = ay * (sp * sx + cp * sy);
  return normalize(vec3(-mx, -my, 1.0));
}
float pb_mf_d(vec3 m, float ax, float ay) {
  if (ax == ay) {
    float z2 = m.z * m.z, a2 = ax * ax;
    float k = (1.0 - z2) + a2 * z2;
    return a2 / max(PB_PI * k * k, 1e-7);
  }
  float sx = -m.x / ax, sy = -m.y / ay;
  float k = m.z * m.z + sx * sx + sy * sy;
  return 1.0 / max(PB_PI * k * k * ax * ay, 1e-7);
}
float pb_mf_phase(vec3 w, float lambda, vec3 wo, float ax, float ay) {
  if (w.z > 0.9999) return 0.0;
  vec3 h = normalize(wo - w);
  if (h.z < 0.0) return 0.0;
  float area = w.z < -0.9999 ? 1.0 : lambda * w.z;
  float wh = -dot(w, h);
  if (wh < 0.0) return 0.0;
  return max(0.0, wh) * 0.25 / max(area * wh, 1e-7) * pb_mf_d(h, ax, ay);
}
vec3 pb_multi_ggx_eval(pb_closure c, vec3 wo, vec3 wi, inout uint rng) {
  vec3 a = wo, b = wi;
  bool swapped = false;
  if (b.z < a.z) {
    a = wi;
    b = wo;
    swapped = true;
  }
  if (a.z < 1e-5 || b.z < 1e-5) return vec3(0.0);
  float ax = c.ax, ay = c.ay;
  float lambda_r = pb_mf_lambda(-a, ax, ay);
  float shadow_lambda = pb_mf_lambda(b, ax, ay);
  vec3 h = normalize(a + b);
  float g2 = 1.0 / (1.0 - (lambda_r + 1.0) + shadow_lambda);
  float single = g2 * 0.25 / a.z * pb_mf_d(h, ax, ay);
  vec3 thr = pb_fresnel_v1(a, h, c.ior, c.f0, c.cspec0);
  vec3 eval = thr * single;
  vec3 wr = -a;
  float hr = 1.0, c1 = 1.0, g1 = 0.0;
  for (int order = 0; order < 10; ++order) {
    float uh = pb_walk_rand(rng);
    if (!pb_mf_next_height(wr, hr, c1, g1, lambda_r, uh)) break;
    float uy = pb_walk_rand(rng), ux = pb_walk_rand(rng);
    vec3 up = -wr;
    vec3 m = pb_walk_vndf(up, ax, ay, ux, uy);
    if (order > 0) {
      float ph = pb_mf_phase(wr, lambda_r, b, ax, ay) * pb_mf_g1(b, pb_mf_c1(hr), shadow_lambda);
      eval += thr * thr * ph;
    }
    if (order + 1 < 10) {
      if (order > 0) thr *= pb_fresnel_v1(up, m, c.ior, c.f0, c.cspec0);
      wr = m * (2.0 * dot(up, m)) - up;
      lambda_r = pb_mf_lambda(wr, ax, ay);
      c1 = pb_mf_c1(hr);
      g1 = pb_mf_g1(wr, c1, lambda_r);
    }
  }
  if (swapped) eval *= abs(a.z / b.z);
  return eval;
}
float pb_multi_ggx_albedo(float r) {
  float a = 0.806495 * exp(-1.98712 * r * r) + 0.199531;
  a -= ((((((1.76741 * r - 8.43891) * r + 15.784) * r - 14.398) * r + 6.45221) * r - 1.19722) * r + 0.027803) * r +
       0.00568739;
  return clamp(a, 0.0, 1.0);
}
float pb_multi_ggx_pdf(pb_closure c, vec3 wo, vec3 wi) {
  float d = pb_mf_d(normalize(wo + wi), c.ax, c.ay);
  float lambda = pb_mf_lambda(wo, c.ax, c.ay);
  float single = 0.25 * d / max((1.0 + lambda) * wo.z, 1e-7);
  float a = pb_multi_ggx_albedo(c.ax == c.ay ? c.ax : sqrt(c.ax * c.ay));
  return a * single + (1.0 - a) * max(wi.z, 0.0) * PB_INV_PI;
}

// Oren-Nayar as Cycles computes it (the reference's oren_nayar has the
// formulas): Fujii's a and b, and from Cycles 4.3 OpenPBR's multiple
// scattering, color = ms (1 - E(wo)), times (1 - E(wi)) in the evaluation.
float pb_oren_nayar_G(float c) {
  if (c < 1e-6) return (0.5 * PB_PI - 2.0 / 3.0) - c;
  float s = sqrt(max(0.0, 1.0 - c * c)), th = acos(min(c, 1.0));
  return s * (th - 2.0 / 3.0 - s * c) + 2.0 / 3.0 * (s / c) * (1.0 - s * s * s);
}
void pb_oren_nayar(inout pb_closure c, float sigma, vec3 albedo, bool ms, vec3 wo) {
  if (sigma <= 0.0) {
    c.on_a = PB_INV_PI; // bsdf_diffuse: Lambert
    return;
  }
  sigma = clamp(sigma, 0.0, 1.0);
  c.on_a = 1.0 / (PB_PI + sigma * (0.5 * PB_PI - 2.0 / 3.0));
  c.on_b = sigma * c.on_a;
  if (!ms) return;
  vec3 rho = clamp(albedo, 0.0, 1.0);
  float eavg = c.on_a * PB_PI + ((2.0 * PB_PI - 5.6) / 3.0) * c.on_b;
  float ev = c.on_a * PB_PI + c.on_b * pb_oren_nayar_G(max(dot(c.n, wo), 0.0));
  c.color = PB_INV_PI * (eavg / (1.0 - eavg)) * (1.0 - ev) * rho * rho / (1.0 - rho * (1.0 - eavg));
}

// ---- one closure ------------------------------------------------------------
// One function per lobe family, so that the per-slot evaluation below
// inlines each only where its slot can hold it (the slot loops unroll).

vec3 pb_eval_diffuse_like(pb_closure c, vec3 ns, uint bump, vec3 wo, vec3 wi, out float pdf) {
  pdf = 0.0;
  vec3 lo = pb_to_lobe(c, wo), li = pb_to_lobe(c, wi);
  if (li.z <= 0.0 || (c.type == PB_CL_SHEEN && lo.z < 0.0)) return vec3(0.0);
  float v;
  if (c.type == PB_CL_DIFFUSE) {
    float fo = pb_schlick_w(lo.z), fi = pb_schlick_w(li.z);
    float rr = c.rough * (dot(wi, wo) + 1.0);
    v = PB_INV_PI * li.z * ((1.0 - 0.5 * fo) * (1.0 - 0.5 * fi) + rr * (fi + fo + fi * fo * (rr - 1.0)));
  } else if (c.type == PB_CL_SHEEN) {
    v = pb_schlick_w(dot(wi, normalize(wi + wo))) * li.z;
  } else {
    float nv = max(lo.z, 0.0), t = dot(wi, wo) - li.z * nv;
    if (t > 0.0) t /= max(li.z, nv) + 1.17549435e-38;
    v = li.z * (c.on_a + c.on_b * t);
  }
  pdf = li.z * PB_INV_PI;
  vec3 f = vec3(v);
  if (c.type == PB_CL_OREN_NAYAR && c.on_b > 0.0) // multiple scattering (0 before Cycles 4.3)
    f += c.color * (li.z * (1.0 - c.on_a * PB_PI - c.on_b * pb_oren_nayar_G(li.z)));
  if (dot(c.n, ns) < 1.0 - 1e-6) f *= pb_bump_shadowing(bump, ns, c.n, wi);
  return f;
}

// GGX reflection or the GTR1 clearcoat.
vec3 pb_eval_reflect(pb_closure c, vec3 ng, vec3 wo, vec3 wi, out float pdf) {
  pdf = 0.0;
  vec3 lo = pb_to_lobe(c, wo), li = pb_to_lobe(c, wi);
  if (dot(ng, wi) < 0.0 || lo.z <= 0.0 || li.z <= 0.0) return vec3(0.0);
  vec3 m = normalize(lo + li);
  bool coat = c.type == PB_CL_CLEARCOAT;
  float d = coat ? pb_gtr1_d(m.z, c.ax) : pb_ggx_d_aniso(m, c.ax, c.ay);
  float ag = coat ? 0.25 : c.ax, bg = coat ? 0.25 : c.ay;
  float g1o = pb_ggx_g1(lo, ag, bg), g1i = pb_ggx_g1(li, ag, bg);
  vec3 f = pb_fresnel_v1(li, m, c.ior, c.f0, c.cspec0) * (coat ? 0.25 * c.clearcoat : 1.0);
  float cmn = d * 0.25 / lo.z;
  float wm = dot(lo, m);
  pdf = coat ? (wm > 0.0 ? d * m.z * 0.25 / wm : 0.0) : g1o * cmn;
  return f * (g1o * g1i * cmn);
}

vec3 pb_eval_multi(pb_closure c, vec3 ng, vec3 wo, vec3 wi, inout uint rng, out float pdf) {
  pdf = 0.0;
  vec3 lo = pb_to_lobe(c, wo), li = pb_to_lobe(c, wi);
  if (dot(ng, wi) < 0.0 || lo.z <= 0.0 || li.z <= 0.0) return vec3(0.0);
  float p = pb_multi_ggx_pdf(c, lo, li);
  if (!(p > 0.0)) return vec3(0.0);
  pdf = p;
  return pb_multi_ggx_eval(c, lo, li, rng);
}

vec3 pb_eval_refract(pb_closure c, vec3 ng, vec3 wo, vec3 wi, out float pdf) {
  pdf = 0.0;
  vec3 lo = pb_to_lobe(c, wo), li = pb_to_lobe(c, wi);
  if (dot(ng, wi) >= 0.0 || lo.z <= 0.0 || li.z >= 0.0) return vec3(0.0);
  float eta = c.ior;
  vec3 ht = -(li * eta + lo);
  float ht2 = dot(ht, ht);
  if (!(ht2 > 0.0)) return vec3(0.0);
  vec3 m = ht * inversesqrt(ht2);
  if (m.z < 0.0) m = -m;
  float d = pb_ggx_d_aniso(m, c.ax, c.ay);
  float g1o = pb_ggx_g1(lo, c.ax, c.ay), g1i = pb_ggx_g1(-li, c.ax, c.ay);
  float cmn = d * eta * eta / (lo.z * ht2);
  float hh = abs(dot(m, lo) * dot(m, li));
  pdf = g1o * hh * cmn;
  return vec3(g1o * g1i * hh * cmn);
}

// ---- setup ------------------------------------------------------------------

float pb_input_value(pb_gpu_material m, uint i, pb_surface s) {
  uint t = m.in_tex[i];
  if (!SC_TEXTURES || t == PB_GPU_NO_TEXTURE) return m.in_value[i];
  vec4 c = pb_texture_lookup(t & PB_GPU_INPUT_TEX_INDEX, s);
  uint ch = t >> PB_GPU_INPUT_TEX_CHANNEL_SHIFT;
  return ch == 0u ? c.r : (ch == 1u ? c.g : (ch == 2u ? c.b : (ch == 3u ? c.a : pb_luma709(c.rgb))));
}
// Every input at uv, in one loop (one texture fetch in the code instead of
// one per input: the shader stays small).
void pb_inputs(pb_gpu_material m, pb_surface s, out float v[PB_GPU_IN_SLOTS]) {
  [[dont_unroll]] for (uint i = 0u; i < PB_GPU_IN_V1_SLOTS; ++i) v[i] = pb_input_value(m, i, s);
  for (uint i = PB_GPU_IN_V1_SLOTS; i < PB_GPU_IN_SLOTS; ++i) v[i] = 0.0;
}

float pb_blender_alpha(pb_surface s) {
  return clamp(pb_input_value(materials[s.mat], PB_GPU_IN_ALPHA, s), 0.0, 1.0);
}

// Whether slot k's closures are compiled in (SC_CLOSURES, set from what the
// scene's materials can make; the transparent slot always is). A slot left
// out is never switched on, so no pass evaluates or samples it.
bool pb_slot_compiled(uint k) { return k >= PB_SLOT_TRANSPARENT || (SC_CLOSURES & (1u << k)) != 0u; }
bool pb_v1_compiled() { return (SC_CLOSURES & PB_CLOSURES_V1) != 0u; }
bool pb_multi_walk_compiled() { return (SC_CLOSURES & PB_CLOSURES_MULTI_WALK) != 0u; }

// Fills slot `slot` with a closure of `type` and colour weight `weight`,
// switched on when the weight averages at least the cutoff (bsdf_alloc).
void pb_add_closure(inout pb_bsdf b, uint slot, uint type, vec3 weight) {
  weight = max(weight, vec3(0.0));
  float sw = abs(pb_avg3(weight));
  pb_closure c;
  c.on = sw >= PB_CUTOFF && pb_slot_compiled(slot);
  c.type = type;
  c.weight = weight;
  c.sample_weight = c.on ? sw : 0.0;
  c.n = vec3(0.0, 0.0, 1.0);
  c.x = vec3(1.0, 0.0, 0.0);
  c.y = vec3(0.0, 1.0, 0.0);
  c.ax = c.ay = 1.0;
  c.ior = 1.0;
  c.f0 = 0.0;
  c.cspec0 = c.color = vec3(0.0);
  c.rough = c.on_a = c.on_b = c.clearcoat = 0.0;
  c.singular = c.stops = false;
  c.fresnel = PB_FR_DIELECTRIC;
  c.ttint = vec3(0.0);
  c.energy = 1.0;
  c.g2 = false;
  c.tf_d = 0.0;
  c.tf_ior = 1.0;
  c.beckmann = false;
  b.cl[slot] = c;
}

void pb_microfacet(inout pb_closure c, vec3 n, vec3 t, float ax, float ay, float ior, vec3 cspec0, vec3 wo) {
  pb_lobe_frame(c, n, t);
  c.ax = ax;
  c.ay = ay;
  c.ior = ior;
  c.f0 = pb_fresnel_diel(1.0, ior);
  c.cspec0 = clamp(cspec0, 0.0, 1.0);
  c.singular = ax * ay <= PB_SINGULAR_ALPHA2;
  if (c.type == PB_CL_GGX || c.type == PB_CL_MULTI_GGX || c.type == PB_CL_CLEARCOAT) {
    vec3 fc = pb_fresnel_v1(wo, n, ior, c.f0, c.cspec0);
    if (c.type == PB_CL_CLEARCOAT) fc *= 0.25 * c.clearcoat;
    c.sample_weight *= pb_avg3(fc);
  }
}


// ---- Principled v2 (Blender 4.x, Cycles 4.5) ---------------------------------
// What Cycles 4.5's svm/closure.h does for the v2 node, written again for the
// GPU (the reference's own code is principled.c "Principled v2"; the two
// share only the tables): transparency, microfiber sheen (LTC), GGX coat
// (dielectric Fresnel, always energy-compensated, Beer tint), emission under
// both, F82-tint metal, GGX glass and the dielectric specular on the
// generalized-Schlick real Fresnel curve, Lambert diffuse; layered by
// closure_layering_weight on tabulated albedos; Multiscatter GGX as Turquin
// energy compensation; height-correlated Smith G2. Slots: sheen SHEEN, coat
// CLEARCOAT, metal GLASS_REFL, glass GLASS_REFR, specular SPECULAR, diffuse
// DIFFUSE. Thin Film (4.2+) on the glass and the specular: pb2_thin_film.

// The table starting at float t (PB_P2T_*, shared/pb_principled2_tables.h)
// at i: the tables follow the texels in the same buffer, from texel index
// frame.principled2_base (src/render/scene/scene_gpu.c), only in scenes that have
// a v2 material; nothing else reads them.
float pb2_fetch(uint t, int i) { return uintBitsToFloat(texels[frame.principled2_base + t + uint(i)]); }
// Samples at k / (n - 1) over [0, 1], clamped; linear in between.
void pb2_axis(float x, int n, out int i, out int j, out float f) {
  x = clamp(x, 0.0, 1.0) * float(n - 1);
  i = min(int(x), n - 1);
  j = min(i + 1, n - 1);
  f = x - float(i);
}
float pb2_lut1(uint t, int off, float x, int n) {
  int i, j;
  float f;
  pb2_axis(x, n, i, j, f);
  return pb2_fetch(t, off + i) * (1.0 - f) + pb2_fetch(t, off + j) * f;
}
float pb2_lut2(uint t, int off, float x, float y, int nx, int ny) {
  int i, j;
  float f;
  pb2_axis(y, ny, i, j, f);
  return pb2_lut1(t, off + nx * i, x, nx) * (1.0 - f) + pb2_lut1(t, off + nx * j, x, nx) * f;
}
float pb2_lut3(uint t, float x, float y, float z) {  // the 16^3 tables
  int i, j;
  float f;
  pb2_axis(z, 16, i, j, f);
  return pb2_lut2(t, 256 * i, x, y, 16, 16) * (1.0 - f) + pb2_lut2(t, 256 * j, x, y, 16, 16) * f;
}

float pb2_f0(float eta) {
  float r = (eta - 1.0) / (eta + 1.0);
  return r * r;
}
float pb2_fss_dielectric(float eta) {
  return eta < 1.0 ? 0.997118 + eta * (0.1014 - eta * (0.965241 + eta * 0.130607)) : (eta - 1.0) / (4.08567 + 1.00071 * eta);
}

// Cycles 4.5 src/kernel/closure/bsdf_util.h fresnel_conductor: a conductor
// of complex IOR n + ik, per channel.
vec3 pb2_fresnel_conductor(float cosi, vec3 eta, vec3 k) {
  float cosi2 = cosi * cosi;
  vec3 tmp_f = eta * eta + k * k, tmp = tmp_f * cosi2;
  vec3 rparl2 = (tmp - 2.0 * eta * cosi + 1.0) / (tmp + 2.0 * eta * cosi + 1.0);
  vec3 rperp2 = (tmp_f - 2.0 * eta * cosi + cosi2) / (tmp_f + 2.0 * eta * cosi + cosi2);
  return 0.5 * (rparl2 + rperp2);
}

// Thin-film iridescence: Cycles 4.5 closure/bsdf_util.h fresnel_iridescence
// (Belcour and Barla 2017). Outside medium of index 1, a film of index e2
// and thickness d (nm), a base of index e3, all relative; both polarisations
// (x: s, y: p) side by side, the Airy sum to the third order, the XYZ
// sensitivities' Gaussian fit (shared/pb_thin_film.h), times the white
// point, to linear Rec.709, clamped.
//
// Interface of relative index eta at cos_i: squared amplitudes (s, p), phase
// shifts, transmitted cosine (negative, relative to the normal); false under
// total internal reflection (fresnel_dielectric_polarized).
bool pb2_tf_interface(float cos_i, float eta, out vec2 rr, out vec2 ph, out float cos_t) {
  rr = vec2(1.0);
  ph = vec2(0.0);
  cos_t = 0.0;
  float d = eta * eta - 1.0 + cos_i * cos_i;
  if (d <= 0.0) return false;
  float ci = abs(cos_i);
  cos_t = -sqrt(d) / eta;
  vec2 amp = vec2((ci + eta * cos_t) / (ci - eta * cos_t), (cos_t + eta * ci) / (eta * ci - cos_t));
  rr = amp * amp;
  ph = mix(vec2(0.0), vec2(PB_PI), lessThan(amp, vec2(0.0)));
  return true;
}

// iridescence_lookup_sensitivity: XYZ of path difference opd (nm), shift.
vec3 pb2_tf_sens(float opd, float shift) {
  float p = 2.0 * PB_PI * opd * 1e-9, p2 = p * p;
  const vec3 val = vec3(PB_TF_VAL_X, PB_TF_VAL_Y, PB_TF_VAL_Z);
  const vec3 pos = vec3(PB_TF_POS_X, PB_TF_POS_Y, PB_TF_POS_Z);
  const vec3 var = vec3(PB_TF_VAR_X, PB_TF_VAR_Y, PB_TF_VAR_Z);
  vec3 xyz = val * sqrt(2.0 * PB_PI * var) * cos(pos * p + shift) * exp(-p2 * var);
  xyz.x += PB_TF_X2_AMP * cos(PB_TF_X2_POS * p + shift) * exp(-PB_TF_X2_VAR * p2);
  return xyz * (1.0 / PB_TF_NORM);
}

// iridescence_airy_summation for one polarisation.
vec3 pb2_tf_airy(float t121, float r12, float r23, float opd, float phi) {
  if (r23 == 1.0) return vec3(1.0);
  float r123 = r12 * r23, q = sqrt(r123), rs = t121 * t121 * r23 / (1.0 - r123);
  vec3 sum = vec3(r12 + rs);
  float cm = rs - t121;
  for (int m = 1; m < 4; ++m) {
    cm *= q;
    sum += (2.0 * cm) * pb2_tf_sens(float(m) * opd, float(m) * phi);
  }
  return sum;
}

vec3 pb2_thin_film(float cos_i, float e2, float e3, float d) {
  if (d < PB_TF_BLEND_THICKNESS) e2 = mix(1.0, e2, smoothstep(0.0, PB_TF_BLEND_THICKNESS, d));
  vec2 r12, p12, r23, p23;
  float c2, c3;
  if (!pb2_tf_interface(cos_i, e2, r12, p12, c2) || all(equal(r12, vec2(1.0)))) return vec3(1.0);
  float opd = -2.0 * e2 * d * c2;
  if (!pb2_tf_interface(-c2, e3 / e2, r23, p23, c3) || all(equal(r23, vec2(1.0)))) return vec3(1.0);
  vec2 t121 = vec2(1.0) - r12, phi = vec2(PB_PI) - p12 + p23;
  vec3 xyz = 0.5 * (pb2_tf_airy(t121.x, r12.x, r23.x, opd, phi.x) + pb2_tf_airy(t121.y, r12.y, r23.y, opd, phi.y));
  xyz *= vec3(PB_TF_WHITE_X, PB_TF_WHITE_Y, PB_TF_WHITE_Z);
  // GLSL matrices are column-major: the rows of XYZ -> RGB as columns, transposed.
  const mat3 to_rgb = transpose(mat3(PB_TF_M00, PB_TF_M01, PB_TF_M02, PB_TF_M10, PB_TF_M11, PB_TF_M12,
                                     PB_TF_M20, PB_TF_M21, PB_TF_M22));
  return clamp(to_rgb * xyz, 0.0, 1.0);
}

// Reflectance r and transmittance t at cos between microfacet and view.
void pb2_fresnel(pb_closure c, float cos_hv, out vec3 r, out vec3 t) {
  t = vec3(0.0);
  if (c.fresnel == PB_FR_DIELECTRIC) {
    float f = pb_fresnel_diel(cos_hv, c.ior);
    r = vec3(f);
  } else if (c.fresnel == PB_FR_CONDUCTOR) {
    r = pb2_fresnel_conductor(cos_hv, c.cspec0, c.color);
  } else if (c.fresnel == PB_FR_NONE) {
    // The Glossy BSDF reflects everything; the Refraction BSDF transmits
    // everything but what total internal reflection keeps (then nothing).
    bool refraction = c.type == PB_CL_V2_GLASS;
    r = vec3(refraction ? 0.0 : 1.0);
    if (refraction && pb_fresnel_diel(cos_hv, c.ior) < 1.0) t = vec3(1.0);
  } else if (c.fresnel == PB_FR_F82_TINT) {
    float mu = clamp(1.0 - cos_hv, 0.0, 1.0);
    float mu5 = mu * mu * mu * mu * mu;
    r = clamp(mix(c.cspec0, vec3(1.0), mu5) - c.color * (cos_hv * mu5 * mu), 0.0, 1.0);
  } else if (c.tf_d > PB_TF_MIN_THICKNESS) {
    // The film (closure/bsdf_microfacet.h microfacet_fresnel): its
    // reflectance scaled per channel towards F0 / F0(ior) by how far it
    // lies from 1 towards F0(ior).
    r = pb2_thin_film(cos_hv, c.tf_ior, c.ior, c.tf_d);
    float f0r = pb2_f0(c.ior);
    if (f0r > 1e-5 && any(notEqual(r, vec3(1.0)))) {
      vec3 s = clamp((r - vec3(1.0)) / (f0r - 1.0), 0.0, 1.0);
      r *= mix(vec3(1.0), c.cspec0 / f0r, s);
    }
    if (c.type == PB_CL_V2_GLASS) t = (vec3(1.0) - r) * c.ttint;
  } else {
    float f0r = pb2_f0(c.ior);
    float s = clamp((pb_fresnel_diel(cos_hv, c.ior) - f0r) / (1.0 - f0r), 0.0, 1.0);
    r = mix(c.cspec0, vec3(1.0), s);
    if (c.type == PB_CL_V2_GLASS) t = (vec3(1.0) - r) * c.ttint;
  }
}

float pb2_lambda(vec3 w, float ax, float ay) {
  float z2 = w.z * w.z;
  if (!(z2 > 0.0)) return 1e30;
  return 0.5 * (sqrt(1.0 + (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2) - 1.0);
}

// Beckmann (closure/bsdf_microfacet.h bsdf_aniso_D, bsdf_lambda_from_sqr_alpha_tan_n:
// Walter et al. 2007's rational approximation of Smith's Lambda).
float pb2_beckmann_d(vec3 m, float ax, float ay) {
  float c2 = m.z * m.z;
  if (!(c2 > 0.0)) return 0.0;
  float sx = m.x / ax, sy = m.y / ay;
  return exp(-(sx * sx + sy * sy) / c2) / (PB_PI * ax * ay * c2 * c2);
}
float pb2_beckmann_lambda(vec3 w, float ax, float ay) {
  float z2 = w.z * w.z;
  if (!(z2 > 0.0)) return 1e30;
  float s = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
  if (s < 0.39) return 0.0;
  float a = inversesqrt(s);
  return ((0.396 * a - 1.259) * a + 1.0) / ((2.181 * a + 3.535) * a);
}
// A Beckmann microfacet normal drawn from D(m) cos(m) (Walter et al. 2007):
// the slopes are Gaussian, (ax, ay) sqrt(-ln(1 - u1)) (cos, sin)(2 pi u2).
vec3 pb2_beckmann_sample(float ax, float ay, float u1, float u2) {
  float r = sqrt(-log(max(1.0 - u1, 1e-30))), phi = 2.0 * PB_PI * u2;
  return normalize(vec3(-ax * r * cos(phi), -ay * r * sin(phi), 1.0));
}

vec3 pb_eval_v2(pb_closure c, vec3 ng, vec3 wo, vec3 wi, out float pdf) {
  pdf = 0.0;
  vec3 lo = pb_to_lobe(c, wo), li = pb_to_lobe(c, wi);
  if (c.type == PB_CL_VELVET) {
    // closure/bsdf_ashikhmin_velvet.h: f cos = D G / (4 cos_view), sampled
    // uniformly over the hemisphere.
    if (!(lo.z > 0.0 && li.z > 0.0)) return vec3(0.0);
    vec3 h = normalize(lo + li);
    float cnh = h.z, chi = abs(dot(lo, h));
    if (!(abs(cnh) < 1.0 - 1e-5 && chi > 1e-5)) return vec3(0.0);
    float q = max(cnh / chi, 1e-5);
    float sin2 = 1.0 - cnh * cnh, cot2 = cnh * cnh / sin2;
    float d = exp(-cot2 * c.on_a) * c.on_a * PB_INV_PI / (sin2 * sin2);
    float g = min(1.0, min(2.0 * abs(q * lo.z), 2.0 * abs(q * li.z)));
    pdf = 0.5 * PB_INV_PI;
    return vec3(0.25 * d * g / lo.z);
  }
  if (c.type == PB_CL_V2_SHEEN) {
    if (li.z <= 0.0) return vec3(0.0);
    float a = c.on_a, b = c.on_b;
    float q = a * li.x + b * li.z, l2 = q * q + a * a * li.y * li.y + li.z * li.z;
    float v = PB_INV_PI * li.z * (a / l2) * (a / l2);
    pdf = v;
    return vec3(v);
  }
  bool is_t = li.z < 0.0;
  if (lo.z <= 0.0 || ((dot(ng, wi) < 0.0) != is_t) || (is_t && c.type != PB_CL_V2_GLASS)) return vec3(0.0);
  vec3 h = is_t ? -(li * c.ior + lo) : lo + li;
  float hl = length(h);
  if (!(hl > 0.0)) return vec3(0.0);
  float inv = 1.0 / hl;
  h *= inv;
  float chv = dot(h, lo);
  vec3 r, t;
  pb2_fresnel(c, chv, r, t);
  float ar = pb_avg3(r), at = pb_avg3(t);
  if (!(ar + at > 0.0)) return vec3(0.0);
  float ax = c.ax, ay = is_t ? c.ax : c.ay;
  float d, lv, ll;
  if (c.beckmann) {
    d = pb2_beckmann_d(h, ax, ay);
    lv = pb2_beckmann_lambda(lo, ax, ay);
    ll = pb2_beckmann_lambda(li, ax, ay);
  } else {
    float sx = h.x / ax, sy = h.y / ay, k = sx * sx + sy * sy + h.z * h.z;
    d = 1.0 / (PB_PI * ax * ay * k * k);
    lv = pb2_lambda(lo, ax, ay);
    ll = pb2_lambda(li, ax, ay);
  }
  float cmn = d / lo.z * (is_t ? (c.ior * inv) * (c.ior * inv) * abs(chv * dot(h, li)) : 0.25);
  float pr = ar / (ar + at);
  // GGX samples visible normals (pdf D G1(wo) |wo.h| / wo.z), Beckmann
  // normals from D cos (pdf D |h.z|), each through the same Jacobian.
  pdf = cmn * (is_t ? 1.0 - pr : pr) * (c.beckmann ? lo.z * abs(h.z) / max(abs(chv), 1e-20) : 1.0 / (1.0 + lv));
  float g = c.g2 ? 1.0 / (1.0 + lv + ll) : 1.0 / ((1.0 + lv) * (1.0 + ll));
  return (is_t ? t : r) * (cmn * g * c.energy);
}

void pb2_preserve_energy(inout pb_closure c, float mu, vec3 fss) {
  float rough = sqrt(sqrt(c.ax * c.ay)), e, eavg;
  if (c.type == PB_CL_V2_GLASS) {
    bool inv = c.ior < 1.0;
    float ior = inv ? 1.0 / c.ior : c.ior;
    float z = sqrt(abs((ior - 1.0) / (ior + 1.0)));
    e = pb2_lut3(inv ? PB_P2T_GGX_GLASS_INV_E : PB_P2T_GGX_GLASS_E, rough, mu, z);
    eavg = pb2_lut2(inv ? PB_P2T_GGX_GLASS_INV_EAVG : PB_P2T_GGX_GLASS_EAVG, 0, rough, z, 16, 16);
  } else {
    e = pb2_lut2(PB_P2T_GGX_E, 0, rough, mu, 32, 32);
    eavg = pb2_lut1(PB_P2T_GGX_EAVG, 0, rough, 32);
  }
  float missing = (1.0 - e) / e;
  c.energy = 1.0 + missing;
  if (any(notEqual(fss, vec3(1.0)))) {
    vec3 fms = fss * eavg / (vec3(1.0) - fss * (1.0 - eavg));
    vec3 dark = (vec3(1.0) + fms * missing) / c.energy;
    c.weight *= dark;
    c.sample_weight *= pb_avg3(dark);
  }
}

// bsdf_microfacet_estimate_albedo at view cosine mu.
vec3 pb2_albedo(pb_closure c, float mu, bool trans) {
  vec3 r, t;
  pb2_fresnel(c, mu, r, t);
  if (!trans) t = vec3(0.0);
  if (all(equal(r, vec3(0.0)))) return t;
  float rough = sqrt(sqrt(c.ax * c.ay));
  float z = sqrt(abs((c.ior - 1.0) / (c.ior + 1.0)));
  if (c.fresnel == PB_FR_GEN_SCHLICK && c.tf_d > PB_TF_MIN_THICKNESS) {
    // the film has no table: its reflectance at mu, as pb2_fresnel gave it
  } else if (c.fresnel == PB_FR_GEN_SCHLICK) {
    r = mix(c.cspec0, vec3(1.0), pb2_lut3(PB_P2T_GGX_GEN_SCHLICK_IOR_S, rough, mu, z));
  } else if (c.fresnel == PB_FR_F82_TINT) {
    r = mix(c.cspec0, vec3(1.0), pb2_lut3(PB_P2T_GGX_GEN_SCHLICK_S, rough, mu, 0.5));
  } else if (c.fresnel == PB_FR_NONE) {
    // no Fresnel: the albedo of the smooth surface, 1
  } else if (c.ior > 1.0) {
    r = vec3(mix(pb2_f0(c.ior), 1.0, pb2_lut3(PB_P2T_GGX_GEN_SCHLICK_IOR_S, rough, mu, z)));
  }
  return r + t;
}

vec3 pb2_layer_under(vec3 albedo, vec3 w) {
  float m = 0.0;
  for (int k = 0; k < 3; ++k)
    if (w[k] != 0.0) m = max(m, albedo[k] / w[k]);
  return w * clamp(1.0 - m, 0.0, 1.0);
}

void pb2_microfacet(inout pb_closure c, vec3 n, vec3 t, float ax, float ay, float ior, uint fresnel, vec3 f0) {
  pb_lobe_frame(c, n, t);
  c.ax = clamp(ax, 0.0, 1.0);
  c.ay = clamp(ay, 0.0, 1.0);
  c.ior = ior;
  c.fresnel = fresnel;
  c.cspec0 = fresnel == PB_FR_GEN_SCHLICK ? clamp(f0, 0.0, 1.0) : f0;
  c.energy = 1.0;
  c.g2 = true;
  c.singular = c.ax * c.ay <= PB_SINGULAR_ALPHA2;
}

vec3 pb2_color(uint tex, vec3 value, pb_surface s) {
  if (SC_TEXTURES && tex != PB_GPU_NO_TEXTURE) value = pb_texture_lookup(tex, s).rgb;
  return max(value, vec3(0.0));
}

// The Metallic BSDF's Physical Conductor as the metal closure c (Cycles 4.5
// svm/closure.h CLOSURE_BSDF_PHYSICAL_CONDUCTOR, closure/bsdf_microfacet.h
// bsdf_microfacet_setup_fresnel_conductor): n = max(IOR, 0), k =
// max(Extinction, 0); the sample weight is the smooth surface's albedo;
// multiscatter with bsdf_util.h fresnel_conductor_Fss, the F82 fit of the
// conductor at cos 1 and 1/7.
void pb2_metal_conductor(inout pb_closure c, vec3 n, vec3 tangent, float ax, float ay, vec3 eta, vec3 k, vec3 wo,
                         bool multi) {
  pb2_microfacet(c, n, tangent, ax, ay, 1.0, PB_FR_CONDUCTOR, max(eta, vec3(0.0)));
  c.color = k;
  float mu = dot(wo, n);
  c.sample_weight *= pb_avg3(pb2_albedo(c, mu, true));
  if (multi) {
    vec3 f0 = pb2_fresnel_conductor(1.0, c.cspec0, k), f82 = pb2_fresnel_conductor(1.0 / 7.0, c.cspec0, k);
    const float f = 6.0 / 7.0;
    float f5 = f * f * f * f * f;
    vec3 bb = (7.0 / (f5 * f)) * (mix(f0, vec3(1.0), f5) - f82);
    pb2_preserve_energy(c, mu, clamp(mix(f0, vec3(1.0), 1.0 / 21.0) - bb * (1.0 / 126.0), 0.0, 1.0));
  }
}

// Blender 4.x's Glossy, Glass and Refraction BSDFs (Cycles 4.5 svm/closure.h
// CLOSURE_BSDF_MICROFACET_GGX_ID / _MULTI_GGX_ID, _GGX_GLASS_ID /
// _MULTI_GGX_GLASS_ID, _GGX_REFRACTION_ID; see src/ref/principled.c
// v2_node for the model): one closure, tinted by Color. Files of Blender
// 3.4 (g2_correlated 0; Multiscatter GGX never comes so) get Cycles 3.4's:
// the shading normal, separable masking, and the Glass as two closures
// split by the Fresnel at that normal.
void pb2_node(pb_gpu_material m, pb_surface surf, vec3 wo, vec3 tangent, vec3 color, float in_v[PB_GPU_IN_SLOTS],
              bool multi, inout pb_bsdf b) {
  bool v34 = m.g2_correlated == 0u;
  bool beckmann = m.distribution == PB_GPU_DISTRIBUTION_BECKMANN;
  vec3 n = v34 ? surf.ns : pb_valid_reflection_normal(surf.ng, wo, surf.ns);
  float r = clamp(in_v[PB_GPU_IN_ROUGHNESS], 0.0, 1.0);
  float a = r * r;
  float mu = dot(wo, n);
  if (m.node == PB_GPU_NODE_GLOSSY) {
    pb_add_closure(b, PB_SLOT_GLASS_REFL, PB_CL_V2_GGX, color);
    if (!b.cl[PB_SLOT_GLASS_REFL].on) return;
    float aniso = clamp(in_v[PB_GPU_IN_ANISOTROPIC], -0.99, 0.99);
    float ax = a, ay = a;
    if (abs(aniso) > 1e-4) {
      ax = aniso < 0.0 ? a / (1.0 + aniso) : a * (1.0 - aniso);
      ay = aniso < 0.0 ? a * (1.0 + aniso) : a / (1.0 - aniso);
      // about the lobe's normal, as svm/closure.h turns it
      tangent = pb_turn_tangent(tangent, n, in_v[PB_GPU_IN_ANISOTROPIC_ROTATION]);
    }
    pb2_microfacet(b.cl[PB_SLOT_GLASS_REFL], n, tangent, ax, ay, 1.0, PB_FR_NONE, vec3(1.0));
    b.cl[PB_SLOT_GLASS_REFL].beckmann = beckmann;
    b.cl[PB_SLOT_GLASS_REFL].g2 = !v34;
    if (multi) pb2_preserve_energy(b.cl[PB_SLOT_GLASS_REFL], mu, color);
    return;
  }
  if (m.node == PB_GPU_NODE_VELVET) {  // svm/closure.h CLOSURE_BSDF_ASHIKHMIN_VELVET_ID
    pb_add_closure(b, PB_SLOT_SHEEN, PB_CL_VELVET, color);
    pb_lobe_frame(b.cl[PB_SLOT_SHEEN], surf.ns, tangent);
    float sigma = max(r, 0.01);
    b.cl[PB_SLOT_SHEEN].on_a = 1.0 / (sigma * sigma);
    return;
  }
  bool glass = m.node == PB_GPU_NODE_GLASS;
  float ior = max(in_v[PB_GPU_IN_IOR], 1e-5);
  if (v34) {  // 3.4 svm/closure.h: reflection F, refraction max(1e-4, 1 - F), neither with a Fresnel
    float eta = surf.front ? ior : 1.0 / ior;
    float f = glass ? pb_fresnel_diel(dot(n, wo), eta) : 0.0;
    if (glass) {
      pb_add_closure(b, PB_SLOT_GLASS_REFL, PB_CL_V2_GGX, color * f);
      pb2_microfacet(b.cl[PB_SLOT_GLASS_REFL], n, n, a, a, eta, PB_FR_NONE, vec3(1.0));
      b.cl[PB_SLOT_GLASS_REFL].beckmann = beckmann;
      b.cl[PB_SLOT_GLASS_REFL].g2 = false;
    }
    pb_add_closure(b, PB_SLOT_GLASS_REFR, PB_CL_V2_GLASS, color * (glass ? max(1e-4, 1.0 - f) : 1.0));
    pb2_microfacet(b.cl[PB_SLOT_GLASS_REFR], n, n, a, a, eta, PB_FR_NONE, vec3(1.0));
    b.cl[PB_SLOT_GLASS_REFR].beckmann = beckmann;
    b.cl[PB_SLOT_GLASS_REFR].g2 = false;
    return;
  }
  pb_add_closure(b, PB_SLOT_GLASS_REFR, PB_CL_V2_GLASS, color);
  if (!b.cl[PB_SLOT_GLASS_REFR].on) return;
  pb2_microfacet(b.cl[PB_SLOT_GLASS_REFR], n, n, a, a, surf.front ? ior : 1.0 / ior,
                 glass ? PB_FR_GEN_SCHLICK : PB_FR_NONE, vec3(pb2_f0(ior)));
  b.cl[PB_SLOT_GLASS_REFR].ttint = vec3(1.0);
  b.cl[PB_SLOT_GLASS_REFR].beckmann = beckmann;
  if (!glass) return;
  // The Color tints reflection and transmission alike: the closure's weight
  // here, the Fresnel's tints in Cycles (the same product).
  b.cl[PB_SLOT_GLASS_REFR].sample_weight *= pb_avg3(pb2_albedo(b.cl[PB_SLOT_GLASS_REFR], mu, true));
  if (multi) pb2_preserve_energy(b.cl[PB_SLOT_GLASS_REFR], mu, color);
}

// The v2 closures into b, top to bottom; returns the weight the emission
// takes (alpha, sheen and coat over it). emission_only: stop there.
vec3 pb2_setup(pb_surface surf, vec3 wo, vec3 tangent, vec3 base, bool emission_only, inout pb_bsdf b) {
  pb_gpu_material m = materials[surf.mat];
  float in_v[PB_GPU_IN_SLOTS];
  [[dont_unroll]] for (uint i = 0u; i < PB_GPU_IN_SLOTS; ++i) in_v[i] = pb_input_value(m, i, surf);
  bool multi = m.distribution == PB_GPU_DISTRIBUTION_MULTI_GGX;
  if (m.node >= PB_GPU_NODE_GLOSSY) {  // a BSDF node: no layers, no emission
    if (!emission_only) pb2_node(m, surf, wo, tangent, base, in_v, multi, b);
    b.albedo = clamp(base, 0.0, 1.0);
    return vec3(0.0);
  }
  float metallic = clamp(in_v[PB_GPU_IN_METALLIC], 0.0, 1.0);
  float ss_w = clamp(in_v[PB_GPU_IN_SUBSURFACE], 0.0, 1.0);
  float level = max(in_v[PB_GPU_IN_SPECULAR_IOR_LEVEL], 0.0);
  float roughness = clamp(in_v[PB_GPU_IN_ROUGHNESS], 0.0, 1.0);
  float aniso = clamp(in_v[PB_GPU_IN_ANISOTROPIC], 0.0, 1.0);
  float sheen_w = max(in_v[PB_GPU_IN_SHEEN_WEIGHT], 0.0);
  float sheen_r = clamp(in_v[PB_GPU_IN_SHEEN_ROUGHNESS], 0.0, 1.0);
  float coat_w = max(in_v[PB_GPU_IN_COAT_WEIGHT], 0.0);
  float coat_r = clamp(in_v[PB_GPU_IN_COAT_ROUGHNESS], 0.0, 1.0);
  float coat_ior = max(in_v[PB_GPU_IN_COAT_IOR], 1.0);
  float trans_w = clamp(in_v[PB_GPU_IN_TRANSMISSION], 0.0, 1.0);
  float ior = max(in_v[PB_GPU_IN_IOR], 1e-5);
  float alpha = clamp(in_v[PB_GPU_IN_ALPHA], 0.0, 1.0);
  // Thin Film Thickness (nm) and IOR, clamped as svm/closure.h does
  float tf_d = max(in_v[PB_GPU_IN_THIN_FILM_THICKNESS], 1e-5);
  float tf_ior = max(in_v[PB_GPU_IN_THIN_FILM_IOR], 1e-5);
  vec3 spec_tint = pb2_color(m.specular_tint_tex, m.specular_tint, surf);
  vec3 coat_tint = pb2_color(m.coat_tint_tex, m.coat_tint, surf);
  vec3 sheen_tint = pb2_color(m.sheen_tint_tex, m.sheen_tint, surf);
  vec3 cbase = min(base, vec3(1.0));
  vec3 ns = surf.ns;
  vec3 n = pb_valid_reflection_normal(surf.ng, wo, ns);
  float ax = roughness * roughness, ay = ax;
  if (aniso > 0.0) {
    float aspect = sqrt(1.0 - aniso * 0.9);
    ax /= aspect;
    ay *= aspect;
    tangent = pb_turn_tangent(tangent, ns, in_v[PB_GPU_IN_ANISOTROPIC_ROTATION]);
  }
  vec3 w = vec3(1.0);
  pb_add_closure(b, PB_SLOT_TRANSPARENT, PB_CL_TRANSPARENT, vec3(1.0 - alpha));
  w *= alpha;
  if (sheen_w > PB_CUTOFF) {
    pb_add_closure(b, PB_SLOT_SHEEN, PB_CL_V2_SHEEN, sheen_tint * sheen_w * w);
    if (b.cl[PB_SLOT_SHEEN].on) {
      // Cycles: the sheen's normal leans toward the coat's by Coat Weight
      vec3 sn = normalize(mix(ns, surf.nc, clamp(coat_w, 0.0, 1.0)));
      float r = clamp(sheen_r, 1e-3, 1.0), cni = dot(sn, wo);
      pb_lobe_frame(b.cl[PB_SLOT_SHEEN], sn, wo);
      b.cl[PB_SLOT_SHEEN].on_a = pb2_lut2(PB_P2T_SHEEN_LTC, 0, cni, r, 32, 32);
      b.cl[PB_SLOT_SHEEN].on_b = pb2_lut2(PB_P2T_SHEEN_LTC, 1024, cni, r, 32, 32);
      float alb = pb2_lut2(PB_P2T_SHEEN_LTC, 2048, cni, r, 32, 32);
      if (abs(b.cl[PB_SLOT_SHEEN].on_a) < 1e-5 || alb < 1e-5) {
        b.cl[PB_SLOT_SHEEN].on = false;
        b.cl[PB_SLOT_SHEEN].sample_weight = 0.0;
      } else {
        b.cl[PB_SLOT_SHEEN].weight *= alb;
        b.cl[PB_SLOT_SHEEN].sample_weight *= alb;
        w = pb2_layer_under(b.cl[PB_SLOT_SHEEN].weight, w);
      }
    }
  }
  if (coat_w > PB_CUTOFF) {
    vec3 cn = pb_valid_reflection_normal(surf.ng, wo, surf.nc);  // Coat Normal: sd->N unless linked
    pb_add_closure(b, PB_SLOT_CLEARCOAT, PB_CL_V2_GGX, w * coat_w);
    if (b.cl[PB_SLOT_CLEARCOAT].on) {
      float a = coat_r * coat_r;
      pb2_microfacet(b.cl[PB_SLOT_CLEARCOAT], cn, cn, a, a, coat_ior, PB_FR_DIELECTRIC, vec3(0.0));
      float mu = dot(wo, cn);
      b.cl[PB_SLOT_CLEARCOAT].sample_weight *= pb_avg3(pb2_albedo(b.cl[PB_SLOT_CLEARCOAT], mu, true));
      pb2_preserve_energy(b.cl[PB_SLOT_CLEARCOAT], mu, vec3(pb2_fss_dielectric(coat_ior)));
      w = pb2_layer_under(b.cl[PB_SLOT_CLEARCOAT].weight * pb2_albedo(b.cl[PB_SLOT_CLEARCOAT], mu, false), w);
    }
    if (any(notEqual(coat_tint, vec3(1.0)))) {
      float cni = dot(wo, cn);
      float cnt = sqrt(max(0.0, 1.0 - (1.0 - cni * cni) / (coat_ior * coat_ior)));
      w *= mix(vec3(1.0), pow(coat_tint, vec3(1.0 / cnt)), coat_w);
    }
  }
  if (emission_only) return w;
  vec3 w_emission = w;
  if (metallic > PB_CUTOFF) {
    pb_add_closure(b, PB_SLOT_GLASS_REFL, PB_CL_V2_GGX, w * metallic);
    // the Metallic BSDF's Beckmann: its D and Lambda, never compensated
    b.cl[PB_SLOT_GLASS_REFL].beckmann = m.distribution == PB_GPU_DISTRIBUTION_BECKMANN;
    if (b.cl[PB_SLOT_GLASS_REFL].on && (m.flags & PB_GPU_MAT_CONDUCTOR) != 0u) {
      vec3 eta = vec3(in_v[PB_GPU_IN_CONDUCTOR_N], in_v[PB_GPU_IN_CONDUCTOR_N + 1u], in_v[PB_GPU_IN_CONDUCTOR_N + 2u]);
      pb2_metal_conductor(b.cl[PB_SLOT_GLASS_REFL], n, tangent, ax, ay, eta, spec_tint, wo, multi);
    } else if (b.cl[PB_SLOT_GLASS_REFL].on) {
      pb2_microfacet(b.cl[PB_SLOT_GLASS_REFL], n, tangent, ax, ay, 1.0, PB_FR_F82_TINT, cbase);
      vec3 f82 = min(spec_tint, vec3(1.0));
      const float f = 6.0 / 7.0;
      float f5 = f * f * f * f * f;
      b.cl[PB_SLOT_GLASS_REFL].color = all(equal(f82, vec3(1.0)))
                                           ? vec3(0.0)
                                           : mix(cbase, vec3(1.0), f5) * (7.0 / (f5 * f)) * (vec3(1.0) - f82);
      float mu = dot(wo, n);
      b.cl[PB_SLOT_GLASS_REFL].sample_weight *= pb_avg3(pb2_albedo(b.cl[PB_SLOT_GLASS_REFL], mu, true));
      if (multi)
        pb2_preserve_energy(b.cl[PB_SLOT_GLASS_REFL], mu,
                            mix(cbase, vec3(1.0), 1.0 / 21.0) - b.cl[PB_SLOT_GLASS_REFL].color * (1.0 / 126.0));
    }
    w *= 1.0 - metallic;
  }
  if (trans_w > PB_CUTOFF) {
    pb_add_closure(b, PB_SLOT_GLASS_REFR, PB_CL_V2_GLASS, w * trans_w);
    if (b.cl[PB_SLOT_GLASS_REFR].on) {
      float r2 = roughness * roughness;
      pb2_microfacet(b.cl[PB_SLOT_GLASS_REFR], n, n, r2, r2, surf.front ? ior : 1.0 / ior, PB_FR_GEN_SCHLICK,
                     spec_tint * pb2_f0(ior));
      b.cl[PB_SLOT_GLASS_REFR].ttint = sqrt(cbase);
      // svm/closure.h: the film on the glass, its IOR relative to wo's side
      b.cl[PB_SLOT_GLASS_REFR].tf_d = tf_d;
      b.cl[PB_SLOT_GLASS_REFR].tf_ior = surf.front ? tf_ior : tf_ior / ior;
      float mu = dot(wo, n);
      b.cl[PB_SLOT_GLASS_REFR].sample_weight *= pb_avg3(pb2_albedo(b.cl[PB_SLOT_GLASS_REFR], mu, true));
      if (multi) pb2_preserve_energy(b.cl[PB_SLOT_GLASS_REFR], mu, b.cl[PB_SLOT_GLASS_REFR].ttint);
    }
    w *= 1.0 - trans_w;
  }
  float eta = ior, f0 = pb2_f0(eta);
  if (level != 0.5) {
    f0 *= 2.0 * level;
    float rf = sqrt(clamp(f0, 0.0, 0.99));
    eta = (1.0 + rf) / (1.0 - rf);
    if (ior < 1.0) eta = 1.0 / eta;
  }
  // svm/closure.h: a film makes the specular lobe even at eta 1.
  if (eta != 1.0 || tf_d > PB_TF_MIN_THICKNESS) {
    pb_add_closure(b, PB_SLOT_SPECULAR, PB_CL_V2_GGX, w);
    if (b.cl[PB_SLOT_SPECULAR].on) {
      pb2_microfacet(b.cl[PB_SLOT_SPECULAR], n, tangent, ax, ay, eta, PB_FR_GEN_SCHLICK, spec_tint * f0);
      b.cl[PB_SLOT_SPECULAR].tf_d = tf_d;
      b.cl[PB_SLOT_SPECULAR].tf_ior = tf_ior;
      float mu = dot(wo, n);
      b.cl[PB_SLOT_SPECULAR].sample_weight *= pb_avg3(pb2_albedo(b.cl[PB_SLOT_SPECULAR], mu, true));
      if (multi) {
        float f0r = pb2_f0(eta);
        float sfs = clamp((pb2_fss_dielectric(eta) - f0r) / (1.0 - f0r), 0.0, 1.0);
        pb2_preserve_energy(b.cl[PB_SLOT_SPECULAR], mu, mix(b.cl[PB_SLOT_SPECULAR].cspec0, vec3(1.0), sfs));
      }
      w = pb2_layer_under(b.cl[PB_SLOT_SPECULAR].weight * pb2_albedo(b.cl[PB_SLOT_SPECULAR], mu, false), w);
    }
  }
  // Diffuse; subsurface rendered as diffuse (the loader warns).
  pb_add_closure(b, PB_SLOT_DIFFUSE, PB_CL_OREN_NAYAR, (base * (1.0 - ss_w) + cbase * ss_w) * w);
  pb_lobe_frame(b.cl[PB_SLOT_DIFFUSE], ns, tangent);
  // Diffuse Roughness (4.3+): Oren-Nayar on the base colour's albedo.
  float dr = clamp(in_v[PB_GPU_IN_DIFFUSE_ROUGHNESS], 0.0, 1.0);
  pb_oren_nayar(b.cl[PB_SLOT_DIFFUSE], dr < PB_CUTOFF ? 0.0 : dr, base, true, wo);
  b.albedo = cbase * alpha;
  return w_emission;
}

// The weight of a v2 material's emission toward wo (pb_emission_toward).
vec3 pb2_emission_weight(pb_surface surf, vec3 wo) {
  pb_gpu_material m = materials[surf.mat];
  vec3 base = m.base_color.rgb;
  if (SC_TEXTURES && m.base_color_tex != PB_GPU_NO_TEXTURE) base = pb_texture_lookup(m.base_color_tex, surf).rgb;
  if ((m.flags & PB_GPU_MAT_VERTEX_COLOR) != 0u) base = surf.color.rgb;
  pb_bsdf b;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) pb_add_closure(b, i, PB_CL_TRANSPARENT, vec3(0.0));
  return pb2_setup(surf, wo, surf.ns, max(base, vec3(0.0)), true, b);
}

void pb_blender_setup_one(pb_surface surf, vec3 wo, vec3 tangent, inout pb_bsdf b) {
  pb_gpu_material m = materials[surf.mat];
  b.model = m.model;
  b.bump = m.bump_model;
  b.sw_sum = 0.0;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) pb_add_closure(b, i, PB_CL_TRANSPARENT, vec3(0.0));
  vec3 base = m.base_color.rgb;
  if (SC_TEXTURES && m.base_color_tex != PB_GPU_NO_TEXTURE) base = pb_texture_lookup(m.base_color_tex, surf).rgb;
  if ((m.flags & PB_GPU_MAT_VERTEX_COLOR) != 0u) base = surf.color.rgb; // a Color Attribute node (COLOR_0)
  base = max(base, vec3(0.0));
  b.base = clamp(base, 0.0, 1.0);
  b.albedo = b.base;
  if (m.model == PB_GPU_MODEL_EMISSION || m.model == PB_GPU_MODEL_HOLDOUT) {
    b.albedo = vec3(0.0);
    return;
  }
  if (SC_PRINCIPLED2 && m.model == PB_GPU_MODEL_PRINCIPLED && m.principled_v2 != 0u) {
    pb2_setup(surf, wo, tangent, base, false, b);
    for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) b.sw_sum += b.cl[i].sample_weight;
    return;
  }
  vec3 n = pb_valid_reflection_normal(surf.ng, wo, surf.ns);
  if (m.model == PB_GPU_MODEL_DIFFUSE) {
    pb_add_closure(b, PB_SLOT_DIFFUSE, PB_CL_OREN_NAYAR, base);
    pb_lobe_frame(b.cl[PB_SLOT_DIFFUSE], n, tangent);
    pb_oren_nayar(b.cl[PB_SLOT_DIFFUSE], clamp(pb_input_value(m, PB_GPU_IN_ROUGHNESS, surf), 0.0, 1.0), base,
                  (m.flags & PB_GPU_MAT_OREN_NAYAR_MS) != 0u, wo);
  } else if (pb_v1_compiled()) {
    float in_v[PB_GPU_IN_SLOTS];
    pb_inputs(m, surf, in_v);
    float metallic = in_v[PB_GPU_IN_METALLIC];
    float roughness = in_v[PB_GPU_IN_ROUGHNESS];
    float specular = in_v[PB_GPU_IN_SPECULAR];
    float spec_tint = in_v[PB_GPU_IN_SPECULAR_TINT];
    float transmission = in_v[PB_GPU_IN_TRANSMISSION];
    float alpha = clamp(in_v[PB_GPU_IN_ALPHA], 0.0, 1.0);
    float eta = max(in_v[PB_GPU_IN_IOR], 1e-5);
    float ior = surf.front ? eta : 1.0 / eta;
    float fresnel = pb_fresnel_diel(dot(n, wo), ior);
    float diffuse_w = (1.0 - clamp(metallic, 0.0, 1.0)) * (1.0 - clamp(transmission, 0.0, 1.0));
    float glass_w = clamp(transmission, 0.0, 1.0) * (1.0 - clamp(metallic, 0.0, 1.0));
    float spec_w = 1.0 - glass_w;
    float w = alpha;
    pb_add_closure(b, PB_SLOT_TRANSPARENT, PB_CL_TRANSPARENT, vec3(1.0 - alpha));
    tangent = pb_turn_tangent(tangent, n, in_v[PB_GPU_IN_ANISOTROPIC_ROTATION]);
    float ss = clamp(in_v[PB_GPU_IN_SUBSURFACE], 0.0, 1.0);
    vec3 ssc = m.subsurface_color;
    if (SC_TEXTURES && m.subsurface_color_tex != PB_GPU_NO_TEXTURE)
      ssc = pb_texture_lookup(m.subsurface_color_tex, surf).rgb;
    vec3 mixed = ssc * ss + base * (1.0 - ss);
    if (abs(pb_avg3(mixed)) > PB_CUTOFF && diffuse_w > PB_CUTOFF) {
      pb_add_closure(b, PB_SLOT_DIFFUSE, PB_CL_DIFFUSE, mixed * (w * diffuse_w));
      pb_lobe_frame(b.cl[PB_SLOT_DIFFUSE], n, tangent);
      b.cl[PB_SLOT_DIFFUSE].rough = roughness;
    }
    float sheen = in_v[PB_GPU_IN_SHEEN];
    if (diffuse_w > PB_CUTOFF && sheen > PB_CUTOFF) {
      float lum = pb_luma709(base);
      vec3 tint = lum > 0.0 ? base / lum : vec3(1.0);
      float st = in_v[PB_GPU_IN_SHEEN_TINT];
      vec3 col = vec3(1.0 - st) + tint * st;
      pb_add_closure(b, PB_SLOT_SHEEN, PB_CL_SHEEN, col * (w * sheen * diffuse_w));
      pb_lobe_frame(b.cl[PB_SLOT_SHEEN], n, tangent);
      float cn = dot(n, wo);
      b.cl[PB_SLOT_SHEEN].sample_weight *= cn < 0.0 ? 0.0 : pb_schlick_w(cn) * cn;
    }
    if (spec_w > PB_CUTOFF && (specular > PB_CUTOFF || metallic > PB_CUTOFF)) {
      bool multi = pb_multi_walk_compiled() && m.distribution == PB_GPU_DISTRIBUTION_MULTI_GGX && roughness > 0.075;
      pb_add_closure(b, PB_SLOT_SPECULAR, multi ? PB_CL_MULTI_GGX : PB_CL_GGX, vec3(w * spec_w));
      float spec_ior = 2.0 / (1.0 - sqrt(max(0.0, 0.08 * specular))) - 1.0;
      float aspect = sqrt(max(0.0, 1.0 - in_v[PB_GPU_IN_ANISOTROPIC] * 0.9));
      float r2 = roughness * roughness;
      float ax = r2 / aspect, ay = r2 * aspect;
      ax = multi ? clamp(ax, 1e-4, 1.0) : clamp(ax, 0.0, 1.0);
      ay = multi ? clamp(ay, 1e-4, 1.0) : clamp(ay, 0.0, 1.0);
      float lum = 0.3 * base.x + 0.6 * base.y + 0.1 * base.z;
      vec3 tint = lum > 0.0 ? base / lum : vec3(1.0);
      vec3 tcol = vec3(1.0 - spec_tint) + tint * spec_tint;
      vec3 cspec0 = tcol * (specular * 0.08 * (1.0 - metallic)) + base * metallic;
      b.cl[PB_SLOT_SPECULAR].color = clamp(base, 0.0, 1.0);
      pb_microfacet(b.cl[PB_SLOT_SPECULAR], n, tangent, ax, ay, spec_ior, cspec0, wo);
    }
    if (glass_w > PB_CUTOFF) {
      vec3 cspec0 = base * spec_tint + vec3(1.0 - spec_tint);
      pb_add_closure(b, PB_SLOT_GLASS_REFL, PB_CL_GGX, vec3(w * glass_w * fresnel));
      float a = clamp(roughness * roughness, 0.0, 1.0);
      b.cl[PB_SLOT_GLASS_REFL].color = base;
      pb_microfacet(b.cl[PB_SLOT_GLASS_REFL], n, n, a, a, ior, cspec0, wo);
      float tr = m.distribution == PB_GPU_DISTRIBUTION_GGX
                     ? 1.0 - (1.0 - roughness) * (1.0 - in_v[PB_GPU_IN_TRANSMISSION_ROUGHNESS])
                     : roughness;
      pb_add_closure(b, PB_SLOT_GLASS_REFR, PB_CL_GGX_REFRACT, base * (w * glass_w * max(1e-4, 1.0 - fresnel)));
      float at = clamp(tr * tr, 0.0, 1.0);
      pb_microfacet(b.cl[PB_SLOT_GLASS_REFR], n, n, at, at, ior, vec3(0.0), wo);
      b.cl[PB_SLOT_GLASS_REFR].singular = at * at <= PB_SINGULAR_ALPHA2 || abs(ior - 1.0) < 1e-4;
    }
    float coat = in_v[PB_GPU_IN_CLEARCOAT];
    if (coat > PB_CUTOFF) {
      pb_add_closure(b, PB_SLOT_CLEARCOAT, PB_CL_CLEARCOAT, vec3(w));
      vec3 cn = pb_valid_reflection_normal(surf.ng, wo, surf.nc);  // Clearcoat Normal: sd->N unless linked
      b.cl[PB_SLOT_CLEARCOAT].clearcoat = coat;
      float ccr = in_v[PB_GPU_IN_CLEARCOAT_ROUGHNESS];
      float a = clamp(ccr * ccr, 0.0, 1.0);
      pb_microfacet(b.cl[PB_SLOT_CLEARCOAT], cn, cn, a, a, 1.5, vec3(0.04), wo);
    }
    b.albedo = clamp(base, 0.0, 1.0) * alpha;
  }
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) b.sw_sum += b.cl[i].sample_weight;
}

// A Mix Shader's factor (pb_gpu_material.mix_fac): its Fac, or Cycles
// 4.5's svm_node_fresnel / svm_node_layer_weight at the interpolated normal
// sd->N (the nodes' Normal unlinked) and sd->wi = wo. The reference's is
// src/ref/principled.c mix_fac.
float pb_mix_fac(pb_surface s, vec3 wo) {
  pb_gpu_material m = materials[s.mat];
  float v = pb_input_value(m, PB_GPU_IN_MIX_FAC, s);
  float c = dot(wo, s.ni);
  if (m.mix_fac == PB_GPU_MIX_FAC_FRESNEL) {
    float eta = max(v, 1e-5);
    return pb_fresnel_diel(c, s.front ? eta : 1.0 / eta);
  }
  if (m.mix_fac == PB_GPU_MIX_FAC_LAYER_FRESNEL) {
    float eta = max(1.0 - v, 1e-5);
    return pb_fresnel_diel(c, s.front ? 1.0 / eta : eta);
  }
  if (m.mix_fac == PB_GPU_MIX_FAC_LAYER_FACING) {
    float f = abs(c);
    if (v != 0.5) {
      float blend = clamp(v, 0.0, 1.0 - 1e-5);
      f = pow(f, blend < 0.5 ? 2.0 * blend : 0.5 / (1.0 - blend));
    }
    return 1.0 - f;
  }
  return v;
}

// The closures of a material and, for a Mix Shader (SC_CLOSURES has
// PB_CLOSURES_MIX), of its second shader: the first's weigh 1 - fac, the
// second's fac (an Add Shader: both 1; Cycles' svm_node_mix_closure; a closure then under the
// cutoff is dropped). The two make closures of different kinds (the loader
// keeps only such mixes, scene.c pb_blender_closures), so each keeps its
// slot; the second takes the first's normals. One set-up in a loop: the
// shader holds one copy of it.
void pb_blender_setup(pb_surface surf, vec3 wo, vec3 tangent, inout pb_bsdf b) {
  if ((SC_CLOSURES & PB_CLOSURES_MIX) == 0u || materials[surf.mat].mix_with == 0u) {
    pb_blender_setup_one(surf, wo, tangent, b);
    return;
  }
  // an Add Shader (svm_node_add_closure): both at the incoming weight
  bool add = materials[surf.mat].mix_fac == PB_GPU_MIX_FAC_ADD;
  float f = add ? 1.0 : clamp(pb_mix_fac(surf, wo), 0.0, 1.0);
  pb_surface sk = surf;
  vec3 albedo = vec3(0.0);
  pb_bsdf first = b;  // the frame bsdf.glsl set
  [[dont_unroll]] for (uint k = 0u; k < 2u; ++k) {
    pb_bsdf t = first;
    pb_blender_setup_one(sk, wo, tangent, t);
    float w = k == 0u && !add ? 1.0 - f : f;
    if (k == 0u) b = t;
    for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) {
      pb_closure c = t.cl[i];
      c.weight *= w;
      c.sample_weight *= w;
      if (c.on && !(abs(pb_avg3(c.weight)) >= PB_CUTOFF)) {
        c.on = false;
        c.sample_weight = 0.0;
      }
      if (k == 0u || c.on) b.cl[i] = c;
    }
    albedo += t.albedo * w;
    sk.mat = materials[surf.mat].mix_with - 1u;
  }
  b.albedo = clamp(albedo, 0.0, 1.0);
  b.sw_sum = 0.0;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) b.sw_sum += b.cl[i].sample_weight;
}

// Marks the specular and clearcoat layers of b whose alpha_x alpha_y is above
// alpha2 (pb_gpu_frame.glossy_path_alpha2) as shaded where the eye
// path stops, with the diffuse closures (PB_GPU_LOBES_DIFFUSE): direct light
// and the photon map, whose photons are stored on every non-delta surface,
// weighted by these closures' BSDF. The smoother ones, the glass pair and
// the delta lobes stay with the eye path (PB_GPU_LOBES_GLOSSY). Either way
// each closure is counted once (gbuffer.comp); only the variance and the
// photon map's blur differ, and the threshold is where the two cross
// (bench/README.md, "Blender materials"). Every pass that reads a lobe
// mask other than ALL calls this with the same alpha2 before it does.
bool pb_layer_stops(pb_closure c, float alpha2) { return c.on && !c.singular && c.ax * c.ay > alpha2; }
void pb_blender_split(inout pb_bsdf b, float alpha2) {
  b.cl[PB_SLOT_SPECULAR].stops = pb_layer_stops(b.cl[PB_SLOT_SPECULAR], alpha2);
  b.cl[PB_SLOT_CLEARCOAT].stops = pb_layer_stops(b.cl[PB_SLOT_CLEARCOAT], alpha2);
  // Principled v2's metal and the Glossy BSDF (a reflection-only GGX in the
  // glass reflection slot), not the reflection half of a 3.4 Glass BSDF
  // (a refraction without Fresnel beside it), which stays with its pair.
  bool pair = b.cl[PB_SLOT_GLASS_REFR].on && b.cl[PB_SLOT_GLASS_REFR].fresnel == PB_FR_NONE;
  b.cl[PB_SLOT_GLASS_REFL].stops =
      b.cl[PB_SLOT_GLASS_REFL].type == PB_CL_V2_GGX && !pair && pb_layer_stops(b.cl[PB_SLOT_GLASS_REFL], alpha2);
}

// Which closures a lobe mask keeps (PB_GPU_LOBES_*): the diffuse-like ones
// and the layers pb_blender_split let stop, which the photon map shades; the
// other glossy and the delta ones, which eye paths follow.
bool pb_lobe_in(pb_closure c, uint mask) {
  bool diffuse = c.type <= PB_CL_SHEEN || c.type == PB_CL_V2_SHEEN || c.type == PB_CL_VELVET || c.stops;
  return c.on && c.type != PB_CL_TRANSPARENT &&
         ((diffuse && (mask & PB_GPU_LOBES_DIFFUSE) != 0u) || (!diffuse && (mask & PB_GPU_LOBES_GLOSSY) != 0u));
}
// Closures a mask samples: its own, and the transparent pass with the glossy
// ones (both are followed by eye paths).
bool pb_lobe_sampled(pb_closure c, uint mask) {
  bool transparent = c.on && c.type == PB_CL_TRANSPARENT && (mask & PB_GPU_LOBES_GLOSSY) != 0u;
  return pb_lobe_in(c, mask) || transparent;
}

// Adds closure c's f cos (e) and pdf (pc) to the sums when it is in the
// mask and not a delta lobe.
void pb_accumulate(pb_closure c, uint mask, vec3 e, float pc, inout vec3 f, inout float p) {
  if (pb_lobe_in(c, mask) && !c.singular && pc != 0.0) {
    f += e * c.weight;
    p += pc * c.sample_weight;
  }
}

// Adds slot k's closure c (b.cl[k]) to f cos and the pdf's sum when it is
// in b.mask and not a delta lobe: the lobe evaluation its type asks for.
// Slots and closure kinds the scene cannot make (SC_CLOSURES, SC_PRINCIPLED2)
// are compiled out.
void pb_eval_slot(pb_bsdf b, pb_closure c, uint k, vec3 wo, vec3 wi, inout uint rng, inout vec3 f, inout float p) {
  if (!pb_slot_compiled(k) || !pb_lobe_in(c, b.mask) || c.singular) return;
  float pc;
  vec3 e;
  if (SC_PRINCIPLED2 && k != PB_SLOT_DIFFUSE &&
      (c.type == PB_CL_V2_SHEEN || c.type == PB_CL_V2_GGX || c.type == PB_CL_V2_GLASS || c.type == PB_CL_VELVET))
    e = pb_eval_v2(c, b.ng, wo, wi, pc);
  else if (k <= PB_SLOT_SHEEN)
    e = pb_eval_diffuse_like(c, b.ni, b.bump, wo, wi, pc);
  else if (!pb_v1_compiled())  // the v1 Principled's lobes below
    return;
  else if (pb_multi_walk_compiled() && k == PB_SLOT_SPECULAR && c.type == PB_CL_MULTI_GGX)
    e = pb_eval_multi(c, b.ng, wo, wi, rng, pc);
  else if (k == PB_SLOT_GLASS_REFR)
    e = pb_eval_refract(c, b.ng, wo, wi, pc);
  else
    e = pb_eval_reflect(c, b.ng, wo, wi, pc);
  pb_accumulate(c, b.mask, e, pc, f, p);
}

#ifdef PB_EVAL_COMPACT
// b.cl[k] for k up to PB_SLOT_CLEARCOAT, each slot read with a constant
// index: an array indexed by a variable would send the whole closure stack
// to scratch memory on some drivers (lavapipe: the gather 3x slower).
pb_closure pb_slot(pb_bsdf b, uint k) {
  if (k == PB_SLOT_DIFFUSE) return b.cl[PB_SLOT_DIFFUSE];
  if (k == PB_SLOT_SHEEN) return b.cl[PB_SLOT_SHEEN];
  if (k == PB_SLOT_SPECULAR) return b.cl[PB_SLOT_SPECULAR];
  if (k == PB_SLOT_GLASS_REFL) return b.cl[PB_SLOT_GLASS_REFL];
  if (k == PB_SLOT_GLASS_REFR) return b.cl[PB_SLOT_GLASS_REFR];
  return b.cl[PB_SLOT_CLEARCOAT];
}
#endif

// f cos over the closures of b.mask, and the mixture pdf over all of them
// (principled.c eval_all), slot by slot. Every call of this function is
// inlined, several times per kernel. A kernel that defines PB_EVAL_COMPACT
// (gbuffer: 4 calls) takes the slots in a loop around one copy of each
// lobe's evaluation: its Blender build compiles in about half the time
// (lavapipe: 1.8 s -> 0.95 s) for a few selects per slot at run time. The
// others unroll the slots, each evaluation reading its closure in place:
// in the gather's and the photon tracer's hot loops and in the direct
// light's (7 calls) the loop measured 1.25-2x slower per pass on lavapipe.
// Both give the same sums in the same order (the same pictures).
vec3 pb_blender_eval_cos(pb_bsdf b, vec3 wo, vec3 wi, inout uint rng, out float pdf) {
  vec3 f = vec3(0.0);
  float p = 0.0;
#ifdef PB_EVAL_COMPACT
  for (uint k = PB_SLOT_DIFFUSE; k <= PB_SLOT_CLEARCOAT; ++k) pb_eval_slot(b, pb_slot(b, k), k, wo, wi, rng, f, p);
#else
  pb_eval_slot(b, b.cl[PB_SLOT_DIFFUSE], PB_SLOT_DIFFUSE, wo, wi, rng, f, p);
  pb_eval_slot(b, b.cl[PB_SLOT_SHEEN], PB_SLOT_SHEEN, wo, wi, rng, f, p);
  pb_eval_slot(b, b.cl[PB_SLOT_SPECULAR], PB_SLOT_SPECULAR, wo, wi, rng, f, p);
  pb_eval_slot(b, b.cl[PB_SLOT_GLASS_REFL], PB_SLOT_GLASS_REFL, wo, wi, rng, f, p);
  pb_eval_slot(b, b.cl[PB_SLOT_GLASS_REFR], PB_SLOT_GLASS_REFR, wo, wi, rng, f, p);
  pb_eval_slot(b, b.cl[PB_SLOT_CLEARCOAT], PB_SLOT_CLEARCOAT, wo, wi, rng, f, p);
#endif
  pdf = b.sw_sum > 0.0 ? p / b.sw_sum : 0.0;
  return f;
}

bool pb_blender_has_smooth(pb_bsdf b) {
  bool any = false;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i)
    any = any || (b.cl[i].on && !b.cl[i].singular && b.cl[i].type != PB_CL_TRANSPARENT);
  return any;
}

bool pb_refract_dir(vec3 wo, vec3 m, float ior, out vec3 wi) {
  wi = vec3(0.0);
  float c = dot(wo, m);
  if (c <= 0.0) return false;
  float inv = 1.0 / ior;
  float k = 1.0 - inv * inv * (1.0 - c * c);
  if (k <= 0.0) return false;
  wi = m * (c * inv - sqrt(k)) - wo * inv;
  return true;
}

// Samples one closure of b.mask by sample weight (the mask's share of the
// weights is pb_lobe_share). Returns false when absorbed. weight: f cos /
// pdf over the mask's closures (delta: the lobe's weight / its choice
// probability); pdf 0 for a delta lobe. importance: photons (the adjoint of
// refraction, see principled.c).
bool pb_blender_sample(pb_bsdf b, vec3 wo, float u0, float u1, float u2, bool importance, inout uint rng,
                       out vec3 wi, out vec3 weight, out float pdf, out bool delta, out bool transmit) {
  wi = weight = vec3(0.0);
  pdf = 0.0;
  delta = transmit = false;
  float sum = 0.0;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i)
    if (pb_lobe_sampled(b.cl[i], b.mask)) sum += b.cl[i].sample_weight;
  if (!(sum > 0.0)) return false;
  // The closure whose interval of the sample weights holds u0 sum (the
  // last sampled one when rounding leaves u0 past them all); x: where in it.
  float x = u0 * sum;
  pb_closure c = b.cl[0];
  bool chosen = false;
  for (uint i = 0u; i < PB_CLOSURE_MAX; ++i) {
    if (chosen || !pb_lobe_sampled(b.cl[i], b.mask)) continue;
    c = b.cl[i];
    if (x < c.sample_weight) chosen = true;
    else x -= c.sample_weight;
  }
  if (!chosen) x = c.sample_weight;
  float pick = c.sample_weight / sum;
  float ur = c.sample_weight > 0.0 ? clamp(x / c.sample_weight, 0.0, 1.0) : 0.0;
  if (!(pick > 0.0)) return false;
  vec3 lo = pb_to_lobe(c, wo);
  if (c.type == PB_CL_TRANSPARENT) {
    wi = -wo;
    weight = c.weight / pick;
    delta = transmit = true;
    return true;
  }
  if (lo.z <= 0.0) return false;
  vec3 li;
  if (SC_PRINCIPLED2 && c.singular && (c.type == PB_CL_V2_GGX || c.type == PB_CL_V2_GLASS)) {
    delta = true;
    vec3 r, t;
    pb2_fresnel(c, lo.z, r, t);
    float ar = pb_avg3(r), at = pb_avg3(t);
    if (!(ar + at > 0.0)) return false;
    float pr = ar / (ar + at);
    if (ur < pr) {
      li = vec3(-lo.x, -lo.y, lo.z);
      wi = pb_from_lobe(c, li);
      if (dot(wi, b.ng) <= 0.0) return false;
      weight = c.weight * r * (c.energy / (pr * pick));
    } else {
      if (!pb_refract_dir(lo, vec3(0.0, 0.0, 1.0), c.ior, li)) return false;
      wi = normalize(pb_from_lobe(c, li));
      if (dot(wi, b.ng) >= 0.0) return false;
      weight = c.weight * t * (c.energy / ((1.0 - pr) * pick));
      transmit = true;
    }
    return true;
  }
  if (c.singular) {  // the v1 Principled's delta lobes
    if (!pb_v1_compiled()) return false;
    delta = true;
    if (c.type == PB_CL_GGX_REFRACT) {
      if (!pb_refract_dir(lo, vec3(0.0, 0.0, 1.0), c.ior, li)) return false;
      wi = normalize(pb_from_lobe(c, li));
      if (dot(wi, b.ng) >= 0.0) return false;
      weight = c.weight / pick;
      transmit = true;
    } else {
      li = vec3(-lo.x, -lo.y, lo.z);
      wi = pb_from_lobe(c, li);
      if (dot(wi, b.ng) <= 0.0) return false;
      vec3 f = pb_fresnel_v1(li, vec3(0.0, 0.0, 1.0), c.ior, c.f0, c.cspec0);
      if (c.type == PB_CL_CLEARCOAT) f *= 0.25 * c.clearcoat;
      weight = c.weight * f / pick;
    }
    return true;
  }
  bool v2_refract = false;
  if (c.type <= PB_CL_SHEEN) {
    li = pb_cosine_dir(u1, u2);
  } else if (SC_PRINCIPLED2 && c.type == PB_CL_VELVET) {  // uniform over the hemisphere
    float st = sqrt(max(0.0, 1.0 - u1 * u1)), phi = 2.0 * PB_PI * u2;
    li = vec3(st * cos(phi), st * sin(phi), u1);
  } else if (SC_PRINCIPLED2 && c.type == PB_CL_V2_SHEEN) {
    float r = sqrt(u1), phi = 2.0 * PB_PI * u2, dz = sqrt(max(0.0, 1.0 - u1));
    li = normalize(vec3(r * cos(phi) - dz * c.on_b, r * sin(phi), dz * c.on_a));
  } else if (SC_PRINCIPLED2 && (c.type == PB_CL_V2_GGX || c.type == PB_CL_V2_GLASS)) {
    vec3 m = c.beckmann ? pb2_beckmann_sample(c.ax, c.ay, u1, u2)
                        : pb_ggx_vndf(lo, c.ax, c.ay, u1, u2);
    if (!(dot(lo, m) > 0.0)) return false;  // a Beckmann normal facing away
    if (c.type == PB_CL_V2_GLASS) {
      vec3 r, t;
      pb2_fresnel(c, dot(lo, m), r, t);
      float ar = pb_avg3(r), at = pb_avg3(t);
      if (!(ar + at > 0.0)) return false;
      v2_refract = ur >= ar / (ar + at);
    }
    if (v2_refract) {
      if (!pb_refract_dir(lo, m, c.ior, li)) return false;
    } else {
      li = m * (2.0 * dot(lo, m)) - lo;
    }
  } else if (!pb_v1_compiled()) {  // the v1 Principled's lobes below
    return false;
  } else if (c.type == PB_CL_GGX) {
    vec3 m = pb_ggx_vndf(lo, c.ax, c.ay, u1, u2);
    li = m * (2.0 * dot(lo, m)) - lo;
  } else if (c.type == PB_CL_CLEARCOAT) {
    float a2 = c.ax * c.ax;
    float ct2 = a2 < 1.0 ? (1.0 - pow(a2, 1.0 - u1)) / (1.0 - a2) : 1.0 - u1;
    float ct = sqrt(clamp(ct2, 0.0, 1.0)), st = sqrt(clamp(1.0 - ct2, 0.0, 1.0)), phi = 2.0 * PB_PI * u2;
    vec3 m = vec3(st * cos(phi), st * sin(phi), ct);
    li = m * (2.0 * dot(lo, m)) - lo;
  } else if (pb_multi_walk_compiled() && c.type == PB_CL_MULTI_GGX) {
    float a = pb_multi_ggx_albedo(c.ax == c.ay ? c.ax : sqrt(c.ax * c.ay));
    if (ur < a) {
      vec3 m = pb_ggx_vndf(lo, c.ax, c.ay, u1, u2);
      li = m * (2.0 * dot(lo, m)) - lo;
    } else {
      li = pb_cosine_dir(u1, u2);
    }
  } else {
    vec3 m = pb_ggx_vndf(lo, c.ax, c.ay, u1, u2);
    if (!pb_refract_dir(lo, m, c.ior, li)) return false;
  }
  wi = normalize(pb_from_lobe(c, li));
  transmit = c.type == PB_CL_GGX_REFRACT || v2_refract;
  float side = dot(wi, b.ng);
  if (transmit ? side >= 0.0 : side <= 0.0) return false;
  // The mixture over the mask's closures: their f cos over their share of
  // the sample weights (the pdf of choosing within the mask).
  float p;
  vec3 f = pb_blender_eval_cos(b, wo, wi, rng, p);
  p *= b.sw_sum / sum;
  if (!(p > 0.0)) return false;
  if (transmit && importance) f /= c.ior * c.ior;
  pdf = p;
  weight = f / p;
  return true;
}

#endif
