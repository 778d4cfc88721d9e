/* Ray queries through VK_KHR_ray_query (raycast_rq.c: acceleration
 * structures of gpu/accel.c, shaders/scene/raycast_rq.comp) against the
 * GLSL BVH (raycast.c, shaders/common/bvh.glsl) on the same random rays, per
 * sample scene, on one device:
 *   closest hit: hit vs. miss the same; the same primitive with t within
 *     1e-4 relative and the same surface point (from the barycentrics) within
 *     1e-4 max(1, t); or, at shared edges and overlaps, another primitive at
 *     the same t;
 *   any hit: the same occlusion answer for tmax drawn around the BVH's closest
 *     hit (rays whose hit lies within 1e-4 relative of tmax are not judged:
 *     the query's interval is closed, the BVH's open).
 * More than 1 in 10^4 rays disagreeing fails. PB_TEST_RAYS overrides the ray
 * count per scene (default 20000).
 *
 * Run on tools/mesa25's lavapipe (Mesa 25, installed by
 * scripts/install-deps.sh; ctest sets VK_ICD_FILENAMES to its manifest): a
 * missing manifest or a device without ray queries fails, it is not skipped,
 * since the set-up provides them. Validation layers on and fatal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "gpu_embree.h"
#include "pbtest.h"
#include "render/render.h"

static const char *const samples[] = {"cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium"};

static int near_t(float a, float b) { return fabsf(a - b) <= 1e-4f * fmaxf(1.0f, fmaxf(fabsf(a), fabsf(b))); }

static float point_dist(const pb_scene *s, uint32_t prim, const pb_gpu_hit *a, const pb_gpu_hit *b) {
  const uint32_t *t = s->triangles[prim];
  float d2 = 0;
  for (int k = 0; k < 3; ++k) {
    float p0 = s->positions[t[0]][k], p1 = s->positions[t[1]][k], p2 = s->positions[t[2]][k];
    float pa = p0 + a->u * (p1 - p0) + a->v * (p2 - p0), pb = p0 + b->u * (p1 - p0) + b->v * (p2 - p0);
    d2 += (pa - pb) * (pa - pb);
  }
  return sqrtf(d2);
}

/* Exact (double) distance to prim's plane along the ray: which side of a
 * disagreement is off. */
static double exact_t(const pb_scene *s, uint32_t prim, const pb_gpu_ray *r) {
  const uint32_t *t = s->triangles[prim];
  double p[3][3], e1[3], e2[3], n[3], a[3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) p[i][k] = s->positions[t[i]][k];
  for (int k = 0; k < 3; ++k) {
    e1[k] = p[1][k] - p[0][k];
    e2[k] = p[2][k] - p[0][k];
    a[k] = p[0][k] - r->org[k];
  }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  return (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / (n[0] * r->dir[0] + n[1] * r->dir[1] + n[2] * r->dir[2]);
}

static void print_ray(const pb_gpu_ray *r) {
  fprintf(stderr, "org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g) tmax %g", r->org[0], r->org[1], r->org[2], r->dir[0],
          r->dir[1], r->dir[2], r->tmax);
}

/* Casts `rays` through the BVH (rc, bound to the GPU scene of s) and as ray
 * queries (rq), closest hit, and checks that they agree (see the top). */
static pb_result closest_check(pb_gpu *g, const char *name, const char *what, const pb_scene *sp,
                               pb_raycast_pass *rc, pb_raycast_rq_pass *rq, const pb_gpu_ray *rays, uint32_t n,
                               pb_gpu_hit *bh, pb_gpu_hit *qh, uint32_t *hits_out) {
  const pb_scene s = *sp;
  double ms_b = 0, ms_q = 0;
  pb_result r = pb_raycast_run(g, rc, rays, n, 0, bh, &ms_b);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) r = pb_raycast_rq_run(g, rq, rays, n, 0, qh, &ms_q);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  uint32_t bad = 0, hits = 0, same_prim = 0, listed = 0;
  for (uint32_t i = 0; i < n && r == PB_OK; ++i) {
    int bm = bh[i].prim == PB_GPU_MISS, qm = qh[i].prim == PB_GPU_MISS;
    int ok;
    if (bm || qm) ok = bm == qm;
    else if (qh[i].prim >= s.triangle_count) ok = 0;
    else if (bh[i].prim == qh[i].prim) {
      ok = near_t(bh[i].t, qh[i].t) && point_dist(&s, bh[i].prim, &bh[i], &qh[i]) <= 1e-4f * fmaxf(1.0f, bh[i].t);
      same_prim++;
    } else ok = near_t(bh[i].t, qh[i].t);
    hits += !bm;
    if (!ok) {
      bad++;
      if (listed++ < 20) {
        fprintf(stderr, "%s: %s ray %u: ", name, what, i);
        print_ray(&rays[i]);
        fprintf(stderr, ": BVH prim %d t %.9g (u %.6f v %.6f), ray query prim %d t %.9g (u %.6f v %.6f); exact t %.9g\n",
                (int)bh[i].prim, bh[i].t, bh[i].u, bh[i].v, (int)qh[i].prim, qh[i].t, qh[i].u, qh[i].v,
                bm ? (qm ? NAN : exact_t(&s, qh[i].prim, &rays[i])) : exact_t(&s, bh[i].prim, &rays[i]));
      }
    }
  }
  printf("%-18s %s: %u rays, %u hits, %u same primitive, %u disagreements; BVH %.1f ms, ray query %.1f ms; "
         "acceleration structures %.1f KiB built in %.1f ms\n",
         name, what, n, hits, same_prim, bad, ms_b, ms_q, (double)rq->accel.bytes / 1024.0, rq->accel.build_ms);
  CHECK(bad <= n / 10000);
  *hits_out = hits;
  return r;
}

/* Moves every vertex by a smooth, non-rigid warp of up to 4 % of the
 * scene's size (triangles stretch, so a refit is not a translation). */
static void warp(pb_scene *s) {
  float c[3], e = 0;
  for (int k = 0; k < 3; ++k) {
    c[k] = 0.5f * (s->bounds_min[k] + s->bounds_max[k]);
    e = fmaxf(e, s->bounds_max[k] - s->bounds_min[k]);
  }
  if (!(e > 0)) e = 1;
  for (uint32_t i = 0; i < s->vertex_count; ++i) {
    float *p = s->positions[i], q[3] = {p[0], p[1], p[2]};
    for (int k = 0; k < 3; ++k) p[k] = q[k] + 0.04f * e * sinf(6.0f * (q[(k + 1) % 3] - c[(k + 1) % 3]) / e);
  }
}

static void run_scene(pb_gpu *g, const char *name, uint32_t n) {
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load(path, &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  pb_gpu_scene gs;
  pb_raycast_pass rc;
  pb_raycast_rq_pass rq;
  pb_gpu_ray *rays = malloc(n * sizeof *rays);
  pb_gpu_hit *bh = malloc(n * sizeof *bh), *qh = malloc(n * sizeof *qh);
  r = pb_gpu_scene_create(g, &s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    goto out_scene;
  }
  r = pb_raycast_create(g, &gs, n, &rc);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    goto out_gs;
  }
  r = pb_raycast_rq_create(g, &s, n, &rq);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    goto out_rc;
  }
  CHECK(rq.accel.blas && rq.accel.tlas && rq.accel.bytes > 0);
  pbt_random_rays(&s, 0x7a0c0000u + n, rays, n);

  /* Closest hit. */
  uint32_t hits = 0;
  r = closest_check(g, name, "closest", &s, &rc, &rq, rays, n, bh, qh, &hits);
  CHECK(hits > n / 4); /* half the rays aim at a triangle */
  /* Any hit with tmax around the BVH's closest hit. */
  double ms_b = 0, ms_q = 0;
  uint32_t listed = 0;
  uint64_t st = 91;
  for (uint32_t i = 0; i < n; ++i) {
    float t = bh[i].prim == PB_GPU_MISS ? 10.0f : bh[i].t;
    rays[i].tmax = t * (float)(0.5 + pbt_rand(&st));
  }
  if (r == PB_OK) r = pb_raycast_run(g, &rc, rays, n, 1, qh, &ms_b);
  CHECK_EQ_INT(r, PB_OK);
  pb_gpu_hit *ah = malloc(n * sizeof *ah);
  if (r == PB_OK) r = pb_raycast_rq_run(g, &rq, rays, n, 1, ah, &ms_q);
  CHECK_EQ_INT(r, PB_OK);
  uint32_t bad_any = 0, occluded = 0, judged = 0;
  for (uint32_t i = 0; i < n && r == PB_OK; ++i) {
    if (bh[i].prim != PB_GPU_MISS && near_t(bh[i].t, rays[i].tmax)) continue;
    judged++;
    int bo = qh[i].prim != PB_GPU_MISS, qo = ah[i].prim != PB_GPU_MISS;
    occluded += bo;
    if (bo != qo) {
      bad_any++;
      if (listed++ < 20) {
        fprintf(stderr, "%s: any-hit ray %u: ", name, i);
        print_ray(&rays[i]);
        fprintf(stderr, ": BVH %s, ray query %s\n", bo ? "occluded" : "clear", qo ? "occluded" : "clear");
      }
    }
  }
  printf("%-18s any-hit: %u judged, %u occluded, %u disagreements; BVH %.1f ms, ray query %.1f ms\n", name, judged,
         occluded, bad_any, ms_b, ms_q);
  CHECK(occluded > 0);
  CHECK(bad_any <= n / 10000);
  free(ah);

  /* The geometry moves (an animated scene's frame): the BVH refitted
   * (pb_gpu_scene_update; a rebuild needs a GPU scene made from an animated
   * one), the acceleration structures refitted (Vulkan's update mode) and
   * then built again in place (pb_gpu_accel_update), the same closest hits
   * on fresh rays. */
  warp(&s);
  pbt_random_rays(&s, 0x7a0d0000u + n, rays, n);
  for (int rebuild = 0; rebuild < 2 && r == PB_OK; ++rebuild) {
    r = pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_REFIT, NULL);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) r = pb_gpu_accel_update(g, &rq.accel, &s.positions[0][0], !rebuild);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) {
      fprintf(stderr, "%s\n", pb_error_message());
      break;
    }
    CHECK(gs.ray_query && gs.accel.tlas); /* the GPU scene's own, brought up to date too */
    uint32_t moved_hits = 0;
    r = closest_check(g, name, rebuild ? "moved, rebuilt" : "moved, refitted", &s, &rc, &rq, rays, n, bh, qh,
                      &moved_hits);
    CHECK(moved_hits > n / 5);
  }

  pb_raycast_rq_destroy(g, &rq);
out_rc:
  pb_raycast_destroy(g, &rc);
out_gs:
  pb_gpu_scene_destroy(g, &gs);
out_scene:
  free(rays);
  free(bh);
  free(qh);
  pb_scene_destroy(&s);
  pb_error_clear();
}

int main(void) {
  uint32_t n = 20000;
  const char *env = getenv("PB_TEST_RAYS");
  if (env && atoi(env) > 0) n = (uint32_t)atoi(env);
  const char *icd = getenv("VK_ICD_FILENAMES");
  if (!icd || access(icd, R_OK) != 0) {
    fprintf(stderr, "FAIL: VK_ICD_FILENAMES (%s) names no readable ICD manifest; tools/mesa25 comes from "
            "scripts/install-deps.sh\n", icd ? icd : "unset");
    return 1;
  }
  unsetenv("PB_GPU_TRAVERSAL"); /* this test says which traversal each device takes */
  pb_gpu *g;
  pb_gpu_desc gd = {.validation = 1, .traversal = PB_GPU_TRAVERSAL_RAY_QUERY}; /* a CPU device: asked for */
  pb_result r = pb_gpu_create(&gd, &g);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return pbt_done();
  }
  printf("device: %s (%s)\n", pb_gpu_device_name(g), icd);
  CHECK(pb_gpu_get_limits(g)->ray_query);
  if (!pb_gpu_get_limits(g)->ray_query) {
    fprintf(stderr, "FAIL: %s has no ray queries; the Mesa 25 lavapipe of tools/mesa25 has\n", pb_gpu_device_name(g));
    pb_gpu_destroy(g);
    return pbt_done();
  }
  for (size_t i = 0; i < sizeof samples / sizeof *samples; ++i) run_scene(g, samples[i], n);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);

  /* The same device with ray queries masked (as a device without them): no
   * acceleration structures, no device-address buffers, a clear error. */
  setenv("PB_GPU_MASK_FEATURES", "ray-query", 1);
  CHECK_EQ_INT(pb_gpu_create(&gd, &g), PB_ERR_NO_DEVICE); /* --traversal ray-query: refused */
  printf("ray queries asked of a device without: %s\n", pb_error_message());
  pb_error_clear();
  gd.traversal = PB_GPU_TRAVERSAL_AUTO;
  r = pb_gpu_create(&gd, &g);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    CHECK(!pb_gpu_get_limits(g)->ray_query);
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t idx[3] = {0, 1, 2};
    pb_gpu_accel a;
    pb_gpu_accel_desc ad = {.positions = pos, .vertex_count = 3, .indices = idx, .triangle_count = 1};
    CHECK_EQ_INT(pb_gpu_accel_create(g, &ad, &a), PB_ERR_NOT_AVAILABLE);
    pb_gpu_buffer b;
    pb_gpu_buffer_desc bd = {.name = "masked", .size = 64, .device_address = 1};
    CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &b), PB_ERR_NOT_AVAILABLE);
    pb_scene s;
    pb_load_desc ld = {0};
    if (pb_scene_load("samples/cornell_box/cornell_box.gltf", &ld, &s) == PB_OK) {
      pb_raycast_rq_pass rq;
      CHECK_EQ_INT(pb_raycast_rq_create(g, &s, 16, &rq), PB_ERR_NOT_AVAILABLE);
      pb_scene_destroy(&s);
    }
    printf("masked: %s\n", pb_error_message());
    pb_error_clear();
    CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
    pb_gpu_destroy(g);
  }
  unsetenv("PB_GPU_MASK_FEATURES");
  return pbt_done();
}
