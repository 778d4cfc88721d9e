/* export-pov through POV-Ray 3.7 against analytic radiance: a Lambertian
 * plane (albedo 0.8) under a point light, a parallel light at 30 degrees and
 * a spot light (inside the inner cone, in the smooth-step band, outside), and
 * an asymmetric scene that must not come out mirrored. Renders are tiny,
 * unantialiased (-A) and single-threaded; the pixel read is the centre of an
 * odd-sized image, which sees the camera's axis exactly. Exit 77 (skip) when
 * povray is not installed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/image.h"
#include "pbtest.h"
#include "pov/pov.h"
#include "test_pov_scene.h"

static char tmpdir[] = "/tmp/pb_test_pov_render.XXXXXX";
static const float rho = 0.8f;

/* Exports camera `cam` of `s`, renders it W x H, returns the image. */
static int render(const pb_scene *s, int cam, const char *name, uint32_t w, uint32_t h, pb_image *img) {
  char pov[256], exr[256], cmd[1024];
  snprintf(pov, sizeof pov, "%s/%s.pov", tmpdir, name);
  snprintf(exr, sizeof exr, "%s/%s.exr", tmpdir, name);
  pb_pov_desc d = {.width = w, .height = h, .camera = cam, .quality = PB_POV_DIRECT, .fade_distance = 0.001f};
  if (pb_pov_export(s, &d, pov, NULL) != PB_OK) {
    fprintf(stderr, "export failed: %s\n", pb_error_message());
    return 0;
  }
  snprintf(cmd, sizeof cmd, "sh validation/run_povray.sh '%s' '%s' -- -A +WT1 >/dev/null", pov, exr);
  if (system(cmd) != 0) {
    fprintf(stderr, "povray failed on %s (log %s.log)\n", pov, exr);
    return 0;
  }
  if (pb_exr_read(exr, NULL, img) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return 0;
  }
  return 1;
}

static float pixel(const pb_image *img, uint32_t x, uint32_t y, const char *ch) {
  int c = pb_image_find_channel(img, ch);
  if (c < 0) return NAN;
  return img->pixels[((size_t)y * img->width + x) * img->channel_count + (uint32_t)c];
}

static float centre(const pb_image *img) { return pixel(img, img->width / 2, img->height / 2, "G"); }

static void ground(pb_scene *s) {
  tps_init(s);
  uint32_t m = tps_material(s, "albedo08", rho, rho, rho);
  tps_quad_y(s, -20, 20, -20, 20, 0, m);
}

static void report(const char *what, double pov, double want) {
  printf("%-44s POV-Ray %.5g  analytic %.5g  (%+.3f %%)\n", what, pov, want, 100.0 * (pov / want - 1.0));
}

/* rho/pi * I / d^2 at the foot of a point light 1 m above the plane. */
static void test_point(void) {
  pb_scene s;
  ground(&s);
  pb_light *l = tps_light(&s, PB_LIGHT_POINT, "point");
  l->position[1] = 1;
  l->intensity = 100.0f / (4.0f * (float)M_PI); /* a 100 W Blender point light */
  tps_camera_down(&s, "top", 0, 3, 0, 10);
  /* Oblique incidence: the points 60 and 80 degrees off the light's foot. */
  tps_camera_down(&s, "at60", (float)tan(M_PI / 3), 3, 0, 0.5f);
  tps_camera_down(&s, "at80", (float)tan(80 * M_PI / 180), 3, 0, 0.5f);
  pb_scene_finalize(&s);
  pb_image img;
  for (int i = 1; i < 3; ++i) {
    const double th = (i == 1 ? 60 : 80) * M_PI / 180, c = cos(th);
    if (!render(&s, i, i == 1 ? "point60" : "point80", 9, 9, &img)) {
      CHECK(0);
      continue;
    }
    const double want = rho / M_PI * l->intensity * c * c * c; /* cos / d^2 = cos^3 / h^2 */
    report(i == 1 ? "point light, 60 deg incidence" : "point light, 80 deg incidence", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    pb_image_destroy(&img);
  }
  if (render(&s, 0, "point", 33, 33, &img)) {
    const double want = rho / M_PI * l->intensity / 1.0;
    report("point light, 1 m, centre", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    /* Red and blue are the same (white light, grey plane). */
    CHECK_NEAR(pixel(&img, 16, 16, "R"), centre(&img), 1e-3 * centre(&img));
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  pb_scene_destroy(&s);
}

/* rho/pi * E cos(30 deg) under a parallel light tilted 30 degrees. */
static void test_parallel(void) {
  pb_scene s;
  ground(&s);
  pb_light *l = tps_light(&s, PB_LIGHT_DIRECTIONAL, "sun");
  l->direction[0] = 0.5f; /* travels down and towards +x, 30 degrees off vertical */
  l->direction[1] = -(float)sqrt(0.75);
  l->intensity = 4;
  tps_camera_down(&s, "top", 0, 3, 0, 10);
  pb_scene_finalize(&s);
  pb_image img;
  if (render(&s, 0, "parallel", 33, 33, &img)) {
    const double want = rho / M_PI * 4.0 * cos(M_PI / 6);
    report("parallel light at 30 deg, centre", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    /* No fall-off: a corner sees the same. */
    CHECK_NEAR(pixel(&img, 0, 0, "G") / want, 1.0, 0.01);
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  pb_scene_destroy(&s);
}

static double smoothstep(double e0, double e1, double x) {
  double t = (x - e0) / (e1 - e0);
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  return t * t * (3 - 2 * t);
}

/* Spot 1 m above the plane pointing down, cones 20/30 degrees. Cameras look
 * straight down at the points 10, 25 (in the band) and 35 degrees off the
 * axis; a very narrow field keeps any half-pixel convention out of it. */
static void test_spot(void) {
  pb_scene s;
  ground(&s);
  pb_light *l = tps_light(&s, PB_LIGHT_SPOT, "spot");
  l->position[1] = 1;
  l->intensity = 100.0f / (4.0f * (float)M_PI);
  l->inner_cone = 20.0f * (float)M_PI / 180;
  l->outer_cone = 30.0f * (float)M_PI / 180;
  const double angles[] = {0, 10, 25, 28, 35};
  for (int i = 0; i < 5; ++i) {
    char name[32];
    snprintf(name, sizeof name, "a%g", angles[i]);
    tps_camera_down(&s, name, (float)tan(angles[i] * M_PI / 180), 2, 0, 0.5f);
  }
  pb_scene_finalize(&s);
  for (int i = 0; i < 5; ++i) {
    pb_image img;
    char name[32];
    snprintf(name, sizeof name, "spot%g", angles[i]);
    if (!render(&s, i, name, 9, 9, &img)) {
      CHECK(0);
      continue;
    }
    const double th = angles[i] * M_PI / 180, c = cos(th);
    /* E = I cos(theta) / d^2 with d = 1/cos(theta): I cos^3. */
    const double want = rho / M_PI * l->intensity * c * c * c *
                        smoothstep(cos(l->outer_cone), cos(l->inner_cone), c);
    char what[64];
    snprintf(what, sizeof what, "spot light, %g deg off axis", angles[i]);
    report(what, centre(&img), want);
    if (want > 0)
      CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    else
      CHECK(centre(&img) == 0.0f);
    pb_image_destroy(&img);
  }
  pb_scene_destroy(&s);
}

/* Top-right quadrant (x > 0, z < 0 in glTF, seen from above with the image's
 * top towards -z) albedo 0.9, top-left 0.5, bottom half 0.1, lit straight
 * down by E = pi so that radiance = albedo. A mirrored export would swap
 * left and right (or top and bottom). */
static void test_handedness(void) {
  pb_scene s;
  tps_init(&s);
  uint32_t a = tps_material(&s, "topright", 0.9f, 0.9f, 0.9f);
  uint32_t b = tps_material(&s, "topleft", 0.5f, 0.5f, 0.5f);
  uint32_t c = tps_material(&s, "bottom", 0.1f, 0.1f, 0.1f);
  tps_quad_y(&s, 0, 5, -5, 0, 0, a);
  tps_quad_y(&s, -5, 0, -5, 0, 0, b);
  tps_quad_y(&s, -5, 5, 0, 5, 0, c);
  pb_light *l = tps_light(&s, PB_LIGHT_DIRECTIONAL, "sun");
  l->intensity = (float)M_PI;
  tps_camera_down(&s, "top", 0, 3, 0, 40);
  pb_scene_finalize(&s);
  pb_image img;
  if (render(&s, 0, "hand", 32, 32, &img)) {
    const float tr = pixel(&img, 24, 8, "G"), tl = pixel(&img, 8, 8, "G"), bl = pixel(&img, 8, 24, "G"),
                br = pixel(&img, 24, 24, "G");
    printf("handedness: top-left %.3f top-right %.3f bottom %.3f %.3f (want 0.5 0.9 0.1 0.1)\n", tl, tr, bl, br);
    CHECK_NEAR(tr, 0.9, 0.01);
    CHECK_NEAR(tl, 0.5, 0.01);
    CHECK_NEAR(bl, 0.1, 0.01);
    CHECK_NEAR(br, 0.1, 0.01);
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  pb_scene_destroy(&s);
}

int main(void) {
  if (system("command -v povray >/dev/null 2>&1") != 0) {
    printf("skip: povray is not installed\n");
    return 77;
  }
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_point();
  test_parallel();
  test_spot();
  test_handedness();
  if (!getenv("PB_KEEP")) {
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  }
  return pbt_done();
}
