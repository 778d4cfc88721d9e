// The reference's material model (src/ref/bsdf.c, see pb_bsdf in
// src/ref/ref_internal.h), evaluated the same way: Lambert weighted by
// (1-m)(1-T)(1 - max F_s(n.wo)), GGX reflection with height-correlated Smith
// (delta mirror under PB_SPECULAR_ROUGHNESS), smooth dielectric transmission.
#ifndef PB_BSDF_GLSL
#define PB_BSDF_GLSL

// A closure of a Blender material (src/ref/ref_internal.h pb_closure).
const uint PB_CL_DIFFUSE = 0u;
const uint PB_CL_OREN_NAYAR = 1u;
const uint PB_CL_SHEEN = 2u;
const uint PB_CL_GGX = 3u;
const uint PB_CL_MULTI_GGX = 4u;
const uint PB_CL_GGX_REFRACT = 5u;
const uint PB_CL_CLEARCOAT = 6u;
const uint PB_CL_TRANSPARENT = 7u;
// Principled v2 (Cycles 4.x; principled.glsl "Principled v2"):
const uint PB_CL_V2_SHEEN = 8u;  // microfiber sheen (LTC)
const uint PB_CL_V2_GGX = 9u;    // GGX reflection: F82-tint metal, generalized-Schlick specular, dielectric coat
const uint PB_CL_V2_GLASS = 10u; // GGX glass, reflection and refraction in one closure
const uint PB_CL_VELVET = 11u;   // Ashikhmin velvet (the Sheen BSDF's Ashikhmin, 3.x's Velvet BSDF); on_a = 1 / sigma^2
const uint PB_FR_DIELECTRIC = 0u;
const uint PB_FR_F82_TINT = 1u;
const uint PB_FR_GEN_SCHLICK = 2u;
const uint PB_FR_CONDUCTOR = 3u; // physical conductor: n in cspec0, k in color
const uint PB_FR_NONE = 4u;      // no Fresnel: all reflected (V2_GGX) or all refracted but TIR (V2_GLASS)
// Every closure has its own slot (no dynamic indexing: loops over the slots
// unroll into registers): diffuse or Oren-Nayar, sheen, specular, glass
// reflection, glass refraction, clearcoat, transparent.
const uint PB_SLOT_DIFFUSE = 0u;
const uint PB_SLOT_SHEEN = 1u;
const uint PB_SLOT_SPECULAR = 2u;
const uint PB_SLOT_GLASS_REFL = 3u;
const uint PB_SLOT_GLASS_REFR = 4u;
const uint PB_SLOT_CLEARCOAT = 5u;
const uint PB_SLOT_TRANSPARENT = 6u;
const uint PB_CLOSURE_MAX = 7u;
struct pb_closure {
  bool on;
  uint type;
  vec3 weight;
  float sample_weight;
  vec3 n, x, y;
  float ax, ay, ior, f0;
  vec3 cspec0, color;
  float rough, on_a, on_b, clearcoat;
  bool singular;
  bool stops; // a glossy closure shaded where the eye path stops (pb_blender_split)
  // Principled v2: cspec0 is F0, color the F82 b term, on_a/on_b the sheen LTC
  uint fresnel;  // PB_FR_*
  vec3 ttint;    // glass transmission tint
  float energy;  // Turquin energy scale 1 / E (1 without compensation)
  bool g2;       // height-correlated Smith G2
  float tf_d;    // v2 generalized Schlick: thin film thickness (nm; off at <= 0.1)
  float tf_ior;  // its IOR, relative to the outside as ior is
  bool beckmann; // v2: Beckmann's D and Lambda instead of GGX's (the Blender BSDF nodes)
};

struct pb_bsdf {
  vec3 base;
  float metallic, roughness, alpha, transmission, ior;
  vec3 f0_diel;
  float spec;
  bool delta_spec;
  vec3 n, t, b;  // shading frame, n facing wo
  vec3 ng;       // facing wo
  bool entering;
  // Blender materials (SC_BLENDER, model != PB_GPU_MODEL_GLTF): closures,
  // which of them eval uses (PB_GPU_LOBES_*), the AOV albedo.
  uint model;
  uint bump;     // PB_GPU_BUMP_*
  vec3 ni;       // pb_surface.ni
  uint mask;
  float sw_sum;
  vec3 albedo;
  pb_closure cl[PB_CLOSURE_MAX];
};

float pb_schlick1(float f0, float c) {
  float m = clamp(1.0 - c, 0.0, 1.0);
  float m2 = m * m;
  return f0 + (1.0 - f0) * m2 * m2 * m;
}
vec3 pb_schlick3(vec3 f0, float c) {
  return vec3(pb_schlick1(f0.x, c), pb_schlick1(f0.y, c), pb_schlick1(f0.z, c));
}
float pb_lum(vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
float pb_max3(vec3 c) { return max(c.x, max(c.y, c.z)); }

#include "common/basis.glsl"

#include "common/principled.glsl"

// tangent: along +u where the scene has tangents (anisotropy), else 0.
pb_bsdf pb_bsdf_setup_t(pb_surface surf, vec3 wo, vec3 tangent) {
  pb_gpu_material m = materials[surf.mat];
  pb_bsdf b;
  b.model = PB_GPU_MODEL_GLTF;
  b.bump = PB_GPU_BUMP_CHIANG;
  b.mask = PB_GPU_LOBES_ALL;
  b.sw_sum = 0.0;
  if (SC_BLENDER && m.model != PB_GPU_MODEL_GLTF) {
    b.ng = surf.ng;
    b.n = surf.ns;
    b.ni = surf.ni;
    pb_basis(b.n, b.t, b.b);
    b.entering = surf.front;
    b.metallic = b.roughness = b.alpha = b.transmission = b.spec = 0.0;
    b.ior = 1.5;
    b.f0_diel = vec3(0.0);
    b.delta_spec = false;
    pb_blender_setup(surf, wo, tangent, b);
    return b;
  }
  vec2 mr = pb_surface_metal_rough(surf);
  float metallic = mr.x, rough = mr.y;
  // An unlit surface reflects nothing (its colour is its emission).
  b.base = (m.flags & PB_GPU_MAT_UNLIT) != 0u ? vec3(0.0) : pb_surface_base_color(surf).rgb;
  b.metallic = clamp(metallic, 0.0, 1.0);
  b.roughness = clamp(rough, 0.0, 1.0);
  b.alpha = b.roughness * b.roughness;
  b.delta_spec = b.roughness < PB_SPECULAR_ROUGHNESS;
  b.transmission = clamp(m.transmission, 0.0, 1.0);
  b.ior = (m.ior >= 1.0 && m.ior < 100.0) ? m.ior : 1.5;
  float r0 = (b.ior - 1.0) / (b.ior + 1.0);
  r0 *= r0;
  b.f0_diel = min(r0 * max(m.specular_color, vec3(0.0)), vec3(1.0));
  b.spec = clamp(m.specular, 0.0, 1.0);
  b.ng = surf.ng;
  b.n = dot(surf.ns, wo) > 1e-4 ? surf.ns : surf.ng;
  pb_basis(b.n, b.t, b.b);
  b.entering = surf.front;
  return b;
}
pb_bsdf pb_bsdf_setup(pb_surface surf, vec3 wo) { return pb_bsdf_setup_t(surf, wo, vec3(0.0)); }

vec3 pb_bsdf_albedo(pb_bsdf b) {
  if (SC_BLENDER && b.model != PB_GPU_MODEL_GLTF) return b.albedo;
  float g = (1.0 - b.metallic) * b.transmission;
  return b.base * (1.0 - g) + vec3(g);
}

bool pb_bsdf_has_smooth(pb_bsdf b) {
  if (SC_BLENDER && b.model != PB_GPU_MODEL_GLTF) return pb_blender_has_smooth(b);
  bool diffuse = (1.0 - b.metallic) * (1.0 - b.transmission) > 0.0 && any(notEqual(b.base, vec3(0.0)));
  return diffuse || !b.delta_spec;
}

vec3 pb_spec_fresnel(pb_bsdf b, float c) {
  float kdiel = (1.0 - b.metallic) * (1.0 - b.transmission) * b.spec;
  return pb_schlick3(b.f0_diel, c) * kdiel + pb_schlick3(b.base, c) * b.metallic;
}

// Lobe selection probabilities (pd, ps, pg) and the diffuse weight kd.
vec4 pb_lobes(pb_bsdf b, float cos_o) {
  float nonmetal = 1.0 - b.metallic;
  vec3 fs = pb_schlick3(b.f0_diel, cos_o) * b.spec;
  float kd = nonmetal * (1.0 - b.transmission) * clamp(1.0 - pb_max3(fs), 0.0, 1.0);
  float wd = kd * pb_lum(b.base);
  float ws = pb_lum(pb_spec_fresnel(b, cos_o));
  float wg = nonmetal * b.transmission;
  float sum = wd + ws + wg;
  if (!(sum > 0.0)) return vec4(0.0, 0.0, 0.0, kd);
  return vec4(wd / sum, ws / sum, wg / sum, kd);
}

vec3 pb_to_local(pb_bsdf b, vec3 w) { return vec3(dot(w, b.t), dot(w, b.b), dot(w, b.n)); }

float pb_ggx_d(float a2, float cos_h) {
  float c2 = cos_h * cos_h;
  float k = c2 * (a2 - 1.0) + 1.0;
  return a2 / (PB_PI * k * k);
}
float pb_smith_lambda(float a2, float cos_w) {
  float c2 = cos_w * cos_w;
  if (c2 <= 0.0) return uintBitsToFloat(0x7f800000u);
  float tan2 = max(0.0, 1.0 - c2) / c2;
  return 0.5 * (sqrt(1.0 + a2 * tan2) - 1.0);
}

// Non-delta f(wo, wi), cosine not included (pb_bsdf_eval). rng: the stream
// of a stochastic evaluation (Blender's Multiscatter GGX); untouched
// otherwise. Blender materials: the closures of b.mask, f cos divided by
// |wi . n| (principled.c pb_blender_bsdf_eval).
vec3 pb_bsdf_eval(pb_bsdf b, vec3 wo, vec3 wi, inout uint rng) {
  if (SC_BLENDER && b.model != PB_GPU_MODEL_GLTF) {
    float pdf, cn = abs(dot(wi, b.n));
    vec3 f = pb_blender_eval_cos(b, wo, wi, rng, pdf);
    return cn > 1e-7 ? f / cn : vec3(0.0);
  }
  if (dot(wi, b.ng) <= 0.0) return vec3(0.0);
  vec3 lo = pb_to_local(b, wo), li = pb_to_local(b, wi);
  if (lo.z <= 0.0 || li.z <= 0.0) return vec3(0.0);
  vec4 l = pb_lobes(b, lo.z);
  vec3 f = vec3(0.0);
  if (l.w > 0.0) f = b.base * (l.w * PB_INV_PI);
  if (!b.delta_spec && l.y > 0.0) {
    vec3 h = normalize(lo + li);
    float a2 = b.alpha * b.alpha;
    float d = pb_ggx_d(a2, h.z);
    float lwo = pb_smith_lambda(a2, lo.z), lwi = pb_smith_lambda(a2, li.z);
    float g2 = 1.0 / (1.0 + lwo + lwi);
    vec3 F = pb_spec_fresnel(b, dot(lo, h));
    f += F * (d * g2 / (4.0 * lo.z * li.z));
  }
  return f;
}

float pb_fresnel_dielectric(float cos_i, float eta, out float cos_t) {
  float sin2_t = eta * eta * max(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) {
    cos_t = 0.0;
    return 1.0;
  }
  cos_t = sqrt(1.0 - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// ---- delta lights (src/ref/lights.c pb_delta_light_at) --------------------

float pb_smoothstep01(float t) {
  t = clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// A spot's falloff for the cosine c of the angle between its axis and the
// direction light leaves in (src/ref/lights.c pb_spot_factor): KHR's smooth
// step between the cones, Cycles 3.4's c x smoothstep over its band, or
// Cycles 4.x's smoothstep alone (kernel/light/spot.h).
float pb_spot_factor(pb_gpu_light l, float c) {
  if ((l.flags & (PB_GPU_LIGHT_CYCLES_SPOT | PB_GPU_LIGHT_CYCLES4_SPOT)) != 0u) {
    if (c <= l.cos_outer) return 0.0;
    float band = (1.0 - l.cos_outer) * l.spot_blend, t = c - l.cos_outer;
    float s = band > 0.0 && t < band ? pb_smoothstep01(t / band) : 1.0;
    return (l.flags & PB_GPU_LIGHT_CYCLES_SPOT) != 0u ? c * s : s;
  }
  if (l.cos_inner - l.cos_outer <= 1e-7) return c >= l.cos_outer ? 1.0 : 0.0;
  return pb_smoothstep01((c - l.cos_outer) / (l.cos_inner - l.cos_outer));
}

// Direction to the light, distance (inf for directional) and Li such that
// reflected radiance is f |cos| Li. Returns false when it adds nothing.
bool pb_delta_light_at(pb_gpu_light l, vec3 p, out vec3 wi, out float dist, out vec3 Li) {
  wi = vec3(0.0);
  dist = 0.0;
  Li = vec3(0.0);
  if (l.type == PB_GPU_LIGHT_DIRECTIONAL) {
    if (all(equal(l.direction, vec3(0.0)))) return false;
    wi = -l.direction;
    dist = uintBitsToFloat(0x7f800000u);
    Li = l.power;
    return any(notEqual(Li, vec3(0.0)));
  }
  vec3 d = l.position - p;
  float d2 = dot(d, d);
  if (!(d2 > 0.0)) return false;
  float dl = sqrt(d2);
  wi = d / dl;
  dist = dl;
  float k = 1.0 / d2;
  if (l.type == PB_GPU_LIGHT_SPOT) k *= pb_spot_factor(l, -dot(l.direction, wi));
  Li = l.power * k;
  return k > 0.0 && any(notEqual(l.power, vec3(0.0)));
}

#endif
