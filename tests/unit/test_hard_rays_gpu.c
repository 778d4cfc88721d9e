/* Ray-robustness hard cases on the GPU ray kernel (shaders/scene/raycast.comp:
 * pb_trace of shaders/common/bvh.glsl, the watertight test of Woop et al.
 * that every GPU pass uses), through pb_raycast_run; see hard_rays.h.
 *
 * Origins are offset on the host with the C pb_offset_ray of src/ref, which
 * is the same formula as the GLSL pb_offset_ray of shaders/common/scene.glsl
 * (Waechter & Binder: 256 float ulps along n, 1/65536 absolute below |p| <
 * 1/32; both truncate int_scale * n to an integer and add it to the bits
 * with the sign of p). Surface points come from the C pb_surface_from_hit,
 * the same interpolation, in the same order, as the GLSL one. (The GLSL
 * versions may contract a * b + c into an FMA, which changes the last bit
 * only.)
 *   self-intersection: 10^6 rays per scene (as the CPU test): zero self-hits
 *     among rays leaving the exact plane;
 *   watertightness: rays through vertices, near vertices and through edge
 *     points of closed meshes, from outside and from inside, and random rays
 *     from inside: at most 2e-5 misses in every class;
 *   no NaN or Inf in any hit's t, u, v.
 * Exit 77 (skipped) without a Vulkan device. PB_TEST_RAYS overrides the
 * self-intersection ray count per scene. */
#include <stdlib.h>

#include "pbtest.h"
#include "hard_rays.h"
#include "core/log.h"
#include "render/render.h"

typedef struct gpu_ctx {
  pb_gpu *g;
  pb_raycast_pass rc;
  int failed;
} gpu_ctx;

static int trace_gpu(void *user, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits) {
  gpu_ctx *c = user;
  pb_result r = pb_raycast_run(c->g, &c->rc, rays, n, 0, hits, NULL);
  if (r != PB_OK) {
    fprintf(stderr, "raycast: %s\n", pb_error_message());
    c->failed = 1;
    return 0;
  }
  return 1;
}

/* Uploads s and makes a ray pass for it. */
static int gpu_scene(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs, gpu_ctx *c) {
  memset(c, 0, sizeof *c);
  c->g = g;
  pb_result r = pb_gpu_scene_create(g, s, gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return 0;
  }
  r = pb_raycast_create(g, gs, HR_BATCH, &c->rc);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    pb_gpu_scene_destroy(g, gs);
    return 0;
  }
  return 1;
}

static void gpu_scene_done(pb_gpu *g, pb_gpu_scene *gs, gpu_ctx *c) {
  pb_raycast_destroy(g, &c->rc);
  pb_gpu_scene_destroy(g, gs);
}

int main(void) {
  uint32_t n = 1000000;
  const char *env = getenv("PB_TEST_RAYS");
  if (env && atoi(env) > 0) n = (uint32_t)atoi(env);
  pb_gpu *g;
  pb_gpu_desc gd = {.validation = 1};
  pb_result r = pb_gpu_create(&gd, &g);
  if (r == PB_ERR_NO_DEVICE || r == PB_ERR_NOT_AVAILABLE) {
    printf("SKIP: %s\n", pb_error_message());
    return 77;
  }
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return pbt_done();
  }
  printf("device: %s\n", pb_gpu_device_name(g));

  uint64_t total = 0, self_hits = 0;
  for (size_t i = 0; i < sizeof hr_self_scenes / sizeof *hr_self_scenes; ++i) {
    const hr_scene_def *d = &hr_self_scenes[i];
    pb_scene s;
    int ok = hr_self_scene(d, 0x5e1f0000u + i, &s);
    CHECK(ok);
    if (!ok) {
      fprintf(stderr, "%s: %s\n", d->name, pb_error_message());
      continue;
    }
    pb_gpu_scene gs;
    gpu_ctx c;
    if (gpu_scene(g, &s, &gs, &c)) {
      hr_self_stats st;
      double t0 = pb_time_now();
      CHECK(hr_self_test(&s, d->name, n, 0xabc00000u + i, trace_gpu, &c, &st));
      CHECK(!c.failed);
      hr_self_print("gpu", d->name, &st);
      printf("gpu %-22s %.1f s\n", d->name, pb_time_now() - t0);
      CHECK_EQ_INT(st.self_hits, 0);
      CHECK_EQ_INT(st.origin_not_lifted, 0);
      CHECK_EQ_INT(st.nonfinite, 0);
      CHECK(st.judged >= st.rays - st.rays / 20);
      CHECK(st.primary_hits >= st.rays / 4);
      total += st.rays;
      self_hits += st.self_hits;
      gpu_scene_done(g, &gs, &c);
    }
    pb_scene_destroy(&s);
    pb_error_clear();
  }
  printf("gpu self-intersection: %llu rays, %llu self-hits\n", (unsigned long long)total,
         (unsigned long long)self_hits);

  hr_water_stats sum;
  memset(&sum, 0, sizeof sum);
  for (size_t i = 0; i < sizeof hr_meshes / sizeof *hr_meshes; ++i) {
    const hr_mesh_def *d = &hr_meshes[i];
    pb_scene s;
    double R;
    hr_mesh(d, &s, &R);
    CHECK(hr_closed(&s));
    pb_gpu_scene gs;
    gpu_ctx c;
    if (gpu_scene(g, &s, &gs, &c)) {
      hr_water_stats st;
      CHECK(hr_watertight(&s, d->name, d->center, R, HR_WATER_RAYS, 0x3a7e0000u + i, trace_gpu, &c, &st));
      CHECK(!c.failed);
      hr_water_print("gpu", d->name, &st);
      hr_water_add(&sum, &st);
      gpu_scene_done(g, &gs, &c);
    }
    pb_scene_destroy(&s);
  }
  hr_water_print("gpu", "all meshes", &sum);
  hr_water_check("gpu", &sum, 2e-5);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
