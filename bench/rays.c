/* Ray-throughput benchmark (not a test): the GPU ray-casting kernel through
 * the GLSL BVH (raycast.c) against Embree's rtcIntersect1 / rtcOccluded1 on
 * exactly the same rays, Embree using as many threads as the machine has
 * cores (the same cores lavapipe runs on); on a device with ray queries
 * (VK_KHR_ray_query: NVIDIA, AMD and Intel GPUs, Mesa 25's lavapipe) the
 * same rays as ray queries too (raycast_rq.c), with their rate against the
 * BVH's and their agreement with it.
 *
 *   pb_bench_rays SCENE [WIDTH] [REPEAT]
 *
 * Rays: the camera's primary rays at WIDTH (default 640) x height from the
 * camera's aspect, through pixel centres; then as many random rays
 * (tests/unit/gpu_embree.h), closest hit and any hit. GPU time is from
 * timestamps around the dispatch (best of REPEAT runs, default 3, after one
 * warm-up that also JIT-compiles the shader on lavapipe); Embree time is wall
 * time of a parallel loop (best of REPEAT). Prints one line per ray set. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "gpu_embree.h"
#include "render/scene/motion.h"
#include "render/render.h"

typedef struct job {
  const pbt_embree *e;
  const pb_gpu_ray *rays;
  pb_gpu_hit *hits;
  uint32_t begin, end;
  int any_hit;
} job;

static void *worker(void *p) {
  job *j = p;
  for (uint32_t i = j->begin; i < j->end; ++i) pbt_embree_trace(j->e, &j->rays[i], j->any_hit, &j->hits[i]);
  return NULL;
}

static double embree_run(const pbt_embree *e, const pb_gpu_ray *rays, pb_gpu_hit *hits, uint32_t n, int any_hit,
                         uint32_t threads) {
  pthread_t th[256];
  job jobs[256];
  double t0 = pb_time_now();
  for (uint32_t t = 0; t < threads; ++t) {
    jobs[t] = (job){e, rays, hits, (uint32_t)((uint64_t)n * t / threads), (uint32_t)((uint64_t)n * (t + 1) / threads),
                    any_hit};
    pthread_create(&th[t], NULL, worker, &jobs[t]);
  }
  for (uint32_t t = 0; t < threads; ++t) pthread_join(th[t], NULL);
  return (pb_time_now() - t0) * 1e3;
}

static void primary_rays(const pb_scene *s, uint32_t w, uint32_t h, pb_gpu_ray *rays) {
  pb_camera_primary_rays(&s->cameras[0], w, h, 0, w * h, rays); /* render/scene/motion.h */
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: pb_bench_rays SCENE [WIDTH] [REPEAT]\n");
    return 2;
  }
  uint32_t width = argc > 2 ? (uint32_t)atoi(argv[2]) : 640, repeat = argc > 3 ? (uint32_t)atoi(argv[3]) : 3;
  if (repeat < 1) repeat = 1;
  long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
  uint32_t threads = ncpu > 0 && ncpu < 256 ? (uint32_t)ncpu : 1;
  pb_scene s;
  pb_load_desc ld = {0};
  if (pb_scene_load(argv[1], &ld, &s) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return 1;
  }
  uint32_t w, h;
  pb_camera_image_size(&s.cameras[0], width, 0, &w, &h);
  uint32_t n = w * h;
  pb_gpu *g = NULL;
  pb_gpu_scene gs;
  pb_raycast_pass rc;
  pb_raycast_rq_pass rq;
  pbt_embree e;
  memset(&gs, 0, sizeof gs);
  memset(&rc, 0, sizeof rc);
  memset(&rq, 0, sizeof rq);
  pb_gpu_ray *rays = malloc((size_t)n * sizeof *rays);
  pb_gpu_hit *gh = malloc((size_t)n * sizeof *gh), *eh = malloc((size_t)n * sizeof *eh),
             *qh = malloc((size_t)n * sizeof *qh);
  /* Ray queries wherever the device has them (a CPU device's too), else
   * the BVH alone. */
  pb_gpu_desc gd = {.traversal = PB_GPU_TRAVERSAL_RAY_QUERY};
  pb_result r = pb_gpu_create(&gd, &g);
  if (r == PB_ERR_NO_DEVICE) {
    pb_error_clear();
    r = pb_gpu_create(NULL, &g);
  }
  if (r == PB_OK) r = pb_gpu_scene_create(g, &s, &gs);
  if (r == PB_OK) r = pb_raycast_create(g, &gs, n, &rc);
  /* Ray queries where the device has them: the same rays through
   * VK_KHR_ray_query (raycast_rq.c), beside the GLSL BVH. */
  int have_rq = r == PB_OK && pb_gpu_get_limits(g)->ray_query;
  if (have_rq) r = pb_raycast_rq_create(g, &s, n, &rq);
  if (r != PB_OK || !rays || !gh || !eh || !qh || !pbt_embree_create(&s, threads, &e)) {
    fprintf(stderr, "setup failed: %s\n", pb_error_message());
    return 1;
  }
  printf("scene %s: %u triangles; %u rays per set (%ux%u); GPU %s; Embree %ld with %u threads\n", argv[1],
         s.triangle_count, n, w, h, pb_gpu_device_name(g), (long)rtcGetDeviceProperty(e.dev, RTC_DEVICE_PROPERTY_VERSION), threads);
  printf("%-16s %12s %12s %8s %8s", "rays", "GPU Mrays/s", "Embree Mr/s", "ratio", "agree");
  if (have_rq) printf(" %12s %8s %8s", "RQ Mrays/s", "RQ/BVH", "RQ agree");
  printf("\n");
  for (int set = 0; set < 3; ++set) {
    const char *label = set == 0 ? "primary" : set == 1 ? "random closest" : "random any-hit";
    if (set == 0) primary_rays(&s, w, h, rays);
    else if (set == 1) pbt_random_rays(&s, 1234, rays, n);
    int any = set == 2;
    double best_g = INFINITY, best_e = INFINITY, best_q = INFINITY, ms;
    for (uint32_t k = 0; k <= repeat; ++k) { /* k == 0: warm-up */
      if (have_rq) {
        if (pb_raycast_rq_run(g, &rq, rays, n, any, qh, &ms) != PB_OK) {
          fprintf(stderr, "%s\n", pb_error_message());
          return 1;
        }
        if (k > 0 && ms < best_q) best_q = ms;
      }
      if (pb_raycast_run(g, &rc, rays, n, any, gh, &ms) != PB_OK) {
        fprintf(stderr, "%s\n", pb_error_message());
        return 1;
      }
      if (k > 0 && ms < best_g) best_g = ms;
      ms = embree_run(&e, rays, eh, n, any, threads);
      if (k > 0 && ms < best_e) best_e = ms;
    }
    uint32_t agree = 0, agree_q = 0;
    for (uint32_t i = 0; i < n; ++i) {
      int gm = gh[i].prim == PB_GPU_MISS;
      agree += gh[i].prim == eh[i].prim || (any && gm == (eh[i].prim == PB_GPU_MISS));
      agree_q += gh[i].prim == qh[i].prim || (any && gm == (qh[i].prim == PB_GPU_MISS));
    }
    double grs = n / best_g * 1e-3, ers = n / best_e * 1e-3, qrs = n / best_q * 1e-3;
    printf("%-16s %12.2f %12.2f %7.2fx %7.4f%%", label, grs, ers, ers / grs, 100.0 * agree / n);
    if (have_rq) printf(" %12.2f %7.2fx %7.4f%%", qrs, qrs / grs, 100.0 * agree_q / n);
    printf("\n");
  }
  pbt_embree_destroy(&e);
  pb_raycast_destroy(g, &rc);
  pb_raycast_rq_destroy(g, &rq);
  pb_gpu_scene_destroy(g, &gs);
  pb_gpu_destroy(g);
  pb_scene_destroy(&s);
  free(rays);
  free(gh);
  free(eh);
  free(qh);
  return 0;
}
