/* Seed 001 (Smal & Aizenshtein, Ray Tracing Gems ch. 24), 24.4.3:
 * incorporating the effect of shading normals (normal maps) into photon-
 * mapped indirect light. Photon density carries the geometric cosine
 * (w_i . w_ng) implicitly; eq. 20 swaps it for the shading one,
 *   L = E_final f_BRDF min((w_i . w_ns) / (w_i . w_ng + eps), s_max),
 * with w_i the power-weighted mean incoming photon direction, filtered as its
 * own target. Here the gather (shaders/estimate/gather.comp) sums w_i, w_ng and w_ns
 * per pixel into pb_gpu_photon_nmap, the resolve pass (shaders/frame/resolve.comp)
 * turns them into AOVs, and this step applies eq. 20 to the resolved
 * indirect plane on the GPU (shaders/estimate/shading_correction.comp, recorded
 * after the filters, filters.h, in the frame's command buffer), so the
 * filtered E f is what gets rescaled. pb_shading_correction_apply is the
 * same step on host arrays: the reference (PB_RESOLVE_ON_HOST=1) and
 * images rendered in several bands. Only scenes with
 * PB_FEATURE_NORMAL_MAPS.
 *
 * Which form. The chapter's text of eq. 20 is garbled; it reads either
 *   (1) (w_i . w_ns) min(1 / (w_i . w_ng + eps), s_max)   or
 *   (2) min((w_i . w_ns) / (w_i . w_ng + eps), s_max).
 * Derivation: a photon density on a face estimates E = int L cos_g dw, while
 * the shading needs int L cos_s dw, so with one mean direction the exact
 * factor is the ratio r = cos_s / cos_g; the clamp only bounds the gain
 * where the mean direction (a few grazing photons) is noisy. Both forms are
 * at most s_max and equal r when cos_g >= 1 / s_max. Below that, (1) clamps
 * the divisor alone and gives s_max cos_s <= min(r, s_max) = (2) <= r: (2)
 * is never further from r than (1) with the same bound on the gain, so (2)
 * is used (it is also the form the code had). Measured (test_gpu_normal_map,
 * the floor lit from a wall): no pixel differs at s_max = 4; at s_max = 1.5,
 * where 584 of 1024 pixels differ, RMSE against the reference 0.143 with (2)
 * and 0.167 with (1). */
#ifndef PB_RENDER_SHADING_CORRECTION_H
#define PB_RENDER_SHADING_CORRECTION_H

#include <stddef.h>
#include <stdint.h>

#include "gpu/gpu.h"
#include "render/render.h"
#include "render/frame/targets.h"
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"

/* s_max, seed 001 24.3.1.2: "a constant defining the maximum scaling factor"
 * (there it bounds s_u = min(1 / (w_g . w_i), s_max), the kernel's
 * stretch towards grazing light; eq. 20 reuses it). The chapter gives no
 * value (its listing names MAX_SCALING_CONSTANT only), so it is chosen here:
 * 4, the ratio 1 / cos at 75.5 degrees, beyond which the mean direction of
 * a few grazing photons is too noisy to scale by. */
#define PB_SHADING_CORRECTION_S_MAX 4.0f
/* eps of eq. 20: keeps the division finite for w_i in the tangent plane. */
#define PB_SHADING_CORRECTION_EPS 1e-3f

/* Eq. 20's factor min(max(w_i . n_s, 0) / (w_i . n_g + eps), s_max) for unit
 * vectors; 1 when w_i is 0 (no photon) or not finite. Light below the
 * shading normal (w_i . n_s <= 0) gives 0, as the BSDF's own guard does. */
float pb_shading_correction_factor(const float wi[3], const float ns[3], const float ng[3], float s_max);

/* The AOVs eq. 20 reads (out->geo_normal, photon_dir, shading_normal) are
 * resolved on the GPU with the others (shaders/frame/resolve.comp, readback.h). */

/* Eq. 20 on out->indirect (n pixels): each pixel's indirect is scaled by
 * 1 + frac (factor - 1), frac the fraction of its samples on a normal-mapped
 * material; the beauty takes the same change. No-op without the AOVs.
 * Returns the number of pixels changed. */
size_t pb_shading_correction_apply(pb_render_result *out, size_t n, float s_max);

/* The pass on the GPU: a pipeline bound to t's planes (targets with normal
 * maps: t->nmap), and its dispatch over the band's pixels. */
pb_result pb_shading_correction_create(pb_gpu *g, const pb_frame_targets *t, pb_gpu_pipeline *out);
pb_result pb_shading_correction_record(pb_gpu *g, const pb_gpu_pipeline *p, uint32_t pixels, float s_max);

#endif
