/* pb_scene: the one scene model every renderer reads (GPU pipeline, Embree
 * reference, POV-Ray export). Flat arrays in world space, so that a difference
 * between two renderers' pictures is a difference in light transport only.
 *
 * Units: lengths in the glTF file's metres; light intensities radiometric
 * (point/spot: W/sr, directional: W/m^2; see pb_light) after conversion from
 * KHR_lights_punctual's photometric values per shared/VALIDATION.md. Colours are
 * linear Rec.709 (textures flagged sRGB are decoded when sampled). */
#ifndef PB_SCENE_H
#define PB_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

enum { PB_NAME_MAX = 64 };

typedef enum pb_wrap {
  PB_WRAP_REPEAT = 0, /* glTF default (10497) */
  PB_WRAP_CLAMP = 1,  /* 33071 */
  PB_WRAP_MIRROR = 2, /* 33648 */
} pb_wrap;

typedef struct pb_texture {
  char name[PB_NAME_MAX];
  uint32_t width, height;
  uint8_t *rgba8;   /* width*height*4 bytes, rows top to bottom as in the file */
  int srgb;         /* 1: texels are sRGB-encoded (base colour, emissive) */
  pb_wrap wrap_s, wrap_t;
  int nearest;      /* 1: magFilter NEAREST; otherwise bilinear */
} pb_texture;

enum { PB_NO_TEXTURE = -1 };

typedef enum pb_alpha_mode {
  PB_ALPHA_OPAQUE = 0,
  PB_ALPHA_MASK = 1,
  PB_ALPHA_BLEND = 2,
} pb_alpha_mode;

/* Which surface shader a material is. PB_MODEL_GLTF is glTF's
 * metallic-roughness (below); the others come from the PHOTONBRIDGE_blender
 * extension (exporters/blender/PHOTONBRIDGE_blender.md, read by
 * blender_material.c) and are rendered as Cycles 3.4 renders Blender's
 * shader of that name. */
typedef enum pb_material_model {
  PB_MODEL_GLTF = 0,
  PB_MODEL_PRINCIPLED = 1, /* Principled BSDF (v1, Blender 3.4) */
  PB_MODEL_DIFFUSE = 2,    /* Diffuse BSDF: Lambert, Oren-Nayar for roughness > 0 */
  PB_MODEL_EMISSION = 3,   /* Emission shader alone: emits, reflects nothing */
  PB_MODEL_HOLDOUT = 4,    /* Holdout: black, absorbs; no coverage for camera rays */
} pb_material_model;

/* The Principled BSDF's scalar inputs (and the Diffuse BSDF's roughness), in
 * the order of pb_blender_material.input; Blender's socket values, as
 * written in the file (the renderers clamp as Cycles does). */
typedef enum pb_blender_input {
  PB_IN_METALLIC = 0, PB_IN_SPECULAR, PB_IN_SPECULAR_TINT, PB_IN_ROUGHNESS,
  PB_IN_ANISOTROPIC, PB_IN_ANISOTROPIC_ROTATION, PB_IN_SHEEN, PB_IN_SHEEN_TINT,
  PB_IN_CLEARCOAT, PB_IN_CLEARCOAT_ROUGHNESS, PB_IN_IOR, PB_IN_TRANSMISSION,
  PB_IN_TRANSMISSION_ROUGHNESS, PB_IN_ALPHA, PB_IN_SUBSURFACE, PB_IN_COUNT
} pb_blender_input;

typedef enum pb_distribution {
  PB_DISTRIBUTION_GGX = 0,       /* single-scatter GGX (Blender 3.4's default) */
  PB_DISTRIBUTION_MULTI_GGX = 1, /* Multiscatter GGX (Heitz et al. 2016) */
} pb_distribution;

/* A texture feeding one scalar input: texels of pb_scene.textures[tex],
 * channel 0..3 = R, G, B, A. The texture replaces the input's constant. */
typedef struct pb_input_texture {
  int32_t tex;      /* PB_NO_TEXTURE: none */
  uint32_t channel;
} pb_input_texture;

/* What the Blender models need beyond pb_material's common fields. For them
 * base_color (+ base_color_tex: the Base Color, or the Diffuse BSDF's
 * Color), emissive (+ emissive_tex: Emission x Emission Strength, or the
 * Emission shader's Color x Strength) and normal_tex are the Blender values;
 * metallic, roughness, transmission and ior hold the same numbers for
 * consumers that only know glTF's model (info, POV-Ray export), while the
 * renderers read `input`. */
typedef struct pb_blender_material {
  pb_material_model model;
  pb_distribution distribution;
  float input[PB_IN_COUNT];
  pb_input_texture input_tex[PB_IN_COUNT];
  float subsurface_color[3];     /* linear RGB */
  int32_t subsurface_color_tex;  /* sRGB texels unless Non-Color */
  float normal_strength;         /* Normal Map node strength (normal_tex) */
} pb_blender_material;

/* glTF metallic-roughness with the extensions Blender writes. Each texture is
 * an index into pb_scene.textures or PB_NO_TEXTURE; factors multiply. A
 * material with the PHOTONBRIDGE_blender extension has blender.model !=
 * PB_MODEL_GLTF (see pb_blender_material for which fields then mean what;
 * its textures replace constants instead of multiplying them, and it emits
 * from both sides, as Cycles' emission does: double_sided is set). */
typedef struct pb_material {
  char name[PB_NAME_MAX];
  float base_color[4];          /* linear RGBA */
  int32_t base_color_tex;
  float metallic, roughness;    /* [0,1] */
  int32_t metallic_roughness_tex; /* B = metallic, G = roughness (linear) */
  /* KHR_materials_specular: dielectric F0 = min(((ior-1)/(ior+1))^2 *
   * specular_color, 1) * specular, F90 = specular. Blender writes
   * specular_color 0 for a purely diffuse material; the loader then sets
   * specular = 0 too, so no renderer keeps a grazing (F90) reflection on it.
   * Without the extension: specular 1, colour 1. */
  float specular;
  float specular_color[3];
  float emissive[3];            /* linear, W/(m^2 sr) units of radiance,
                                   already times KHR_materials_emissive_strength */
  int32_t emissive_tex;
  float transmission;           /* KHR_materials_transmission, [0,1] */
  float ior;                    /* KHR_materials_ior, default 1.5 */
  int32_t normal_tex;
  float normal_scale;
  pb_alpha_mode alpha_mode;
  float alpha_cutoff;
  int double_sided;
  pb_blender_material blender;  /* model PB_MODEL_GLTF (zeroed) without the extension */
} pb_material;

/* What a material does to light, for renderers that branch on it. */
typedef enum pb_bsdf_kind {
  PB_BSDF_DIFFUSE = 0,   /* Lambertian (dielectric with no specular layer) */
  PB_BSDF_GLOSSY = 1,    /* GGX metal or dielectric with a specular layer */
  PB_BSDF_MIRROR = 2,    /* metallic, roughness below PB_SPECULAR_ROUGHNESS */
  PB_BSDF_GLASS = 3,     /* transmission, roughness below PB_SPECULAR_ROUGHNESS */
} pb_bsdf_kind;

/* Roughness under which a surface is treated as perfectly specular. */
#define PB_SPECULAR_ROUGHNESS 0.02f

/* The closest glTF kind; for the Blender models, from their inputs. */
pb_bsdf_kind pb_material_kind(const pb_material *m);
int pb_material_is_emissive(const pb_material *m);
/* Could the material have a singular (delta) lobe somewhere? Never 0 where
 * a renderer's BSDF can make one (textures counted as reaching any value):
 * it aims photons and switches on specular paths. */
int pb_material_may_be_singular(const pb_material *m);
const char *pb_material_model_name(pb_material_model m);

typedef enum pb_light_type {
  PB_LIGHT_POINT = 0,
  PB_LIGHT_SPOT = 1,
  PB_LIGHT_DIRECTIONAL = 2,
} pb_light_type;

/* Radiometric light. Per channel c:
 *   point/spot: radiant intensity I_c = color_c * intensity [W/sr]
 *   directional: irradiance E_c = color_c * intensity [W/m^2] normal to it.
 * A spot scales I by smoothstep over the angle to `direction`, between
 * cos(outer_cone) and cos(inner_cone) (KHR_lights_punctual's recommended
 * falloff). `direction` is the unit direction light travels (the node's -Z). */
typedef struct pb_light {
  char name[PB_NAME_MAX];
  pb_light_type type;
  float position[3];
  float direction[3];
  float color[3];
  float intensity;
  float inner_cone, outer_cone; /* radians, spot only */
  float range;                  /* 0: infinite */
  float file_intensity;         /* as written in the file: cd or lx */
} pb_light;

/* Total emitted power [W] of a light per channel, used to split photon
 * budgets; directional lights use the area of the scene's bounding disc. */
void pb_light_power(const pb_light *l, float scene_radius, float power[3]);

/* Perspective camera in world space. Looks along -Z of its node. */
typedef struct pb_camera {
  char name[PB_NAME_MAX];
  float position[3];
  float forward[3], up[3], right[3]; /* orthonormal, right-handed */
  float yfov;                        /* radians, vertical */
  float aspect;                      /* width/height; 0 if the file gives none */
  float znear, zfar;                 /* zfar 0: infinite */
  int synthesized;                   /* 1: made by the loader (file had none) */
} pb_camera;

/* Features the scene needs; renderers build only the machinery a scene uses. */
enum {
  PB_FEATURE_SPECULAR = 1u << 0,     /* mirror or glass: specular paths, caustics */
  PB_FEATURE_TRANSMISSION = 1u << 1, /* refraction */
  PB_FEATURE_GLOSSY = 1u << 2,       /* rough metal / specular layer */
  PB_FEATURE_TEXTURES = 1u << 3,
  PB_FEATURE_EMISSIVE = 1u << 4,     /* emissive triangles */
  PB_FEATURE_ANIMATION = 1u << 5,
  PB_FEATURE_ALPHA = 1u << 6,        /* alpha mask/blend materials */
  PB_FEATURE_NORMAL_MAPS = 1u << 7,
  PB_FEATURE_BLENDER = 1u << 8,      /* PHOTONBRIDGE_blender materials (Principled, ...) */
  PB_FEATURE_MULTI_GGX = 1u << 9,    /* a Principled BSDF with Multiscatter GGX */
  PB_FEATURE_HOLDOUT = 1u << 10,     /* holdout materials */
  PB_FEATURE_ANISOTROPY = 1u << 11,  /* an anisotropic Principled BSDF (needs tangents) */
};
const char *pb_feature_name(uint32_t bit);

/* How KHR_lights_punctual intensities were written (the file does not say;
 * see shared/VALIDATION.md). STANDARD: photometric per the glTF spec, and
 * Blender's default export (cd = W * 683 / 4pi): W/sr = cd / 683.
 * UNITLESS: Blender's "Unitless" mode (value = W / 4pi): W/sr = value. */
typedef enum pb_light_units {
  PB_LIGHT_UNITS_STANDARD = 0,
  PB_LIGHT_UNITS_UNITLESS = 1,
} pb_light_units;

#define PB_LUMENS_PER_WATT 683.0f

typedef struct pb_scene {
  char *path;

  /* Geometry: shared vertex arrays, world space. */
  float (*positions)[3];
  float (*normals)[3];   /* unit length; generated when the file has none */
  float (*uvs)[2];       /* (0,0) when the file has none */
  /* Normal-map tangent frames, world space (scenes/tangents.h): xyz unit,
   * orthogonal to the normal, along +u; w = +-1, bitangent = cross(normal,
   * xyz) * w (glTF TANGENT). From the file's TANGENT where a normal-mapped
   * primitive has one, generated from the uvs otherwise; on the vertices of
   * an anisotropic Blender Principled BSDF without a normal map, Cycles'
   * default tangent instead (blender_material.h pb_blender_radial_tangent).
   * NULL unless the scene has PB_FEATURE_NORMAL_MAPS or
   * PB_FEATURE_ANISOTROPY. */
  float (*tangents)[4];
  uint32_t vertex_count;
  uint32_t (*triangles)[3];   /* counter-clockwise seen from the front */
  uint32_t *triangle_material; /* index into materials */
  uint32_t triangle_count;

  pb_material *materials;
  uint32_t material_count;
  pb_texture *textures;
  uint32_t texture_count;
  pb_light *lights;
  uint32_t light_count;
  pb_camera *cameras;
  uint32_t camera_count;

  uint32_t animation_count;  /* glTF animations in the file */
  uint32_t animation_channel_count;
  /* Node animation (translation / rotation / scale channels), posed by
   * pb_scene_set_time. Opaque; NULL when the file has no usable channel
   * (none, or only morph "weights" and channels on `matrix` nodes, which
   * are ignored with a warning). Every animation of the file plays at once on
   * one timeline (Blender exports one action per object). anim_start,
   * anim_end: seconds, the union of the key times of the samplers those
   * channels use; 0, 0 without anim. After loading, the arrays hold the rest
   * pose (the nodes' own TRS), which need not be the pose at any time. */
  struct pb_scene_anim *anim;
  double anim_start, anim_end;

  float bounds_min[3], bounds_max[3];
  uint32_t features;   /* PB_FEATURE_* */
  /* World position of this scene's (0, 0, 0). Every position, camera and
   * light above is relative to it: a scene far from the world origin (its
   * centre more than 8 box radii away) is moved next to it when loaded,
   * in double precision, so floats keep their resolution (load.c). Zero
   * for scenes near the origin and for code-built scenes. */
  double origin[3];

  /* Warnings found while loading, in file order ("meshes[2].primitives[0]:
   * mode POINTS skipped"). */
  char **warnings;
  uint32_t warning_count;

  /* Provenance. */
  char generator[128];  /* asset.generator */
  pb_light_units light_units;
} pb_scene;

typedef struct pb_load_desc {
  pb_light_units light_units;  /* default STANDARD */
  int allow_external_files;    /* 0: URIs must stay inside the scene folder */
  uint64_t max_file_bytes;     /* 0: 2 GiB */
  uint32_t max_image_dim;      /* 0: 16384 per side */
  uint64_t max_image_pixels;   /* 0: 64 Mpixel per image */
  uint64_t max_triangles;      /* 0: 64 M */
} pb_load_desc;

/* Loads a .gltf or .glb into `out` (zeroed first). On failure returns the
 * code and sets pb_error_message() to one line "FILE: JSON-PATH: why", and
 * `out` holds nothing to free. */
pb_result pb_scene_load(const char *path, const pb_load_desc *desc, pb_scene *out);
void pb_scene_destroy(pb_scene *s);

/* Adds a warning (printf format). Returns PB_ERR_NOMEM on failure. */
pb_result pb_scene_warn(pb_scene *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Poses the scene at time t seconds, clamped to [anim_start, anim_end] (glTF
 * holds the first and last keys outside them): rewrites positions, normals
 * (inverse-transpose, unit length), cameras (position and frame), lights
 * (position, direction) and the bounds, all relative to pb_scene.origin as
 * the static load is. Topology, triangle order, materials, counts and
 * features never change: triangle i is the same triangle at every time (for
 * motion vectors and BVH refits). A deterministic function of t (not of
 * earlier calls). PB_OK and nothing changed for scenes without anim.
 * Sampling per glTF 2.0 Appendix C: STEP, LINEAR (rotations: slerp on the
 * shorter arc), CUBICSPLINE (Hermite, tangents times the key interval;
 * rotations normalised). Errors: PB_ERR_USAGE for t NaN; PB_ERR_SCENE_INVALID
 * when the pose leaves float range (the scene is then partly posed: pose it
 * at another time before use). Not thread-safe on one scene. */
pb_result pb_scene_set_time(pb_scene *s, double t);

/* Recomputes bounds and features from the arrays (loaders and code-built test
 * scenes call it once the arrays are filled). */
void pb_scene_finalize(pb_scene *s);

/* Camera by name; NULL name picks the first. Returns -1 when absent. */
int pb_scene_find_camera(const pb_scene *s, const char *name);

/* Image size from a camera and optional overrides (0 = derive): width
 * defaults to 640, height from the camera's aspect (or 480 if none). */
void pb_camera_image_size(const pb_camera *c, uint32_t want_w, uint32_t want_h,
                          uint32_t *w, uint32_t *h);

/* Sample a texture at uv: bilinear (or nearest) with the wrap modes, linear
 * RGBA out (sRGB decoded when the texture is sRGB). */
void pb_texture_sample(const pb_texture *t, float u, float v, float out[4]);

/* sRGB transfer, exact IEC 61966-2-1 piecewise form. */
float pb_srgb_to_linear(float v);
float pb_linear_to_srgb(float v);

#endif
