/* The scene BVH for GPU traversal: built on the CPU with Embree's
 * rtcBuildBVH (binned SAH, PB_BVH_WIDTH-wide, at most PB_BVH_MAX_LEAF triangles per
 * leaf) and flattened into the layout of shaders/shared/pb_gpu.h: node 0 is
 * the root, an inner node's PB_BVH_WIDTH child slots are adjacent (unused
 * ones empty), leaves own a contiguous
 * range of the BVH-ordered triangle array, every node's box is exactly the
 * union of its children's (leaves: of their triangles' vertices). */
#ifndef PB_RENDER_SCENE_BVH_H
#define PB_RENDER_SCENE_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"
#include "scene/scene.h"
#include "shared/pb_gpu.h"

typedef struct pb_bvh {
  pb_gpu_bvh_node *nodes;
  uint32_t node_count;     /* empty child slots included */
  pb_gpu_tri *tris;        /* BVH order; tris[i].prim is the scene index */
  uint32_t tri_count;      /* triangles with finite vertices (all, normally) */
  uint32_t leaf_count;
  uint32_t depth;          /* levels, root = 1 */
  double build_s;
} pb_bvh;

/* Builds the BVH of every triangle of `s` whose vertices are finite.
 * Errors: PB_ERR_SCENE_EMPTY (no triangles), PB_ERR_SCENE_INVALID (index out
 * of range), PB_ERR_LIMIT (tree deeper than PB_BVH_MAX_DEPTH, the traversal
 * stack), PB_ERR_NOMEM, PB_ERR_INTERNAL (Embree). */
pb_result pb_bvh_build(const pb_scene *s, pb_bvh *out);
void pb_bvh_destroy(pb_bvh *b);

/* Refits `b` to the current vertex positions of `s` (the scene it was built
 * from, posed again: same triangles, pb_scene_set_time): the triangle copies
 * in b->tris are refreshed and every box is recomputed bottom-up (children
 * sit after their parent, so one reverse sweep). The topology is kept, so a
 * refitted tree loses quality as objects move apart (see pb_bvh_sah_cost).
 * PB_ERR_SCENE_INVALID when a vertex index is out of range or a triangle in
 * the tree is no longer finite (rebuild instead); b is unchanged then. */
pb_result pb_bvh_refit(const pb_scene *s, pb_bvh *b);

/* Surface-area heuristic cost of the tree, in m^2, not divided by the root's
 * area: sum over inner nodes of area(box) + sum over leaves of area(box) x
 * triangles. Compare a tree with its refits: when the scene spreads out (the
 * root grows), the root-normalised cost of a stale refit can even fall while
 * its rays slow down 1.5x (bench/README.md, spot_room_debris); this one
 * follows the slowdown. */
double pb_bvh_sah_cost(const pb_bvh *b);

/* Structural check: every node reached exactly once from the root (empty
 * child slots: never entered, zero box), no inner node with fewer than two
 * children or a repeated child, leaves of 1..PB_BVH_MAX_LEAF
 * triangles, each parent box equal to the union of its children's, each leaf
 * box equal to its triangles' bounds, every triangle in exactly one leaf,
 * depth within PB_BVH_MAX_DEPTH. Returns 1 when sound; otherwise 0 with the
 * first problem in `why`. */
int pb_bvh_check(const pb_bvh *b, char *why, size_t why_size);

#endif
