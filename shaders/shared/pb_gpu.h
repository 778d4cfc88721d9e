/* Every struct the GPU sees, written once and compiled both as C11 (host) and
 * as GLSL 4.50 (std430 storage buffers and push constants). The host side
 * checks each size and offset with _Static_assert (src/gpu/gpu_types.c and
 * the layout test tests/unit/test_gpu_layout.c); the GLSL side gets the same
 * layout from std430 because every vec3 sits on a 16-byte boundary and is
 * followed by a 4-byte scalar, every struct is a multiple of 16 bytes.
 *
 * Conventions: PB_VEC3(n) is float[3] in C and vec3 in GLSL; uint is
 * uint32_t. Flags and enums are plain uints (GLSL has no enums). */
#ifndef PB_GPU_SHARED_H
#define PB_GPU_SHARED_H

#ifdef PB_GLSL
#ifdef PB_RAY_QUERY
/* The ray-query builds (shaders.cmake): every kernel includes this header
 * first, so the extension is enabled before the kernel's declarations. */
#extension GL_EXT_ray_query : require
#endif
#define PB_VEC3(n) vec3 n
#define PB_VEC4(n) vec4 n
#define PB_STRUCT(name) struct name
#define PB_END(name) ;
#define PB_CONST(name, value) const uint name = value;
#else
#include <stdint.h>
#define PB_VEC3(n) float n[3]
#define PB_VEC4(n) float n[4]
#define PB_STRUCT(name) typedef struct name name; struct name
#define PB_END(name) ;
#define PB_CONST(name, value) enum { name = value };
typedef uint32_t uint;
#endif

/* Descriptor bindings and specialization-constant ids of every kernel. */
#include "shared/pb_contract.h"

/* Compute workgroup size of every kernel (1-D). No kernel assumes anything
 * about the subgroup size (lavapipe runs 8, NVIDIA 32, AMD 64). */
PB_CONST(PB_GPU_WORKGROUP, 64)

/* BVH traversal stack depth; the builder refuses deeper trees. */
PB_CONST(PB_BVH_MAX_DEPTH, 48)
/* Triangles per BVH leaf at most. */
PB_CONST(PB_BVH_MAX_LEAF, 4)

/* Children per inner node (a 4-wide BVH: half the depth of a binary one, so
 * half the divergent loop iterations and stack traffic per ray). */
PB_CONST(PB_BVH_WIDTH, 4)

/* A BVH node, 32 bytes. Inner node (count == 0): PB_BVH_WIDTH child slots at
 * `first` .. `first + PB_BVH_WIDTH - 1` (always adjacent, so one index
 * addresses all); an inner node with fewer children fills the remaining
 * slots with empty nodes (first == 0, count == 0, box lo = hi = 0), which
 * the root (node 0) can never be a child of, so they are recognised by
 * first == 0 && count == 0 and never entered. Leaf (count > 0): triangles
 * first .. first + count - 1 of the BVH-ordered triangle array. lo/hi: the
 * node's own box. Node 0 is the root. */
PB_STRUCT(pb_gpu_bvh_node) {
  PB_VEC3(lo);
  uint first;
  PB_VEC3(hi);
  uint count;
} PB_END(pb_gpu_bvh_node)

/* A triangle in BVH order, 48 bytes: vertices in world space and the index
 * of the triangle in pb_scene (its primitive id, as Embree reports it). */
PB_STRUCT(pb_gpu_tri) {
  PB_VEC3(p0);
  uint prim;
  PB_VEC3(p1);
  uint pad0;
  PB_VEC3(p2);
  uint pad1;
} PB_END(pb_gpu_tri)

/* A ray for the ray-query kernel (tests, benchmark). Hits in (tmin, tmax). */
PB_STRUCT(pb_gpu_ray) {
  PB_VEC3(org);
  float tmin;
  PB_VEC3(dir);
  float tmax;
} PB_END(pb_gpu_ray)

/* Result of a ray query. prim = PB_GPU_MISS on a miss; u, v: Embree's
 * barycentrics (p = (1-u-v) p0 + u p1 + v p2). Any-hit queries set prim to 0
 * when occluded and t to the tmax. */
PB_CONST(PB_GPU_MISS, 0xffffffffu)
PB_STRUCT(pb_gpu_hit) {
  float t;
  uint prim;
  float u;
  float v;
} PB_END(pb_gpu_hit)

/* Material: the reference's model (src/ref/bsdf.c) with glTF factors, or
 * a Blender shader (model != PB_GPU_MODEL_GLTF; src/ref/principled.c,
 * shaders/common/principled.glsl) with its inputs. Textures are indices
 * into the pb_gpu_texture table or PB_GPU_NO_TEXTURE. */
PB_CONST(PB_GPU_NO_TEXTURE, 0xffffffffu)
PB_CONST(PB_GPU_MAT_DOUBLE_SIDED, 1u)
PB_CONST(PB_GPU_MAT_UNLIT, 2u)             /* KHR_materials_unlit (pb_material.unlit) */
PB_CONST(PB_GPU_MAT_VERTEX_COLOR, 4u)      /* a Blender model's base colour is COLOR_0
                                              (pb_blender_material.base_from_vertex_color) */
PB_CONST(PB_GPU_MAT_NORMAL_MAP_CYCLES4, 8u) /* Normal Map strength as Cycles 4.0+
                                              (pb_blender_material.normal_map_cycles4) */
PB_CONST(PB_GPU_MAT_CONDUCTOR, 32u)       /* the v2 metal lobe's Fresnel is a physical
                                              conductor's: n in_value[PB_GPU_IN_CONDUCTOR_N..+2],
                                              k specular_tint (pb_blender_material.conductor) */
PB_CONST(PB_GPU_MAT_OREN_NAYAR_MS, 16u)   /* Oren-Nayar with Cycles 4.3's multiple
                                              scattering (pb_blender_material.oren_nayar_ms) */
/* bump_model: pb_bump_model's values. */
PB_CONST(PB_GPU_BUMP_CHIANG, 0u)
PB_CONST(PB_GPU_BUMP_NONE, 1u)
PB_CONST(PB_GPU_BUMP_CONTY, 2u)
/* node: pb_blender_node's values (the Metallic and Sheen BSDFs render as
 * Principled v2 inputs; the others have closures of their own). */
PB_CONST(PB_GPU_NODE_PRINCIPLED, 0u)
PB_CONST(PB_GPU_NODE_GLOSSY, 3u)
PB_CONST(PB_GPU_NODE_GLASS, 4u)
PB_CONST(PB_GPU_NODE_REFRACTION, 5u)
PB_CONST(PB_GPU_NODE_VELVET, 6u)
/* model: pb_material_model's values. */
PB_CONST(PB_GPU_MODEL_GLTF, 0u)
PB_CONST(PB_GPU_MODEL_PRINCIPLED, 1u)
PB_CONST(PB_GPU_MODEL_DIFFUSE, 2u)
PB_CONST(PB_GPU_MODEL_EMISSION, 3u)
PB_CONST(PB_GPU_MODEL_HOLDOUT, 4u)
PB_CONST(PB_GPU_DISTRIBUTION_GGX, 0u)
PB_CONST(PB_GPU_DISTRIBUTION_MULTI_GGX, 1u)
PB_CONST(PB_GPU_DISTRIBUTION_BECKMANN, 2u)
/* in_value / in_tex slots: pb_blender_input's values. */
PB_CONST(PB_GPU_IN_METALLIC, 0u)
PB_CONST(PB_GPU_IN_SPECULAR, 1u)
PB_CONST(PB_GPU_IN_SPECULAR_TINT, 2u)
PB_CONST(PB_GPU_IN_ROUGHNESS, 3u)
PB_CONST(PB_GPU_IN_ANISOTROPIC, 4u)
PB_CONST(PB_GPU_IN_ANISOTROPIC_ROTATION, 5u)
PB_CONST(PB_GPU_IN_SHEEN, 6u)
PB_CONST(PB_GPU_IN_SHEEN_TINT, 7u)
PB_CONST(PB_GPU_IN_CLEARCOAT, 8u)
PB_CONST(PB_GPU_IN_CLEARCOAT_ROUGHNESS, 9u)
PB_CONST(PB_GPU_IN_IOR, 10u)
PB_CONST(PB_GPU_IN_TRANSMISSION, 11u)
PB_CONST(PB_GPU_IN_TRANSMISSION_ROUGHNESS, 12u)
PB_CONST(PB_GPU_IN_ALPHA, 13u)
PB_CONST(PB_GPU_IN_SUBSURFACE, 14u)
/* Principled v2 only (principled_v2 != 0; it also reads METALLIC,
 * ROUGHNESS, ANISOTROPIC(_ROTATION), IOR, TRANSMISSION, ALPHA, SUBSURFACE). */
PB_CONST(PB_GPU_IN_SPECULAR_IOR_LEVEL, 15u)
PB_CONST(PB_GPU_IN_COAT_WEIGHT, 16u)
PB_CONST(PB_GPU_IN_COAT_ROUGHNESS, 17u)
PB_CONST(PB_GPU_IN_COAT_IOR, 18u)
PB_CONST(PB_GPU_IN_SHEEN_WEIGHT, 19u)
PB_CONST(PB_GPU_IN_SHEEN_ROUGHNESS, 20u)
PB_CONST(PB_GPU_IN_SUBSURFACE_SCALE, 21u)
PB_CONST(PB_GPU_IN_SUBSURFACE_IOR, 22u)
PB_CONST(PB_GPU_IN_SUBSURFACE_ANISOTROPY, 23u)
PB_CONST(PB_GPU_IN_THIN_FILM_THICKNESS, 24u)
PB_CONST(PB_GPU_IN_THIN_FILM_IOR, 25u)
PB_CONST(PB_GPU_IN_DIFFUSE_ROUGHNESS, 26u)
PB_CONST(PB_GPU_IN_EMISSION_STRENGTH, 27u)
PB_CONST(PB_GPU_IN_CONDUCTOR_N, 28u)       /* 28..30: a conductor's n (PB_GPU_MAT_CONDUCTOR) */
PB_CONST(PB_GPU_IN_MIX_FAC, 31u)           /* a Mix Shader's Fac, or its Fresnel's IOR or Layer Weight's Blend */
/* mix_fac: pb_mix_fac's values. */
PB_CONST(PB_GPU_MIX_FAC_VALUE, 0u)
PB_CONST(PB_GPU_MIX_FAC_FRESNEL, 1u)
PB_CONST(PB_GPU_MIX_FAC_LAYER_FRESNEL, 2u)
PB_CONST(PB_GPU_MIX_FAC_LAYER_FACING, 3u)
PB_CONST(PB_GPU_MIX_FAC_ADD, 4u)           /* an Add Shader: both at weight 1 */
PB_CONST(PB_GPU_IN_V1_SLOTS, 16u)           /* the slots the v1 model reads */
PB_CONST(PB_GPU_IN_SLOTS, 32u)
/* in_tex: texture index in the low 28 bits, the channel above (0..3 R, G,
 * B, A; 4 the Rec.709 luminance of RGB, Cycles' colour-to-float), or
 * PB_GPU_NO_TEXTURE. */
PB_CONST(PB_GPU_INPUT_TEX_INDEX, 0x0fffffffu)
PB_CONST(PB_GPU_INPUT_TEX_CHANNEL_SHIFT, 28u)
PB_STRUCT(pb_gpu_material) {
  PB_VEC4(base_color);       /* linear RGBA */
  PB_VEC3(emissive);         /* W/(m^2 sr) */
  uint base_color_tex;
  PB_VEC3(specular_color);
  uint metallic_roughness_tex;
  float metallic;
  float roughness;
  float transmission;
  float ior;
  float specular;
  uint emissive_tex;
  uint flags;                /* PB_GPU_MAT_* */
  uint normal_tex;           /* glTF normalTexture (linear texels), or
                                PB_GPU_NO_TEXTURE; only set for scenes with
                                tangents (pb_gpu_frame.tangent_base) */
  float normal_scale;        /* normalTexture.scale */
  uint model;                /* PB_GPU_MODEL_*; the rest is for model != GLTF */
  uint distribution;         /* PB_GPU_DISTRIBUTION_* */
  uint subsurface_color_tex;
  PB_VEC3(subsurface_color); /* linear */
  float normal_strength;     /* Blender's Normal Map strength (normal_tex) */
  float in_value[32];        /* PB_GPU_IN_* inputs, Blender's socket values */
  uint in_tex[32];           /* their textures (see PB_GPU_INPUT_TEX_INDEX) */
  PB_VEC3(attenuation);      /* KHR_materials_volume: sigma_a [1/m] of the
                                medium inside (pb_material.attenuation) */
  uint principled_v2;        /* 1: Principled v2 (Blender 4.x), model PRINCIPLED */
  /* Principled v2's colour inputs (linear) and their textures (sRGB
   * unless Non-Color, as base_color_tex), or PB_GPU_NO_TEXTURE. */
  PB_VEC3(specular_tint);
  uint specular_tint_tex;
  PB_VEC3(coat_tint);
  uint coat_tint_tex;
  PB_VEC3(sheen_tint);
  uint sheen_tint_tex;
  PB_VEC3(subsurface_radius); /* m, before Subsurface Scale */
  uint coat_normal_tex;      /* Normal Map on Coat Normal (as normal_tex) */
  float coat_normal_strength;
  uint subsurface_method;    /* pb_subsurface_method */
  uint g2_correlated;        /* 1: height-correlated Smith G2 (Blender 3.5+) */
  uint bump_model;           /* PB_GPU_BUMP_* (pb_bump_model) */
  uint node;                 /* PB_GPU_NODE_* (pb_blender_node): the Blender
                                BSDF node a principled_v2 material is */
  /* A Mix Shader (pb_blender_material.mix_with): index + 1 of the
   * material holding its second shader, 0 none; where its factor comes
   * from (PB_GPU_MIX_FAC_*; the value in_value[PB_GPU_IN_MIX_FAC]). */
  uint mix_with;
  uint mix_fac;
  uint pad0;                 /* std430 rounds the struct to 16 bytes */
} PB_END(pb_gpu_material)

/* Texture table entry: texels are RGBA8 packed one per uint (R in the low
 * byte), rows top to bottom, starting at texel `offset` of the texel buffer.
 * flags: bit 0 sRGB, bit 1 nearest; wrap modes as pb_wrap. How the material
 * reads it (pb_texture.texcoord, uv_xform): uv set `texcoord` (0 or 1),
 * then u' = dot(xform_u.xyz, (u, v, 1)), v' = dot(xform_v.xyz, (u, v, 1))
 * (the identity rows without KHR_texture_transform). */
PB_CONST(PB_GPU_TEX_SRGB, 1u)
PB_CONST(PB_GPU_TEX_NEAREST, 2u)
PB_CONST(PB_GPU_TEX_HALF, 4u)   /* two texel words a texel: unpackHalf2x16(R | G << 16), (B | A << 16); linear */
PB_STRUCT(pb_gpu_texture) {
  uint offset;
  uint width;
  uint height;
  uint flags;
  uint wrap_s;
  uint wrap_t;
  uint texcoord;
  uint pad1;
  PB_VEC4(xform_u);
  PB_VEC4(xform_v);
} PB_END(pb_gpu_texture)

/* Light, radiometric (scene.h pb_light): color * intensity folded into
 * `power` (point/spot: W/sr; directional: W/m^2; area: W/(m^2 sr) normal to
 * it). direction: unit, the way light travels. Spot: cos_outer/cos_inner of
 * KHR's smooth step, or with PB_GPU_LIGHT_CYCLES_SPOT Cycles 3.4's falloff
 * from cos_outer and spot_blend (PB_GPU_LIGHT_CYCLES4_SPOT: Cycles 4.x's). Soft lights (src/ref/soft_lights.c,
 * shaders/common/lights.glsl): point/spot with radius > 0 (Cycles' disc
 * facing the lit point); directional with radius = tan(angle / 2) > 0 (the
 * sun's disc at unit distance; cos_half = cos(angle / 2)); area lights of
 * full widths size_u, size_v along the unit axes axis_u, axis_v, with the
 * spread profile's tan_spread (tan a; 0: no spread) and norm_spread N(a). */
PB_CONST(PB_GPU_LIGHT_POINT, 0u)
PB_CONST(PB_GPU_LIGHT_SPOT, 1u)
PB_CONST(PB_GPU_LIGHT_DIRECTIONAL, 2u)
PB_CONST(PB_GPU_LIGHT_AREA, 3u)
PB_CONST(PB_GPU_LIGHT_ELLIPSE, 1u)     /* flags: an area light's shape is an ellipse */
PB_CONST(PB_GPU_LIGHT_CYCLES_SPOT, 2u) /* Cycles 3.4's spot falloff */
PB_CONST(PB_GPU_LIGHT_NO_SHADOW, 4u)   /* casts no shadow */
PB_CONST(PB_GPU_LIGHT_NO_MIS, 8u)      /* not seen by BSDF-sampled rays */
PB_CONST(PB_GPU_LIGHT_CYCLES4_SPOT, 16u) /* Cycles 4.x's spot falloff (3.4's without its cosine) */
PB_CONST(PB_GPU_LIGHT_SPHERE, 32u)       /* point/spot: Cycles 4.x's sphere light, not the facing disc */
PB_STRUCT(pb_gpu_light) {
  PB_VEC3(position);
  uint type;
  PB_VEC3(direction);
  float cos_outer;
  PB_VEC3(power);
  float cos_inner;
  PB_VEC3(axis_u);
  float radius;
  PB_VEC3(axis_v);
  float spot_blend;
  float size_u;
  float size_v;
  float tan_spread;
  float norm_spread;
  uint flags;              /* PB_GPU_LIGHT_* flags */
  float cos_half;          /* directional: cos(angle / 2) */
  uint pad0;
  uint pad1;
} PB_END(pb_gpu_light)

/* The world light (scene.h pb_world, scene/world.h), at the start of its own
 * buffer, followed by float data[]: per map texel (top row first) a vec4
 * (R, G, B radiance before `scale`, and the row's conditional CDF at this
 * cell's left edge), then height + 1 floats of the marginal CDF over the
 * rows. map_to: rows of the 3x3 taking a scene direction to the map's
 * frame. flags: PB_GPU_WORLD_*. */
PB_CONST(PB_GPU_WORLD_PRESENT, 1u)
PB_CONST(PB_GPU_WORLD_MAP, 2u)         /* a map (else the constant colour) */
PB_CONST(PB_GPU_WORLD_CAMERA, 4u)      /* camera rays see it (opaque film, visible) */
PB_CONST(PB_GPU_WORLD_SAMPLED, 8u)     /* the map has a sampling table */
PB_CONST(PB_GPU_WORLD_LIGHT, 0xffffffffu) /* pb_gpu_photon_light.light of the world */
PB_CONST(PB_GPU_EMITTER_LIGHT, 0xfffffffeu) /* ... and of the emissive triangles (emitters[]) */
PB_STRUCT(pb_gpu_world) {
  PB_VEC3(color);
  uint flags;
  PB_VEC4(map_to0);
  PB_VEC4(map_to1);
  PB_VEC4(map_to2);
  uint width;
  uint height;
  float scale;
  uint marg_offset;        /* float index of the marginal CDF in data[] */
} PB_END(pb_gpu_world)

/* Emissive triangle of the light-sampling table, 16 bytes, in scene order.
 * Picked by power (area x luminance of `emissive` x sides, the reference's
 * weight, src/ref/lights.c): entry i is chosen for u in [cdf, next entry's
 * cdf) (the last entry up to 1), with probability `pick` (the difference of
 * the two, so the pdf the shader divides by is the one it sampled with).
 * area: the triangle's area [m^2]. */
PB_STRUCT(pb_gpu_emitter) {
  uint prim;
  float cdf;
  float pick;
  float area;
} PB_END(pb_gpu_emitter)

/* A camera's rays for one image, 128 bytes (src/scene/camera.h builds it from
 * a pb_camera; shaders/common/camera.glsl and pb_camera_ray trace it). Image
 * position (px, py) in pixels, top row first, maps to the screen point
 *   sx = x0 + px dx, sy = y0 + py dy  (dy < 0: rows run down);
 * perspective: the ray leaves `position` along normalize(forward + sx right
 * + sy up) (sx, sy at distance 1); orthographic: it leaves position + sx
 * right + sy up (metres) along forward. Either starts at the near clip plane
 * (depth clip_near along forward) and ends at the far one (clip_far, 0:
 * none), as Cycles' camera rays do (kernel/camera/camera.h). A crop of a
 * larger image keeps the larger image's window (pb_gpu_frame.key_*).
 * Thin lens (Cycles 3.4 camera_sample_perspective / _orthographic /
 * _panorama): aperture > 0 moves the origin to a point of the aperture
 * (radius `aperture` m; a disc when blades is 0, else a regular polygon of
 * `blades` corners turned by blade_rotation; its x times inv_ratio) and
 * aims it at the pinhole ray's point at depth `focus` (perspective:
 * along forward; panoramic: along the ray). projection != PLANAR: a
 * panoramic camera (shared with pb_camera_panorama): sx, sy are Cycles'
 * panorama u, v in [0, 1] (x0 = shift x, dx = 1 / width, y0 = 1 + shift y,
 * dy = -1 / height) and pano holds EQUIRECTANGULAR: Cycles'
 * equirectangular_range; FISHEYE_EQUIDISTANT: fov; FISHEYE_EQUISOLID:
 * lens (mm), fov, sensor width and height (mm). */
PB_STRUCT(pb_gpu_camera) {
  PB_VEC3(position);
  float x0;
  PB_VEC3(forward);
  float dx;
  PB_VEC3(right);
  float y0;
  PB_VEC3(up);
  float dy;
  float clip_near;
  float clip_far;
  uint orthographic;
  uint projection;       /* PB_GPU_CAMERA_* */
  float aperture;        /* lens radius, m; 0: pinhole */
  float focus;           /* focal distance, m */
  float blades;          /* 0: disc; >= 3: polygon corners */
  float blade_rotation;  /* radians */
  float pano0;
  float pano1;
  float pano2;
  float pano3;
  float inv_ratio;       /* 1 / aperture ratio (anamorphic bokeh) */
  uint pad0;
  uint pad1;
  uint pad2;
} PB_END(pb_gpu_camera)
PB_CONST(PB_GPU_CAMERA_PLANAR, 0u)
PB_CONST(PB_GPU_CAMERA_EQUIRECTANGULAR, 1u)
PB_CONST(PB_GPU_CAMERA_FISHEYE_EQUIDISTANT, 2u)
PB_CONST(PB_GPU_CAMERA_FISHEYE_EQUISOLID, 3u)
PB_CONST(PB_GPU_CAMERA_MIRRORBALL, 4u)

/* Per-frame constants (a storage buffer, read by every render pass).
 * A crop of a larger frame (render --crop): pixel (x, y) of this image is
 * the frame's pixel (x + key_x0, y + key_y0): `cam` is the frame's window,
 * traced at that position, and the pixel's random numbers are keyed by its
 * index in the frame, (y + key_y0) key_width + x + key_x0, so a crop has
 * exactly the full frame's samples there. key_width 0: no crop. */
PB_STRUCT(pb_gpu_frame) {
  pb_gpu_camera cam;
  uint width;
  uint height;
  uint spp;              /* samples per pixel of the whole frame */
  uint emitter_count;    /* entries of the emitter table (0: none) */
  uint light_count;
  uint max_specular_depth;
  uint seed_lo;
  uint seed_hi;
  uint flags;            /* PB_GPU_FRAME_* */
  uint pixel_count;      /* pixels in this band (the dispatch size) */
  uint pixel_base;       /* first pixel of the band: the image is rendered
                            in bands of rows when its buffers would exceed
                            maxStorageBufferRange */
  uint tangent_base;     /* normal maps: the vertex tangents (float[4] per
                            vertex, pb_scene.tangents) start at this float
                            index of the normals buffer; 0: the scene has
                            no normal maps */
  uint key_x0;
  uint key_y0;
  uint key_width;
  uint uv1_base;         /* TEXCOORD_1 (float[2] per vertex, pb_scene.uvs1)
                            from this float index of the uvs buffer; 0: none */
  uint color_base;       /* COLOR_0 (float[4] per vertex, pb_scene.colors)
                            from this float index of the uvs buffer; 0: none */
  float glossy_path_alpha2; /* Blender materials: a specular or clearcoat
                            closure whose alpha_x alpha_y (alpha = Blender
                            roughness^2) is above this is shaded where the
                            eye path stops, a smoother one followed by the
                            eye path (render.h glossy_path_roughness^4;
                            bench/README.md has the measurement) */
  uint principled2_base; /* Principled v2: Cycles' BSDF albedo and sheen
                            tables (shared/pb_principled2_tables.h, PB_P2T_*)
                            from this index of the texels buffer; 0: the
                            scene has no v2 material */
  uint pad2;
} PB_END(pb_gpu_frame)
PB_CONST(PB_GPU_FRAME_DIRECT_ONLY, 1u)
PB_CONST(PB_GPU_FRAME_JITTER, 2u)      /* jitter the sample in the pixel also at 1 spp */
PB_CONST(PB_GPU_FRAME_OPEN_SAMPLES, 4u) /* an open-ended sample count (a time
                                          limit, a noise threshold): sample
                                          positions from a (0,2)-sequence,
                                          stratified at every prefix, not an
                                          m x m grid over spp */

/* G-buffer entry of one pixel for the current sample, 64 bytes: the first
 * non-delta surface along the eye path (after any specular chain), in world
 * space. prim == PB_GPU_MISS when the path left the scene or was absorbed.
 * throughput: the specular chain's weight; wo: toward the eye. u, v: Embree
 * barycentrics of prim. The motion vector slot is for temporal passes. */
PB_STRUCT(pb_gpu_gbuffer) {
  PB_VEC3(position);
  uint prim;
  PB_VEC3(wo);
  float u;
  PB_VEC3(throughput);
  float v;
  float motion_x;        /* reserved: motion vector, pixels */
  float motion_y;
  uint chain;            /* delta (and, for Blender materials, glossy)
                            interactions before this vertex */
  uint lobes;            /* which closures of a Blender material the direct
                            light and the gather evaluate here
                            (PB_GPU_LOBES_*); 0 for glTF materials */
} PB_END(pb_gpu_gbuffer)
/* A Blender material's closures: DIFFUSE, those shaded where the eye path
 * stops, by direct light and the photon map (diffuse, sheen, Oren-Nayar, and
 * the specular and clearcoat layers above pb_gpu_frame.glossy_path_alpha2);
 * GLOSSY, those the eye path follows (the smoother layers, glass, delta
 * lobes; gbuffer.comp). */
PB_CONST(PB_GPU_LOBES_DIFFUSE, 1u)
PB_CONST(PB_GPU_LOBES_GLOSSY, 2u)
PB_CONST(PB_GPU_LOBES_ALL, 3u)

/* Per-pixel accumulators of the band (sums over samples; the host divides by
 * spp), 80 bytes.
 * beauty.w: samples that hit geometry. depth: camera-space z summed over hit
 * samples (divide by beauty.w). emission: what the first hit emits toward
 * the camera (Blender's Emit pass; also in direct and beauty). */
PB_STRUCT(pb_gpu_accum) {
  PB_VEC4(beauty);
  PB_VEC3(direct);       /* at most one scattering event (reference's split) */
  float depth;
  PB_VEC3(albedo);
  float material;        /* material index of the first hit, + 1 (0: miss) */
  PB_VEC3(normal);
  float pad0;
  PB_VEC3(emission);
  float pad1;
} PB_END(pb_gpu_accum)

/* Push constants of the render passes: which sample of the frame this
 * dispatch renders (many samples are recorded into one command buffer). */
PB_STRUCT(pb_gpu_pass_push) {
  uint sample_index;
  uint pad0;
  uint pad1;
  uint pad2;
} PB_END(pb_gpu_pass_push)

/* Push constants of the ray-query kernel. */
PB_STRUCT(pb_gpu_raycast_push) {
  uint ray_count;
  uint any_hit;          /* 1: occlusion query (stops at the first hit) */
  uint pad0;
  uint pad1;
} PB_END(pb_gpu_raycast_push)


/* Photon tracer (shaders/photon/photon_trace.comp, src/render/photon/photon_trace.c).
 * Header of the tracer's parameter buffer, followed by one
 * pb_gpu_photon_light per light that receives photons. guarded, absorbed
 * and escaped are statistics the kernel adds to (atomics). */
PB_CONST(PB_PHOTON_PARAM_RAW_FOOTPRINT, 1u) /* tests: store Delta dP, no
                                               -3/4 compression, s, r_max */
PB_CONST(PB_PHOTON_PARAM_STORE_FIRST, 2u)   /* tests: store the first hit too */
PB_CONST(PB_PHOTON_PARAM_CAUSTIC_RAW, 8u)   /* caustic footprints uncompressed,
                                               s_caustic Delta dP (the photon footprints) */
PB_CONST(PB_PHOTON_PARAM_RSM, 4u)           /* first hits from the reflective
                                               shadow maps (shared/pb_rsm.h) */
PB_CONST(PB_PHOTON_PARAM_RSM_AUTO, 16u)     /* with RSM: per light, the map only
                                               where its coverage is below
                                               PB_RSM_AUTO_COVERAGE, else traced */
PB_STRUCT(pb_gpu_photon_params) {
  PB_VEC3(scene_center);  /* centre of the scene's bounding sphere */
  float scene_radius;     /* its radius (directional lights' disc) */
  uint photons;           /* paths this iteration (the dispatch size) */
  uint light_count;       /* entries of the light table that follows */
  uint max_bounces;       /* stored photons per path at most */
  uint max_depth;         /* surface interactions per path at most */
  uint capacity;          /* pb_gpu_photon records in the photon buffer */
  float delta;            /* global spacing Delta = 2 sqrt(pi / photons) */
  float smoothing;        /* s, diffuse photons */
  float smoothing_caustic;/* s, caustic photons */
  float r_max;            /* footprint semi-major clamp, metres */
  uint iteration;         /* RNG stream of this iteration */
  uint flags;             /* PB_PHOTON_PARAM_* */
  float stencil_h;        /* tests: > 0 traces paths in triples: path
                             gid / 3, member gid % 3 steps its (scaled)
                             parameters by stencil_h at decision
                             `stencil_depth` (0: emission, k: the k-th
                             surface interaction); 0 normally */
  uint stencil_depth;
  uint guarded;           /* stats: divisions guarded or records dropped for
                             non-finite values */
  uint absorbed;          /* stats: paths ended by Russian roulette */
  uint escaped;           /* stats: paths that left the scene */
  /* Seed 003's variable bandwidth (section 6, "variable bandwidth
   * splatting"), on when bandwidth_h0 > 0: every footprint a disc of radius
   * h = bandwidth_h0 / sqrt(clamp(p R^2, p_min, p_max)), p = cos(theta) / d^2
   * (see pb_store in photon_trace.comp); bandwidth_h0 = C0 sqrt(A / N). */
  float bandwidth_h0;
  float bandwidth_p_min;
  float bandwidth_p_max;
  uint bandwidth_pad;
} PB_END(pb_gpu_photon_params)

/* One light's share of the photon budget: paths first .. first + count - 1
 * start at lights[light] (or the world, light == PB_GPU_WORLD_LIGHT, or the
 * emissive triangles, light == PB_GPU_EMITTER_LIGHT: `emitters` entries of
 * emitters[], power pi / count, times L_e A sides / pick of the photon's
 * triangle).
 * power: flux of each photon before its direction's factor, W (point,
 * sphere: 4 pi I / count; spot: 2 pi (1 - cos_outer) I / count, times the
 * falloff; directional, soft sun: E pi R^2 / count; area: L A pi cos^2 a /
 * count, times the spread profile; world: pi R^2 / count, times L / pdf of
 * the direction). diff_scale: factor on the emission differentials so that
 * the global Delta applies (see photon_trace.comp). */
PB_STRUCT(pb_gpu_photon_light) {
  PB_VEC3(power);
  uint light;
  uint first;
  uint count;
  float diff_scale;
  float cos_max;          /* cosine of the emission cone (-1: sphere) */
  uint emitters;          /* PB_GPU_EMITTER_LIGHT: entries of emitters[] (the table's count) */
  uint pad0, pad1, pad2;
} PB_END(pb_gpu_photon_light)

#ifndef PB_GLSL
/* Host-side layout checks: the std430 offsets GLSL assigns (vec3 and vec4 on
 * 16-byte boundaries, scalars on 4) must be the C offsets. The layout test
 * (tests/unit/test_gpu_layout.c) also checks them against the compiled
 * SPIR-V's reflection. */
#include <stddef.h>
#define PB_LAYOUT(T, size) _Static_assert(sizeof(T) == (size), #T " size");
#define PB_OFFSET(T, f, off) _Static_assert(offsetof(T, f) == (off), #T "." #f " offset");
PB_LAYOUT(pb_gpu_bvh_node, 32)
PB_OFFSET(pb_gpu_bvh_node, first, 12) PB_OFFSET(pb_gpu_bvh_node, hi, 16)
PB_OFFSET(pb_gpu_bvh_node, count, 28)
PB_LAYOUT(pb_gpu_tri, 48)
PB_OFFSET(pb_gpu_tri, prim, 12) PB_OFFSET(pb_gpu_tri, p1, 16) PB_OFFSET(pb_gpu_tri, p2, 32)
PB_LAYOUT(pb_gpu_ray, 32)
PB_OFFSET(pb_gpu_ray, tmin, 12) PB_OFFSET(pb_gpu_ray, dir, 16) PB_OFFSET(pb_gpu_ray, tmax, 28)
PB_LAYOUT(pb_gpu_hit, 16)
PB_OFFSET(pb_gpu_hit, prim, 4) PB_OFFSET(pb_gpu_hit, v, 12)
PB_LAYOUT(pb_gpu_material, 480)
PB_OFFSET(pb_gpu_material, emissive, 16) PB_OFFSET(pb_gpu_material, base_color_tex, 28)
PB_OFFSET(pb_gpu_material, specular_color, 32) PB_OFFSET(pb_gpu_material, metallic_roughness_tex, 44)
PB_OFFSET(pb_gpu_material, metallic, 48) PB_OFFSET(pb_gpu_material, ior, 60)
PB_OFFSET(pb_gpu_material, specular, 64) PB_OFFSET(pb_gpu_material, flags, 72)
PB_OFFSET(pb_gpu_material, normal_tex, 76) PB_OFFSET(pb_gpu_material, normal_scale, 80)
PB_OFFSET(pb_gpu_material, model, 84) PB_OFFSET(pb_gpu_material, subsurface_color, 96)
PB_OFFSET(pb_gpu_material, normal_strength, 108) PB_OFFSET(pb_gpu_material, in_value, 112)
PB_OFFSET(pb_gpu_material, in_tex, 240) PB_OFFSET(pb_gpu_material, attenuation, 368)
PB_OFFSET(pb_gpu_material, principled_v2, 380) PB_OFFSET(pb_gpu_material, specular_tint, 384)
PB_OFFSET(pb_gpu_material, coat_tint, 400) PB_OFFSET(pb_gpu_material, sheen_tint, 416)
PB_OFFSET(pb_gpu_material, subsurface_radius, 432) PB_OFFSET(pb_gpu_material, coat_normal_tex, 444)
PB_OFFSET(pb_gpu_material, g2_correlated, 456) PB_OFFSET(pb_gpu_material, node, 464)
PB_LAYOUT(pb_gpu_texture, 64)
PB_OFFSET(pb_gpu_texture, flags, 12) PB_OFFSET(pb_gpu_texture, wrap_t, 20)
PB_OFFSET(pb_gpu_texture, texcoord, 24) PB_OFFSET(pb_gpu_texture, xform_u, 32)
PB_OFFSET(pb_gpu_texture, xform_v, 48)
PB_LAYOUT(pb_gpu_light, 112)
PB_OFFSET(pb_gpu_light, type, 12) PB_OFFSET(pb_gpu_light, direction, 16)
PB_OFFSET(pb_gpu_light, cos_outer, 28) PB_OFFSET(pb_gpu_light, power, 32)
PB_OFFSET(pb_gpu_light, cos_inner, 44) PB_OFFSET(pb_gpu_light, axis_u, 48)
PB_OFFSET(pb_gpu_light, radius, 60) PB_OFFSET(pb_gpu_light, axis_v, 64)
PB_OFFSET(pb_gpu_light, spot_blend, 76) PB_OFFSET(pb_gpu_light, size_u, 80)
PB_OFFSET(pb_gpu_light, norm_spread, 92) PB_OFFSET(pb_gpu_light, flags, 96)
PB_OFFSET(pb_gpu_light, cos_half, 100)
PB_LAYOUT(pb_gpu_world, 80)
PB_OFFSET(pb_gpu_world, flags, 12) PB_OFFSET(pb_gpu_world, map_to0, 16)
PB_OFFSET(pb_gpu_world, map_to2, 48) PB_OFFSET(pb_gpu_world, width, 64)
PB_OFFSET(pb_gpu_world, scale, 72) PB_OFFSET(pb_gpu_world, marg_offset, 76)
PB_LAYOUT(pb_gpu_emitter, 16)
PB_OFFSET(pb_gpu_emitter, cdf, 4) PB_OFFSET(pb_gpu_emitter, pick, 8) PB_OFFSET(pb_gpu_emitter, area, 12)
PB_LAYOUT(pb_gpu_camera, 128)
PB_OFFSET(pb_gpu_camera, x0, 12) PB_OFFSET(pb_gpu_camera, forward, 16) PB_OFFSET(pb_gpu_camera, dx, 28)
PB_OFFSET(pb_gpu_camera, right, 32) PB_OFFSET(pb_gpu_camera, y0, 44) PB_OFFSET(pb_gpu_camera, up, 48)
PB_OFFSET(pb_gpu_camera, dy, 60) PB_OFFSET(pb_gpu_camera, clip_near, 64) PB_OFFSET(pb_gpu_camera, orthographic, 72)
PB_OFFSET(pb_gpu_camera, projection, 76) PB_OFFSET(pb_gpu_camera, aperture, 80) PB_OFFSET(pb_gpu_camera, pano0, 96)
PB_OFFSET(pb_gpu_camera, inv_ratio, 112)
PB_LAYOUT(pb_gpu_frame, 208)
PB_OFFSET(pb_gpu_frame, width, 128) PB_OFFSET(pb_gpu_frame, spp, 136)
PB_OFFSET(pb_gpu_frame, seed_lo, 152) PB_OFFSET(pb_gpu_frame, flags, 160)
PB_OFFSET(pb_gpu_frame, pixel_base, 168) PB_OFFSET(pb_gpu_frame, tangent_base, 172)
PB_OFFSET(pb_gpu_frame, key_x0, 176) PB_OFFSET(pb_gpu_frame, key_width, 184)
PB_OFFSET(pb_gpu_frame, uv1_base, 188) PB_OFFSET(pb_gpu_frame, color_base, 192)
PB_OFFSET(pb_gpu_frame, glossy_path_alpha2, 196)
PB_LAYOUT(pb_gpu_gbuffer, 64)
PB_OFFSET(pb_gpu_gbuffer, prim, 12) PB_OFFSET(pb_gpu_gbuffer, wo, 16) PB_OFFSET(pb_gpu_gbuffer, u, 28)
PB_OFFSET(pb_gpu_gbuffer, throughput, 32) PB_OFFSET(pb_gpu_gbuffer, v, 44)
PB_OFFSET(pb_gpu_gbuffer, motion_x, 48) PB_OFFSET(pb_gpu_gbuffer, chain, 56)
PB_LAYOUT(pb_gpu_accum, 80)
PB_OFFSET(pb_gpu_accum, direct, 16) PB_OFFSET(pb_gpu_accum, depth, 28)
PB_OFFSET(pb_gpu_accum, albedo, 32) PB_OFFSET(pb_gpu_accum, material, 44)
PB_OFFSET(pb_gpu_accum, normal, 48) PB_OFFSET(pb_gpu_accum, emission, 64)
PB_LAYOUT(pb_gpu_raycast_push, 16)
PB_LAYOUT(pb_gpu_pass_push, 16)
PB_LAYOUT(pb_gpu_photon_params, 96)
PB_OFFSET(pb_gpu_photon_params, scene_radius, 12) PB_OFFSET(pb_gpu_photon_params, photons, 16)
PB_OFFSET(pb_gpu_photon_params, capacity, 32) PB_OFFSET(pb_gpu_photon_params, r_max, 48)
PB_OFFSET(pb_gpu_photon_params, stencil_h, 60) PB_OFFSET(pb_gpu_photon_params, guarded, 68)
PB_OFFSET(pb_gpu_photon_params, escaped, 76) PB_OFFSET(pb_gpu_photon_params, bandwidth_h0, 80)
PB_OFFSET(pb_gpu_photon_params, bandwidth_p_max, 88)
PB_LAYOUT(pb_gpu_photon_light, 48)
PB_OFFSET(pb_gpu_photon_light, light, 12) PB_OFFSET(pb_gpu_photon_light, first, 16)
PB_OFFSET(pb_gpu_photon_light, cos_max, 28) PB_OFFSET(pb_gpu_photon_light, emitters, 32)
#undef PB_LAYOUT
#undef PB_OFFSET
#endif

#endif
