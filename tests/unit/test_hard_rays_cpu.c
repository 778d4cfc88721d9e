/* Ray-robustness hard cases on the reference renderer's Embree accel
 * (pb_ref_accel_create: robust mode plus the exact side filter;
 * pb_ref_intersect) with its pb_offset_ray (src/ref/accel.c); see
 * hard_rays.h for the method.
 *   self-intersection: 10^6 rays per scene (sun_atrium, ring, four soups of
 *     random and sliver triangles at scales 1e-3, 1, 1e3 and 100 around 1e4,
 *     large triangles around the origin): zero hits on the ray's own
 *     triangle among rays whose float direction leaves the exact plane, and
 *     every offset origin strictly on its side of the exact plane;
 *   watertightness: 3 x 65536 rays per closed mesh (icosphere and cube at
 *     scales 1e-3, 1, 1e3 and 1 around 1e4): at most 2e-5 misses through
 *     edges and on Embree's random-inside test; through and near vertices,
 *     at most 5e-3 (Embree 3's known cracks at vertices, see below);
 *   no NaN or Inf in any hit's t, u, v nor in any origin.
 * PB_TEST_RAYS overrides the self-intersection ray count per scene. */
#include <stdlib.h>

#include "pbtest.h"
#include "hard_rays.h"

static int trace_cpu(void *user, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits) {
  const pb_ref_accel *a = user;
  for (uint32_t i = 0; i < n; ++i) {
    pb_ref_hit h;
    if (pb_ref_intersect(a, v3_load(rays[i].org), v3_load(rays[i].dir), rays[i].tmax, &h)) {
      hits[i].t = h.t;
      hits[i].prim = h.prim;
      hits[i].u = h.u;
      hits[i].v = h.v;
    } else {
      hits[i].t = rays[i].tmax;
      hits[i].prim = PB_GPU_MISS;
      hits[i].u = hits[i].v = 0.0f;
    }
  }
  return 1;
}

int main(void) {
  uint32_t n = 1000000;
  const char *env = getenv("PB_TEST_RAYS");
  if (env && atoi(env) > 0) n = (uint32_t)atoi(env);

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
    pb_ref_accel a;
    pb_result r = pb_ref_accel_create(&s, &a);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) {
      hr_self_stats st;
      CHECK(hr_self_test(&s, d->name, n, 0xabc00000u + i, trace_cpu, &a, &st));
      hr_self_print("cpu", d->name, &st);
      CHECK_EQ_INT(st.self_hits, 0);
      CHECK_EQ_INT(st.origin_not_lifted, 0);
      CHECK_EQ_INT(st.nonfinite, 0);
      /* The judged set is nearly everything (the test cannot pass by
       * excluding rays), and most points are the primary ray's own hit. */
      CHECK(st.judged >= st.rays - st.rays / 20);
      CHECK(st.primary_hits >= st.rays / 4);
      total += st.rays;
      self_hits += st.self_hits;
      pb_ref_accel_destroy(&a);
    }
    pb_scene_destroy(&s);
    pb_error_clear();
  }
  printf("cpu self-intersection: %llu rays, %llu self-hits\n", (unsigned long long)total,
         (unsigned long long)self_hits);

  hr_water_stats sum;
  memset(&sum, 0, sizeof sum);
  for (size_t i = 0; i < sizeof hr_meshes / sizeof *hr_meshes; ++i) {
    const hr_mesh_def *d = &hr_meshes[i];
    pb_scene s;
    double R;
    hr_mesh(d, &s, &R);
    CHECK(hr_closed(&s));
    pb_ref_accel a;
    pb_result r = pb_ref_accel_create(&s, &a);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) {
      hr_water_stats st;
      CHECK(hr_watertight(&s, d->name, d->center, R, HR_WATER_RAYS, 0x3a7e0000u + i, trace_cpu, &a, &st));
      hr_water_print("cpu", d->name, &st);
      hr_water_add(&sum, &st);
      pb_ref_accel_destroy(&a);
    }
    pb_scene_destroy(&s);
  }
  hr_water_print("cpu", "all meshes", &sum);
  /* Embree 3's robust intersector leaves tiny cracks at vertices (upstream:
   * RenderKit/embree#174, #181, #387): rays through and within 1e-5
   * of an edge from a vertex miss about 1e-3 of the time on the icosphere
   * (0 on edges, 0 on Embree's own random-ray test). Bounded at 5e-3, so
   * that losing robust mode (~10 % misses) fails. */
  hr_water_check("cpu", &sum, 5e-3);
  return pbt_done();
}
