/* The glTF loader's own header, shared by its files only (load.c and
 * load_*.c): the loader state and what each concept's file gives the
 * others. load.c orchestrates: materials (load_material.c, which decodes
 * the textures it uses through load_texture.c), the node graph's checks
 * (load_node.c), skins and morph weights (deform.h), animations
 * (load_anim.c), then the walk of the scene shown (load_node.c), which
 * flattens each node's mesh primitives (load_mesh.c), camera
 * (load_camera.c) and light (load_light.c) into the pb_scene. Every
 * function here returns a pb_result with one line "FILE: JSON-PATH: why"
 * set on failure (FILE: L->path). */
#ifndef PB_SCENE_LOAD_INTERNAL_H
#define PB_SCENE_LOAD_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "scene/accessor.h"
#include "scene/deform.h"
#include "scene/gltf_doc.h"
#include "scene/scene.h"
#include "scene/xform.h"

typedef struct loader {
  const char *path;           /* the file, or the memory load's name: in every message */
  const char *dir;            /* where URIs resolve (gltf_doc.h), NULL: no external files */
  const pb_load_desc *desc;
  pb_gltf_doc *doc;
  pb_scene *s;
  uint32_t vertex_cap, triangle_cap, light_cap, camera_cap, texture_cap;
  int32_t default_material;   /* index in s->materials, -1 until needed */
  /* Mix Shaders' second shaders: stored after the glTF materials. */
  uint32_t mix_capacity, mix_count;
  int32_t *texture_src;       /* per s->textures: its glTF texture */
  uint8_t **image_cache;      /* decoded RGBA8 per gltf image */
  float **image_cache_f;      /* or RGBA floats (16-bit PNG, HDR, EXR: image/decode.h) */
  uint8_t *image_linear;      /* 1: image_cache_f holds scene-linear values (HDR, EXR) */
  uint32_t *image_w, *image_h;
  uint8_t *node_state;        /* cycle detection: 0 new, 1 on stack, 2 done */
  int32_t *parent;
  struct pb_scene_anim *anim; /* being built (anim.h); moved to s->anim */
  /* TANGENT attributes of normal-mapped primitives, world space, per vertex
   * of s (grown lazily to tan_cap; NULL until the first one); tan_given[v]
   * != 0 where the file gave vertex v one. load_tangents() hands them to
   * pb_tangents_generate (tangents.c) for the rest. */
  float (*tan)[4];
  uint8_t *tan_given;
  uint32_t tan_cap;
  /* Skins and morph targets (deform.h): moved to the scene's anim when an
   * instance moves, freed after the static pose otherwise. world: every
   * node's world matrix in the file's own pose (with the precision origin),
   * which the static pose of skinned instances needs before visit() has
   * reached their joints. */
  pb_deform deform;
  mat4 *world;
  int need_uv1;               /* some texture reads TEXCOORD_1 */
  uint64_t texels;            /* over every s->textures (load_texture_ref's budget) */
} loader;

/* ---- load.c: helpers ---------------------------------------------------- */

/* Grows *p (of *cap elements of `elem` bytes) to hold `need`; the limit
 * and out-of-memory errors name `what`. */
pb_result load_grow(loader *L, void **p, uint32_t *cap, uint64_t need, size_t elem, const char *what);
/* A warning on the scene (printf format); PB_ERR_NOMEM when it cannot be kept. */
pb_result load_warn(loader *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* a if non-empty, else b (NULL: ""), truncated to a name. */
void load_copy_name(char dst[PB_NAME_MAX], const char *a, const char *b);
/* A node's local matrix: `matrix`, or T R S (xform.h). */
mat4 load_node_local(const pb_gltf_node *n);

/* ---- load_texture.c ------------------------------------------------------ */

/* A material's texture reference as an index in s->textures (PB_NO_TEXTURE
 * when none), the image decoded on first use; `where` its JSON path. */
pb_result load_texture_ref(loader *L, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out);

/* ---- load_material.c ----------------------------------------------------- */

/* materials[i] checked and converted into *m. */
pb_result load_material(loader *L, int i, pb_material *m);
/* The index of the material of primitives without one (added on first use,
 * in the slot s->materials keeps for it). */
int32_t load_default_material(loader *L);
/* Whether any texture of m reads uv set 1. */
int load_reads_uv1(const pb_scene *s, const pb_material *m);

/* ---- load_anim.c --------------------------------------------------------- */

/* The file's animations into L->anim (NULL when nothing moves), with the
 * nodes they animate marked. */
pb_result load_anims(loader *L);
/* Room for `more` local vertices of animated rigid instances. */
pb_result load_anim_reserve(loader *L, struct pb_scene_anim *a, uint64_t more);
/* (*arr)[at] = node, growing *arr (-1 filled) to hold it. */
pb_result load_anim_push_node(loader *L, int32_t **arr, uint32_t *cap, uint32_t at, int32_t node);
/* The union of the key times of the samplers in use. */
void load_anim_range(const struct pb_scene_anim *a, double *start, double *end);
/* Once every camera and light exists: their nodes and rest frames. */
pb_result load_anim_finish(loader *L, struct pb_scene_anim *a);

/* ---- load_mesh.c --------------------------------------------------------- */

/* meshes[mesh].primitives[pi], drawn by nodes[node] with world transform M,
 * into the scene's vertex and triangle arrays. */
pb_result load_primitive(loader *L, int32_t node, int32_t mesh, size_t pi, const mat4 *M);
/* After the walk: the deformed instances that move kept for posing. */
pb_result load_deform_finish(loader *L);
/* Tangent frames for normal-mapped and anisotropic scenes. */
pb_result load_tangents(loader *L);

/* ---- load_camera.c, load_light.c ----------------------------------------- */

/* nodes[node].camera placed with world transform M. */
pb_result load_camera(loader *L, int32_t node, const mat4 *M);
/* A camera framing the scene's bounds, for files without one. */
pb_result load_default_camera(loader *L);
/* nodes[node]'s light (PHOTONBRIDGE_blender's, else KHR_lights_punctual's),
 * placed with world transform M. */
pb_result load_node_light(loader *L, int32_t node, const mat4 *M);

/* ---- load_node.c --------------------------------------------------------- */

/* The node graph is a forest (L->parent filled); node TRS finite. */
pb_result load_check_nodes(loader *L);
/* The scene shown walked into the pb_scene (precision origin, rest worlds,
 * every node's mesh, camera and light). */
pb_result load_scene_nodes(loader *L);

#endif
