/* HDR-FLIP: NVIDIA's FLIP image-difference metric for high-dynamic-range
 * images, as NVIDIA FLIP 1.7 (pip `flip-evaluator` 1.7) computes it:
 *
 *   P. Andersson, J. Nilsson, T. Akenine-Moller, M. Oskarsson, K. Astrom,
 *   M. D. Fairchild, "FLIP: A Difference Evaluator for Alternating Images",
 *   Proc. ACM Comput. Graph. Interact. Tech. 3(2), 2020 (LDR-FLIP), and
 *   P. Andersson, J. Nilsson, P. Shirley, T. Akenine-Moller, "Visualizing
 *   Errors in Rendered High Dynamic Range Images", Eurographics 2021 short
 *   papers (HDR-FLIP).
 *
 * Inputs are scene-linear Rec.709/sRGB-primaries RGB. The reference fixes a
 * range of exposures (FLIP's ACES tone mapper: the start exposure maps the
 * reference's largest luminance, the stop exposure its median luminance, to
 * the tone mapper's output 0.85; ceil(stop - start), at least 2, exposures
 * evenly spaced between them); at each, both images are exposed, tone mapped,
 * clamped to [0, 1] and compared with LDR-FLIP; a pixel's HDR-FLIP is its
 * largest LDR-FLIP over the exposures, in [0, 1] (0: indistinguishable). The
 * viewing condition is FLIP's default, 67.02 pixels per degree (0.7 m from a
 * 0.7 m wide monitor of 3840 pixels).
 *
 * A negative or non-finite value of either image is taken as 0 (FLIP needs
 * non-negative radiance) and its pixel counted. A reference that is black
 * everywhere leaves FLIP's exposure range undefined (the start exposure is
 * infinite; NVIDIA's tool refuses it): pb_flip_hdr then reports defined = 0
 * and no numbers. */
#ifndef PB_METRICS_FLIP_H
#define PB_METRICS_FLIP_H

#include <stdint.h>

#include "core/result.h"

/* FLIP's default pixels per degree: 0.7 m * (3840 px / 0.7 m) * pi / 180. */
#define PB_FLIP_DEFAULT_PPD 67.0206451f

typedef struct pb_flip_result {
  int defined;            /* 0: the reference is black everywhere (see above) */
  double mean;            /* mean over pixels of the HDR-FLIP error map */
  float start_exposure;   /* log2 exposure scales, from the reference */
  float stop_exposure;
  int exposures;          /* how many exposures were evaluated */
  uint64_t zeroed_pixels; /* pixels of either image with a negative or
                             non-finite value, taken as 0 */
} pb_flip_result;

/* HDR-FLIP of `test` against `ref` (same size; `channels` 3 or 4 floats per
 * pixel, row-major, top row first, R, G, B first). `error_map`, if not NULL,
 * receives width*height per-pixel errors in [0, 1] (all 0 when the result is
 * not defined). Runs on up to as many threads as the machine has cores for
 * images large enough to gain from it. Errors: PB_ERR_USAGE (bad size or
 * channels), PB_ERR_NOMEM. */
pb_result pb_flip_hdr(const float *test, const float *ref, uint32_t width,
                      uint32_t height, uint32_t channels, float *error_map,
                      pb_flip_result *out);

/* FLIP's magma colour map (256 entries, FLIP's table) at error e in [0, 1]:
 * entry round(255 e), as 8-bit sRGB-encoded values round(255 v), no
 * rescaling (0 black, 1 light yellow). */
void pb_flip_magma(float e, uint8_t rgb[3]);

/* An error map written as an 8-bit RGB PNG through pb_flip_magma, as FLIP's
 * own tool writes it (flip_heatmap.c). */
pb_result pb_flip_write_heatmap(const char *path, const float *error_map,
                                uint32_t width, uint32_t height);

#endif
