/* What Blender's glTF exporter writes beyond the core, through export-pov and
 * POV-Ray 3.7 (the scenes of tests/data/gltf_ext; test_gpu_gltf_ext checks
 * the other two renderers on them). Unantialiased renders (-A) sample pixel
 * centres; POV-Ray writes half floats (about 1e-3 relative):
 *   - COLOR_0 through a texture_list that POV-Ray interpolates per face:
 *     every pixel inside a triangle within 2e-3 of the analytic colour;
 *   - KHR_texture_transform (and its texCoord) written into the uv_vectors:
 *     the picture equals the baked texture's on 99 % of the pixels;
 *   - unlit: the card at its colour; with radiosity on and no light, the
 *     floor under it stays black (no_radiosity);
 *   - a blend-0 spot (radius = falloff): inside within 0.5 % of rho/pi I
 *     cos/d^2, outside exactly 0;
 *   - KHR_materials_volume as an absorbing medium: through the slab over
 *     through the clear one 0.4994 within 2 %.
 * Exit 77 (skip) when povray is not installed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/image.h"
#include "pbtest.h"
#include "pov/pov.h"

static char tmpdir[] = "/tmp/pb_test_pov_gltf_ext.XXXXXX";

static int load(const char *name, pb_scene *s) {
  char path[256];
  snprintf(path, sizeof path, "tests/data/gltf_ext/%s.gltf", name);
  pb_result r = pb_scene_load(path, NULL, s);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

/* Exports and renders `name` at w x h (quality q), returning channel G and
 * the RGB of every pixel in rgb[3 w h] (caller frees). */
static float *render(const char *name, pb_pov_quality q, uint32_t w, uint32_t h) {
  pb_scene s;
  if (!load(name, &s)) return NULL;
  char pov[256], exr[256], cmd[1024];
  snprintf(pov, sizeof pov, "%s/%s.pov", tmpdir, name);
  snprintf(exr, sizeof exr, "%s/%s.exr", tmpdir, name);
  pb_pov_desc d = {.width = w, .height = h, .quality = q, .fade_distance = 0.001f};
  pb_result r = pb_pov_export(&s, &d, pov, NULL);
  pb_scene_destroy(&s);
  if (r != PB_OK) {
    fprintf(stderr, "export failed: %s\n", pb_error_message());
    CHECK(0);
    return NULL;
  }
  snprintf(cmd, sizeof cmd, "sh validation/run_povray.sh '%s' '%s' -- -A +WT1 >/dev/null", pov, exr);
  if (system(cmd) != 0) {
    fprintf(stderr, "povray failed on %s (log %s.log)\n", pov, exr);
    CHECK(0);
    return NULL;
  }
  pb_image img;
  if (pb_exr_read(exr, NULL, &img) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    CHECK(0);
    return NULL;
  }
  float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
  int ch[3] = {pb_image_find_channel(&img, "R"), pb_image_find_channel(&img, "G"), pb_image_find_channel(&img, "B")};
  for (size_t i = 0; rgb && i < (size_t)w * h; ++i)
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = img.pixels[i * img.channel_count + (uint32_t)ch[k]];
  pb_image_destroy(&img);
  return rgb;
}

/* The floor point (y = 0) of pixel position (fx, fy) for the camera at
 * (0, height, 0) looking down (right +X, up -Z) with tan(yfov / 2) = ty. */
static void floor_point(double height, double ty, uint32_t w, uint32_t h, double fx, double fy, double p[3]) {
  double tx = ty * w / h;
  p[0] = (2 * fx / w - 1) * tx * height;
  p[1] = 0;
  p[2] = -(1 - 2 * fy / h) * ty * height;
}

static void vertex_colors(void) {
  const uint32_t W = 96, H = 32;
  float *img = render("vertex_colors", PB_POV_DIRECT, W, H);
  if (!img) return;
  static const double corner[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, base[3] = {0.5, 1, 0.8};
  double err = 0;
  uint32_t n = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      double p[3];
      floor_point(6, 0.2, W, H, x + 0.5, y + 0.5, p);
      if (p[0] < -3 || p[0] > 3 || p[2] < -1 || p[2] > 1) continue;
      double x0 = p[0] < -1 ? -3 : p[0] < 1 ? -1 : 1, u = (p[0] - x0) / 2, v = (p[2] + 1) / 2;
      if (fabs(u - v) < 0.05 || u < 0.05 || u > 0.95 || v < 0.05 || v > 0.95) continue; /* away from edges */
      double wt[4] = {0, 0, 0, 0};
      if (v >= u) wt[0] = 1 - v, wt[1] = v - u, wt[2] = u;
      else wt[0] = 1 - u, wt[2] = v, wt[3] = u - v;
      n++;
      for (int k = 0; k < 3; ++k) {
        double want = 0;
        for (int c = 0; c < 4; ++c) want += wt[c] * corner[c][k];
        want *= base[k];
        err = fmax(err, fabs(img[3 * ((size_t)y * W + x) + k] - want));
      }
    }
  printf("POV-Ray: COLOR_0 x base colour through a texture_list, %u pixels, max |error| %.2g\n", n, err);
  CHECK(n > 1000);
  CHECK(err < 2e-3);
  free(img);
}

static void texture_transform(void) {
  const uint32_t W = 32, H = 32;
  float *a = render("texture_transform", PB_POV_DIRECT, W, H), *b = render("texture_baked", PB_POV_DIRECT, W, H);
  if (a && b) {
    size_t same = 0;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < (size_t)W * H; ++i) {
      int e = 1;
      for (int k = 0; k < 3; ++k) {
        e &= fabs(a[3 * i + k] - b[3 * i + k]) <= 2e-3 * fmax(1.0, b[3 * i + k]);
        lo = fmin(lo, a[3 * i + k]), hi = fmax(hi, a[3 * i + k]);
      }
      same += (size_t)e;
    }
    printf("POV-Ray: KHR_texture_transform in the uv_vectors vs the baked texture: %.1f %% of the pixels equal (range %.2f)\n",
           100.0 * (double)same / (W * H), hi - lo);
    CHECK(same >= (size_t)(0.99 * W * H));
    CHECK(hi - lo > 0.3);
  }
  free(a);
  free(b);
}

static void unlit(void) {
  const uint32_t W = 32, H = 32;
  static const double colour[3] = {0.2, 0.5, 0.8};
  float *img = render("unlit_dark", PB_POV_DRAFT, W, H); /* radiosity on: the card must light nothing */
  if (!img) return;
  double card = 0, floor = 0;
  double ty = 2.1 / 4;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      double p[3];
      floor_point(4, ty, W, H, x + 0.5, y + 0.5, p);
      double sc = 3.5 / 4.0;
      size_t i = (size_t)y * W + x;
      for (int k = 0; k < 3; ++k) {
        if (fabs(p[0] * sc) < 0.45 && fabs(p[2] * sc) < 0.45) card = fmax(card, fabs(img[3 * i + k] - colour[k]));
        else if (fabs(p[0]) < 1.9 && fabs(p[2]) < 1.9 && !(fabs(p[0] * sc) < 0.6 && fabs(p[2] * sc) < 0.6))
          floor = fmax(floor, fabs(img[3 * i + k]));
      }
    }
  printf("POV-Ray: unlit card (emission 1, no_radiosity), no light, radiosity on: card max |error| %.2g, floor max %g\n", card,
         floor);
  CHECK(card < 2e-3);
  CHECK(floor == 0);
  free(img);
}

static void spot(void) {
  const uint32_t W = 48, H = 48;
  float *img = render("spot_blend0", PB_POV_DIRECT, W, H);
  if (!img) return;
  double co = cos(0.4), err = 0, out = 0, ty = 1.5 / 4;
  double I = 100.0; /* W/sr: 100 x 683 cd in the file */
  uint32_t ni = 0, no = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      int in = 1, o = 1;
      for (int k = 0; k < 4; ++k) {
        double p[3];
        floor_point(4, ty, W, H, x + (k & 1), y + (k >> 1), p);
        double c = 2 / sqrt(p[0] * p[0] + 4 + p[2] * p[2]);
        in &= c > co, o &= c < co;
      }
      double p[3];
      floor_point(4, ty, W, H, x + 0.5, y + 0.5, p);
      double d2 = p[0] * p[0] + 4 + p[2] * p[2], want = 0.8 / M_PI * I * (2 / sqrt(d2)) / d2;
      float v = img[3 * ((size_t)y * W + x) + 1];
      if (in) ni++, err = fmax(err, fabs(v - want) / want);
      else if (o) no++, out = fmax(out, v);
    }
  printf("POV-Ray: blend-0 spot (radius = falloff): %u pixels inside, max relative error %.2g; %u outside, max %g\n", ni, err,
         no, out);
  CHECK(ni > 100 && no > 100);
  CHECK(err < 5e-3);
  CHECK(out == 0);
  free(img);
}

static void volume(void) {
  const uint32_t W = 17, H = 17;
  float *a = render("volume_eye", PB_POV_DIRECT, W, H), *c = render("volume_eye_clear", PB_POV_DIRECT, W, H);
  if (a && c) {
    size_t i = (size_t)(H / 2) * W + W / 2;
    double q = a[3 * i + 1] / c[3 * i + 1], F = 0.04, T = 0.5, want = T * (1 - F * F) / (1 - F * F * T * T);
    printf("POV-Ray: KHR_materials_volume as media { absorption }: centre through the absorbing slab / the clear one %.4f "
           "(expected %.4f; clear %.4f)\n",
           q, want, c[3 * i + 1]);
    CHECK_NEAR(q, want, 0.02 * want);
  }
  free(a);
  free(c);
}

int main(void) {
  if (system("command -v povray >/dev/null 2>&1") != 0) {
    printf("SKIP: povray is not installed\n");
    return 77;
  }
  if (!mkdtemp(tmpdir)) return 1;
  vertex_colors();
  texture_transform();
  unlit();
  spot();
  volume();
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return pbt_done();
}
