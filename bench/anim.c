/* Animated scenes: BVH refit against rebuild (not a test).
 *
 *   pb_bench_anim SCENE T0 T1 [T2 ...] [--width W] [--repeat R]
 *
 * For each Ti: the scene posed at T0 goes to the GPU twice
 * (pb_gpu_scene_create), is posed at Ti, and one copy is updated by REFIT,
 * the other by REBUILD. Update: wall ms of pb_gpu_scene_update (host refit or
 * Embree build plus the uploads), best of R. Rays: the camera's primary rays
 * at W (default 640) x height and as many random rays (tests/unit/
 * gpu_embree.h, closest hit), GPU timestamps, best of R after a warm-up, the
 * two trees alternating (load from other processes hits both alike).
 * "sah" is the refitted tree's SAH cost over the tree's built at T0, what AUTO
 * (PB_BVH_REFIT_MAX_SAH in src/render/scene/scene_gpu.c) looks at; "sah/rb" the
 * refitted tree's over the tree rebuilt at Ti (what a rebuild would gain,
 * unknown to AUTO without building). "break-even":
 * rays per frame above which the rebuild's faster rays repay its longer
 * update (negative: the rebuild never loses; "never": the refit's rays are
 * as fast). bench/anim_scenes.py makes animated variants of the samples. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu_embree.h"
#include "render/scene/motion.h"
#include "render/render.h"

static void primary_rays(const pb_scene *s, uint32_t w, uint32_t h, pb_gpu_ray *rays) {
  pb_camera_primary_rays(&s->cameras[0], w, h, 0, w * h, rays); /* render/scene/motion.h */
}

int main(int argc, char **argv) {
  const char *path = NULL;
  double times[32];
  int nt = 0;
  uint32_t width = 640, repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--width") == 0 && i + 1 < argc) width = (uint32_t)atoi(argv[++i]);
    else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = (uint32_t)atoi(argv[++i]);
    else if (!path) path = argv[i];
    else if (nt < 32) times[nt++] = atof(argv[i]);
  }
  if (!path || nt < 2 || width < 8 || repeat < 1) {
    fprintf(stderr, "usage: pb_bench_anim SCENE T0 T1 [T2 ...] [--width W] [--repeat R]\n");
    return 2;
  }
  pb_scene s;
  pb_load_desc ld = {0};
  if (pb_scene_load(path, &ld, &s) != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
    return 1;
  }
  if (!s.anim) fprintf(stderr, "warning: %s has no animation; every pose is the same\n", path);
  uint32_t w, h;
  pb_camera_image_size(&s.cameras[0], width, 0, &w, &h);
  uint32_t n = w * h;
  pb_gpu *g = NULL;
  pb_gpu_ray *prim = malloc((size_t)n * sizeof *prim), *rnd = malloc((size_t)n * sizeof *rnd);
  pb_gpu_hit *hits = malloc((size_t)n * sizeof *hits);
  if (!prim || !rnd || !hits || pb_gpu_create(NULL, &g) != PB_OK) {
    fprintf(stderr, "setup failed: %s\n", pb_error_message());
    return 1;
  }
  printf("scene %s: %u triangles, animation %.3g..%.3g s; %u rays per set (%ux%u); GPU %s\n", path, s.triangle_count,
         s.anim_start, s.anim_end, n, w, h, pb_gpu_device_name(g));
  printf("%-6s %-6s %6s %6s | %10s %10s %10s | %10s %10s %10s | %s\n", "t0", "t1", "sah", "sah/rb", "refit ms", "prim Mr/s", "rand Mr/s",
         "rebuild ms", "prim Mr/s", "rand Mr/s", "break-even rays/frame");
  for (int i = 1; i < nt; ++i) {
    /* Both trees side by side, their rays timed alternately (best of R
     * each), so that load from other processes hits both alike. */
    pb_gpu_scene gs[2];
    double up[2] = {INFINITY, INFINITY}, pms[2] = {INFINITY, INFINITY}, rms[2] = {INFINITY, INFINITY};
    pb_raycast_pass rc[2];
    if (pb_scene_set_time(&s, times[0]) != PB_OK || pb_gpu_scene_create(g, &s, &gs[0]) != PB_OK ||
        pb_gpu_scene_create(g, &s, &gs[1]) != PB_OK || pb_scene_set_time(&s, times[i]) != PB_OK) {
      fprintf(stderr, "%s\n", pb_error_message());
      return 1;
    }
    /* The first REFIT is the one from T0; later ones refit to the same pose
     * (the same work). Every REBUILD builds anew. */
    double sah = 0;
    for (uint32_t k = 0; k < repeat; ++k)
      for (int m = 0; m < 2; ++m) {
        double ms;
        if (pb_gpu_scene_update(g, &s, &gs[m], m ? PB_BVH_UPDATE_REBUILD : PB_BVH_UPDATE_REFIT, &ms) != PB_OK) {
          fprintf(stderr, "%s\n", pb_error_message());
          return 1;
        }
        if (ms < up[m]) up[m] = ms;
        if (k == 0 && m == 0) sah = gs[0].sah / gs[0].sah_built;
      }
    primary_rays(&s, w, h, prim);
    pbt_random_rays(&s, 1234, rnd, n);
    for (int m = 0; m < 2; ++m)
      if (pb_raycast_create(g, &gs[m], n, &rc[m]) != PB_OK) {
        fprintf(stderr, "%s\n", pb_error_message());
        return 1;
      }
    for (uint32_t k = 0; k <= repeat; ++k) /* k == 0: warm-up */
      for (int m = 0; m < 2; ++m) {
        double a = INFINITY, b = INFINITY;
        if (pb_raycast_run(g, &rc[m], prim, n, 0, hits, &a) != PB_OK || pb_raycast_run(g, &rc[m], rnd, n, 0, hits, &b) != PB_OK) {
          fprintf(stderr, "%s\n", pb_error_message());
          return 1;
        }
        if (k > 0 && a < pms[m]) pms[m] = a;
        if (k > 0 && b < rms[m]) rms[m] = b;
      }
    double sah_rb = gs[0].sah / gs[1].sah;
    for (int m = 0; m < 2; ++m) {
      pb_raycast_destroy(g, &rc[m]);
      pb_gpu_scene_destroy(g, &gs[m]);
    }
    /* Per ray (random, the renderer's typical secondary ray): ms. */
    double per_refit = rms[0] / n, per_rebuild = rms[1] / n, gain = per_refit - per_rebuild;
    char be[64];
    if (gain <= 0) snprintf(be, sizeof be, "never");
    else snprintf(be, sizeof be, "%.3g", (up[1] - up[0]) / gain);
    printf("%-6.3g %-6.3g %6.2f %6.2f | %10.2f %10.2f %10.2f | %10.2f %10.2f %10.2f | %s\n", times[0], times[i], sah, sah_rb,
           up[0], n / pms[0] * 1e-3, n / rms[0] * 1e-3, up[1], n / pms[1] * 1e-3, n / rms[1] * 1e-3, be);
    fflush(stdout);
  }
  free(prim);
  free(rnd);
  free(hits);
  pb_gpu_destroy(g);
  pb_scene_destroy(&s);
  return 0;
}
