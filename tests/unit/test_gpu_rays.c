/* GPU ray queries against Embree (rtcIntersect1 / rtcOccluded1, robust mode)
 * on the same random rays, per sample scene:
 *   closest hit: same primitive with t within 1e-4 relative and the same
 *     surface point (from the barycentrics) within 1e-4 max(1, t); or, at
 *     shared edges and overlaps, another primitive at the same t; hit vs.
 *     miss is a disagreement;
 *   any hit: the occlusion answer for tmax drawn around the closest hit
 *     (rays whose hit lies within 1e-4 relative of tmax are not judged).
 * Disagreements are listed; the test fails when more than 1 in 10^4 rays
 * disagree. PB_TEST_RAYS overrides the ray count (default 10^5). Exit 77
 * (skipped) when there is no Vulkan device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* Exact (double) distance to prim's plane along the ray, and the triangle's
 * smallest height relative to its longest edge (slivers are ill-conditioned). */
static double exact_t(const pb_scene *s, uint32_t prim, const pb_gpu_ray *r, double *thin) {
  const uint32_t *t = s->triangles[prim];
  double p[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) p[i][k] = s->positions[t[i]][k];
  double e1[3], e2[3], n[3], a[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = p[1][k] - p[0][k];
    e2[k] = p[2][k] - p[0][k];
    a[k] = p[0][k] - r->org[k];
  }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  double area2 = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), lmax = 0;
  for (int i = 0; i < 3; ++i) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (p[(i + 1) % 3][k] - p[i][k]) * (p[(i + 1) % 3][k] - p[i][k]);
    if (d2 > lmax) lmax = d2;
  }
  *thin = lmax > 0 ? area2 / lmax : 0; /* height / longest edge */
  double den = n[0] * r->dir[0] + n[1] * r->dir[1] + n[2] * r->dir[2];
  return (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / den;
}

static void print_ray(const pb_gpu_ray *r) {
  fprintf(stderr, "org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g) tmax %g", r->org[0], r->org[1], r->org[2], r->dir[0],
          r->dir[1], r->dir[2], r->tmax);
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
  pbt_embree e;
  pb_gpu_ray *rays = malloc(n * sizeof *rays);
  pb_gpu_hit *gh = malloc(n * sizeof *gh), *eh = malloc(n * sizeof *eh);
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
  CHECK(pbt_embree_create(&s, 0, &e));
  pbt_random_rays(&s, 0x5eed0000u + n, rays, n);

  /* Closest hit. */
  double ms = 0;
  r = pb_raycast_run(g, &rc, rays, n, 0, gh, &ms);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  uint32_t bad = 0, hits = 0, same_prim = 0, listed = 0;
  for (uint32_t i = 0; i < n && r == PB_OK; ++i) {
    pbt_embree_trace(&e, &rays[i], 0, &eh[i]);
    int gm = gh[i].prim == PB_GPU_MISS, em = eh[i].prim == PB_GPU_MISS;
    int ok;
    if (gm || em) ok = gm == em;
    else if (gh[i].prim == eh[i].prim) {
      /* Barycentrics are ill-conditioned for grazing rays and slivers: judge
       * the surface points they give instead. */
      ok = near_t(gh[i].t, eh[i].t) &&
           point_dist(&s, gh[i].prim, &gh[i], &eh[i]) <= 1e-4f * fmaxf(1.0f, eh[i].t);
      /* Where Embree and the GPU differ, the exact (double) answer decides:
       * the GPU passes when it is at least as close to it as Embree. */
      double thin, te = exact_t(&s, gh[i].prim, &rays[i], &thin);
      if (!ok && fabs(gh[i].t - te) <= fabs(eh[i].t - te)) ok = 1;
      same_prim++;
    } else ok = near_t(gh[i].t, eh[i].t);
    hits += !em;
    if (!ok) {
      bad++;
      if (listed++ < 20) {
        fprintf(stderr, "%s: closest ray %u: ", name, i);
        print_ray(&rays[i]);
        double thin = 0, te = em ? NAN : exact_t(&s, eh[i].prim, &rays[i], &thin);
        fprintf(stderr, ": GPU prim %d t %.9g (u %.6f v %.6f), Embree prim %d t %.9g (u %.6f v %.6f); "
                "exact t %.9g, triangle height/edge %.2g\n",
                (int)gh[i].prim, gh[i].t, gh[i].u, gh[i].v, (int)eh[i].prim, eh[i].t, eh[i].u, eh[i].v, te, thin);
      }
    }
  }
  printf("%-18s closest: %u rays, %u hits, %u same primitive, %u disagreements, %.1f ms GPU (%.2f Mrays/s)\n",
         name, n, hits, same_prim, bad, ms, ms > 0 ? n / ms * 1e-3 : 0.0);
  CHECK(bad <= n / 10000);

  /* Any hit with tmax around the closest hit. */
  uint64_t st = 77;
  for (uint32_t i = 0; i < n; ++i) {
    float t = eh[i].prim == PB_GPU_MISS ? 10.0f : eh[i].t;
    rays[i].tmax = t * (float)(0.5 + pbt_rand(&st));
  }
  r = pb_raycast_run(g, &rc, rays, n, 1, gh, &ms);
  CHECK_EQ_INT(r, PB_OK);
  uint32_t bad_any = 0, occluded = 0, judged = 0;
  listed = 0;
  for (uint32_t i = 0; i < n && r == PB_OK; ++i) {
    if (eh[i].prim != PB_GPU_MISS && near_t(eh[i].t, rays[i].tmax)) continue;
    judged++;
    pb_gpu_hit a;
    pbt_embree_trace(&e, &rays[i], 1, &a);
    int go = gh[i].prim != PB_GPU_MISS, eo = a.prim != PB_GPU_MISS;
    occluded += eo;
    if (go != eo) {
      bad_any++;
      if (listed++ < 20) {
        fprintf(stderr, "%s: any-hit ray %u: ", name, i);
        print_ray(&rays[i]);
        fprintf(stderr, ": GPU %s, Embree %s\n", go ? "occluded" : "clear", eo ? "occluded" : "clear");
      }
    }
  }
  printf("%-18s any-hit: %u judged, %u occluded, %u disagreements, %.1f ms GPU\n", name, judged, occluded, bad_any, ms);
  CHECK(bad_any <= n / 10000);

  pbt_embree_destroy(&e);
  pb_raycast_destroy(g, &rc);
out_gs:
  pb_gpu_scene_destroy(g, &gs);
out_scene:
  free(rays);
  free(gh);
  free(eh);
  pb_scene_destroy(&s);
  pb_error_clear();
}

int main(void) {
  uint32_t n = 100000;
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
  for (size_t i = 0; i < sizeof samples / sizeof *samples; ++i) run_scene(g, samples[i], n);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
