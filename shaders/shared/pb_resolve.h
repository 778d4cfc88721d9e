/* The resolve pass (shaders/frame/resolve.comp, src/render/frame/resolve.c): the
 * accumulators of a band (sums over samples) turned into the AOVs that leave
 * the GPU, on the GPU, in one buffer of planes: plane P of a band of
 * `pixels` pixels starts at float PB_RESOLVE_P * pixels and holds its
 * channels pixel after pixel (the layout of pb_render_result's arrays), so
 * that the readback (src/render/frame/readback.c) copies each plane as it is.
 * Planes from PB_RESOLVE_BASE_CHANNELS on (the photon AOVs) lie in a second
 * buffer, at P - PB_RESOLVE_BASE_CHANNELS: neither needs more than 72 bytes
 * per pixel, so the band (frame.c) stays as wide as the accumulators allow.
 * Non-finite values are replaced by 0 and counted with an atomic (the
 * NaN guard, formerly on the host). Shared by C and GLSL. */
#ifndef PB_RESOLVE_SHARED_H
#define PB_RESOLVE_SHARED_H

#include "shared/pb_gpu.h"

/* Plane offsets, in floats per pixel of the band. */
PB_CONST(PB_RESOLVE_BEAUTY, 0u)    /* RGBA */
PB_CONST(PB_RESOLVE_DIRECT, 4u)    /* RGB */
PB_CONST(PB_RESOLVE_ALBEDO, 7u)    /* RGB */
PB_CONST(PB_RESOLVE_NORMAL, 10u)   /* XYZ, unit or 0 */
PB_CONST(PB_RESOLVE_DEPTH, 13u)
PB_CONST(PB_RESOLVE_MATERIAL, 14u)
PB_CONST(PB_RESOLVE_EMISSION, 15u) /* RGB */
PB_CONST(PB_RESOLVE_BASE_CHANNELS, 18u)
/* With the photon stages: */
PB_CONST(PB_RESOLVE_INDIRECT, 18u) /* RGB */
PB_CONST(PB_RESOLVE_CAUSTIC, 21u)  /* RGB */
PB_CONST(PB_RESOLVE_KPD, 24u)      /* photons gathered, samples that hit (raw sums, for k_PD) */
PB_CONST(PB_RESOLVE_PHOTON_CHANNELS, 26u)
/* With normal maps (eq. 20's inputs; shading_correction.h): */
PB_CONST(PB_RESOLVE_GEO_NORMAL, 26u)  /* XYZ */
PB_CONST(PB_RESOLVE_PHOTON_DIR, 29u)  /* XYZ */
PB_CONST(PB_RESOLVE_SHADING_NORMAL, 32u) /* XYZW */
PB_CONST(PB_RESOLVE_NMAP_CHANNELS, 36u)

PB_CONST(PB_RESOLVE_PHOTONS, 1u) /* flags: photon accumulators bound */
PB_CONST(PB_RESOLVE_NMAP, 2u)    /* eq. 20's sums bound */
PB_CONST(PB_RESOLVE_OPAQUE, 4u)  /* beauty alpha 1 (pb_scene.film_opaque) */

/* k_PD's sums over the frame (the statistic pb_render_stats.k_pd = photons
 * / hits), reduced on the GPU so that a lean readback (render.h
 * PB_RENDER_READBACK_BEAUTY, _STATS) brings these 16 bytes instead of the
 * k_PD plane (8 bytes a pixel). Each workgroup of the resolve sums its
 * pixels' values (the KPD plane's two channels) in shared memory and adds
 * the sums with atomics, as 64-bit unsigned fixed point (lo, hi words; the
 * carry from lo into hi detected from atomicAdd's previous value), scale
 * 2^PB_RESOLVE_KPD_FRAC_BITS. The values are counts (photons in an estimate,
 * samples that hit: integers, exact in the float accumulators below 2^24),
 * so the sums are exact and equal the host's double sums of the plane
 * (readback.c) bit for bit. No overflow: 2^64 / 2^8 = 2^56 counts in all,
 * at 4K (3840 x 2160 < 2^23 pixels) a mean of 2^33 per pixel, that is
 * k x spp <= 8.6e9 (k 10^4 photons a gather at 8.6e5 samples), beyond the
 * 2^24 the float accumulators count exactly; a pixel's value is clamped to
 * [0, 2^40] (non-finite: 0) so that its own conversion cannot overflow.
 * The 8 fraction bits keep a non-integer value's sum to 2^-8 a pixel. Zeroed
 * with the guard at the frame's start; summed over the frame's bands. */
PB_CONST(PB_RESOLVE_KPD_FRAC_BITS, 8u) /* scale 2^8 */
PB_CONST(PB_RESOLVE_KPD_MAX_LOG2, 40u) /* a pixel's value clamped to 2^40 */

PB_STRUCT(pb_gpu_resolve_kpd) {
  uint photons_lo, photons_hi; /* sum of the KPD plane's channel 0, x scale */
  uint hits_lo, hits_hi;       /* channel 1 */
} PB_END(pb_gpu_resolve_kpd)

PB_STRUCT(pb_gpu_resolve_push) {
  uint pixels;    /* of the band */
  float inv_spp;  /* 1 / samples accumulated (the host's float, so the
                     products equal the host resolve's bit for bit) */
  uint flags;     /* PB_RESOLVE_* */
  uint pad0;
} PB_END(pb_gpu_resolve_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_resolve_push) == 16, "pb_gpu_resolve_push size");
_Static_assert(sizeof(pb_gpu_resolve_kpd) == 16, "pb_gpu_resolve_kpd size");
#endif
#endif
