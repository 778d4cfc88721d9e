/* Multi-level up-sampling of the diffuse photon irradiance (seed 003 sec. 6
 * "Rendering", Figure 9; src/render/estimate/upsample.c, shaders/estimate/upsample_mark.comp,
 * shaders/estimate/upsample_compose.comp and gather.comp built with -DPB_UPSAMPLE=1).
 * Included after pb_gpu.h.
 *
 * Buffers (bindings: shared/pb_contract.h PB_UPS_BIND_*):
 *   irradiance  vec4 per pixel of the band: rgb the diffuse irradiance per
 *               unit albedo, sum_i K_i / A_i Phi_i (the adjoint shading-normal
 *               weight included), of the non-caustic photons, W/m^2; w the
 *               state of this sample: PB_UPS_NONE (no diffuse part here, or
 *               queued for the estimate), PB_UPS_ESTIMATED (the gather ran
 *               here), PB_UPS_INTERPOLATED (from the level above);
 *   list        uint: PB_UPS_HEADER_WORDS of counters (below), then the
 *               pixel indices the gather estimates at the current level.
 * Header words: [PB_UPS_H_QUEUED + l] pixels queued at level l this sample
 * (reset by the compose pass), [PB_UPS_H_ESTIMATED + l] and
 * [PB_UPS_H_INTERPOLATED + l] summed over the frame's samples,
 * [PB_UPS_H_FULL_RES] pixels the full-resolution pass (glossy lobes,
 * caustic photons, Blender materials) traversed the photon LBVH at,
 * [PB_UPS_H_DIFFUSE] pixels the compose pass shaded from the irradiance. */
#ifndef PB_UPSAMPLE_SHARED_H
#define PB_UPSAMPLE_SHARED_H

PB_CONST(PB_UPS_MAX_LEVELS, 4u)
PB_CONST(PB_UPS_NONE, 0u)
PB_CONST(PB_UPS_ESTIMATED, 1u)
PB_CONST(PB_UPS_INTERPOLATED, 2u)
PB_CONST(PB_UPS_HEADER_WORDS, 32u)
PB_CONST(PB_UPS_H_QUEUED, 0u)
PB_CONST(PB_UPS_H_ESTIMATED, 8u)
PB_CONST(PB_UPS_H_INTERPOLATED, 16u)
PB_CONST(PB_UPS_H_FULL_RES, 24u)
PB_CONST(PB_UPS_H_DIFFUSE, 25u)

/* upsample_mark.comp and upsample_compose.comp. */
PB_STRUCT(pb_gpu_upsample_push) {
  uint sample_index;
  uint level;            /* mark: the level whose pixels (stride 2^level) are
                            made, from those of level + 1 (level == levels:
                            the coarse grid, all queued) */
  uint levels;           /* L, 1 .. PB_UPS_MAX_LEVELS */
  uint flags;            /* compose: PB_GATHER_NO_BEAUTY */
} PB_END(pb_gpu_upsample_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_upsample_push) == 16, "pb_gpu_upsample_push size");
#endif

#endif
