/* The viewer's picture on the GPU: the OCIO view baked to
 * a 66^3 or 129^3 LUT with its shaper (color.h pb_color_bake_lut) and the display
 * pass (shaders/frame/present.comp, view/present_pass.h) against the host path
 * (pb_color_apply_display, then pb_png_write_display's rounding: what
 * `photonbridge display` writes), within one 8-bit step, on
 *   - a scene-linear ramp: grey 2^-20 .. 2^12 in 1/32 stops, and coloured
 *     ramps (saturated and pastel hues, up to 2^10: values > 1 included),
 *   - the same ramp at +1.5 EV (the pass's exposure scale against a view
 *     opened with exposure 1.5),
 *   - a rendered frame (cornell_box, 96 px, 4 spp, photons on; peak 44),
 * for sRGB / Standard and sRGB / Filmic of the built-in config and, when
 * Blender is installed, of Blender's config. The host evaluation of the
 * LUT (pb_color_lut_eval, the pass's arithmetic) is checked the same way,
 * and the shaper's range: Standard's top node is 1 (it clips there),
 * Filmic's above 2^12. Validation layers on. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "sample_fixture.h"
#include "view/present_pass.h"

/* The ramp, RGBA. */
static float *make_ramp(uint32_t *count) {
  static const float hues[][3] = {{1, 1, 1},       {1, 0, 0},      {0, 1, 0},     {0, 0, 1},
                                  {1, 0.5f, 0.1f}, {0.2f, 0.6f, 1}, {1, 1, 0},    {0.9f, 0.8f, 0.7f},
                                  {0, 1, 1},       {1, 0, 1},       {0.05f, 0.02f, 0.3f}};
  const uint32_t grey = 32 * 32 + 1, per = 32 * 24 + 1, nh = sizeof hues / sizeof hues[0];
  uint32_t n = grey + nh * per + 4;
  float *p = calloc((size_t)4 * n, sizeof *p);
  uint32_t i = 0;
  for (uint32_t j = 0; j < grey; ++j, ++i)
    for (int k = 0; k < 3; ++k) p[4 * i + k] = exp2f(-20.0f + (float)j / 32.0f);
  for (uint32_t h = 0; h < nh; ++h)
    for (uint32_t j = 0; j < per; ++j, ++i)
      for (int k = 0; k < 3; ++k) p[4 * i + k] = hues[h][k] * exp2f(-14.0f + (float)j / 32.0f);
  /* 0, a huge value, a negative channel */
  i++;
  p[4 * i] = p[4 * i + 1] = p[4 * i + 2] = 1e6f, i++;
  p[4 * i] = -0.5f, p[4 * i + 1] = 0.5f, p[4 * i + 2] = 2.0f, i++;
  p[4 * i] = 3.0f, p[4 * i + 1] = 0.0f, p[4 * i + 2] = 0.25f, i++;
  for (uint32_t j = 0; j < n; ++j) p[4 * j + 3] = 1.0f;
  *count = n;
  return p;
}

/* The host path's bytes: apply_display then the PNG rounding. */
static void host_bytes(const pb_color *c, const float *rgba, uint32_t n, uint8_t *out) {
  float *t = malloc((size_t)4 * n * sizeof *t);
  memcpy(t, rgba, (size_t)4 * n * sizeof *t);
  CHECK_EQ_INT(pb_color_apply_display(c, t, n, 1, 4), PB_OK);
  for (uint32_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) out[4 * i + k] = pb_color_to_u8(t[4 * i + k]);
    out[4 * i + 3] = 255;
  }
  free(t);
}

/* Largest byte difference; *differ: how many channels differ at all. */
static int max_diff(const uint8_t *a, const uint8_t *b, uint32_t n, uint32_t *differ, uint32_t *worst) {
  int m = 0;
  *differ = 0;
  *worst = 0;
  for (uint32_t i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k) {
      int d = abs((int)a[4 * i + k] - (int)b[4 * i + k]);
      if (d) (*differ)++;
      if (d > m) m = d, *worst = i;
    }
  return m;
}

static void check_view(pb_gpu *g, const char *config, const char *view, const float *ramp, uint32_t n,
                       const pb_render_result *frame) {
  pb_color_desc cd = {.config = config, .display = "sRGB", .view = view};
  pb_color *c = NULL, *ce = NULL;
  CHECK_EQ_INT(pb_color_open(&cd, &c), PB_OK);
  cd.exposure = 1.5;
  CHECK_EQ_INT(pb_color_open(&cd, &ce), PB_OK);
  if (!c || !ce) return;
  pb_color_lut lut;
  CHECK_EQ_INT(pb_color_bake_lut(c, 0, &lut), PB_OK);
  CHECK(lut.size == 66 || lut.size == 129);
  printf("present %s / %s: shaper 2^%.4g .. 2^%.4g, bake error %.2e (%.3f 8-bit steps)\n", pb_color_config_name(c),
         view, lut.lo, lut.hi, lut.max_error, lut.max_error * 255.0);
  CHECK(lut.max_error * 255.0 < 1.0);
  if (strcmp(view, "Standard") == 0) CHECK(fabsf(lut.hi) < 0.07f); /* clips at 1 */
  else CHECK(lut.hi > 8.0f); /* Filmic: where its curve reaches 1, 2^8.56 */
  uint32_t cap = n;
  if (frame && frame->width * frame->height > cap) cap = frame->width * frame->height;
  pb_present_pass pp;
  CHECK_EQ_INT(pb_present_pass_create(g, &lut, cap, &pp), PB_OK);
  uint8_t *host = malloc((size_t)4 * cap), *gpu = malloc((size_t)4 * cap), *cpu = malloc((size_t)4 * cap);
  for (int pass = 0; pass < 3; ++pass) {
    const float *src = pass < 2 ? ramp : frame->beauty;
    uint32_t m = pass < 2 ? n : frame->width * frame->height;
    const pb_color *hc = pass == 1 ? ce : c;
    float scale = pass == 1 ? exp2f(1.5f) : 1.0f;
    host_bytes(hc, src, m, host);
    for (uint32_t i = 0; i < m; ++i) {
      float v[3];
      pb_color_lut_eval(&lut, scale, src + 4 * i, v);
      for (int k = 0; k < 3; ++k) cpu[4 * i + k] = pb_color_to_u8(v[k]);
      cpu[4 * i + 3] = 255;
    }
    CHECK_EQ_INT(pb_present_pass_upload(g, &pp, src, m, 4), PB_OK);
    pb_present_job job = {.channels = 4, .pixels = m, .scale = scale};
    CHECK_EQ_INT(pb_present_pass_run(g, &pp, &job), PB_OK);
    CHECK_EQ_INT(pb_present_pass_download(g, &pp, gpu, m), PB_OK);
    uint32_t dg, dc, wg, wc;
    int mg = max_diff(gpu, host, m, &dg, &wg), mc = max_diff(cpu, host, m, &dc, &wc);
    static const char *what[] = {"ramp", "ramp +1.5 EV", "cornell_box frame"};
    printf("  %s (%u pixels): GPU pass vs host path max %d step(s), %u of %u channels differ; host LUT max %d, %u "
           "differ\n", what[pass], m, mg, dg, 3 * m, mc, dc);
    if (mg > 1)
      printf("  worst pixel %u: in %g %g %g, GPU %u %u %u, host %u %u %u\n", wg, src[4 * wg], src[4 * wg + 1],
             src[4 * wg + 2], gpu[4 * wg], gpu[4 * wg + 1], gpu[4 * wg + 2], host[4 * wg], host[4 * wg + 1],
             host[4 * wg + 2]);
    CHECK(mg <= 1);
    CHECK(mc <= 1);
    /* Within a step, and not by luck: most channels are the same byte. */
    CHECK(dg * 50u <= 3 * m);
  }
  free(host);
  free(gpu);
  free(cpu);
  pb_present_pass_destroy(g, &pp);
  pb_color_lut_destroy(&lut);
  pb_color_destroy(c);
  pb_color_destroy(ce);
}

int main(void) {
  PBT_GPU_OPEN(g);
  uint32_t n = 0;
  float *ramp = make_ramp(&n);
  pbt_sample fx;
  pb_render_result frame;
  memset(&frame, 0, sizeof frame);
  if (pbt_sample_open(g, "cornell_box", 96, NULL, &fx)) {
    pb_render_desc rd = {.spp = 4, .seed = 3, .photons = 1u << 14};
    CHECK_EQ_INT(pb_render_frame(g, &fx.s, &fx.gs, 0, fx.w, fx.h, &rd, &frame), PB_OK);
  }
  if (frame.beauty) {
    /* Bright enough that Filmic's and Standard's tops are exercised. */
    float peak = 0;
    for (uint32_t i = 0; i < frame.width * frame.height; ++i) peak = fmaxf(peak, frame.beauty[4 * i]);
    printf("cornell_box %ux%u: peak red %.3g\n", frame.width, frame.height, peak);
    const char *views[] = {"Standard", "Filmic"};
    for (int v = 0; v < 2; ++v) check_view(g, "built-in", views[v], ramp, n, &frame);
    const char *blender = pb_color_blender_config();
    if (blender) {
      char path[1024];
      snprintf(path, sizeof path, "%s", blender);
      for (int v = 0; v < 2; ++v) check_view(g, path, views[v], ramp, n, &frame);
    } else {
      printf("no Blender config here: the built-in one only\n");
    }
  }
  /* Bad sizes are refused. */
  pb_color *c = NULL;
  pb_color_desc cd = {.config = "built-in"};
  CHECK_EQ_INT(pb_color_open(&cd, &c), PB_OK);
  pb_color_lut bad;
  CHECK_EQ_INT(pb_color_bake_lut(c, 1000, &bad), PB_ERR_USAGE);
  pb_color_destroy(c);
  pb_error_clear();
  pb_render_result_destroy(&frame);
  pbt_sample_close(g, &fx);
  free(ramp);
  pb_gpu_destroy(g);
  return pbt_done();
}
