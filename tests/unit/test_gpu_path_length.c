/* Path length: a closed room (a 2 x 2 x 2 m box, every
 * wall Lambert 0.75, no specular layer) lit by a point light inside. All the
 * light stays in the room, so a path of k scattering events carries rho^k
 * of it and a limit of 8 events loses rho^8 (10 %) of the indirect light.
 *
 * The truth is the Embree reference with an explicit limit of 1024 events
 * (Russian roulette ends its paths; test_ref_furnace checks that the
 * reference's default equals Le / (1 - rho) exactly). The GPU pipeline at its
 * defaults (photon paths ended by Russian roulette, photon.h) must agree with
 * it on the image mean within 3 % (its own noise and the kernel's blur at
 * the room's edges are below 1 %); at the old default of 7 stored photon
 * bounces it is measured too, and must be darker by more than 5 %, so the
 * test tells the two apart. 32 x 32 px, 4 maps of 2^15 photons. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "test_ref_scene.h"
#include "ref/ref.h"
#include "render/render.h"

static const float RHO = 0.75f;

static void room(pb_scene *s) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert(RHO, RHO, RHO));
  /* The eight corners of [-1, 1]^3; every quad counter-clockwise seen from
   * inside (its front faces the room). */
  float c[8][3];
  for (int i = 0; i < 8; ++i) {
    c[i][0] = (i & 1) ? 1.0f : -1.0f;
    c[i][1] = (i & 2) ? 1.0f : -1.0f;
    c[i][2] = (i & 4) ? 1.0f : -1.0f;
  }
  static const int q[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                              {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (int f = 0; f < 6; ++f) tsc_quad(s, c[q[f][0]], c[q[f][1]], c[q[f][2]], c[q[f][3]], m);
  pb_light *l = tsc_light(s, PB_LIGHT_POINT);
  l->position[0] = 0.2f, l->position[1] = 0.5f, l->position[2] = -0.1f;
  l->intensity = 2.0f;
  float pos[3] = {-0.6f, -0.5f, 0.7f}, fwd[3] = {0.6f, 0.4f, -0.7f}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, 75.0f);
  pb_scene_finalize(s);
}

static double image_mean(const float *px, uint32_t w, uint32_t h, uint32_t ch) {
  double m = 0;
  for (int c = 0; c < 3; ++c) m += tsc_mean(px, w, h, ch, c) / 3.0;
  return m;
}

int main(void) {
  PBT_GPU_OPEN(g);
  pb_scene s;
  room(&s);
  /* The quads must face inward: the reference's direct light is then lit. */
  enum { W = 32, H = 32 };
  pb_ref_desc fd = {.spp = 256, .max_bounces = 1024, .seed = 3, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_ref_result rr;
  memset(&rr, 0, sizeof rr);
  r = pb_ref_render(&s, 0, W, H, &fd, &rr);
  CHECK_EQ_INT(r, PB_OK);
  pb_gpu_scene gs;
  r = pb_gpu_scene_create(g, &s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK || !rr.beauty) goto out;
  double ref = image_mean(rr.beauty, W, H, 4), ref_direct = image_mean(rr.direct, W, H, 3);
  printf("reference, 1024 events: mean %.5f (direct %.5f, indirect / direct %.3f; a room of albedo %.2f: about "
         "rho / (1 - rho) = %.2f)\n",
         ref, ref_direct, (ref - ref_direct) / ref_direct, (double)RHO, RHO / (1.0 - RHO));
  CHECK(ref_direct > 0);
  double got[2] = {0, 0};
  for (int old = 0; old < 2; ++old) {
    pb_render_desc rd = {.spp = 4, .seed = 1, .photons = 1u << 15, .iterations = 4,
                         .photon_bounces = old ? 7u : 0u};
    pb_render_result gr;
    memset(&gr, 0, sizeof gr);
    r = pb_render_frame(g, &s, &gs, 0, W, H, &rd, &gr);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) {
      got[old] = image_mean(gr.beauty, W, H, 4);
      printf("GPU %-28s mean %.5f, %+.2f %% against the reference; photons emitted %llu, stored %llu, "
             "k_PD %.1f\n",
             old ? "7 stored bounces (old):" : "default (Russian roulette):", got[old],
             100.0 * (got[old] / ref - 1.0), (unsigned long long)gr.stats.photons_emitted,
             (unsigned long long)gr.stats.photons_stored, gr.stats.k_pd);
    } else {
      fprintf(stderr, "%s\n", pb_error_message());
    }
    pb_render_result_destroy(&gr);
  }
  CHECK(fabs(got[0] / ref - 1.0) < 0.03);
  CHECK(got[1] / ref - 1.0 < -0.05);
  pb_gpu_scene_destroy(g, &gs);
out:
  pb_ref_result_destroy(&rr);
  pb_scene_destroy(&s);
  pb_gpu_destroy(g);
  return pbt_done();
}
