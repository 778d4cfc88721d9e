/* Screen-space photon splatting (seed 001 section 24.3, eq. 2-9; the
 * estimator "splat", src/render/estimate/estimator_splat.c): the push constants of
 * its three passes, the per-pixel splat target and its statistics.
 * Included after pb_gpu.h (PB_STRUCT / PB_VEC3 / PB_CONST).
 *
 * Passes, per sample (after the G-buffer pass of that sample):
 *   splat_count.comp    one thread per stored photon: camera-frustum and
 *                       facing culling (24.2.1), the per-tile photon count
 *                       n_p (atomics);
 *   splat_splat.comp    one thread per photon: the kernel of eq. 2-8, its
 *                       screen rectangle, the depth test against the
 *                       G-buffer and eq. 9 added (float adds by
 *                       compare-and-swap) into the pixel's splat target;
 *   splat_resolve.comp  one thread per pixel: the splatted irradiance times
 *                       the BSDF at the power-weighted mean direction
 *                       (24.3: "the product of the photon's irradiance and
 *                       the surface's BRDF using a mean incoming direction")
 *                       added into pb_gpu_photon_accum; clears the target
 *                       and the tile counts for the next sample. */
#ifndef PB_SPLAT_SHARED_H
#define PB_SPLAT_SHARED_H

/* The splat target of one pixel: PB_SPLAT_PIXEL_WORDS uints (floats as
 * bits, added by compare-and-swap): irradiance E = sum Phi / a of the
 * non-caustic photons (rgb, W m^-2), of the caustic ones (rgb), the
 * power-weighted incoming direction (xyz: sum w wi, then sum w; w = lum(Phi)
 * / a), and the number of kernels that covered the pixel (a plain uint). */
PB_CONST(PB_SPLAT_PIXEL_WORDS, 12u)
PB_CONST(PB_SPLAT_W_IND, 0u)
PB_CONST(PB_SPLAT_W_CAU, 3u)
PB_CONST(PB_SPLAT_W_DIR, 6u)
PB_CONST(PB_SPLAT_W_WSUM, 9u)
PB_CONST(PB_SPLAT_W_HITS, 10u)

PB_CONST(PB_SPLAT_USE_COUNTS, 4u) /* flags: the stored count from the map's
                                     pb_gpu_photon_counts (else push.stored);
                                     bits 0-1 are PB_GATHER_* */
PB_CONST(PB_SPLAT_STATS, 8u)      /* flags: count pb_gpu_splat_stats (the
                                     first sample after a map is bound) */

/* Push constants of the three passes, 64 bytes. */
PB_STRUCT(pb_gpu_splat_push) {
  uint sample_index;
  uint flags;            /* PB_GATHER_NO_BEAUTY, PB_SPLAT_USE_COUNTS */
  uint stored;           /* photons of a map without counts buffer */
  uint capacity;         /* photons the map's buffer holds */
  uint tile;             /* tile edge t_x = t_y, pixels (eq. 3) */
  uint tiles_x;          /* tiles per image row */
  uint tiles_y;
  uint tiles;            /* tiles_x tiles_y (the resolve clears them) */
  float l_max;           /* eq. 2's l_max, m */
  float n_tile;          /* eq. 6's n_tile: photons expected per point */
  float s_max;           /* eq. 7's s_max */
  float s_n;             /* the kernel's compression along the normal */
  float r_min;           /* eq. 6's clamp of the kernel radius, m */
  float r_max;
  float footprint_scale; /* progressive bandwidth of this map (1: none) */
  uint max_extent;       /* a kernel's screen rectangle is clipped to this
                            many pixels per side around the photon */
} PB_END(pb_gpu_splat_push)

/* Statistics of the first sample of the last map (atomics, PB_SPLAT_STATS;
 * zeroed by the host when a map is bound), 32 bytes. */
PB_STRUCT(pb_gpu_splat_stats) {
  uint stored;           /* photons read */
  uint back_facing;      /* culled: normal away from the camera */
  uint outside;          /* culled: behind the near plane / past the far one */
  uint off_screen;       /* in front, centre outside the image (splatted,
                            not counted in a tile: expanded frustum) */
  uint counted;          /* photons in some tile (sum of n_p) */
  uint tested;           /* kernel-pixel pairs tested against the G-buffer */
  uint splatted;         /* pairs that passed and were added */
  uint clipped;          /* kernels whose rectangle max_extent clipped */
} PB_END(pb_gpu_splat_stats)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_splat_push) == 64, "pb_gpu_splat_push size");
_Static_assert(offsetof(pb_gpu_splat_push, tile) == 16, "pb_gpu_splat_push.tile");
_Static_assert(offsetof(pb_gpu_splat_push, l_max) == 32, "pb_gpu_splat_push.l_max");
_Static_assert(offsetof(pb_gpu_splat_push, r_min) == 48, "pb_gpu_splat_push.r_min");
_Static_assert(offsetof(pb_gpu_splat_push, max_extent) == 60, "pb_gpu_splat_push.max_extent");
_Static_assert(sizeof(pb_gpu_splat_stats) == 32, "pb_gpu_splat_stats size");
_Static_assert(offsetof(pb_gpu_splat_stats, tested) == 20, "pb_gpu_splat_stats.tested");
#endif

#endif
