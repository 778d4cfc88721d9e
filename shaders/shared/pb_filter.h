/* The spatial filter (seed 001 24.4.2): the push constants shared by
 * src/render/filter/atrous.c and shaders/atrous.comp. Included after pb_gpu.h.
 * Buffers, vec4 per pixel, top row first: 0 irradiance (s_i, two halves of
 * width x height for the ping-pong), 1 the clipped detail sum, 2 geometry
 * (shading normal xyz, camera depth; depth 0: no surface), 3 the indirect
 * radiance (input, w: the history length L of the A-Trous's clipping; and
 * the filtered result), 4 the albedo (demodulation). */
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

/* The temporal filter (seed 001 24.4.1; src/render/filter/temporal.c,
 * shaders/filter/temporal.comp). Buffers, vec4 per pixel, top row first: 0 the
 * previous frame's temporally filtered irradiance (rgb) and history length
 * (w), 1 the previous frame's geometry (shading normal xyz, camera depth),
 * 2 this frame's geometry, 3 this frame's radiance (rgb; read only), 4 the albedo
 * (demodulation, as the A-Trous), 5 the motion (dx, dy: where this pixel's
 * surface point was in the previous frame, in pixels, previous minus
 * current; z: its camera depth in the previous frame; w: 1 valid, 0 none),
 * 6 the new history (filtered irradiance, length): the next frame's
 * history, 7 this frame's result: the filtered irradiance times the albedo
 * (w: L) on pixels with a surface, the input radiance (w: 0) elsewhere;
 * 8 the statistics below. */
PB_STRUCT(pb_gpu_temporal_push) {
  uint width;
  uint height;
  uint has_history; /* 0: first frame (or reset): no history read */
  uint still;       /* 1: camera and scene unchanged: progressive mean */
  float alpha;      /* eq. 13's 0.95 */
  float sigma_z;    /* eq. 10 (1) */
  float sigma_n;    /* eq. 11 (32) */
  float max_history;/* cap on the history length with still = 1 */
  float clamp_gamma;/* > 0: history clamped to this frame's 3x3 mean +-
                       clamp_gamma sigma (caustics); 0: off (eq. 13 only) */
  uint pad0;
  uint pad1;
  uint pad2;
} PB_END(pb_gpu_temporal_push)

/* What temporal.comp counts over a frame (atomics, zeroed per frame):
 * pixels with a surface, of those with no usable history (L < 1.0001), and
 * the sum of their history lengths L in fixed point, PB_TEMPORAL_LEN_SCALE
 * units, as a 64-bit count in two words (each workgroup adds its sum,
 * rounded: at most 0.5 / PB_TEMPORAL_LEN_SCALE of error per 64 pixels). */
PB_CONST(PB_TEMPORAL_LEN_SCALE, 256u)
PB_STRUCT(pb_gpu_temporal_stats) {
  uint surface;
  uint reset;
  uint len_lo;
  uint len_hi;
} PB_END(pb_gpu_temporal_stats)

/* filter_io.comp (src/render/filter/filters.c): PACK copies the resolved planes
 * into the filters' vec4 buffers (geometry, albedo, indirect with L = 1,
 * caustics); COMPOSE writes the filtered indirect and caustics back into
 * their planes, non-finite values as 0 (counted in the resolve's guard),
 * and moves the beauty by the same change: beauty += filtered - raw. */
PB_CONST(PB_FILTER_IO_PACK, 0u)
PB_CONST(PB_FILTER_IO_COMPOSE, 1u)
PB_CONST(PB_FILTER_IO_GEO_NORMAL, 1u) /* flags: edge-stop on the geometric normal plane */
PB_CONST(PB_FILTER_IO_INDIRECT, 2u)   /* flags: compose the filtered indirect */
PB_CONST(PB_FILTER_IO_CAUSTIC, 4u)    /* flags: compose the filtered caustics */
PB_STRUCT(pb_gpu_filter_io_push) {
  uint pixels;
  uint mode;
  uint flags;
  uint pad0;
} PB_END(pb_gpu_filter_io_push)

/* shading_correction.comp: eq. 20 (src/render/estimate/shading_correction.h). */
PB_STRUCT(pb_gpu_shading_push) {
  uint pixels;
  float s_max;
  uint pad0;
  uint pad1;
} PB_END(pb_gpu_shading_push)

/* Motion vectors (src/render/scene/motion.c, shaders/scene/motion.comp): this frame's
 * camera (its pixel-centre rays) and the previous frame's (the
 * reprojection), both for the same image. Binding 4 of the pass. */
PB_STRUCT(pb_gpu_motion_params) {
  pb_gpu_camera cam;
  pb_gpu_camera prev;
  uint width;
  uint height;
  uint triangle_count;
  uint pad0;
} PB_END(pb_gpu_motion_params)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_motion_params) == 272, "pb_gpu_motion_params size");
_Static_assert(sizeof(pb_gpu_atrous_push) == 32, "pb_gpu_atrous_push size");
_Static_assert(sizeof(pb_gpu_temporal_push) == 48, "pb_gpu_temporal_push size");
_Static_assert(sizeof(pb_gpu_temporal_stats) == 16, "pb_gpu_temporal_stats size");
_Static_assert(sizeof(pb_gpu_filter_io_push) == 16, "pb_gpu_filter_io_push size");
_Static_assert(sizeof(pb_gpu_shading_push) == 16, "pb_gpu_shading_push size");
#endif

#endif
