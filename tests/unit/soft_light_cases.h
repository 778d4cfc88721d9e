/* The soft-light and world cases both renderers are tested on
 * (test_ref_soft_lights.c, test_gpu_soft_lights.c): scenes built in code,
 * closed forms and independent integrals written here from their
 * definitions (Howell's point-to-rectangle factor, the circular segment,
 * Blender's Euler angles, the equirectangular map), never from the
 * renderers' code. The including test sets slc_renderer and calls
 * slc_run_all(). See test_ref_soft_lights.c for the list and thresholds. */
#ifndef PB_TEST_SOFT_LIGHT_CASES_H
#define PB_TEST_SOFT_LIGHT_CASES_H

#include "pbtest.h"
#include "test_ref_scene.h"

#include "scene/world.h"

enum { W = 24, H = 24 };

/* ---- independent integrals ---------------------------------------------- */

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double cycles_spot(const pb_light *l, double c) {
  double c0 = cos(l->outer_cone);
  if (c <= c0) return 0;
  double band = (1 - c0) * l->spot_blend, t = c - c0;
  if (band > 0 && t < band) {
    double x = t / band;
    return c * x * x * (3 - 2 * x);
  }
  return c;
}

/* Irradiance at p (normal +z) from soft light l, by a midpoint rule over
 * the light's surface (n x n cells). */
static double irradiance(const pb_light *l, const double p[3], int n) {
  double c[3] = {l->position[0], l->position[1], l->position[2]};
  double u[3], v[3], nl[3], lu, lv;
  int ellipse;
  if (l->type == PB_LIGHT_AREA) {
    for (int k = 0; k < 3; ++k) u[k] = l->axis_u[k], v[k] = l->axis_v[k], nl[k] = l->direction[k];
    lu = l->size[0], lv = l->size[1];
    ellipse = l->shape == PB_AREA_ELLIPSE;
  } else { /* sphere light: the disc through c facing p */
    double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]}, dl = sqrt(dot3(d, d));
    for (int k = 0; k < 3; ++k) nl[k] = d[k] / dl;
    double a[3] = {fabs(nl[0]) < 0.9 ? 1 : 0, fabs(nl[0]) < 0.9 ? 0 : 1, 0};
    double t = dot3(a, nl);
    for (int k = 0; k < 3; ++k) u[k] = a[k] - t * nl[k];
    double ul = sqrt(dot3(u, u));
    for (int k = 0; k < 3; ++k) u[k] /= ul;
    v[0] = nl[1] * u[2] - nl[2] * u[1], v[1] = nl[2] * u[0] - nl[0] * u[2], v[2] = nl[0] * u[1] - nl[1] * u[0];
    lu = lv = 2 * l->radius;
    ellipse = 1;
  }
  double tan_a = 0, norm = 1;
  if (l->type == PB_LIGHT_AREA && l->spread < M_PI) {
    double a = 0.5 * (M_PI - l->spread);
    tan_a = tan(a);
    norm = 2.0 / (2.0 + (2.0 * a - M_PI) * tan_a);
  }
  double L = l->intensity * l->color[0];
  if (l->type != PB_LIGHT_AREA) L /= M_PI * l->radius * l->radius;
  double sum = 0, dA = lu * lv / ((double)n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double x = ((i + 0.5) / n - 0.5), y = ((j + 0.5) / n - 0.5);
      if (ellipse && x * x + y * y > 0.25) continue;
      double q[3], w[3];
      for (int k = 0; k < 3; ++k) q[k] = c[k] + u[k] * x * lu + v[k] * y * lv, w[k] = p[k] - q[k];
      double r2 = dot3(w, w), r = sqrt(r2);
      for (int k = 0; k < 3; ++k) w[k] /= r; /* from the light toward p */
      double cl = dot3(w, nl), cp = -w[2];
      if (cl <= 0 || cp <= 0) continue;
      double f = 1;
      if (tan_a > 0) f = fmax((1 - tan_a * sqrt(1 - cl * cl) / cl) * norm, 0);
      if (l->type == PB_LIGHT_SPOT) {
        double ax[3] = {l->direction[0], l->direction[1], l->direction[2]};
        f *= cycles_spot(l, dot3(ax, w));
      }
      sum += L * f * cl * cp / r2 * dA;
    }
  return sum;
}

/* Point-to-rectangle form factor times pi (irradiance per unit radiance)
 * from a rectangle [0, a] x [0, b] at height c above a point under its
 * corner, receiver parallel (Howell's catalogue, factor B-3). */
static double corner_ff(double a, double b, double c) {
  double A = a / c, B = b / c;
  double sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
  return 0.5 * (A / sa * atan(B / sa) + B / sb * atan(A / sb));
}
/* The corner factor made odd in each side, so that any rectangle
 * [x0, x1] x [y0, y1] around or beside the point is the inclusion-exclusion
 * of four corner rectangles. */
static double corner_signed(double x, double y, double c) {
  double sg = (x < 0 ? -1 : 1) * (y < 0 ? -1 : 1);
  return sg * corner_ff(fabs(x), fabs(y), c);
}
static double square_irradiance(double L, double half, double h, double px, double py) {
  double x0 = -half - px, x1 = half - px, y0 = -half - py, y1 = half - py;
  return L * (corner_signed(x1, y1, h) - corner_signed(x0, y1, h) - corner_signed(x1, y0, h) +
              corner_signed(x0, y0, h));
}

/* ---- scenes -------------------------------------------------------------- */

static void plane_scene(pb_scene *s, float rho, float cam_h, float yfov) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert(rho, rho, rho));
  tsc_floor(s, 20.0f, 0.0f, m);
  float pos[3] = {0, 0, cam_h}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, yfov);
}

static pb_light *area_light(pb_scene *s, pb_area_shape shape, float su, float sv, float h, float L) {
  pb_light *l = tsc_light(s, PB_LIGHT_AREA);
  l->shape = shape;
  l->size[0] = su, l->size[1] = sv;
  l->position[2] = h;
  l->direction[0] = 0, l->direction[1] = 0, l->direction[2] = -1;
  l->axis_u[0] = 1;
  l->axis_v[1] = -1; /* u x v = -z would be the other way round: either works */
  l->intensity = L;
  l->spread = (float)M_PI;
  return l;
}

/* The renderer under test: renders camera 0 of s (direct light is all
 * these scenes have, but for the furnace) into a malloc'd RGBA beauty, or
 * returns NULL after a failed CHECK. */
typedef float *(*slc_render_fn)(const pb_scene *s, uint32_t w, uint32_t h, uint32_t spp, uint64_t seed);
static slc_render_fn slc_renderer;

typedef struct slc_image {
  float *beauty;
} slc_image;

static int render_wh(const pb_scene *s, uint32_t w, uint32_t h, uint32_t spp, uint64_t seed, slc_image *r) {
  r->beauty = slc_renderer(s, w, h, spp, seed);
  return r->beauty != NULL;
}
static int render(const pb_scene *s, uint32_t spp, uint64_t seed, slc_image *r) {
  return render_wh(s, W, H, spp, seed, r);
}
static void image_destroy(slc_image *r) {
  free(r->beauty);
  r->beauty = NULL;
}

/* The point of the plane z = 0 at the centre of pixel (x, y). */
static void plane_point(const pb_camera *c, uint32_t x, uint32_t y, double p[3]) {
  double d[3];
  tsc_camera_ray(c, W, H, x + 0.5, y + 0.5, d);
  double t = -c->position[2] / d[2];
  for (int k = 0; k < 3; ++k) p[k] = c->position[k] + t * d[k];
}

/* Checks b x b blocks of pixels of a direct-light render against the mean
 * of rho/pi E(p) at their pixel centres (the view is narrow: E varies
 * little across a pixel; a block averages the estimator's noise); returns
 * the worst relative error. */
typedef double (*irr_fn)(const pb_light *l, const double p[3]);
static double check_plane_b(const char *what, const pb_scene *s, const slc_image *r, double rho, irr_fn f,
                            double tol, uint32_t b) {
  static const uint32_t blocks[][2] = {{9, 9}, {0, 1}, {17, 4}, {3, 17}, {18, 18}, {9, 0}};
  double worst = 0;
  for (size_t i = 0; i < sizeof blocks / sizeof *blocks; ++i) {
    double want = 0, got = 0, n = (double)b * b;
    for (uint32_t y = blocks[i][1]; y < blocks[i][1] + b; ++y)
      for (uint32_t x = blocks[i][0]; x < blocks[i][0] + b; ++x) {
        double p[3];
        plane_point(&s->cameras[0], x, y, p);
        want += rho / M_PI * f(&s->lights[0], p) / n;
        got += r->beauty[4 * ((size_t)y * W + x)] / n;
      }
    double e = tsc_rel(got, want);
    if (e > worst) worst = e;
    if (e > tol)
      printf("  block at (%u, %u): render %.5f, expected %.5f\n", blocks[i][0], blocks[i][1], got, want);
    CHECK(e <= tol);
  }
  printf("%-34s worst %ux%u block %.3f %% (tolerance %.2f %%)\n", what, b, b, 100 * worst, 100 * tol);
  return worst;
}
static double check_plane(const char *what, const pb_scene *s, const slc_image *r, double rho, irr_fn f,
                          double tol) {
  return check_plane_b(what, s, r, rho, f, tol, 4);
}

static double irr_numeric(const pb_light *l, const double p[3]) { return irradiance(l, p, 300); }

static double irr_square(const pb_light *l, const double p[3]) {
  return square_irradiance(l->intensity, 0.5 * l->size[0], l->position[2], p[0], p[1]);
}

static void test_area_lights(void) {
  pb_scene s;
  slc_image r;
  /* A 0.5 m square 1 m above, seen over 1 m of the plane. */
  plane_scene(&s, 0.8f, 3.0f, 2.0f * (float)(atan(0.5 / 3.0) * 180.0 / M_PI));
  area_light(&s, PB_AREA_RECTANGLE, 0.5f, 0.5f, 1.0f, 100.0f);
  pb_scene_finalize(&s);
  if (render(&s, 128, 1, &r)) {
    check_plane("area square vs form factor", &s, &r, 0.8, irr_square, 0.005);
    image_destroy(&r);
  }
  /* The same square with spread 60 degrees: integrated. */
  s.lights[0].spread = (float)(M_PI / 3);
  /* Spread: the profile varies across the light, so light samples vary
   * much more (Cycles' strategy, as here); more samples, wider tolerance. */
  if (render(&s, 2048, 2, &r)) {
    check_plane_b("area square, spread 60", &s, &r, 0.8, irr_numeric, 0.015, 6);
    image_destroy(&r);
  }
  /* A 2 x 0.6 m rectangle with spread 30 degrees: the clamped part. */
  s.lights[0].size[0] = 2.0f, s.lights[0].size[1] = 0.6f, s.lights[0].spread = (float)(M_PI / 6);
  if (render(&s, 2048, 3, &r)) {
    check_plane_b("area rectangle, spread 30", &s, &r, 0.8, irr_numeric, 0.015, 6);
    image_destroy(&r);
  }
  /* A disc of 0.6 m and an ellipse 1.0 x 0.4 m turned 30 degrees. */
  s.lights[0].shape = PB_AREA_ELLIPSE, s.lights[0].size[0] = s.lights[0].size[1] = 0.6f;
  s.lights[0].spread = (float)M_PI;
  if (render(&s, 2048, 4, &r)) {
    check_plane("area disc", &s, &r, 0.8, irr_numeric, 0.0075);
    image_destroy(&r);
  }
  pb_light *l = &s.lights[0];
  l->size[0] = 1.0f, l->size[1] = 0.4f;
  l->axis_u[0] = (float)cos(M_PI / 6), l->axis_u[1] = (float)sin(M_PI / 6);
  l->axis_v[0] = (float)sin(M_PI / 6), l->axis_v[1] = -(float)cos(M_PI / 6);
  if (render(&s, 2048, 5, &r)) {
    check_plane("area ellipse", &s, &r, 0.8, irr_numeric, 0.0075);
    image_destroy(&r);
  }
  pb_scene_destroy(&s);
}

static void test_sphere_lights(void) {
  pb_scene s;
  slc_image r;
  /* The camera below the light (which the camera would see otherwise). */
  plane_scene(&s, 0.8f, 0.5f, 2.0f * (float)(atan(0.6 / 0.5) * 180.0 / M_PI));
  pb_light *l = tsc_light(&s, PB_LIGHT_POINT);
  l->position[0] = 0.2f, l->position[2] = 0.8f;
  l->intensity = 10.0f;
  pb_scene_finalize(&s);
  double p[3];
  plane_point(&s.cameras[0], 12, 12, p);
  double v[3] = {l->position[0] - p[0], l->position[1] - p[1], l->position[2] - p[2]}, d2 = dot3(v, v);
  double point = 0.8 / M_PI * l->intensity * v[2] / sqrt(d2) / d2, prev = 1e30;
  for (int i = 0; i < 3; ++i) {
    s.lights[0].radius = (float)(0.3 / pow(10, i)); /* 0.3, 0.03, 0.003 m */
    pb_scene_finalize(&s);
    if (!render(&s, 256, 10 + (uint64_t)i, &r)) continue;
    char what[64];
    snprintf(what, sizeof what, "sphere light r = %g m", s.lights[0].radius);
    check_plane(what, &s, &r, 0.8, irr_numeric, 0.005);
    double got = r.beauty[4 * (12 * W + 12)], e = tsc_rel(got, point);
    printf("  centre pixel against the point light: %.4f %%\n", 100 * e);
    /* Converges: r = 0.3 is 8 % off, 0.03 below 0.2 %, 0.003 within noise. */
    CHECK(e < prev || e < 0.002);
    if (i == 2) CHECK(e < 0.002);
    prev = e;
    image_destroy(&r);
  }
  /* A soft spot with Cycles' falloff: 120 degrees, blend 0.3, radius 0.15
   * (the view inside the cone: at its fringe only part of the disc lights a
   * point, and light samples are mostly zero, in Cycles too). */
  s.lights[0].type = PB_LIGHT_SPOT;
  s.lights[0].spot_model = PB_SPOT_CYCLES;
  s.lights[0].outer_cone = (float)(M_PI / 3);
  s.lights[0].spot_blend = 0.3f;
  s.lights[0].radius = 0.15f;
  s.lights[0].position[0] = 0.0f;
  s.lights[0].direction[0] = 0.3f, s.lights[0].direction[2] = -1.0f;
  tsc_norm3(s.lights[0].direction);
  pb_scene_finalize(&s);
  if (render(&s, 2048, 20, &r)) {
    check_plane_b("soft spot (Cycles falloff)", &s, &r, 0.8, irr_numeric, 0.01, 6);
    image_destroy(&r);
  }
  pb_scene_destroy(&s);
}

/* Sun straight down, angle 4 degrees, behind a plate covering x < 0 at
 * height 1 m: the floor sees the part of the sun's disc (radius R =
 * tan(2 deg) at unit distance) with u > -x / h, u along x. */
static double segment(double s) { /* area fraction of the unit disc where u >= s */
  if (s <= -1) return 1;
  if (s >= 1) return 0;
  return (acos(s) - s * sqrt(1 - s * s)) / M_PI;
}

static void test_sun_penumbra(void) {
  pb_scene s;
  tsc_init(&s);
  uint32_t m = tsc_material(&s, tsc_lambert(0.8f, 0.8f, 0.8f)), black = tsc_material(&s, tsc_lambert(0, 0, 0));
  tsc_floor(&s, 20.0f, 0.0f, m);
  /* The plate: x in [-20, 0] at 1 m, black (no light bounces back). */
  float a[3] = {-20, -20, 1}, b[3] = {0, -20, 1}, c[3] = {0, 20, 1}, d[3] = {-20, 20, 1};
  tsc_quad(&s, a, d, c, b, black); /* facing -z */
  float pos[3] = {0, 0, 0.5f}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  /* 0.12 m across at the floor (the penumbra is 0.056 m wide) in a W x 4 W
   * image: yfov spans 0.48 m. */
  tsc_camera(&s, pos, fwd, up, 2.0f * (float)(atan(0.24 / 0.5) * 180.0 / M_PI));
  pb_light *l = tsc_light(&s, PB_LIGHT_DIRECTIONAL);
  l->intensity = 3.0f;
  l->angle = (float)(4.0 * M_PI / 180.0);
  pb_scene_finalize(&s);
  /* 24 columns across the edge, 96 rows averaged into each, 512 spp: the
   * profile's noise (a visible-or-not sun sample) is then about 0.25 % of
   * full. */
  enum { PH = 96 };
  slc_image r;
  s.cameras[0].aspect = (float)W / PH;
  if (!render_wh(&s, W, PH, 512, 30, &r)) {
    pb_scene_destroy(&s);
    return;
  }
  double R = tan(0.5 * l->angle), E = l->intensity * 2 * (sqrt(1 + R * R) - 1) / (R * R);
  double full = 0.8 / M_PI * E, worst = 0, x5 = NAN, x95 = NAN;
  double prof[W];
  for (uint32_t x = 0; x < W; ++x) {
    double sum = 0;
    for (uint32_t y = 0; y < PH; ++y) sum += r.beauty[4 * ((size_t)y * W + x)];
    prof[x] = sum / PH;
    /* The pixel's centre on the floor, and the closed form averaged over
     * its width (the render's box filter). */
    double p[3] = {((x + 0.5) / W - 0.5) * 0.12, 0, 0};
    double pw = 0.12 / W, want = 0;
    for (int k = 0; k < 64; ++k) want += full * segment(-(p[0] + ((k + 0.5) / 64 - 0.5) * pw) / (1.0 * R)) / 64;
    double e = fabs(prof[x] - want) / full;
    if (e > worst) worst = e;
    CHECK(e <= 0.01);
  }
  /* Width between 5 % and 95 % of full, linearly interpolated. */
  for (uint32_t x = 1; x < W; ++x) {
    double xa = (x - 0.5) * 0.12 / W - 0.06, xb = xa + 0.12 / W;
    double fa = prof[x - 1] / full, fb = prof[x] / full;
    if (isnan(x5) && fa < 0.05 && fb >= 0.05) x5 = xa + (0.05 - fa) / (fb - fa) * (xb - xa);
    if (isnan(x95) && fa < 0.95 && fb >= 0.95) x95 = xa + (0.95 - fa) / (fb - fa) * (xb - xa);
  }
  /* Closed form: segment(s) = 0.05 and 0.95 at s = -+s0, x = -s h R. */
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i) {
    double mid = 0.5 * (lo + hi);
    if (segment(mid) > 0.05) lo = mid;
    else hi = mid;
  }
  double width = 2 * lo * 1.0 * R;
  printf("sun penumbra: worst %.3f %% of full; width (5-95 %%) %.4f m, closed form %.4f m\n", 100 * worst,
         x95 - x5, width);
  CHECK(fabs((x95 - x5) - width) < 0.12 / W);
  image_destroy(&r);
  pb_scene_destroy(&s);
}

static void test_uniform_world(void) {
  pb_scene s;
  plane_scene(&s, 0.7f, 3.0f, 10.0f);
  s.world.present = 1;
  s.world.color[0] = s.world.color[1] = s.world.color[2] = 1.5f;
  pb_world_update_integral(&s.world);
  pb_scene_finalize(&s);
  slc_image r;
  if (render(&s, 16, 40, &r)) {
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H; ++i) worst = fmax(worst, fabs(r.beauty[4 * i] - 0.7 * 1.5));
    printf("uniform world over a plane: worst |L - rho Lw| %.2e\n", worst);
    CHECK(worst < 1e-4);
    image_destroy(&r);
  }
  pb_scene_destroy(&s);

}

/* ---- environment maps ---------------------------------------------------- */

enum { MW = 256, MH = 128 };

/* Blender's XYZ Euler (R = Rz Ry Rx) and glTF -> Blender axes, written here
 * from their definitions, independently of world.c. */
static void test_dir_to_map(const double e[3], const double g[3], double m[3]) {
  double b[3] = {g[0], -g[2], g[1]};
  double cx = cos(e[0]), sx = sin(e[0]), cy = cos(e[1]), sy = sin(e[1]), cz = cos(e[2]), sz = sin(e[2]);
  double x1[3] = {b[0], cx * b[1] - sx * b[2], sx * b[1] + cx * b[2]};
  double y1[3] = {cy * x1[0] + sy * x1[2], x1[1], -sy * x1[0] + cy * x1[2]};
  m[0] = cz * y1[0] - sz * y1[1], m[1] = sz * y1[0] + cz * y1[1], m[2] = y1[2];
}

static double map_radiance(const float *map, double scale, const double e[3], const double g[3], int ch) {
  double m[3];
  test_dir_to_map(e, g, m);
  double u = 0.5 - atan2(m[1], m[0]) / (2 * M_PI), v = acos(fmax(-1, fmin(1, m[2]))) / M_PI;
  u -= floor(u);
  double fx = u * MW - 0.5, fy = v * MH - 0.5;
  int x0 = (int)floor(fx), y0 = (int)floor(fy);
  double ax = fx - x0, ay = fy - y0, s = 0;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      int x = ((x0 + dx) % MW + MW) % MW, y = y0 + dy < 0 ? 0 : (y0 + dy >= MH ? MH - 1 : y0 + dy);
      s += (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay) * map[3 * (y * MW + x) + ch];
    }
  return scale * s;
}

static void env_world(pb_scene *s, float *map, const double rot[3], float scale) {
  s->world.present = 1;
  s->world.env = map;
  s->world.env_width = MW;
  s->world.env_height = MH;
  s->world.env_scale = scale;
  pb_world_set_rotation(&s->world, rot);
  pb_world_update_integral(&s->world);
}

static void test_environment(void) {
  const double rot[3] = {0.3, -0.2, 1.1};
  float *map = calloc((size_t)MW * MH * 3, sizeof *map);
  /* One bright texel, the first (row by row) whose direction is at least
   * 45 degrees above the test's plane (z up) after the rotation. */
  int tx = -1, ty = -1;
  for (int y = 0; y < MH && tx < 0; ++y)
    for (int x = 0; x < MW && tx < 0; ++x) {
      double th = M_PI * (y + 0.5) / MH, ph = M_PI * (1 - 2 * (x + 0.5) / MW);
      double md[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)}, ez[3] = {0, 0, 1}, mz[3];
      test_dir_to_map(rot, ez, mz);
      if (dot3(mz, md) > 0.7071 && x > 8) tx = x, ty = y;
    }
  CHECK(tx >= 0);
  for (int c = 0; c < 3; ++c) map[3 * (ty * MW + tx) + c] = 5000.0f * (c == 1 ? 0.5f : 1.0f);
  pb_scene s;
  plane_scene(&s, 0.8f, 3.0f, 10.0f);
  env_world(&s, map, rot, 2.0f);
  pb_scene_finalize(&s);
  /* Its direction, from the map's own (u, v) of the texel centre, and its
   * integrated radiance by a fine midpoint rule in (u, v) with sin theta. */
  double E[3] = {0, 0, 0}, dir[3] = {0, 0, 0};
  int n = 16;
  for (int y = (ty - 1) * n; y < (ty + 2) * n; ++y)
    for (int x = (tx - 1) * n; x < (tx + 2) * n; ++x) {
      double u = (x + 0.5) / (MW * n), v = (y + 0.5) / (MH * n);
      double th = M_PI * v, ph = M_PI * (1 - 2 * u);
      double mdir[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
      /* Back to the scene: find g with test_dir_to_map(g) = mdir by the
       * inverse rotation (transpose), computed from the forward map on the
       * three axes. */
      double g[3] = {0, 0, 0};
      for (int k = 0; k < 3; ++k) {
        double ek[3] = {k == 0, k == 1, k == 2}, mk[3];
        test_dir_to_map(rot, ek, mk);
        g[k] = dot3(mk, mdir);
      }
      double dw = (2 * M_PI / (MW * n)) * (M_PI / (MH * n)) * sin(th);
      for (int c = 0; c < 3; ++c) E[c] += map_radiance(map, 2.0, rot, g, c) * dw;
      for (int k = 0; k < 3; ++k) dir[k] += map_radiance(map, 2.0, rot, g, 0) * dw * g[k];
    }
  double dl = sqrt(dot3(dir, dir));
  for (int k = 0; k < 3; ++k) dir[k] /= dl;
  /* glTF +Y up, but the test plane faces +z: the direction's z is the cosine. */
  double want = 0.8 / M_PI * E[0] * fmax(dir[2], 0);
  printf("environment texel: direction (%.3f %.3f %.3f), integrated %.4f W/m^2, cos %.3f\n", dir[0], dir[1], dir[2],
         E[0], dir[2]);
  CHECK(dir[2] > 0.7); /* the texel found above */
  slc_image r;
  if (render(&s, 512, 50, &r)) {
    double got = tsc_mean(r.beauty, W, H, 4, 0), got_g = tsc_mean(r.beauty, W, H, 4, 1);
    printf("environment texel lights the plane: render %.5f, directional %.5f (%.3f %%)\n", got, want,
           100 * tsc_rel(got, want));
    CHECK(tsc_rel(got, want) < 0.005);
    CHECK(tsc_rel(got_g / got, 0.5) < 1e-3); /* colour survives */
    image_destroy(&r);
  }
  /* The world's sampling table agrees with its pdf, and the pdf integrates
   * to 1 over the sphere. */
  pb_world_dist dist;
  CHECK_EQ_INT(pb_world_dist_build(&s.world, &dist), PB_OK);
  double integral = 0;
  int bad = 0;
  for (int i = 0; i < 4096; ++i) {
    float u1 = (float)((i * 0.6180339887) - floor(i * 0.6180339887)), u2 = (float)((i + 0.5) / 4096.0);
    float d3[3], pdf;
    if (!pb_world_sample(&s.world, &dist, u1, u2, d3, &pdf)) continue;
    float back = pb_world_pdf(&s.world, &dist, d3);
    if (fabs(back / pdf - 1) > 1e-3) bad++;
  }
  printf("world sampling (one texel): %d of 4096 samples disagree with the pdf\n", bad);
  CHECK_EQ_INT(bad, 0);
  pb_world_dist_destroy(&dist);
  s.world.env = NULL; /* the map is freed below */
  pb_scene_destroy(&s);

  /* Camera rays that leave the scene: a smooth map (every texel its own
   * colour), a camera looking up at the sky. */
  for (int y = 0; y < MH; ++y)
    for (int x = 0; x < MW; ++x)
      for (int c = 0; c < 3; ++c)
        map[3 * (y * MW + x) + c] = (float)(1.0 + 0.5 * sin(2 * M_PI * (x + 0.5) / MW + c) * sin(M_PI * (y + 0.5) / MH));
  tsc_init(&s);
  uint32_t m = tsc_material(&s, tsc_lambert(0.5f, 0.5f, 0.5f));
  float a[3] = {-.1f, -.1f, -5}, b[3] = {.1f, -.1f, -5}, c[3] = {.1f, .1f, -5}, d[3] = {-.1f, .1f, -5};
  tsc_quad(&s, a, b, c, d, m); /* a small card behind the camera: coverage 0 in view */
  float pos[3] = {0, 0, 0}, fwd[3] = {0.3f, 1.0f, 0.2f}, up[3] = {0, 0, 1};
  tsc_camera(&s, pos, fwd, up, 60.0f);
  env_world(&s, map, rot, 1.5f);
  s.film_opaque = 1;
  pb_scene_finalize(&s);
  /* The pdf of a smooth map integrates to 1 over the sphere. */
  CHECK_EQ_INT(pb_world_dist_build(&s.world, &dist), PB_OK);
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 800; ++x) {
      double th = M_PI * (y + 0.5) / 400, ph = 2 * M_PI * (x + 0.5) / 800;
      float d3[3] = {(float)(sin(th) * cos(ph)), (float)(sin(th) * sin(ph)), (float)cos(th)};
      integral += pb_world_pdf(&s.world, &dist, d3) * sin(th) * (M_PI / 400) * (2 * M_PI / 800);
    }
  printf("world sampling (smooth map): pdf integral over the sphere %.5f\n", integral);
  CHECK(fabs(integral - 1) < 0.002);
  pb_world_dist_destroy(&dist);
  if (render(&s, 1, 51, &r)) {
    CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 3), 1.0, 0); /* opaque film: alpha 1 */
    CHECK(tsc_mean(r.beauty, W, H, 4, 0) > 0.5);
    image_destroy(&r);
  }
  /* More samples: the box-filtered pixel converges to the mean of the map
   * over the pixel; with 256 samples at the centre pixel within 0.3 %. */
  if (render(&s, 256, 54, &r)) {
    double bg = 0;
    int k = 32;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        double dd[3];
        tsc_camera_ray(&s.cameras[0], W, H, 12 + (i + 0.5) / k, 12 + (j + 0.5) / k, dd);
        bg += map_radiance(map, 1.5, rot, dd, 0) / (k * k);
      }
    double got = r.beauty[4 * (12 * W + 12)];
    printf("background pixel (12, 12): render %.5f, map %.5f\n", got, bg);
    CHECK(tsc_rel(got, bg) < 0.003);
    image_destroy(&r);
  }
  /* Transparent film: no colour, alpha 0; hidden from the camera: black,
   * alpha 1. */
  s.film_opaque = 0;
  if (render(&s, 1, 52, &r)) {
    CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 0), 0, 0);
    CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 3), 0, 0);
    image_destroy(&r);
  }
  s.film_opaque = 1;
  s.world.hidden_from_camera = 1;
  if (render(&s, 1, 53, &r)) {
    CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 0), 0, 0);
    CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 3), 1, 0);
    image_destroy(&r);
  }
  s.world.env = NULL;
  pb_scene_destroy(&s);
  free(map);
}


/* Cycles 3.4 shows lights only in reflections: camera rays do not see an
 * area light, a sphere light or a sun in front of them, a mirror does, at
 * their radiance (and lights do not stop rays: the floor behind is hit). */
static void test_lights_seen(void) {
  for (int mirror = 0; mirror < 2; ++mirror) {
    pb_scene s;
    tsc_init(&s);
    uint32_t m = tsc_material(&s, mirror ? tsc_mirror() : tsc_lambert(0, 0, 0));
    tsc_floor(&s, 20.0f, 0.0f, m);
    /* Camera at 2 m looking down; the lights at 1 m facing it (direct) or
     * at 3 m facing down, seen in the mirror floor. */
    float pos[3] = {0, 0, 2.0f}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
    tsc_camera(&s, pos, fwd, up, 10.0f);
    pb_light *l = area_light(&s, PB_AREA_RECTANGLE, 4.0f, 4.0f, mirror ? 3.0f : 1.0f, 7.0f);
    if (!mirror) l->direction[2] = 1.0f, l->axis_v[1] = 1.0f; /* facing up, to the camera */
    pb_scene_finalize(&s);
    slc_image r;
    const char *what = mirror ? "in a mirror" : "by the camera";
    if (render(&s, 4, 60, &r)) {
      double got = tsc_mean(r.beauty, W, H, 4, 0);
      printf("area light seen %s: %.5f (expected %g)\n", what, got, mirror ? 7.0 : 0.0);
      CHECK(fabs(got - (mirror ? 7.0 : 0.0)) < 1e-4);
      CHECK_NEAR(tsc_mean(r.beauty, W, H, 4, 3), 1.0, 0); /* the floor is still hit */
      image_destroy(&r);
    }
    s.lights[0].type = PB_LIGHT_POINT;
    s.lights[0].radius = 2.0f;
    s.lights[0].intensity = 2.0f;
    pb_scene_finalize(&s);
    if (render(&s, 4, 61, &r)) {
      double got = r.beauty[4 * (12 * W + 12)], want = mirror ? 2.0 / (M_PI * 4.0) : 0.0;
      printf("sphere light seen %s: %.5f (expected %.5f)\n", what, got, want);
      CHECK(fabs(got - want) < 1e-4);
      image_destroy(&r);
    }
    s.lights[0].type = PB_LIGHT_DIRECTIONAL;
    s.lights[0].direction[2] = mirror ? -1.0f : 1.0f; /* toward the camera, or down onto the mirror */
    s.lights[0].angle = (float)(M_PI / 3);
    s.lights[0].intensity = 1.0f;
    pb_scene_finalize(&s);
    if (render(&s, 4, 62, &r)) {
      double R = tan(M_PI / 6), got = r.beauty[4 * (12 * W + 12)];
      double want = mirror ? 1.0 / (M_PI * R * R) : 0.0; /* at the disc's centre: cos = 1 */
      printf("sun seen %s: %.5f (expected about %.5f)\n", what, got, want);
      CHECK(fabs(got - want) < (mirror ? 0.01 * want : 1e-6));
      image_destroy(&r);
    }
    pb_scene_destroy(&s);
  }
}

static void slc_run_all(void) {
  test_area_lights();
  test_sphere_lights();
  test_sun_penumbra();
  test_uniform_world();
  test_environment();
  test_lights_seen();
}

#endif
