/* HDR-FLIP (flip.h), written from the FLIP papers (Andersson et al. 2020,
 * "FLIP: A Difference Evaluator for Alternating Images", and 2021,
 * "Visualizing Errors in Rendered High Dynamic Range Images") with the
 * constants, filter sizes and order of operations of NVIDIA FLIP 1.7
 * (github.com/NVlabs/flip, pip flip-evaluator 1.7), so that its numbers
 * match that tool's. Arithmetic is single precision, as FLIP's.
 *
 * Per exposure, each image goes through
 *   colour:  linear RGB -> XYZ -> YCxCz (an opponent space, linear in XYZ),
 *            filtered by the contrast sensitivity functions (Gaussians in
 *            the spatial domain: one per channel for Y and Cx, a sum of two
 *            for Cz, separated as two rank-one filters), back to linear RGB
 *            clamped to [0, 1], to L*a*b*, Hunt-adjusted (a, b scaled by
 *            0.01 L), and compared with HyAB (|dL| + |d(a,b)|) raised to
 *            qc = 0.7, remapped so that pc * cmax goes to pt and cmax (the
 *            Hunt-adjusted distance from green to blue) to 1;
 *   feature: the achromatic channel normalised to [0, 1], filtered by the
 *            first (edges) and second (points) derivatives of a Gaussian of
 *            standard deviation 0.5 w ppd (w = 0.082 degrees), the larger
 *            difference of the gradient magnitudes scaled by 1/sqrt(2) and
 *            raised to qf = 0.5;
 * and the pixel's LDR-FLIP is colour^(1 - feature). Borders replicate the
 * edge pixels. All filters are separable and run as a horizontal pass over
 * rows and a vertical pass over rows; the vertical pass ends in the per-pixel
 * arithmetic, and both passes split the rows over threads. */
#include "metrics/flip.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"

/* FLIP 1.7's constants (FLIP paper, section 4 and table 1). */
#define FLIP_QC 0.7f
#define FLIP_PC 0.4f
#define FLIP_PT 0.95f
#define FLIP_W 0.082f /* degrees, the feature detector's width */
#define FLIP_QF 0.5f
#define FLIP_PI 3.14159265358979f

/* The largest filter radius taken (FLIP's at its default 67 pixels per
 * degree are 10 and 9). */
#define MAX_R 64

/* D65 reference white (XYZ) and its inverse, FLIP's values. */
static const float white[3] = {0.950428545f, 1.000000000f, 1.088900371f};
static const float inv_white[3] = {1.052156925f, 1.000000000f, 0.918357670f};

/* The ACES filmic fit FLIP uses (Narkowicz 2015) with FLIP's 0.6 pre-exposure
 * folded in: (c0 x^2 + c1 x + c2) / (c3 x^2 + c4 x + c5). */
static const float aces[6] = {0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f,
                              0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f};

/* Linear sRGB (Rec.709 primaries, D65) to XYZ and back. */
static inline void rgb_to_xyz(float r, float g, float b, float *x, float *y, float *z) {
  *x = (10135552.0f / 24577794.0f) * r + (8788810.0f / 24577794.0f) * g +
       (4435075.0f / 24577794.0f) * b;
  *y = (2613072.0f / 12288897.0f) * r + (8788810.0f / 12288897.0f) * g +
       (887015.0f / 12288897.0f) * b;
  *z = (1425312.0f / 73733382.0f) * r + (8788810.0f / 73733382.0f) * g +
       (70074185.0f / 73733382.0f) * b;
}

static inline void xyz_to_rgb(float x, float y, float z, float *r, float *g, float *b) {
  *r = 3.241003275f * x + -1.537398934f * y + -0.498615861f * z;
  *g = -0.969224334f * x + 1.875930071f * y + 0.041554224f * z;
  *b = 0.055639423f * x + -0.204011202f * y + 1.057148933f * z;
}

static inline float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

/* Cube root of t > 0: a first guess from the exponent bits (within a few
 * per cent), then two Halley steps, each tripling the correct digits (to
 * within an ulp or two of cbrtf, at a fraction of libm's cost; the 6 cube
 * roots a pixel takes per exposure were a quarter of the run time). */
static inline float cbrt_pos(float t) {
  union { float f; uint32_t u; } v = {t};
  v.u = v.u / 3u + 0x2a5137a0u;
  float y = v.f;
  for (int i = 0; i < 2; ++i) {
    float y3 = y * y * y;
    y = y * (y3 + 2.0f * t) / (2.0f * y3 + t);
  }
  return y;
}

/* CIE L*a*b* companding of one white-relative coordinate. */
static inline float lab_f(float t) {
  const float d = 6.0f / 29.0f;
  return t > d * d * d ? cbrt_pos(t) : t * (1.0f / (3.0f * d * d)) + 4.0f / 29.0f;
}

/* Linear RGB to Hunt-adjusted L*a*b*. */
static inline void rgb_to_lab_hunt(float r, float g, float b, float lab[3]) {
  float x, y, z;
  rgb_to_xyz(r, g, b, &x, &y, &z);
  float fx = lab_f(x * inv_white[0]), fy = lab_f(y * inv_white[1]), fz = lab_f(z * inv_white[2]);
  float L = 116.0f * fy - 16.0f;
  lab[0] = L;
  lab[1] = 0.01f * L * (500.0f * (fx - fy));
  lab[2] = 0.01f * L * (200.0f * (fy - fz));
}

static inline float hyab(const float p[3], const float q[3]) {
  float da = p[1] - q[1], db = p[2] - q[2];
  return fabsf(p[0] - q[0]) + sqrtf(da * da + db * db);
}

typedef struct flip_filters {
  int rc, rf;     /* radii of the colour (CSF) and feature filters */
  float *csf[4];  /* Y, Cx, Cz (first Gaussian), Cz (second), 2 rc + 1 taps */
  float *feat[3]; /* Gaussian, 1st and 2nd derivative, 2 rf + 1 taps */
  float cmax, pccmax;
  float *store;
} flip_filters;

/* The CSF Gaussians in FLIP's spatial form a sqrt(pi/b) exp(-pi^2 x^2 / b),
 * x in degrees (FLIP paper, equation 3 and table 1). */
static inline float csf_gauss(float x2, float a, float b) {
  return a * sqrtf(FLIP_PI / b) * expf(-(FLIP_PI * FLIP_PI) * x2 / b);
}

static int filters_init(flip_filters *f, float ppd) {
  /* Radius: three standard deviations of the widest CSF Gaussian (b = 0.04). */
  const float bmax = 0.04f;
  f->rc = (int)ceilf(3.0f * sqrtf(bmax / (2.0f * (FLIP_PI * FLIP_PI))) * ppd);
  const float sd = 0.5f * FLIP_W * ppd;
  f->rf = (int)ceilf(3.0f * sd);
  if (f->rc > MAX_R || f->rf > MAX_R) return 0;
  int nc = 2 * f->rc + 1, nf = 2 * f->rf + 1;
  f->store = malloc((size_t)(4 * nc + 3 * nf) * sizeof(float));
  if (!f->store) return 0;
  for (int i = 0; i < 4; ++i) f->csf[i] = f->store + i * nc;
  for (int i = 0; i < 3; ++i) f->feat[i] = f->store + 4 * nc + i * nf;

  /* Y and Cx: one Gaussian each, normalised to sum 1. Cz: a sum of two
   * Gaussians, each split into two equal 1D factors sqrt(a sqrt(pi/b))
   * exp(...), the pair scaled so that the 2D filter sums to 1. */
  const float a[4] = {1.0f, 1.0f, 34.1f, 13.5f};
  const float b[4] = {0.0047f, 0.0053f, 0.04f, 0.025f};
  float sum[4] = {0, 0, 0, 0};
  for (int k = 0; k < nc; ++k) {
    float x = (float)(k - f->rc) * (1.0f / ppd);
    float x2 = x * x;
    for (int c = 0; c < 4; ++c) {
      float v = c < 2 ? csf_gauss(x2, a[c], b[c])
                      : sqrtf(a[c] * sqrtf(FLIP_PI / b[c])) * expf(-(FLIP_PI * FLIP_PI) * x2 / b[c]);
      f->csf[c][k] = v;
      sum[c] += v;
    }
  }
  float cz_norm = 1.0f / sqrtf(sum[2] * sum[2] + sum[3] * sum[3]);
  for (int k = 0; k < nc; ++k) {
    f->csf[0][k] *= 1.0f / sum[0];
    f->csf[1][k] *= 1.0f / sum[1];
    f->csf[2][k] *= cz_norm;
    f->csf[3][k] *= cz_norm;
  }

  /* Feature filters: the Gaussian sums to 1, the derivatives' positive
   * taps to 1 and their negative taps to -1. */
  float gs = 0, d1p = 0, d1n = 0, d2p = 0, d2n = 0;
  for (int k = 0; k < nf; ++k) {
    float x = (float)(k - f->rf);
    float g = expf(-(x * x) / (2.0f * sd * sd));
    float d1 = -x * g, d2 = (x * x / (sd * sd) - 1.0f) * g;
    f->feat[0][k] = g;
    f->feat[1][k] = d1;
    f->feat[2][k] = d2;
    gs += g;
    if (d1 > 0.0f) d1p += d1;
    else d1n -= d1;
    if (d2 > 0.0f) d2p += d2;
    else d2n -= d2;
  }
  for (int k = 0; k < nf; ++k) {
    f->feat[0][k] /= gs;
    f->feat[1][k] /= f->feat[1][k] > 0.0f ? d1p : d1n;
    f->feat[2][k] /= f->feat[2][k] > 0.0f ? d2p : d2n;
  }

  /* cmax: the Hunt-adjusted HyAB distance of pure green and pure blue,
   * raised to qc. */
  float green[3], blue[3];
  rgb_to_lab_hunt(0.0f, 1.0f, 0.0f, green);
  rgb_to_lab_hunt(0.0f, 0.0f, 1.0f, blue);
  f->cmax = powf(hyab(green, blue), FLIP_QC);
  f->pccmax = FLIP_PC * f->cmax;
  return 1;
}

/* Horizontal-pass planes per image: the four CSF channels, then the
 * feature channel through the 1st derivative, the 2nd derivative and the
 * Gaussian. */
enum { H_Y, H_CX, H_CZ1, H_CZ2, H_DX, H_DDX, H_G, H_PLANES };

typedef struct flip_job {
  const flip_filters *f;
  const float *lin[2]; /* cleaned linear RGB, 3 floats a pixel: reference, test */
  uint32_t w, h;
  float scale;         /* 2^exposure */
  float *hp[2][H_PLANES];
  float *err;          /* running maximum over exposures */
} flip_job;

typedef struct flip_worker {
  flip_job *job;
  uint32_t y0, y1;
  float *scratch; /* max(4 (w + 2 pad), 16 VBLOCK) floats */
  int phase;
} flip_worker;

/* One row of one image, exposed and tone mapped, as YCxCz and normalised
 * achromatic channels into padded buffers (pad replicated edge pixels). */
static void row_to_ycxcz(const flip_job *j, const float *lin, int pad, float *Y, float *Cx,
                         float *Cz, float *Yn) {
  const float s = j->scale;
  for (uint32_t x = 0; x < j->w; ++x) {
    float rgb[3];
    for (int c = 0; c < 3; ++c) {
      float v = lin[3 * x + (uint32_t)c] * s;
      v = ((v * v) * aces[0] + v * aces[1] + aces[2]) / (v * v * aces[3] + v * aces[4] + aces[5]);
      rgb[c] = clamp01(v);
    }
    float X, Yv, Z;
    rgb_to_xyz(rgb[0], rgb[1], rgb[2], &X, &Yv, &Z);
    X *= inv_white[0];
    Yv *= inv_white[1];
    Z *= inv_white[2];
    float yy = 116.0f * Yv - 16.0f;
    size_t i = (size_t)pad + x;
    Y[i] = yy;
    Cx[i] = 500.0f * (X - Yv);
    Cz[i] = 200.0f * (Yv - Z);
    Yn[i] = yy * (1.0f / 116.0f) + 16.0f / 116.0f;
  }
  size_t last = (size_t)pad + j->w - 1;
  for (int k = 0; k < pad; ++k) {
    Y[k] = Y[pad], Cx[k] = Cx[pad], Cz[k] = Cz[pad], Yn[k] = Yn[pad];
    Y[last + 1 + (size_t)k] = Y[last], Cx[last + 1 + (size_t)k] = Cx[last];
    Cz[last + 1 + (size_t)k] = Cz[last], Yn[last + 1 + (size_t)k] = Yn[last];
  }
}

/* Every filter is symmetric (odd = 0: wt[r - k] = wt[r + k]) or, the first
 * derivative, antisymmetric (odd = 1: wt[r - k] = -wt[r + k]), so the taps
 * at -k and +k share one multiply. The sums run four pixels at a time in
 * GCC/Clang vector types (SSE on x86-64, NEON on ARM, at any -O), each
 * pixel's taps in order -- the same arithmetic as one pixel at a time. */
typedef float v4f __attribute__((vector_size(16)));

static inline v4f ld4(const float *p) {
  v4f v;
  memcpy(&v, p, sizeof v);
  return v;
}

/* out[x] = sum_{k=-r..r} wt[r + k] src[k][x], x < n, where src[k] is the
 * row k below (k > 0) or above the centre src[0]; src points at src[0]. */
static void conv_taps(float *restrict out, const float *const *src, const float *restrict wt,
                      int r, int odd, uint32_t n) {
  const float c0 = wt[r];
  uint32_t x = 0;
  for (; x + 4 <= n; x += 4) {
    v4f acc = c0 * ld4(src[0] + x);
    if (odd)
      for (int k = 1; k <= r; ++k) acc += wt[r + k] * (ld4(src[k] + x) - ld4(src[-k] + x));
    else
      for (int k = 1; k <= r; ++k) acc += wt[r + k] * (ld4(src[k] + x) + ld4(src[-k] + x));
    memcpy(out + x, &acc, sizeof acc);
  }
  for (; x < n; ++x) {
    float acc = c0 * src[0][x];
    for (int k = 1; k <= r; ++k)
      acc += wt[r + k] * (odd ? src[k][x] - src[-k][x] : src[k][x] + src[-k][x]);
    out[x] = acc;
  }
}

/* out[x] = sum_{k=-r..r} wt[r + k] in[x + k] (in: the row at its first
 * pixel, r readable values each side). */
static void conv_row(float *restrict out, const float *in, const float *restrict wt, int r,
                     int odd, uint32_t w) {
  const float *src[2 * MAX_R + 1];
  for (int k = -r; k <= r; ++k) src[MAX_R + k] = in + k;
  conv_taps(out, src + MAX_R, wt, r, odd, w);
}

static void horizontal(flip_worker *wk) {
  flip_job *j = wk->job;
  const flip_filters *f = j->f;
  const int pad = f->rc > f->rf ? f->rc : f->rf;
  const size_t pw = (size_t)j->w + 2 * (size_t)pad;
  float *Y = wk->scratch, *Cx = Y + pw, *Cz = Cx + pw, *Yn = Cz + pw;
  for (uint32_t y = wk->y0; y < wk->y1; ++y) {
    size_t row = (size_t)y * j->w;
    for (int im = 0; im < 2; ++im) {
      row_to_ycxcz(j, j->lin[im] + 3 * row, pad, Y, Cx, Cz, Yn);
      float *const *hp = j->hp[im];
      conv_row(hp[H_Y] + row, Y + pad, f->csf[0], f->rc, 0, j->w);
      conv_row(hp[H_CX] + row, Cx + pad, f->csf[1], f->rc, 0, j->w);
      conv_row(hp[H_CZ1] + row, Cz + pad, f->csf[2], f->rc, 0, j->w);
      conv_row(hp[H_CZ2] + row, Cz + pad, f->csf[3], f->rc, 0, j->w);
      conv_row(hp[H_DX] + row, Yn + pad, f->feat[1], f->rf, 1, j->w);
      conv_row(hp[H_DDX] + row, Yn + pad, f->feat[2], f->rf, 0, j->w);
      conv_row(hp[H_G] + row, Yn + pad, f->feat[0], f->rf, 0, j->w);
    }
  }
}

/* out[x] = sum_{k=-r..r} wt[r + k] plane[clamp(y + k)][x0 + x], x < n. */
static void conv_col(float *restrict out, const float *plane, const float *restrict wt, int r,
                     int odd, uint32_t y, uint32_t x0, uint32_t n, uint32_t w, uint32_t h) {
  const float *src[2 * MAX_R + 1];
  for (int k = -r; k <= r; ++k) {
    long yy = (long)y + k;
    if (yy < 0) yy = 0;
    if (yy > (long)h - 1) yy = (long)h - 1;
    src[MAX_R + k] = plane + (size_t)yy * w + x0;
  }
  conv_taps(out, src + MAX_R, wt, r, odd, n);
}

/* Filtered YCxCz back to clamped linear RGB, then Hunt-adjusted L*a*b*. */
static inline void ycxcz_to_lab_hunt(float Y, float Cx, float Cz, float lab[3]) {
  float yy = (Y + 16.0f) / 116.0f;
  float X = (yy + Cx / 500.0f) * white[0], Yv = yy * white[1], Z = (yy - Cz / 200.0f) * white[2];
  float r, g, b;
  xyz_to_rgb(X, Yv, Z, &r, &g, &b);
  rgb_to_lab_hunt(clamp01(r), clamp01(g), clamp01(b), lab);
}

/* Columns are taken in blocks of VBLOCK so that the rows under the filters
 * stay in cache from one output row to the next. */
#define VBLOCK 256u

static void vertical(flip_worker *wk) {
  flip_job *j = wk->job;
  const flip_filters *f = j->f;
  const uint32_t w = j->w, h = j->h;
  float *acc[2][8];
  for (int im = 0; im < 2; ++im)
    for (int c = 0; c < 8; ++c) acc[im][c] = wk->scratch + (size_t)(im * 8 + c) * VBLOCK;
  const float norm = 1.0f / sqrtf(2.0f);
  for (uint32_t x0 = 0; x0 < w; x0 += VBLOCK) {
    const uint32_t n = w - x0 < VBLOCK ? w - x0 : VBLOCK;
    for (uint32_t y = wk->y0; y < wk->y1; ++y) {
      for (int im = 0; im < 2; ++im) {
        float *const *hp = j->hp[im];
        float **a = acc[im];
        for (int c = 0; c < 4; ++c) conv_col(a[c], hp[H_Y + c], f->csf[c], f->rc, 0, y, x0, n, w, h);
        conv_col(a[4], hp[H_DX], f->feat[0], f->rf, 0, y, x0, n, w, h);  /* d/dx */
        conv_col(a[5], hp[H_DDX], f->feat[0], f->rf, 0, y, x0, n, w, h); /* d2/dx2 */
        conv_col(a[6], hp[H_G], f->feat[1], f->rf, 1, y, x0, n, w, h);   /* d/dy */
        conv_col(a[7], hp[H_G], f->feat[2], f->rf, 0, y, x0, n, w, h);   /* d2/dy2 */
      }
      float *err = j->err + (size_t)y * w + x0;
      for (uint32_t x = 0; x < n; ++x) {
        float lab[2][3], edge[2], point[2];
        for (int im = 0; im < 2; ++im) {
          float **a = acc[im];
          ycxcz_to_lab_hunt(a[0][x], a[1][x], a[2][x] + a[3][x], lab[im]);
          edge[im] = sqrtf(a[4][x] * a[4][x] + a[6][x] * a[6][x]);
          point[im] = sqrtf(a[5][x] * a[5][x] + a[7][x] * a[7][x]);
        }
        float cd = powf(hyab(lab[0], lab[1]), FLIP_QC);
        if (cd < f->pccmax) cd *= FLIP_PT / f->pccmax;
        else cd = FLIP_PT + ((cd - f->pccmax) / (f->cmax - f->pccmax)) * (1.0f - FLIP_PT);
        float de = fabsf(edge[0] - edge[1]), dp = fabsf(point[0] - point[1]);
        float fd = sqrtf(norm * (de > dp ? de : dp)); /* ^qf, qf = 1/2 */
        float e = powf(cd, 1.0f - fd);
        if (e > err[x]) err[x] = e;
      }
    }
  }
}

static void worker_run(void *user, uint32_t item, uint32_t thread) {
  (void)thread;
  flip_worker *wk = (flip_worker *)user + item;
  if (wk->phase == 0) horizontal(wk);
  else vertical(wk);
}

/* Runs one phase over all rows, each worker's band once (core/parallel.h);
 * one worker runs on this thread. */
static void run_phase(flip_worker *wk, int n, int phase) {
  for (int i = 0; i < n; ++i) wk[i].phase = phase;
  if (n > 1) {
    if (pb_parallel_for((uint32_t)n, (uint32_t)n, worker_run, wk, NULL, NULL) == PB_OK) return;
    pb_error_clear(); /* no thread could start: the bands in turn here */
  }
  for (int i = 0; i < n; ++i) worker_run(wk, (uint32_t)i, 0);
}

static int thread_count(uint32_t w, uint32_t h) {
  if ((uint64_t)w * h < 256u * 256u) return 1; /* threads cost more than they save */
  long n = (long)pb_cpu_count();
  if (n > 16) n = 16;
  if ((long)h / 32 < n) n = (long)h / 32 > 0 ? (long)h / 32 : 1;
  return (int)n;
}

/* The k-th smallest of v[0..n) (v reordered). */
static float select_kth(float *v, size_t n, size_t k) {
  size_t lo = 0, hi = n - 1;
  while (lo < hi) {
    float p = v[lo + (hi - lo) / 2];
    size_t i = lo, jj = hi;
    while (i <= jj) {
      while (v[i] < p) ++i;
      while (v[jj] > p) --jj;
      if (i <= jj) {
        float t = v[i];
        v[i] = v[jj];
        v[jj] = t;
        ++i;
        if (jj == 0) break;
        --jj;
      }
    }
    if (k <= jj) hi = jj;
    else if (k >= i) lo = i;
    else return v[k];
  }
  return v[k];
}

/* FLIP's exposure range from the reference's luminances: the exposures at
 * which its largest and its median luminance (at least FLT_EPSILON) tone
 * map to 0.85. Returns 0 when the range is undefined. */
static int exposure_range(const float *lin, size_t n, float *lum, float *start, float *stop) {
  const float t = 0.85f;
  float a = aces[0] - t * aces[3], b = aces[1] - t * aces[4], c = aces[2] - t * aces[5];
  float d1 = -0.5f * (b / a), d2 = sqrtf(d1 * d1 - c / a);
  float xmax = d1 + d2;
  float ymax = -1e30f;
  for (size_t i = 0; i < n; ++i) {
    const float *p = lin + 3 * i;
    lum[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
    if (lum[i] > ymax) ymax = lum[i];
  }
  float ymed = select_kth(lum, n, n / 2);
  if (ymed < FLT_EPSILON) ymed = FLT_EPSILON;
  if (!(ymax > 0.0f)) return 0;
  *start = log2f(xmax / ymax);
  *stop = log2f(xmax / ymed);
  return isfinite(*start) && isfinite(*stop) && *start <= *stop;
}

pb_result pb_flip_hdr(const float *test, const float *ref, uint32_t w, uint32_t h,
                      uint32_t ch, float *error_map, pb_flip_result *out) {
  if (!test || !ref || !out || w == 0 || h == 0 || (ch != 3 && ch != 4))
    return pb_fail(PB_ERR_USAGE, "FLIP: bad image (%ux%u, %u channels)", w, h, ch);
  memset(out, 0, sizeof *out);
  const size_t n = (size_t)w * h;
  flip_filters f;
  memset(&f, 0, sizeof f);
  const int nthreads = thread_count(w, h);
  flip_worker wk[16];
  memset(wk, 0, sizeof wk);
  float *lin = malloc(6 * n * sizeof *lin);
  float *planes = malloc(2 * H_PLANES * n * sizeof *planes);
  float *err = error_map ? error_map : malloc(n * sizeof *err);
  int ok = lin && planes && err && filters_init(&f, PB_FLIP_DEFAULT_PPD);
  const int pad = f.rc > f.rf ? f.rc : f.rf;
  size_t scratch = 4 * ((size_t)w + 2 * (size_t)pad);
  if (scratch < 16 * (size_t)VBLOCK) scratch = 16 * (size_t)VBLOCK;
  for (int i = 0; ok && i < nthreads; ++i) ok = (wk[i].scratch = malloc(scratch * sizeof(float))) != NULL;
  pb_result r = PB_OK;
  if (!ok) {
    r = pb_fail(PB_ERR_NOMEM, "FLIP: out of memory for %ux%u images", w, h);
    goto done;
  }

  /* Cleaned copies: negative and non-finite values to 0. */
  for (size_t i = 0; i < n; ++i) {
    int bad = 0;
    for (int im = 0; im < 2; ++im) {
      const float *src = (im ? test : ref) + i * ch;
      float *dst = lin + (size_t)im * 3 * n + 3 * i;
      for (int c = 0; c < 3; ++c) {
        float v = src[c];
        if (!(v >= 0.0f) || !isfinite(v)) v = 0.0f, bad = 1;
        dst[c] = v;
      }
    }
    out->zeroed_pixels += (uint64_t)bad;
  }
  memset(err, 0, n * sizeof *err);
  /* The luminance scratch borrows the first plane. */
  if (!exposure_range(lin, n, planes, &out->start_exposure, &out->stop_exposure)) goto done;
  out->defined = 1;
  float span = out->stop_exposure - out->start_exposure;
  out->exposures = (int)fmaxf(2.0f, ceilf(span));
  float step = span / (float)(out->exposures - 1);

  flip_job job;
  memset(&job, 0, sizeof job);
  job.f = &f;
  job.lin[0] = lin;
  job.lin[1] = lin + 3 * n;
  job.w = w;
  job.h = h;
  job.err = err;
  for (int im = 0; im < 2; ++im)
    for (int p = 0; p < H_PLANES; ++p) job.hp[im][p] = planes + (size_t)(im * H_PLANES + p) * n;
  for (int i = 0; i < nthreads; ++i) {
    wk[i].job = &job;
    wk[i].y0 = (uint32_t)((uint64_t)h * (uint64_t)i / (uint64_t)nthreads);
    wk[i].y1 = (uint32_t)((uint64_t)h * (uint64_t)(i + 1) / (uint64_t)nthreads);
  }
  for (int e = 0; e < out->exposures; ++e) {
    job.scale = exp2f(out->start_exposure + (float)e * step);
    run_phase(wk, nthreads, 0);
    run_phase(wk, nthreads, 1);
  }
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) sum += err[i];
  out->mean = sum / (double)n;

done:
  for (int i = 0; i < nthreads; ++i) free(wk[i].scratch);
  if (err != error_map) free(err);
  free(planes);
  free(lin);
  free(f.store);
  return r;
}

/* FLIP's magma table (matplotlib's magma, 256 entries) as FLIP's tools
 * write it: each value v as round(255 v). */
static const uint8_t magma[256][3] = {
    {0, 0, 4}, {1, 0, 5}, {1, 1, 6}, {1, 1, 8}, {2, 1, 9}, {2, 2, 11}, {2, 2, 13}, {3, 3, 15},
    {3, 3, 18}, {4, 4, 20}, {5, 4, 22}, {6, 5, 24}, {6, 5, 26}, {7, 6, 28}, {8, 7, 30}, {9, 7, 32},
    {10, 8, 34}, {11, 9, 36}, {12, 9, 38}, {13, 10, 41}, {14, 11, 43}, {16, 11, 45}, {17, 12, 47}, {18, 13, 49},
    {19, 13, 52}, {20, 14, 54}, {21, 14, 56}, {22, 15, 59}, {24, 15, 61}, {25, 16, 63}, {26, 16, 66}, {28, 16, 68},
    {29, 17, 71}, {30, 17, 73}, {32, 17, 75}, {33, 17, 78}, {34, 17, 80}, {36, 18, 83}, {37, 18, 85}, {39, 18, 88},
    {41, 17, 90}, {42, 17, 92}, {44, 17, 95}, {45, 17, 97}, {47, 17, 99}, {49, 17, 101}, {51, 16, 103}, {52, 16, 105},
    {54, 16, 107}, {56, 16, 108}, {57, 15, 110}, {59, 15, 112}, {61, 15, 113}, {63, 15, 114}, {64, 15, 116}, {66, 15, 117},
    {68, 15, 118}, {69, 16, 119}, {71, 16, 120}, {73, 16, 120}, {74, 16, 121}, {76, 17, 122}, {78, 17, 123}, {79, 18, 123},
    {81, 18, 124}, {82, 19, 124}, {84, 19, 125}, {86, 20, 125}, {87, 21, 126}, {89, 21, 126}, {90, 22, 126}, {92, 22, 127},
    {93, 23, 127}, {95, 24, 127}, {96, 24, 128}, {98, 25, 128}, {100, 26, 128}, {101, 26, 128}, {103, 27, 128}, {104, 28, 129},
    {106, 28, 129}, {107, 29, 129}, {109, 29, 129}, {110, 30, 129}, {112, 31, 129}, {114, 31, 129}, {115, 32, 129}, {117, 33, 129},
    {118, 33, 129}, {120, 34, 129}, {121, 34, 130}, {123, 35, 130}, {124, 35, 130}, {126, 36, 130}, {128, 37, 130}, {129, 37, 129},
    {131, 38, 129}, {132, 38, 129}, {134, 39, 129}, {136, 39, 129}, {137, 40, 129}, {139, 41, 129}, {140, 41, 129}, {142, 42, 129},
    {144, 42, 129}, {145, 43, 129}, {147, 43, 128}, {148, 44, 128}, {150, 44, 128}, {152, 45, 128}, {153, 45, 128}, {155, 46, 127},
    {156, 46, 127}, {158, 47, 127}, {160, 47, 127}, {161, 48, 126}, {163, 48, 126}, {165, 49, 126}, {166, 49, 125}, {168, 50, 125},
    {170, 51, 125}, {171, 51, 124}, {173, 52, 124}, {174, 52, 123}, {176, 53, 123}, {178, 53, 123}, {179, 54, 122}, {181, 54, 122},
    {183, 55, 121}, {184, 55, 121}, {186, 56, 120}, {188, 57, 120}, {189, 57, 119}, {191, 58, 119}, {192, 58, 118}, {194, 59, 117},
    {196, 60, 117}, {197, 60, 116}, {199, 61, 115}, {200, 62, 115}, {202, 62, 114}, {204, 63, 113}, {205, 64, 113}, {207, 64, 112},
    {208, 65, 111}, {210, 66, 111}, {211, 67, 110}, {213, 68, 109}, {214, 69, 108}, {216, 69, 108}, {217, 70, 107}, {219, 71, 106},
    {220, 72, 105}, {222, 73, 104}, {223, 74, 104}, {224, 76, 103}, {226, 77, 102}, {227, 78, 101}, {228, 79, 100}, {229, 80, 100},
    {231, 82, 99}, {232, 83, 98}, {233, 84, 98}, {234, 86, 97}, {235, 87, 96}, {236, 88, 96}, {237, 90, 95}, {238, 91, 94},
    {239, 93, 94}, {240, 95, 94}, {241, 96, 93}, {242, 98, 93}, {242, 100, 92}, {243, 101, 92}, {244, 103, 92}, {244, 105, 92},
    {245, 107, 92}, {246, 108, 92}, {246, 110, 92}, {247, 112, 92}, {247, 114, 92}, {248, 116, 92}, {248, 118, 92}, {249, 120, 93},
    {249, 121, 93}, {249, 123, 93}, {250, 125, 94}, {250, 127, 94}, {250, 129, 95}, {251, 131, 95}, {251, 133, 96}, {251, 135, 97},
    {252, 137, 97}, {252, 138, 98}, {252, 140, 99}, {252, 142, 100}, {252, 144, 101}, {253, 146, 102}, {253, 148, 103}, {253, 150, 104},
    {253, 152, 105}, {253, 154, 106}, {253, 155, 107}, {254, 157, 108}, {254, 159, 109}, {254, 161, 110}, {254, 163, 111}, {254, 165, 113},
    {254, 167, 114}, {254, 169, 115}, {254, 170, 116}, {254, 172, 118}, {254, 174, 119}, {254, 176, 120}, {254, 178, 122}, {254, 180, 123},
    {254, 182, 124}, {254, 183, 126}, {254, 185, 127}, {254, 187, 129}, {254, 189, 130}, {254, 191, 132}, {254, 193, 133}, {254, 194, 135},
    {254, 196, 136}, {254, 198, 138}, {254, 200, 140}, {254, 202, 141}, {254, 204, 143}, {254, 205, 144}, {254, 207, 146}, {254, 209, 148},
    {254, 211, 149}, {254, 213, 151}, {254, 215, 153}, {254, 216, 154}, {253, 218, 156}, {253, 220, 158}, {253, 222, 160}, {253, 224, 161},
    {253, 226, 163}, {253, 227, 165}, {253, 229, 167}, {253, 231, 169}, {253, 233, 170}, {253, 235, 172}, {252, 236, 174}, {252, 238, 176},
    {252, 240, 178}, {252, 242, 180}, {252, 244, 182}, {252, 246, 184}, {252, 247, 185}, {252, 249, 187}, {252, 251, 189}, {252, 253, 191},
};

void pb_flip_magma(float e, uint8_t rgb[3]) {
  if (!(e > 0.0f)) e = 0.0f;
  if (e > 1.0f) e = 1.0f;
  int i = (int)(e * 255.0f + 0.5f) % 256;
  memcpy(rgb, magma[i], 3);
}
