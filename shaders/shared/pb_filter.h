/* The spatial filter (seed 001 24.4.2): the push constants shared by
 * src/render/atrous.c and shaders/atrous.comp. Included after pb_gpu.h.
 * Buffers, vec4 per pixel, top row first: 0 irradiance (s_i, two halves of
 * width x height for the ping-pong), 1 the clipped detail sum, 2 geometry
 * (shading normal xyz, camera depth; depth 0: no surface), 3 the indirect
 * radiance (input, and the filtered result), 4 the albedo (demodulation). */
#ifndef PB_FILTER_SHARED_H
#define PB_FILTER_SHARED_H

PB_CONST(PB_ATROUS_INIT, 0u)     /* s_0 = indirect / albedo, detail = 0 */
PB_CONST(PB_ATROUS_STEP, 1u)     /* s_{i+1} from s_i at tap spacing `step` */
PB_CONST(PB_ATROUS_FINISH, 2u)   /* indirect = (s_n + clipped details) albedo */

PB_STRUCT(pb_gpu_atrous_push) {
  uint width;
  uint height;
  uint mode;
  uint step;        /* 2^i pixels between taps */
  uint src_half;    /* which half of buffer 0 holds s_i (0 or 1) */
  float sigma_z;    /* eq. 10 (1) */
  float sigma_n;    /* eq. 11 (32) */
  float gamma;      /* variance clipping: b_i = gamma sigma_i (eq. 18) */
} PB_END(pb_gpu_atrous_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_atrous_push) == 32, "pb_gpu_atrous_push size");
#endif

#endif
