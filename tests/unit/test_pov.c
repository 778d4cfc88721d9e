/* export-pov without POV-Ray: the SDL carries the unit mappings of pov.h,
 * the mirrored coordinates, the camera, photons only when needed, reports of
 * approximations, and exact error codes. (test_pov_render runs POV-Ray.) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/fs.h"
#include "pbtest.h"
#include "pov/pov.h"
#include "test_pov_scene.h"

static char tmpdir[] = "/tmp/pb_test_pov.XXXXXX";

static char *slurp(const char *path) {
  uint8_t *d = NULL;
  size_t n = 0;
  if (pb_read_file(path, 64u << 20, &d, &n) != PB_OK) return NULL;
  return (char *)d;
}

static int has(const char *text, const char *needle) {
  int ok = text && strstr(text, needle) != NULL;
  if (!ok) fprintf(stderr, "  SDL lacks: %s\n", needle);
  return ok;
}

static void build_basic(pb_scene *s) {
  tps_init(s);
  uint32_t m = tps_material(s, "white", 0.8f, 0.8f, 0.8f);
  tps_quad_y(s, -5, 5, -5, 5, 0, m);
  pb_light *p = tps_light(s, PB_LIGHT_POINT, "point");
  p->position[0] = 1;
  p->position[1] = 2;
  p->position[2] = 3;
  p->intensity = 10;
  pb_light *sp = tps_light(s, PB_LIGHT_SPOT, "spot");
  sp->position[1] = 1;
  sp->intensity = 5;
  sp->inner_cone = 20.0f * (float)M_PI / 180;
  sp->outer_cone = 30.0f * (float)M_PI / 180;
  pb_light *d = tps_light(s, PB_LIGHT_DIRECTIONAL, "sun");
  d->direction[0] = 0.5f;
  d->direction[1] = -(float)sqrt(0.75);
  d->intensity = 4;
  tps_camera_down(s, "top", 0, 3, 0, 30);
  pb_scene_finalize(s);
}

static void test_units_and_camera(void) {
  CHECK_NEAR(pb_pov_point_color_scale(0.001), 1.0 / (2 * M_PI * 1e-6), 1e-3);
  CHECK_NEAR(pb_pov_parallel_color_scale(), 1.0 / M_PI, 1e-15);

  pb_scene s;
  build_basic(&s);
  CHECK_NEAR(pb_pov_default_fade_distance(&s), 1e-3 * sqrt(200.0), 1e-7);
  char path[256];
  snprintf(path, sizeof path, "%s/basic.pov", tmpdir);
  pb_pov_desc d = {.width = 64, .height = 32, .quality = PB_POV_DRAFT, .fade_distance = 0.001f};
  pb_pov_report rep;
  CHECK_EQ_INT(pb_pov_export(&s, &d, path, &rep), PB_OK);
  CHECK_EQ_INT(rep.width, 64);
  CHECK_EQ_INT(rep.height, 32);
  CHECK_EQ_INT(rep.photons, 0); /* diffuse only: pay only for what is used */
  CHECK_EQ_INT(rep.note_count, 0);
  pb_pov_report_destroy(&rep);
  char *t = slurp(path);
  CHECK(t != NULL);
  CHECK(has(t, "#version 3.7;"));
  CHECK(has(t, "assumed_gamma 1.0"));
  CHECK(has(t, "+W64 +H32"));
  CHECK(t && !strstr(t, "photons {"));
  CHECK(has(t, "radiosity {"));
  /* Point light: I / (2 pi f^2) = 10 / (2 pi 1e-6) ~ 1.59155e6 (with f as
   * the float written); z mirrored. */
  char want[512];
  const float f = 0.001f;
  const double col = 10 * pb_pov_point_color_scale(f);
  CHECK_NEAR(col, 1591549.43, 1.0);
  snprintf(want, sizeof want, "<1,2,-3>\n  color rgb <%.9g,%.9g,%.9g>\n  fade_distance %.9g fade_power 2", col, col, col, f);
  CHECK(has(t, want));
  /* Spot: radius = inner, falloff = outer (degrees), tightness 0, pointing down. */
  snprintf(want, sizeof want, "spotlight radius %.9g falloff %.9g tightness 0\n  point_at <0,0,-0>",
           s.lights[1].inner_cone * 180.0 / M_PI, s.lights[1].outer_cone * 180.0 / M_PI);
  CHECK(has(t, want));
  CHECK(has(t, "spotlight radius 20.00000"));
  /* Sun: E / pi = 1.2732, parallel, placed against its direction (mirrored z). */
  CHECK(has(t, "color rgb <1.27323954,1.27323954,1.27323954>\n  parallel"));
  /* Diffuse: pigment = albedo, diffuse 1 brilliance 1, ambient 0 emission 0. */
  CHECK(has(t, "pigment { rgb <0.800000012,0.800000012,0.800000012> }"));
  CHECK(has(t, "finish { ambient 0 emission rgb <0,0,0> diffuse 1 brilliance 1"));
  /* Camera: looking down, mirrored: direction along -y with length
   * 0.5 / tan(15 deg) = 1.8660254; right |2| (aspect 64/32) along +x; up
   * along glTF -z = POV +z. */
  CHECK(has(t, "right <2,0,-0>"));
  CHECK(has(t, "up <0,0,1>"));
  snprintf(want, sizeof want, "direction <0,%.17g,-0>", -0.5 / tan(0.5 * s.cameras[0].yfov));
  CHECK(has(t, want));
  CHECK(has(t, "direction <0,-1.86602"));
  CHECK(has(t, "vertex_vectors { 4,\n    <-5,0,5>"));
  free(t);

  /* Quality presets: direct has neither radiosity nor photons. */
  d.quality = PB_POV_DIRECT;
  CHECK_EQ_INT(pb_pov_export(&s, &d, path, NULL), PB_OK);
  t = slurp(path);
  CHECK(t && !strstr(t, "radiosity {"));
  free(t);
  pb_scene_destroy(&s);
}

static void test_specular_and_reports(void) {
  pb_scene s;
  tps_init(&s);
  uint32_t floor = tps_material(&s, "floor", 0.5f, 0.5f, 0.5f);
  uint32_t mirror = tps_material(&s, "mirror", 0.9f, 0.8f, 0.7f);
  s.materials[mirror].metallic = 1;
  s.materials[mirror].roughness = 0;
  uint32_t glass = tps_material(&s, "glass", 1, 1, 1);
  s.materials[glass].transmission = 1;
  s.materials[glass].roughness = 0;
  s.materials[glass].ior = 1.45f;
  uint32_t lamp = tps_material(&s, "lamp", 1, 1, 1);
  s.materials[lamp].emissive[0] = s.materials[lamp].emissive[1] = s.materials[lamp].emissive[2] = 5;
  uint32_t brass = tps_material(&s, "brass", 0.9f, 0.7f, 0.3f);
  s.materials[brass].metallic = 1;
  s.materials[brass].roughness = 0.4f;
  s.materials[brass].alpha_mode = PB_ALPHA_MASK;
  tps_quad_y(&s, -5, 5, -5, 5, 0, floor);
  tps_quad_y(&s, -1, 0, -1, 0, 0.5f, mirror);
  tps_quad_y(&s, 0, 1, 0, 1, 0.5f, glass); /* open: reported */
  tps_quad_y(&s, 2, 3, 2, 3, 2, lamp);
  tps_quad_y(&s, -3, -2, 2, 3, 0.1f, brass);
  pb_light *p = tps_light(&s, PB_LIGHT_POINT, "p");
  p->position[1] = 3;
  p->intensity = 1;
  p->range = 10;
  tps_camera_down(&s, "top", 0, 5, 0, 40);
  pb_scene_finalize(&s);
  char path[256];
  snprintf(path, sizeof path, "%s/spec.pov", tmpdir);
  pb_pov_desc d = {.width = 16, .height = 16, .quality = PB_POV_HIGH};
  pb_pov_report rep;
  CHECK_EQ_INT(pb_pov_export(&s, &d, path, &rep), PB_OK);
  CHECK_EQ_INT(rep.photons, 1);
  CHECK_EQ_INT(rep.emitter_count, 1);
  for (uint32_t i = 0; i < rep.note_count; ++i) printf("note: %s\n", rep.notes[i]);
  /* emitter, glossy metal, alpha mask, open glass, light range. */
  CHECK_EQ_INT(rep.unsupported_count, 5);
  int saw_emitter = 0, saw_range = 0, saw_glossy = 0, saw_alpha = 0, saw_open = 0;
  for (uint32_t i = 0; i < rep.note_count; ++i) {
    saw_emitter |= strstr(rep.notes[i], "'lamp': emissive") != NULL;
    saw_range |= strstr(rep.notes[i], "range 10") != NULL;
    saw_glossy |= strstr(rep.notes[i], "'brass': glossy metal") != NULL;
    saw_alpha |= strstr(rep.notes[i], "'brass': alpha mask") != NULL;
    saw_open |= strstr(rep.notes[i], "'glass': glass surface is not closed") != NULL;
  }
  CHECK(saw_emitter && saw_range && saw_glossy && saw_alpha && saw_open);
  pb_pov_report_destroy(&rep);
  char *t = slurp(path);
  CHECK(has(t, "photons {\n    count 2000000"));
  CHECK(has(t, "reflection { 1 metallic }"));
  CHECK(has(t, "interior { ior 1.45"));
  CHECK(has(t, "reflection { 0, 1 fresnel on } conserve_energy"));
  CHECK(has(t, "photons { target reflection on refraction on collect off }"));
  CHECK(has(t, "photons { target reflection on refraction off collect off }"));
  CHECK(has(t, "emission rgb <5,5,5>"));
  CHECK(has(t, "// Export notes:"));
  free(t);
  pb_scene_destroy(&s);
}

static void test_errors(void) {
  pb_scene s;
  build_basic(&s);
  char path[256];
  snprintf(path, sizeof path, "%s/err.pov", tmpdir);
  pb_pov_desc d = {.camera = 3};
  CHECK_EQ_INT(pb_pov_export(&s, &d, path, NULL), PB_ERR_USAGE);
  pb_error_clear();
  CHECK(access(path, F_OK) != 0);
  pb_pov_desc bad_fade = {.fade_distance = -1};
  CHECK_EQ_INT(pb_pov_export(&s, &bad_fade, path, NULL), PB_ERR_USAGE);
  pb_error_clear();
  CHECK_EQ_INT(pb_pov_export(&s, NULL, "/nonexistent-dir/x.pov", NULL), PB_ERR_IO);
  pb_error_clear();
  s.triangle_count = 0;
  CHECK_EQ_INT(pb_pov_export(&s, NULL, path, NULL), PB_ERR_SCENE_EMPTY);
  pb_error_clear();
  pb_scene_destroy(&s);
}

int main(void) {
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_units_and_camera();
  test_specular_and_reports();
  test_errors();
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  if (!getenv("PB_KEEP") && system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
  return pbt_done();
}
