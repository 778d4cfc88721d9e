/* The GPU pipeline's soft lights and world (lavapipe, validation layers on,
 * any message fatal; exit 77 without a device):
 *  - every case of soft_light_cases.h (the closed forms and integrals the
 *    reference is tested against, same thresholds) with `--direct-only`
 *    renders: area lights (form factor, surface integrals, spread), sphere
 *    lights converging to the point light, the soft spot, the sun's
 *    penumbra, a uniform world over a plane, a one-texel map, the background
 *    and film transparency, lights seen by the camera;
 *  - full renders with photons against the reference, on a closed box lit by
 *    an area light, a sphere light and, through an opening, a soft sun and a
 *    world map: direct AOV (relMSE < 4e-3 at 128 spp, noise: same estimators up to
 *    the BSDF strategy), the indirect light's mean within 5 % (the photon
 *    density estimate's bias, as for point lights: tests/unit/
 *    test_gpu_render.c) and the beauty's PSNR above 24 dB;
 *  - a white furnace: an open box of albedo 1 in a uniform world, full
 *    render: mean within 3 % of L (photon density estimation loses a little
 *    in corners);
 *  - the budget split gives the world its share, and with the RSM first
 *    bounce (the box's delta point light from its map, the soft lights and
 *    the world traced) the indirect light's mean is the traced one's within
 *    3 %. */
#include "soft_light_cases.h"

#include "gpu_test.h"
#include "metrics/metrics.h"
#include "render/photon/photon.h"
#include "render/render.h"

static pb_gpu *G;

static float *gpu_render_desc(const pb_scene *s, uint32_t w, uint32_t h, const pb_render_desc *rd,
                              pb_render_result *keep) {
  pb_gpu_scene gs;
  pb_result r = pb_gpu_scene_create(G, s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "gpu scene: %s\n", pb_error_message());
    return NULL;
  }
  pb_render_result res;
  r = pb_render_frame(G, s, &gs, 0, w, h, rd, &res);
  CHECK_EQ_INT(r, PB_OK);
  pb_gpu_scene_destroy(G, &gs);
  if (r != PB_OK) {
    fprintf(stderr, "render: %s\n", pb_error_message());
    return NULL;
  }
  CHECK_EQ_INT(res.stats.nonfinite_values, 0);
  float *b = res.beauty;
  res.beauty = NULL;
  if (keep) *keep = res;
  else pb_render_result_destroy(&res);
  return b;
}

/* soft_light_cases.h's renderer: direct light only (all these scenes have). */
static float *gpu_render(const pb_scene *s, uint32_t w, uint32_t h, uint32_t spp, uint64_t seed) {
  pb_render_desc rd = {.spp = spp, .direct_only = 1, .seed = seed};
  return gpu_render_desc(s, w, h, &rd, NULL);
}

/* A closed box (2 x 2 x 2 m, albedo 0.7, a red left wall) with a window in
 * the ceiling, a 0.5 m area light under the ceiling, a sphere light of
 * radius 0.1, a point light, and the soft sun and a world map shining in
 * through the window. */
static void lit_box(pb_scene *s, float *map) {
  tsc_init(s);
  uint32_t w = tsc_material(s, tsc_lambert(0.7f, 0.7f, 0.7f)), red = tsc_material(s, tsc_lambert(0.7f, 0.1f, 0.1f));
  float P[8][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}};
  tsc_quad(s, P[0], P[1], P[2], P[3], w);   /* floor */
  tsc_quad(s, P[0], P[4], P[5], P[1], w);   /* y = -1 */
  tsc_quad(s, P[1], P[5], P[6], P[2], w);   /* x = 1 */
  tsc_quad(s, P[2], P[6], P[7], P[3], w);   /* y = 1 */
  tsc_quad(s, P[3], P[7], P[4], P[0], red); /* x = -1 */
  /* Ceiling with a 0.6 x 0.6 window at (0.4, 0.4). */
  float c[][3] = {{-1, -1, 2}, {1, -1, 2}, {1, 0.1f, 2}, {-1, 0.1f, 2}, {-1, 0.1f, 2}, {0.1f, 0.1f, 2},
                  {0.1f, 1, 2}, {-1, 1, 2}, {0.7f, 0.1f, 2}, {1, 0.1f, 2}, {1, 1, 2}, {0.7f, 1, 2},
                  {0.1f, 0.7f, 2}, {0.7f, 0.7f, 2}, {0.7f, 1, 2}, {0.1f, 1, 2}};
  for (int q = 0; q < 4; ++q) tsc_quad(s, c[4 * q + 3], c[4 * q + 2], c[4 * q + 1], c[4 * q], w);
  float pos[3] = {0, -0.9f, 1.2f}, fwd[3] = {0, 1, -0.35f}, up[3] = {0, 0, 1};
  tsc_camera(s, pos, fwd, up, 70.0f);
  pb_light *a = area_light(s, PB_AREA_RECTANGLE, 0.5f, 0.5f, 1.9f, 20.0f);
  a->position[0] = -0.4f;
  pb_light *sp = tsc_light(s, PB_LIGHT_POINT);
  sp->position[0] = 0.5f, sp->position[1] = -0.3f, sp->position[2] = 0.8f;
  sp->radius = 0.1f;
  sp->intensity = 2.0f;
  pb_light *sun = tsc_light(s, PB_LIGHT_DIRECTIONAL);
  sun->direction[0] = -0.3f, sun->direction[1] = -0.2f, sun->direction[2] = -1.0f;
  tsc_norm3(sun->direction);
  sun->angle = 0.05f;
  sun->intensity = 3.0f;
  pb_light *pt = tsc_light(s, PB_LIGHT_POINT); /* a delta light too: the RSM's */
  pt->position[0] = -0.5f, pt->position[1] = 0.5f, pt->position[2] = 1.5f;
  pt->intensity = 1.0f;
  for (int y = 0; y < MH; ++y)
    for (int x = 0; x < MW; ++x)
      for (int k = 0; k < 3; ++k)
        map[3 * (y * MW + x) + k] = (float)(0.5 + 0.4 * sin(2 * M_PI * (x + 0.5) / MW + k) * cos(M_PI * (y + 0.5) / MH));
  const double rot[3] = {0.5, 0.0, 0.3};
  env_world(s, map, rot, 0.8f);
  s->film_opaque = 1;
  pb_scene_finalize(s);
}

static void test_full_render(void) {
  enum { BW = 48, BH = 48 };
  float *map = calloc((size_t)MW * MH * 3, sizeof *map);
  pb_scene s;
  lit_box(&s, map);
  pb_ref_desc fd = {.spp = 512, .seed = 3};
  pb_ref_result rr;
  pb_result r = pb_ref_render(&s, 0, BW, BH, &fd, &rr);
  CHECK_EQ_INT(r, PB_OK);
  pb_render_result gr;
  memset(&gr, 0, sizeof gr);
  pb_render_desc rd = {.spp = 128, .iterations = 8, .photons = 1u << 16, .seed = 4};
  float *b = gpu_render_desc(&s, BW, BH, &rd, &gr);
  if (r == PB_OK && b) {
    pb_metrics md, mb;
    CHECK_EQ_INT(pb_metrics_compute(gr.direct, rr.direct, BW, BH, 3, NULL, &md), PB_OK);
    CHECK_EQ_INT(pb_metrics_compute(b, rr.beauty, BW, BH, 4, NULL, &mb), PB_OK);
    double gi = tsc_mean(gr.indirect, BW, BH, 3, 1), ri = tsc_mean(rr.indirect, BW, BH, 3, 1);
    double gd = tsc_mean(gr.direct, BW, BH, 3, 1), rdm = tsc_mean(rr.direct, BW, BH, 3, 1);
    printf("lit box %ux%u: direct relMSE %.2e (mean %.4f vs %.4f), indirect mean %.4f vs %.4f (%.2f %%), "
           "beauty PSNR %.2f dB, %u photons stored\n",
           BW, BH, md.relmse, gd, rdm, gi, ri, 100 * (gi / ri - 1), mb.psnr, (unsigned)gr.stats.photons_stored);
    CHECK(md.relmse < 4e-3);
    CHECK(tsc_rel(gd, rdm) < 0.01);
    CHECK(tsc_rel(gi, ri) < 0.05);
    CHECK(mb.psnr > 24.0);
    CHECK(gr.stats.photons_stored > 0);
  }
  free(b);
  pb_render_result_destroy(&gr);
  pb_ref_result_destroy(&rr);

  /* The world gets its share of the budget; RSM traces the soft lights and
   * the world, so its picture matches the traced one within noise. */
  uint32_t n[8], f[8];
  CHECK_EQ_INT(pb_photon_slots(&s), 5);
  pb_photon_split_budget(&s, 100000, n, f);
  CHECK(n[4] > 0);
  CHECK_EQ_INT(n[0] + n[1] + n[2] + n[3] + n[4], 100000);
  pb_render_desc rt = {.spp = 16, .iterations = 4, .photons = 1u << 15, .seed = 5};
  pb_render_desc rs = rt;
  rs.first_bounce = PB_FIRST_BOUNCE_RSM;
  pb_render_result a, c;
  memset(&a, 0, sizeof a);
  memset(&c, 0, sizeof c);
  float *ba = gpu_render_desc(&s, 32, 32, &rt, &a), *bc = gpu_render_desc(&s, 32, 32, &rs, &c);
  if (ba && bc) {
    double ia = tsc_mean(a.indirect, 32, 32, 3, 1), ic = tsc_mean(c.indirect, 32, 32, 3, 1);
    printf("indirect mean, traced first bounce %.4f, RSM %.4f (%.2f %%)\n", ia, ic, 100 * (ic / ia - 1));
    CHECK(tsc_rel(ic, ia) < 0.03);
  }
  free(ba);
  free(bc);
  pb_render_result_destroy(&a);
  pb_render_result_destroy(&c);
  s.world.env = NULL;
  pb_scene_destroy(&s);
  free(map);
}

static void test_furnace(void) {
  pb_scene s;
  tsc_init(&s);
  uint32_t m = tsc_material(&s, tsc_lambert(1, 1, 1));
  float P[8][3] = {{-.5f, -.5f, 0}, {.5f, -.5f, 0}, {.5f, .5f, 0}, {-.5f, .5f, 0},
                   {-.5f, -.5f, 1}, {.5f, -.5f, 1}, {.5f, .5f, 1}, {-.5f, .5f, 1}};
  tsc_quad(&s, P[0], P[1], P[2], P[3], m);
  tsc_quad(&s, P[0], P[4], P[5], P[1], m);
  tsc_quad(&s, P[1], P[5], P[6], P[2], m);
  tsc_quad(&s, P[2], P[6], P[7], P[3], m);
  tsc_quad(&s, P[3], P[7], P[4], P[0], m);
  float pos[3] = {0.1f, 0.05f, 3}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  tsc_camera(&s, pos, fwd, up, 15.0f);
  s.world.present = 1;
  s.world.color[0] = s.world.color[1] = s.world.color[2] = 0.5f;
  pb_world_update_integral(&s.world);
  s.film_opaque = 1;
  pb_scene_finalize(&s);
  pb_render_desc rd = {.spp = 64, .iterations = 8, .photons = 1u << 16, .photon_bounces = 32, .seed = 6};
  float *b = gpu_render_desc(&s, W, H, &rd, NULL);
  if (b) {
    double mean = tsc_mean(b, W, H, 4, 0);
    printf("GPU furnace (open box, albedo 1, world 0.5): mean %.4f (%.2f %%)\n", mean, 100 * (mean / 0.5 - 1));
    CHECK(fabs(mean / 0.5 - 1) < 0.03);
    CHECK_NEAR(tsc_mean(b, W, H, 4, 3), 1.0, 0);
  }
  free(b);
  pb_scene_destroy(&s);
}

int main(void) {
  PBT_GPU_OPEN(g);
  G = g;
  slc_renderer = gpu_render;
  slc_run_all();
  test_full_render();
  test_furnace();
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
