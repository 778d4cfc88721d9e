/* Calibration of the reference against POV-Ray 3.7 with
 * thresholds that fail.
 *
 *   direct light only (reference --max-bounces 1, POV-Ray `direct`: no
 *   radiosity, no photons, no antialiasing) on a Lambertian plane (albedo 0.8)
 *   under a point, a spot and a directional light, and on cornell_box:
 *   mean over pixels of |pov - ref| / ref within 1 %. Spots: only pixels
 *   inside the inner cone (< 17 deg, the cone is 20) and outside the outer
 *   one (> 33 deg, the cone is 30; a 33x33 pixel spans up to 2.5 deg; there both must be 0), i.e. never in the
 *   smooth-step band. cornell_box: only pixels whose 4 neighbours are within
 *   10 % in the reference (no silhouettes or shadow edges, where a box-filtered
 *   pixel and POV-Ray's pixel-centre sample differ by construction).
 *
 *   cornell_caustics: the caustic alone (reference SPPM minus PT, both at
 *   max 3 bounces; POV-Ray photons without radiosity minus `direct`), its
 *   centroid (luminance-weighted, pixels over 20 % of the peak after a 3x3
 *   blur) in both within 2 % of the image width.
 *
 *   full GI on cornell_box against POV-Ray radiosity (medium): PSNR and
 *   relMSE printed, not gated (radiosity gathers a limited number of bounces;
 *   see validation/README.md).
 *
 * Invocations: no argument: the plane cases and the caustic; --cornell-direct;
 * --gi (tests/validate.cmake registers each).
 *
 * Renders are 33x33 (plane) and 64x64 (Cornell scenes), POV-Ray single
 * threaded. Exit 77 (skip) without povray. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/image.h"
#include "metrics/metrics.h"
#include "pbtest.h"
#include "pov/pov.h"
#include "ref/ref.h"
#include "test_pov_scene.h"

static char tmpdir[] = "/tmp/pb_test_validate_calib.XXXXXX";
static const float rho = 0.8f;

/* POV-Ray render of camera `cam`, returned as packed RGB (w*h*3). `strip_radiosity`
 * removes the radiosity block (photons only). */
static float *pov_render(const pb_scene *s, int cam, const char *name, uint32_t w, uint32_t h,
                         pb_pov_quality q, int strip_radiosity, double *secs) {
  char pov[256], exr[300], cmd[1024];
  snprintf(pov, sizeof pov, "%s/%s.pov", tmpdir, name);
  snprintf(exr, sizeof exr, "%s/%s.exr", tmpdir, name);
  pb_pov_desc d = {.width = w, .height = h, .camera = cam, .quality = q};
  if (pb_pov_export(s, &d, pov, NULL) != PB_OK) {
    fprintf(stderr, "export failed: %s\n", pb_error_message());
    return NULL;
  }
  if (strip_radiosity) {
    FILE *f = fopen(pov, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *t = malloc((size_t)n + 1);
    if (!t || fread(t, 1, (size_t)n, f) != (size_t)n) abort();
    t[n] = 0;
    fclose(f);
    char *a = strstr(t, "  radiosity {"), *b = a ? strstr(a, "\n  }\n") : NULL;
    if (!a || !b) {
      fprintf(stderr, "%s: no radiosity block to strip\n", pov);
      free(t);
      return NULL;
    }
    b += 5;
    memmove(a, b, strlen(b) + 1);
    f = fopen(pov, "wb");
    if (!f) abort();
    fputs(t, f);
    fclose(f);
    free(t);
  }
  snprintf(cmd, sizeof cmd, "sh validation/run_povray.sh '%s' '%s' -- -A +WT1 >/dev/null", pov, exr);
  if (system(cmd) != 0) {
    fprintf(stderr, "povray failed on %s (log %s.log)\n", pov, exr);
    return NULL;
  }
  if (secs) {
    char log[320], line[256];
    snprintf(log, sizeof log, "%s.log", exr);
    FILE *f = fopen(log, "r");
    *secs = NAN;
    while (f && fgets(line, sizeof line, f))
      if (strncmp(line, "wall_s=", 7) == 0) *secs = atof(line + 7);
    if (f) fclose(f);
  }
  pb_image img;
  if (pb_exr_read(exr, NULL, &img) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return NULL;
  }
  int c[3] = {pb_image_find_channel(&img, "R"), pb_image_find_channel(&img, "G"),
              pb_image_find_channel(&img, "B")};
  float *rgb = NULL;
  if (img.width == w && img.height == h && c[0] >= 0 && c[1] >= 0 && c[2] >= 0) {
    rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    for (size_t i = 0; rgb && i < (size_t)w * h; ++i)
      for (int k = 0; k < 3; ++k) rgb[3 * i + k] = img.pixels[i * img.channel_count + (size_t)c[k]];
  } else {
    fprintf(stderr, "%s: %ux%u, expected %ux%u with R, G, B\n", exr, img.width, img.height, w, h);
  }
  pb_image_destroy(&img);
  return rgb;
}

/* Reference render; returns packed RGB of the beauty (RGBA in the result). */
static float *ref_render(const pb_scene *s, int cam, uint32_t w, uint32_t h, uint32_t spp,
                         uint32_t bounces, pb_ref_mode mode, double *secs) {
  pb_ref_desc d = {.spp = spp, .max_bounces = bounces, .seed = 1, .mode = mode, .threads = 2};
  pb_ref_result r;
  if (pb_ref_render(s, cam, w, h, &d, &r) != PB_OK) {
    fprintf(stderr, "reference failed: %s\n", pb_error_message());
    return NULL;
  }
  if (secs) *secs = r.stats.time_s;
  float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
  for (size_t i = 0; rgb && i < (size_t)w * h; ++i)
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = r.beauty[4 * i + k];
  pb_ref_result_destroy(&r);
  return rgb;
}

static double lum(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

/* Mean over masked pixels (and channels with ref > floor) of |t - r| / r. */
static double mean_rel(const float *t, const float *r, uint32_t n, const unsigned char *mask,
                       double floor, uint32_t *count) {
  double s = 0;
  uint32_t c = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (mask && !mask[i]) continue;
    for (int k = 0; k < 3; ++k) {
      double rv = r[3 * i + k];
      if (rv <= floor) continue;
      s += fabs(t[3 * i + k] - rv) / rv;
      ++c;
    }
  }
  if (count) *count = c;
  return c ? s / c : NAN;
}

/* Ratio of summed luminance over the mask (a bias check next to mean_rel). */
static double sum_ratio(const float *t, const float *r, uint32_t n, const unsigned char *mask) {
  double a = 0, b = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (!mask || mask[i]) {
      a += lum(t + 3 * i);
      b += lum(r + 3 * i);
    }
  return a / b;
}

/* Plane at y = 0, camera 3 m above looking down at +-1 m: 33x33 pixels. */
enum { PW = 33 };
static const double cam_h = 3.0, half_extent = 1.0;

/* Angle from the vertical under a light 1 m above the origin, at pixel (x, y). */
static double pixel_angle(uint32_t x, uint32_t y) {
  double u = ((x + 0.5) / PW * 2 - 1) * half_extent, v = ((y + 0.5) / PW * 2 - 1) * half_extent;
  return atan(sqrt(u * u + v * v)) * 180 / M_PI;
}

static void plane_case(const char *name, pb_light_type type) {
  pb_scene s;
  tps_init(&s);
  uint32_t m = tps_material(&s, "albedo08", rho, rho, rho);
  tps_quad_y(&s, -20, 20, -20, 20, 0, m);
  pb_light *l = tps_light(&s, type, name);
  if (type == PB_LIGHT_DIRECTIONAL) {
    l->direction[0] = 0.5f;
    l->direction[1] = -(float)sqrt(0.75);
    l->intensity = 4;
  } else {
    l->position[1] = 1;
    l->intensity = 100.0f / (4.0f * (float)M_PI);
    if (type == PB_LIGHT_SPOT) {
      l->inner_cone = 20.0f * (float)M_PI / 180;
      l->outer_cone = 30.0f * (float)M_PI / 180;
    }
  }
  tps_camera_down(&s, "top", 0, (float)cam_h, 0, (float)(2 * atan(half_extent / cam_h) * 180 / M_PI));
  pb_scene_finalize(&s);
  double tr = 0, tp = 0;
  float *ref = ref_render(&s, 0, PW, PW, 16, 1, PB_REF_MODE_PT, &tr);
  float *pov = pov_render(&s, 0, name, PW, PW, PB_POV_DIRECT, 0, &tp);
  CHECK(ref && pov);
  if (ref && pov) {
    unsigned char mask[PW * PW];
    uint32_t outside = 0, outside_bad = 0;
    for (uint32_t y = 0; y < PW; ++y)
      for (uint32_t x = 0; x < PW; ++x) {
        uint32_t i = y * PW + x;
        mask[i] = 1;
        if (type == PB_LIGHT_SPOT) {
          double a = pixel_angle(x, y);
          mask[i] = a < 17.0;
          if (a > 33.0) {
            ++outside;
            if (lum(ref + 3 * i) != 0 || lum(pov + 3 * i) != 0) ++outside_bad;
          }
        }
      }
    uint32_t n = 0;
    double e = mean_rel(pov, ref, PW * PW, mask, 1e-6, &n);
    printf("plane, %-11s %ux%u, ref 16 spp (%.2f s), POV-Ray direct -A (%.2f s): mean rel. error "
           "%.4f %% over %u values, sum ratio %.5f\n",
           name, PW, PW, tr, tp, 100 * e, n, sum_ratio(pov, ref, PW * PW, mask));
    CHECK(n > 100);
    CHECK(e < 0.01);
    if (type == PB_LIGHT_SPOT) {
      printf("  spot: %u pixels outside the outer cone, %u not black in either\n", outside, outside_bad);
      CHECK(outside > 50);
      CHECK_EQ_INT(outside_bad, 0);
    }
  }
  free(ref);
  free(pov);
  pb_scene_destroy(&s);
}

static int load(const char *path, pb_scene *s) {
  pb_load_desc ld = {0};
  if (pb_scene_load(path, &ld, s) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return 0;
  }
  return 1;
}

/* Pixels whose 4 neighbours are within `tol` (relative luminance) in `img`. */
static void smooth_mask(const float *img, uint32_t w, uint32_t h, double tol, unsigned char *mask) {
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      uint32_t i = y * w + x;
      double c = lum(img + 3 * i);
      int ok = x > 0 && y > 0 && x + 1 < w && y + 1 < h && c > 1e-4;
      if (ok) {
        const uint32_t nb[4] = {i - 1, i + 1, i - w, i + w};
        for (int k = 0; k < 4; ++k)
          if (fabs(lum(img + 3 * nb[k]) - c) > tol * c) ok = 0;
      }
      mask[i] = (unsigned char)ok;
    }
}

enum { CW = 64 };

static void cornell_direct(void) {
  pb_scene s;
  if (!load("samples/cornell_box/cornell_box.gltf", &s)) {
    CHECK(0);
    return;
  }
  double tr = 0, tp = 0;
  float *ref = ref_render(&s, 0, CW, CW, 64, 1, PB_REF_MODE_PT, &tr);
  float *pov = pov_render(&s, 0, "cb_direct", CW, CW, PB_POV_DIRECT, 0, &tp);
  CHECK(ref && pov);
  if (ref && pov) {
    unsigned char mask[CW * CW];
    smooth_mask(ref, CW, CW, 0.10, mask);
    uint32_t n = 0, px = 0;
    for (int i = 0; i < CW * CW; ++i) px += mask[i];
    double e = mean_rel(pov, ref, CW * CW, mask, 1e-4, &n);
    printf("cornell_box direct %ux%u, ref 64 spp max-bounces 1 (%.2f s), POV-Ray direct -A (%.2f s): "
           "mean rel. error %.4f %% over %u pixels (%u values; smooth regions), sum ratio %.5f\n",
           CW, CW, tr, tp, 100 * e, px, n, sum_ratio(pov, ref, CW * CW, mask));
    /* Coverage floor: at 64x64 the steep fall-off near the light, the
     * edges and the shadows leave 1126 of 4096 pixels (27 %) within 10 % of
     * their neighbours (measured 2026-11-22); a fifth of the image keeps the
     * comparison meaningful while the noise of the 64-spp reference moves
     * the mask a little. The accuracy limit is the point of the test. */
    CHECK(px > CW * CW / 5);
    CHECK(e < 0.01);
  }
  free(ref);
  free(pov);
  pb_scene_destroy(&s);
}

/* Centroid (pixels) of the positive part of a - b, blurred 3x3, over pixels
 * above `frac` of the peak. Returns the weight. */
static double caustic_centroid(const float *a, const float *b, uint32_t w, uint32_t h, double frac,
                               double *cx, double *cy) {
  double *d = calloc((size_t)w * h, sizeof *d), *bl = calloc((size_t)w * h, sizeof *bl);
  for (uint32_t i = 0; i < w * h; ++i) d[i] = fmax(0.0, lum(a + 3 * i) - lum(b + 3 * i));
  double peak = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      double s = 0;
      int c = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int xx = (int)x + dx, yy = (int)y + dy;
          if (xx < 0 || yy < 0 || xx >= (int)w || yy >= (int)h) continue;
          s += d[(uint32_t)yy * w + (uint32_t)xx];
          ++c;
        }
      bl[y * w + x] = s / c;
      if (bl[y * w + x] > peak) peak = bl[y * w + x];
    }
  double sw = 0, sx = 0, sy = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      double v = bl[y * w + x];
      if (v < frac * peak) continue;
      sw += v;
      sx += v * (x + 0.5);
      sy += v * (y + 0.5);
    }
  *cx = sx / sw;
  *cy = sy / sw;
  free(d);
  free(bl);
  return sw;
}

static void cornell_caustic(void) {
  pb_scene s;
  if (!load("samples/cornell_caustics/cornell_caustics.gltf", &s)) {
    CHECK(0);
    return;
  }
  double t1 = 0, t2 = 0, t3 = 0, t4 = 0;
  float *sp = ref_render(&s, 0, CW, CW, 32, 3, PB_REF_MODE_SPPM, &t1);
  float *pt = ref_render(&s, 0, CW, CW, 32, 3, PB_REF_MODE_PT, &t2);
  float *ph = pov_render(&s, 0, "cc_photons", CW, CW, PB_POV_MEDIUM, 1, &t3);
  float *di = pov_render(&s, 0, "cc_direct", CW, CW, PB_POV_DIRECT, 0, &t4);
  CHECK(sp && pt && ph && di);
  if (sp && pt && ph && di) {
    double rx, ry, px, py;
    double rw = caustic_centroid(sp, pt, CW, CW, 0.2, &rx, &ry);
    double pw = caustic_centroid(ph, di, CW, CW, 0.2, &px, &py);
    double dist = hypot(rx - px, ry - py) / CW;
    printf("cornell_caustics %ux%u caustic centroid: reference SPPM-PT 32 spp (%.2f+%.2f s) (%.2f, %.2f) "
           "px, POV-Ray photons(medium, no radiosity)-direct (%.2f+%.2f s) (%.2f, %.2f) px: "
           "distance %.2f %% of the width; summed caustic ratio POV/ref %.3f\n",
           CW, CW, t1, t2, rx, ry, t3, t4, px, py, 100 * dist, pw / rw);
    CHECK(rw > 0 && pw > 0);
    CHECK(dist < 0.02);
  }
  free(sp);
  free(pt);
  free(ph);
  free(di);
  pb_scene_destroy(&s);
}

static void cornell_gi(void) {
  pb_scene s;
  if (!load("samples/cornell_box/cornell_box.gltf", &s)) {
    CHECK(0);
    return;
  }
  double tr = 0, tp = 0;
  float *ref = ref_render(&s, 0, CW, CW, 64, 8, PB_REF_MODE_PT, &tr);
  float *pov = pov_render(&s, 0, "cb_gi", CW, CW, PB_POV_MEDIUM, 0, &tp);
  CHECK(ref && pov);
  if (ref && pov) {
    pb_metrics m;
    CHECK_EQ_INT(pb_metrics_compute(pov, ref, CW, CW, 3, NULL, &m), PB_OK);
    printf("cornell_box full GI %ux%u, ref 64 spp 8 bounces (%.2f s) vs POV-Ray radiosity medium -A "
           "(%.2f s): PSNR %.2f dB, SSIM %.4f, relMSE %.4f, mean ratio POV/ref %.4f (reported, not gated)\n",
           CW, CW, tr, tp, m.psnr, m.ssim, m.relmse, sum_ratio(pov, ref, CW * CW, NULL));
    CHECK(isfinite(m.psnr));
  }
  free(ref);
  free(pov);
  pb_scene_destroy(&s);
}

int main(int argc, char **argv) {
  (void)argv;
  if (system("command -v povray >/dev/null 2>&1") != 0) {
    printf("skip: povray not installed\n");
    return 77;
  }
  if (!mkdtemp(tmpdir)) return 1;
  const char *what = argc > 1 ? argv[1] : "";
  if (strcmp(what, "--gi") == 0) {
    cornell_gi();
  } else if (strcmp(what, "--cornell-direct") == 0) {
    cornell_direct();
  } else {
    plane_case("point", PB_LIGHT_POINT);
    plane_case("spot", PB_LIGHT_SPOT);
    plane_case("directional", PB_LIGHT_DIRECTIONAL);
    cornell_caustic();
  }
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return pbt_done();
}
