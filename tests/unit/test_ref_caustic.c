/* SPPM caustics against a closed form. A point light at (0, 0, 1) above a
 * Lambertian floor (z = 0, albedo rho) and a perfect mirror (metal, base
 * colour 1, roughness 0: F = 1) in the plane x = 1, y in [-0.5, 0.5],
 * z in [0.2, 1.2], facing the light. The mirror's caustic on the floor is the
 * direct light of the light's mirror image at (2, 0, 1), where the line from
 * that image to the floor point passes through the mirror:
 *     L = rho/pi I cos / d^2 (direct, unless the mirror blocks it)
 *       + rho/pi I cos_v / d_v^2 (caustic, inside the reflected region).
 * With max_bounces 2 nothing else reaches the camera (which sees only the
 * floor): floor -> mirror -> floor needs three bounces.
 *
 * Checks: path tracing finds the direct part only (indirect exactly 0), the
 * SPPM render has the same direct part sample for sample and its indirect
 * part (the caustic) is within 5 % of the closed form at the brightest
 * pixels inside the region (away from its edge by more than the first photon
 * radius), and 0 outside. `--full` (tests/ref.cmake, not under sanitizers)
 * uses 4x the photons and checks six pixels at 2.5 %. */
#include <string.h>

#include "pbtest.h"
#include "test_ref_scene.h"

static const double RHO = 0.8, I = 10.0;

/* Does the segment from a to b cross the mirror rectangle? */
static int through_mirror(const double a[3], const double b[3]) {
  if ((a[0] - 1.0) * (b[0] - 1.0) >= 0) return 0;
  double t = (1.0 - a[0]) / (b[0] - a[0]);
  double y = a[1] + t * (b[1] - a[1]), z = a[2] + t * (b[2] - a[2]);
  return fabs(y) <= 0.5 && z >= 0.2 && z <= 1.2;
}

static double lit(const double src[3], const double p[3]) {
  double v[3] = {src[0] - p[0], src[1] - p[1], src[2] - p[2]};
  double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  return RHO / M_PI * I * (v[2] / sqrt(d2)) / d2;
}

static double direct(const double p[3], void *u) {
  (void)u;
  static const double light[3] = {0, 0, 1};
  return through_mirror(light, p) ? 0.0 : lit(light, p);
}

static double caustic(const double p[3], void *u) {
  (void)u;
  static const double image[3] = {2, 0, 1};
  /* Reflected light reaches the floor in front of the mirror only. */
  return p[0] < 1.0 && through_mirror(image, p) ? lit(image, p) : 0.0;
}

static void build(pb_scene *s) {
  tsc_init(s);
  uint32_t floor_m = tsc_material(s, tsc_lambert((float)RHO, (float)RHO, (float)RHO));
  uint32_t mirror_m = tsc_material(s, tsc_mirror());
  tsc_floor(s, 20.0f, 0.0f, floor_m);
  /* Facing -x (towards the light): counter-clockwise seen from x < 1. */
  float a[3] = {1, 0.5f, 0.2f}, b[3] = {1, -0.5f, 0.2f}, c[3] = {1, -0.5f, 1.2f},
        d[3] = {1, 0.5f, 1.2f};
  tsc_quad(s, a, b, c, d, mirror_m);
  pb_light *l = tsc_light(s, PB_LIGHT_POINT);
  l->position[2] = 1.0f;
  l->intensity = (float)I;
  float pos[3] = {-0.3f, 0, 3}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, 40.0f);
  pb_scene_finalize(s);
}

int main(int argc, char **argv) {
  int full = argc > 1 && strcmp(argv[1], "--full") == 0;
  enum { W = 16, H = 16 };
  pb_scene s;
  build(&s);
  CHECK(pb_ref_auto_mode(&s) == PB_REF_MODE_SPPM);

  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 64;
  d.max_bounces = 2;
  d.seed = 3;
  d.photons_per_pass = full ? 200000 : 50000;
  d.photon_radius = 0.15f;
  /* --full: a slower radius reduction keeps more photons per gather, for a
   * tighter check of the transport (bias ~ r^2 / 8 Laplacian(E) / E, under
   * 0.3 % here at r = 0.15). */
  if (full) d.photon_alpha = 0.9f;
  pb_ref_result pt, sp;
  d.mode = PB_REF_MODE_PT;
  CHECK_EQ_INT(pb_ref_render(&s, 0, W, H, &d, &pt), PB_OK);
  d.mode = PB_REF_MODE_SPPM;
  CHECK_EQ_INT(pb_ref_render(&s, 0, W, H, &d, &sp), PB_OK);
  if (!pt.beauty || !sp.beauty) {
    fprintf(stderr, "render failed: %s\n", pb_error_message());
    return pbt_done();
  }
  CHECK_EQ_INT(sp.stats.mode, PB_REF_MODE_SPPM);
  CHECK(sp.stats.photons_stored > 0);
  printf("photons: %llu paths, %llu stored; radius %.4f -> %.4f\n",
         (unsigned long long)sp.stats.photon_paths,
         (unsigned long long)sp.stats.photons_stored, (double)sp.stats.photon_radius_first,
         (double)sp.stats.photon_radius_last);

  /* Path tracing: no caustic at all, and the same direct light as SPPM. */
  int same_direct = 1;
  double pt_indirect = 0;
  for (size_t i = 0; i < 3 * (size_t)W * H; ++i) {
    pt_indirect += fabs(pt.indirect[i]);
    if (pt.direct[i] != sp.direct[i]) same_direct = 0;
  }
  CHECK_NEAR(pt_indirect, 0.0, 0.0);
  CHECK(same_direct);

  /* Pixels inside the reflected region, and beyond its side edges
   * (|y| > (2 - x) / 2) by more than the first radius. */
  static const uint32_t in[][2] = {{12, 8}, {14, 6}, {9, 11}, {2, 5}, {4, 13}, {7, 2}};
  static const uint32_t out[][2] = {{13, 0}, {14, 15}};
  /* Photon noise: about 1.5 % at the first three (brightest) pixels with the
   * short run, which checks only those at 5 %; --full checks all at 2.5 %. */
  double tol = full ? 0.025 : 0.05;
  unsigned n_in = full ? 6 : 3;
  for (unsigned k = 0; k < n_in; ++k) {
    uint32_t x = in[k][0], y = in[k][1];
    size_t i = (size_t)y * W + x;
    double wd = tsc_pixel_mean_on_plane(&s.cameras[0], W, H, x, y, 0.0, 48, direct, NULL);
    double wc = tsc_pixel_mean_on_plane(&s.cameras[0], W, H, x, y, 0.0, 48, caustic, NULL);
    printf("pixel (%2u,%2u): direct %.5f (want %.5f)  caustic %.5f (want %.5f, rel %.4f)\n",
           x, y, (double)sp.direct[3 * i], wd, (double)sp.indirect[3 * i], wc,
           tsc_rel(sp.indirect[3 * i], wc));
    CHECK(wc > 0.05);
    CHECK(tsc_rel(sp.direct[3 * i], wd) <= 0.01);
    for (int c = 0; c < 3; ++c) CHECK(tsc_rel(sp.indirect[3 * i + (size_t)c], wc) <= tol);
  }
  for (unsigned k = 0; k < sizeof out / sizeof *out; ++k) {
    uint32_t x = out[k][0], y = out[k][1];
    size_t i = (size_t)y * W + x;
    double wc = tsc_pixel_mean_on_plane(&s.cameras[0], W, H, x, y, 0.0, 48, caustic, NULL);
    printf("pixel (%2u,%2u): caustic %.5f (want %.5f)\n", x, y, (double)sp.indirect[3 * i], wc);
    CHECK_NEAR(wc, 0.0, 0.0);
    CHECK_NEAR(sp.indirect[3 * i], 0.0, 1e-3);
  }
  pb_ref_result_destroy(&pt);
  pb_ref_result_destroy(&sp);
  pb_scene_destroy(&s);
  return pbt_done();
}
