/* The reference renderer's soft lights and world against closed forms and
 * independent integrals (every threshold can fail):
 *  - a square area light over a Lambertian plane: the point-to-rectangle
 *    form factor (four corner rectangles, Howell's factor B-3), 4 x 4 pixel
 *    blocks within 0.5 %;
 *  - a disc and an ellipse (0.75 %; sampled by area, as Cycles does, so
 *    noisier), squares and rectangles with spread 60
 *    and 30 degrees (1.5 %: the profile makes light samples noisy, in
 *    Cycles too): the irradiance integrated over the light's surface in
 *    double precision (radiance x spread profile x both cosines / r^2);
 *  - a sphere light of radius r (Cycles 3.4's disc facing the lit point)
 *    against its integral within 0.5 %, converging to the point light as
 *    r -> 0 (the difference falls like r^2);
 *  - a soft spot (Cycles' falloff, radius 0.2) against its integral (1 %);
 *  - a sun of 4 degrees behind the straight edge of a plate: the penumbra's
 *    profile is the area of the sun's disc beyond the edge (the circular
 *    segment, closed form), within 1 % of the full irradiance, and its
 *    width (5 % to 95 %) is the closed form's within a pixel;
 *  - a uniform world over a plane: rho x L exactly (every pixel 1e-4);
 *  - a white furnace: an open box of albedo 1 in a uniform world has
 *    radiance L everywhere (6 x 6 blocks within 5 % at 256 spp, the mean
 *    within 0.5 %);
 *  - an environment map with one bright texel, turned by a Mapping
 *    rotation, lights a plane as a directional light of its integrated
 *    radiance from the direction the test computes on its own (0.5 %); the
 *    map's sampling pdf matches its samples and integrates to 1;
 *  - camera rays that leave the scene: the map's bilinear texel at the
 *    direction the test maps independently, box-filtered over a pixel
 *    (0.3 %), alpha 1 with an opaque
 *    film, the coverage and no colour with a transparent one, black when
 *    hidden from the camera;
 *  - MIS: an area light over a glossy plane with and without MIS agree
 *    (the same integral, two estimators) within their noise;
 *  - lights are seen by the camera and do not stop rays. */
#include "soft_light_cases.h"

/* The reference as the renderer of soft_light_cases.h (SPP overrides the
 * sample counts, for exploring noise). */
static float *ref_render(const pb_scene *s, uint32_t w, uint32_t h, uint32_t spp, uint64_t seed) {
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = getenv("SPP") ? (uint32_t)atoi(getenv("SPP")) : spp;
  d.seed = seed;
  pb_ref_result r;
  pb_result res = pb_ref_render(s, 0, w, h, &d, &r);
  CHECK_EQ_INT(res, PB_OK);
  if (res != PB_OK) {
    fprintf(stderr, "render: %s\n", pb_error_message());
    return NULL;
  }
  CHECK_EQ_INT(r.stats.guarded_samples, 0);
  float *b = r.beauty;
  r.beauty = NULL;
  pb_ref_result_destroy(&r);
  return b;
}

static void test_furnace(void) {
  pb_scene s;
  pb_ref_result r;
  /* Furnace: an open box (floor and four walls, 1 m, albedo 1) seen from
   * above, inside the uniform world. */
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
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 256;
  d.max_bounces = 64;
  d.seed = 41;
  pb_result res = pb_ref_render(&s, 0, W, H, &d, &r);
  CHECK_EQ_INT(res, PB_OK);
  if (res == PB_OK) {
    /* Russian roulette makes single pixels noisy: 6 x 6 blocks, and the
     * whole image's mean. */
    double worst = 0, mean = 0;
    for (uint32_t by = 0; by < H; by += 6)
      for (uint32_t bx = 0; bx < W; bx += 6) {
        double b = 0;
        for (uint32_t y = by; y < by + 6; ++y)
          for (uint32_t x = bx; x < bx + 6; ++x) b += r.beauty[4 * ((size_t)y * W + x)] / 36;
        worst = fmax(worst, fabs(b / 0.5 - 1));
        mean += b / 16;
      }
    printf("furnace (open box, albedo 1): worst 6x6 block %.2f %%, mean %.3f %%\n", 100 * worst, 100 * (mean / 0.5 - 1));
    CHECK(worst < 0.05);
    CHECK(fabs(mean / 0.5 - 1) < 0.005);
    pb_ref_result_destroy(&r);
  }
  pb_scene_destroy(&s);
}

/* ---- MIS and visibility ---------------------------------------------------- */

static void test_mis(void) {
  pb_scene s;
  tsc_init(&s);
  pb_material g = tsc_lambert(0.6f, 0.6f, 0.6f);
  g.specular = 1; /* a glossy dielectric layer: rough GGX over diffuse */
  g.specular_color[0] = g.specular_color[1] = g.specular_color[2] = 1;
  g.roughness = 0.3f;
  uint32_t m = tsc_material(&s, g);
  tsc_floor(&s, 20.0f, 0.0f, m);
  float pos[3] = {0, -2.0f, 1.0f}, fwd[3] = {0, 2.0f, -1.0f}, up[3] = {0, 0, 1};
  tsc_camera(&s, pos, fwd, up, 40.0f);
  pb_light *l = area_light(&s, PB_AREA_RECTANGLE, 1.0f, 0.5f, 1.0f, 20.0f);
  l->position[1] = 1.0f;
  pb_scene_finalize(&s);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 256;
  d.estimate_noise = 1;
  pb_ref_result a, b;
  int ok = pb_ref_render(&s, 0, W, H, &d, &a) == PB_OK;
  s.lights[0].no_mis = 1;
  d.seed = 99;
  ok = ok && pb_ref_render(&s, 0, W, H, &d, &b) == PB_OK;
  CHECK(ok);
  if (ok) {
    double ma = tsc_mean(a.beauty, W, H, 4, 0), mb = tsc_mean(b.beauty, W, H, 4, 0);
    double na = a.stats.noise_rmse, nb = b.stats.noise_rmse;
    printf("glossy plane, MIS %.5f (noise rmse %.4f) vs light sampling only %.5f (%.4f): %.3f %%\n", ma, na, mb, nb,
           100 * tsc_rel(ma, mb));
    CHECK(tsc_rel(ma, mb) < 0.01);
    CHECK(na <= nb * 1.1); /* MIS is not worse here */
    pb_ref_result_destroy(&a);
    pb_ref_result_destroy(&b);
  }
  pb_scene_destroy(&s);
}

int main(void) {
  slc_renderer = ref_render;
  slc_run_all();
  test_furnace();
  test_mis();
  return pbt_done();
}
