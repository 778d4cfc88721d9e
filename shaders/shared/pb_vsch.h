/* The view-sample cluster hierarchy estimator (seed 004, Moreau et al. 2016;
 * src/render/estimate/estimator_vsch.c, shaders/vsch_*.comp): constants, the push
 * constants and the layout of its one data buffer. Included after pb_gpu.h.
 *
 * The hierarchy (seed 004 4.1, after Sintorn et al. 2014), rebuilt over the
 * G-buffer samples of every sample pass:
 *   level 0  clusters: the cells of a view-space 3-D grid, a screen tile of
 *            PB_VSCH_TILE x PB_VSCH_TILE pixels times one of PB_VSCH_SLICES
 *            depth slices (log-spaced in the distance from the camera, as
 *            close to cubical as the band's depth range allows); stored
 *            compact, only the occupied ones (the paper's "compact list" of
 *            the final level);
 *   level 1  the screen tiles (dense): a 32-bit occupancy mask over the 32
 *            depth slices, the index of the tile's first cluster;
 *   level L  (2 .. PB_VSCH_LEVELS) dense nodes of 8 x 4 nodes of level
 *            L - 1, a 32-bit occupancy mask over them.
 * Every node has a view-space box and a normal cone (seed 004 4.5)
 * propagated up. All of it lives in one uint buffer, `vd` below, at the word
 * offsets of the push constants. */
#ifndef PB_VSCH_SHARED_H
#define PB_VSCH_SHARED_H

PB_CONST(PB_VSCH_TILE, 8)     /* cluster tile edge, pixels */
PB_CONST(PB_VSCH_SLICES, 32)  /* depth slices per tile (one mask word) */
PB_CONST(PB_VSCH_BRANCH_X, 8) /* children of an inner node: 8 x 4 */
PB_CONST(PB_VSCH_BRANCH_Y, 4)
PB_CONST(PB_VSCH_LEVELS, 7)   /* levels above the clusters (1: tiles) */
PB_CONST(PB_VSCH_NONE, 0xffffffffu)
/* Fixed-point flux sums (trivially accepted photons, directional buckets):
 * 64-bit unsigned, two words (low, high), in units of emax / 2^20 where
 * emax is the largest photon irradiance max_c Phi_c / (pi r^2) of the map.
 * Integer sums do not depend on the order of the atomics: the estimate is
 * the same bit for bit from run to run. */
PB_CONST(PB_VSCH_FIXED_ONE, 1048576u)

/* Words of one node record (every level; global node id g at
 * node_off + g * PB_VSCH_NODE_WORDS):
 *  0-2   box lo (view space, order-preserving uints: atomics)
 *  3-5   box hi
 *  6     occupancy mask of the children (clusters: 0)
 *  7     view samples below
 *  8-10  normal-cone axis: clusters the integer sum of their samples'
 *        normals times 2^16 (atomics); other levels the unit axis as floats
 *  11    normal-cone half-angle alpha, radians (float bits)
 *  12-13 the node's photon list: first and end in the sorted pairs
 *  14    tiles: the global id of the first cluster of the tile
 *  15    the smallest in-plane distance from a sample below to an edge of
 *        its face where a wall stands (common/kernel_edges.glsl; float
 *        bits, non-negative, so uint order is float order: atomicMin;
 *        +inf: no edge within reach of any) */
PB_CONST(PB_VSCH_NODE_WORDS, 16)
/* Trivially accepted flux per node (seed 004 4.6), fixed point (two words
 * each): E_r, E_g, E_b; sum of lum(E) (wi + 1) / 2 (x, y, z); sum lum(E). */
PB_CONST(PB_VSCH_TRIVIAL_WORDS, 14)
/* Directional buckets per node (seed 004 4.7): 8 octants x RGB, fixed
 * point. */
PB_CONST(PB_VSCH_DIR_WORDS, 48)
/* Words per pixel: 0 cluster (global id, PB_VSCH_NONE: no sample), 1 tile
 * index * 32 + slice, 2-4 geometric normal (floats, facing the eye), 5-7
 * view-space position, 8-10 directional irradiance, 11-13 the factor that
 * turns it into radiance (f times the specular chain's throughput), 14 the
 * in-plane distance to the nearest edge of the sample's face (float bits,
 * +inf: none within reach), 15 unused. */
PB_CONST(PB_VSCH_PIXEL_WORDS, 16)

/* Header words (vd[0 ..]). */
PB_CONST(PB_VSCH_H_NEAR, 0)      /* nearest sample distance (ordered uint) */
PB_CONST(PB_VSCH_H_FAR, 1)       /* farthest */
PB_CONST(PB_VSCH_H_EMAX, 2)      /* largest photon irradiance (float bits) */
PB_CONST(PB_VSCH_H_RMAX, 3)      /* largest photon radius (float bits): the edges'
                                    reach is twice it (vsch_leaf) */
PB_CONST(PB_VSCH_H_LEAVES, 4)    /* occupied clusters */
PB_CONST(PB_VSCH_H_PAIRS, 5)     /* (node, photon) pairs written (sort count) */
PB_CONST(PB_VSCH_H_ARGS, 6)      /* 6-8: indirect dispatch over the pairs */
PB_CONST(PB_VSCH_H_PAIR_OVERFLOW, 9) /* pairs dropped: the list was full */
PB_CONST(PB_VSCH_H_REJECTED, 11) /* node visits rejected by the normal cone */
PB_CONST(PB_VSCH_H_TRIVIAL, 12)  /* photon-node flux additions (4.6) */
PB_CONST(PB_VSCH_H_LISTED, 13)   /* pairs wanted (before the cap) */
PB_CONST(PB_VSCH_H_DIRECTIONAL, 14) /* bucket additions (4.7) */
PB_CONST(PB_VSCH_H_PHOTONS, 15)  /* photons traversed */
PB_CONST(PB_VSCH_H_NX, 16)       /* 16-23: nodes along x of level L (1..7) */
PB_CONST(PB_VSCH_H_NY, 24)       /* 24-31: along y */
PB_CONST(PB_VSCH_HEADER_WORDS, 64)

/* flags */
PB_CONST(PB_VSCH_DIRECTIONAL, 1u) /* seed 004 4.7: octant buckets, blur */
PB_CONST(PB_VSCH_NO_BEAUTY, 2u)   /* = PB_GATHER_NO_BEAUTY */
PB_CONST(PB_VSCH_NO_TRIVIAL, 4u)  /* ablation: no cluster-trivial acceptance */
PB_CONST(PB_VSCH_NO_CONE, 8u)     /* ablation: no normal-cone rejection */
PB_CONST(PB_VSCH_NO_EDGES, 16u)   /* no edge tests (--no-edge-correction) */

/* Push constants of every vsch kernel, 112 bytes (within the 128 every device has). */
PB_STRUCT(pb_gpu_vsch_push) {
  uint sample_index;
  uint flags;
  uint level;            /* vsch_up: the level built; vsch_scan: 0 tiles, 1 photons */
  uint pixels;           /* pixels of the band (the pixel dispatch size) */
  uint node_off;         /* word offsets in vd */
  uint triv_off;
  uint dir_off;          /* 0: no buckets (not directional) */
  uint pixel_off;
  uint photon_off;       /* per photon: insertions, then their exclusive prefix */
  uint nodes;            /* node records (the clear's dispatch size) */
  uint capacity;         /* photon records of the map (the photon dispatch size) */
  uint pair_cap;         /* pairs the sort holds */
  uint level_base[8];    /* global id of the first node of level L (0: the clusters) */
  float radius;          /* photon radius, m; 0: each photon's footprint radius */
  float footprint_scale; /* the iteration's bandwidth (radius 0 only) */
  uint host_count;       /* photons of a map without a counts buffer */
  uint count_from_map;   /* 1: min(counts.stored, capacity) */
  uint sorted;           /* first sorted element of the sort's buffers */
  uint max_groups_x;     /* maxComputeWorkGroupCount[0] */
  uint pad0, pad1;
} PB_END(pb_gpu_vsch_push)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_vsch_push) == 112, "pb_gpu_vsch_push size");
_Static_assert(offsetof(pb_gpu_vsch_push, level_base) == 48, "pb_gpu_vsch_push.level_base");
_Static_assert(offsetof(pb_gpu_vsch_push, radius) == 80, "pb_gpu_vsch_push.radius");
#endif

#endif
