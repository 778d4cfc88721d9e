/* A plain-C view of a parsed glTF document, filled by the tinygltf shim
 * (gltf_shim.cpp). It is the raw file content: nothing in it is validated
 * beyond what JSON parsing guarantees (types of fields). The loader (load.c, load_*.c) checks every
 * index, offset, stride and count before reading any data.
 *
 * Indices are -1 when absent. Arrays are pointer + count. All memory belongs to
 * the document and is released by pb_gltf_doc_destroy(). */
#ifndef PB_GLTF_DOC_H
#define PB_GLTF_DOC_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

/* A JSON value of an extension the loader reads itself (PHOTONBRIDGE_blender
 * on the root, nodes and materials; blender_lights.c, blender_material.c), as
 * parsed: objects keep their members in name order (tinygltf's; a repeated
 * name keeps one value), numbers are doubles (tinygltf's integers converted;
 * a literal too large for a double is refused by the shim, naming its JSON
 * path); is_integer: the number was written as an integer. */
typedef enum pb_gltf_value_type {
  PB_GLTF_NULL = 0, PB_GLTF_BOOL, PB_GLTF_NUMBER, PB_GLTF_STRING, PB_GLTF_ARRAY, PB_GLTF_OBJECT
} pb_gltf_value_type;

typedef struct pb_gltf_value {
  pb_gltf_value_type type;
  int boolean;
  int is_integer;
  double number;
  const char *string;                 /* STRING */
  const struct pb_gltf_value *items;  /* ARRAY: the elements; OBJECT: the members' values */
  const char *const *keys;            /* OBJECT: the members' names */
  size_t count;
} pb_gltf_value;

/* Member `key` of an object, NULL when absent (or v is not an object). */
const pb_gltf_value *pb_gltf_value_get(const pb_gltf_value *v, const char *key);
/* "object", "array", ... for messages. */
const char *pb_gltf_value_type_name(const pb_gltf_value *v);

typedef struct pb_gltf_buffer {
  const uint8_t *data; /* loaded bytes (GLB BIN chunk, data URI or file) */
  uint64_t size;       /* bytes actually loaded */
  uint64_t byte_length;/* as declared */
  const char *uri;     /* "" for the GLB chunk */
} pb_gltf_buffer;

typedef struct pb_gltf_buffer_view {
  int32_t buffer;
  uint64_t byte_offset, byte_length;
  uint32_t byte_stride; /* 0: tightly packed */
} pb_gltf_buffer_view;

/* accessor.sparse: `count` elements replaced; indices and values are
 * packed in their bufferViews (offsets default 0, views -1 when absent). */
typedef struct pb_gltf_sparse {
  uint64_t count;
  int32_t indices_view, indices_ct;
  uint64_t indices_offset;
  int32_t values_view;
  uint64_t values_offset;
} pb_gltf_sparse;

typedef struct pb_gltf_accessor {
  int32_t buffer_view;    /* -1: all zeros (then sparse values, if any) */
  uint64_t byte_offset;
  int32_t component_type; /* 5120..5126 */
  int32_t components;     /* 1 (SCALAR) .. 16 (MAT4), 0 if type unknown */
  uint64_t count;
  int normalized;
  int sparse;             /* 1: sparse_info applies */
  pb_gltf_sparse sparse_info;
  int has_min_max;
  double min[3], max[3];  /* first three components */
} pb_gltf_accessor;

/* A morph target: displacement accessors, -1 when absent. */
typedef struct pb_gltf_target {
  int32_t position, normal, tangent;
} pb_gltf_target;

typedef struct pb_gltf_primitive {
  int32_t mode;           /* 4 = TRIANGLES */
  int32_t position, normal, texcoord0, indices, material;
  int32_t tangent;        /* TANGENT accessor, -1: absent */
  int32_t texcoord1;      /* TEXCOORD_1, -1: absent */
  int32_t color0;         /* COLOR_0, -1: absent */
  /* JOINTS_n and WEIGHTS_n for n = 0 .. count - 1 (count: one past the
   * highest n present; a gap below it is -1). */
  int32_t *joints, *weights;
  size_t joint_set_count, weight_set_count;
  pb_gltf_target *targets;
  size_t target_count;
  /* KHR_materials_variants: mappings of this primitive (the default,
   * `material`, is what photonbridge shows). */
  size_t variant_mapping_count;
} pb_gltf_primitive;

typedef struct pb_gltf_mesh {
  const char *name;
  pb_gltf_primitive *primitives;
  size_t primitive_count;
  const double *weights;  /* default morph weights, weight_count of them */
  size_t weight_count;
} pb_gltf_mesh;

/* skins[i]: joints are node indices; inverse_bind_matrices an accessor of
 * MAT4 (-1: identities); skeleton a node or -1. */
typedef struct pb_gltf_skin {
  const char *name;
  int32_t inverse_bind_matrices, skeleton;
  const int32_t *joints;
  size_t joint_count;
} pb_gltf_skin;

typedef struct pb_gltf_node {
  const char *name;
  int32_t *children;
  size_t child_count;
  int32_t mesh, camera, light, skin;
  int has_matrix;
  double matrix[16];      /* column-major, as in glTF */
  double translation[3], rotation[4] /* x y z w */, scale[3];
  const double *weights;  /* morph weights of its mesh, overriding the
                             mesh's; weight_count 0: not given */
  size_t weight_count;
  const pb_gltf_value *blender; /* extensions.PHOTONBRIDGE_blender, NULL if absent */
} pb_gltf_node;

typedef struct pb_gltf_scene {
  const char *name;
  int32_t *nodes;
  size_t node_count;
} pb_gltf_scene;

/* cameras[i].extensions.PHOTONBRIDGE_blender
 * (exporters/blender/PHOTONBRIDGE_blender.md), as written: strings NULL and
 * numbers NAN where a member is absent. A member of the wrong JSON type is
 * named by bad_member (bad_expect says what it should be: "a number", "a
 * string"; bad_member "" when the extension itself is not an object); the
 * loader reports it. */
typedef struct pb_gltf_camera_blender {
  int present;
  const char *bad_member, *bad_expect;
  const char *type, *sensor_fit, *panorama_type;
  double lens, sensor_width, sensor_height, ortho_scale, shift_x, shift_y, clip_start, clip_end, aspect;
  /* depth of field (absent aperture_fstop: none) and panoramas */
  double focus_distance, aperture_fstop, aperture_blades, aperture_rotation, aperture_ratio;
  double fisheye_fov, fisheye_lens, latitude_min, latitude_max, longitude_min, longitude_max;
} pb_gltf_camera_blender;

typedef struct pb_gltf_camera {
  const char *name;
  int perspective;        /* type "perspective" */
  int orthographic;       /* type "orthographic" */
  const char *type;
  double yfov, aspect_ratio; /* perspective; aspect 0: absent */
  double xmag, ymag;      /* orthographic */
  double znear, zfar;     /* of the camera's type; zfar 0: absent */
  pb_gltf_camera_blender blender;
} pb_gltf_camera;

typedef struct pb_gltf_light {
  const char *name;
  const char *type;       /* "point", "spot", "directional" or other */
  double color[3], intensity, range;
  double inner_cone, outer_cone;
} pb_gltf_light;

/* KHR_texture_transform on a textureInfo: uv' = T(offset) R(rotation)
 * S(scale) uv, with the extension's texCoord (if given) replacing the
 * textureInfo's. */
typedef struct pb_gltf_texture_transform {
  int present;
  double offset[2], rotation, scale[2];
  int32_t texcoord;       /* -1: not given */
} pb_gltf_texture_transform;

typedef struct pb_gltf_texture_ref {
  int32_t index;          /* textures[index], -1: none */
  int32_t texcoord;
  double scale;           /* normalTexture.scale */
  pb_gltf_texture_transform transform;
} pb_gltf_texture_ref;

typedef struct pb_gltf_material {
  const char *name;
  double base_color[4];
  pb_gltf_texture_ref base_color_tex;
  double metallic, roughness;
  pb_gltf_texture_ref metallic_roughness_tex;
  pb_gltf_texture_ref normal_tex;
  pb_gltf_texture_ref emissive_tex;
  double emissive[3];
  double emissive_strength;     /* KHR_materials_emissive_strength, 1 if absent */
  int has_specular;             /* KHR_materials_specular present */
  double specular, specular_color[3];
  double transmission;          /* KHR_materials_transmission */
  double ior;                   /* KHR_materials_ior, 1.5 if absent */
  int unlit;                    /* KHR_materials_unlit present */
  int has_volume;               /* KHR_materials_volume present */
  double thickness;             /* its thicknessFactor (0 if absent: thin-walled) */
  double attenuation_distance;  /* metres; 0 if absent (= infinite) */
  double attenuation_color[3];  /* 1 if absent */
  /* KHR_materials_iridescence: its factor (0 if absent), the film's IOR
   * (1.3) and thickness range in nm (100, 400); NaN for a member present
   * that is not a number. iridescence_textures: it names a texture. */
  int has_iridescence;
  int has_clearcoat, has_sheen; /* KHR_materials_clearcoat / _sheen present (read only through
                                   PHOTONBRIDGE_blender, which renders those layers) */
  double iridescence, iridescence_ior, iridescence_thickness_min, iridescence_thickness_max;
  int iridescence_textures;
  const char *alpha_mode;
  double alpha_cutoff;
  int double_sided;
  const pb_gltf_value *blender; /* extensions.PHOTONBRIDGE_blender, NULL if absent */
} pb_gltf_material;

typedef struct pb_gltf_texture {
  int32_t source, sampler;
  /* extensions.PHOTONBRIDGE_blender.source: the same image with more than 8
   * bits a channel (a 16-bit PNG, HDR or EXR: image/decode.h), read in place
   * of `source`, which stays the 8-bit fallback other glTF readers show; -1
   * none, -2 present but not an integer (an error). */
  int32_t float_source;
} pb_gltf_texture;

typedef struct pb_gltf_image {
  const char *name;
  const char *uri;        /* "" when from a bufferView or a data URI */
  const char *mime_type;
  int32_t buffer_view;
  /* A data URI's decoded bytes (image/png or image/jpeg, base64 checked
   * strictly by the shim); NULL otherwise. */
  const uint8_t *data;
  size_t data_size;
} pb_gltf_image;

typedef struct pb_gltf_sampler {
  int32_t mag_filter, min_filter, wrap_s, wrap_t;
} pb_gltf_sampler;

/* animations[i].samplers[j]: keyframe times (input) and values (output). */
typedef struct pb_gltf_anim_sampler {
  int32_t input, output;      /* accessors; -1 when absent */
  const char *interpolation;  /* "LINEAR" (the default), "STEP",
                                 "CUBICSPLINE", or whatever the file says */
} pb_gltf_anim_sampler;

/* animations[i].channels[j]: which sampler drives which node property. */
typedef struct pb_gltf_anim_channel {
  int32_t sampler;            /* index into the animation's samplers */
  int32_t target_node;        /* -1 when absent */
  const char *path;           /* "translation", "rotation", "scale",
                                 "weights", or whatever the file says */
} pb_gltf_anim_channel;

typedef struct pb_gltf_animation {
  const char *name;
  pb_gltf_anim_sampler *samplers;
  size_t sampler_count;
  pb_gltf_anim_channel *channels;
  size_t channel_count;
} pb_gltf_animation;

typedef struct pb_gltf_doc {
  const char *generator;
  const char *const *extensions_used;
  size_t extensions_used_count;
  const char *const *extensions_required;
  size_t extensions_required_count;
  int32_t default_scene;  /* -1: none */
  pb_gltf_buffer *buffers; size_t buffer_count;
  pb_gltf_buffer_view *buffer_views; size_t buffer_view_count;
  pb_gltf_accessor *accessors; size_t accessor_count;
  pb_gltf_mesh *meshes; size_t mesh_count;
  pb_gltf_node *nodes; size_t node_count;
  pb_gltf_scene *scenes; size_t scene_count;
  pb_gltf_camera *cameras; size_t camera_count;
  pb_gltf_light *lights; size_t light_count;
  pb_gltf_material *materials; size_t material_count;
  pb_gltf_texture *textures; size_t texture_count;
  pb_gltf_image *images; size_t image_count;
  pb_gltf_sampler *samplers; size_t sampler_count;
  pb_gltf_animation *animations; /* animation_count of them */
  size_t animation_count, animation_channel_count;
  pb_gltf_skin *skins; size_t skin_count;
  /* KHR_materials_variants: the names of the file's variants. */
  const char *const *variant_names; size_t variant_count;
  const pb_gltf_value *blender; /* root extensions.PHOTONBRIDGE_blender, NULL if absent */
  void *impl;             /* the shim's own storage */
} pb_gltf_doc;

typedef struct pb_gltf_read_desc {
  int allow_external_files;
  uint64_t max_file_bytes;
  /* The folder relative URIs (buffers, images, the PHOTONBRIDGE_blender
   * world map) resolve against: the file's own folder for
   * pb_gltf_doc_read; for pb_gltf_doc_parse the caller's, or NULL for none
   * (every URI that names a file is then refused; data: URIs and the GLB
   * BIN chunk still work). */
  const char *dir;
} pb_gltf_read_desc;

/* Parses `path` (.gltf JSON or .glb by magic) and loads its buffers. External
 * buffer URIs must resolve inside the file's folder unless allowed (desc->dir
 * is ignored: the file's folder is used). Images are not decoded here (load.c
 * does it, with size limits). Errors: one line "PATH: where: why" through
 * pb_fail. */
pb_result pb_gltf_doc_read(const char *path, const pb_gltf_read_desc *desc,
                           pb_gltf_doc *doc);
/* The same on `size` bytes in memory (read during the call only): `name`
 * stands for the file in every message; URIs resolve against desc->dir
 * (NULL: no external files). */
pb_result pb_gltf_doc_parse(const char *name, const uint8_t *data, size_t size,
                            const pb_gltf_read_desc *desc, pb_gltf_doc *doc);
void pb_gltf_doc_destroy(pb_gltf_doc *doc);

/* Resolves a relative URI against the folder `dir` with percent-decoding,
 * refusing absolute paths and paths that leave the folder (after resolving
 * "..", and symlinks through realpath) unless allow_external. `dir` NULL:
 * the document has no folder (loaded from memory without one) and every
 * file URI is refused (PB_ERR_SCENE_UNSUPPORTED). Messages begin with
 * `scene_name`. On success *out is a malloc'd file path. Shared by buffers,
 * images and the PHOTONBRIDGE_blender world map. */
pb_result pb_gltf_resolve_uri(const char *scene_name, const char *dir, const char *uri,
                              int allow_external, const char *where, char **out);

#endif
