/* Convergence: in a closed diffuse box lit by an emissive ceiling quad (soft
 * shadows, inter-reflection, MIS), the error of a render against a 16x longer
 * one falls like 1/sqrt(spp):
 *   MSE(n) = s^2 / n + e_ref^2,
 * with e_ref the reference's own noise, estimated from its two halves
 * (--estimate-noise) and subtracted. Checks: the least-squares slope of
 * log RMSE against log spp over spp = 2, 8, 32 (two renders each, against
 * a 512 spp reference) is -0.5 +- 0.1, and RMSE(2) / RMSE(32) is 4 within
 * 25 %. Also: the reference's noise estimate
 * agrees with the error actually measured between two independent
 * references (within 25 %), the rendering is identical for 1 and 3 threads,
 * and different seeds give different images. `--full` (tests/ref.cmake, not
 * under sanitizers) renders 32x32 instead of 16x16. */
#include <stdlib.h>
#include <string.h>

#include "metrics/metrics.h"
#include "pbtest.h"
#include "test_ref_scene.h"

static void build_box(pb_scene *s) {
  tsc_init(s);
  uint32_t white = tsc_material(s, tsc_lambert(0.7f, 0.7f, 0.7f));
  uint32_t red = tsc_material(s, tsc_lambert(0.7f, 0.1f, 0.1f));
  uint32_t green = tsc_material(s, tsc_lambert(0.1f, 0.7f, 0.1f));
  pb_material e = tsc_lambert(0, 0, 0);
  e.emissive[0] = e.emissive[1] = e.emissive[2] = 12.0f;
  uint32_t lamp = tsc_material(s, e);
  /* Box [-1, 1]^3, every wall facing inward. */
  float p[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  tsc_quad(s, p[0], p[1], p[2], p[3], white); /* floor, +z */
  tsc_quad(s, p[4], p[7], p[6], p[5], white); /* ceiling, -z */
  tsc_quad(s, p[0], p[3], p[7], p[4], red);   /* x = -1, +x */
  tsc_quad(s, p[1], p[5], p[6], p[2], green); /* x = +1, -x */
  tsc_quad(s, p[3], p[2], p[6], p[7], white); /* y = +1, -y */
  tsc_quad(s, p[0], p[4], p[5], p[1], white); /* y = -1, +y */
  /* A small lamp under the ceiling, facing down, and a block to cast a
   * shadow. */
  float l0[3] = {-0.25f, -0.25f, 0.98f}, l1[3] = {-0.25f, 0.25f, 0.98f},
        l2[3] = {0.25f, 0.25f, 0.98f}, l3[3] = {0.25f, -0.25f, 0.98f};
  tsc_quad(s, l0, l1, l2, l3, lamp);
  float b0[3] = {-0.3f, 0.1f, -0.2f}, b1[3] = {0.3f, 0.1f, -0.2f}, b2[3] = {0.3f, 0.6f, -0.2f},
        b3[3] = {-0.3f, 0.6f, -0.2f};
  tsc_quad(s, b0, b1, b2, b3, white); /* a floating tile, facing up */
  tsc_quad(s, b0, b3, b2, b1, white); /* and its underside */
  float pos[3] = {0, -0.95f, 0.1f}, fwd[3] = {0, 1, -0.15f}, up[3] = {0, 0, 1};
  tsc_camera(s, pos, fwd, up, 65.0f);
  pb_scene_finalize(s);
}

static pb_ref_result render(const pb_scene *s, uint32_t n, uint32_t spp, uint64_t seed,
                            uint32_t threads, int noise) {
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = spp;
  d.seed = seed;
  d.max_bounces = 4;
  d.threads = threads;
  d.estimate_noise = noise;
  pb_ref_result r;
  pb_result res = pb_ref_render(s, 0, n, n, &d, &r);
  CHECK_EQ_INT(res, PB_OK);
  if (res != PB_OK) {
    fprintf(stderr, "render: %s\n", pb_error_message());
    exit(pbt_done());
  }
  CHECK_EQ_INT(r.stats.guarded_samples, 0);
  return r;
}

static double rmse(const pb_ref_result *a, const pb_ref_result *b) {
  pb_metrics m;
  CHECK_EQ_INT(pb_metrics_compute(a->beauty, b->beauty, a->width, a->height, 4, NULL, &m),
               PB_OK);
  return m.rmse;
}

int main(int argc, char **argv) {
  int full = argc > 1 && strcmp(argv[1], "--full") == 0;
  uint32_t n = full ? 32 : 16;
  pb_scene s;
  build_box(&s);

  uint64_t base = argc > 2 ? strtoull(argv[2], NULL, 10) : 0; /* for experiments */
  pb_ref_result ref = render(&s, n, 512, 1000 + base, 0, 1);
  double e_ref = ref.stats.noise_rmse;
  CHECK(e_ref > 0);

  /* Each level's MSE is the mean of two independent renders (the estimate of
   * an MSE over 256 pixels is itself noisy). */
  static const uint32_t spp[3] = {2, 8, 32};
  double lx[3], ly[3];
  for (int i = 0; i < 3; ++i) {
    double mse = 0;
    for (int k = 0; k < 2; ++k) {
      pb_ref_result t = render(&s, n, spp[i], base + 1 + (uint64_t)(2 * i + k), 0, 0);
      double e = rmse(&t, &ref);
      mse += 0.5 * e * e;
      pb_ref_result_destroy(&t);
    }
    double e = sqrt(mse);
    double corrected = sqrt(fmax(mse - e_ref * e_ref, 0.0));
    printf("spp %3u: RMSE %.5f  (reference noise %.5f)  corrected %.5f  x sqrt(spp) %.4f\n",
           spp[i], e, e_ref, corrected, corrected * sqrt(spp[i]));
    lx[i] = log((double)spp[i]);
    ly[i] = log(corrected);
  }
  double mx = (lx[0] + lx[1] + lx[2]) / 3, my = (ly[0] + ly[1] + ly[2]) / 3, sxy = 0, sxx = 0;
  for (int i = 0; i < 3; ++i) {
    sxy += (lx[i] - mx) * (ly[i] - my);
    sxx += (lx[i] - mx) * (lx[i] - mx);
  }
  double slope = sxy / sxx, ratio = exp(ly[0] - ly[2]);
  printf("slope %.3f (want -0.5), RMSE(2)/RMSE(32) %.3f (want 4)\n", slope, ratio);
  CHECK_NEAR(slope, -0.5, 0.1);
  CHECK_NEAR(ratio, 4.0, 1.0);

  /* The noise estimate against the truth: two independent references differ
   * by sqrt(2) times the noise of one. */
  pb_ref_result ref2 = render(&s, n, 512, 2000 + base, 0, 1);
  double between = rmse(&ref2, &ref) / sqrt(2.0);
  printf("reference noise: estimated %.5f, %.5f; measured %.5f\n", e_ref,
         ref2.stats.noise_rmse, between);
  CHECK_NEAR(e_ref, between, 0.25 * between);
  CHECK(ref.stats.noise_relmse > 0 && ref.stats.noise_psnr > 0);
  pb_ref_result_destroy(&ref2);
  pb_ref_result_destroy(&ref);

  /* Determinism: thread count does not matter, the seed does. */
  pb_ref_result a = render(&s, n, 8, 5, 1, 1), b = render(&s, n, 8, 5, 3, 1),
                c = render(&s, n, 8, 6, 2, 1);
  size_t px = (size_t)n * n;
  CHECK(memcmp(a.beauty, b.beauty, 4 * px * sizeof(float)) == 0);
  CHECK(memcmp(a.indirect, b.indirect, 3 * px * sizeof(float)) == 0);
  CHECK(memcmp(a.depth, b.depth, px * sizeof(float)) == 0);
  CHECK(a.stats.rays == b.stats.rays);
  CHECK(a.stats.noise_rmse == b.stats.noise_rmse);
  CHECK(memcmp(a.beauty, c.beauty, 4 * px * sizeof(float)) != 0);
  CHECK_EQ_INT(a.stats.threads, 1);
  CHECK_EQ_INT(b.stats.threads, 3);
  pb_ref_result_destroy(&a);
  pb_ref_result_destroy(&b);
  pb_ref_result_destroy(&c);
  pb_scene_destroy(&s);
  return pbt_done();
}
