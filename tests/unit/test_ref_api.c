/* pb_ref_render's contract: exact error codes for bad input (and nothing to
 * free after a failure), no NaN or Inf in any output even from a broken
 * light or broken normals (the bad samples are counted instead), the time
 * limit, bounce limit 0, AUTO's choice, progress reports and even spp under
 * --estimate-noise. */
#include "pbtest.h"
#include "test_ref_scene.h"

static void lit_plane(pb_scene *s) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert(0.5f, 0.5f, 0.5f));
  tsc_floor(s, 5.0f, 0.0f, m);
  pb_light *l = tsc_light(s, PB_LIGHT_POINT);
  l->position[2] = 1.0f;
  l->intensity = 3.0f;
  float pos[3] = {0, 0, 3}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, 50.0f);
  pb_scene_finalize(s);
}

static int all_zero(const pb_ref_result *r) {
  return !r->beauty && !r->direct && !r->indirect && !r->albedo && !r->normal && !r->depth &&
         !r->half_a && !r->half_b && r->width == 0;
}

static int all_finite(const pb_ref_result *r) {
  size_t n = (size_t)r->width * r->height;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c)
      if (!isfinite(r->beauty[4 * i + (size_t)c])) return 0;
    for (int c = 0; c < 3; ++c) {
      size_t k = 3 * i + (size_t)c;
      if (!isfinite(r->direct[k]) || !isfinite(r->indirect[k]) || !isfinite(r->albedo[k]) ||
          !isfinite(r->normal[k]))
        return 0;
    }
    if (!isfinite(r->depth[i])) return 0;
  }
  return 1;
}

static void test_errors(void) {
  pb_scene s;
  lit_plane(&s);
  pb_ref_result r;
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 1;
  CHECK_EQ_INT(pb_ref_render(&s, 1, 8, 8, &d, &r), PB_ERR_USAGE);
  CHECK(all_zero(&r));
  CHECK(strstr(pb_error_message(), "camera 1") != NULL);
  pb_error_clear();
  CHECK_EQ_INT(pb_ref_render(&s, -1, 8, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  CHECK_EQ_INT(pb_ref_render(&s, 0, 0, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  d.photon_alpha = 1.5f;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  d.photon_alpha = 0;
  d.time_limit_s = NAN;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  d.time_limit_s = 0;
  d.mode = (pb_ref_mode)7;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  d.mode = PB_REF_MODE_AUTO;
  s.cameras[0].yfov = 0;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_SCENE_INVALID);
  pb_error_clear();
  s.cameras[0].yfov = 1;
  s.triangles[1][2] = s.vertex_count;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_SCENE_INVALID);
  CHECK(all_zero(&r));
  pb_error_clear();
  s.triangles[1][2] = 0;
  s.triangle_material[0] = 9;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_SCENE_INVALID);
  pb_error_clear();
  s.triangle_material[0] = 0;
  s.triangle_count = 0;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_ERR_SCENE_EMPTY);
  pb_error_clear();
  s.triangle_count = 2;
  CHECK_EQ_INT(pb_ref_render(NULL, 0, 8, 8, &d, &r), PB_ERR_USAGE);
  pb_error_clear();
  /* NULL desc: every default. */
  CHECK_EQ_INT(pb_ref_render(&s, 0, 4, 4, NULL, &r), PB_OK);
  CHECK_EQ_INT(r.stats.spp, 64);
  CHECK(r.stats.threads >= 1);
  CHECK_EQ_INT(r.stats.mode, PB_REF_MODE_PT); /* diffuse scene: AUTO is PT */
  pb_ref_result_destroy(&r);
  pb_ref_result_destroy(&r); /* idempotent */
  pb_scene_destroy(&s);
}

/* Infinite light intensity and NaN vertex normals: the output stays finite
 * and the bad samples are counted. */
static void test_guard(void) {
  pb_scene s;
  lit_plane(&s);
  s.lights[0].intensity = INFINITY;
  for (uint32_t v = 0; v < s.vertex_count; ++v) s.normals[v][0] = NAN;
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = 4;
  d.estimate_noise = 1;
  pb_ref_result r;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_OK);
  if (r.beauty) {
    CHECK(all_finite(&r));
    CHECK_EQ_INT(r.stats.guarded_samples, 8 * 8 * 4);
    CHECK(isfinite(r.stats.noise_rmse));
  }
  pb_ref_result_destroy(&r);
  /* Finite light, NaN normals only: the geometric normal takes over. */
  s.lights[0].intensity = 3.0f;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_OK);
  if (r.beauty) {
    CHECK(all_finite(&r));
    CHECK_EQ_INT(r.stats.guarded_samples, 0);
    CHECK(r.beauty[4 * 36] > 0.1f);
  }
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

typedef struct progress_log {
  uint64_t calls, last_done, last_total;
} progress_log;

static void on_progress(void *user, uint64_t done, uint64_t total) {
  progress_log *p = user;
  p->calls++;
  p->last_done = done;
  p->last_total = total;
}

static void test_limits(void) {
  pb_scene s;
  lit_plane(&s);
  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  pb_ref_result r;
  /* Bounce limit 0: only emitters seen directly (there are none). */
  d.spp = 2;
  d.max_bounces = PB_REF_BOUNCES_ZERO;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_OK);
  if (r.beauty) {
    double sum = 0;
    for (int i = 0; i < 64; ++i) sum += r.beauty[4 * i];
    CHECK_NEAR(sum, 0.0, 0.0);
    CHECK_NEAR(r.beauty[3], 1.0, 0.0); /* the plane still covers the pixel */
  }
  pb_ref_result_destroy(&r);

  /* Time limit with unbounded spp; even passes under estimate_noise. */
  memset(&d, 0, sizeof d);
  d.time_limit_s = 0.2;
  d.estimate_noise = 1;
  progress_log pl = {0, 0, 0};
  d.progress = on_progress;
  d.progress_user = &pl;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 16, 16, &d, &r), PB_OK);
  printf("time limit 0.2 s: %u spp in %.3f s, %llu progress calls\n", r.stats.spp,
         r.stats.time_s, (unsigned long long)pl.calls);
  CHECK(r.stats.spp >= 2);
  CHECK_EQ_INT(r.stats.spp % 2, 0);
  CHECK(r.stats.time_s >= 0.2);
  CHECK(r.stats.time_s < 5.0);
  CHECK(pl.calls >= 1);
  CHECK(r.half_a && r.half_b);
  pb_ref_result_destroy(&r);

  /* Odd spp is rounded up under estimate_noise; progress ends at total. */
  memset(&d, 0, sizeof d);
  d.spp = 3;
  d.estimate_noise = 1;
  pl.calls = 0;
  d.progress = on_progress;
  d.progress_user = &pl;
  CHECK_EQ_INT(pb_ref_render(&s, 0, 8, 8, &d, &r), PB_OK);
  CHECK_EQ_INT(r.stats.spp, 4);
  CHECK_EQ_INT(pl.last_total, 4 * 64);
  CHECK_EQ_INT(pl.last_done, pl.last_total);
  CHECK_EQ_INT(r.stats.camera_samples, 4 * 64);
  CHECK(r.stats.rays >= 4 * 64);
  pb_ref_result_destroy(&r);
  pb_scene_destroy(&s);
}

int main(void) {
  test_errors();
  test_guard();
  test_limits();
  return pbt_done();
}
