/* export-peer through LuxCoreRender (pyluxcore) and Mitsuba 3 against
 * analytic radiance, as test_pov_render does for POV-Ray: a Lambertian plane
 * (albedo 0.8) under a point light (1 m above, and seen 60 and 80 degrees off
 * its foot), a parallel light at 30 degrees, and a spot light (cones 20/30
 * degrees) seen 0, 10, 25, 28 and 35 degrees off its axis. Each centre pixel
 * within 1 % of rho/pi x irradiance: a wrong unit (4 pi, pi, 683) fails by
 * far more. The spot's profile differs by design (docs/peers.md): each peer
 * is held to its own documented profile off the axis, and to glTF's where the
 * profiles agree (on the axis; Mitsuba inside the inner cone).
 *
 * Needs the peers' virtual environments (scripts/install-deps.sh):
 * tools/luxcore/bin/python and tools/mitsuba3/bin/python, or
 * $PB_LUXCORE_PYTHON / $PB_MITSUBA_PYTHON; a missing one FAILS (no skip).
 * argv[1]: luxcore, mitsuba or both (default); $PB_MITSUBA_VARIANT picks
 * Mitsuba's variant (default scalar_rgb). Renders 33x33 / 9x9 px, 16
 * samples (the plane is alone: no indirect light; the pixels are narrow, so
 * there is no noise to speak of), two threads. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/image.h"
#include "pbtest.h"
#include "peer/peer.h"
#include "test_pov_scene.h"

static char tmpdir[] = "/tmp/pb_test_peer_render.XXXXXX";
static const float rho = 0.8f;
static const char *python[2];

static int render(const pb_scene *s, int cam, pb_peer_format fmt, const char *name, uint32_t w, uint32_t h,
                  pb_image *img) {
  char dir[256], exr[300], cmd[1400];
  snprintf(dir, sizeof dir, "%s/%s_%s", tmpdir, name, pb_peer_format_names[fmt]);
  snprintf(exr, sizeof exr, "%s.exr", dir);
  pb_peer_desc d = {.format = fmt, .width = w, .height = h, .camera = cam, .spp = 16, .threads = 2};
  if (pb_peer_export(s, &d, dir, NULL) != PB_OK) {
    fprintf(stderr, "export failed: %s\n", pb_error_message());
    return 0;
  }
  const char *variant = getenv("PB_MITSUBA_VARIANT"); /* default scalar_rgb (the driver's) */
  char extra[96] = "";
  if (fmt == PB_PEER_MITSUBA && variant && variant[0]) snprintf(extra, sizeof extra, " --variant '%s'", variant);
  snprintf(cmd, sizeof cmd, "'%s' validation/peer_render.py %s '%s' '%s' --spp 16 --threads 2%s >'%s.log' 2>&1",
           python[fmt], pb_peer_format_names[fmt], dir, exr, extra, exr);
  if (system(cmd) != 0) {
    fprintf(stderr, "%s failed on %s (log %s.log)\n", pb_peer_format_names[fmt], dir, exr);
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

static void report(pb_peer_format f, const char *what, double got, double want) {
  printf("%-8s %-40s %.6g  analytic %.6g  (%+.3f %%)\n", pb_peer_format_names[f], what, got, want,
         want > 0 ? 100.0 * (got / want - 1.0) : 0.0);
}

static void test_point(pb_peer_format f) {
  pb_scene s;
  ground(&s);
  pb_light *l = tps_light(&s, PB_LIGHT_POINT, "point");
  l->position[1] = 1;
  l->intensity = 100.0f / (4.0f * (float)M_PI);
  tps_camera_down(&s, "top", 0, 3, 0, 10);
  tps_camera_down(&s, "at60", (float)tan(M_PI / 3), 3, 0, 0.5f);
  tps_camera_down(&s, "at80", (float)tan(80 * M_PI / 180), 3, 0, 0.5f);
  pb_scene_finalize(&s);
  pb_image img;
  if (render(&s, 0, f, "point", 33, 33, &img)) {
    const double want = rho / M_PI * l->intensity;
    report(f, "point light, 1 m, centre", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    CHECK_NEAR(pixel(&img, 16, 16, "R"), centre(&img), 1e-3 * centre(&img));
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  for (int i = 1; i < 3; ++i) {
    const double c = cos((i == 1 ? 60 : 80) * M_PI / 180);
    if (!render(&s, i, f, i == 1 ? "point60" : "point80", 9, 9, &img)) {
      CHECK(0);
      continue;
    }
    const double want = rho / M_PI * l->intensity * c * c * c;
    report(f, i == 1 ? "point light, 60 deg incidence" : "point light, 80 deg incidence", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    pb_image_destroy(&img);
  }
  pb_scene_destroy(&s);
}

static void test_parallel(pb_peer_format f) {
  pb_scene s;
  ground(&s);
  pb_light *l = tps_light(&s, PB_LIGHT_DIRECTIONAL, "sun");
  l->direction[0] = 0.5f;
  l->direction[1] = -(float)sqrt(0.75);
  l->intensity = 4;
  tps_camera_down(&s, "top", 0, 3, 0, 10);
  pb_scene_finalize(&s);
  pb_image img;
  if (render(&s, 0, f, "parallel", 33, 33, &img)) {
    const double want = rho / M_PI * 4.0 * cos(M_PI / 6);
    report(f, "parallel light at 30 deg, centre", centre(&img), want);
    CHECK_NEAR(centre(&img) / want, 1.0, 0.01);
    report(f, "parallel light at 30 deg, corner", pixel(&img, 0, 0, "G"), want);
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

/* Each peer's own spot profile: the factor on I0 at angle th from the axis.
 * LuxCore (slg/lights/spotlight.cpp): ((cos th - cos outer) / (cos inner -
 * cos outer))^4 between the cones, 1 inside, divided by cos th everywhere.
 * Mitsuba (emitters/spot.cpp falloff_curve): (outer - th) / (outer - inner)
 * between the cones, 1 inside. */
static double peer_profile(pb_peer_format f, double th, double inner, double outer) {
  const double c = cos(th);
  if (th >= outer) return 0;
  if (f == PB_PEER_LUXCORE) {
    double t = c > cos(inner) ? 1 : pow((c - cos(outer)) / (cos(inner) - cos(outer)), 4);
    return t / c;
  }
  return th <= inner ? 1 : (outer - th) / (outer - inner);
}

static void test_spot(pb_peer_format f) {
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
    if (!render(&s, i, f, name, 9, 9, &img)) {
      CHECK(0);
      continue;
    }
    const double th = angles[i] * M_PI / 180, c = cos(th);
    const double base = rho / M_PI * l->intensity * c * c * c;
    const double gltf = base * smoothstep(cos(l->outer_cone), cos(l->inner_cone), c);
    const double own = base * peer_profile(f, th, l->inner_cone, l->outer_cone);
    char what[64];
    snprintf(what, sizeof what, "spot, %g deg off axis (glTF profile)", angles[i]);
    report(f, what, centre(&img), gltf);
    snprintf(what, sizeof what, "spot, %g deg off axis (its own profile)", angles[i]);
    report(f, what, centre(&img), own);
    if (own > 0)
      CHECK_NEAR(centre(&img) / own, 1.0, 0.01);
    else
      CHECK(centre(&img) == 0.0f);
    /* Where the two profiles agree, the analytic glTF radiance itself. */
    if (gltf > 0 && fabs(own / base - gltf / base) < 1e-6) CHECK_NEAR(centre(&img) / gltf, 1.0, 0.01);
    pb_image_destroy(&img);
  }
  pb_scene_destroy(&s);
}

/* Top-right quadrant (x > 0, z < 0, seen from above with the image's top
 * towards -z) albedo 0.9, top-left 0.5, bottom half 0.1, lit straight down
 * by E = pi so that radiance = albedo: a mirrored camera would swap them. */
static void test_handedness(pb_peer_format f) {
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
  if (render(&s, 0, f, "hand", 32, 32, &img)) {
    const float tr = pixel(&img, 24, 8, "G"), tl = pixel(&img, 8, 8, "G"), bl = pixel(&img, 8, 24, "G"),
                br = pixel(&img, 24, 24, "G");
    printf("%-8s handedness: top-left %.3f top-right %.3f bottom %.3f %.3f (want 0.5 0.9 0.1 0.1)\n",
           pb_peer_format_names[f], tl, tr, bl, br);
    CHECK_NEAR(tr, 0.9, 0.01);
    CHECK_NEAR(tl, 0.5, 0.01);
    CHECK_NEAR(bl, 0.1, 0.01);
    CHECK_NEAR(br, 0.1, 0.01);
    /* The quadrants' edges fall on pixel edges (rows 15 | 16, columns 15 |
     * 16): a camera off by a pixel (or half of one) mixes them. */
    const float r15 = pixel(&img, 8, 15, "G"), r16 = pixel(&img, 8, 16, "G"), c15 = pixel(&img, 15, 8, "G"),
                c16 = pixel(&img, 16, 8, "G");
    printf("%-8s pixel edges: row 15 %.3f row 16 %.3f column 15 %.3f column 16 %.3f (want 0.5 0.1 0.5 0.9)\n",
           pb_peer_format_names[f], r15, r16, c15, c16);
    CHECK_NEAR(r15, 0.5, 0.01);
    CHECK_NEAR(r16, 0.1, 0.01);
    CHECK_NEAR(c15, 0.5, 0.01);
    CHECK_NEAR(c16, 0.9, 0.01);
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  pb_scene_destroy(&s);
}

/* The same quadrants from a base colour texture (8x8, linear texels, 4x4
 * blocks, so that bilinear filtering sees one value inside each block) on a
 * plane whose uvs run u along +x and v along +z (v = 0 at the image's top,
 * as glTF's v = 0 is the texture's top row), times a base colour factor
 * 0.5: the peers must read glTF uvs unflipped and get the factor. */
static void test_texture(pb_peer_format f) {
  pb_scene s;
  tps_init(&s);
  uint32_t m = tps_material(&s, "checker", 0.5f, 0.5f, 0.5f);
  tps_quad_y(&s, -1.2f, 1.2f, -1.2f, 1.2f, 0, m);
  s.textures = calloc(1, sizeof *s.textures);
  s.texture_count = 1;
  pb_texture *t = &s.textures[0];
  snprintf(t->name, sizeof t->name, "quadrants");
  t->width = t->height = 8;
  t->rgba8 = malloc(8 * 8 * 4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      uint8_t v = y >= 4 ? 51 : x >= 4 ? 255 : 153; /* 0.2 bottom, 1.0 top right, 0.6 top left */
      uint8_t *p = t->rgba8 + (y * 8 + x) * 4;
      p[0] = p[1] = p[2] = v;
      p[3] = 255;
    }
  s.materials[m].base_color_tex = 0;
  pb_light *l = tps_light(&s, PB_LIGHT_DIRECTIONAL, "sun");
  l->intensity = (float)M_PI;
  tps_camera_down(&s, "top", 0, 3, 0, 40);
  pb_scene_finalize(&s);
  pb_image img;
  if (render(&s, 0, f, "texture", 32, 32, &img)) {
    const float tr = pixel(&img, 24, 8, "G"), tl = pixel(&img, 8, 8, "G"), bl = pixel(&img, 8, 24, "G"),
                br = pixel(&img, 24, 24, "G");
    printf("%-8s texture: top-left %.3f top-right %.3f bottom %.3f %.3f (want 0.3 0.5 0.1 0.1)\n",
           pb_peer_format_names[f], tl, tr, bl, br);
    CHECK_NEAR(tr, 0.5, 0.005);
    CHECK_NEAR(tl, 0.3, 0.005);
    CHECK_NEAR(bl, 0.1, 0.005);
    CHECK_NEAR(br, 0.1, 0.005);
    pb_image_destroy(&img);
  } else {
    CHECK(0);
  }
  pb_scene_destroy(&s);
}

int main(int argc, char **argv) {
  const char *which = argc > 1 ? argv[1] : "both";
  const char *env[2] = {getenv("PB_LUXCORE_PYTHON"), getenv("PB_MITSUBA_PYTHON")};
  const char *dflt[2] = {"tools/luxcore/bin/python", "tools/mitsuba3/bin/python"};
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  for (int f = 0; f < 2; ++f) {
    if (strcmp(which, "both") != 0 && strcmp(which, pb_peer_format_names[f]) != 0) continue;
    python[f] = env[f] && env[f][0] ? env[f] : dflt[f];
    if (access(python[f], X_OK) != 0) {
      printf("FAIL %s: %s missing: run scripts/install-deps.sh\n", pb_peer_format_names[f], python[f]);
      CHECK(0);
      continue;
    }
    test_point((pb_peer_format)f);
    test_parallel((pb_peer_format)f);
    test_spot((pb_peer_format)f);
    test_handedness((pb_peer_format)f);
    test_texture((pb_peer_format)f);
  }
  char cmd[300];
  if (!getenv("PB_KEEP_TMP")) {
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  } else {
    printf("renders kept in %s\n", tmpdir);
  }
  return pbt_done();
}
