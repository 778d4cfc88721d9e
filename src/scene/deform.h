/* Skinned and morphed primitives (glTF 2.0 3.7.3 skins, 3.7.2.2 morph
 * targets), internal to src/scene.
 *
 * The loader (load_mesh.c) keeps, for every primitive instance whose node has a
 * skin or whose mesh has morph targets, its rest data in the mesh's own
 * space (positions, normals, tangents per scene vertex), its targets'
 * displacements (morph.c) and its joint influences (skin.c); pb_deform_pose
 * writes the posed world-space vertices into pb_scene from the morph weights
 * and the nodes' world matrices. The static load poses every instance once
 * with the file's own transforms and weights; pb_scene_set_time (anim.c)
 * poses again the instances that move (`dynamic`: an animated joint, an
 * animated mesh node, or morph weights driven by a "weights" channel), so
 * a static scene, or a static skinned one, pays nothing per frame.
 *
 * Per vertex, in double:
 *   p_m = p + sum_k w_k dP_k          (morph; normals and tangents alike,
 *   n_m = n + sum_k w_k dN_k           then renormalised)
 *   S   = sum_j v_j (W_j IBM_j)       (skin: influences j with normalised
 *                                      weights v_j; W_j the joint's world
 *                                      matrix, IBM_j its inverse bind matrix)
 *       = M, the node's world matrix, for an instance without a skin, and
 *         for a skinned vertex none of whose weights is positive (repair,
 *         skin.c: it stays with its mesh node)
 *   p'  = S p_m,  n' = normalize(cof(S) n_m),  t' = normalize(S t_m)
 * The skinned mesh node's own transform is ignored, as the specification
 * requires (3.7.3.1). */
#ifndef PB_SCENE_DEFORM_H
#define PB_SCENE_DEFORM_H

#include <stdint.h>

#include "scene/accessor.h"
#include "scene/gltf_doc.h"
#include "scene/scene.h"
#include "scene/xform.h"

typedef struct pb_skin {
  uint32_t joint_count;
  int32_t *joints;     /* node of each joint */
  mat4 *ibm;           /* inverse bind matrices (identities without the accessor) */
  mat4 *joint_mat;     /* W_j IBM_j of the pose being made (pb_skins_update) */
} pb_skin;

/* One skinned or morphed primitive instance: scene vertices
 * [first_vertex, +vertex_count), triangles [first_tri, +tri_count). Every
 * per-vertex array is indexed by scene vertex - first_vertex (for a
 * primitive without NORMAL the loader makes one vertex per triangle corner,
 * and each corner holds its source vertex's data). */
typedef struct pb_deform_range {
  int32_t node;        /* the mesh's node */
  int32_t skin;        /* into pb_deform.skins; -1: none */
  uint32_t first_vertex, vertex_count, first_tri, tri_count;
  int flat;            /* no NORMAL: normals are the posed face normals */
  float (*pos)[3];     /* rest position, mesh space */
  float (*nrm)[3];     /* rest normal; NULL when flat */
  float (*tan)[4];     /* rest TANGENT (normal-mapped with the file's
                          tangents only), else NULL */
  uint32_t target_count;
  float *dpos, *dnrm, *dtan; /* [target][vertex][3]; NULL when no target
                                has that attribute */
  uint32_t weights;    /* first of its target_count weights in
                          pb_deform.weights (its node's) */
  uint32_t influences; /* joint influences per vertex (4 per set) */
  uint16_t *joint;     /* [vertex][influence], into the skin's joints */
  float *weight;       /* [vertex][influence], normalised (sum 1) or all 0 */
  int dynamic;         /* posed again by pb_scene_set_time */
} pb_deform_range;

typedef struct pb_deform {
  pb_skin *skins;
  uint32_t skin_count;
  pb_deform_range *ranges;
  uint32_t range_count, range_cap;
  /* Morph weights of the nodes that draw a morphed mesh: node n's are
   * weights[node_weights[n]] .. + its mesh's target count; node_weights[n]
   * is UINT32_MAX for the others. The loader fills the file's (node.weights,
   * else mesh.weights, else 0); "weights" channels overwrite them. */
  float *weights;
  uint32_t weight_count;
  uint32_t *node_weights;
  uint32_t node_count;
  uint32_t skinned_vertices, morphed_vertices;  /* scene vertices, for info */
} pb_deform;

void pb_deform_destroy(pb_deform *d);

/* ---- loading (skin.c, morph.c; load.c calls them) ------------------------ */

/* Checks doc->skins and reads them into d->skins: joints (existing nodes,
 * each once), skeleton, inverse bind matrices (MAT4 float, at least one per
 * joint, finite). */
pb_result pb_skins_load(const char *path, const pb_gltf_doc *doc, pb_deform *d);

/* Reads the JOINTS_n / WEIGHTS_n sets of meshes[mesh].primitives[pi] for its
 * `count` vertices, checked and normalised as skin.c says (warnings through
 * pb_scene_warn on s): *joint and *weight are malloc'd [count][*influences]. */
pb_result pb_skin_read_influences(const char *path, const pb_gltf_doc *doc, pb_scene *s, int32_t mesh, size_t pi,
                                  const pb_skin *skin, uint64_t count, uint32_t *influences, uint16_t **joint,
                                  float **weight);

/* Checks every mesh's targets (the same count in all its primitives) and
 * the weights arrays (mesh.weights, node.weights: one per target, finite),
 * and gives each node that draws a morphed mesh its block of d->weights
 * (node.weights, else mesh.weights, else 0). */
pb_result pb_morph_weights_load(const char *path, const pb_gltf_doc *doc, pb_deform *d);

/* Reads the targets of meshes[mesh].primitives[pi] for its `count`
 * vertices: malloc'd [target][count][3] displacement arrays per attribute,
 * NULL where no target has it (NORMAL only when want_normal, TANGENT only
 * when want_tangent). Every target accessor is VEC3 float with POSITION's
 * count, every value finite. */
pb_result pb_morph_read_targets(const char *path, const pb_gltf_doc *doc, int32_t mesh, size_t pi, uint64_t count,
                                int want_normal, int want_tangent, float **dpos, float **dnrm, float **dtan);

/* A skinned or morphed primitive's data per source (accessor) vertex, read
 * by pb_deform_read; pb_deform_add_range then keeps it per scene vertex. */
typedef struct pb_deform_src {
  int32_t skin;        /* -1: morphed only */
  uint64_t count;      /* source vertices */
  float (*pos)[3], (*nrm)[3], (*tan)[4]; /* rest data; nrm, tan may be NULL */
  float *dpos, *dnrm, *dtan;             /* [target][source][3], NULL if none */
  uint32_t targets;
  uint32_t influences;
  uint16_t *joint;
  float *weight;
} pb_deform_src;

void pb_deform_src_free(pb_deform_src *D);

/* Reads meshes[mesh].primitives[pi]'s rest vertices (the checked spans
 * pos, nrm and tng; nrm NULL: no NORMAL, tng NULL: no TANGENT wanted), its
 * morph targets and, with skin >= 0, its joint influences (warnings on s). */
pb_result pb_deform_read(const char *path, const pb_gltf_doc *doc, pb_scene *s, const pb_deform *d, int32_t mesh,
                         size_t pi, int32_t skin, const pb_span *pos, const pb_span *nrm, const pb_span *tng,
                         pb_deform_src *out);

/* Whether most of a skinned source's vertices mirror in the rest pose (det
 * of the skin matrix < 0; after pb_skins_update with the rest worlds): the
 * loader then reverses the winding, as a mirroring node transform does. */
int pb_deform_src_mirrors(const pb_deform *d, const pb_deform_src *D, int32_t node, const mat4 *node_world);

/* Keeps D as a new range of node's instance: scene vertices [first, +count)
 * (src_of[i]: the source vertex of scene vertex first + i), triangles
 * [first_tri, +tri_count); flat: no NORMAL. *out: the range (NULL when count
 * is 0), owned by d. */
pb_result pb_deform_add_range(const char *path, pb_deform *d, const pb_deform_src *D, int32_t node,
                              const uint32_t *src_of, uint32_t first, uint32_t count, uint32_t first_tri,
                              uint32_t tri_count, int flat, pb_deform_range **out);

/* ---- posing ----------------------------------------------------------------- */

/* W_j IBM_j of every joint of every skin, from the nodes' world matrices. */
void pb_skins_update(pb_deform *d, const mat4 *world);

/* Poses range r (after pb_skins_update with the same `world`, per glTF
 * node): rewrites its positions and normals in s, and its tangents into
 * `tangents` where r->tan is set (world space, w = +-1). Returns
 * PB_ERR_SCENE_INVALID ("FILE: nodes[n]: ...") when a posed position leaves
 * float range; `t` is the time for the message (NAN: the static load). */
pb_result pb_deform_pose(pb_scene *s, const pb_deform *d, const pb_deform_range *r, const mat4 *world,
                         float (*tangents)[4], double t);

/* The morphed rest data of vertex i of r, mesh space (morph.c): position,
 * and normal and tangent direction where nrm / tan are not NULL (the
 * tangent's w is r->tan's). */
void pb_morph_vertex(const pb_deform *d, const pb_deform_range *r, uint32_t i, double pos[3], double nrm[3],
                     double tan[3]);

/* The skin matrix of vertex i of r (skin.c): sum_j v_j W_j IBM_j from the
 * last pb_skins_update; `node_world` when r has no skin or the vertex no
 * weight. */
void pb_skin_matrix(const pb_deform *d, const pb_deform_range *r, uint32_t i, const mat4 *node_world, mat4 *out);

#endif
