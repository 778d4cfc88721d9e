/* Image-comparison metrics, defined once for every tool (compare, the
 * validation reports, the reference's own noise estimate, the GPU tests):
 *
 *  RMSE    sqrt(mean over pixels and R,G,B of (t - r)^2), scene-linear.
 *  relMSE  mean over pixels and R,G,B of (t - r)^2 / (r^2 + 0.01), r the
 *          reference, scene-linear (the 0.01 keeps black pixels finite).
 *  PSNR    10 log10(1 / MSE) on the display image in [0, 1] (peak 1), MSE
 *          over pixels and R,G,B; +INFINITY for identical images.
 *  SSIM    Wang, Bovik, Sheikh & Simoncelli 2004 ("Image Quality Assessment:
 *          From Error Visibility to Structural Similarity", IEEE TIP 13(4)):
 *            SSIM = (2 mu_t mu_r + C1)(2 s_tr + C2) /
 *                   ((mu_t^2 + mu_r^2 + C1)(s_t^2 + s_r^2 + C2)),
 *          C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 1, with the paper's 11x11
 *          Gaussian window (sigma 1.5, normalised), statistics weighted by
 *          it, over every window position that fits inside the image
 *          ("valid", as the authors' ssim_index.m; no downsampling). The mean
 *          over windows is taken per channel of the display image and the
 *          three channels are averaged. Images under 11 pixels on a side use
 *          one window covering the whole image with uniform weights.
 *
 * The display image is the plain sRGB encoding (IEC 61966-2-1) of the linear
 * values clamped to [0, 1], until the shared OCIO view replaces it: callers
 * pass pb_metrics_desc.display to use another transform, so that every
 * renderer's picture goes through the same colour pipeline before the
 * display metrics see it.
 *
 * HDR-FLIP (NVIDIA FLIP 1.7), which compare reports beside these, is in
 * flip.h.
 *
 * Pixel buffers are row-major, top row first, `channels` (3 or 4) floats per
 * pixel; only the first three (R, G, B) are compared. A value that is NaN or
 * Inf is taken as 0 and counted in pb_metrics.nonfinite. */
#ifndef PB_METRICS_H
#define PB_METRICS_H

#include <stdint.h>

#include "core/result.h"

/* Maps an RGB image (3 floats per pixel, row-major) in place from
 * scene-linear to display values in [0, 1]. compare wraps the shared OCIO
 * view (pb_color_apply_display) in one of these. */
typedef pb_result (*pb_display_fn)(void *user, float *rgb, uint32_t width,
                                   uint32_t height);

/* The default display transform: clamp to [0, 1], sRGB encode (what the
 * built-in OCIO config's sRGB "Standard" view does). */
pb_result pb_display_srgb(void *user, float *rgb, uint32_t width, uint32_t height);

typedef struct pb_metrics_desc {
  pb_display_fn display; /* NULL: pb_display_srgb */
  void *display_user;
} pb_metrics_desc;

typedef struct pb_metrics {
  uint32_t width, height;
  double rmse, relmse;   /* scene-linear RGB */
  double mse_display;
  double psnr;           /* dB; +INFINITY when mse_display is 0 */
  double ssim;           /* mean of ssim_rgb */
  double ssim_rgb[3];
  double max_abs;        /* largest |t - r| over pixels and channels, linear */
  uint64_t nonfinite;    /* NaN/Inf values met in either image */
} pb_metrics;

/* Compares `test` against `ref` (same size and channel count). desc may be
 * NULL. Errors: PB_ERR_USAGE (bad size or channels), PB_ERR_NOMEM, and
 * whatever the display transform returns. */
pb_result pb_metrics_compute(const float *test, const float *ref, uint32_t width,
                             uint32_t height, uint32_t channels,
                             const pb_metrics_desc *desc, pb_metrics *out);

/* SSIM of two single-channel display images (planar, width*height values in
 * [0, 1]) as defined above. Returns a negative value on allocation failure. */
double pb_metrics_ssim_plane(const float *a, const float *b, uint32_t width,
                             uint32_t height);

/* PSNR in dB of a display-image MSE with peak 1 (+INFINITY for 0). */
double pb_metrics_psnr_from_mse(double mse);

/* The noise of an image from two independent renders A and B of it with
 * equal sample counts, for their average M = (A + B) / 2: each pixel's
 * variance is estimated as (A - B)^2 / 4 (Var(A - B) = 2 Var(A) and
 * Var(M) = Var(A) / 2), so
 *   rmse   = sqrt(mean((A - B)^2) / 4),
 *   relmse = mean(((A - B)^2 / 4) / (M^2 + 0.01)),
 *   psnr   = PSNR of mean((display(A) - display(B))^2) / 4 (a first-order
 *            estimate of the display image's own error).
 * These are the errors M would have against a noise-free image; bias (such
 * as photon mapping's) is not seen. */
typedef struct pb_noise_estimate {
  double rmse, relmse, psnr;
  double rmse_display; /* sqrt of the display MSE estimate (psnr's) */
} pb_noise_estimate;

pb_result pb_metrics_noise_from_halves(const float *a, const float *b, uint32_t width,
                                       uint32_t height, uint32_t channels,
                                       const pb_metrics_desc *desc,
                                       pb_noise_estimate *out);

/* The same from two independent parts of unequal sizes: `a` the mean of na
 * samples, `b` of nb, for their pooled mean M = (na A + nb B) / (na + nb).
 * With v the variance of one sample, Var(A - B) = v (1/na + 1/nb) and
 * Var(M) = v / (na + nb), so each pixel's Var(M) is estimated as
 * (A - B)^2 / ((1/na + 1/nb)(na + nb)) (4 for halves), and its display
 * error by the delta method at M: with s that estimate's square root per
 * pixel and channel, (display(M + s) - display(M - s)) / 2, so that the
 * display's slope is taken at the pooled mean, not at the noisier parts
 * (which, a part of one or two samples, overstate the noise of dark
 * pixels through the sRGB curve's steep start). */
pb_result pb_metrics_noise_from_parts(const float *a, double na, const float *b, double nb, uint32_t width,
                                      uint32_t height, uint32_t channels, const pb_metrics_desc *desc,
                                      pb_noise_estimate *out);

/* Per-pixel error heat maps. */
typedef enum pb_heatmap_metric {
  PB_HEATMAP_RELATIVE = 0, /* sqrt(mean over RGB of (t - r)^2 / (r^2 + 0.01)) */
  PB_HEATMAP_ABSOLUTE = 1, /* sqrt(mean over RGB of (t - r)^2), linear units */
} pb_heatmap_metric;

/* Fills rgb_out (width*height*3, linear RGB ready for pb_png_write_srgb) with
 * the per-pixel error through the viridis colour map, 0 at the dark end and
 * `scale_max` (0: the 99th percentile of the error, or 1 if that is 0) at
 * the bright end, values above clamped. *scale_used receives the scale. */
pb_result pb_metrics_heatmap(const float *test, const float *ref, uint32_t width,
                             uint32_t height, uint32_t channels,
                             pb_heatmap_metric metric, float scale_max,
                             float *rgb_out, float *scale_used);

/* pb_metrics_heatmap written as an 8-bit PNG (heatmap.c). */
pb_result pb_metrics_write_heatmap(const char *path, const float *test,
                                   const float *ref, uint32_t width, uint32_t height,
                                   uint32_t channels, pb_heatmap_metric metric,
                                   float scale_max, float *scale_used);

#endif
