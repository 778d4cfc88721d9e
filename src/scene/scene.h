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
#include "scene/light.h" /* pb_light_type: the kinds, and what depends on them */

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
  uint16_t *rgbah;  /* or (rgba8 NULL) width*height*4 IEEE halfs, linear: an
                       image of more than 8 bits a channel (16-bit PNG, HDR,
                       EXR: image/decode.h), sRGB already decoded for a colour
                       slot (srgb then only names the slot); NaN and negative
                       texels 0, at most 65504 */
  int srgb;         /* 1: texels are sRGB-encoded (base colour, emissive) */
  pb_wrap wrap_s, wrap_t;
  int nearest;      /* 1: magFilter NEAREST; otherwise bilinear */
  /* How the material reads it (glTF textureInfo): the uv set (0: uvs,
   * 1: uvs1) and, when uv_transformed, KHR_texture_transform as the affine
   * map u' = m[0] u + m[1] v + m[2],  v' = m[3] u + m[4] v + m[5] (0: the
   * uvs as they are). A texture read two ways is two pb_textures. */
  int texcoord;
  int uv_transformed;
  float uv_xform[6];
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
  PB_IN_TRANSMISSION_ROUGHNESS, PB_IN_ALPHA, PB_IN_SUBSURFACE,
  /* Principled v2 (Blender 4.0+, pb_blender_material.principled_v2) only;
   * v2 also reads METALLIC, ROUGHNESS, ANISOTROPIC(_ROTATION), IOR,
   * TRANSMISSION (Transmission Weight), ALPHA and SUBSURFACE (Subsurface
   * Weight), whose meaning it keeps. */
  PB_IN_SPECULAR_IOR_LEVEL, PB_IN_COAT_WEIGHT, PB_IN_COAT_ROUGHNESS, PB_IN_COAT_IOR,
  PB_IN_SHEEN_WEIGHT, PB_IN_SHEEN_ROUGHNESS, PB_IN_SUBSURFACE_SCALE, PB_IN_SUBSURFACE_IOR,
  PB_IN_SUBSURFACE_ANISOTROPY, PB_IN_THIN_FILM_THICKNESS, PB_IN_THIN_FILM_IOR, PB_IN_DIFFUSE_ROUGHNESS,
  PB_IN_EMISSION_STRENGTH,
  /* The Metallic BSDF's Physical Conductor (pb_blender_material.conductor):
   * its IOR n per channel (its Extinction k is specular_tint). */
  PB_IN_CONDUCTOR_N_R, PB_IN_CONDUCTOR_N_G, PB_IN_CONDUCTOR_N_B,
  /* A Mix Shader's factor (pb_blender_material.mix_with): its Fac, or the
   * Fresnel node's IOR, or the Layer Weight node's Blend (mix_fac). */
  PB_IN_MIX_FAC, PB_IN_COUNT
} pb_blender_input;

/* Where a Mix Shader's factor comes from (Cycles svm/fresnel.h, the same in
 * 3.4 and 4.5): its Fac (a constant or a texture), a Fresnel node (IOR), a
 * Layer Weight node's Fresnel or Facing output (Blend), each with its Normal
 * left unlinked (the interpolated normal); or no factor: an Add Shader. */
typedef enum pb_mix_fac {
  PB_MIX_FAC_VALUE = 0,
  PB_MIX_FAC_FRESNEL = 1,
  PB_MIX_FAC_LAYER_FRESNEL = 2,
  PB_MIX_FAC_LAYER_FACING = 3,
  PB_MIX_FAC_ADD = 4, /* an Add Shader: both shaders at weight 1 */
} pb_mix_fac;

/* Subsurface method by what it does (Blender 3.4's RANDOM_WALK is 4.x's
 * RANDOM_WALK_SKIN, 3.4's RANDOM_WALK_FIXED_RADIUS 4.x's RANDOM_WALK). */
typedef enum pb_subsurface_method {
  PB_SUBSURFACE_RANDOM_WALK_SKIN = 0, /* automatic radius */
  PB_SUBSURFACE_RANDOM_WALK_FIXED_RADIUS = 1,
  PB_SUBSURFACE_BURLEY = 2,
} pb_subsurface_method;

typedef enum pb_distribution {
  PB_DISTRIBUTION_GGX = 0,       /* single-scatter GGX (Blender 3.4's default) */
  PB_DISTRIBUTION_MULTI_GGX = 1, /* Multiscatter GGX (Heitz et al. 2016) */
  PB_DISTRIBUTION_BECKMANN = 2,  /* Beckmann (the Glossy, Glass and Refraction BSDFs only) */
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
/* Cycles' term for diffuse light on a shading normal n that a normal or bump
 * map moved from the interpolated normal ns (bsdf.h bump_shadowing_term):
 * by the Blender version that wrote the file and the material's Bump Map
 * Correction (Blender 4.2+). The values are the GPU's (PB_GPU_BUMP_*). */
typedef enum pb_bump_model {
  PB_BUMP_CHIANG = 0, /* Chiang et al. 2019 smoothing (up to 4.4) */
  PB_BUMP_NONE = 1,   /* correction off (4.2+): light below n or ns only */
  PB_BUMP_CONTY = 2,  /* Conty Estevez et al. 2019 GGX shadowing (4.5+) */
} pb_bump_model;

typedef enum pb_blender_node {
  PB_NODE_PRINCIPLED = 0, /* the model's own node (or glTF) */
  PB_NODE_METALLIC,       /* Metallic BSDF (F82 or Physical Conductor) */
  PB_NODE_SHEEN,          /* Sheen BSDF, Microfiber */
  /* Blender 4.x's Glossy, Glass and Refraction BSDFs (models "glossy",
   * "glass", "refraction"): a closure of their own in the v2 renderers,
   * base_color its Color; input[] holds ROUGHNESS, IOR and (Glossy)
   * ANISOTROPIC in -1..1 and ANISOTROPIC_ROTATION, with METALLIC 1
   * (Glossy) or TRANSMISSION 1 for the code that classifies materials. */
  PB_NODE_GLOSSY,
  PB_NODE_GLASS,
  PB_NODE_REFRACTION,
  /* The Sheen BSDF's Ashikhmin distribution (Blender 3.x's Velvet BSDF):
   * base_color its Color, input[ROUGHNESS] its Roughness (3.x: Sigma). */
  PB_NODE_VELVET,
} pb_blender_node;

typedef struct pb_blender_material {
  pb_material_model model;
  pb_distribution distribution;
  float input[PB_IN_COUNT];
  pb_input_texture input_tex[PB_IN_COUNT];
  float subsurface_color[3];     /* linear RGB */
  int32_t subsurface_color_tex;  /* sRGB texels unless Non-Color */
  float normal_strength;         /* Normal Map node strength (normal_tex) */
  pb_subsurface_method subsurface_method;
  /* Principled v2 (model "principled2" of the extension, Blender 4.0+):
   * input[] then holds Blender 4.x's sockets in the slots named above, and
   * the v1 slots (SPECULAR, SPECULAR_TINT, SHEEN, SHEEN_TINT, CLEARCOAT,
   * CLEARCOAT_ROUGHNESS, TRANSMISSION_ROUGHNESS, subsurface_color) a
   * Blender 3.4 approximation of them for code that only knows v1.
   * emissive is Emission Color x Emission Strength (an emission texture:
   * the Emission Color's, times the strength). */
  int principled_v2;
  /* The Blender node the extension's model names (model "metallic", "sheen"):
   * rendered as the Principled v2 inputs that make the same closure. */
  pb_blender_node node;
  /* Metallic BSDF, Fresnel type Physical Conductor: the metal lobe's
   * Fresnel is the conductor's of IOR input[PB_IN_CONDUCTOR_N_*] and
   * extinction specular_tint (not F82 tint); base_color is its F0. */
  int conductor;
  /* Smith masking-shadowing of every GGX lobe: 1 height-correlated G2 =
   * 1/(1 + L(wi) + L(wo)) (Cycles 3.5 and later), 0 separable G1 G1 (3.4).
   * From the root's "blender" version; 0 without it. */
  int g2_correlated;
  /* Normal Map node strength s in tangent space: 1 Cycles 4.0 and later
   * (xy s, z mix(1, z, sat(s)) before the tangent frame), 0 Cycles 3.x
   * (normalize(n + (nm - n) s) after it). From the same version; 0
   * without it unless the material is principled2. */
  int normal_map_cycles4;
  pb_bump_model bump_model;      /* diffuse light on a mapped normal */
  /* Oren-Nayar (Diffuse BSDF Roughness, Principled v2 Diffuse Roughness)
   * with Cycles 4.3's energy-preserving multiple-scattering term (OpenPBR;
   * Blender calls the model EON); 0: 3.x's single scattering only. */
  int oren_nayar_ms;
  float specular_tint[3], coat_tint[3], sheen_tint[3]; /* linear RGB */
  int32_t specular_tint_tex, coat_tint_tex, sheen_tint_tex;
  float subsurface_radius[3];    /* m, before Subsurface Scale */
  int32_t coat_normal_tex;       /* Normal Map on Coat Normal (tangent space) */
  float coat_normal_strength;
  /* The base colour (Principled Base Color, Diffuse Color) comes from a
   * Color Attribute node: the primitive's COLOR_0 RGB replaces the constant
   * and any texture, as a linked socket does in Cycles (extension member
   * "vertexColor"; white where the primitive has no COLOR_0). */
  int base_from_vertex_color;
  /* A Mix Shader of this material's shader and a second one: index + 1 of
   * the material that holds the second shader (0: no mix); the closures of
   * this one weigh 1 - fac, the second's fac (fac from mix_fac and
   * input[PB_IN_MIX_FAC], clamped to [0, 1]). The second material is
   * opaque, emits nothing, has no mix of its own and takes this material's
   * normals; the two make closures of different kinds
   * (pb_blender_closures), so the GPU keeps each in its own slot. */
  uint32_t mix_with;
  pb_mix_fac mix_fac;
  int mix_singular; /* the second material may have a delta lobe */
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
  /* KHR_materials_unlit: the surface shows its base colour (factor x
   * texture x COLOR_0) as radiance [W/(m^2 sr)] to camera paths (the eye and
   * its mirror/glass chains) and neither reflects nor emits light into the
   * scene; the loader zeroes its other lobes and its emission. */
  int unlit;
  /* KHR_materials_volume: absorption coefficient sigma_a [1/m] per channel
   * of the medium inside the (closed) surface, -ln(attenuationColor) /
   * attenuationDistance (Beer-Lambert: transmittance exp(-sigma_a d) over a
   * path length d inside); 0 when absent, thin-walled (thicknessFactor 0)
   * or infinitely clear. Applies to paths that refract into it. */
  float attenuation[3];
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
/* The Blender models' input i at most and at least: its constant, or, where
 * a texture feeds it, anything from the smaller of 0 and the constant to
 * the larger of 1 and the constant (a texel in [0, 1]). */
float pb_blender_input_max(const pb_blender_material *b, pb_blender_input i);
/* A tangent-space normal map on the material's Normal or, for the Blender
 * models, on the Principled BSDF's Coat Normal (tangents are then loaded). */
int pb_material_has_normal_map(const pb_material *m);
float pb_blender_input_min(const pb_blender_material *b, pb_blender_input i);
const char *pb_material_model_name(pb_material_model m);

/* The kinds of closure a Blender material may make (the renderers' closure
 * slots; textures counted as reaching any value), and what its set-up needs:
 * the v1 Principled code, v1 Multiscatter GGX's walk, a Mix Shader. */
enum {
  PB_BLENDER_CL_DIFFUSE = 1u << 0,
  PB_BLENDER_CL_SHEEN = 1u << 1,
  PB_BLENDER_CL_SPECULAR = 1u << 2,
  PB_BLENDER_CL_REFLECTION = 1u << 3, /* glass's reflection, the v2 metal, the Glossy BSDF */
  PB_BLENDER_CL_REFRACTION = 1u << 4,
  PB_BLENDER_CL_COAT = 1u << 5,
  PB_BLENDER_CL_SLOTS = 0x3fu,        /* the closure kinds above */
  PB_BLENDER_CL_MULTI_WALK = 1u << 6,
  PB_BLENDER_CL_V1 = 1u << 7,
  PB_BLENDER_CL_MIX = 1u << 8,
  PB_BLENDER_CL_BITS = 9,
};
uint32_t pb_blender_closures(const pb_material *m);
/* Bit k's name: diffuse, sheen, specular, reflection, refraction, coat,
 * multiscatter_walk, principled_v1, mix (info, --json, the loader's warnings). */
extern const char *const pb_blender_closure_names[PB_BLENDER_CL_BITS];
/* The extension's model of a Blender material: principled2, metallic, sheen
 * or pb_material_model_name's. */
const char *pb_blender_model_name(const pb_blender_material *b);

/* How a spot's intensity falls off with the angle to its axis. */
typedef enum pb_spot_model {
  /* KHR_lights_punctual's recommendation: smoothstep from cos(outer_cone)
   * to cos(inner_cone). */
  PB_SPOT_SMOOTHSTEP = 0,
  /* Cycles 3.4 (kernel/light/light.h spot_light_attenuation): with
   * c = cos(angle), c0 = cos(outer_cone) (half of Blender's spot size) and
   * band = (1 - c0) spot_blend: 0 for c <= c0, else c, times
   * smoothstep((c - c0) / band) inside the band (3 t^2 - 2 t^3). The factor
   * c is Cycles' own (measured: validation/VALIDATE.md). */
  PB_SPOT_CYCLES = 1,
  /* Cycles 4.0 and later (kernel/light/spot.h spot_attenuation): the same
   * band without the factor c: 0 for c <= c0, else smoothstep((c - c0) /
   * band) inside the band and 1 beyond it. Blender 4.x files (the writer's
   * light "model": "cycles4"). */
  PB_SPOT_CYCLES4 = 2,
} pb_spot_model;

typedef enum pb_area_shape {
  PB_AREA_RECTANGLE = 0, /* Blender's SQUARE and RECTANGLE */
  PB_AREA_ELLIPSE = 1,   /* DISK and ELLIPSE */
} pb_area_shape;

/* Radiometric light. Per channel c, with C_c = color_c * intensity:
 *   point/spot: radiant intensity I_c = C_c [W/sr]. With radius r > 0 it is
 *     Cycles 3.4's soft light: a disc of radius r centred at `position`,
 *     facing the lit point, of uniform radiance I_c / (pi r^2) (so far away
 *     it is the point light; on its axis at distance d the irradiance is
 *     I / (d^2 + r^2)). A spot multiplies by its falloff, evaluated for the
 *     direction from the disc's point to the lit point.
 *   directional: irradiance E_c = C_c [W/m^2] normal to it. With angle > 0,
 *     Cycles 3.4's soft sun: a disc of radius R = tan(angle / 2) at unit
 *     distance, uniform in area, so the radiance in a direction at angle t
 *     from the axis is E / (pi R^2 cos^3 t) inside the cone of half-angle
 *     angle / 2 (and the irradiance normal to the axis E 2 (sqrt(1 + R^2) -
 *     1) / R^2, slightly under E).
 *   area: a one-sided rectangle or ellipse of full widths size[0] along
 *     axis_u and size[1] along axis_v, centred at `position`, emitting along
 *     `direction` with radiance L_c = C_c [W/(m^2 sr)] normal to itself, times
 *     the spread profile: with s = spread in (0, pi], a = (pi - max(s, 1
 *     degree)) / 2, the radiance at angle t from the normal is
 *     L max(0, 1 - tan(a) tan(t)) N(a), N(a) = 2 / (2 + (2 a - pi) tan(a)),
 *     which keeps the emitted power pi A L for every spread (Cycles 3.4,
 *     scene/light.cpp; s = pi is the Lambertian emitter). Blender's power P
 *     [W] gives L = P / (4 A) (Cycles 3.4's eval_fac = 1/(4 A), measured:
 *     src/scene/blender_lights.c), A the shape's area; from Blender 4.0 on
 *     L = P / (pi A) (Cycles 4.x kernel/light/area.h eval_fac = invarea /
 *     pi: 4 / pi brighter for the same power, which is then the emitted flux).
 * A spot's falloff follows `spot_model`. `direction` is the unit direction
 * light travels (the node's -Z). Soft lights (radius, angle > 0, area
 * lights) are seen by rays: specular chains see their emission and
 * BSDF-sampled rays hit them (combined with light sampling by multiple
 * importance sampling), unless no_mis; they never occlude. As in Cycles 3.4
 * (measured: a 3 m area light, a point light of radius 2 m and a 60 degree
 * sun in front of the camera give 0, in a mirror their radiance), camera
 * rays do not see them. */
typedef struct pb_light {
  char name[PB_NAME_MAX];
  pb_light_type type;           /* scene/light.h: the kind */
  float position[3];
  float direction[3];
  float color[3];
  float intensity;
  float inner_cone, outer_cone; /* radians, spot only (PB_SPOT_CYCLES: outer only) */
  float range;                  /* 0: infinite */
  float file_intensity;         /* as written in the file: cd or lx (KHR), or
                                   Blender's watts / W/m^2 (PHOTONBRIDGE_blender) */
  pb_spot_model spot_model;
  float spot_blend;             /* PB_SPOT_CYCLES(4): Blender's spot blend, [0, 1] */
  float radius;                 /* point/spot: soft radius [m]; 0: a delta light */
  float angle;                  /* directional: angular diameter [rad]; 0: delta */
  pb_area_shape shape;          /* area lights */
  float axis_u[3], axis_v[3];   /* area: unit, orthogonal to each other and to `direction` */
  float size[2];                /* area: full widths along axis_u, axis_v [m] */
  float spread;                 /* area: (0, pi] radians; 0 in a code-built
                                   scene means pi */
  int no_shadow;                /* Blender's "Cast Shadow" off: lights through geometry */
  int sphere;                   /* point/spot with radius > 0: Cycles 4.x's sphere light
                                   (Blender 4.1+ Soft Falloff off) instead of the disc: a
                                   sphere of radius r and radiance I / (pi r^2); a spot's
                                   falloff applies outside it, not inside */
  int no_mis;                   /* Blender's "Multiple Importance" off: only
                                   light sampling (and camera rays) reach it */
  int from_blender;             /* read from PHOTONBRIDGE_blender (Blender's
                                   own units), not from KHR_lights_punctual */
  float blender_exposure;       /* PHOTONBRIDGE_blender: the light's Exposure
                                   in stops, already in file_intensity (Blender
                                   4.x: power x 2^exposure); for info's "as
                                   typed" figure only */
} pb_light;


/* The world (Blender's World: a Background shader, optionally fed by an
 * equirectangular Environment Texture), light arriving from infinitely far
 * in every direction. Radiance [W/(m^2 sr)] arriving from direction w (unit,
 * pointing away from the scene, scene axes):
 *   no map: color;
 *   map: env_scale x the map's bilinear texel (Cycles' "Linear" filter,
 *     texel centres at (i + 1/2) / width, u periodic, v clamped) at
 *     m = env_to_map w (Blender's Z-up axes after the Mapping node's
 *     rotation): u = 1/2 - atan2(m_y, m_x) / (2 pi), v = acos(m_z) / pi
 *     from the top row (Cycles 3.4 direction_to_equirectangular: the top
 *     row is the zenith, the image centre looks along +X).
 * `integral` is the radiance integrated over the sphere [W/m^2] (photon
 * budgets). */
typedef struct pb_world {
  int present;               /* 0: black, no world light */
  float color[3];
  float *env;                /* RGB float, env_width x env_height, top row first;
                                NULL: constant colour */
  uint32_t env_width, env_height;
  float env_scale;           /* Environment strength x Background strength */
  float env_to_map[9];       /* row-major 3x3 */
  char env_name[PB_NAME_MAX];
  int hidden_from_camera;    /* Blender: World ray visibility "Camera" off */
  float integral[3];
} pb_world;

/* Radiance of the world arriving from unit direction w. */
void pb_world_radiance(const pb_world *w, const float dir[3], float out[3]);

/* Which side of the picture a camera's field of view (or orthographic size)
 * spans; the other side follows the image's aspect ratio. glTF's yfov and
 * ymag are vertical; Blender's sensor fit is any of the three, AUTO being
 * the larger side (BKE_camera_sensor_fit: width when width >= height). */
typedef enum pb_camera_fit {
  PB_CAMERA_FIT_VERTICAL = 0,
  PB_CAMERA_FIT_HORIZONTAL = 1,
  PB_CAMERA_FIT_AUTO = 2,
} pb_camera_fit;

/* Camera in world space, looking along -Z of its node. Zero-initialised
 * extras (orthographic, fit, shift) give glTF's perspective camera. The
 * rays of an image of it are pb_camera_view's (camera.c); every renderer
 * goes through that one function. */
typedef struct pb_camera {
  char name[PB_NAME_MAX];
  float position[3];
  float forward[3], up[3], right[3]; /* orthonormal, right-handed */
  int orthographic;                  /* 1: parallel rays along forward */
  pb_camera_fit fit;                 /* the side yfov / ortho_size spans */
  float yfov;                        /* perspective: radians, the full angle
                                        across the fitted side (vertical for
                                        glTF cameras); 0 when orthographic */
  float ortho_size;                  /* orthographic: metres across the fitted
                                        side (glTF 2 ymag, Blender's
                                        ortho_scale) */
  float shift[2];                    /* lens shift right and up, in units of
                                        the fitted side's extent (Blender's
                                        shift_x, shift_y) */
  float aspect;                      /* width/height; 0 if the file gives none */
  float znear, zfar;                 /* clip planes, metres along forward
                                        (Cycles' clip_start / clip_end);
                                        zfar 0: infinite */
  int synthesized;                   /* 1: made by the loader (file had none) */
  /* Thin lens, Cycles 3.4's depth of field (blender/camera.cpp sync,
   * kernel/camera/camera.h sampling): aperture_radius in metres (0: a
   * pinhole; Blender: lens / (2 f-stop), 1 / (2 f-stop) when orthographic),
   * focus_distance in metres along forward (Cycles' focaldistance; a focus
   * object's distance along the view axis), aperture_blades 0 (a disc) or
   * >= 3 (a regular polygon turned by aperture_rotation, radians) and
   * aperture_ratio (anamorphic bokeh: the aperture's x is divided by it;
   * 0 reads as 1). All 0: no depth of field. */
  float aperture_radius, focus_distance, aperture_rotation, aperture_ratio;
  uint32_t aperture_blades;
  /* Panoramic cameras (Cycles' CAMERA_PANORAMA, kernel/camera/projection.h);
   * PB_CAMERA_PANO_NONE: the perspective or orthographic camera above.
   * latitude / longitude: Cycles' equirectangular ranges (min, max,
   * radians); fisheye_fov (radians) and fisheye_lens (mm) the fisheyes';
   * sensor (mm, width and height) the equisolid fisheye's, with `fit`. yfov
   * stays a perspective angle (the plain glTF camera's) for the code that
   * sizes pixels. */
  int panorama;                      /* pb_camera_panorama */
  float latitude[2], longitude[2];
  float fisheye_fov, fisheye_lens;
  float sensor[2];
} pb_camera;

typedef enum pb_camera_panorama {
  PB_CAMERA_PANO_NONE = 0,
  PB_CAMERA_PANO_EQUIRECTANGULAR = 1,
  PB_CAMERA_PANO_FISHEYE_EQUIDISTANT = 2,
  PB_CAMERA_PANO_FISHEYE_EQUISOLID = 3,
  PB_CAMERA_PANO_MIRRORBALL = 4,
} pb_camera_panorama;

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
  PB_FEATURE_VERTEX_COLORS = 1u << 8,  /* COLOR_0 */
  PB_FEATURE_SKINNING = 1u << 9,       /* skinned instances */
  PB_FEATURE_MORPH_TARGETS = 1u << 10, /* morphed instances */
  PB_FEATURE_UNLIT = 1u << 11,         /* KHR_materials_unlit surfaces */
  PB_FEATURE_VOLUME = 1u << 12,        /* absorbing media (KHR_materials_volume) */
  PB_FEATURE_SOFT_LIGHTS = 1u << 13,   /* area lights, radius > 0, sun angle > 0 */
  PB_FEATURE_WORLD = 1u << 14,         /* world light (constant or map) */
  PB_FEATURE_BLENDER = 1u << 15,       /* PHOTONBRIDGE_blender materials (Principled, ...) */
  PB_FEATURE_MULTI_GGX = 1u << 16,     /* a Principled BSDF with Multiscatter GGX */
  PB_FEATURE_HOLDOUT = 1u << 17,       /* holdout materials */
  PB_FEATURE_ANISOTROPY = 1u << 18,    /* an anisotropic Principled BSDF (needs tangents) */
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

/* Names as Blender's OCIO config spells them ("sRGB", "Filmic",
 * "Medium High Contrast"); look "" for Blender's "None". config: the OCIO
 * config Blender used (its own config.ocio or $OCIO, as the add-on found
 * it on the machine that wrote the scene), "" when not recorded. */
#define PB_SCENE_VIEW_NAME 64
#define PB_SCENE_VIEW_PATH 4096
typedef struct pb_scene_view {
  int set;
  char display[PB_SCENE_VIEW_NAME], view[PB_SCENE_VIEW_NAME], look[PB_SCENE_VIEW_NAME];
  char config[PB_SCENE_VIEW_PATH];
  double exposure; /* stops, before the view */
  double gamma;    /* after the view; 1: none */
} pb_scene_view;

typedef struct pb_scene {
  char *path;            /* the file, or pb_scene_load_memory's name */

  /* Geometry: shared vertex arrays, world space. */
  float (*positions)[3];
  float (*normals)[3];   /* unit length; generated when the file has none */
  float (*uvs)[2];       /* (0,0) when the file has none */
  /* TEXCOORD_1, NULL unless a texture reads uv set 1 (pb_texture.texcoord);
   * (0,0) where a primitive has none. */
  float (*uvs1)[2];
  /* COLOR_0, linear RGBA in [0,1], NULL unless a primitive has one; (1,1,1,1)
   * on vertices without. Multiplies the base colour (glTF 2.0 3.9.2). */
  float (*colors)[4];
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
  pb_world world;
  /* What camera rays that leave the scene give. 0 (plain glTF, and Blender's
   * Film > Transparent): no colour, alpha 0 (the beauty's A is the fraction of
   * camera samples that met geometry; lights seen on the way add their
   * emission, as Cycles' lights do not stop rays). 1 (Blender's opaque film):
   * alpha 1 everywhere and the world's radiance, unless it is hidden from the
   * camera. */
  int film_opaque;
  /* How the artist looks at the scene in Blender (its Colour Management
   * panel: scene.display_settings / view_settings, PHOTONBRIDGE_blender.
   * colorManagement): the defaults of the display images made from it (PNG
   * previews; the EXR stays scene-linear). set 0: the file does not say
   * (plain glTF), the display images use the config's defaults. */
  pb_scene_view view;

  uint32_t animation_count;  /* glTF animations in the file */
  uint32_t animation_channel_count;
  /* Node animation (translation / rotation / scale channels) and morph
   * weight channels, posed by pb_scene_set_time with the skins. Opaque; NULL
   * when the file has no usable channel (none, or only channels on `matrix`
   * nodes and weights of meshes without targets, which are ignored with a
   * warning). Every animation of the file plays at once on
   * one timeline (Blender exports one action per object). anim_start,
   * anim_end: seconds, the union of the key times of the samplers those
   * channels use; 0, 0 without anim. After loading, the arrays hold the rest
   * pose (the nodes' own TRS), which need not be the pose at any time. */
  struct pb_scene_anim *anim;
  double anim_start, anim_end;

  /* Skins and morph targets (glTF 2.0 3.7.3, 3.7.2.2), deformed on the CPU:
   * scene vertices of skinned and of morphed instances, and how many of
   * them pb_scene_set_time poses again (the rest were posed once, when
   * loaded). */
  uint32_t skinned_vertex_count, morphed_vertex_count, posed_vertex_count;

  float bounds_min[3], bounds_max[3];
  uint32_t features;   /* PB_FEATURE_* */
  /* World position of this scene's (0, 0, 0). Every position, camera and
   * light above is relative to it: a scene far from the world origin (its
   * centre more than 8 box radii away) is moved next to it when loaded,
   * in double precision, so floats keep their resolution (load_node.c). Zero
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

/* pb_scene_load on a .gltf or .glb held in memory: `size` bytes at `data`
 * (the kind by its magic, as for a file), read during the call only.
 * `name` stands for the file: every message begins with it ("NAME:
 * JSON-PATH: why") and it becomes out->path; NULL or "" gives "<memory>".
 * How URIs are resolved:
 *   - data: URIs (buffers, images) and the GLB's BIN chunk: always read,
 *     exactly as from a file;
 *   - a URI naming a file (buffers, images, the PHOTONBRIDGE_blender world
 *     map): resolved against `base_dir` as pb_scene_load resolves it
 *     against the file's folder (relative, percent-decoded, confined to the
 *     folder unless desc->allow_external_files);
 *   - base_dir NULL: no external files; every URI naming one fails with
 *     PB_ERR_SCENE_UNSUPPORTED ("NAME: buffers[0].uri: 'a.bin': an external
 *     file, and the scene was loaded from memory without a folder ...").
 * desc->max_file_bytes bounds `size` too (PB_ERR_LIMIT). Results, limits
 * and `out` on failure are those of pb_scene_load. */
pb_result pb_scene_load_memory(const char *name, const char *base_dir, const void *data, size_t size,
                               const pb_load_desc *desc, pb_scene *out);
void pb_scene_destroy(pb_scene *s);

/* Adds a warning (printf format). Returns PB_ERR_NOMEM on failure. */
pb_result pb_scene_warn(pb_scene *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Poses the scene at time t seconds, clamped to [anim_start, anim_end] (glTF
 * holds the first and last keys outside them): rewrites positions, normals
 * (inverse-transpose, unit length), the skinned and morphed vertices that
 * move (deform.h; their file tangents too), cameras (position and frame),
 * lights (position, direction) and the bounds, all relative to
 * pb_scene.origin as the static load is. Topology, triangle order, materials, counts and
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

/* Camera by name or index. NULL picks the first; a string of decimal digits
 * is an index into cameras (the numbers `info` lists); anything else is a
 * name. Returns the index; -1 when there is no such camera; -2 when several
 * cameras share the name (glTF does not require unique names: select one by
 * index). */
enum { PB_CAMERA_ABSENT = -1, PB_CAMERA_AMBIGUOUS = -2 };
int pb_scene_find_camera(const pb_scene *s, const char *name);

/* Image size from a camera and optional overrides (0 = derive): width
 * defaults to 640, height from the camera's aspect (or 480 if none). */
void pb_camera_image_size(const pb_camera *c, uint32_t want_w, uint32_t want_h,
                          uint32_t *w, uint32_t *h);

/* Whether camera c's clip range (znear..zfar along forward, as every
 * renderer clips) can hold a surface of s: 0 when every vertex of s lies
 * nearer than znear or every vertex beyond zfar, so the image can show only
 * the world (e.g. a scene modelled in millimetres under Blender's default
 * 0.1 m Clip Start); 1 otherwise, and for panoramic cameras (clipped by
 * distance, which a vertex test cannot decide) and empty scenes. depth: the
 * nearest and farthest vertex depth along forward (metres; NULL: not
 * wanted). Exact for depth: a triangle's depth is extreme at a vertex. */
int pb_camera_clip_sees(const pb_scene *s, const pb_camera *c, float depth[2]);

/* Sample a texture at uv: bilinear (or nearest) with the wrap modes, linear
 * RGBA out (sRGB decoded when the texture is sRGB). */
void pb_texture_sample(const pb_texture *t, float u, float v, float out[4]);
/* The mean of t's decoded texels (linear RGBA, as pb_texture_sample reads
 * them), over every texel. */
void pb_texture_mean(const pb_texture *t, float out[4]);

/* A material's texture at a surface point with uv sets uv0 and uv1 (uv1 may
 * be NULL: zero): the texture's uv set through its uv_xform, then
 * pb_texture_sample. */
void pb_texture_lookup(const pb_texture *t, const float uv0[2], const float uv1[2], float out[4]);
/* Its uv transform alone (the POV-Ray export writes transformed uvs). */
void pb_texture_uv(const pb_texture *t, const float uv0[2], const float uv1[2], float out[2]);

/* A material's inputs at a surface point with uv sets uv0, uv1 (uv1 NULL:
 * zero) and vertex colour `color` (NULL: white), the same in every renderer
 * (shaders/common/scene.glsl mirrors them):
 *   base colour (glTF 2.0 3.9.2): baseColorFactor x baseColorTexture x
 *     COLOR_0, RGBA, each channel clamped to [0, 1];
 *   metallic, roughness: the factors x the metallicRoughnessTexture's B, G;
 *   emission: emissive x emissiveTexture, or for an unlit material the base
 *     colour (scene.h, pb_material.unlit). */
void pb_material_base_color(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                            const float color[4], float out[4]);
void pb_material_metal_rough(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                             float *metallic, float *roughness);
void pb_material_emission(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                          const float color[4], float out[3]);

#endif
