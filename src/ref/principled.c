/* The Blender materials of the reference renderer: Blender 3.4's Principled
 * BSDF, Diffuse BSDF, Emission and Holdout shaders as Cycles 3.4 evaluates
 * them, and Blender 4.x's Principled BSDF v2 as Cycles 4.5 does (its own
 * section below, "Principled v2"). Read from Blender 3.4.1's own kernel source (installed with Debian's
 * Blender under scripts/addons/cycles/source/kernel): svm/closure.h turns the
 * Principled node's inputs into closures and weights, closure/
 * bsdf_principled_diffuse.h, bsdf_principled_sheen.h, bsdf_microfacet.h,
 * bsdf_microfacet_multi{,_impl}.h, bsdf_oren_nayar.h, bsdf_diffuse.h and
 * bsdf_util.h define the lobes, integrator/surface_shader.h combines them.
 * This file is our own code for the same functions; the GPU's copy is
 * shaders/common/principled.glsl (same names, same order).
 *
 * Closures of a Principled BSDF (diffuse_w = (1 - metallic)(1 - transmission),
 * glass_w = transmission (1 - metallic), spec_w = 1 - glass_w; each
 * closure exists when its colour weight averages >= 1e-5, Cycles'
 * CLOSURE_WEIGHT_CUTOFF):
 *   diffuse    base x diffuse_w: Burley's diffuse with retro-reflection,
 *              f cos = cos_i / pi ((1 - F_o/2)(1 - F_i/2) + R (F_o + F_i +
 *              F_o F_i (R - 1))), F = (1 - cos)^5, R = roughness (1 + wi.wo);
 *              subsurface is rendered as this lobe with the subsurface-mixed
 *              colour (what Cycles does after a diffuse bounce);
 *   sheen      sheen x tint colour x diffuse_w: f cos = (1 - wi.h)^5 cos_i
 *              (no 1/pi: Cycles' formula as written);
 *   specular   spec_w: GGX (or Multiscatter GGX for roughness > 0.075) with
 *              alpha = r^2 stretched by sqrt(1 - 0.9 anisotropic), index
 *              2 / (1 - sqrt(0.08 specular)) - 1 (so F0 = 0.08 specular), and
 *              the Principled v1 Fresnel  F = cspec0 (1 - t) + t,
 *              t = (F_diel(wi.h) - F0) / (1 - F0), cspec0 = 0.08 specular x
 *              tint colour (1 - metallic) + base metallic;
 *   glass      glass_w: GGX reflection x F_diel(n.wo) with Fresnel colour
 *              base x specular tint + (1 - specular tint), and GGX
 *              refraction x base x (1 - F_diel(n.wo)); roughness r (the
 *              refraction 1 - (1 - r)(1 - transmission roughness) with the GGX
 *              distribution);
 *   clearcoat  GTR1 distribution of alpha = clearcoat roughness^2, Smith G
 *              of alpha 0.25, exact dielectric Fresnel (index 1.5),
 *              times 0.25 clearcoat;
 *   transparent 1 - alpha, everything else x alpha (Cycles mixes a
 *              Transparent BSDF in for Alpha < 1).
 * Separable Smith G1 G1 throughout (Cycles 3.4's GGX), and every lobe's
 * normal lifted by ensure_valid_reflection (bsdf_util.h) so that the
 * mirror direction of wo stays above the geometric surface.
 *
 * The combination is Cycles' one-sample MIS over closures: f cos = sum of
 * weight_c f_c cos, pdf = sum sw_c pdf_c / sum sw (sw: sample weights; the
 * delta lobes are in the sum of weights but not of pdfs), a lobe sampled
 * with probability sw_c / sum sw.
 *
 * Where we sample differently from Cycles (evaluation is Cycles'; only
 * variance changes, and the pdfs below are the exact densities of our
 * sampling, so MIS in pathtrace.c stays unbiased):
 *  - GGX lobes: the exact visible-normal sampling of Heitz 2018 (Cycles:
 *    Heitz & d'Eon 2014's slope sampling, same density);
 *  - clearcoat: the GTR1 distribution itself, cos^2 theta_h =
 *    (1 - a^(2(1-u))) / (1 - a^2) (Burley 2012, appendix B). Cycles samples
 *    GGX visible normals of the clearcoat alpha and divides by the GTR1
 *    pdf, so its BSDF-sampled clearcoat differs from its evaluated one;
 *    direct light (evaluation) is the same here and there;
 *  - Multiscatter GGX: with probability A (Cycles' fitted single-scatter
 *    albedo mf_ggx_albedo) a GGX visible normal, else a cosine direction:
 *    exactly Cycles' approximate pdf mf_ggx_pdf, which is here the true
 *    density. Cycles walks the microsurface instead (mf_sample), whose
 *    throughput is not its mf_eval's: in mf_eval the multiple-scattering
 *    orders are weighted by the Fresnel product twice (eval += throughput *
 *    phase, phase already times throughput). We evaluate exactly as mf_eval
 *    does, so lights match Cycles; bounced light off coloured rough metal
 *    differs from Cycles' by that second Fresnel product of its >= 2-bounce
 *    part (nothing for white or dielectric layers at low F0);
 *  - Oren-Nayar: cosine-weighted (Cycles: uniform hemisphere).
 * Multiscatter GGX glass (transmission with roughness > 0.05 and the
 * Multiscatter distribution) is rendered with the single-scatter GGX glass
 * pair (the loader says so in a warning). Anisotropy turns around the
 * surface's tangent (pb_surface.tangent). */
#include <float.h>
#include <string.h>

#include "ref/bsdf.h"
#include "shared/pb_principled2_tables.h"
#include "shared/pb_thin_film.h"

#define CUTOFF 1e-5f               /* CLOSURE_WEIGHT_CUTOFF */
#define SINGULAR_ALPHA2 1e-7f      /* alpha_x alpha_y at or below: a delta lobe */

static inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline float sat(float x) { return clampf(x, 0.0f, 1.0f); }
static inline float sqr(float x) { return x * x; }
static inline float avg3(v3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }
static inline v3 v3_sat(v3 c) { return v3_make(sat(c.x), sat(c.y), sat(c.z)); }
static inline v3 v3_splat(float x) { return v3_make(x, x, x); }

/* Rec.709 luminance of scene-linear RGB (Cycles' rgb_to_y for Blender's
 * default scene-linear space). */
static inline float luma709(v3 c) { return 0.2126729f * c.x + 0.7151522f * c.y + 0.0721750f * c.z; }

/* (1 - u)^5, u clamped: Schlick's weight. */
static inline float schlick_w(float u) {
  float m = sat(1.0f - u), m2 = m * m;
  return m2 * m2 * m;
}

/* Unpolarised reflectance of a dielectric of relative index eta at |cos i|
 * (Cycles' fresnel_dielectric_cos: 1 under total internal reflection). */
static float fresnel_diel(float cos_i, float eta) {
  float c = fabsf(cos_i);
  float g = eta * eta - 1.0f + c * c;
  if (g <= 0.0f) return 1.0f;
  g = sqrtf(g);
  float a = (g - c) / (g + c);
  float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
  return 0.5f * a * a * (1.0f + b * b);
}

/* Principled v1 Fresnel colour: cspec0 blended to white by the dielectric
 * Fresnel renormalised to 0 at normal incidence (interpolate_fresnel_color). */
static v3 fresnel_v1(v3 l, v3 h, float ior, float f0, v3 cspec0) {
  float t = (fresnel_diel(v3_dot(l, h), ior) - f0) / (1.0f - f0);
  return v3_add(v3_scale(cspec0, 1.0f - t), v3_splat(t));
}

/* A shading normal whose mirror image of i lies above the geometric surface
 * by at least min(0.9 ng.i, 0.01) (Cycles' ensure_valid_reflection, written
 * from its derivation): n is turned towards ng in the plane of n and ng, to
 * the new normal n' = (sqrt(1 - z^2), z) in the (x, ng) frame, x the part of
 * n orthogonal to ng, where z solves 2 (n'.i) z - i.z = t, i.e.
 * z^2 = (c +- b) / (2 a) with a = ix^2 + iz^2, b = sqrt(ix^2 (a - t^2)),
 * c = iz t + a. Of the two roots in (0, 1] the one giving the shallower
 * valid reflection is kept; ng when neither is. */
static v3 valid_reflection_normal(v3 ng, v3 i, v3 n) {
  v3 r = v3_sub(v3_scale(n, 2.0f * v3_dot(n, i)), i);
  float t = fminf(0.9f * v3_dot(ng, i), 0.01f);
  if (v3_dot(ng, r) >= t) return n;
  v3 x = v3_norm(v3_sub(n, v3_scale(ng, v3_dot(n, ng))));
  float ix = v3_dot(i, x), iz = v3_dot(i, ng);
  float a = ix * ix + iz * iz;
  float b = sqrtf(fmaxf(0.0f, ix * ix * (a - t * t)));
  float c = iz * t + a;
  float z1 = 0.5f / a * (b + c), z2 = 0.5f / a * (c - b);
  int ok1 = z1 > 1e-5f && z1 <= 1.0f + 1e-5f, ok2 = z2 > 1e-5f && z2 <= 1.0f + 1e-5f;
  float nz2;
  if (ok1 && ok2) {
    float n1x = sqrtf(fmaxf(0.0f, 1.0f - z1)), n1z = sqrtf(fmaxf(0.0f, z1));
    float n2x = sqrtf(fmaxf(0.0f, 1.0f - z2)), n2z = sqrtf(fmaxf(0.0f, z2));
    float r1 = 2.0f * (n1x * ix + n1z * iz) * n1z - iz, r2 = 2.0f * (n2x * ix + n2z * iz) * n2z - iz;
    int v1 = r1 >= 1e-5f, v2 = r2 >= 1e-5f;
    if (v1 && v2) nz2 = r1 < r2 ? z1 : z2;
    else nz2 = r1 > r2 ? z1 : z2;
  } else if (ok1 || ok2) {
    nz2 = ok1 ? z1 : z2;
  } else {
    return ng;
  }
  return v3_add(v3_scale(x, sqrtf(fmaxf(0.0f, 1.0f - nz2))), v3_scale(ng, sqrtf(fmaxf(0.0f, nz2))));
}

/* Cycles' "bump shadowing" for diffuse lobes whose normal n differs from
 * the interpolated shading normal ns (bsdf.h bump_shadowing_term): no light
 * from below n seen from above ns or the reverse; then, up to Blender 4.4,
 * Chiang et al. 2019 ("Taming the Shadow Terminator") smoothing, and from
 * 4.5 the GGX shadowing of Conty Estevez et al. 2019 ("A Microfacet-Based
 * Shadowing Function to Solve the Bump Terminator Problem") with alpha^2 =
 * tan^2(n, ns) / 8; none with Bump Map Correction off (4.2+). */
static float bump_shadowing(pb_bump_model model, v3 ns, v3 n, v3 wi) {
  float cgi = v3_dot(ns, wi), cgn = v3_dot(ns, n), cni = v3_dot(n, wi);
  if (model == PB_BUMP_CONTY) {
    if (cgi * cgn * cni < 0.0f) return 0.0f;
    float ci = fabsf(cgi), cd = fabsf(cgn);
    if (cd >= 1.0f || ci >= 1.0f) return 1.0f;
    if (ci < 1e-6f) return 0.0f;
    float a2 = sat(0.125f * (1.0f / (cd * cd) - 1.0f));
    float lambda = 0.5f * (sqrtf(1.0f + a2 * fmaxf(1.0f / (ci * ci) - 1.0f, 0.0f)) - 1.0f);
    return 1.0f / (1.0f + lambda);
  }
  v3 g = cni < 0.0f ? v3_neg(ns) : ns;
  float den = cni * v3_dot(g, n);
  float x = den != 0.0f ? v3_dot(g, wi) / den : 0.0f;
  if (x >= 1.0f) return 1.0f;
  if (x < 0.0f) return 0.0f;
  if (model == PB_BUMP_NONE) return 1.0f;
  float x2 = x * x;
  return -x2 * x + x2 + x;
}

/* Oren-Nayar as Cycles computes it (bsdf_oren_nayar.h): Fujii's improved
 * model, f = (a + b t) / 1 with a = 1 / (pi + sigma (pi/2 - 2/3)), b =
 * sigma a, t = max(0, cos phi) sin sin / max(cos, cos); from Cycles 4.3
 * (Blender's "EON") plus OpenPBR's energy-preserving multiple scattering,
 * ms (1 - E(wo)) (1 - E(wi)) with E(mu) = a pi + b G(mu) its albedo and
 * ms = rho^2 Eavg / (1 - Eavg) / (pi (1 - rho (1 - Eavg))) for the
 * albedo rho. Kept in the closure: on_a, on_b, and color = ms (1 - E(wo)). */
static float oren_nayar_G(float c) {
  if (c < 1e-6f) return (0.5f * PB_PI_F - 2.0f / 3.0f) - c;
  float s = sqrtf(fmaxf(0.0f, 1.0f - c * c)), th = acosf(fminf(c, 1.0f));
  return s * (th - 2.0f / 3.0f - s * c) + 2.0f / 3.0f * (s / c) * (1.0f - s * s * s);
}
static void oren_nayar(pb_closure *c, float sigma, v3 albedo, int ms, v3 wo) {
  if (sigma <= 0.0f) {
    c->on_a = PB_INV_PI_F; /* bsdf_diffuse: Lambert */
    return;
  }
  sigma = sat(sigma);
  c->on_a = 1.0f / (PB_PI_F + sigma * (0.5f * PB_PI_F - 2.0f / 3.0f));
  c->on_b = sigma * c->on_a;
  if (!ms) return;
  v3 rho = v3_sat(albedo);
  float eavg = c->on_a * PB_PI_F + ((2.0f * PB_PI_F - 5.6f) / 3.0f) * c->on_b;
  float ev = c->on_a * PB_PI_F + c->on_b * oren_nayar_G(fmaxf(v3_dot(c->n, wo), 0.0f));
  float k = PB_INV_PI_F * (eavg / (1.0f - eavg)) * (1.0f - ev);
  c->color = v3_make(k * rho.x * rho.x / (1.0f - rho.x * (1.0f - eavg)), k * rho.y * rho.y / (1.0f - rho.y * (1.0f - eavg)),
                     k * rho.z * rho.z / (1.0f - rho.z * (1.0f - eavg)));
}

/* Frame (x, y, n) of a lobe: around the tangent t when it is usable. */
static void lobe_frame(pb_closure *c, v3 n, v3 t) {
  c->n = n;
  v3 y = v3_cross(n, t);
  float l = v3_len(y);
  if (l > 1e-6f && isfinite(l)) {
    c->y = v3_scale(y, 1.0f / l);
    c->x = v3_cross(c->y, n);
  } else {
    v3_basis(n, &c->x, &c->y);
  }
}
/* Cycles' rotate_around_axis: tangent t turned about axis n by `turns` full
 * turns (Rodrigues), as the Anisotropic Rotation inputs turn it. */
static v3 turn_tangent(v3 t, v3 n, float turns) {
  if (turns == 0.0f) return t;
  float th = turns * 2.0f * PB_PI_F, cs = cosf(th), sn = sinf(th);
  return v3_add(v3_add(v3_scale(t, cs), v3_scale(v3_cross(n, t), sn)), v3_scale(n, v3_dot(n, t) * (1.0f - cs)));
}
static inline v3 to_lobe(const pb_closure *c, v3 w) { return v3_make(v3_dot(w, c->x), v3_dot(w, c->y), v3_dot(w, c->n)); }
static inline v3 from_lobe(const pb_closure *c, v3 l) {
  return v3_add(v3_add(v3_scale(c->x, l.x), v3_scale(c->y, l.y)), v3_scale(c->n, l.z));
}

/* ---- microfacet distribution (GGX) ------------------------------------- */

/* D of GGX for a lobe-space half vector, anisotropic alphas. */
static float ggx_d(v3 m, float ax, float ay) {
  if (m.z <= 0.0f) return 0.0f;
  float sx = m.x / ax, sy = m.y / ay;
  float k = sx * sx + sy * sy + m.z * m.z;
  return 1.0f / (PB_PI_F * ax * ay * k * k);
}
/* Smith G1 of GGX for lobe-space w (projected roughness for anisotropy). */
static float ggx_g1(v3 w, float ax, float ay) {
  float c2 = w.z * w.z;
  if (c2 <= 0.0f) return 0.0f;
  float s2 = w.x * w.x + w.y * w.y;
  float a2 = s2 > 0.0f ? (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / s2 : ax * ay;
  return 2.0f / (1.0f + sqrtf(fmaxf(0.0f, 1.0f + a2 * (1.0f - c2) / c2)));
}
/* Burley's GTR1 (clearcoat), cos of the half vector, alpha = a. */
static float gtr1_d(float c, float a) {
  if (a >= 1.0f) return PB_INV_PI_F;
  float a2 = a * a;
  return (a2 - 1.0f) / (PB_PI_F * logf(a2) * (1.0f + (a2 - 1.0f) * c * c));
}

/* Visible normal of GGX for lobe-space v (v.z > 0): Heitz 2018, listing 1. */
static v3 ggx_vndf(v3 v, float ax, float ay, float u1, float u2) {
  v3 vh = v3_norm(v3_make(ax * v.x, ay * v.y, v.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  v3 t1 = lensq > 0.0f ? v3_scale(v3_make(-vh.y, vh.x, 0.0f), 1.0f / sqrtf(lensq)) : v3_make(1.0f, 0.0f, 0.0f);
  v3 t2 = v3_cross(vh, t1);
  float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
  float p1 = r * cosf(phi), p2 = r * sinf(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrtf(fmaxf(0.0f, 1.0f - p1 * p1)) + s * p2;
  v3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)),
                 v3_scale(vh, sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2))));
  return v3_norm(v3_make(ax * nh.x, ay * nh.y, fmaxf(1e-7f, nh.z)));
}

static v3 cosine_dir(float u1, float u2) {
  float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
  return v3_make(r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.0f, 1.0f - u1)));
}

/* ---- Multiscatter GGX: the random walk of Heitz et al. 2016 ------------
 * ("Multiple-Scattering Microfacet BSDFs with the Smith Model"), as Cycles
 * 3.4 evaluates it (bsdf_microfacet_multi{,_impl}.h): the single-scattering
 * term analytically (height-correlated G2 of the uncorrelated Smith heights,
 * G2 = 1 / (1 + Lambda(wi) + Lambda(wo))), then up to 9 further bounces on
 * the microsurface, each adding the phase function towards wo times the
 * masking G1 of wo from that height. Directions are lobe space; "down"
 * directions (into the surface) have z < 0. */

static float mf_lambda(v3 w, float ax, float ay) {
  if (w.z > 0.9999f) return 0.0f;
  if (w.z < -0.9999f) return -0.9999f;
  float inv = 1.0f / fmaxf(w.z * w.z, 1e-7f);
  float wx = w.x * ax, wy = w.y * ay;
  float v = sqrtf(1.0f + (wx * wx + wy * wy) * inv);
  if (w.z <= 0.0f) v = -v;
  return 0.5f * (v - 1.0f);
}
static inline float mf_c1(float h) { return sat(0.5f * (h + 1.0f)); }
static inline float mf_inv_c1(float c) { return 2.0f * sat(c) - 1.0f; }
static float mf_g1(v3 w, float c1, float lambda) {
  if (w.z > 0.9999f) return 1.0f;
  if (w.z < 1e-5f) return 0.0f;
  return powf(c1, lambda);
}
/* Next height along w from the current one (c1 = C1(h)); 0: the ray
 * leaves the surface. */
static int mf_next_height(v3 w, float *h, float *c1, float *g1, float lambda, float u) {
  if (w.z > 0.9999f) return 0;
  if (w.z < -0.9999f) {
    *c1 *= u;
    *h = mf_inv_c1(*c1);
    *g1 = mf_g1(w, *c1, lambda);
  } else if (fabsf(w.z) >= 1e-4f) {
    if (u > 1.0f - *g1) return 0;
    *c1 = lambda >= 0.0f ? 1.0f : *c1 * powf(1.0f - u, -1.0f / lambda);
    *h = mf_inv_c1(*c1);
    *g1 = mf_g1(w, *c1, lambda);
  }
  return 1;
}
/* A visible normal of GGX seen from any direction v (also from below, as
 * the walk needs): Heitz & d'Eon 2014 ("Importance Sampling Microfacet-Based
 * BSDFs using the Distribution of Visible Normals"): stretch v to alpha 1,
 * draw the slope of the visible-normal distribution there (x by inverting
 * its CDF in closed form, y through the supplemental material's rational
 * fit of the inverse CDF), rotate to v's azimuth, unstretch. */
static v3 walk_vndf(v3 v, float ax, float ay, float u1, float u2) {
  v3 s = v3_norm(v3_make(ax * v.x, ay * v.y, v.z));
  float sx, sy;
  if (s.z > 0.9999f || fabsf(s.z) < 1e-6f) {
    float r = sqrtf(u1 / fmaxf(1.0f - u1, 1e-7f)), phi = 2.0f * PB_PI_F * u2;
    sx = r * cosf(phi);
    sy = r * sinf(phi);
  } else {
    float sin_t = sqrtf(fmaxf(0.0f, 1.0f - s.z * s.z)), tan_t = sin_t / s.z;
    float proj = 0.5f * (s.z + 1.0f); /* the stretched G1 is s.z / proj */
    if (proj < 1e-4f) return v3_make(0.0f, 0.0f, 1.0f);
    float a = 2.0f * u1 * proj / s.z - 1.0f;
    float q = a * a - 1.0f;
    if (fabsf(q) < 1e-7f) return v3_make(0.0f, 0.0f, 1.0f);
    q = 1.0f / q;
    float d = sqrtf(fmaxf(0.0f, tan_t * tan_t * q * q - (a * a - tan_t * tan_t) * q));
    float x2 = tan_t * q + d;
    sx = (a < 0.0f || x2 > 1.0f / tan_t) ? tan_t * q - d : x2;
    float sign = u2 >= 0.5f ? 1.0f : -1.0f, w = 2.0f * fabsf(u2 - 0.5f);
    float z = (w * (w * (w * 0.27385f - 0.73369f) + 0.46341f)) /
              (w * (w * (w * 0.093073f + 0.309420f) - 1.0f) + 0.597999f);
    sy = sign * z * sqrtf(1.0f + sx * sx);
  }
  float pl = sqrtf(s.x * s.x + s.y * s.y);
  float cp = pl > 0.0f ? s.x / pl : 1.0f, sp = pl > 0.0f ? s.y / pl : 0.0f;
  float mx = ax * (cp * sx - sp * sy), my = ay * (sp * sx + cp * sy);
  return v3_norm(v3_make(-mx, -my, 1.0f));
}

/* GGX D as Cycles' random walk writes it (guarded denominators). */
static float mf_d(v3 m, float ax, float ay) {
  if (ax == ay) {
    float z2 = m.z * m.z, a2 = ax * ax;
    float k = (1.0f - z2) + a2 * z2;
    return a2 / fmaxf(PB_PI_F * k * k, 1e-7f);
  }
  float sx = -m.x / ax, sy = -m.y / ay;
  float k = m.z * m.z + sx * sx + sy * sy;
  return 1.0f / fmaxf(PB_PI_F * k * k * ax * ay, 1e-7f);
}
/* Reflection phase function from travel direction w (downwards) to wo. */
static float mf_phase(v3 w, float lambda, v3 wo, float ax, float ay) {
  if (w.z > 0.9999f) return 0.0f;
  v3 h = v3_norm(v3_sub(wo, w));
  if (h.z < 0.0f) return 0.0f;
  float area = w.z < -0.9999f ? 1.0f : lambda * w.z;
  float wh = -v3_dot(w, h);
  if (wh < 0.0f) return 0.0f;
  return fmaxf(0.0f, wh) * 0.25f / fmaxf(area * wh, 1e-7f) * mf_d(h, ax, ay);
}

/* f cos of the Multiscatter GGX reflection lobe c, lobe-space wo (view),
 * wi (light), one random walk. */
static v3 multi_ggx_eval(const pb_closure *c, v3 wo, v3 wi, pb_rng *rng) {
  /* Walk from the shallower direction (less noise), as Cycles does; the
   * BSDF is reciprocal, the cosine is swapped back at the end. */
  v3 a = wo, b = wi;
  int swapped = 0;
  if (b.z < a.z) {
    a = wi;
    b = wo;
    swapped = 1;
  }
  if (a.z < 1e-5f || b.z < 1e-5f) return v3_splat(0.0f);
  float ax = c->ax, ay = c->ay;
  float lambda_r = mf_lambda(v3_neg(a), ax, ay);
  float shadow_lambda = mf_lambda(b, ax, ay);
  v3 h = v3_norm(v3_add(a, b));
  float g2 = 1.0f / (1.0f - (lambda_r + 1.0f) + shadow_lambda);
  float single = g2 * 0.25f / a.z * mf_d(h, ax, ay);
  v3 thr = fresnel_v1(a, h, c->ior, c->f0, c->cspec0);
  v3 eval = v3_scale(thr, single);
  v3 wr = v3_neg(a);
  float hr = 1.0f, c1 = 1.0f, g1 = 0.0f;
  for (int order = 0; order < 10; ++order) {
    float uh = rng ? pb_rng_f(rng) : 0.5f;
    if (!mf_next_height(wr, &hr, &c1, &g1, lambda_r, uh)) break;
    float uy = rng ? pb_rng_f(rng) : 0.5f, ux = rng ? pb_rng_f(rng) : 0.5f;
    v3 up = v3_neg(wr);
    v3 m = walk_vndf(up, ax, ay, ux, uy);
    if (order > 0) {
      /* Cycles' mf_eval: phase x throughput, added x throughput again. */
      float ph = mf_phase(wr, lambda_r, b, ax, ay) * mf_g1(b, mf_c1(hr), shadow_lambda);
      eval = v3_add(eval, v3_scale(v3_mul(thr, thr), ph));
    }
    if (order + 1 < 10) {
      if (order > 0) thr = v3_mul(thr, fresnel_v1(up, m, c->ior, c->f0, c->cspec0));
      wr = v3_sub(v3_scale(m, 2.0f * v3_dot(up, m)), up);
      lambda_r = mf_lambda(wr, ax, ay);
      c1 = mf_c1(hr);
      g1 = mf_g1(wr, c1, lambda_r);
    }
  }
  if (swapped) eval = v3_scale(eval, fabsf(a.z / b.z));
  return eval;
}

/* Cycles' fitted single-scatter albedo of GGX (mf_ggx_albedo), the share
 * of visible-normal sampling in our Multiscatter GGX sampling. */
static float multi_ggx_albedo(float r) {
  float a = 0.806495f * expf(-1.98712f * r * r) + 0.199531f;
  a -= ((((((1.76741f * r - 8.43891f) * r + 15.784f) * r - 14.398f) * r + 6.45221f) * r - 1.19722f) * r +
        0.027803f) * r + 0.00568739f;
  return sat(a);
}
/* Density of that sampling (Cycles' mf_ggx_pdf / mf_ggx_aniso_pdf). */
static float multi_ggx_pdf(const pb_closure *c, v3 wo, v3 wi) {
  float d = mf_d(v3_norm(v3_add(wo, wi)), c->ax, c->ay);
  float lambda = mf_lambda(wo, c->ax, c->ay);
  float single = 0.25f * d / fmaxf((1.0f + lambda) * wo.z, 1e-7f);
  float a = multi_ggx_albedo(c->ax == c->ay ? c->ax : sqrtf(c->ax * c->ay));
  return a * single + (1.0f - a) * fmaxf(wi.z, 0.0f) * PB_INV_PI_F;
}

/* ---- one closure --------------------------------------------------------- */

static v3 v2_eval(const pb_closure *c, v3 lo, v3 li, float cos_gi, float *pdf);

/* f cos of closure c for world wo (view) and wi (light), and its pdf under
 * our sampling of c; ng: geometric normal facing wo; ns: the interpolated
 * shading normal (pb_surface.ni, for bump shadowing). */
static v3 closure_eval(const pb_closure *c, v3 ng, v3 ns, pb_bump_model bump, v3 wo, v3 wi, pb_rng *rng, float *pdf) {
  *pdf = 0.0f;
  v3 zero = v3_splat(0.0f);
  if (c->singular || c->type == PB_CL_TRANSPARENT) return zero;
  float cos_gi = v3_dot(ng, wi);
  v3 lo = to_lobe(c, wo), li = to_lobe(c, wi);
  switch (c->type) {
  case PB_CL_DIFFUSE:
  case PB_CL_SHEEN:
  case PB_CL_OREN_NAYAR: {
    if (li.z <= 0.0f) return zero;
    float v;
    if (c->type == PB_CL_DIFFUSE) {
      float fo = schlick_w(lo.z), fi = schlick_w(li.z);
      float rr = c->rough * (v3_dot(wi, wo) + 1.0f);
      v = PB_INV_PI_F * li.z * ((1.0f - 0.5f * fo) * (1.0f - 0.5f * fi) + rr * (fi + fo + fi * fo * (rr - 1.0f)));
    } else if (c->type == PB_CL_SHEEN) {
      if (lo.z < 0.0f) return zero;
      v = schlick_w(v3_dot(wi, v3_norm(v3_add(wi, wo)))) * li.z;
    } else {
      float nv = fmaxf(lo.z, 0.0f), t = v3_dot(wi, wo) - li.z * nv;
      if (t > 0.0f) t /= fmaxf(li.z, nv) + FLT_MIN;
      v = li.z * (c->on_a + c->on_b * t);
    }
    *pdf = li.z * PB_INV_PI_F;
    /* Oren-Nayar's multiple scattering (oren_nayar; 0 but from Cycles 4.3). */
    v3 f = v3_splat(v);
    if (c->type == PB_CL_OREN_NAYAR && c->on_b > 0.0f)
      f = v3_add(f, v3_scale(c->color, li.z * (1.0f - c->on_a * PB_PI_F - c->on_b * oren_nayar_G(li.z))));
    /* Diffuse lobes on a lifted normal: Cycles' bump shadowing term. */
    if (v3_dot(c->n, ns) < 1.0f - 1e-6f) f = v3_scale(f, bump_shadowing(bump, ns, c->n, wi));
    return f;
  }
  case PB_CL_GGX:
  case PB_CL_CLEARCOAT: {
    if (cos_gi < 0.0f || lo.z <= 0.0f || li.z <= 0.0f) return zero;
    v3 m = v3_norm(v3_add(lo, li));
    float d, g1o, g1i;
    if (c->type == PB_CL_CLEARCOAT) {
      d = gtr1_d(m.z, c->ax);
      g1o = ggx_g1(lo, 0.25f, 0.25f);
      g1i = ggx_g1(li, 0.25f, 0.25f);
    } else {
      d = ggx_d(m, c->ax, c->ay);
      g1o = ggx_g1(lo, c->ax, c->ay);
      g1i = ggx_g1(li, c->ax, c->ay);
    }
    v3 f = fresnel_v1(li, m, c->ior, c->f0, c->cspec0);
    if (c->type == PB_CL_CLEARCOAT) f = v3_scale(f, 0.25f * c->clearcoat);
    float common = d * 0.25f / lo.z;
    float wm = v3_dot(lo, m);
    /* Our sampling: GGX visible normals (Cycles' pdf), GTR1 for the coat. */
    *pdf = c->type == PB_CL_CLEARCOAT ? (wm > 0.0f ? d * m.z * 0.25f / wm : 0.0f) : g1o * common;
    /* Blender 3.5+: height-correlated 1 / (1 + L(o) + L(i)), with
     * 1 / G1 = 1 + L. */
    float g = c->g2 && g1o > 0.0f && g1i > 0.0f ? 1.0f / (1.0f / g1o + 1.0f / g1i - 1.0f) : g1o * g1i;
    return v3_scale(f, g * common);
  }
  case PB_CL_MULTI_GGX: {
    if (cos_gi < 0.0f || lo.z <= 0.0f || li.z <= 0.0f) return zero;
    *pdf = multi_ggx_pdf(c, lo, li);
    if (!(*pdf > 0.0f)) {
      *pdf = 0.0f;
      return zero;
    }
    return multi_ggx_eval(c, lo, li, rng);
  }
  case PB_CL_GGX_REFRACT: {
    if (cos_gi >= 0.0f || lo.z <= 0.0f || li.z >= 0.0f) return zero;
    float eta = c->ior;
    v3 ht = v3_neg(v3_add(v3_scale(li, eta), lo));
    float ht2 = v3_dot(ht, ht);
    if (!(ht2 > 0.0f)) return zero;
    v3 m = v3_scale(ht, 1.0f / sqrtf(ht2));
    if (m.z < 0.0f) m = v3_neg(m);
    float d = ggx_d(m, c->ax, c->ay);
    float g1o = ggx_g1(lo, c->ax, c->ay), g1i = ggx_g1(v3_neg(li), c->ax, c->ay);
    float common = d * eta * eta / (lo.z * ht2);
    float hh = fabsf(v3_dot(m, lo) * v3_dot(m, li));
    *pdf = g1o * hh * common;
    float g = c->g2 && g1o > 0.0f && g1i > 0.0f ? 1.0f / (1.0f / g1o + 1.0f / g1i - 1.0f) : g1o * g1i;
    return v3_splat(g * hh * common);
  }
  case PB_CL_V2_SHEEN:
  case PB_CL_V2_GGX:
  case PB_CL_V2_GLASS:
    return v2_eval(c, lo, li, cos_gi, pdf);
  case PB_CL_VELVET: {
    /* Cycles 4.5 closure/bsdf_ashikhmin_velvet.h (OSL's): f cos = D G /
     * (4 cos_view), D = exp(-cot^2 / sigma^2) / (pi sigma^2 sin^4), G =
     * min(1, 2 |cos_nh / cos_hv| cos_view, ... cos_light); sampled uniformly
     * over the hemisphere. */
    if (!(lo.z > 0.0f && li.z > 0.0f)) return zero;
    v3 h = v3_norm(v3_add(lo, li));
    float cos_nh = h.z, cos_hv = fabsf(v3_dot(lo, h));
    if (!(fabsf(cos_nh) < 1.0f - 1e-5f && cos_hv > 1e-5f)) return zero;
    float q = fmaxf(cos_nh / cos_hv, 1e-5f);
    float sin2 = 1.0f - cos_nh * cos_nh, cot2 = cos_nh * cos_nh / sin2;
    float d = expf(-cot2 * c->on_a) * c->on_a * PB_INV_PI_F / (sin2 * sin2);
    float g = fminf(1.0f, fminf(2.0f * fabsf(q * lo.z), 2.0f * fabsf(q * li.z)));
    *pdf = 0.5f * PB_INV_PI_F;
    return v3_splat(0.25f * d * g / lo.z);
  }
  default:
    return zero;
  }
}

/* ---- setup ---------------------------------------------------------------- */

static float input_value(const pb_scene *s, const pb_material *m, const pb_surface *surf, pb_blender_input i) {
  const pb_blender_material *b = &m->blender;
  const pb_input_texture *t = &b->input_tex[i];
  if (t->tex < 0 || (uint32_t)t->tex >= s->texture_count) return b->input[i];
  float c[4];
  pb_texture_lookup(&s->textures[t->tex], surf->uv, surf->uv1, c);
  return t->channel < 4 ? c[t->channel] : luma709(v3_make(c[0], c[1], c[2]));
}

float pb_blender_alpha(const pb_scene *s, const pb_surface *surf) {
  return sat(input_value(s, surf->mat, surf, PB_IN_ALPHA));
}

static v3 color_value(const pb_scene *s, v3 constant, int32_t tex, const pb_surface *surf) {
  if (tex < 0 || (uint32_t)tex >= s->texture_count) return constant;
  float c[4];
  pb_texture_lookup(&s->textures[tex], surf->uv, surf->uv1, c);
  return v3_make(c[0], c[1], c[2]);
}

static pb_closure *add_closure(pb_bsdf *b, pb_closure_type type, v3 weight) {
  weight = v3_make(fmaxf(weight.x, 0.0f), fmaxf(weight.y, 0.0f), fmaxf(weight.z, 0.0f));
  float sw = fabsf(avg3(weight));
  if (!(sw >= CUTOFF) || b->ncl >= PB_CLOSURE_MAX) return NULL;
  pb_closure *c = &b->cl[b->ncl++];
  memset(c, 0, sizeof *c);
  c->type = type;
  c->weight = weight;
  c->sample_weight = sw;
  return c;
}

/* A GGX-family lobe's alphas and Fresnel; sample weight x the average
 * Fresnel colour at the normal (bsdf_microfacet_fresnel_color). */
static void microfacet(pb_closure *c, v3 n, v3 t, float ax, float ay, float ior, v3 cspec0, v3 wo) {
  lobe_frame(c, n, t);
  c->ax = ax;
  c->ay = ay;
  c->ior = ior;
  c->f0 = fresnel_diel(1.0f, ior);
  c->cspec0 = v3_sat(cspec0);
  c->singular = ax * ay <= SINGULAR_ALPHA2;
  if (c->type == PB_CL_GGX || c->type == PB_CL_MULTI_GGX || c->type == PB_CL_CLEARCOAT) {
    v3 fc = fresnel_v1(wo, n, ior, c->f0, c->cspec0);
    if (c->type == PB_CL_CLEARCOAT) fc = v3_scale(fc, 0.25f * c->clearcoat);
    c->sample_weight *= avg3(fc);
  }
}


/* ---- Principled v2 (Blender 4.x, Cycles 4.5) ------------------------------
 * Read from Cycles v4.5.0: svm/closure.h (CLOSURE_BSDF_PRINCIPLED_ID) builds
 * the closures top to bottom with a running colour weight w:
 *   transparent (1 - alpha), w *= alpha;
 *   sheen       sheen x tint x w x LTC albedo; w layered under it;
 *   coat        coat x w, GGX of coat roughness^2, dielectric Fresnel of the
 *               coat IOR, always energy-compensated; w layered under it, then
 *               w *= mix(1, tint^(1/cos_t), coat) (Beer through the coat);
 *   emission    x w (pb_principled2_emission_weight);
 *   metal       metallic x w, GGX aniso, F82-tint Fresnel; w *= 1 - metallic;
 *   glass       transmission x w, GGX glass, generalized Schlick on the real
 *               Fresnel curve, F0 = F0(ior) specular tint, transmission tint
 *               sqrt(base); w *= 1 - transmission;
 *   specular    w, GGX aniso, F0 = F0(ior) 2 level x tint on the real curve of
 *               ior_from_F0; w layered under it;
 *   diffuse     Lambert, or Oren-Nayar with multiple scattering where the
 *               Diffuse Roughness is above 0 (oren_nayar), base (1 -
 *               subsurface) w, plus the subsurface part clamped base x
 *               subsurface x w rendered as diffuse too.
 * Layering is closure_layering_weight: w sat(1 - max(albedo / w)), albedo
 * the closure weight x bsdf_microfacet_estimate_albedo (tables). MULTI_GGX
 * compensates energy as microfacet_ggx_preserve_energy (Turquin 2019: scale
 * 1/E; Kulla-Conty darkening of the weight for coloured Fss). Smith G2 is
 * height-correlated (Cycles 3.5+). Tables: shaders/shared/
 * pb_principled2_tables.h (Cycles' own figures). Thin film (4.2+) on the
 * glass and the specular: thin_film_fresnel below. Not rendered:
 * subsurface scattering (diffuse), coat normal. */

static inline v3 v3_maxv(v3 a, v3 b) { return v3_make(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)); }

static float lut1(const float *t, float x, int n) {
  x = sat(x) * (float)(n - 1);
  int i = (int)x;
  if (i > n - 1) i = n - 1;
  int j = i + 1 < n ? i + 1 : n - 1;
  float f = x - (float)i;
  return f == 0.0f ? t[i] : (1.0f - f) * t[i] + f * t[j];
}
static float lut2(const float *t, float x, float y, int nx, int ny) {
  y = sat(y) * (float)(ny - 1);
  int i = (int)y;
  if (i > ny - 1) i = ny - 1;
  int j = i + 1 < ny ? i + 1 : ny - 1;
  float f = y - (float)i;
  float a = lut1(t + nx * i, x, nx);
  return f == 0.0f ? a : (1.0f - f) * a + f * lut1(t + nx * j, x, nx);
}
static float lut3(const float *t, float x, float y, float z, int nx, int ny, int nz) {
  z = sat(z) * (float)(nz - 1);
  int i = (int)z;
  if (i > nz - 1) i = nz - 1;
  int j = i + 1 < nz ? i + 1 : nz - 1;
  float f = z - (float)i;
  float a = lut2(t + nx * ny * i, x, y, nx, ny);
  return f == 0.0f ? a : (1.0f - f) * a + f * lut2(t + nx * ny * j, x, y, nx, ny);
}

static inline float f0_of(float eta) { return sqr((eta - 1.0f) / (eta + 1.0f)); }
static inline float eta_of_f0(float f0) {
  float r = sqrtf(clampf(f0, 0.0f, 0.99f));
  return (1.0f + r) / (1.0f - r);
}
static inline float avgmix(v3 a, float s) { return avg3(v3_add(v3_scale(a, 1.0f - s), v3_splat(s))); }
static inline v3 mix1(v3 a, float s) { return v3_add(v3_scale(a, 1.0f - s), v3_splat(s)); }
/* Average single-scattering dielectric Fresnel (Cycles' fitted polynomial). */
static float fresnel_diel_avg(float eta) {
  if (eta < 1.0f) return 0.997118f + eta * (0.1014f - eta * (0.965241f + eta * 0.130607f));
  return (eta - 1.0f) / (4.08567f + 1.00071f * eta);
}

/* Cycles 4.5 src/kernel/closure/bsdf_util.h fresnel_conductor: a conductor
 * of complex IOR n + ik, per channel. */
static float fresnel_cond1(float cosi, float eta, float k) {
  float cosi2 = cosi * cosi, tmp_f = eta * eta + k * k, tmp = tmp_f * cosi2;
  float rparl2 = (tmp - 2.0f * eta * cosi + 1.0f) / (tmp + 2.0f * eta * cosi + 1.0f);
  float rperp2 = (tmp_f - 2.0f * eta * cosi + cosi2) / (tmp_f + 2.0f * eta * cosi + cosi2);
  return 0.5f * (rparl2 + rperp2);
}
static v3 fresnel_cond(float cosi, v3 eta, v3 k) {
  return v3_make(fresnel_cond1(cosi, eta.x, k.x), fresnel_cond1(cosi, eta.y, k.y), fresnel_cond1(cosi, eta.z, k.z));
}

/* ---- thin-film iridescence ------------------------------------------------
 * Cycles 4.5 closure/bsdf_util.h fresnel_iridescence (Belcour and Barla
 * 2017, "A Practical Extension to Microfacet Theory for the Modeling of
 * Varying Iridescence"): the Airy sum of the film's two interfaces, outside
 * medium (index 1) / film / base, per polarisation, to the third order of
 * path differences, integrated against the CIE XYZ sensitivities in Fourier
 * space (the Gaussian fit), times the white point and converted to linear
 * Rec.709, clamped to [0, 1]. Computed here in double. */

#define TF_PI 3.14159265358979323846

/* One interface of relative index eta at cos_i (either sign):
 * reflectances s and p, their phase shifts (0 or pi) and the cosine of the
 * transmitted ray relative to the normal (negative). 0 under total internal
 * reflection (closure/bsdf_util.h fresnel_dielectric_polarized). */
static int tf_interface(double cos_i, double eta, double rr[2], double ph[2], double *cos_t) {
  double e2 = eta * eta - (1.0 - cos_i * cos_i);
  if (e2 <= 0.0) return 0;
  double ci = fabs(cos_i), ct = -sqrt(e2) / eta;
  double as = (ci + eta * ct) / (ci - eta * ct), ap = (ct + eta * ci) / (eta * ci - ct);
  rr[0] = as * as;
  rr[1] = ap * ap;
  ph[0] = as < 0.0 ? TF_PI : 0.0;
  ph[1] = ap < 0.0 ? TF_PI : 0.0;
  *cos_t = ct;
  return 1;
}

/* The XYZ sensitivity of optical path difference opd (nm) with phase shift
 * `shift` (iridescence_lookup_sensitivity). */
static void tf_sensitivity(double opd, double shift, double xyz[3]) {
  double ph = 2.0 * TF_PI * opd * 1e-9, ph2 = ph * ph;
  const double val[3] = {PB_TF_VAL_X, PB_TF_VAL_Y, PB_TF_VAL_Z};
  const double pos[3] = {PB_TF_POS_X, PB_TF_POS_Y, PB_TF_POS_Z};
  const double var[3] = {PB_TF_VAR_X, PB_TF_VAR_Y, PB_TF_VAR_Z};
  for (int k = 0; k < 3; ++k) xyz[k] = val[k] * sqrt(2.0 * TF_PI * var[k]) * cos(pos[k] * ph + shift) * exp(-ph2 * var[k]);
  xyz[0] += PB_TF_X2_AMP * cos(PB_TF_X2_POS * ph + shift) * exp(-PB_TF_X2_VAR * ph2);
  for (int k = 0; k < 3; ++k) xyz[k] /= PB_TF_NORM;
}

/* Reflectance (XYZ) of one polarisation: orders 0..3 of the Airy sum
 * (iridescence_airy_summation, the paper's equation 10). */
static void tf_airy(double t121, double r12, double r23, double opd, double phi, double xyz[3]) {
  if (r23 == 1.0) {
    xyz[0] = xyz[1] = xyz[2] = 1.0;
    return;
  }
  double r123 = r12 * r23, a = sqrt(r123), rs = t121 * t121 * r23 / (1.0 - r123);
  xyz[0] = xyz[1] = xyz[2] = r12 + rs;
  double cm = rs - t121;
  for (int m = 1; m <= 3; ++m) {
    double sm[3];
    cm *= a;
    tf_sensitivity(m * opd, m * phi, sm);
    for (int k = 0; k < 3; ++k) xyz[k] += 2.0 * cm * sm[k];
  }
}

/* Reflectance (linear Rec.709) of a film of index eta2 and thickness d (nm)
 * between the outside (1) and a base of index eta3, at cos_i. */
static v3 thin_film_fresnel(float cos_i, float eta2, float eta3, float d) {
  double e1 = 1.0, e2 = eta2, e3 = eta3;
  if (d < PB_TF_BLEND_THICKNESS) {
    double u = d / PB_TF_BLEND_THICKNESS;
    u = u <= 0.0 ? 0.0 : (u >= 1.0 ? 1.0 : u * u * (3.0 - 2.0 * u));
    e2 = e1 + (e2 - e1) * u;
  }
  double r12[2], p12[2], r23[2], p23[2], c2, c3;
  if (!tf_interface(cos_i, e2 / e1, r12, p12, &c2) || (r12[0] == 1.0 && r12[1] == 1.0)) return v3_splat(1.0f);
  double opd = -2.0 * e2 * d * c2;
  if (!tf_interface(-c2, e3 / e2, r23, p23, &c3) || (r23[0] == 1.0 && r23[1] == 1.0)) return v3_splat(1.0f);
  double xs[3], xp[3], xyz[3];
  tf_airy(1.0 - r12[0], r12[0], r23[0], opd, TF_PI - p12[0] + p23[0], xs);
  tf_airy(1.0 - r12[1], r12[1], r23[1], opd, TF_PI - p12[1] + p23[1], xp);
  const double white[3] = {PB_TF_WHITE_X, PB_TF_WHITE_Y, PB_TF_WHITE_Z};
  for (int k = 0; k < 3; ++k) xyz[k] = 0.5 * (xs[k] + xp[k]) * white[k];
  double r = PB_TF_M00 * xyz[0] + PB_TF_M01 * xyz[1] + PB_TF_M02 * xyz[2];
  double g = PB_TF_M10 * xyz[0] + PB_TF_M11 * xyz[1] + PB_TF_M12 * xyz[2];
  double b = PB_TF_M20 * xyz[0] + PB_TF_M21 * xyz[1] + PB_TF_M22 * xyz[2];
  return v3_sat(v3_make((float)r, (float)g, (float)b));
}

/* Reflectance R and transmittance T of a v2 microfacet closure at cos
 * between the microfacet and the view. */
static void fresnel_v2(const pb_closure *c, float cos_hv, v3 *r, v3 *t) {
  if (c->fresnel == PB_FRESNEL_DIELECTRIC) {
    float f = fresnel_diel(cos_hv, c->ior);
    *r = v3_splat(f);
    *t = v3_splat(1.0f - f);
  } else if (c->fresnel == PB_FRESNEL_CONDUCTOR) {
    /* n in cspec0, k in color */
    *r = fresnel_cond(cos_hv, c->cspec0, c->color);
    *t = v3_splat(0.0f);
  } else if (c->fresnel == PB_FRESNEL_NONE) {
    /* microfacet_fresnel without a Fresnel: a reflection closure reflects
     * everything; a refraction closure transmits everything, except under
     * total internal reflection, where it has nothing. */
    int refraction = c->type == PB_CL_V2_GLASS;
    *r = v3_splat(refraction ? 0.0f : 1.0f);
    *t = v3_splat(refraction && fresnel_diel(cos_hv, c->ior) != 1.0f ? 1.0f : 0.0f);
  } else if (c->fresnel == PB_FRESNEL_F82_TINT) {
    float mu = sat(1.0f - cos_hv), mu5 = sqr(sqr(mu)) * mu;
    v3 fs = mix1(c->cspec0, mu5);
    *r = v3_sat(v3_sub(fs, v3_scale(c->color, cos_hv * mu5 * mu)));
    *t = v3_splat(0.0f);
  } else if (c->tf_thickness > (float)PB_TF_MIN_THICKNESS) {
    /* Generalized Schlick with a thin film (closure/bsdf_microfacet.h
     * microfacet_fresnel): the film's reflectance, scaled per channel by
     * F0 / F0(ior) as far as it lies from 1 towards F0(ior) (Specular Tint
     * and Specular IOR Level). */
    v3 f = thin_film_fresnel(cos_hv, c->tf_ior, c->ior, c->tf_thickness);
    float f0r = f0_of(c->ior);
    if (f0r > 1e-5f && !(f.x == 1.0f && f.y == 1.0f && f.z == 1.0f)) {
      float *fc = &f.x;
      const float *f0c = &c->cspec0.x;
      for (int k = 0; k < 3; ++k) {
        float sk = sat((fc[k] - 1.0f) / (f0r - 1.0f));
        fc[k] *= 1.0f + (f0c[k] / f0r - 1.0f) * sk;
      }
    }
    *r = f;
    *t = v3_mul(v3_sub(v3_splat(1.0f), f), c->ttint);
  } else {
    /* Generalized Schlick with a negative exponent: F0 to 1 along the real
     * dielectric curve of c->ior. */
    float fr = fresnel_diel(cos_hv, c->ior), f0r = f0_of(c->ior);
    float s = sat((fr - f0r) / (1.0f - f0r));
    v3 f = mix1(c->cspec0, s);
    *r = f;
    *t = v3_mul(v3_sub(v3_splat(1.0f), f), c->ttint);
  }
  if (c->type != PB_CL_V2_GLASS) *t = v3_splat(0.0f);
}

static inline float ggx_lambda(v3 w, float ax, float ay) {
  float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return 1e30f;
  return 0.5f * (sqrtf(1.0f + (sqr(ax * w.x) + sqr(ay * w.y)) / z2) - 1.0f);
}
/* GGX D, symmetric in the half vector's hemisphere (Cycles' bsdf_D). */
static float ggx_d2(v3 m, float ax, float ay) {
  float sx = m.x / ax, sy = m.y / ay;
  float k = sx * sx + sy * sy + m.z * m.z;
  return 1.0f / (PB_PI_F * ax * ay * k * k);
}

/* Beckmann (Cycles 4.5 closure/bsdf_microfacet.h): bsdf_aniso_D, and
 * bsdf_lambda_from_sqr_alpha_tan_n (Walter et al. 2007, below eq. 69). */
static float beckmann_d(v3 m, float ax, float ay) {
  float c2 = m.z * m.z;
  if (!(c2 > 0.0f)) return 0.0f;
  return expf(-(sqr(m.x / ax) + sqr(m.y / ay)) / c2) / (PB_PI_F * ax * ay * c2 * c2);
}
static float beckmann_lambda(v3 w, float ax, float ay) {
  float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return 1e30f;
  float s = (sqr(ax * w.x) + sqr(ay * w.y)) / z2;
  if (s < 0.39f) return 0.0f;
  float a = 1.0f / sqrtf(s);
  return ((0.396f * a - 1.259f) * a + 1.0f) / ((2.181f * a + 3.535f) * a);
}
/* A microfacet normal with density D(m) m.z (Walter et al. 2007, eq. 28-29
 * for the isotropic case): Beckmann's slopes are Gaussian of variance
 * alpha^2 / 2 per axis. */
static v3 beckmann_sample(float ax, float ay, float u1, float u2) {
  float r = sqrtf(-logf(fmaxf(1.0f - u1, 1e-30f))), phi = 2.0f * PB_PI_F * u2;
  return v3_norm(v3_make(-ax * r * cosf(phi), -ay * r * sinf(phi), 1.0f));
}

static v3 v2_eval(const pb_closure *c, v3 lo, v3 li, float cos_gi, float *pdf) {
  v3 zero = v3_splat(0.0f);
  if (c->type == PB_CL_V2_SHEEN) {
    if (li.z <= 0.0f) return zero;
    float a = c->on_a, b = c->on_b;
    float l2 = sqr(a * li.x + b * li.z) + sqr(a * li.y) + sqr(li.z);
    float v = PB_INV_PI_F * li.z * sqr(a / l2);
    *pdf = v;
    return v3_splat(v);
  }
  if (lo.z <= 0.0f) return zero;
  int is_t = li.z < 0.0f;
  if ((cos_gi < 0.0f) != is_t || (is_t && c->type != PB_CL_V2_GLASS)) return zero;
  v3 h = is_t ? v3_neg(v3_add(v3_scale(li, c->ior), lo)) : v3_add(lo, li);
  float hl = v3_len(h);
  if (!(hl > 0.0f)) return zero;
  float inv = 1.0f / hl;
  h = v3_scale(h, inv);
  float cos_hv = v3_dot(h, lo);
  v3 r, t;
  fresnel_v2(c, cos_hv, &r, &t);
  float ar = avg3(r), at = avg3(t);
  if (!(ar + at > 0.0f)) return zero;
  float ax = c->ax, ay = is_t ? c->ax : c->ay;
  float d = c->beckmann ? beckmann_d(h, ax, ay) : ggx_d2(h, ax, ay);
  float lv = c->beckmann ? beckmann_lambda(lo, ax, ay) : ggx_lambda(lo, ax, ay);
  float ll = c->beckmann ? beckmann_lambda(li, ax, ay) : ggx_lambda(li, ax, ay);
  float common = d / lo.z * (is_t ? sqr(c->ior * inv) * fabsf(cos_hv * v3_dot(h, li)) : 0.25f);
  float p_r = ar / (ar + at);
  /* The sampled normal's density: GGX's visible normals D G1(wo) |wo.h| /
   * wo.z, Beckmann's D |h.z|, through the same Jacobian. */
  float p_m = c->beckmann ? lo.z * fabsf(h.z) / fmaxf(fabsf(cos_hv), 1e-20f) : 1.0f / (1.0f + lv);
  *pdf = common * (is_t ? 1.0f - p_r : p_r) * p_m;
  float g = c->g2 ? 1.0f / (1.0f + lv + ll) : 1.0f / ((1.0f + lv) * (1.0f + ll));
  return v3_scale(is_t ? t : r, common * g * c->energy);
}

/* Turquin energy compensation of closure c for view cosine mu, with the
 * average single-scattering Fresnel fss (microfacet_ggx_preserve_energy). */
static void preserve_energy(pb_closure *c, float mu, v3 fss) {
  float rough = sqrtf(sqrtf(c->ax * c->ay)), e, eavg;
  if (c->type == PB_CL_V2_GLASS) {
    float ior = c->ior;
    const float *te = pb_ggx_glass_E, *ta = pb_ggx_glass_Eavg;
    if (ior < 1.0f) {
      ior = 1.0f / ior;
      te = pb_ggx_glass_inv_E;
      ta = pb_ggx_glass_inv_Eavg;
    }
    float z = sqrtf(fabsf((ior - 1.0f) / (ior + 1.0f)));
    e = lut3(te, rough, mu, z, 16, 16, 16);
    eavg = lut2(ta, rough, z, 16, 16);
  } else {
    e = lut2(pb_ggx_E, rough, mu, 32, 32);
    eavg = lut1(pb_ggx_Eavg, rough, 32);
  }
  float missing = (1.0f - e) / e;
  c->energy = 1.0f + missing;
  if (fss.x != 1.0f || fss.y != 1.0f || fss.z != 1.0f) {
    v3 dark;
    float *dk = &dark.x;
    const float *fs = &fss.x;
    for (int k = 0; k < 3; ++k) {
      float fms = fs[k] * eavg / (1.0f - fs[k] * (1.0f - eavg));
      dk[k] = (1.0f + fms * missing) / c->energy;
    }
    c->weight = v3_mul(c->weight, dark);
    c->sample_weight *= avg3(dark);
  }
}

/* bsdf_microfacet_estimate_albedo for view cosine mu (reflection, and
 * transmission when `trans`). */
static v3 v2_albedo(const pb_closure *c, float mu, int trans) {
  v3 r, t;
  fresnel_v2(c, mu, &r, &t);
  if (!trans) t = v3_splat(0.0f);
  if (r.x == 0.0f && r.y == 0.0f && r.z == 0.0f) return t;
  float rough = sqrtf(sqrtf(c->ax * c->ay));
  if (c->fresnel == PB_FRESNEL_GEN_SCHLICK && c->tf_thickness > (float)PB_TF_MIN_THICKNESS) {
    /* No table for the film: its reflectance at mu, as fresnel_v2 gave it
     * (bsdf_microfacet_estimate_albedo). */
  } else if (c->fresnel == PB_FRESNEL_GEN_SCHLICK) {
    float z = sqrtf(fabsf((c->ior - 1.0f) / (c->ior + 1.0f)));
    r = mix1(c->cspec0, lut3(pb_ggx_gen_schlick_ior_s, rough, mu, z, 16, 16, 16));
  } else if (c->fresnel == PB_FRESNEL_F82_TINT) {
    r = mix1(c->cspec0, lut3(pb_ggx_gen_schlick_s, rough, mu, 0.5f, 16, 16, 16));
  } else if (c->fresnel == PB_FRESNEL_NONE) {
    /* the smooth surface's: all */
  } else if (c->ior > 1.0f) {
    float z = sqrtf(fabsf((c->ior - 1.0f) / (c->ior + 1.0f)));
    r = v3_splat(avgmix(v3_splat(f0_of(c->ior)), lut3(pb_ggx_gen_schlick_ior_s, rough, mu, z, 16, 16, 16)));
  }
  return v3_add(r, t);
}

/* closure_layering_weight */
static v3 layer_under(v3 albedo, v3 w) {
  float m = 0.0f;
  const float *a = &albedo.x, *ww = &w.x;
  for (int k = 0; k < 3; ++k)
    if (ww[k] != 0.0f) m = fmaxf(m, a[k] / ww[k]);
  return v3_scale(w, sat(1.0f - m));
}

/* A v2 GGX-family closure: frame, alphas, and its sample weight x albedo. */
static void v2_microfacet(pb_closure *c, v3 n, v3 t, float ax, float ay, float ior, int fresnel, v3 f0, int g2) {
  lobe_frame(c, n, t);
  c->ax = sat(ax);
  c->ay = sat(ay);
  c->ior = ior;
  c->fresnel = fresnel;
  c->cspec0 = fresnel == PB_FRESNEL_GEN_SCHLICK ? v3_sat(f0) : f0;
  c->energy = 1.0f;
  c->g2 = g2;
  c->singular = c->ax * c->ay <= SINGULAR_ALPHA2;
}

typedef struct v2_inputs {
  float in[PB_IN_COUNT];
  v3 base, spec_tint, coat_tint, sheen_tint;
} v2_inputs;

static void v2_read(const pb_scene *s, const pb_surface *surf, v3 base, v2_inputs *v) {
  const pb_material *m = surf->mat;
  const pb_blender_material *bm = &m->blender;
  for (int i = 0; i < PB_IN_COUNT; ++i) v->in[i] = input_value(s, m, surf, (pb_blender_input)i);
  v->base = base;
  v3 z = v3_splat(0.0f);
  v->spec_tint = v3_maxv(color_value(s, v3_load(bm->specular_tint), bm->specular_tint_tex, surf), z);
  v->coat_tint = v3_maxv(color_value(s, v3_load(bm->coat_tint), bm->coat_tint_tex, surf), z);
  v->sheen_tint = v3_maxv(color_value(s, v3_load(bm->sheen_tint), bm->sheen_tint_tex, surf), z);
}

/* Blender 4.x's Glossy, Glass and Refraction BSDFs (Cycles 4.5
 * src/kernel/svm/closure.h, closure/bsdf_microfacet.h): one microfacet
 * closure each, on the valid reflection normal, with no layers and no
 * emission.
 * - Glossy (CLOSURE_BSDF_MICROFACET_GGX_ID, _MULTI_GGX_ID): weight Color,
 *   no Fresnel (bsdf_microfacet_ggx_setup); alpha = saturate(Roughness)^2,
 *   and for Anisotropy a = clamp(-0.99, 0.99) beyond 1e-4 alpha_x =
 *   alpha (1 - a), alpha_y = alpha / (1 - a) (a >= 0) or alpha / (1 + a),
 *   alpha (1 + a) (a < 0), the default tangent turned about that normal by
 *   Rotation x 2 pi; Multiscatter GGX compensates its energy with Fss =
 *   Color (bsdf_microfacet_setup_fresnel_constant).
 * - Glass (_GGX_GLASS_ID, _MULTI_GGX_GLASS_ID): weight 1 with both Fresnel
 *   tints Color, generalized Schlick F0 = F0(IOR), F90 = 1, exponent -IOR
 *   (the real dielectric curve); IOR inverted on the back; the sample weight
 *   times the albedo estimate; Multiscatter GGX compensates with Fss = the
 *   transmission tint. Here the tint is the weight and the Fresnel untinted,
 *   which is the same product.
 * - Refraction (_GGX_REFRACTION_ID): weight Color, no Fresnel, no
 *   compensation.
 * Files of Blender 3.4 (before 3.5: g2_correlated 0; the writer sends no
 * Multiscatter GGX then) get Cycles 3.4's svm/closure.h: the shading normal
 * itself, separable G1 G1, and the Glass as a reflection of weight Color x
 * F and a refraction of Color x max(1e-4, 1 - F), F the dielectric Fresnel
 * at that normal, neither closure with a Fresnel of its own. */
static void v2_node(const pb_surface *surf, v3 wo, v3 color, const float *in, int multi, pb_bsdf *b) {
  const pb_blender_material *bm = &surf->mat->blender;
  int v34 = !bm->g2_correlated, beckmann = bm->distribution == PB_DISTRIBUTION_BECKMANN;
  v3 n = v34 ? surf->ns : valid_reflection_normal(surf->ng, wo, surf->ns);
  float alpha = sqr(sat(in[PB_IN_ROUGHNESS])), mu = v3_dot(wo, n);
  if (bm->node == PB_NODE_GLOSSY) {
    pb_closure *c = add_closure(b, PB_CL_V2_GGX, color);
    if (!c) return;
    float a = clampf(in[PB_IN_ANISOTROPIC], -0.99f, 0.99f), ax = alpha, ay = alpha;
    v3 t = surf->tangent;
    if (fabsf(a) > 1e-4f) {
      if (a < 0.0f) {
        ax = alpha / (1.0f + a);
        ay = alpha * (1.0f + a);
      } else {
        ax = alpha * (1.0f - a);
        ay = alpha / (1.0f - a);
      }
      t = turn_tangent(t, n, in[PB_IN_ANISOTROPIC_ROTATION]);
    }
    v2_microfacet(c, n, t, ax, ay, 1.0f, PB_FRESNEL_NONE, v3_splat(1.0f), !v34);
    c->beckmann = beckmann;
    if (multi) preserve_energy(c, mu, color);
    return;
  }
  if (bm->node == PB_NODE_VELVET) {
    /* CLOSURE_BSDF_ASHIKHMIN_VELVET_ID: weight Color on the shading normal,
     * sigma = max(saturate(Roughness), 0.01). */
    pb_closure *c = add_closure(b, PB_CL_VELVET, color);
    if (!c) return;
    lobe_frame(c, surf->ns, surf->tangent);
    float sigma = fmaxf(sat(in[PB_IN_ROUGHNESS]), 0.01f);
    c->on_a = 1.0f / (sigma * sigma);
    return;
  }
  int glass = bm->node == PB_NODE_GLASS;
  float ior = fmaxf(in[PB_IN_IOR], 1e-5f);
  if (v34) {
    float eta = surf->front ? ior : 1.0f / ior, f = glass ? fresnel_diel(v3_dot(n, wo), eta) : 0.0f;
    pb_closure *c = glass ? add_closure(b, PB_CL_V2_GGX, v3_scale(color, f)) : NULL;
    if (c) {
      v2_microfacet(c, n, n, alpha, alpha, eta, PB_FRESNEL_NONE, v3_splat(1.0f), 0);
      c->beckmann = beckmann;
    }
    c = add_closure(b, PB_CL_V2_GLASS, v3_scale(color, glass ? fmaxf(1e-4f, 1.0f - f) : 1.0f));
    if (c) {
      v2_microfacet(c, n, n, alpha, alpha, eta, PB_FRESNEL_NONE, v3_splat(1.0f), 0);
      c->beckmann = beckmann;
    }
    return;
  }
  pb_closure *c = add_closure(b, PB_CL_V2_GLASS, color);
  if (!c) return;
  v2_microfacet(c, n, n, alpha, alpha, surf->front ? ior : 1.0f / ior,
                glass ? PB_FRESNEL_GEN_SCHLICK : PB_FRESNEL_NONE, v3_splat(f0_of(ior)), 1);
  c->ttint = v3_splat(1.0f);
  c->beckmann = beckmann;
  if (!glass) return;
  c->sample_weight *= avg3(v2_albedo(c, mu, 1));
  if (multi) preserve_energy(c, mu, color);
}

/* The v2 layering weight down to (and including) the emission: what the
 * emission is multiplied by, for view direction wo (alpha, sheen and coat
 * layering, coat tint). */
static v3 v2_build(const pb_scene *s, const pb_surface *surf, v3 wo, v3 base, pb_bsdf *b, int emission_only) {
  const pb_blender_material *bm = &surf->mat->blender;
  v2_inputs V;
  v2_read(s, surf, base, &V);
  const float *in = V.in;
  int multi = bm->distribution == PB_DISTRIBUTION_MULTI_GGX, g2 = 1;
  if (bm->node == PB_NODE_GLOSSY || bm->node == PB_NODE_GLASS || bm->node == PB_NODE_REFRACTION ||
      bm->node == PB_NODE_VELVET) {
    if (!emission_only) {
      v2_node(surf, wo, base, V.in, multi, b);
      b->albedo = v3_sat(base);
    }
    return v3_splat(0.0f);
  }
  float metallic = sat(in[PB_IN_METALLIC]), ss_w = sat(in[PB_IN_SUBSURFACE]);
  float level = fmaxf(in[PB_IN_SPECULAR_IOR_LEVEL], 0.0f), roughness = sat(in[PB_IN_ROUGHNESS]);
  float aniso = sat(in[PB_IN_ANISOTROPIC]), sheen_w = fmaxf(in[PB_IN_SHEEN_WEIGHT], 0.0f);
  float sheen_r = sat(in[PB_IN_SHEEN_ROUGHNESS]), coat_w = fmaxf(in[PB_IN_COAT_WEIGHT], 0.0f);
  float coat_r = sat(in[PB_IN_COAT_ROUGHNESS]), coat_ior = fmaxf(in[PB_IN_COAT_IOR], 1.0f);
  float trans_w = sat(in[PB_IN_TRANSMISSION]), ior = fmaxf(in[PB_IN_IOR], 1e-5f);
  float alpha = sat(in[PB_IN_ALPHA]);
  /* Thin Film Thickness (nm) and IOR, clamped as svm/closure.h does. */
  float tf_d = fmaxf(in[PB_IN_THIN_FILM_THICKNESS], 1e-5f), tf_ior = fmaxf(in[PB_IN_THIN_FILM_IOR], 1e-5f);
  v3 cbase = v3_make(fminf(base.x, 1.0f), fminf(base.y, 1.0f), fminf(base.z, 1.0f));
  v3 n_shade = surf->ns;
  v3 n = valid_reflection_normal(surf->ng, wo, surf->ns);
  v3 tangent = surf->tangent;
  float ax = sqr(roughness), ay = ax;
  if (aniso > 0.0f) {
    float aspect = sqrtf(1.0f - aniso * 0.9f);
    ax /= aspect;
    ay *= aspect;
    tangent = turn_tangent(tangent, n_shade, in[PB_IN_ANISOTROPIC_ROTATION]);
  }
  pb_bsdf dummy;
  if (emission_only) {
    memset(&dummy, 0, sizeof dummy);
    b = &dummy;
  }
  v3 w = v3_splat(1.0f);
  if (alpha < 1.0f) {
    add_closure(b, PB_CL_TRANSPARENT, v3_splat(1.0f - alpha));
    w = v3_scale(w, alpha);
  }
  v3 coat_n = surf->nc; /* the Coat Normal (Cycles: sd->N unless linked) */
  if (sheen_w > CUTOFF) {
    pb_closure *c = add_closure(b, PB_CL_V2_SHEEN, v3_mul(v3_scale(V.sheen_tint, sheen_w), w));
    if (c) {
      v3 sn = v3_norm(v3_add(v3_scale(n_shade, 1.0f - sat(coat_w)), v3_scale(coat_n, sat(coat_w))));
      float r = clampf(sheen_r, 1e-3f, 1.0f), cni = v3_dot(sn, wo);
      lobe_frame(c, sn, wo);
      c->on_a = lut2(pb_sheen_ltc, cni, r, 32, 32);
      c->on_b = lut2(pb_sheen_ltc + 1024, cni, r, 32, 32);
      float alb = lut2(pb_sheen_ltc + 2048, cni, r, 32, 32);
      if (fabsf(c->on_a) < 1e-5f || alb < 1e-5f) {
        b->ncl--;
      } else {
        c->weight = v3_scale(c->weight, alb);
        c->sample_weight *= alb;
        w = layer_under(c->weight, w);
      }
    }
  }
  if (coat_w > CUTOFF) {
    v3 cn = valid_reflection_normal(surf->ng, wo, coat_n);
    pb_closure *c = add_closure(b, PB_CL_V2_GGX, v3_scale(w, coat_w));
    if (c) {
      float a = sqr(coat_r);
      v2_microfacet(c, cn, cn, a, a, coat_ior, PB_FRESNEL_DIELECTRIC, v3_splat(0.0f), g2);
      float mu = v3_dot(wo, cn);
      c->sample_weight *= avg3(v2_albedo(c, mu, 1));
      preserve_energy(c, mu, v3_splat(fresnel_diel_avg(coat_ior)));
      w = layer_under(v3_mul(c->weight, v2_albedo(c, mu, 0)), w);
    }
    if (V.coat_tint.x != 1.0f || V.coat_tint.y != 1.0f || V.coat_tint.z != 1.0f) {
      float cni = v3_dot(wo, cn);
      float cnt = sqrtf(fmaxf(0.0f, 1.0f - sqr(1.0f / coat_ior) * (1.0f - cni * cni)));
      float depth = 1.0f / cnt;
      v3 tt = v3_make(powf(V.coat_tint.x, depth), powf(V.coat_tint.y, depth), powf(V.coat_tint.z, depth));
      w = v3_mul(w, v3_add(v3_scale(v3_splat(1.0f), 1.0f - coat_w), v3_scale(tt, coat_w)));
    }
  }
  if (emission_only) return w;
  v3 w_emission = w;
  if (metallic > CUTOFF) {
    pb_closure *c = add_closure(b, PB_CL_V2_GGX, v3_scale(w, metallic));
    /* The Metallic BSDF's Beckmann distribution: Beckmann's D and Lambda,
     * never compensated (multi is 0). */
    if (c) c->beckmann = bm->distribution == PB_DISTRIBUTION_BECKMANN;
    if (c && bm->conductor) {
      /* The Metallic BSDF's Physical Conductor (Cycles 4.5 svm/closure.h
       * CLOSURE_BSDF_PHYSICAL_CONDUCTOR, closure/bsdf_microfacet.h
       * bsdf_microfacet_setup_fresnel_conductor): n = max(IOR, 0), k =
       * max(Extinction, 0); the sample weight is the smooth surface's
       * albedo; multiscatter with fresnel_conductor_Fss, the F82 fit of
       * the conductor at cos 1 and 1/7. */
      v3 eta = v3_maxv(v3_make(in[PB_IN_CONDUCTOR_N_R], in[PB_IN_CONDUCTOR_N_G], in[PB_IN_CONDUCTOR_N_B]),
                       v3_splat(0.0f));
      v2_microfacet(c, n, tangent, ax, ay, 1.0f, PB_FRESNEL_CONDUCTOR, eta, g2);
      c->color = V.spec_tint;
      float mu = v3_dot(wo, n);
      c->sample_weight *= avg3(v2_albedo(c, mu, 1));
      if (multi) {
        v3 f0 = fresnel_cond(1.0f, eta, c->color), f82 = fresnel_cond(1.0f / 7.0f, eta, c->color);
        float f = 6.0f / 7.0f, f5 = sqr(sqr(f)) * f;
        v3 bb = v3_scale(v3_sub(mix1(f0, f5), f82), 7.0f / (f5 * f)); /* fresnel_f82_B */
        preserve_energy(c, mu, v3_sat(v3_sub(mix1(f0, 1.0f / 21.0f), v3_scale(bb, 1.0f / 126.0f))));
      }
    } else if (c) {
      v3 f82 = v3_make(fminf(V.spec_tint.x, 1.0f), fminf(V.spec_tint.y, 1.0f), fminf(V.spec_tint.z, 1.0f));
      v2_microfacet(c, n, tangent, ax, ay, 1.0f, PB_FRESNEL_F82_TINT, cbase, g2);
      /* fresnel_f82tint_B: b = F_schlick(1/7) 7 / (f^6) (1 - tint), f = 6/7. */
      float f = 6.0f / 7.0f, f5 = sqr(sqr(f)) * f;
      v3 fs = mix1(cbase, f5);
      c->color = (f82.x == 1.0f && f82.y == 1.0f && f82.z == 1.0f)
                     ? v3_splat(0.0f)
                     : v3_mul(v3_scale(fs, 7.0f / (f5 * f)), v3_sub(v3_splat(1.0f), f82));
      float mu = v3_dot(wo, n);
      c->sample_weight *= avg3(v2_albedo(c, mu, 1));
      if (multi) {
        v3 fss = v3_sub(mix1(cbase, 1.0f / 21.0f), v3_scale(c->color, 1.0f / 126.0f));
        preserve_energy(c, mu, fss);
      }
    }
    w = v3_scale(w, 1.0f - metallic);
  }
  if (trans_w > CUTOFF) {
    pb_closure *c = add_closure(b, PB_CL_V2_GLASS, v3_scale(w, trans_w));
    if (c) {
      float r2 = sqr(roughness);
      v2_microfacet(c, n, n, r2, r2, surf->front ? ior : 1.0f / ior, PB_FRESNEL_GEN_SCHLICK,
                    v3_scale(V.spec_tint, f0_of(ior)), g2);
      c->ttint = v3_make(sqrtf(cbase.x), sqrtf(cbase.y), sqrtf(cbase.z));
      /* svm/closure.h: the film on the glass, its IOR relative to the
       * side wo is on. */
      c->tf_thickness = tf_d;
      c->tf_ior = surf->front ? tf_ior : tf_ior / ior;
      float mu = v3_dot(wo, n);
      c->sample_weight *= avg3(v2_albedo(c, mu, 1));
      if (multi) preserve_energy(c, mu, c->ttint);
    }
    w = v3_scale(w, 1.0f - trans_w);
  }
  float eta = ior, f0 = f0_of(eta);
  if (level != 0.5f) {
    f0 *= 2.0f * level;
    eta = eta_of_f0(f0);
    if (ior < 1.0f) eta = 1.0f / eta;
  }
  /* svm/closure.h: a film alone makes a specular lobe even at eta 1. */
  if (eta != 1.0f || tf_d > (float)PB_TF_MIN_THICKNESS) {
    pb_closure *c = add_closure(b, PB_CL_V2_GGX, w);
    if (c) {
      v2_microfacet(c, n, tangent, ax, ay, eta, PB_FRESNEL_GEN_SCHLICK, v3_scale(V.spec_tint, f0), g2);
      c->tf_thickness = tf_d;
      c->tf_ior = tf_ior;
      float mu = v3_dot(wo, n);
      c->sample_weight *= avg3(v2_albedo(c, mu, 1));
      if (multi) {
        float f0r = f0_of(eta);
        float sfs = sat((fresnel_diel_avg(eta) - f0r) / (1.0f - f0r));
        preserve_energy(c, mu, mix1(c->cspec0, sfs));
      }
      w = layer_under(v3_mul(c->weight, v2_albedo(c, mu, 0)), w);
    }
  }
  /* Diffuse, and subsurface rendered as diffuse (the loader warns). */
  v3 dw = v3_add(v3_scale(base, 1.0f - ss_w), v3_scale(cbase, ss_w));
  pb_closure *c = add_closure(b, PB_CL_OREN_NAYAR, v3_mul(dw, w));
  if (c) {
    lobe_frame(c, n_shade, tangent);
    /* Diffuse Roughness (4.3+): Oren-Nayar on the base colour's albedo. */
    float dr = sat(in[PB_IN_DIFFUSE_ROUGHNESS]);
    oren_nayar(c, dr < CUTOFF ? 0.0f : dr, base, 1, wo);
  }
  b->albedo = v3_scale(cbase, alpha);
  return w_emission;
}

v3 pb_principled2_emission_weight(const pb_scene *s, const pb_surface *surf, v3 wo) {
  v3 base = color_value(s, v3_load(surf->mat->base_color), surf->mat->base_color_tex, surf);
  if (surf->mat->blender.base_from_vertex_color) base = v3_make(surf->color[0], surf->color[1], surf->color[2]);
  base = v3_maxv(base, v3_splat(0.0f));
  return v2_build(s, surf, wo, base, NULL, 1);
}

static void setup_one(const pb_scene *s, const pb_surface *surf, v3 wo, pb_bsdf *b) {
  const pb_material *m = surf->mat;
  const pb_blender_material *bm = &m->blender;
  b->model = bm->model;
  b->bump = bm->bump_model;
  b->ni = surf->ni;
  b->ng = surf->ng;
  b->n = surf->ns;
  v3_basis(b->n, &b->t, &b->b);
  b->entering = surf->front;
  v3 base = color_value(s, v3_load(m->base_color), m->base_color_tex, surf);
  if (bm->base_from_vertex_color) base = v3_make(surf->color[0], surf->color[1], surf->color[2]); /* COLOR_0 */
  base = v3_make(fmaxf(base.x, 0.0f), fmaxf(base.y, 0.0f), fmaxf(base.z, 0.0f));
  b->albedo = v3_sat(base);
  if (bm->model == PB_MODEL_EMISSION || bm->model == PB_MODEL_HOLDOUT) {
    b->albedo = v3_splat(0.0f);
    return;
  }
  if (bm->model == PB_MODEL_PRINCIPLED && bm->principled_v2) {
    v2_build(s, surf, wo, base, b, 0);
    b->sw_sum = 0.0f;
    for (int i = 0; i < b->ncl; ++i) b->sw_sum += b->cl[i].sample_weight;
    return;
  }
  /* Every closure's normal, as Cycles' svm_node_closure_bsdf lifts it. */
  v3 n = valid_reflection_normal(surf->ng, wo, surf->ns);
  v3 tangent = surf->tangent;
  if (bm->model == PB_MODEL_DIFFUSE) {
    pb_closure *c = add_closure(b, PB_CL_OREN_NAYAR, base);
    if (c) {
      lobe_frame(c, n, tangent);
      oren_nayar(c, sat(input_value(s, m, surf, PB_IN_ROUGHNESS)), base, bm->oren_nayar_ms, wo);
    }
  } else {
    float in[PB_IN_COUNT];
    for (int i = 0; i < PB_IN_COUNT; ++i) in[i] = input_value(s, m, surf, (pb_blender_input)i);
    float metallic = in[PB_IN_METALLIC], roughness = in[PB_IN_ROUGHNESS], specular = in[PB_IN_SPECULAR];
    float spec_tint = in[PB_IN_SPECULAR_TINT], transmission = in[PB_IN_TRANSMISSION];
    float alpha = sat(in[PB_IN_ALPHA]);
    float eta = fmaxf(in[PB_IN_IOR], 1e-5f);
    float ior = surf->front ? eta : 1.0f / eta;
    float fresnel = fresnel_diel(v3_dot(n, wo), ior);
    float diffuse_w = (1.0f - sat(metallic)) * (1.0f - sat(transmission));
    float glass_w = sat(transmission) * (1.0f - sat(metallic));
    float spec_w = 1.0f - glass_w;
    /* Alpha < 1: a Transparent BSDF of weight 1 - alpha mixed in, the rest
     * scaled by alpha (the Mix Shader Cycles' PrincipledBsdfNode::expand
     * adds). */
    float w = alpha;
    if (alpha < 1.0f) add_closure(b, PB_CL_TRANSPARENT, v3_splat(1.0f - alpha));
    tangent = turn_tangent(tangent, n, in[PB_IN_ANISOTROPIC_ROTATION]);
    /* Diffuse: subsurface rendered as diffuse with the mixed colour. */
    float ss = sat(in[PB_IN_SUBSURFACE]);
    v3 ssc = color_value(s, v3_load(bm->subsurface_color), bm->subsurface_color_tex, surf);
    v3 mixed = v3_add(v3_scale(ssc, ss), v3_scale(base, 1.0f - ss));
    if (fabsf(avg3(mixed)) > CUTOFF && diffuse_w > CUTOFF) {
      pb_closure *c = add_closure(b, PB_CL_DIFFUSE, v3_scale(mixed, w * diffuse_w));
      if (c) {
        lobe_frame(c, n, tangent);
        c->rough = roughness;
      }
    }
    if (diffuse_w > CUTOFF && in[PB_IN_SHEEN] > CUTOFF) {
      float lum = luma709(base);
      v3 tint = lum > 0.0f ? v3_scale(base, 1.0f / lum) : v3_splat(1.0f);
      float st = in[PB_IN_SHEEN_TINT];
      v3 col = v3_add(v3_splat(1.0f - st), v3_scale(tint, st));
      pb_closure *c = add_closure(b, PB_CL_SHEEN, v3_scale(col, w * in[PB_IN_SHEEN] * diffuse_w));
      if (c) {
        lobe_frame(c, n, tangent);
        float cn = v3_dot(n, wo);
        c->sample_weight *= cn < 0.0f ? 0.0f : schlick_w(cn) * cn;
      }
    }
    if (spec_w > CUTOFF && (specular > CUTOFF || metallic > CUTOFF)) {
      int multi = bm->distribution == PB_DISTRIBUTION_MULTI_GGX && roughness > 0.075f;
      pb_closure *c = add_closure(b, multi ? PB_CL_MULTI_GGX : PB_CL_GGX, v3_splat(w * spec_w));
      if (c) {
        float spec_ior = 2.0f / (1.0f - sqrtf(fmaxf(0.0f, 0.08f * specular))) - 1.0f;
        float aspect = sqrtf(fmaxf(0.0f, 1.0f - in[PB_IN_ANISOTROPIC] * 0.9f));
        float r2 = roughness * roughness;
        float ax = r2 / aspect, ay = r2 * aspect;
        if (multi) {
          ax = clampf(ax, 1e-4f, 1.0f);
          ay = clampf(ay, 1e-4f, 1.0f);
        } else {
          ax = sat(ax);
          ay = sat(ay);
        }
        float lum = 0.3f * base.x + 0.6f * base.y + 0.1f * base.z;
        v3 tint = lum > 0.0f ? v3_scale(base, 1.0f / lum) : v3_splat(1.0f);
        v3 tcol = v3_add(v3_splat(1.0f - spec_tint), v3_scale(tint, spec_tint));
        v3 cspec0 = v3_add(v3_scale(tcol, specular * 0.08f * (1.0f - metallic)), v3_scale(base, metallic));
        c->color = v3_sat(base);
        microfacet(c, n, tangent, ax, ay, spec_ior, cspec0, wo);
      }
    }
    if (glass_w > CUTOFF) {
      v3 cspec0 = v3_add(v3_scale(base, spec_tint), v3_splat(1.0f - spec_tint));
      float rr = roughness;
      pb_closure *c = add_closure(b, PB_CL_GGX, v3_splat(w * glass_w * fresnel));
      if (c) {
        float a = sat(rr * rr);
        c->color = base;
        microfacet(c, n, n, a, a, ior, cspec0, wo);
      }
      float tr = bm->distribution == PB_DISTRIBUTION_GGX
                     ? 1.0f - (1.0f - rr) * (1.0f - in[PB_IN_TRANSMISSION_ROUGHNESS])
                     : rr;
      c = add_closure(b, PB_CL_GGX_REFRACT, v3_scale(base, w * glass_w * fmaxf(1e-4f, 1.0f - fresnel)));
      if (c) {
        float a = sat(tr * tr);
        microfacet(c, n, n, a, a, ior, v3_splat(0.0f), wo);
        c->singular = a * a <= SINGULAR_ALPHA2 || fabsf(ior - 1.0f) < 1e-4f;
      }
    }
    if (in[PB_IN_CLEARCOAT] > CUTOFF) {
      pb_closure *c = add_closure(b, PB_CL_CLEARCOAT, v3_splat(w));
      if (c) {
        v3 cn = valid_reflection_normal(surf->ng, wo, surf->nc); /* Clearcoat Normal: sd->N unless linked */
        c->clearcoat = in[PB_IN_CLEARCOAT];
        float a = sat(sqr(in[PB_IN_CLEARCOAT_ROUGHNESS]));
        microfacet(c, cn, cn, a, a, 1.5f, v3_splat(0.04f), wo);
      }
    }
    b->albedo = v3_scale(v3_sat(base), alpha);
    for (int i = 0; i < b->ncl; ++i)
      if (b->cl[i].type == PB_CL_GGX || b->cl[i].type == PB_CL_GGX_REFRACT) b->cl[i].g2 = bm->g2_correlated;
  }
  b->sw_sum = 0.0f;
  for (int i = 0; i < b->ncl; ++i) b->sw_sum += b->cl[i].sample_weight;
}

/* A Mix Shader's factor (scene.h pb_mix_fac): its Fac, or Cycles 4.5's
 * svm_node_fresnel / svm_node_layer_weight at the interpolated normal sd->N
 * (the nodes' Normal unlinked) and sd->wi = wo. */
static float mix_fac(const pb_scene *s, const pb_surface *surf, v3 wo) {
  const pb_material *m = surf->mat;
  float v = input_value(s, m, surf, PB_IN_MIX_FAC);
  float c = v3_dot(wo, surf->ni);
  switch (m->blender.mix_fac) {
  case PB_MIX_FAC_FRESNEL: {
    float eta = fmaxf(v, 1e-5f);
    return fresnel_diel(c, surf->front ? eta : 1.0f / eta);
  }
  case PB_MIX_FAC_LAYER_FRESNEL: {
    float eta = fmaxf(1.0f - v, 1e-5f);
    return fresnel_diel(c, surf->front ? 1.0f / eta : eta);
  }
  case PB_MIX_FAC_LAYER_FACING: {
    float f = fabsf(c);
    if (v != 0.5f) {
      float blend = clampf(v, 0.0f, 1.0f - 1e-5f);
      f = powf(f, blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend));
    }
    return 1.0f - f;
  }
  default: return v;
  }
}

/* Closures [from, b->ncl) of b weighed by w, those then under the cutoff
 * dropped (Cycles allocates a closure of weight mix weight x its own). */
static void weigh_closures(pb_bsdf *b, int from, float w) {
  int n = from;
  for (int i = from; i < b->ncl; ++i) {
    pb_closure c = b->cl[i];
    c.weight = v3_scale(c.weight, w);
    c.sample_weight *= w;
    if (!(fabsf(avg3(c.weight)) >= CUTOFF)) continue;
    b->cl[n++] = c;
  }
  b->ncl = n;
}

void pb_blender_bsdf_setup(const pb_scene *s, const pb_surface *surf, v3 wo, pb_bsdf *b) {
  setup_one(s, surf, wo, b);
  const pb_blender_material *bm = &surf->mat->blender;
  if (!bm->mix_with || bm->mix_with > s->material_count) return;
  /* A Mix Shader (svm_node_mix_closure): the first shader's closures weigh
   * 1 - fac, the second's fac; the second takes the first's normals. */
  /* An Add Shader (svm_node_add_closure): both at the incoming weight. */
  int add = bm->mix_fac == PB_MIX_FAC_ADD;
  float f = add ? 1.0f : sat(mix_fac(s, surf, wo));
  weigh_closures(b, 0, add ? 1.0f : 1.0f - f);
  pb_surface s2 = *surf;
  s2.mat = &s->materials[bm->mix_with - 1];
  pb_bsdf b2;
  memset(&b2, 0, sizeof b2);
  setup_one(s, &s2, wo, &b2);
  int n0 = b->ncl;
  for (int i = 0; i < b2.ncl && b->ncl < PB_CLOSURE_MAX; ++i) b->cl[b->ncl++] = b2.cl[i];
  weigh_closures(b, n0, f);
  b->albedo = v3_sat(v3_add(v3_scale(b->albedo, add ? 1.0f : 1.0f - f), v3_scale(b2.albedo, f)));
  b->sw_sum = 0.0f;
  for (int i = 0; i < b->ncl; ++i) b->sw_sum += b->cl[i].sample_weight;
}

/* ---- the whole BSDF ------------------------------------------------------- */

/* f cos summed over the non-delta closures, and the mixture pdf. */
static v3 eval_all(const pb_bsdf *b, v3 wo, v3 wi, float *pdf) {
  v3 f = v3_splat(0.0f);
  float p = 0.0f;
  for (int i = 0; i < b->ncl; ++i) {
    const pb_closure *c = &b->cl[i];
    float pc;
    v3 e = closure_eval(c, b->ng, b->ni, b->bump, wo, wi, b->rng, &pc);
    if (pc != 0.0f) {
      f = v3_add(f, v3_mul(e, c->weight));
      p += pc * c->sample_weight;
    }
  }
  *pdf = b->sw_sum > 0.0f ? p / b->sw_sum : 0.0f;
  return f;
}

v3 pb_blender_bsdf_eval(const pb_bsdf *b, v3 wo, v3 wi, float *pdf) {
  /* pb_bsdf_eval's contract is f without the cosine, which its callers
   * multiply by |wi . n| (n the shading normal): divided out here, since the
   * closures bring their own (lifted normals, Cycles' forms). */
  float cn = fabsf(v3_dot(wi, b->n));
  v3 f = eval_all(b, wo, wi, pdf);
  if (!(cn > 1e-7f)) return v3_splat(0.0f);
  return v3_scale(f, 1.0f / cn);
}

int pb_blender_bsdf_has_smooth(const pb_bsdf *b) {
  for (int i = 0; i < b->ncl; ++i)
    if (!b->cl[i].singular && b->cl[i].type != PB_CL_TRANSPARENT) return 1;
  return 0;
}

float pb_bsdf_transparency(const pb_bsdf *b) {
  if (b->model == PB_MODEL_GLTF) return 0.0f;
  for (int i = 0; i < b->ncl; ++i)
    if (b->cl[i].type == PB_CL_TRANSPARENT) return b->cl[i].weight.x;
  return 0.0f;
}

/* Refraction of wo (lobe space, above) through microfacet m with relative
 * index ior (n_wi / n_wo); 0 under total internal reflection. */
static int refract_dir(v3 wo, v3 m, float ior, v3 *wi) {
  float c = v3_dot(wo, m);
  if (c <= 0.0f) return 0;
  float inv = 1.0f / ior;
  float k = 1.0f - inv * inv * (1.0f - c * c);
  if (k <= 0.0f) return 0;
  *wi = v3_sub(v3_scale(m, c * inv - sqrtf(k)), v3_scale(wo, inv));
  return 1;
}

int pb_blender_bsdf_sample(const pb_bsdf *b, v3 wo, float u0, float u1, float u2, pb_transport mode,
                           pb_bsdf_sample *out) {
  memset(out, 0, sizeof *out);
  if (!(b->sw_sum > 0.0f)) return 0;
  /* Pick a closure by sample weight; u0's remainder inside its interval
   * drives the choices within the lobe. */
  float x = u0 * b->sw_sum;
  int k = 0;
  while (k + 1 < b->ncl && x >= b->cl[k].sample_weight) x -= b->cl[k++].sample_weight;
  const pb_closure *c = &b->cl[k];
  float pick = c->sample_weight / b->sw_sum;
  float ur = c->sample_weight > 0.0f ? sat(x / c->sample_weight) : 0.0f;
  if (!(pick > 0.0f)) return 0;
  v3 lo = to_lobe(c, wo);
  if (c->type == PB_CL_TRANSPARENT) {
    out->wi = v3_neg(wo);
    out->weight = v3_scale(c->weight, 1.0f / pick);
    out->delta = 1;
    out->transmit = 1;
    return 1;
  }
  if (lo.z <= 0.0f) return 0;
  v3 li;
  int v2_transmit = 0;
  if (c->singular && (c->type == PB_CL_V2_GGX || c->type == PB_CL_V2_GLASS)) {
    v3 r, t;
    fresnel_v2(c, lo.z, &r, &t);
    float ar = avg3(r), at = avg3(t);
    if (!(ar + at > 0.0f)) return 0;
    float p_r = ar / (ar + at);
    if (ur < p_r) {
      li = v3_make(-lo.x, -lo.y, lo.z);
      out->wi = from_lobe(c, li);
      if (v3_dot(out->wi, b->ng) <= 0.0f) return 0;
      out->weight = v3_scale(v3_mul(c->weight, r), c->energy / (p_r * pick));
    } else {
      if (!refract_dir(lo, v3_make(0.0f, 0.0f, 1.0f), c->ior, &li)) return 0;
      out->wi = v3_norm(from_lobe(c, li));
      if (v3_dot(out->wi, b->ng) >= 0.0f) return 0;
      out->weight = v3_scale(v3_mul(c->weight, t), c->energy / ((1.0f - p_r) * pick));
      out->transmit = 1;
    }
    out->delta = 1;
    return 1;
  }
  if (c->singular) {
    if (c->type == PB_CL_GGX_REFRACT) {
      if (!refract_dir(lo, v3_make(0.0f, 0.0f, 1.0f), c->ior, &li)) return 0;
      out->wi = v3_norm(from_lobe(c, li));
      if (v3_dot(out->wi, b->ng) >= 0.0f) return 0;
      out->weight = v3_scale(c->weight, 1.0f / pick);
      out->transmit = 1;
    } else {
      li = v3_make(-lo.x, -lo.y, lo.z);
      out->wi = from_lobe(c, li);
      if (v3_dot(out->wi, b->ng) <= 0.0f) return 0;
      v3 f = fresnel_v1(li, v3_make(0.0f, 0.0f, 1.0f), c->ior, c->f0, c->cspec0);
      if (c->type == PB_CL_CLEARCOAT) f = v3_scale(f, 0.25f * c->clearcoat);
      out->weight = v3_scale(v3_mul(c->weight, f), 1.0f / pick);
    }
    out->delta = 1;
    return 1;
  }
  switch (c->type) {
  case PB_CL_DIFFUSE:
  case PB_CL_SHEEN:
  case PB_CL_OREN_NAYAR:
    li = cosine_dir(u1, u2);
    break;
  case PB_CL_GGX: {
    v3 m = ggx_vndf(lo, c->ax, c->ay, u1, u2);
    li = v3_sub(v3_scale(m, 2.0f * v3_dot(lo, m)), lo);
    break;
  }
  case PB_CL_CLEARCOAT: {
    float a2 = c->ax * c->ax;
    float ct2 = a2 < 1.0f ? (1.0f - powf(a2, 1.0f - u1)) / (1.0f - a2) : 1.0f - u1;
    float ct = sqrtf(sat(ct2)), st = sqrtf(sat(1.0f - ct2)), phi = 2.0f * PB_PI_F * u2;
    v3 m = v3_make(st * cosf(phi), st * sinf(phi), ct);
    li = v3_sub(v3_scale(m, 2.0f * v3_dot(lo, m)), lo);
    break;
  }
  case PB_CL_MULTI_GGX: {
    float a = multi_ggx_albedo(c->ax == c->ay ? c->ax : sqrtf(c->ax * c->ay));
    if (ur < a) {
      v3 m = ggx_vndf(lo, c->ax, c->ay, u1, u2);
      li = v3_sub(v3_scale(m, 2.0f * v3_dot(lo, m)), lo);
    } else {
      li = cosine_dir(u1, u2);
    }
    break;
  }
  case PB_CL_GGX_REFRACT: {
    v3 m = ggx_vndf(lo, c->ax, c->ay, u1, u2);
    if (!refract_dir(lo, m, c->ior, &li)) return 0;
    break;
  }
  case PB_CL_VELVET: { /* uniform over the hemisphere */
    float st = sqrtf(fmaxf(0.0f, 1.0f - u1 * u1)), phi = 2.0f * PB_PI_F * u2;
    li = v3_make(st * cosf(phi), st * sinf(phi), u1);
    break;
  }
  case PB_CL_V2_SHEEN: {
    float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
    float dx = r * cosf(phi), dy = r * sinf(phi), dz = sqrtf(fmaxf(0.0f, 1.0f - u1));
    li = v3_norm(v3_make(dx - dz * c->on_b, dy, dz * c->on_a));
    break;
  }
  case PB_CL_V2_GGX:
  case PB_CL_V2_GLASS: {
    v3 m = c->beckmann ? beckmann_sample(c->ax, c->ay, u1, u2) : ggx_vndf(lo, c->ax, c->ay, u1, u2);
    if (!(v3_dot(lo, m) > 0.0f)) return 0; /* a Beckmann normal facing away */
    if (c->type == PB_CL_V2_GLASS) {
      v3 r, t;
      fresnel_v2(c, v3_dot(lo, m), &r, &t);
      float ar = avg3(r), at = avg3(t);
      if (!(ar + at > 0.0f)) return 0;
      if (ur >= ar / (ar + at)) {
        if (!refract_dir(lo, m, c->ior, &li)) return 0;
        v2_transmit = 1;
        break;
      }
    }
    li = v3_sub(v3_scale(m, 2.0f * v3_dot(lo, m)), lo);
    break;
  }
  default:
    return 0;
  }
  v3 wi = v3_norm(from_lobe(c, li));
  int transmit = c->type == PB_CL_GGX_REFRACT || v2_transmit;
  float side = v3_dot(wi, b->ng);
  if (transmit ? side >= 0.0f : side <= 0.0f) return 0;
  float pdf;
  v3 f = eval_all(b, wo, wi, &pdf);
  if (!(pdf > 0.0f)) return 0;
  /* Photons carry the adjoint of Cycles' refraction, which has the light
   * side's index squared in it (bsdf_microfacet_ggx_eval_transmit's m_eta^2):
   * seen from the photon, light and view swap, so 1 / ior^2. */
  if (transmit && mode == PB_IMPORTANCE) f = v3_scale(f, 1.0f / (c->ior * c->ior));
  out->wi = wi;
  out->pdf = pdf;
  out->weight = v3_scale(f, 1.0f / pdf);
  out->transmit = transmit;
  return 1;
}
