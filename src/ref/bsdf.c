/* The reference renderer's material model (see pb_bsdf in ref/bsdf.h):
 * glTF metallic-roughness with KHR_materials_specular, _transmission and
 * _ior, evaluated and sampled in a shading frame whose z axis is the shading
 * normal facing the outgoing direction wo.
 *
 * Microfacet reflection: GGX / Trowbridge-Reitz distribution (Walter et al.
 * 2007, "Microfacet Models for Refraction through Rough Surfaces"),
 *   D(h) = a^2 / (pi (cos^2 h (a^2 - 1) + 1)^2),  a = roughness^2,
 * height-correlated Smith masking-shadowing (Heitz 2014, "Understanding the
 * Masking-Shadowing Function"),
 *   G2(wo, wi) = 1 / (1 + L(wo) + L(wi)),  L(w) = (sqrt(1 + a^2 tan^2 w) - 1) / 2,
 * and the visible-normal sampling of Heitz 2018 ("Sampling the GGX
 * Distribution of Visible Normals", JCGT 7(4)), whose pdf of wi is
 *   G1(wo) D(h) / (4 cos wo),
 * so the sample weight f cos / pdf reduces to F G2 / G1(wo). */
#include <string.h>

#include "ref/bsdf.h"

static inline float clamp01(float x) { return x < 0 ? 0 : (x > 1 ? 1 : x); }

static inline float schlick1(float f0, float c) {
  float m = clamp01(1.0f - c);
  float m2 = m * m;
  return f0 + (1.0f - f0) * m2 * m2 * m;
}
static inline v3 schlick3(v3 f0, float c) {
  return v3_make(schlick1(f0.x, c), schlick1(f0.y, c), schlick1(f0.z, c));
}

/* Unpolarised Fresnel reflectance of a dielectric interface; cos_i > 0 on the
 * incident side, eta = eta_incident / eta_transmitted. 1 under total internal
 * reflection. */
static float fresnel_dielectric(float cos_i, float eta, float *cos_t_out) {
  float sin2_t = eta * eta * fmaxf(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) {
    *cos_t_out = 0.0f;
    return 1.0f;
  }
  float cos_t = sqrtf(1.0f - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  *cos_t_out = cos_t;
  return 0.5f * (rs * rs + rp * rp);
}

static inline v3 to_local(const pb_bsdf *b, v3 w) {
  return v3_make(v3_dot(w, b->t), v3_dot(w, b->b), v3_dot(w, b->n));
}
static inline v3 to_world(const pb_bsdf *b, v3 l) {
  return v3_add(v3_add(v3_scale(b->t, l.x), v3_scale(b->b, l.y)), v3_scale(b->n, l.z));
}

static inline float ggx_d(float a2, float cos_h) {
  float c2 = cos_h * cos_h;
  float k = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (PB_PI_F * k * k);
}
static inline float smith_lambda(float a2, float cos_w) {
  float c2 = cos_w * cos_w;
  if (c2 <= 0.0f) return INFINITY;
  float tan2 = fmaxf(0.0f, 1.0f - c2) / c2;
  return 0.5f * (sqrtf(1.0f + a2 * tan2) - 1.0f);
}

static v3 spec_fresnel(const pb_bsdf *b, float c) {
  float kdiel = (1.0f - b->metallic) * (1.0f - b->transmission) * b->spec;
  v3 f = b->metallic > 0.0f ? v3_scale(schlick3(b->base, c), b->metallic) : v3_make(0, 0, 0);
  return kdiel > 0.0f ? v3_add(f, v3_scale(schlick3(b->f0_diel, c), kdiel)) : f;
}

/* Lobe choice probabilities and the diffuse weight for this wo. */
static void lobe_weights(pb_bsdf *b, float cos_o) {
  float nonmetal = 1.0f - b->metallic;
  float fs_max = b->spec > 0.0f ? v3_max(schlick3(b->f0_diel, cos_o)) * b->spec : 0.0f;
  b->kd = nonmetal * (1.0f - b->transmission) * clamp01(1.0f - fs_max);
  float wd = b->kd * v3_lum(b->base);
  float ws = v3_lum(spec_fresnel(b, cos_o));
  float wg = nonmetal * b->transmission;
  float sum = wd + ws + wg;
  if (!(sum > 0.0f)) {
    b->pd = b->ps = b->pg = 0.0f;
    return;
  }
  b->pd = wd / sum;
  b->ps = ws / sum;
  b->pg = wg / sum;
}

void pb_bsdf_setup(const pb_scene *s, const pb_surface *surf, v3 wo, pb_rng *rng, pb_bsdf *b) {
  const pb_material *m = surf->mat;
  memset(b, 0, sizeof *b);
  b->rng = rng;
  if (m->blender.model != PB_MODEL_GLTF) {
    pb_blender_bsdf_setup(s, surf, wo, b);
    return;
  }
  float bc[4], metallic, rough;
  pb_material_base_color(s, m, surf->uv, surf->uv1, surf->color, bc);
  pb_material_metal_rough(s, m, surf->uv, surf->uv1, &metallic, &rough);
  /* An unlit surface reflects nothing (its colour is its emission). */
  b->base = m->unlit ? v3_make(0, 0, 0) : v3_make(bc[0], bc[1], bc[2]);
  b->metallic = clamp01(metallic);
  b->roughness = clamp01(rough);
  b->alpha = b->roughness * b->roughness;
  b->delta_spec = b->roughness < PB_SPECULAR_ROUGHNESS;
  b->transmission = clamp01(m->transmission);
  b->ior = (m->ior >= 1.0f && m->ior < 100.0f) ? m->ior : 1.5f;
  float r0 = (b->ior - 1.0f) / (b->ior + 1.0f);
  r0 *= r0;
  b->f0_diel = v3_make(fminf(r0 * fmaxf(m->specular_color[0], 0.0f), 1.0f),
                       fminf(r0 * fmaxf(m->specular_color[1], 0.0f), 1.0f),
                       fminf(r0 * fmaxf(m->specular_color[2], 0.0f), 1.0f));
  b->spec = clamp01(m->specular);
  b->ng = surf->ng;
  /* Shading normals can put wo below the shading hemisphere although it is
   * above the geometric one; fall back to the geometric normal there. */
  b->n = v3_dot(surf->ns, wo) > 1e-4f ? surf->ns : surf->ng;
  v3_basis(b->n, &b->t, &b->b);
  b->entering = surf->front;
  lobe_weights(b, fmaxf(v3_dot(b->n, wo), 0.0f));
}

int pb_bsdf_has_smooth(const pb_bsdf *b) {
  if (b->model != PB_MODEL_GLTF) return pb_blender_bsdf_has_smooth(b);
  int diffuse = (1.0f - b->metallic) * (1.0f - b->transmission) > 0.0f &&
                !v3_is_zero(b->base);
  return diffuse || !b->delta_spec;
}

v3 pb_bsdf_albedo(const pb_bsdf *b) {
  if (b->model != PB_MODEL_GLTF) return b->albedo;
  float g = (1.0f - b->metallic) * b->transmission;
  return v3_add(v3_scale(b->base, 1.0f - g), v3_make(g, g, g));
}

/* f and pdf for reflection directions, local frame. */
static v3 eval_local(const pb_bsdf *b, v3 wo, v3 wi, float *pdf) {
  v3 f = {0, 0, 0};
  float p = 0.0f;
  if (wo.z <= 0.0f || wi.z <= 0.0f) {
    *pdf = 0.0f;
    return f;
  }
  if (b->kd > 0.0f) {
    f = v3_scale(b->base, b->kd * PB_INV_PI_F);
    p += b->pd * wi.z * PB_INV_PI_F;
  }
  if (!b->delta_spec && b->ps > 0.0f) {
    v3 h = v3_norm(v3_add(wo, wi));
    float a2 = b->alpha * b->alpha;
    float d = ggx_d(a2, h.z);
    float lo = smith_lambda(a2, wo.z), li = smith_lambda(a2, wi.z);
    float g2 = 1.0f / (1.0f + lo + li);
    float g1 = 1.0f / (1.0f + lo);
    v3 F = spec_fresnel(b, v3_dot(wo, h));
    f = v3_add(f, v3_scale(F, d * g2 / (4.0f * wo.z * wi.z)));
    p += b->ps * g1 * d / (4.0f * wo.z);
  }
  *pdf = p;
  return f;
}

v3 pb_bsdf_eval(const pb_bsdf *b, v3 wo, v3 wi, float *pdf) {
  if (b->model != PB_MODEL_GLTF) return pb_blender_bsdf_eval(b, wo, wi, pdf);
  /* Smooth lobes only reflect: both directions on the geometric side of wo
   * (which ng faces) as well as the shading side, else light would leak
   * through the surface where shading and geometric normals disagree. */
  if (v3_dot(wi, b->ng) <= 0.0f) {
    *pdf = 0.0f;
    return v3_make(0, 0, 0);
  }
  return eval_local(b, to_local(b, wo), to_local(b, wi), pdf);
}

/* Heitz 2018, listing 1 (isotropic: alpha_x = alpha_y = a). */
static v3 sample_vndf(v3 ve, float a, float u1, float u2) {
  v3 vh = v3_norm(v3_make(a * ve.x, a * ve.y, ve.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  v3 t1 = lensq > 0.0f ? v3_scale(v3_make(-vh.y, vh.x, 0.0f), 1.0f / sqrtf(lensq))
                       : v3_make(1.0f, 0.0f, 0.0f);
  v3 t2 = v3_cross(vh, t1);
  float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
  float p1 = r * cosf(phi), p2 = r * sinf(phi);
  float sm = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - sm) * sqrtf(fmaxf(0.0f, 1.0f - p1 * p1)) + sm * p2;
  v3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)),
                 v3_scale(vh, sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2))));
  return v3_norm(v3_make(a * nh.x, a * nh.y, fmaxf(0.0f, nh.z)));
}

static inline v3 reflect_local(v3 w, v3 h) {
  return v3_sub(v3_scale(h, 2.0f * v3_dot(w, h)), w);
}

int pb_bsdf_sample_dir(const pb_bsdf *b, v3 wo, float u0, float u1, float u2,
                       pb_transport mode, pb_bsdf_sample *out) {
  if (b->model != PB_MODEL_GLTF) return pb_blender_bsdf_sample(b, wo, u0, u1, u2, mode, out);
  memset(out, 0, sizeof *out);
  v3 lo = to_local(b, wo);
  if (lo.z <= 0.0f) return 0;
  if (u0 < b->pd || (u0 < b->pd + b->ps && !b->delta_spec)) {
    /* A smooth lobe: sample it, then weight by the whole mixture (one-sample
     * MIS over lobes), so the pdf matches pb_bsdf_eval's. */
    v3 li;
    if (u0 < b->pd) {
      float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
      li = v3_make(r * cosf(phi), r * sinf(phi), sqrtf(fmaxf(0.0f, 1.0f - u1)));
    } else {
      v3 h = sample_vndf(lo, b->alpha, u1, u2);
      li = reflect_local(lo, h);
    }
    if (li.z <= 0.0f) return 0;
    v3 wi = to_world(b, li);
    if (v3_dot(wi, b->ng) <= 0.0f) return 0;
    float pdf;
    v3 f = eval_local(b, lo, li, &pdf);
    if (!(pdf > 0.0f)) return 0;
    out->wi = wi;
    out->pdf = pdf;
    out->weight = v3_scale(f, li.z / pdf);
    return 1;
  }
  if (u0 < b->pd + b->ps) {
    /* Delta mirror: wi = reflect(wo, n), weight F(n.wo) / P(lobe). */
    v3 wi = to_world(b, v3_make(-lo.x, -lo.y, lo.z));
    if (v3_dot(wi, b->ng) <= 0.0f) return 0;
    out->wi = wi;
    out->delta = 1;
    out->weight = v3_scale(spec_fresnel(b, lo.z), 1.0f / b->ps);
    return 1;
  }
  if (b->pg <= 0.0f) return 0;
  /* Smooth dielectric: reflect with probability F, refract with 1 - F, so
   * the Fresnel factors cancel against the choice. */
  float eta_o = b->entering ? 1.0f : b->ior;  /* medium wo lies in */
  float eta_t = b->entering ? b->ior : 1.0f;
  float eta = eta_o / eta_t;
  float cos_t;
  float F = fresnel_dielectric(lo.z, eta, &cos_t);
  /* Reuse u0's position inside the glass interval for the choice. */
  float ug = (u0 - b->pd - b->ps) / b->pg;
  float kg = (1.0f - b->metallic) * b->transmission / b->pg;
  if (ug < F) {
    v3 wi = to_world(b, v3_make(-lo.x, -lo.y, lo.z));
    if (v3_dot(wi, b->ng) <= 0.0f) return 0;
    out->wi = wi;
    out->delta = 1;
    out->weight = v3_make(kg, kg, kg);
    return 1;
  }
  /* wi = -eta wo + (eta cos_o - cos_t) n, on the far side. */
  v3 li = v3_make(-eta * lo.x, -eta * lo.y, -cos_t);
  v3 wi = v3_norm(to_world(b, li));
  if (v3_dot(wi, b->ng) >= 0.0f) return 0;
  float k = kg;
  if (mode == PB_RADIANCE) k *= eta * eta;
  out->wi = wi;
  out->delta = 1;
  out->transmit = 1;
  out->weight = v3_scale(b->base, k);
  return 1;
}

v3 pb_surface_emission(const pb_scene *s, const pb_surface *surf, v3 wo, int camera_path) {
  const pb_material *m = surf->mat;
  if (!surf->front && !m->double_sided) return v3_make(0, 0, 0);
  if (m->unlit ? !camera_path : !pb_material_is_emissive(m)) return v3_make(0, 0, 0);
  float e[3];
  pb_material_emission(s, m, surf->uv, surf->uv1, surf->color, e);
  v3 le = v3_make(e[0], e[1], e[2]);
  /* A Principled BSDF's emission is weighted by its Alpha (Cycles); v2's
   * also by the sheen and coat layered over it. */
  if (m->blender.model == PB_MODEL_PRINCIPLED && m->blender.principled_v2)
    return v3_mul(le, pb_principled2_emission_weight(s, surf, wo));
  return m->blender.model == PB_MODEL_PRINCIPLED ? v3_scale(le, pb_blender_alpha(s, surf)) : le;
}
