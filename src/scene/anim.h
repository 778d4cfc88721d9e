/* glTF node animation, internal to src/scene: what the loader (load.c)
 * records so that pb_scene_set_time (anim.c) can pose the scene again later.
 *
 * The loader keeps, for every primitive instance under an animated node (a
 * node with a translation/rotation/scale channel, or a descendant of one),
 * its vertices in the node's local space, and the node of every camera and
 * light; posing re-runs the static load's transform arithmetic (xform.h) on
 * them with the sampled local TRS, so a pose with the file's own TRS gives
 * exactly the arrays of the static load. Nothing else in pb_scene changes. */
#ifndef PB_SCENE_ANIM_H
#define PB_SCENE_ANIM_H

#include <stdint.h>

#include "scene/scene.h"
#include "scene/xform.h"

enum { PB_ANIM_STEP = 0, PB_ANIM_LINEAR = 1, PB_ANIM_CUBICSPLINE = 2 };
enum { PB_ANIM_TRANSLATION = 0, PB_ANIM_ROTATION = 1, PB_ANIM_SCALE = 2, PB_ANIM_WEIGHTS = 3 };

typedef struct pb_anim_sampler {
  float *times;        /* key_count, non-decreasing, finite */
  float *values;       /* key_count * comps, or 3 * key_count * comps for
                          CUBICSPLINE (in-tangent, value, out-tangent per key) */
  uint32_t key_count;
  int comps;           /* 3 (translation, scale), 4 (rotation x y z w), or
                          the morph target count (weights) */
  int interp;          /* PB_ANIM_* */
} pb_anim_sampler;

typedef struct pb_anim_channel {
  uint32_t sampler;    /* into pb_scene_anim.samplers */
  int32_t node;
  int path;            /* PB_ANIM_TRANSLATION .. WEIGHTS */
} pb_anim_channel;

typedef struct pb_anim_node {
  int32_t parent;      /* -1: root */
  int has_matrix;      /* nodes given by `matrix` are never animated */
  mat4 matrix;
  double t[3], r[4], s[3];  /* the file's TRS (the rest pose) */
  int animated;        /* it or an ancestor has a translation, rotation or
                          scale channel */
  int weights_animated;/* it has a "weights" channel */
} pb_anim_node;

/* One primitive instance under an animated node: scene vertices
 * [first_vertex, +vertex_count) and triangles [first_tri, +tri_count). */
typedef struct pb_anim_range {
  int32_t node;
  uint32_t first_vertex, vertex_count;
  uint32_t first_tri, tri_count;
  uint32_t local;      /* first of its vertices in local_pos / local_nrm */
  int flat;            /* 1: no NORMAL in the file: one vertex per triangle
                          corner, normals are face normals */
} pb_anim_range;

struct pb_scene_anim {
  pb_anim_node *nodes;
  uint32_t node_count;
  int32_t *order;      /* every node, parents before children: the shown
                          scene's first (the loader's order), then the
                          others (joints may lie outside the scene) */
  uint32_t order_count;
  pb_anim_sampler *samplers;
  uint32_t sampler_count;
  pb_anim_channel *channels;   /* applied in order: a later channel on the
                                  same node and path wins */
  uint32_t channel_count;
  pb_anim_range *ranges;
  uint32_t range_count, range_cap;
  float (*local_pos)[3], (*local_nrm)[3];
  uint32_t local_count, local_cap;
  int32_t *camera_node, *light_node;  /* per pb_scene camera / light; -1: none */
  uint32_t camera_cap, light_cap;
  float (*camera_frame)[9];  /* rest forward, up, right (fallback when a pose
                                degenerates the frame, e.g. scale 0) */
  float (*light_dir)[3];     /* rest direction, same use */
  /* Skinned and morphed instances (deform.h); NULL when none moves. */
  struct pb_deform *deform;
  uint8_t *tan_given;        /* vertices whose tangents the deformation
                                poses (the file's TANGENT), NULL if none */
  /* Scratch for posing (pb_scene_set_time is not reentrant per scene). */
  double (*trs)[10];         /* per node: t[3] r[4] s[3] */
  mat4 *world;
  double *values;            /* one sampled key: max(4, target count) */
};

void pb_scene_anim_destroy(struct pb_scene_anim *a);

/* Bounds of the referenced vertices (pb_scene_finalize's, features untouched). */
void pb_scene_update_bounds(pb_scene *s);

#endif
