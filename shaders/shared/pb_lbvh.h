/* The photon LBVH and the gather (seed 000 sections 5-6): structs shared by
 * src/render/lbvh.c, src/render/gather.c, shaders/lbvh_*.comp and
 * shaders/gather.comp. Included after pb_gpu.h and pb_photon.h.
 *
 * The tree is Karras' (2012) binary radix tree over the photons sorted by
 * 30-bit Morton code (ties broken by sorted index): N - 1 inner nodes, node 0
 * the root, the photons (in sorted order) its leaves. Every inner node covers
 * the sorted interval first..last. Leaf merge (section 5.3, reversed as in
 * 6.2): a node whose count is <= T_auto, or whose photons all share one
 * Morton code, is collapsed into a leaf. A child reference with
 * PB_LBVH_LEAF set is a leaf: the index of its first sorted photon; the leaf
 * runs to the photon whose flags carry PB_PHOTON_LEAF_END (section 6.3). */
#ifndef PB_LBVH_SHARED_H
#define PB_LBVH_SHARED_H

PB_CONST(PB_LBVH_LEAF, 0x80000000u)
PB_CONST(PB_LBVH_NONE, 0xffffffffu)
/* Traversal stack: Karras depth is at most 30 code bits + 32 index bits. */
PB_CONST(PB_LBVH_STACK, 64)
/* Radix sort: 4 bits per pass, 8 passes over the 30-bit codes, tiles of
 * PB_GPU_WORKGROUP keys per workgroup. */
PB_CONST(PB_LBVH_RADIX_BITS, 4)
PB_CONST(PB_LBVH_RADIX, 16)
PB_CONST(PB_LBVH_SORT_PASSES, 8)
/* Boxes: nodes of at most this many photons (or count / 4096 where larger)
 * loop over their interval (lbvh_boxes), larger ones combine those
 * (lbvh_boxes_top). */
PB_CONST(PB_LBVH_BOX_INTERVAL, 1024u)
/* T_auto = clamp(round(footprint area sum / scene area), 1, PB_LBVH_MAX_LEAF) */
PB_CONST(PB_LBVH_MAX_LEAF, 256)
/* A fixed threshold (info.t_fixed) may go up to this (seed 000 Table 1's
 * sweep reaches 512). */
PB_CONST(PB_LBVH_MAX_FIXED_LEAF, 4096)

/* Inner node, 48 bytes. lo/hi: the union of the footprint boxes (exact
 * AABBs of the ellipsoids) below it. left/right: child references (an inner
 * node index, or PB_LBVH_LEAF | first sorted photon). first/last: sorted
 * photon interval. flags: bit 0 collapsed (a leaf by the merge). */
PB_STRUCT(pb_gpu_lbvh_node) {
  PB_VEC3(lo);
  uint left;
  PB_VEC3(hi);
  uint right;
  uint parent;           /* PB_LBVH_NONE at the root */
  uint first;
  uint last;
  uint flags;
} PB_END(pb_gpu_lbvh_node)
PB_CONST(PB_LBVH_NODE_COLLAPSED, 1u)

/* Build state and results, 96 bytes (one per map). The host writes count,
 * scene_area, tiles, root and the bound sentinels before each build. */
PB_STRUCT(pb_gpu_lbvh_info) {
  uint count;            /* photons in the map */
  uint root;             /* reference of the root (PB_LBVH_NONE: empty) */
  uint t_auto;           /* leaf-size threshold (written by lbvh_reduce) */
  uint leaves;           /* leaves after the merge (atomic count) */
  uint bmin[3];          /* position bounds as order-preserving uints */
  uint tiles;            /* sort tiles: ceil(count / PB_GPU_WORKGROUP) */
  uint bmax[3];
  uint area_tiles;       /* partial area sums written by lbvh_bounds */
  PB_VEC3(lo);           /* position bounds as floats (lbvh_reduce) */
  float area_sum;        /* sum of footprint ellipse areas, m^2 */
  PB_VEC3(hi);
  float scene_area;      /* sum of the scene's triangle areas, m^2 */
  uint stack_overflow;   /* gather: traversals cut short (should be 0) */
  float footprint_scale; /* host: factor on every footprint's axes and normal
                            extent for this build (progressive bandwidth;
                            lbvh_bounds, lbvh_reorder) */
  uint t_fixed;          /* host: leaf-size threshold to use instead of T_auto
                            (benchmark sweeps); 0: T_auto */
  uint t_computed;       /* T_auto as computed (lbvh_reduce), also when
                            t_fixed overrides it */
} PB_END(pb_gpu_lbvh_info)

/* Push constants of the LBVH passes. */
PB_STRUCT(pb_gpu_lbvh_push) {
  uint shift;            /* radix pass: first bit of the digit */
  uint src;              /* radix pass: offset of the source keys/values;
                            boxes passes: the interval bound B */
  uint dst;              /* radix pass: offset of the destination */
  uint count;            /* invocation bound of this dispatch */
} PB_END(pb_gpu_lbvh_push)

/* Gather output per pixel of the band, sums over samples, 32 bytes.
 * indirect.w: photons that contributed (for k_PD); caustic.w: unused. */
PB_STRUCT(pb_gpu_photon_accum) {
  PB_VEC4(indirect);
  PB_VEC4(caustic);
} PB_END(pb_gpu_photon_accum)

/* Only in scenes with normal maps (a buffer of its own, so other scenes
 * move 32 bytes per pixel, not 80), per pixel, sums over samples, for seed
 * 001's shading-normal correction (24.4.3, eq. 20;
 * src/render/shading_correction.c): dir.xyz: sum of w_i wi over the
 * non-caustic photons gathered, w_i the kernel weight times the luminance
 * of the photon's power ("an additional blending target"), dir.w: sum of
 * w_i; geo.xyz: sum of the gather surface's geometric normal (facing the
 * eye); ns.xyz: sum of its normal-mapped shading normal n_s; ns.w: samples
 * whose gather surface has a normal-mapped material; geo.w: unused. */
PB_STRUCT(pb_gpu_photon_nmap) {
  PB_VEC4(dir);
  PB_VEC4(geo);
  PB_VEC4(ns);
} PB_END(pb_gpu_photon_nmap)

PB_CONST(PB_GATHER_CONSTANT_KERNEL, 1u) /* box kernel instead of Epanechnikov */
PB_CONST(PB_GATHER_NO_BEAUTY, 2u)       /* do not add into accum.beauty */
PB_STRUCT(pb_gpu_gather_push) {
  uint sample_index;
  uint flags;            /* PB_GATHER_* */
  uint pad0;
  uint pad1;
} PB_END(pb_gpu_gather_push)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_lbvh_node) == 48, "pb_gpu_lbvh_node size");
_Static_assert(offsetof(pb_gpu_lbvh_node, left) == 12, "pb_gpu_lbvh_node.left");
_Static_assert(offsetof(pb_gpu_lbvh_node, hi) == 16, "pb_gpu_lbvh_node.hi");
_Static_assert(offsetof(pb_gpu_lbvh_node, right) == 28, "pb_gpu_lbvh_node.right");
_Static_assert(offsetof(pb_gpu_lbvh_node, flags) == 44, "pb_gpu_lbvh_node.flags");
_Static_assert(sizeof(pb_gpu_lbvh_info) == 96, "pb_gpu_lbvh_info size");
_Static_assert(offsetof(pb_gpu_lbvh_info, bmin) == 16, "pb_gpu_lbvh_info.bmin");
_Static_assert(offsetof(pb_gpu_lbvh_info, tiles) == 28, "pb_gpu_lbvh_info.tiles");
_Static_assert(offsetof(pb_gpu_lbvh_info, bmax) == 32, "pb_gpu_lbvh_info.bmax");
_Static_assert(offsetof(pb_gpu_lbvh_info, lo) == 48, "pb_gpu_lbvh_info.lo");
_Static_assert(offsetof(pb_gpu_lbvh_info, area_sum) == 60, "pb_gpu_lbvh_info.area_sum");
_Static_assert(offsetof(pb_gpu_lbvh_info, hi) == 64, "pb_gpu_lbvh_info.hi");
_Static_assert(offsetof(pb_gpu_lbvh_info, stack_overflow) == 80, "pb_gpu_lbvh_info.stack_overflow");
_Static_assert(offsetof(pb_gpu_lbvh_info, footprint_scale) == 84, "pb_gpu_lbvh_info.footprint_scale");
_Static_assert(sizeof(pb_gpu_lbvh_push) == 16, "pb_gpu_lbvh_push size");
_Static_assert(sizeof(pb_gpu_photon_accum) == 32, "pb_gpu_photon_accum size");
_Static_assert(sizeof(pb_gpu_photon_nmap) == 48, "pb_gpu_photon_nmap size");
_Static_assert(sizeof(pb_gpu_gather_push) == 16, "pb_gpu_gather_push size");
#endif

#endif
