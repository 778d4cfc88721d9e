/* Image metrics (definitions in metrics.h). Sums are kept in double: a 4K
 * image has 25 million terms. */
#include "metrics/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/srgb.h"

pb_result pb_display_srgb(void *user, float *rgb, uint32_t w, uint32_t h) {
  (void)user;
  for (size_t i = 0; i < 3 * (size_t)w * h; ++i) {
    float v = rgb[i];
    v = v > 1.0f ? 1.0f : v; /* pb_linear_to_srgb maps <= 0 and NaN to 0 */
    rgb[i] = pb_linear_to_srgb(v);
  }
  return PB_OK;
}

double pb_metrics_psnr_from_mse(double mse) {
  if (!(mse > 0.0)) return INFINITY;
  return -10.0 * log10(mse);
}

static inline float clean(float v, uint64_t *bad) {
  if (isfinite(v)) return v;
  (*bad)++;
  return 0.0f;
}

/* 11x11 Gaussian, sigma 1.5, separable: w(i, j) = g(i) g(j), sum 1. */
enum { WIN = 11 };
static void gauss_1d(double g[WIN]) {
  double s = 0.0;
  for (int i = 0; i < WIN; ++i) {
    double x = i - WIN / 2;
    g[i] = exp(-x * x / (2.0 * 1.5 * 1.5));
    s += g[i];
  }
  for (int i = 0; i < WIN; ++i) g[i] /= s;
}

static double ssim_of(double ma, double mb, double va, double vb, double cab) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  return ((2.0 * ma * mb + c1) * (2.0 * cab + c2)) /
         ((ma * ma + mb * mb + c1) * (va + vb + c2));
}

double pb_metrics_ssim_plane(const float *a, const float *b, uint32_t w, uint32_t h) {
  if (w < WIN || h < WIN) {
    double n = (double)w * h, sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i) {
      sa += a[i];
      sb += b[i];
      saa += (double)a[i] * a[i];
      sbb += (double)b[i] * b[i];
      sab += (double)a[i] * b[i];
    }
    double ma = sa / n, mb = sb / n;
    return ssim_of(ma, mb, saa / n - ma * ma, sbb / n - mb * mb, sab / n - ma * mb);
  }
  double g[WIN];
  gauss_1d(g);
  uint32_t ow = w - (WIN - 1), oh = h - (WIN - 1);
  /* Horizontal pass over every row into five moment planes (ow x h), then
   * the vertical pass per output pixel. */
  size_t np = (size_t)ow * h;
  double *m = malloc(5 * np * sizeof *m);
  if (!m) return -1.0;
  double *ha = m, *hb = m + np, *haa = m + 2 * np, *hbb = m + 3 * np, *hab = m + 4 * np;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < ow; ++x) {
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0;
      const float *ra = a + (size_t)y * w + x, *rb = b + (size_t)y * w + x;
      for (int k = 0; k < WIN; ++k) {
        double va = ra[k], vb = rb[k];
        s0 += g[k] * va;
        s1 += g[k] * vb;
        s2 += g[k] * va * va;
        s3 += g[k] * vb * vb;
        s4 += g[k] * va * vb;
      }
      size_t o = (size_t)y * ow + x;
      ha[o] = s0;
      hb[o] = s1;
      haa[o] = s2;
      hbb[o] = s3;
      hab[o] = s4;
    }
  double total = 0.0;
  for (uint32_t y = 0; y < oh; ++y)
    for (uint32_t x = 0; x < ow; ++x) {
      double ma = 0, mb = 0, maa = 0, mbb = 0, mab = 0;
      for (int k = 0; k < WIN; ++k) {
        size_t o = (size_t)(y + (uint32_t)k) * ow + x;
        ma += g[k] * ha[o];
        mb += g[k] * hb[o];
        maa += g[k] * haa[o];
        mbb += g[k] * hbb[o];
        mab += g[k] * hab[o];
      }
      total += ssim_of(ma, mb, maa - ma * ma, mbb - mb * mb, mab - ma * mb);
    }
  free(m);
  return total / ((double)ow * oh);
}

/* Copies the RGB of an image into rgb (3 per pixel), non-finite -> 0. */
static void copy_rgb(const float *src, size_t n, uint32_t ch, float *rgb, uint64_t *bad) {
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + (size_t)c] = clean(src[i * ch + (size_t)c], bad);
}

/* Both images through the display transform: display-space RGB copies. */
static pb_result to_display(const float *t, const float *r, uint32_t w, uint32_t h,
                            uint32_t ch, const pb_metrics_desc *desc, float **td,
                            float **rd) {
  size_t n = (size_t)w * h;
  pb_display_fn disp = desc && desc->display ? desc->display : pb_display_srgb;
  void *du = desc ? desc->display_user : NULL;
  *td = malloc(3 * n * sizeof **td);
  *rd = malloc(3 * n * sizeof **rd);
  if (!*td || !*rd) {
    free(*td);
    free(*rd);
    *td = *rd = NULL;
    return pb_fail(PB_ERR_NOMEM, "metrics: out of memory for a %ux%u image", w, h);
  }
  uint64_t bad = 0;
  copy_rgb(t, n, ch, *td, &bad);
  copy_rgb(r, n, ch, *rd, &bad);
  pb_result res = disp(du, *td, w, h);
  if (res == PB_OK) res = disp(du, *rd, w, h);
  if (res != PB_OK) {
    free(*td);
    free(*rd);
    *td = *rd = NULL;
  }
  return res;
}

pb_result pb_metrics_compute(const float *test, const float *ref, uint32_t w,
                             uint32_t h, uint32_t ch, const pb_metrics_desc *desc,
                             pb_metrics *out) {
  memset(out, 0, sizeof *out);
  if (!test || !ref || w == 0 || h == 0 || (ch != 3 && ch != 4))
    return pb_fail(PB_ERR_USAGE, "metrics: bad image (%ux%u, %u channels)", w, h, ch);
  size_t n = (size_t)w * h;
  double se = 0.0, rel = 0.0, sed = 0.0, max_abs = 0.0;
  uint64_t bad = 0;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      double t = clean(test[i * ch + (size_t)c], &bad), r = clean(ref[i * ch + (size_t)c], &bad);
      double d = t - r;
      se += d * d;
      rel += d * d / (r * r + 0.01);
      if (fabs(d) > max_abs) max_abs = fabs(d);
    }
  float *td, *rd;
  pb_result res = to_display(test, ref, w, h, ch, desc, &td, &rd);
  if (res != PB_OK) return res;
  float *planes = malloc(6 * n * sizeof *planes); /* t R,G,B then r R,G,B */
  if (!planes) {
    free(td);
    free(rd);
    return pb_fail(PB_ERR_NOMEM, "metrics: out of memory for a %ux%u image", w, h);
  }
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      double d = (double)td[3 * i + (size_t)c] - rd[3 * i + (size_t)c];
      sed += d * d;
      planes[(size_t)c * n + i] = td[3 * i + (size_t)c];
      planes[(size_t)(3 + c) * n + i] = rd[3 * i + (size_t)c];
    }
  free(td);
  free(rd);
  double cnt = 3.0 * (double)n;
  out->width = w;
  out->height = h;
  out->rmse = sqrt(se / cnt);
  out->relmse = rel / cnt;
  out->mse_display = sed / cnt;
  out->psnr = pb_metrics_psnr_from_mse(out->mse_display);
  out->max_abs = max_abs;
  out->nonfinite = bad;
  double ssim = 0.0;
  for (int c = 0; c < 3; ++c) {
    double s = pb_metrics_ssim_plane(planes + (size_t)c * n, planes + (size_t)(3 + c) * n, w, h);
    if (s < -1.5) { /* allocation failure (SSIM itself is >= -1) */
      free(planes);
      return pb_fail(PB_ERR_NOMEM, "metrics: out of memory for SSIM of %ux%u", w, h);
    }
    out->ssim_rgb[c] = s;
    ssim += s;
  }
  out->ssim = ssim / 3.0;
  free(planes);
  return PB_OK;
}

/* The noise estimate of M from parts A (na samples) and B (nb).
 * delta: the display error by the delta method at M (see metrics.h); else
 * the difference of the parts' own display images, scaled. */
static pb_result noise_parts(const float *a, double na, const float *b, double nb, uint32_t w, uint32_t h,
                             uint32_t ch, const pb_metrics_desc *desc, int delta, pb_noise_estimate *out) {
  memset(out, 0, sizeof *out);
  if (!a || !b || w == 0 || h == 0 || (ch != 3 && ch != 4) || !(na > 0) || !(nb > 0))
    return pb_fail(PB_ERR_USAGE, "noise estimate: bad image (%ux%u, %u channels) or sample counts", w, h, ch);
  /* Per sample variance v: Var(A - B) = v (1/na + 1/nb), Var(M) = v / (na + nb),
   * M = (na A + nb B) / (na + nb): Var(M) = (A - B)^2 / q. */
  double q = (1.0 / na + 1.0 / nb) * (na + nb), wa = na / (na + nb);
  size_t n = (size_t)w * h;
  double se = 0.0, rel = 0.0, sed = 0.0;
  uint64_t bad = 0;
  float *hi = NULL, *lo = NULL;
  if (delta && (!(hi = malloc(3 * n * sizeof *hi)) || !(lo = malloc(3 * n * sizeof *lo)))) {
    free(hi);
    return pb_fail(PB_ERR_NOMEM, "metrics: out of memory for a %ux%u image", w, h);
  }
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      double va = clean(a[i * ch + (size_t)c], &bad), vb = clean(b[i * ch + (size_t)c], &bad);
      double d = va - vb, m = wa * va + (1.0 - wa) * vb;
      se += d * d;
      rel += d * d / q / (m * m + 0.01);
      if (delta) { /* M plus and minus its own standard deviation */
        double sd = fabs(d) / sqrt(q);
        hi[3 * i + (size_t)c] = (float)(m + sd);
        lo[3 * i + (size_t)c] = (float)(m - sd);
      }
    }
  float *da, *db;
  pb_result res;
  if (delta) {
    pb_display_fn disp = desc && desc->display ? desc->display : pb_display_srgb;
    void *du = desc ? desc->display_user : NULL;
    res = disp(du, hi, w, h);
    if (res == PB_OK) res = disp(du, lo, w, h);
    da = hi, db = lo;
    if (res != PB_OK) {
      free(hi);
      free(lo);
      return res;
    }
    q = 4.0; /* (disp(M + s) - disp(M - s)) / 2 is the error of M */
  } else if ((res = to_display(a, b, w, h, ch, desc, &da, &db)) != PB_OK) {
    return res;
  }
  for (size_t i = 0; i < 3 * n; ++i) {
    double d = (double)da[i] - db[i];
    sed += d * d;
  }
  free(da);
  free(db);
  double cnt = 3.0 * (double)n;
  out->rmse = sqrt(se / ((1.0 / na + 1.0 / nb) * (na + nb)) / cnt);
  out->relmse = rel / cnt;
  out->rmse_display = sqrt(sed / q / cnt);
  out->psnr = pb_metrics_psnr_from_mse(sed / q / cnt);
  return PB_OK;
}

pb_result pb_metrics_noise_from_parts(const float *a, double na, const float *b, double nb, uint32_t w,
                                      uint32_t h, uint32_t ch, const pb_metrics_desc *desc,
                                      pb_noise_estimate *out) {
  return noise_parts(a, na, b, nb, w, h, ch, desc, 1, out);
}

pb_result pb_metrics_noise_from_halves(const float *a, const float *b, uint32_t w,
                                       uint32_t h, uint32_t ch,
                                       const pb_metrics_desc *desc,
                                       pb_noise_estimate *out) {
  return noise_parts(a, 1.0, b, 1.0, w, h, ch, desc, 0, out);
}

/* matplotlib's viridis at 0, 1/8, ..., 1 (sRGB-encoded 8-bit). */
static const unsigned char viridis[9][3] = {
    {68, 1, 84},    {72, 40, 120},  {62, 73, 137},  {49, 104, 142}, {38, 130, 142},
    {31, 158, 137}, {53, 183, 121}, {110, 206, 88}, {253, 231, 37}};

static void colormap(float v, float rgb[3]) {
  if (!(v > 0.0f)) v = 0.0f;
  if (v > 1.0f) v = 1.0f;
  float x = v * 8.0f;
  int i = (int)x;
  if (i > 7) i = 7;
  float f = x - (float)i;
  for (int c = 0; c < 3; ++c) {
    float s = ((1.0f - f) * viridis[i][c] + f * viridis[i + 1][c]) / 255.0f;
    rgb[c] = pb_srgb_to_linear(s);
  }
}

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

pb_result pb_metrics_heatmap(const float *test, const float *ref, uint32_t w,
                             uint32_t h, uint32_t ch, pb_heatmap_metric metric,
                             float scale_max, float *rgb_out, float *scale_used) {
  if (!test || !ref || w == 0 || h == 0 || (ch != 3 && ch != 4))
    return pb_fail(PB_ERR_USAGE, "heat map: bad image (%ux%u, %u channels)", w, h, ch);
  size_t n = (size_t)w * h;
  float *err = malloc(n * sizeof *err);
  if (!err) return pb_fail(PB_ERR_NOMEM, "heat map: out of memory");
  uint64_t bad = 0;
  for (size_t i = 0; i < n; ++i) {
    double s = 0.0;
    for (int c = 0; c < 3; ++c) {
      double t = clean(test[i * ch + (size_t)c], &bad), r = clean(ref[i * ch + (size_t)c], &bad);
      double d = t - r;
      s += metric == PB_HEATMAP_RELATIVE ? d * d / (r * r + 0.01) : d * d;
    }
    err[i] = (float)sqrt(s / 3.0);
  }
  float scale = scale_max;
  if (!(scale > 0.0f)) {
    float *sorted = malloc(n * sizeof *sorted);
    if (!sorted) {
      free(err);
      return pb_fail(PB_ERR_NOMEM, "heat map: out of memory");
    }
    memcpy(sorted, err, n * sizeof *sorted);
    qsort(sorted, n, sizeof *sorted, cmp_float);
    scale = sorted[(size_t)((double)(n - 1) * 0.99)];
    free(sorted);
    if (!(scale > 0.0f) || !isfinite(scale)) scale = 1.0f;
  }
  for (size_t i = 0; i < n; ++i) colormap(err[i] / scale, rgb_out + 3 * i);
  free(err);
  if (scale_used) *scale_used = scale;
  return PB_OK;
}
