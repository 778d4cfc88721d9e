/* The photon gather (shaders/estimate/gather.comp) against an analytic answer:
 * synthetic photons uploaded as a photon map onto a 2 x 2 m Lambert plane
 * (albedo 0.8, no specular layer), seen from above by a camera whose pixel
 * centres hit known points. Every pixel's indirect (and caustic) AOV must be
 * the sum over photons whose footprint ellipse holds the point of
 * K(q) / (pi |u x v|) * albedo / pi * Phi, q from the skewed axes, for the
 * Epanechnikov kernel 2 (1 - q) and the constant kernel 1. Photons on the
 * plane's other side (normal -y) must contribute nothing. No lights, so
 * beauty = indirect + caustic. Validation layers on; exit 77 without a
 * Vulkan device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metrics/metrics.h"
#include "pbtest.h"
#include "plane_fixture.h"
#include "gpu_test.h"
#include "sample_fixture.h"
#include "ref/ref.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

static uint64_t rng_state = 777;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

enum { W = 33, H = 33, NPH = 400 };
/* Achieved 24.47 dB with 8 iterations (20.60 dB with 1) on llvmpipe, 7
 * stored bounces; 2.5 dB of margin. Without the indirect light the beauty
 * is ~45 % darker; with the tracer's default 3 bounces it is 23.7 dB and the
 * indirect mean 8 % low (truncation). */
#define CORNELL_PSNR_MIN 22.0

static void run(pb_gpu *g, int constant_kernel) {
  static plane_fixture f; /* the lit plane (plane_fixture.h) */
  plane_fixture_build(&f);
  pb_scene *sp = &f.s;

  pb_gpu_photon *ph = calloc(NPH, sizeof *ph);
  for (int i = 0; i < NPH; ++i) {
    pb_gpu_photon *p = &ph[i];
    p->position[0] = frand() * 1.6f - 0.8f;
    p->position[2] = frand() * 1.6f - 0.8f;
    p->power[0] = 0.01f * (0.5f + frand()), p->power[1] = 0.02f * frand(), p->power[2] = 0.005f;
    float r = 0.05f + 0.25f * frand(), sk = frand() - 0.5f, ang = 6.2831853f * frand();
    float cu = cosf(ang), su = sinf(ang);
    p->axis_u[0] = r * cu, p->axis_u[2] = r * su;
    p->axis_v[0] = r * (0.4f + frand()) * (-su + sk * cu), p->axis_v[2] = r * (0.4f + frand()) * (cu + sk * su);
    p->radius = 2 * r;
    p->normal_extent = 0.05f;
    float wl = sqrtf(0.09f + 1 + 0.04f);
    p->wi[0] = 0.3f / wl, p->wi[1] = 1 / wl, p->wi[2] = 0.2f / wl;
    p->normal[1] = i % 10 == 9 ? -1.0f : 1.0f; /* every tenth: the other side */
    p->flags = i % 3 == 0 ? PB_PHOTON_CAUSTIC : 0u;
    p->path = (uint32_t)i;
  }
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  map.capacity = NPH;
  map.stored = NPH;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = NPH * sizeof(pb_gpu_photon)};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &map.photons), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.photons, 0, ph, NPH * sizeof(pb_gpu_photon)), PB_OK);

  pb_gpu_scene gs;
  pb_render_result res;
  memset(&res, 0, sizeof res);
  CHECK_EQ_INT(pb_gpu_scene_create(g, sp, &gs), PB_OK);
  pb_render_desc rd = {.estimator = {.lbvh = {.constant_kernel = constant_kernel}}};
  pb_render_io io = {.photon_map = &map};
  pb_result r = pb_render_frame_io(g, sp, &gs, 0, W, H, &rd, &io, &res);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  if (r == PB_OK) {
    CHECK(res.indirect != NULL && res.caustic != NULL);
    float tan_y = tanf(0.5f * f.cam.yfov), tan_x = tan_y;
    double max_err = 0, max_val = 0, beauty_err = 0;
    uint32_t lit = 0;
    for (int py = 0; py < H; ++py)
      for (int px = 0; px < W; ++px) {
        float sx = (2.0f * (px + 0.5f) / W - 1) * tan_x, sy = (1 - 2.0f * (py + 0.5f) / H) * tan_y;
        double x = 3.0 * sx, z = -3.0 * sy;
        if (fabs(x) > 0.99 || fabs(z) > 0.99) continue;
        double want[2][3] = {{0}};
        for (int i = 0; i < NPH; ++i) {
          const pb_gpu_photon *p = &ph[i];
          if (p->normal[1] < 0) continue;
          double dx = x - p->position[0], dz = z - p->position[2];
          double uu = p->axis_u[0] * p->axis_u[0] + p->axis_u[2] * p->axis_u[2];
          double vv = p->axis_v[0] * p->axis_v[0] + p->axis_v[2] * p->axis_v[2];
          double uvd = p->axis_u[0] * p->axis_v[0] + p->axis_u[2] * p->axis_v[2];
          double det = uu * vv - uvd * uvd;
          double du = dx * p->axis_u[0] + dz * p->axis_u[2], dv = dx * p->axis_v[0] + dz * p->axis_v[2];
          double a = (vv * du - uvd * dv) / det, b = (uu * dv - uvd * du) / det, q = a * a + b * b;
          if (q > 1) continue;
          double k = (constant_kernel ? 1.0 : 2.0 * (1 - q)) / (M_PI * sqrt(det));
          for (int c = 0; c < 3; ++c) want[(p->flags & PB_PHOTON_CAUSTIC) ? 1 : 0][c] += k * 0.8 / M_PI * p->power[c];
        }
        size_t o = (size_t)py * W + px;
        for (int c = 0; c < 3; ++c) {
          double e0 = fabs(res.indirect[3 * o + c] - want[0][c]), e1 = fabs(res.caustic[3 * o + c] - want[1][c]);
          if (e0 > max_err) max_err = e0;
          if (e1 > max_err) max_err = e1;
          if (want[0][c] > max_val) max_val = want[0][c];
          if (want[1][c] > max_val) max_val = want[1][c];
          double be = fabs(res.beauty[4 * o + c] - res.indirect[3 * o + c] - res.caustic[3 * o + c]);
          if (be > beauty_err) beauty_err = be;
        }
        lit += want[0][0] > 0;
      }
    /* Constant kernel: a point on an ellipse's rim flips in or out with float
     * rounding (a step of up to one photon's weight); Epanechnikov is 0 there. */
    double tol = constant_kernel ? 0.15 * max_val : 2e-4 * max_val;
    printf("gather %s kernel: %u lit pixels, max |GPU - analytic| %.3g (largest value %.3g, tolerance %.3g), "
           "beauty - (indirect + caustic) %.3g, T_auto %u, k_PD %.2f, LBVH %.2f ms, gather %.2f ms\n",
           constant_kernel ? "constant" : "Epanechnikov", lit, max_err, max_val, tol, beauty_err, (unsigned)pb_render_estimator_stat(&res.stats, "t_auto", 0),
           res.stats.k_pd, res.stats.estimator_build_ms, res.stats.gather_ms);
    CHECK(lit > 200);
    CHECK(max_err <= tol);
    CHECK(beauty_err <= 1e-5 * max_val);
    CHECK_EQ_INT(res.stats.photons_stored, NPH);
    CHECK(res.stats.k_pd > 1);
  }
  pb_render_result_destroy(&res);
  pb_gpu_scene_destroy(g, &gs);
  pb_photon_map_destroy(g, &map);
  free(ph);
  pb_error_clear();
}

/* cornell_box at 64 x 64: GPU beauty (direct + photon-mapped indirect)
 * against the reference's beauty. PSNR must reach the threshold with K
 * iterations and improve from 1 to K iterations (same spp). */
static double cornell_psnr(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_ref_result *rr,
                           uint32_t w, uint32_t h, uint32_t iterations, pb_render_stats *st) {
  pb_render_result gr;
  memset(&gr, 0, sizeof gr);
  pb_render_desc rd = {.spp = 16, .seed = 5, .photons = 1u << 16, .iterations = iterations,
                       .photon_bounces = 7 /* + the unstored direct bounce: the reference's 8 */};
  pb_result r = pb_render_frame(g, s, gs, 0, w, h, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  double psnr = -1;
  if (r == PB_OK) {
    pb_metrics m;
    CHECK_EQ_INT(pb_metrics_compute(gr.beauty, rr->beauty, w, h, 4, NULL, &m), PB_OK);
    psnr = m.psnr;
    double gm = 0, rm = 0, gi = 0, ri = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i)
      for (int c = 0; c < 3; ++c) {
        gm += gr.beauty[4 * i + c], rm += rr->beauty[4 * i + c];
        gi += gr.indirect[3 * i + c] + gr.caustic[3 * i + c], ri += rr->indirect[3 * i + c];
      }
    printf("cornell_box %ux%u, 16 spp, %u x 2^16 photons: beauty PSNR %.2f dB, relMSE %.4g; mean beauty %.4f vs ref "
           "%.4f, mean indirect %.4f vs ref %.4f; T_auto %u, k_PD %.1f, LBVH %.1f ms, gather %.1f ms\n",
           w, h, iterations, m.psnr, m.relmse, gm / (3.0 * w * h), rm / (3.0 * w * h), gi / (3.0 * w * h),
           ri / (3.0 * w * h), (unsigned)pb_render_estimator_stat(&gr.stats, "t_auto", 0), gr.stats.k_pd,
           gr.stats.estimator_build_ms, gr.stats.gather_ms);
    CHECK_EQ_INT(m.nonfinite, 0);
    CHECK(fabs(gi - ri) < 0.05 * ri); /* energy: the indirect means within 5 % (measured +1.7 %) */
    *st = gr.stats;
  }
  pb_render_result_destroy(&gr);
  return psnr;
}

static void cornell(pb_gpu *g) {
  pbt_sample f;
  pb_ref_desc fd = {.spp = 256, .seed = 9};
  if (pbt_sample_open(g, "cornell_box", 64, &fd, &f)) {
    pb_render_stats st1, st8;
    memset(&st1, 0, sizeof st1);
    memset(&st8, 0, sizeof st8);
    double p1 = cornell_psnr(g, &f.s, &f.gs, &f.ref, f.w, f.h, 1, &st1);
    double p8 = cornell_psnr(g, &f.s, &f.gs, &f.ref, f.w, f.h, 8, &st8);
    CHECK(p8 > CORNELL_PSNR_MIN);
    CHECK(p8 > p1);
    CHECK(st8.photons_stored > 0);
  }
  pbt_sample_close(g, &f);
}

/* cornell_box with the default photon budget (over 65535 stored photons, an
 * LBVH whose root covers more than llvmpipe's 65535 loop iterations): the
 * indirect light of the left and right image halves within a factor 1.5
 * (the box is symmetric but for the wall colours). The root's box once
 * covered only the first 65535 Morton-ordered photons, the x < 0 half, and
 * the right half's indirect was exactly 0. */
static void cornell_halves(pb_gpu *g) {
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load("samples/cornell_box/cornell_box.gltf", &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  uint32_t w, h;
  pb_camera_image_size(&s.cameras[0], 32, 0, &w, &h);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_render_result gr;
  memset(&gr, 0, sizeof gr);
  pb_render_desc rd = {.spp = 1, .seed = 3};
  r = pb_render_frame(g, &s, &gs, 0, w, h, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    double half[2] = {0, 0};
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) half[2 * x >= w] += gr.indirect[3 * ((size_t)y * w + x) + c];
    printf("cornell_box %ux%u, %llu photons stored: indirect left %.4f, right %.4f, k_PD %.2f\n", w, h,
           (unsigned long long)gr.stats.photons_stored, half[0], half[1], gr.stats.k_pd);
    CHECK(gr.stats.photons_stored > 65535);
    CHECK(half[0] > 0 && half[1] > 0);
    CHECK(half[0] < 1.5 * half[1] && half[1] < 1.5 * half[0]);
  }
  pb_render_result_destroy(&gr);
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
  pb_error_clear();
}

/* cornell_caustics (a glass sphere and a mirror box in a Cornell box, point
 * light) at 48 px: GPU beauty (direct + specular eye paths + indirect +
 * caustic photons) against the reference with SPPM caustics (256 spp). The
 * PSNR must pass CAUSTICS_PSNR_MIN with 8 maps and rise from 1 to 8 maps,
 * the mean beauty must be within 5 % of the reference's, and the caustic
 * photons must carry light (caustic AOV mean > 2 % of the indirect mean;
 * measured 5.9 %). Measured on llvmpipe: 29.25 dB (1 map), 30.17 dB (8),
 * mean beauty 1.8255 vs 1.8251. */
#ifndef CAUSTICS_PSNR_MIN
#define CAUSTICS_PSNR_MIN 27.0
#endif
static double caustics_psnr(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_ref_result *rr,
                            uint32_t w, uint32_t h, uint32_t iterations) {
  pb_render_result gr;
  memset(&gr, 0, sizeof gr);
  pb_render_desc rd = {.spp = 16, .seed = 5, .photons = 1u << 16, .iterations = iterations, .photon_bounces = 7};
  pb_result r = pb_render_frame(g, s, gs, 0, w, h, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  double psnr = -1;
  if (r == PB_OK) {
    pb_metrics m;
    CHECK_EQ_INT(pb_metrics_compute(gr.beauty, rr->beauty, w, h, 4, NULL, &m), PB_OK);
    psnr = m.psnr;
    double ci = 0, ii = 0, gm = 0, rm = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i)
      for (int c = 0; c < 3; ++c) {
        ci += gr.caustic[3 * i + c], ii += gr.indirect[3 * i + c];
        gm += gr.beauty[4 * i + c], rm += rr->beauty[4 * i + c];
      }
    printf("cornell_caustics %ux%u, 16 spp, %u x 2^16 photons: beauty PSNR %.2f dB, relMSE %.4g, mean beauty %.4f vs "
           "ref %.4f; caustic AOV mean %.4f, indirect %.4f; %llu caustic photons\n",
           w, h, iterations, m.psnr, m.relmse, gm / (3.0 * w * h), rm / (3.0 * w * h), ci / (3.0 * w * h),
           ii / (3.0 * w * h), (unsigned long long)gr.stats.photons_caustic);
    CHECK_EQ_INT(m.nonfinite, 0);
    CHECK(gr.stats.photons_caustic > 0);
    CHECK(ci > 0.02 * ii);
    CHECK(fabs(gm - rm) < 0.05 * rm); /* energy: mean beauty within 5 % */
  }
  pb_render_result_destroy(&gr);
  return psnr;
}

static void caustics(pb_gpu *g) {
  pbt_sample f;
  pb_ref_desc fd = {.spp = 256, .seed = 9, .mode = PB_REF_MODE_SPPM};
  if (pbt_sample_open(g, "cornell_caustics", 48, &fd, &f)) {
    double p1 = caustics_psnr(g, &f.s, &f.gs, &f.ref, f.w, f.h, 1);
    double p8 = caustics_psnr(g, &f.s, &f.gs, &f.ref, f.w, f.h, 8);
    CHECK(p8 > CAUSTICS_PSNR_MIN);
    CHECK(p8 > p1);
  }
  pbt_sample_close(g, &f);
}

int main(void) {
  PBT_GPU_OPEN(g);
  run(g, 0);
  run(g, 1);
  cornell(g);
  cornell_halves(g);
  caustics(g);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
