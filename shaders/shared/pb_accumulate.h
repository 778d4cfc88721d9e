/* A still run's progressive accumulation on the GPU (shaders/frame/accumulate.comp,
 * src/render/frame/accumulate.c): the running means the sequence
 * kept in host arrays (sequence.c accumulate), in a target of the sequence
 * (targets.h pb_still_sum), updated in place on the resolved planes.
 * Shared by C and GLSL. */
#ifndef PB_ACCUMULATE_SHARED_H
#define PB_ACCUMULATE_SHARED_H

#include "shared/pb_gpu.h"

/* The running means of a pixel: the rest of the beauty (RGBA: beauty minus
 * the temporally filtered parts), direct (RGB), unfiltered caustics (RGB). */
PB_CONST(PB_ACCUM_REST, 0u)
PB_CONST(PB_ACCUM_DIRECT, 4u)
PB_CONST(PB_ACCUM_CAUSTIC, 7u)
PB_CONST(PB_ACCUM_FLOATS, 10u)

PB_CONST(PB_ACCUM_FIRST, 1u)            /* flags: the run's first frame (the means restart) */
PB_CONST(PB_ACCUM_PHOTONS, 2u)          /* the photon planes are there (indirect, caustic) */
PB_CONST(PB_ACCUM_CAUSTIC_FILTERED, 4u) /* caustics have their own temporal filter */

PB_STRUCT(pb_gpu_accumulate_push) {
  uint pixels;
  float k;    /* frames in the means so far (the host's float) */
  float inv;  /* 1 / (k + 1), the host's float */
  uint flags; /* PB_ACCUM_* */
} PB_END(pb_gpu_accumulate_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_accumulate_push) == 16, "pb_gpu_accumulate_push size");
#endif
#endif
