/* The reference renderer against closed-form answers for a Lambertian plane
 * (albedo rho, nothing else in the scene) lit by one delta light:
 *   point:       L = rho/pi * I cos(theta) / d^2
 *   spot:        the same times smoothstep(cos outer, cos inner, cos angle),
 *                checked inside the inner cone, in the smooth-step band and
 *                outside the outer cone (exactly 0)
 *   directional: L = rho/pi * E cos(theta)
 * Each pixel's expected value is the analytic radiance averaged over the
 * pixel's footprint on the plane (a 48x48 midpoint rule through the same
 * camera model), which is what a box-filtered render converges to; the
 * render's only noise is then the jitter of sample positions inside a pixel.
 * Threshold: 0.5 % per pixel. Also: the back of a single-sided plane shades
 * like its front (flipped normal), and AOVs hold what ref.h promises. */
#include "pbtest.h"
#include "test_ref_scene.h"

enum { W = 32, H = 32 };

typedef struct plane_case {
  double rho;
  pb_light light;
} plane_case;

static double smoothstep(double e0, double e1, double x) {
  double t = (x - e0) / (e1 - e0);
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return t * t * (3 - 2 * t);
}

/* Radiance leaving the plane z = 0 (normal +z) at p. */
static double analytic(const double p[3], void *user) {
  const plane_case *pc = user;
  const pb_light *l = &pc->light;
  double I = l->intensity * l->color[0];
  if (l->type == PB_LIGHT_DIRECTIONAL) {
    double d[3] = {l->direction[0], l->direction[1], l->direction[2]};
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double c = -d[2] / n;
    return c > 0 ? pc->rho / M_PI * I * c : 0.0;
  }
  double v[3] = {l->position[0] - p[0], l->position[1] - p[1], l->position[2] - p[2]};
  double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], d = sqrt(d2);
  double c = v[2] / d;
  if (c <= 0) return 0;
  double k = 1.0;
  if (l->type == PB_LIGHT_SPOT) {
    double ax[3] = {l->direction[0], l->direction[1], l->direction[2]};
    double an = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    double ca = -(ax[0] * v[0] + ax[1] * v[1] + ax[2] * v[2]) / (an * d);
    k = smoothstep(cos(l->outer_cone), cos(l->inner_cone), ca);
  }
  return pc->rho / M_PI * I * k * c / d2;
}

static void build(pb_scene *s, const plane_case *pc, float cam_z, float yfov) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert((float)pc->rho, (float)pc->rho, (float)pc->rho));
  tsc_floor(s, 20.0f, 0.0f, m);
  pb_light *l = tsc_light(s, pc->light.type);
  char name[PB_NAME_MAX];
  memcpy(name, l->name, sizeof name);
  *l = pc->light;
  memcpy(l->name, name, sizeof name);
  float pos[3] = {0, 0, cam_z}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, yfov);
  pb_scene_finalize(s);
}

/* Renders and checks pixel (x, y) within tol (relative), or <= 1e-6 when the
 * expected value is 0. */
static void check_pixels(const char *what, const plane_case *pc, float cam_z,
                         float yfov, const uint32_t (*px)[2], int npx, double tol,
                         uint32_t spp) {
  pb_scene s;
  build(&s, pc, cam_z, yfov);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = spp;
  d.seed = 7;
  pb_ref_result r;
  pb_result res = pb_ref_render(&s, 0, W, H, &d, &r);
  CHECK_EQ_INT(res, PB_OK);
  if (res != PB_OK) {
    fprintf(stderr, "%s: %s\n", what, pb_error_message());
    pb_scene_destroy(&s);
    return;
  }
  CHECK_EQ_INT(r.stats.guarded_samples, 0);
  CHECK_EQ_INT(r.stats.spp, spp);
  for (int i = 0; i < npx; ++i) {
    uint32_t x = px[i][0], y = px[i][1];
    double want = tsc_pixel_mean_on_plane(&s.cameras[0], W, H, x, y, 0.0, 48, analytic,
                                          (void *)pc);
    const float *got = &r.beauty[4 * ((size_t)y * W + x)];
    printf("%-12s pixel (%2u,%2u): render %.6f  analytic %.6f  rel %.2e\n", what, x, y,
           (double)got[0], want, want > 0 ? tsc_rel(got[0], want) : fabs(got[0]));
    for (int c = 0; c < 3; ++c) {
      if (want > 0) CHECK(tsc_rel(got[c], want) <= tol);
      else CHECK(fabs(got[c]) <= 1e-6);
    }
    /* Everything here is direct light: one scattering event. */
    CHECK_NEAR(r.indirect[3 * ((size_t)y * W + x)], 0.0, 1e-9);
  }
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

static void test_point(void) {
  plane_case pc;
  memset(&pc, 0, sizeof pc);
  pc.rho = 0.8;
  pc.light.type = PB_LIGHT_POINT;
  pc.light.position[0] = 0.3f;
  pc.light.position[1] = -0.2f;
  pc.light.position[2] = 1.0f;
  pc.light.color[0] = pc.light.color[1] = pc.light.color[2] = 1;
  pc.light.intensity = 10.0f;
  static const uint32_t px[][2] = {{16, 16}, {19, 18}, {3, 28}, {28, 5}, {0, 0}, {10, 20}};
  check_pixels("point", &pc, 3.0f, 40.0f, px, 6, 0.005, 512);
}

static void test_spot(void) {
  plane_case pc;
  memset(&pc, 0, sizeof pc);
  pc.rho = 0.6;
  pc.light.type = PB_LIGHT_SPOT;
  pc.light.position[2] = 1.5f;
  pc.light.direction[2] = -1.0f;
  pc.light.color[0] = pc.light.color[1] = pc.light.color[2] = 1;
  pc.light.intensity = 20.0f;
  pc.light.inner_cone = 20.0f * (float)M_PI / 180.0f;
  pc.light.outer_cone = 35.0f * (float)M_PI / 180.0f;
  /* Camera at z = 3 with yfov 60: the image spans +-1.73 m, 0.108 m per
   * pixel. Inner cone edge on the plane: r = 0.546 m, outer: r = 1.050 m. */
  static const uint32_t px[][2] = {
      {16, 16}, {18, 14},          /* inside: r < 0.3 */
      {23, 16}, {16, 23}, {21, 21}, /* band: r = 0.76, 0.76, 0.76 */
      {24, 16}, {16, 7},           /* band, outer part: r 0.87-0.97 */
      {30, 16}, {2, 2}, {29, 29}}; /* outside: r > 1.5 */
  check_pixels("spot", &pc, 3.0f, 60.0f, px, 10, 0.005, 512);
}

static void test_directional(void) {
  plane_case pc;
  memset(&pc, 0, sizeof pc);
  pc.rho = 0.5;
  pc.light.type = PB_LIGHT_DIRECTIONAL;
  pc.light.direction[0] = -0.5f;
  pc.light.direction[2] = -1.0f;
  tsc_norm3(pc.light.direction);
  pc.light.color[0] = pc.light.color[1] = pc.light.color[2] = 1;
  pc.light.intensity = 3.0f;
  static const uint32_t px[][2] = {{16, 16}, {0, 31}, {31, 0}, {7, 9}};
  check_pixels("directional", &pc, 3.0f, 40.0f, px, 4, 0.005, 16);
}

/* The back of a single-sided plane, seen and lit from below, shades like the
 * front with the normal flipped; AOVs: albedo = rho, normal faces the
 * camera, depth = camera-space z, alpha = 1 where the plane covers. */
static void test_back_face_and_aovs(void) {
  plane_case pc;
  memset(&pc, 0, sizeof pc);
  pc.rho = 0.8;
  pc.light.type = PB_LIGHT_POINT;
  pc.light.position[2] = -1.0f;
  pc.light.color[0] = pc.light.color[1] = pc.light.color[2] = 1;
  pc.light.intensity = 5.0f;
  pb_scene s;
  tsc_init(&s);
  uint32_t m = tsc_material(&s, tsc_lambert(0.8f, 0.8f, 0.8f));
  tsc_floor(&s, 20.0f, 0.0f, m);
  pb_light *l = tsc_light(&s, PB_LIGHT_POINT);
  l->position[2] = -1.0f;
  l->intensity = 5.0f;
  float pos[3] = {0, 0, -3}, fwd[3] = {0, 0, 1}, up[3] = {0, 1, 0};
  tsc_camera(&s, pos, fwd, up, 40.0f);
  pb_scene_finalize(&s);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 256;
  pb_ref_result r;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 16, 16, &d, &r), PB_OK);
  if (!r.beauty) {
    pb_scene_destroy(&s);
    return;
  }
  /* Pixel (8, 8)'s footprint straddles the light's foot; compare the mean of
   * the centre 2x2 pixels with the analytic mean of the same area, mirrored
   * (the plane seen from below is the plane seen from above, reflected). */
  double want = 0, got = 0;
  pb_light mirrored = pc.light;
  mirrored.position[2] = 1.0f;
  pc.light = mirrored;
  /* The same camera mirrored through the plane (right and up kept), so a
   * pixel sees the same point of the plane. */
  pb_camera above = s.cameras[0];
  above.position[2] = 3.0f;
  above.forward[2] = -1.0f;
  for (uint32_t y = 7; y <= 8; ++y)
    for (uint32_t x = 7; x <= 8; ++x) {
      want += 0.25 * tsc_pixel_mean_on_plane(&above, 16, 16, x, y, 0.0, 48,
                                             analytic, &pc);
      got += 0.25 * r.beauty[4 * (y * 16 + x)];
    }
  printf("back face: render %.6f analytic %.6f\n", got, want);
  CHECK(tsc_rel(got, want) <= 0.005);
  size_t i = 8 * 16 + 8;
  CHECK_NEAR(r.albedo[3 * i], 0.8, 1e-5);
  CHECK_NEAR(r.normal[3 * i + 2], -1.0, 1e-5);  /* facing the camera below */
  CHECK_NEAR(r.depth[i], 3.0, 0.01);            /* camera-space z */
  CHECK_NEAR(r.beauty[4 * i + 3], 1.0, 1e-6);   /* coverage */
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

int main(void) {
  test_point();
  test_spot();
  test_directional();
  test_back_face_and_aovs();
  return pbt_done();
}
