/* Furnace test: the camera inside a closed sphere whose inner surface is
 * Lambertian with albedo rho and emits radiance Le. Everywhere inside,
 * radiance is Le + rho (Le + rho (...)), so with at most B scattering events
 *     L = Le * sum_{k=0..B} rho^k,
 * whatever the sphere's tessellation. Checked per channel (rho differs per
 * channel) for B = 1, 3 and 40 (where Russian roulette is at work) and for
 * the default path length (B = 0 here: unbounded, L = Le / (1 - rho); the
 * old default of 8 events gave Le (1 - rho^9) / (1 - rho), 13 % dark at
 * rho 0.8), on the
 * mean over the image within 1 % and on every pixel within 10 %. It also
 * checks the emission convention: a single-sided emitter whose front faces
 * away from the camera shows nothing. */
#include "pbtest.h"
#include "test_ref_scene.h"

static const float RHO[3] = {0.8f, 0.5f, 0.2f};
static const float LE = 0.5f;

/* Icosphere of radius 1 (two subdivisions, 320 triangles), flat normals;
 * front faces inward when `inward`. */
static void icosphere(pb_scene *s, uint32_t mat, int inward) {
  const float t = (1.0f + sqrtf(5.0f)) / 2.0f;
  float v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  static const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int i = 0; i < 12; ++i) tsc_norm3(v[i]);
  /* Recursive midpoint subdivision, two levels, on the fly. */
  for (int i = 0; i < 20; ++i) {
    float tri[3][3];
    for (int k = 0; k < 3; ++k) memcpy(tri[k], v[f[i][k]], sizeof tri[k]);
    float l1[4][3][3];
    int n1 = 0;
    {
      float m[3][3];
      for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) m[k][c] = 0.5f * (tri[k][c] + tri[(k + 1) % 3][c]);
        tsc_norm3(m[k]);
      }
      const float *tt[4][3] = {{tri[0], m[0], m[2]}, {m[0], tri[1], m[1]},
                               {m[2], m[1], tri[2]}, {m[0], m[1], m[2]}};
      for (int q = 0; q < 4; ++q, ++n1)
        for (int k = 0; k < 3; ++k) memcpy(l1[n1][k], tt[q][k], sizeof l1[n1][k]);
    }
    for (int q = 0; q < n1; ++q) {
      float (*a)[3] = l1[q];
      float m[3][3];
      for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) m[k][c] = 0.5f * (a[k][c] + a[(k + 1) % 3][c]);
        tsc_norm3(m[k]);
      }
      const float *tt[4][3] = {{a[0], m[0], m[2]}, {m[0], a[1], m[1]},
                               {m[2], m[1], a[2]}, {m[0], m[1], m[2]}};
      for (int r = 0; r < 4; ++r) {
        if (inward) tsc_triangle(s, tt[r][0], tt[r][2], tt[r][1], mat);
        else tsc_triangle(s, tt[r][0], tt[r][1], tt[r][2], mat);
      }
    }
  }
}

static void build(pb_scene *s, int inward, int double_sided) {
  tsc_init(s);
  pb_material m = tsc_lambert(RHO[0], RHO[1], RHO[2]);
  m.emissive[0] = m.emissive[1] = m.emissive[2] = LE;
  m.double_sided = double_sided;
  uint32_t mi = tsc_material(s, m);
  icosphere(s, mi, inward);
  float pos[3] = {0.1f, -0.05f, 0.2f}, fwd[3] = {0.3f, 0.2f, -1}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, 70.0f);
  pb_scene_finalize(s);
}

static void furnace(uint32_t bounces, uint32_t spp, int inward, int double_sided) {
  pb_scene s;
  build(&s, inward, double_sided);
  CHECK_EQ_INT(s.triangle_count, 320);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = spp;
  d.max_bounces = bounces;
  d.seed = 11;
  pb_ref_result r;
  enum { W = 16, H = 16 };
  pb_result res = pb_ref_render(&s, 0, W, H, &d, &r);
  CHECK_EQ_INT(res, PB_OK);
  if (res != PB_OK) {
    pb_scene_destroy(&s);
    return;
  }
  CHECK_EQ_INT(r.stats.guarded_samples, 0);
  char bname[16];
  if (bounces) snprintf(bname, sizeof bname, "%u", bounces);
  else snprintf(bname, sizeof bname, "def");
  for (int c = 0; c < 3; ++c) {
    double want = 0, p = 1;
    for (uint32_t k = 0; k <= bounces; ++k, p *= RHO[c]) want += LE * p;
    if (bounces == 0) want = LE / (1.0 - RHO[c]); /* the default: no truncation */
    double mean = tsc_mean(r.beauty, W, H, 4, c);
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H; ++i)
      worst = fmax(worst, tsc_rel(r.beauty[4 * i + (size_t)c], want));
    printf("furnace B=%-2s channel %d rho %.1f: mean %.5f want %.5f rel %.2e, worst "
           "pixel rel %.3f\n", bname, c, (double)RHO[c], mean, want, tsc_rel(mean, want),
           worst);
    CHECK(tsc_rel(mean, want) <= 0.01);
    CHECK(worst <= 0.10);
    /* direct = Le + rho Le (emission seen, and scattered once) */
    double direct = tsc_mean(r.direct, W, H, 3, c);
    double want_direct = LE * (1 + RHO[c]);
    CHECK(tsc_rel(direct, want_direct) <= 0.01);
  }
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

/* Front faces outward, single-sided: the camera inside sees only back
 * faces, which emit nothing; they still reflect (flipped normal), but there
 * is no light at all. */
static void dark_inside(void) {
  pb_scene s;
  build(&s, 0, 0);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 4;
  pb_ref_result r;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_OK);
  if (r.beauty) {
    double m = tsc_mean(r.beauty, 8, 8, 4, 0) + tsc_mean(r.beauty, 8, 8, 4, 1);
    CHECK_NEAR(m, 0.0, 0.0);
  }
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

int main(void) {
  furnace(1, 64, 1, 0);
  furnace(3, 64, 1, 0);
  furnace(40, 1024, 0, 1); /* double-sided: emission from the back faces too */
  furnace(0, 1024, 1, 0);  /* the default: Russian roulette, no truncation */
  dark_inside();
  return pbt_done();
}
