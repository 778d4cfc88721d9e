/* Internals of the reference renderer shared by its files: small vector
 * maths, the random stream, the Embree wrapper, the material model, light
 * sampling and the caustic photon map. Not for use outside src/ref. */
#ifndef PB_REF_INTERNAL_H
#define PB_REF_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include <embree3/rtcore.h>

#include "core/mix.h"
#include "ref/ref.h"
#include "scene/camera.h"
#include "scene/emitters.h"
#include "scene/scene.h"
#include "scene/world.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define PB_PI_F 3.14159265358979323846f
#define PB_INV_PI_F 0.31830988618379067154f
/* Shadow rays to point, spot and directional lights stop this fraction of the
 * distance short of the light (pbrt's ShadowEpsilon), so a light placed
 * exactly on a surface is not hidden by that surface. The GPU's direct.comp
 * uses the same value. */
#define PB_SHADOW_EPSILON 1e-4f

/* ---- vectors ------------------------------------------------------------ */

typedef struct v3 {
  float x, y, z;
} v3;

static inline v3 v3_make(float x, float y, float z) { return (v3){x, y, z}; }
static inline v3 v3_load(const float *p) { return (v3){p[0], p[1], p[2]}; }
static inline v3 v3_add(v3 a, v3 b) { return (v3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline v3 v3_sub(v3 a, v3 b) { return (v3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline v3 v3_mul(v3 a, v3 b) { return (v3){a.x * b.x, a.y * b.y, a.z * b.z}; }
static inline v3 v3_scale(v3 a, float s) { return (v3){a.x * s, a.y * s, a.z * s}; }
static inline v3 v3_madd(v3 a, v3 b, float s) {
  return (v3){a.x + b.x * s, a.y + b.y * s, a.z + b.z * s};
}
static inline float v3_dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline v3 v3_cross(v3 a, v3 b) {
  return (v3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline float v3_len(v3 a) { return sqrtf(v3_dot(a, a)); }
static inline v3 v3_norm(v3 a) {
  float l = v3_len(a);
  return l > 0 ? v3_scale(a, 1.0f / l) : a;
}
static inline v3 v3_neg(v3 a) { return (v3){-a.x, -a.y, -a.z}; }
static inline float v3_max(v3 a) { return fmaxf(a.x, fmaxf(a.y, a.z)); }
static inline float v3_lum(v3 a) { return 0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z; }
static inline int v3_is_zero(v3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }
static inline int v3_finite(v3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline float v3_get(v3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }

/* Orthonormal basis around unit n (Duff et al. 2017, "Building an
 * orthonormal basis, revisited"). */
static inline void v3_basis(v3 n, v3 *t, v3 *b) {
  float s = copysignf(1.0f, n.z);
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  *t = v3_make(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = v3_make(c, s + n.y * n.y * a, -n.y);
}

/* ---- random numbers ----------------------------------------------------- */

/* PCG32 (O'Neill 2014). One stream per (seed, pixel, sample) or (seed, pass,
 * photon path), so the picture does not depend on which thread drew what. */
typedef struct pb_rng {
  uint64_t state, inc;
} pb_rng;


static inline uint32_t pb_rng_u32(pb_rng *r) {
  uint64_t old = r->state;
  r->state = old * 6364136223846793005ull + r->inc;
  uint32_t xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xs >> rot) | (xs << ((-rot) & 31));
}

/* Stream from three keys: a domain tag (camera, photon), a 64-bit index and
 * a 32-bit index, with the user's seed. */
static inline pb_rng pb_rng_make(uint64_t seed, uint32_t tag, uint64_t a, uint64_t b) {
  pb_rng r;
  uint64_t h = pb_mix64(seed ^ pb_mix64(((uint64_t)tag << 32) ^ pb_mix64(a) ^ (b * 0xd1b54a32d192ed03ull)));
  r.inc = (pb_mix64(h ^ 0x5851f42d4c957f2dull) << 1) | 1u;
  r.state = 0; /* pcg32_srandom_r: advance, add the initial state, advance */
  pb_rng_u32(&r);
  r.state += h;
  pb_rng_u32(&r);
  return r;
}

/* Uniform in [0, 1). */
static inline float pb_rng_f(pb_rng *r) {
  return (float)(pb_rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}

enum { PB_RNG_CAMERA = 1, PB_RNG_PHOTON = 2, PB_RNG_PIXEL = 3, PB_RNG_LENS = 4 };

/* ---- Embree ------------------------------------------------------------- */

typedef struct pb_ref_accel {
  RTCDevice device;
  RTCScene scene;
} pb_ref_accel;

typedef struct pb_ref_hit {
  float t;
  uint32_t prim;
  float u, v; /* Embree barycentrics: p = (1-u-v) p0 + u p1 + v p2 */
} pb_ref_hit;

/* The scene's indices must be in range (ref.c checks them first). */
pb_result pb_ref_accel_create(const pb_scene *s, pb_ref_accel *a);
void pb_ref_accel_destroy(pb_ref_accel *a);
/* Closest hit in (0, tmax]; returns 0 on a miss. */
int pb_ref_intersect(const pb_ref_accel *a, v3 o, v3 d, float tmax, pb_ref_hit *hit);
/* 1 when anything lies in (0, tmax). */
int pb_ref_occluded(const pb_ref_accel *a, v3 o, v3 d, float tmax);

/* Waechter & Binder, "A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6: moves p off the surface along
 * the geometric normal n (pointing to the side the new ray leaves) by a fixed
 * number of float ULPs, so the offset scales with |p| and works at any
 * distance from the origin; near the origin (|p| < 1/32) a small absolute
 * offset takes over where ULPs are too fine. */
v3 pb_offset_ray(v3 p, v3 n);

/* ---- surfaces and materials --------------------------------------------- */

/* What a ray sees where it hits, with normals facing the incoming ray. */
typedef struct pb_surface {
  v3 p;       /* on the triangle, from barycentrics (not o + t d) */
  v3 ng;      /* geometric normal, unit, facing the incoming ray */
  v3 ns;      /* shading normal, unit, same hemisphere as ng */
  v3 ni;      /* the interpolated normal: ns before a normal map moved it
                 (Cycles' sd->N, which bump shadowing compares with) */
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
} pb_closure_type;

enum { PB_CLOSURE_MAX = 8 };
/* Fresnel of a Principled v2 microfacet closure (Cycles' MicrofacetFresnel). */
enum { PB_FRESNEL_DIELECTRIC = 0, PB_FRESNEL_F82_TINT, PB_FRESNEL_GEN_SCHLICK, PB_FRESNEL_CONDUCTOR };

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

/* ---- lights ------------------------------------------------------------- */

typedef struct pb_ref_lights {
  /* Emissive triangles, sampled by power from the scene's table
   * (scene/emitters.h). */
  uint32_t *emitters;     /* triangle indices */
  double *emitter_cdf;    /* emitter_count + 1 entries, cdf[last] = 1 */
  float *tri_pick_pdf;    /* per triangle: probability of picking it, or 0 */
  uint32_t emitter_count;
  /* Delta lights (point, spot and directional lights without size). */
  uint32_t delta_count;
  /* Soft lights (sphere, area, soft sun): every one sampled at every smooth
   * vertex, and hit by rays. */
  uint32_t soft_count;
  /* The world's sampling table (scene/world.h); world_nee: the world gets
   * a light sample at smooth vertices (a map). A constant world is reached
   * by BSDF sampling alone, as Cycles 3.4 does (scene/light.cpp disables a
   * spatially constant background's MIS), which is its best strategy. */
  pb_world_dist world_dist;
  int world_nee;
  /* Scene bounding sphere, for directional lights. */
  v3 center;
  float radius;
  /* Bounding sphere of triangles with a delta lobe (photon emission target),
   * radius 0 when there are none. */
  v3 spec_center;
  float spec_radius;
} pb_ref_lights;

pb_result pb_ref_lights_build(const pb_scene *s, pb_ref_lights *l);
void pb_ref_lights_destroy(pb_ref_lights *l);

/* Radiance-like contribution of delta light i at point p: the direction to
 * the light, the distance (INFINITY for directional), and Li such that the
 * reflected radiance is f |cos| Li. Returns 0 when it contributes nothing. */
int pb_delta_light_at(const pb_light *l, v3 p, v3 *wi, float *dist, v3 *Li);


/* Cycles 3.4's or 4.x's spot falloff or KHR's smooth step (scene.h pb_spot_model)
 * for the cosine of the angle between the spot's axis and the direction
 * light leaves in. */
float pb_spot_factor(const pb_light *l, float cos_angle);

/* A light sample toward a soft light (soft_lights.c). */
typedef struct pb_light_sample {
  v3 wi;      /* unit, from the lit point toward the light */
  float dist; /* to the sampled point (INFINITY for the sun) */
  v3 L;       /* radiance arriving along -wi */
  float pdf;  /* solid-angle density of wi */
} pb_light_sample;

/* Samples soft light l (pb_light_is_delta false) from point p with (u1, u2)
 * in [0, 1)^2, with Cycles 3.4's strategies: sphere light: uniform on the
 * disc facing p; area light: a rectangle by solid angle (Urena et al. 2013,
 * "An Area-Preserving Parametrization for Spherical Rectangles", on the part
 * of it that its spread lets reach p, as Cycles' light_spread_clamp_area_light;
 * by area below 1e-3 sr, where the solid angle loses float precision), an
 * ellipse by area; sun: uniform on its disc at unit distance. Returns 0 when
 * the light cannot reach p. */
int pb_soft_light_sample(const pb_light *l, v3 p, float u1, float u2, pb_light_sample *out);
/* The ray (o, d), d unit, meets soft light l at distance t in (0, tmax)
 * (the sun only when tmax is INFINITY, a ray that left the scene): its
 * radiance toward o and the density pb_soft_light_sample gives that
 * direction from o. Lights are one-sided where Cycles' are (area lights,
 * spots' discs). */
int pb_soft_light_hit(const pb_light *l, v3 o, v3 d, float tmax, float *t, v3 *L, float *pdf);

/* Photon emission from soft lights (photons.c; the GPU's photon_trace.comp
 * emits the same way):
 * area light: origin o uniform on the shape, direction d cosine-weighted in
 * the cone of half-angle pi/2 - a that the spread allows (sin^2 t = u3 cos^2
 * a); the photon's flux is the light's radiance L times *weight = A pi cos^2
 * a x the spread profile at t (radiance x cos / the two densities). 0 when
 * the sample carries nothing. */
int pb_area_light_emit(const pb_light *l, float u1, float u2, float u3, float u4, v3 *o, v3 *d, float *weight);
/* Sphere light: the point of the sphere of radius r about the light whose
 * projection along d is uniform on the disc of radius r (the hemisphere
 * facing d, weighted by its cosine to d): a photon leaving in direction d
 * starts there and carries I(d) / (its direction density), as from a point
 * light. The sphere of radius r and radiance I / (pi r^2) emits I per
 * steradian in every direction, the point light's flux; its irradiance at
 * distance D is I / D^2 where Cycles 3.4's disc facing the lit point gives
 * I / (D^2 + r^2), so photons differ from next-event estimation by at most
 * r^2 / D^2 at the first hit (1 % at 10 radii), only in indirect light and
 * caustics, where the sphere's blur is the disc's. */
v3 pb_sphere_light_origin(const pb_light *l, v3 d, float u1, float u2);

/* Picks an emissive triangle by power and a uniform point on it, as a hit
 * (prim and Embree barycentrics) for pb_surface_from_hit, with the pdf of
 * that point in area measure. Returns 0 when there are no emitters. */
int pb_emitter_sample(const pb_scene *s, const pb_ref_lights *l, float u0,
                      float u1, float u2, pb_ref_hit *hit, float *pdf_area);
/* pdf (area measure) of pb_emitter_sample returning a point on triangle t. */
float pb_emitter_pdf_area(const pb_scene *s, const pb_ref_lights *l, uint32_t t);

/* Power heuristic with beta = 2 (Veach 1997, ch. 9). */
static inline float pb_mis_power(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

/* ---- caustic photon map (photons.c) ------------------------------------- */

/* One caustic photon: flux arriving at a surface with a smooth lobe after a
 * chain of `chain` >= 1 delta interactions that started at a delta light. */
typedef struct pb_photon {
  float p[3];
  float wi[3];     /* toward where the photon came from */
  float n[3];      /* geometric normal facing wi */
  float power[3];  /* flux [W], already divided by the pass's path count */
  uint32_t chain;
} pb_photon;

typedef struct pb_photon_map {
  pb_photon *photons; /* sorted by grid cell */
  uint32_t count;
  uint32_t *cell_start; /* bucket -> first photon, bucket_count + 1 entries */
  uint32_t bucket_count; /* power of two */
  float radius, cell;
  uint64_t rays;
} pb_photon_map;

typedef struct pb_ref_ctx pb_ref_ctx;

/* Traces `paths` photon paths of pass `pass` (deterministic for a seed) in
 * parallel and builds the map for gathering at `radius`. */
pb_result pb_photon_pass(pb_ref_ctx *ctx, uint32_t pass, uint32_t paths,
                         float radius, pb_photon_map *map);
void pb_ref_photon_map_destroy(pb_photon_map *m);
/* Caustic radiance toward wo at a surface point with bsdf b (the eye vertex
 * at bounce `depth`), from photons whose chain keeps the path within
 * max_bounces. */
v3 pb_photon_gather(const pb_photon_map *m, const pb_bsdf *b, v3 p, v3 wo,
                    uint32_t depth, uint32_t max_bounces);

/* ---- shared render state (ref.c) ---------------------------------------- */

struct pb_ref_ctx {
  const pb_scene *scene;
  const pb_camera *cam;
  uint32_t width, height;
  uint32_t max_bounces;
  uint32_t threads;
  uint64_t seed;
  pb_ref_mode mode;
  pb_ref_accel accel;
  pb_ref_lights lights;
  /* The camera's window for this image (scene/camera.h). */
  pb_gpu_camera view;
};

/* Runs fn(ctx, item, thread) for item in [0, count) on ctx->threads threads
 * (work handed out by an atomic counter), reporting progress from the
 * calling thread. */
typedef void (*pb_ref_work_fn)(void *user, uint32_t item, uint32_t thread);
pb_result pb_ref_parallel(uint32_t threads, uint32_t count, pb_ref_work_fn fn,
                          void *user, void (*tick)(void *tick_user, uint32_t done),
                          void *tick_user);

/* One camera sample's outputs (pathtrace.c). */
typedef struct pb_sample_out {
  v3 direct, indirect;
  v3 albedo, normal;
  float depth;   /* camera-space z, 0 on a miss */
  int hit;
  uint64_t rays;
} pb_sample_out;

/* Traces one path from pixel (x, y) for sample index `sample`, with caustic
 * photon lookups when map is not NULL. */
void pb_trace_camera_sample(const pb_ref_ctx *ctx, const pb_photon_map *map,
                            uint32_t x, uint32_t y, uint32_t sample,
                            pb_sample_out *out);

#endif
