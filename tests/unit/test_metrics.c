/* The metrics module against image pairs with known answers:
 *  - identical images: RMSE 0, relMSE 0, PSNR +inf, SSIM 1;
 *  - constants 0.5 vs 0.25: RMSE 0.25, relMSE 0.0625 / 0.0725, PSNR and
 *    SSIM from the sRGB values (SSIM of constants is the luminance term);
 *  - a 0/1 checkerboard vs its inverse: RMSE 1, relMSE (1/1.01 + 1/0.01)/2,
 *    PSNR 0 dB, and SSIM from the Gaussian window's weight on even and odd
 *    offsets (derived here by parity, not by sliding a window);
 *  - NaN/Inf counted and taken as 0; bad channel counts rejected;
 *  - a custom display transform is used for PSNR/SSIM but not RMSE;
 *  - noise from halves A = M + d, B = M - d gives RMSE |d|;
 *  - heat maps: zero error maps to the dark end of viridis, error at the
 *    scale to the bright end. */
#include <stdlib.h>
#include <string.h>

#include "core/srgb.h"
#include "metrics/metrics.h"
#include "pbtest.h"
#include "scene/scene.h"

static double srgb(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static float *constant(uint32_t w, uint32_t h, uint32_t ch, float v) {
  float *p = malloc((size_t)w * h * ch * sizeof *p);
  for (size_t i = 0; i < (size_t)w * h * ch; ++i) p[i] = v;
  return p;
}

static void test_identical(void) {
  enum { W = 40, H = 30 };
  float *a = malloc(W * H * 4 * sizeof *a);
  unsigned s = 1;
  for (int i = 0; i < W * H * 4; ++i) {
    s = s * 1103515245u + 12345u;
    a[i] = (float)((s >> 8) & 0xffff) / 16384.0f; /* 0..4, HDR */
  }
  pb_metrics m;
  CHECK_EQ_INT(pb_metrics_compute(a, a, W, H, 4, NULL, &m), PB_OK);
  CHECK_NEAR(m.rmse, 0, 0);
  CHECK_NEAR(m.relmse, 0, 0);
  CHECK(isinf(m.psnr) && m.psnr > 0);
  CHECK_NEAR(m.ssim, 1.0, 1e-12);
  CHECK_EQ_INT(m.nonfinite, 0);
  free(a);
}

static void test_constants(uint32_t w, uint32_t h) {
  float *a = constant(w, h, 3, 0.5f), *b = constant(w, h, 3, 0.25f);
  pb_metrics m;
  CHECK_EQ_INT(pb_metrics_compute(a, b, w, h, 3, NULL, &m), PB_OK);
  double da = srgb(0.5), db = srgb(0.25);
  double c1 = 1e-4;
  double want_ssim = (2 * da * db + c1) / (da * da + db * db + c1);
  printf("constants %ux%u: RMSE %.6f relMSE %.6f PSNR %.4f SSIM %.6f (want %.6f)\n", w, h,
         m.rmse, m.relmse, m.psnr, m.ssim, want_ssim);
  CHECK_NEAR(m.rmse, 0.25, 1e-9);
  CHECK_NEAR(m.relmse, 0.0625 / 0.0725, 1e-9);
  CHECK_NEAR(m.psnr, -20.0 * log10(da - db), 1e-4);
  CHECK_NEAR(m.ssim, want_ssim, 1e-6);
  CHECK_NEAR(m.max_abs, 0.25, 1e-7);
  free(a);
  free(b);
}

static void test_checker(void) {
  enum { W = 32, H = 32 };
  float *a = malloc(W * H * 3 * sizeof *a), *b = malloc(W * H * 3 * sizeof *b);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) {
        a[(y * W + x) * 3 + c] = (float)((x + y) & 1);
        b[(y * W + x) * 3 + c] = (float)(1 - ((x + y) & 1));
      }
  pb_metrics m;
  CHECK_EQ_INT(pb_metrics_compute(a, b, W, H, 3, NULL, &m), PB_OK);
  /* Gaussian 11x11, sigma 1.5: weight on even and odd offsets. */
  double g[11], sum = 0, se = 0, so = 0;
  for (int i = 0; i < 11; ++i) sum += g[i] = exp(-(i - 5) * (i - 5) / 4.5);
  for (int i = 0; i < 11; ++i) *((i - 5) % 2 == 0 ? &se : &so) += g[i] / sum;
  /* A window centred on a 1 pixel sees mean Se^2 + So^2, on a 0 pixel
   * 2 Se So; the inverse image has 1 - that; var = mu (1 - mu) for 0/1
   * values and the covariance is minus it. Half the 22x22 windows each. */
  double c1 = 1e-4, c2 = 9e-4, want = 0;
  double mus[2] = {se * se + so * so, 2 * se * so};
  for (int k = 0; k < 2; ++k) {
    double mu = mus[k], v = mu * (1 - mu);
    want += 0.5 * ((2 * mu * (1 - mu) + c1) * (-2 * v + c2)) /
            ((mu * mu + (1 - mu) * (1 - mu) + c1) * (2 * v + c2));
  }
  printf("checker: RMSE %.6f relMSE %.6f PSNR %.4f SSIM %.6f (want %.6f)\n", m.rmse,
         m.relmse, m.psnr, m.ssim, want);
  CHECK_NEAR(m.rmse, 1.0, 1e-9);
  CHECK_NEAR(m.relmse, 0.5 * (1 / 1.01 + 1 / 0.01), 1e-9);
  CHECK_NEAR(m.psnr, 0.0, 1e-5); /* sRGB(1) is 1 within float rounding */
  CHECK_NEAR(m.ssim, want, 1e-6);
  CHECK(m.ssim < -0.9); /* structurally opposite */
  for (int c = 0; c < 3; ++c) CHECK_NEAR(m.ssim_rgb[c], want, 1e-6);
  free(a);
  free(b);
}

static pb_result identity_display(void *user, float *rgb, uint32_t w, uint32_t h) {
  (*(int *)user)++;
  for (size_t i = 0; i < 3 * (size_t)w * h; ++i)
    rgb[i] = rgb[i] < 0 ? 0 : (rgb[i] > 1 ? 1 : rgb[i]);
  return PB_OK;
}

static pb_result failing_display(void *user, float *rgb, uint32_t w, uint32_t h) {
  return pb_fail(PB_ERR_NOT_AVAILABLE, "display: no view");
}

static void test_display_and_errors(void) {
  float *a = constant(12, 12, 3, 0.5f), *b = constant(12, 12, 3, 0.25f);
  int calls = 0;
  pb_metrics_desc d = {identity_display, &calls};
  pb_metrics m;
  CHECK_EQ_INT(pb_metrics_compute(a, b, 12, 12, 3, &d, &m), PB_OK);
  CHECK_EQ_INT(calls, 2); /* one call per image */
  CHECK_NEAR(m.psnr, -20.0 * log10(0.25), 1e-4);
  CHECK_NEAR(m.rmse, 0.25, 1e-9);

  a[7] = NAN;
  a[8] = INFINITY;
  CHECK_EQ_INT(pb_metrics_compute(a, b, 12, 12, 3, NULL, &m), PB_OK);
  CHECK_EQ_INT(m.nonfinite, 2);
  CHECK(isfinite(m.rmse) && isfinite(m.relmse) && isfinite(m.psnr) && isfinite(m.ssim));

  pb_metrics_desc fd = {failing_display, NULL};
  CHECK_EQ_INT(pb_metrics_compute(a, b, 12, 12, 3, &fd, &m), PB_ERR_NOT_AVAILABLE);
  pb_error_clear();
  CHECK_EQ_INT(pb_metrics_compute(a, b, 12, 12, 2, NULL, &m), PB_ERR_USAGE);
  CHECK_EQ_INT(pb_metrics_compute(a, b, 0, 12, 3, NULL, &m), PB_ERR_USAGE);
  pb_error_clear();
  free(a);
  free(b);
}

static void test_noise(void) {
  float *a = constant(20, 10, 3, 0.6f), *b = constant(20, 10, 3, 0.4f);
  pb_noise_estimate n;
  CHECK_EQ_INT(pb_metrics_noise_from_halves(a, b, 20, 10, 3, NULL, &n), PB_OK);
  CHECK_NEAR(n.rmse, 0.1, 1e-7);
  CHECK_NEAR(n.relmse, 0.01 / (0.25 + 0.01), 1e-7);
  double dd = srgb(0.6) - srgb(0.4);
  CHECK_NEAR(n.psnr, -10 * log10(dd * dd / 4), 1e-4);
  free(a);
  free(b);
}

/* Unequal parts: A the mean of 3 samples, B of 1; Var(M) = (A - B)^2 / q with
 * q = (1/3 + 1) * 4 = 16/3, and the display error by the delta method at
 * M = 0.75 A + 0.25 B (metrics.h); a bright pixel clamped at white on both
 * sides of its deviation has no display noise. */
static void test_noise_parts(void) {
  float *a = constant(20, 10, 3, 0.5f), *b = constant(20, 10, 3, 0.3f);
  pb_noise_estimate n;
  CHECK_EQ_INT(pb_metrics_noise_from_parts(a, 3, b, 1, 20, 10, 3, NULL, &n), PB_OK);
  double q = 16.0 / 3.0, s = 0.2 / sqrt(q), m = 0.45;
  CHECK_NEAR(n.rmse, s, 1e-7);
  double dd = (srgb(m + s) - srgb(m - s)) / 2;
  CHECK_NEAR(n.rmse_display, dd, 1e-6);
  CHECK_NEAR(n.psnr, -20 * log10(dd), 1e-4);
  for (int i = 0; i < 20 * 10 * 3; ++i) a[i] = 5.0f, b[i] = 4.0f;
  CHECK_EQ_INT(pb_metrics_noise_from_parts(a, 2, b, 2, 20, 10, 3, NULL, &n), PB_OK);
  CHECK_NEAR(n.rmse_display, 0.0, 0);
  CHECK_EQ_INT(pb_metrics_noise_from_parts(a, 0, b, 2, 20, 10, 3, NULL, &n), PB_ERR_USAGE);
  pb_error_clear();
  free(a);
  free(b);
}

static void test_heatmap(void) {
  float *a = constant(4, 2, 3, 1.0f), *b = constant(4, 2, 3, 1.0f);
  float rgb[4 * 2 * 3], scale = 0;
  CHECK_EQ_INT(pb_metrics_heatmap(a, b, 4, 2, 3, PB_HEATMAP_RELATIVE, 0, rgb, &scale), PB_OK);
  CHECK_NEAR(scale, 1.0, 0);
  CHECK_NEAR(rgb[0], pb_srgb_to_linear(68 / 255.0f), 1e-6);
  CHECK_NEAR(rgb[2], pb_srgb_to_linear(84 / 255.0f), 1e-6);
  a[3 * 5] = a[3 * 5 + 1] = a[3 * 5 + 2] = 3.0f; /* pixel 5: |d| = 2 */
  CHECK_EQ_INT(pb_metrics_heatmap(a, b, 4, 2, 3, PB_HEATMAP_ABSOLUTE, 2.0f, rgb, &scale), PB_OK);
  CHECK_NEAR(rgb[15], pb_srgb_to_linear(253 / 255.0f), 1e-6);
  CHECK_NEAR(rgb[17], pb_srgb_to_linear(37 / 255.0f), 1e-6);
  CHECK_NEAR(rgb[0], pb_srgb_to_linear(68 / 255.0f), 1e-6);
  free(a);
  free(b);
}

int main(void) {
  test_identical();
  test_constants(32, 24);
  test_constants(8, 5); /* under one window: global statistics */
  test_checker();
  test_display_and_errors();
  test_noise();
  test_noise_parts();
  test_heatmap();
  return pbt_done();
}
