/* The photon LBVH and the gather (seed 000 sections 5-6): structs shared by
 * src/render/photon/lbvh.c, lbvh_sort.c, gather.c, shaders/lbvh_*.comp and
 * shaders/gather.comp. Included after pb_gpu.h and pb_photon.h.
 *
 * The tree is the binary radix tree (Karras 2012) over the photons sorted by
 * 30-bit Morton code, ties broken by sorted index, built bottom-up in one
 * pass (Apetrei 2014): inner node p is the split between sorted photons p
 * and p + 1 (0 <= p <= count - 2). Leaf merge (seed 000 5.3, reversed as in
 * 6.2): a subtree of at most T_auto photons, or whose photons all share one
 * Morton code, is one leaf. A node stores its two children, each with its
 * box, its reference and its photon count (seed 000 6.3 keeps the child
 * boxes with the inner node): the reference is an inner node index, or
 * PB_LBVH_LEAF | the first sorted photon of a leaf of `count` photons. When
 * the whole map is one leaf, node count - 1 holds it as child 0 (child 1
 * empty) and is the root. */
#ifndef PB_LBVH_SHARED_H
#define PB_LBVH_SHARED_H

PB_CONST(PB_LBVH_LEAF, 0x80000000u)
PB_CONST(PB_LBVH_NONE, 0xffffffffu)
/* Traversal stack: one entry per level, and the tree is at most 30 code bits
 * + 32 index bits deep. */
PB_CONST(PB_LBVH_STACK, 64)
/* Photons per invocation of lbvh_bounds (a tile of 64 x 16). */
PB_CONST(PB_LBVH_BOUNDS_PPT, 16)
PB_CONST(PB_LBVH_BOUNDS_TILE, 1024)
/* T_auto: the leaf-size threshold of least modelled traversal cost for
 * k = footprint area sum / scene area, in [1, PB_LBVH_MAX_LEAF] (lbvh_bounds.comp) */
PB_CONST(PB_LBVH_MAX_LEAF, 256)
/* A fixed threshold (push.t_fixed) may go up to this (seed 000 Table 1's
 * sweep reaches 512). */
PB_CONST(PB_LBVH_MAX_FIXED_LEAF, 4096)
/* The Morton codes' bits (10 per axis): the radix sort's key width. */
PB_CONST(PB_LBVH_MORTON_BITS, 30)

/* One child of an inner node, 32 bytes. lo/hi: the union of the exact AABBs
 * of the footprint ellipsoids below it (an empty child: lo = +inf, hi =
 * -inf, count 0). */
PB_STRUCT(pb_gpu_lbvh_child) {
  PB_VEC3(lo);
  uint ref;              /* inner node index, or PB_LBVH_LEAF | first photon */
  PB_VEC3(hi);
  uint count;            /* photons below (a leaf's size) */
} PB_END(pb_gpu_lbvh_child)

/* Inner node, 64 bytes (one cache line of most GPUs and CPUs). */
PB_STRUCT(pb_gpu_lbvh_node) {
  pb_gpu_lbvh_child child[2];
} PB_END(pb_gpu_lbvh_node)

/* Build state and results, 128 bytes (one per map), written by lbvh_setup
 * from the push constants at the start of every build: nothing is uploaded
 * or read back between the passes. */
PB_STRUCT(pb_gpu_lbvh_info) {
  uint count;            /* photons in the map (min of the stored count and the capacity) */
  uint root;             /* the root node (PB_LBVH_NONE: empty map) */
  uint t_auto;           /* leaf-size threshold in use (lbvh_bounds) */
  uint leaves;           /* leaves after the merge (atomic count, lbvh_climb) */
  uint bmin[3];          /* position bounds as order-preserving uints (atomics) */
  uint tiles;            /* lbvh_bounds tiles: ceil(count / PB_LBVH_BOUNDS_TILE) */
  uint bmax[3];
  uint tiles_done;       /* lbvh_bounds workgroups finished (the last one reduces) */
  PB_VEC3(lo);           /* position bounds as floats (the Morton codes' box) */
  float area_sum;        /* sum of the scaled footprint ellipse areas, m^2 */
  PB_VEC3(hi);
  float scene_area;      /* sum of the scene's triangle areas, m^2 (push) */
  uint stack_overflow;   /* gather: traversals cut short (should be 0) */
  float footprint_scale; /* factor on every footprint's axes and normal extent
                            for this build (progressive bandwidth; push) */
  uint t_fixed;          /* leaf-size threshold to use instead of T_auto
                            (benchmark sweeps; push); 0: T_auto */
  uint t_computed;       /* T_auto as computed, also when t_fixed overrides it */
  uint photon_args[4];   /* VkDispatchIndirectCommand: one invocation per photon */
  uint tile_args[4];     /* one workgroup per lbvh_bounds tile */
} PB_END(pb_gpu_lbvh_info)

/* Push constants of the LBVH passes (lbvh_setup reads the host's values,
 * the others only `sorted`). */
PB_CONST(PB_LBVH_COUNT_FROM_MAP, 1u) /* flags: the count is the map's pb_gpu_photon_counts.stored */
PB_STRUCT(pb_gpu_lbvh_push) {
  uint capacity;         /* photons the buffers hold */
  uint host_count;       /* the count without PB_LBVH_COUNT_FROM_MAP (maps made by the host) */
  uint flags;
  uint max_groups_x;     /* maxComputeWorkGroupCount[0] (grids fold into y) */
  float scene_area;
  float footprint_scale;
  uint t_fixed;
  uint sorted;           /* offset of the sorted keys/values in the sort's buffers */
} PB_END(pb_gpu_lbvh_push)

/* ---- GPU radix sort (src/render/photon/lbvh_sort.c, shaders/lbvh_sort_*.comp) ----
 * LSD radix sort of 32-bit keys with 32-bit values, one pass per digit,
 * reduce-then-scan (Merrill & Grimshaw 2011, "High performance and scalable
 * radix sorting", section 4): per pass an upsweep counts each tile's
 * digits, a spine scans the counts digit-major, a downsweep ranks every key
 * within its tile (stable) and scatters it (on CPU devices one invocation
 * counts and ranks a whole tile in order, see lbvh_sort.c). No pass waits on
 * another workgroup (no decoupled look-back, so no forward-progress
 * assumption); the key count is read on the GPU and every pass is dispatched
 * indirectly. Digits: PB_SORT_RADIX_BITS wide on the workgroup paths (their
 * shared arrays), PB_SORT_SERIAL_BITS by default on the serial path (8..
 * PB_SORT_MAX_RADIX_BITS for benchmarks; the default is derived from
 * lavapipe's measured per-pass cost in lbvh_sort.c); every pass but the
 * last takes the full width, the last the key bits left. */
PB_CONST(PB_SORT_RADIX_BITS, 8)
PB_CONST(PB_SORT_RADIX, 256)
PB_CONST(PB_SORT_SERIAL_BITS, 8)
PB_CONST(PB_SORT_MIN_RADIX_BITS, 8)
PB_CONST(PB_SORT_MAX_RADIX_BITS, 11)
PB_CONST(PB_SORT_MAX_RADIX, 2048)
/* ceil(32 / PB_SORT_MIN_RADIX_BITS) */
PB_CONST(PB_SORT_MAX_PASSES, 4)
/* Keys per invocation of the up- and downsweep; a tile is the
 * PB_GPU_WORKGROUP x PB_SORT_KPT keys of one workgroup. */
PB_CONST(PB_SORT_KPT, 16)
PB_CONST(PB_SORT_TILE, 1024)
/* The serial variant's tile: one invocation's keys (4x fewer tiles, so 4x
 * less histogram and spine per key, for a loop that stays far below
 * llvmpipe's 65535 iterations per invocation). */
PB_CONST(PB_SORT_SERIAL_TILE, 4096)
/* The spine gives each workgroup whole digits and at least this many tile
 * counts, so that small sorts run on one workgroup and large ones on 256. */
PB_CONST(PB_SORT_SPINE_MIN, 4096)

/* Sort state, written by lbvh_sort_setup for every sort. */
PB_STRUCT(pb_gpu_sort_state) {
  uint count;            /* keys to sort (min of the source word and the capacity) */
  uint tiles;            /* ceil(count / tile), tile = push.tile */
  uint spine_digits;     /* digits per spine workgroup (power of two, <= PB_SORT_RADIX) */
  uint pad0;
  uint tile_args[4];     /* VkDispatchIndirectCommand of the up/downsweeps (x, y, z), pad:
                            a workgroup per tile */
  uint serial_args[4];   /* the serial variant's: an invocation per tile */
  uint spine_args[4];    /* of the spine */
  uint totals[PB_SORT_MAX_PASSES * PB_SORT_MAX_RADIX]; /* keys per digit and pass (atomics),
                                                          row pass * PB_SORT_MAX_RADIX */
} PB_END(pb_gpu_sort_state)

/* Push constants of the sort passes. */
PB_STRUCT(pb_gpu_sort_push) {
  uint shift;            /* first bit of this pass's digit */
  uint src;              /* offset of the source keys/values (0 or capacity) */
  uint dst;              /* offset of the destination */
  uint pass;             /* pass index (totals row) */
  uint count_word;       /* setup: index of the key count in the count buffer */
  uint capacity;         /* setup: keys the buffers hold */
  uint max_groups_x;     /* setup: maxComputeWorkGroupCount[0] (grids fold into y) */
  uint tile;             /* setup: keys per tile (PB_SORT_TILE or PB_SORT_SERIAL_TILE) */
  uint bits;             /* this pass's digit width (setup: the widest pass's) */
  uint pad[3];
} PB_END(pb_gpu_sort_push)

/* Gather output per pixel of the band, sums over samples, 32 bytes.
 * indirect.w: photons that contributed (for k_PD); caustic.w: unused. */
PB_STRUCT(pb_gpu_photon_accum) {
  PB_VEC4(indirect);
  PB_VEC4(caustic);
} PB_END(pb_gpu_photon_accum)

/* Only in scenes with normal maps (a buffer of its own, so other scenes
 * move 32 bytes per pixel, not 80), per pixel, sums over samples, for seed
 * 001's shading-normal correction (24.4.3, eq. 20;
 * src/render/estimate/shading_correction.c): dir.xyz: sum of w_i wi over the
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
/* gather_upsample (gather.comp with -DPB_UPSAMPLE=1; shared/pb_upsample.h):
 * UPS_LIST: the diffuse irradiance of the non-caustic photons at the pixels
 * of the list (level `level`), into the irradiance buffer; UPS_REST: at
 * every pixel, what is not up-sampled (glossy lobes; caustic photons where
 * UPS_CAUSTICS says the map has some; all of a Blender material's closures),
 * into the photon accumulators; pixels with none of it skip the traversal. */
PB_CONST(PB_GATHER_UPS_LIST, 4u)
PB_CONST(PB_GATHER_UPS_REST, 8u)
PB_CONST(PB_GATHER_UPS_CAUSTICS, 16u)
PB_STRUCT(pb_gpu_gather_push) {
  uint sample_index;
  uint flags;            /* PB_GATHER_* */
  float edge_reach;      /* largest footprint radius, m: the kernel's edge
                            renormalisation looks this far (gather.comp); 0: off */
  uint level;            /* PB_GATHER_UPS_LIST: the up-sampling level */
} PB_END(pb_gpu_gather_push)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_lbvh_child) == 32, "pb_gpu_lbvh_child size");
_Static_assert(offsetof(pb_gpu_lbvh_child, ref) == 12, "pb_gpu_lbvh_child.ref");
_Static_assert(offsetof(pb_gpu_lbvh_child, hi) == 16, "pb_gpu_lbvh_child.hi");
_Static_assert(offsetof(pb_gpu_lbvh_child, count) == 28, "pb_gpu_lbvh_child.count");
_Static_assert(sizeof(pb_gpu_lbvh_node) == 64, "pb_gpu_lbvh_node size");
_Static_assert(sizeof(pb_gpu_lbvh_info) == 128, "pb_gpu_lbvh_info size");
_Static_assert(offsetof(pb_gpu_lbvh_info, bmin) == 16, "pb_gpu_lbvh_info.bmin");
_Static_assert(offsetof(pb_gpu_lbvh_info, tiles) == 28, "pb_gpu_lbvh_info.tiles");
_Static_assert(offsetof(pb_gpu_lbvh_info, bmax) == 32, "pb_gpu_lbvh_info.bmax");
_Static_assert(offsetof(pb_gpu_lbvh_info, lo) == 48, "pb_gpu_lbvh_info.lo");
_Static_assert(offsetof(pb_gpu_lbvh_info, area_sum) == 60, "pb_gpu_lbvh_info.area_sum");
_Static_assert(offsetof(pb_gpu_lbvh_info, hi) == 64, "pb_gpu_lbvh_info.hi");
_Static_assert(offsetof(pb_gpu_lbvh_info, stack_overflow) == 80, "pb_gpu_lbvh_info.stack_overflow");
_Static_assert(offsetof(pb_gpu_lbvh_info, footprint_scale) == 84, "pb_gpu_lbvh_info.footprint_scale");
_Static_assert(offsetof(pb_gpu_lbvh_info, photon_args) == 96, "pb_gpu_lbvh_info.photon_args");
_Static_assert(offsetof(pb_gpu_lbvh_info, tile_args) == 112, "pb_gpu_lbvh_info.tile_args");
_Static_assert(sizeof(pb_gpu_lbvh_push) == 32, "pb_gpu_lbvh_push size");
_Static_assert(PB_LBVH_BOUNDS_TILE == PB_GPU_WORKGROUP * PB_LBVH_BOUNDS_PPT, "bounds tile");
_Static_assert(sizeof(pb_gpu_sort_state) == 64 + 4 * PB_SORT_MAX_PASSES * PB_SORT_MAX_RADIX, "pb_gpu_sort_state size");
_Static_assert(offsetof(pb_gpu_sort_state, tile_args) == 16, "pb_gpu_sort_state.tile_args");
_Static_assert(offsetof(pb_gpu_sort_state, serial_args) == 32, "pb_gpu_sort_state.serial_args");
_Static_assert(offsetof(pb_gpu_sort_state, spine_args) == 48, "pb_gpu_sort_state.spine_args");
_Static_assert(offsetof(pb_gpu_sort_state, totals) == 64, "pb_gpu_sort_state.totals");
_Static_assert(sizeof(pb_gpu_sort_push) == 48, "pb_gpu_sort_push size");
_Static_assert(offsetof(pb_gpu_sort_push, bits) == 32, "pb_gpu_sort_push.bits");
_Static_assert(PB_SORT_RADIX == 1 << PB_SORT_RADIX_BITS, "sort radix");
_Static_assert(PB_SORT_MAX_RADIX == 1 << PB_SORT_MAX_RADIX_BITS, "sort max radix");
_Static_assert((int)PB_SORT_MAX_PASSES * (int)PB_SORT_MIN_RADIX_BITS >= 32, "sort passes");
_Static_assert((int)PB_SORT_SERIAL_BITS >= (int)PB_SORT_MIN_RADIX_BITS &&
                   (int)PB_SORT_SERIAL_BITS <= (int)PB_SORT_MAX_RADIX_BITS,
               "serial digit");
_Static_assert(PB_SORT_TILE == PB_GPU_WORKGROUP * PB_SORT_KPT, "sort tile");
_Static_assert(sizeof(pb_gpu_photon_accum) == 32, "pb_gpu_photon_accum size");
_Static_assert(sizeof(pb_gpu_photon_nmap) == 48, "pb_gpu_photon_nmap size");
_Static_assert(sizeof(pb_gpu_gather_push) == 16, "pb_gpu_gather_push size");
#endif

#endif
