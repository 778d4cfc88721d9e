/* A plain-C view of a parsed glTF document, filled by the tinygltf shim
 * (gltf_shim.cpp). It is the raw file content: nothing in it is validated
 * beyond what JSON parsing guarantees (types of fields). load.c checks every
 * index, offset, stride and count before reading any data.
 *
 * Indices are -1 when absent. Arrays are pointer + count. All memory belongs to
 * the document and is released by pb_gltf_doc_destroy(). */
#ifndef PB_GLTF_DOC_H
#define PB_GLTF_DOC_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

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

typedef struct pb_gltf_accessor {
  int32_t buffer_view;    /* -1: all zeros (or sparse) */
  uint64_t byte_offset;
  int32_t component_type; /* 5120..5126 */
  int32_t components;     /* 1 (SCALAR) .. 16 (MAT4), 0 if type unknown */
  uint64_t count;
  int normalized;
  int sparse;             /* sparse accessors are refused by the loader */
  int has_min_max;
  double min[3], max[3];  /* first three components */
} pb_gltf_accessor;

typedef struct pb_gltf_primitive {
  int32_t mode;           /* 4 = TRIANGLES */
  int32_t position, normal, texcoord0, indices, material;
  int32_t tangent;        /* TANGENT accessor, -1: absent */
  int has_targets;        /* morph targets (ignored with a warning) */
} pb_gltf_primitive;

typedef struct pb_gltf_mesh {
  const char *name;
  pb_gltf_primitive *primitives;
  size_t primitive_count;
} pb_gltf_mesh;

typedef struct pb_gltf_node {
  const char *name;
  int32_t *children;
  size_t child_count;
  int32_t mesh, camera, light, skin;
  int has_matrix;
  double matrix[16];      /* column-major, as in glTF */
  double translation[3], rotation[4] /* x y z w */, scale[3];
} pb_gltf_node;

typedef struct pb_gltf_scene {
  const char *name;
  int32_t *nodes;
  size_t node_count;
} pb_gltf_scene;

typedef struct pb_gltf_camera {
  const char *name;
  int perspective;        /* 0: orthographic or unknown type */
  const char *type;
  double yfov, aspect_ratio, znear, zfar; /* aspect 0 / zfar 0: absent */
} pb_gltf_camera;

typedef struct pb_gltf_light {
  const char *name;
  const char *type;       /* "point", "spot", "directional" or other */
  double color[3], intensity, range;
  double inner_cone, outer_cone;
} pb_gltf_light;

typedef struct pb_gltf_texture_ref {
  int32_t index;          /* textures[index], -1: none */
  int32_t texcoord;
  double scale;           /* normalTexture.scale */
} pb_gltf_texture_ref;

/* A JSON value of an extension the shim hands over whole: objects' members
 * in name order (as tinygltf keeps them). Numbers are doubles; is_integer:
 * the number was written as an integer. */
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
  const char *alpha_mode;
  double alpha_cutoff;
  int double_sided;
  const pb_gltf_value *blender; /* extensions.PHOTONBRIDGE_blender, NULL if absent */
} pb_gltf_material;

typedef struct pb_gltf_texture {
  int32_t source, sampler;
} pb_gltf_texture;

typedef struct pb_gltf_image {
  const char *name;
  const char *uri;        /* "" when from a bufferView */
  const char *mime_type;
  int32_t buffer_view;
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
  size_t animation_count, animation_channel_count, skin_count;
  void *impl;             /* the shim's own storage */
} pb_gltf_doc;

typedef struct pb_gltf_read_desc {
  int allow_external_files;
  uint64_t max_file_bytes;
} pb_gltf_read_desc;

/* Parses `path` (.gltf JSON or .glb by magic) and loads its buffers. External
 * buffer URIs must resolve inside the file's folder unless allowed. Images are
 * not decoded here (load.c does it, with size limits). Errors: one line
 * "PATH: where: why" through pb_fail. */
pb_result pb_gltf_doc_read(const char *path, const pb_gltf_read_desc *desc,
                           pb_gltf_doc *doc);
void pb_gltf_doc_destroy(pb_gltf_doc *doc);

/* Resolves a relative URI against the scene's folder with percent-decoding,
 * refusing absolute paths and paths that leave the folder (after resolving
 * "..", and symlinks through realpath) unless allow_external. On success
 * *out is a malloc'd file path. Shared by buffers and images. */
pb_result pb_gltf_resolve_uri(const char *scene_path, const char *uri,
                              int allow_external, const char *where, char **out);

#endif
