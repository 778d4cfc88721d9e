/* The resolve pass (shaders/resolve.comp, src/render/resolve.c): the
 * accumulators of a band (sums over samples) turned into the AOVs that leave
 * the GPU, on the GPU, in one buffer of planes: plane P of a band of
 * `pixels` pixels starts at float PB_RESOLVE_P * pixels and holds its
 * channels pixel after pixel (the layout of pb_render_result's arrays), so
 * that the readback (src/render/readback.c) copies each plane as it is.
 * Planes from PB_RESOLVE_BASE_CHANNELS on (the photon AOVs) lie in a second
 * buffer, at P - PB_RESOLVE_BASE_CHANNELS: neither needs more than 72 bytes
 * per pixel, so the band (frame.c) stays as wide as the accumulators allow.
 * Non-finite values are replaced by 0 and counted with an atomic (the
 * issue 9 guard, formerly on the host). Shared by C and GLSL. */
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

PB_STRUCT(pb_gpu_resolve_push) {
  uint pixels;    /* of the band */
  float inv_spp;  /* 1 / samples accumulated (the host's float, so the
                     products equal the host resolve's bit for bit) */
  uint flags;     /* PB_RESOLVE_* */
  uint pad0;
} PB_END(pb_gpu_resolve_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_resolve_push) == 16, "pb_gpu_resolve_push size");
#endif
#endif
