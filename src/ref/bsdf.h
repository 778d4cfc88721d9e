/* What a ray sees where it hits and the material model of the reference
 * renderer: the glTF metal/rough BSDF (bsdf.c) and Blender's Principled
 * BSDF and nodes (principled.c). */
#ifndef PB_REF_BSDF_H
#define PB_REF_BSDF_H

#include "ref/accel.h"
#include "ref/vec.h"
#include "scene/scene.h"

/* What a ray sees where it hits, with normals facing the incoming ray. */
typedef struct pb_surface {
  v3 p;       /* on the triangle, from barycentrics (not o + t d) */
  v3 ng;      /* geometric normal, unit, facing the incoming ray */
  v3 ns;      /* shading normal, unit, same hemisphere as ng */
  v3 ni;      /* the interpolated normal: ns before a normal map moved it
                 (Cycles' sd->N, which bump shadowing compares with) */
  v3 nc;      /* the Principled BSDF's coat normal: its Coat Normal's map
                 (pb_blender_material.coat_normal_tex), else ni (Cycles:
                 an unlinked Coat Normal is sd->N, not the Normal input) */
  int front;  /* 1: the ray hit the counter-clockwise (front) side */
  uint32_t prim;
  float uv[2], uv1[2]; /* TEXCOORD_0 and _1 (0 when the scene has none) */
  float color[4];      /* COLOR_0 (white when the scene has none) */
  v3 tangent; /* unit, along +u (the scene's tangents where it has them),
                 else 0: anisotropic lobes then turn around an arbitrary
                 frame */
  const pb_material *mat;
} pb_surface;

void pb_surface_from_hit(const pb_scene *s, const pb_ref_hit *h, v3 ray_dir,
                         pb_surface *out);
/* Replaces out->ns by the normal-mapped shading normal where the material has
 * a normal map and the scene has tangents (called by pb_surface_from_hit). */
void pb_apply_normal_map(const pb_scene *s, const pb_ref_hit *h, pb_surface *out);

/* The material at one point with textures applied, split into lobes:
 *  D  Lambertian: (1-m)(1-T)(1 - max F_s(n.wo)) base / pi
 *  S  specular reflection, GGX (Walter et al. 2007) with height-correlated
 *     Smith shadowing, or a delta mirror when roughness < PB_SPECULAR_ROUGHNESS,
 *     Fresnel (1-m)(1-T) F_s + m Schlick(base): KHR_materials_specular's
 *     F_s = specular * Schlick(min(((ior-1)/(ior+1))^2 specular_color, 1))
 *     for the dielectric part and the base colour as F0 for the metal part
 *  G  (1-m) T: a smooth solid dielectric interface with the exact Fresnel
 *     equations and total internal reflection; the refracted part is tinted
 *     by the base colour at each crossing (as Cycles' glass does). Rough
 *     transmission is rendered as smooth (roughness is ignored for G).
 * m = metallic, T = transmission. The diffuse weight uses the Fresnel of the
 * outgoing direction only, so D is not exactly reciprocal: a simple
 * energy-plausible mix (reflectance <= 1), as the design asks. */
/* One closure of a Blender material (principled.c), as Cycles 3.4 builds
 * them (svm/closure.h): a BSDF lobe with its colour weight and its share of
 * lobe sampling. */
typedef enum pb_closure_type {
  PB_CL_DIFFUSE = 0,   /* Principled diffuse (Burley, retro-reflection) */
  PB_CL_OREN_NAYAR,    /* Diffuse BSDF: Oren-Nayar (Lambert at sigma 0) */
  PB_CL_SHEEN,         /* Principled sheen */
  PB_CL_GGX,           /* GGX reflection, Principled v1 Fresnel (specular, glass reflection) */
  PB_CL_MULTI_GGX,     /* Multiscatter GGX reflection, Principled v1 Fresnel */
  PB_CL_GGX_REFRACT,   /* GGX refraction (glass) */
  PB_CL_CLEARCOAT,     /* GTR1 clearcoat */
  PB_CL_TRANSPARENT,   /* alpha < 1: straight through */
  /* Principled v2 (Cycles 4.x): */
  PB_CL_V2_SHEEN,      /* microfiber sheen, LTC (Zeltner et al. 2022) */
  PB_CL_V2_GGX,        /* GGX reflection: F82-tint metal, generalized-Schlick specular or dielectric coat */
  PB_CL_V2_GLASS,      /* GGX glass: reflection and refraction in one closure, generalized Schlick */
  PB_CL_VELVET,        /* Ashikhmin velvet (Sheen BSDF Ashikhmin, 3.x Velvet BSDF); on_a = 1 / sigma^2 */
} pb_closure_type;

enum { PB_CLOSURE_MAX = 12 }; /* a Mix Shader's two shaders' */
/* Fresnel of a Principled v2 microfacet closure (Cycles' MicrofacetFresnel). */
/* PB_FRESNEL_NONE: the Glossy BSDF reflects all (V2_GGX), the Refraction
 * BSDF refracts all but total internal reflection (V2_GLASS). */
enum { PB_FRESNEL_DIELECTRIC = 0, PB_FRESNEL_F82_TINT, PB_FRESNEL_GEN_SCHLICK, PB_FRESNEL_CONDUCTOR, PB_FRESNEL_NONE };

typedef struct pb_closure {
  pb_closure_type type;
  v3 weight;           /* colour weight (Cycles' closure weight) */
  float sample_weight; /* lobe choice: probability sample_weight / sum */
  v3 n, x, y;          /* lobe frame; x along the anisotropy tangent */
  float ax, ay;        /* microfacet alphas */
  float ior;           /* microfacet Fresnel / refraction index, seen from wo */
  float f0;            /* dielectric Fresnel at normal incidence for ior */
  v3 cspec0, color;    /* Principled v1 Fresnel colours */
  float rough;         /* diffuse: retro-reflection roughness */
  float on_a, on_b;    /* Oren-Nayar A, B (1/pi, 0 for Lambert) */
  float clearcoat;     /* clearcoat: Clearcoat input (F scaled by 0.25 of it) */
  int singular;        /* a delta lobe: not evaluated, sampled by reflection/refraction */
  /* Principled v2 (PB_CL_V2_*): cspec0 holds F0 (colour), color the F82
   * b term, on_a/on_b the sheen LTC's a and b. */
  int fresnel;         /* PB_FRESNEL_* */
  v3 ttint;            /* glass: transmission tint */
  float energy;        /* Turquin energy scale 1 / E (1 without compensation) */
  int g2;              /* height-correlated Smith G2 (else separable G1 G1) */
  float tf_thickness;  /* v2 generalized Schlick: thin film (nm; off at <= 0.1) */
  float tf_ior;        /* its IOR, relative to the outside as ior is */
  int beckmann;        /* v2: Beckmann's D and Lambda instead of GGX's (Blender's BSDF nodes) */
} pb_closure;

typedef struct pb_bsdf {
  v3 base;
  float metallic, roughness, alpha, transmission, ior;
  v3 f0_diel;     /* dielectric layer F0 (times nothing: `spec` scales it) */
  float spec;     /* KHR specular factor */
  int delta_spec; /* S is a delta mirror */
  v3 n, t, b;     /* shading frame, n facing wo */
  v3 ng;          /* geometric normal facing wo */
  int entering;   /* G: wo on the outside (front) of the dielectric */
  /* Lobe choice probabilities for setup's wo, and the diffuse weight
   * (1-m)(1-T)(1 - max F_s(n.wo)). */
  float pd, ps, pg, kd;
  /* Blender materials (model != PB_MODEL_GLTF): the closures above replace
   * everything from `base` to `kd`. rng: the stream a stochastic evaluation
   * (Multiscatter GGX's random walk) draws from; its expectation is the
   * BSDF, so estimators stay unbiased. */
  pb_material_model model;
  pb_closure cl[PB_CLOSURE_MAX];
  int ncl;
  float sw_sum;     /* sum of the closures' sample weights */
  v3 albedo;        /* for the AOV */
  pb_rng *rng;
  pb_bump_model bump; /* diffuse light on a mapped normal */
  v3 ni;              /* pb_surface.ni */
} pb_bsdf;

/* Prepares the material at surf for outgoing direction wo; eval and sample
 * must then be called with that same wo. rng: the random stream of the path
 * (Multiscatter GGX evaluates stochastically; may be NULL for materials
 * without it). */
void pb_bsdf_setup(const pb_scene *s, const pb_surface *surf, v3 wo, pb_rng *rng, pb_bsdf *b);
/* Non-delta part f(wo, wi) (cosine not included) and the pdf of sampling wi
 * with pb_bsdf_sample's lobe mixture. wi, wo point away from the surface. */
v3 pb_bsdf_eval(const pb_bsdf *b, v3 wo, v3 wi, float *pdf);
int pb_bsdf_has_smooth(const pb_bsdf *b); /* any non-delta lobe (D, rough S) */

typedef enum pb_transport { PB_RADIANCE = 0, PB_IMPORTANCE = 1 } pb_transport;

typedef struct pb_bsdf_sample {
  v3 wi;
  v3 weight;   /* f |cos| / pdf, or the delta lobe's weight / its probability */
  float pdf;   /* solid-angle pdf (mixture) for smooth lobes; 0 for delta */
  int delta;   /* 1: a delta lobe (mirror, glass) */
  int transmit; /* wi on the other side of the surface */
} pb_bsdf_sample;

/* Samples a lobe and direction. PB_RADIANCE (eye paths) scales refraction by
 * (eta_wo / eta_wi)^2 (radiance is not conserved across an interface, Veach
 * 1997 ch. 5.2); PB_IMPORTANCE (photons carry flux) does not. Returns 0 when
 * the path is absorbed. */
int pb_bsdf_sample_dir(const pb_bsdf *b, v3 wo, float u0, float u1, float u2,
                       pb_transport mode, pb_bsdf_sample *out);
/* Albedo for the AOV: base colour, glass as white. */
v3 pb_bsdf_albedo(const pb_bsdf *b);

/* The Blender materials' BSDF (principled.c), behind pb_bsdf_setup / _eval /
 * _sample_dir / _has_smooth / _albedo for model != PB_MODEL_GLTF. */
void pb_blender_bsdf_setup(const pb_scene *s, const pb_surface *surf, v3 wo, pb_bsdf *b);
v3 pb_blender_bsdf_eval(const pb_bsdf *b, v3 wo, v3 wi, float *pdf);
int pb_blender_bsdf_sample(const pb_bsdf *b, v3 wo, float u0, float u1, float u2, pb_transport mode,
                           pb_bsdf_sample *out);
int pb_blender_bsdf_has_smooth(const pb_bsdf *b);
/* Fraction of light the material lets through straight (Alpha < 1,
 * Cycles' Transparent BSDF): 1 - alpha; 0 for opaque materials. */
float pb_bsdf_transparency(const pb_bsdf *b);
/* A Principled BSDF's Alpha at surf (its emission is scaled by it too). */
float pb_blender_alpha(const pb_scene *s, const pb_surface *surf);
/* Principled v2: the colour weight of its emission for view direction wo
 * (alpha, sheen and coat layered over it; principled.c). */
v3 pb_principled2_emission_weight(const pb_scene *s, const pb_surface *surf, v3 wo);

/* Emitted radiance leaving surf toward wo (facing the surface's hit side):
 * material emissive x emissive texture (pb_material_emission), from the front
 * side only unless the material is double-sided. An unlit surface's base
 * colour is counted only on camera paths (camera_path: the eye, or a chain of
 * delta interactions from it); it is no light to anything else. */
v3 pb_surface_emission(const pb_scene *s, const pb_surface *surf, v3 wo, int camera_path);

/* The medium a path is in after a sampled bounce (KHR_materials_volume,
 * pb_material.attenuation): refracting into a front face enters the
 * material's, refracting out of a back face leaves it for clear air (media
 * are not nested); reflections stay where they are. */
static inline v3 pb_medium_after(v3 sigma, const pb_surface *surf, const pb_bsdf_sample *bs) {
  if (!bs->transmit) return sigma;
  return surf->front ? v3_load(surf->mat->attenuation) : v3_make(0, 0, 0);
}
/* Beer-Lambert transmittance exp(-sigma t) over a segment of length t; t
 * may be INFINITY (a ray that leaves the scene): 1 where sigma is 0, else 0. */
static inline float pb_medium_transmittance1(float sigma, float t) { return sigma > 0 ? expf(-sigma * t) : 1.0f; }
static inline v3 pb_medium_transmittance(v3 sigma, float t) {
  return v3_make(pb_medium_transmittance1(sigma.x, t), pb_medium_transmittance1(sigma.y, t),
                 pb_medium_transmittance1(sigma.z, t));
}

#endif
