/* Filter cost per frame (not a test; bench/run_filters.py runs it):
 *
 *   pb_bench_filters [--device N] [--repeat R] [--iterations K] WxH...
 *
 * For each size: a synthetic frame (a sloped floor and wall meeting at a
 * crease, boxes in front with depth and normal edges, noisy irradiance,
 * albedo 0.5) and a camera pan of (1.3, 0.4) pixels between frames, so the
 * temporal filter reprojects bilinearly and meets disocclusions; the work
 * of both passes does not depend on the picture otherwise (fixed taps).
 * Runs the temporal filter (seed 001 24.4.1) then K (default 4) A-Trous
 * passes (24.4.2) R times (default 5) after one warm-up frame, keeps the
 * best, and prints one JSON object per size:
 *
 *   {"width": W, "height": H, "temporal_ms": .., "atrous_ms": ..,
 *    "filters_ms": .., "wall_ms": .., "device": ".."}
 *
 * *_ms are GPU timestamps of the passes alone; wall_ms also counts the host
 * packing and the uploads and downloads of the AOVs (the filters read
 * resolved AOVs from the host today). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/filter/atrous.h"
#include "render/filter/temporal.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static float frand(void) {
  rng = rng * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng >> 40) & 0xffffff) / 16777216.0f;
}

static void frame(uint32_t w, uint32_t h, float *normal, float *depth, float *albedo, float *indirect,
                  float *motion) {
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      size_t p = (size_t)y * w + x;
      float u = (float)x / w, v = (float)y / h;
      float z = v > 0.5f ? 2.0f + 6.0f * (1.0f - v) : 5.0f;                    /* floor / wall */
      float n[3] = {0.0f, v > 0.5f ? 1.0f : 0.0f, v > 0.5f ? 0.0f : 1.0f};
      int box = ((int)(u * 8) % 3 == 1) && ((int)(v * 6) % 2 == 1);         /* boxes in front */
      if (box) z = 1.5f, n[0] = 0.6f, n[1] = 0.0f, n[2] = 0.8f;
      depth[p] = z;
      for (int k = 0; k < 3; ++k) {
        normal[3 * p + k] = n[k];
        albedo[3 * p + k] = 0.5f;
        indirect[3 * p + k] = 0.5f * (0.3f + 0.2f * u) * (0.5f + frand()); /* photon-like noise */
      }
      motion[4 * p + 0] = 1.3f, motion[4 * p + 1] = 0.4f, motion[4 * p + 2] = z, motion[4 * p + 3] = 1.0f;
    }
}

int main(int argc, char **argv) {
  uint32_t device = UINT32_MAX, repeat = 5, iterations = 4;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; ++i) {
    if (!strcmp(argv[i], "--device") && i + 1 < argc) device = (uint32_t)atoi(argv[++i]);
    else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = (uint32_t)atoi(argv[++i]);
    else if (!strcmp(argv[i], "--iterations") && i + 1 < argc) iterations = (uint32_t)atoi(argv[++i]);
    else {
      fprintf(stderr, "usage: pb_bench_filters [--device N] [--repeat R] [--iterations K] WxH...\n");
      return 2;
    }
  }
  if (i >= argc || !repeat || !iterations) {
    fprintf(stderr, "usage: pb_bench_filters [--device N] [--repeat R] [--iterations K] WxH...\n");
    return 2;
  }
  pb_gpu_desc gd = {.device_set = device != UINT32_MAX, .device = device};
  pb_gpu *g = NULL;
  if (pb_gpu_create(&gd, &g) != PB_OK) {
    fprintf(stderr, "pb_bench_filters: %s\n", pb_error_message());
    return 1;
  }
  int rc = 0;
  for (; i < argc; ++i) {
    unsigned w = 0, h = 0;
    if (sscanf(argv[i], "%ux%u", &w, &h) != 2 || !w || !h || w > 16384 || h > 16384) {
      fprintf(stderr, "pb_bench_filters: size '%s' (expected WxH)\n", argv[i]);
      rc = 2;
      break;
    }
    size_t n = (size_t)w * h;
    float *normal = malloc(3 * n * sizeof(float)), *depth = malloc(n * sizeof(float));
    float *albedo = malloc(3 * n * sizeof(float)), *ind = malloc(3 * n * sizeof(float));
    float *motion = malloc(4 * n * sizeof(float)), *hist = malloc(n * sizeof(float));
    pb_temporal *t = NULL;
    pb_result r = PB_ERR_NOMEM;
    double best_t = 1e30, best_a = 1e30, best_wall = 1e30;
    if (normal && depth && albedo && ind && motion && hist) r = pb_temporal_create(g, w, h, NULL, &t);
    for (uint32_t k = 0; r == PB_OK && k <= repeat; ++k) {
      frame(w, h, normal, depth, albedo, ind, motion);
      pb_temporal_stats ts;
      double w0 = pb_time_now(), a_ms = 0;
      r = pb_temporal_apply(g, t, normal, depth, albedo, k ? motion : NULL, k == 0, ind, hist, &ts);
      pb_atrous_desc ad = {.iterations = iterations, .history = hist};
      if (r == PB_OK) r = pb_atrous_filter(g, w, h, normal, depth, albedo, ind, &ad, &a_ms);
      double wall = (pb_time_now() - w0) * 1e3;
      if (r == PB_OK && k > 0) { /* frame 0: warm-up (and no history) */
        if (ts.gpu_ms < best_t) best_t = ts.gpu_ms;
        if (a_ms < best_a) best_a = a_ms;
        if (wall < best_wall) best_wall = wall;
      }
    }
    if (r == PB_OK)
      printf("{\"width\": %u, \"height\": %u, \"atrous_iterations\": %u, \"temporal_ms\": %.4f, \"atrous_ms\": %.4f, "
             "\"filters_ms\": %.4f, \"wall_ms\": %.3f, \"device\": \"%s\"}\n",
             w, h, iterations, best_t, best_a, best_t + best_a, best_wall, pb_gpu_device_name(g));
    else
      printf("{\"width\": %u, \"height\": %u, \"error\": \"%s\"}\n", w, h, pb_error_message()), rc = 1;
    fflush(stdout);
    pb_temporal_destroy(g, t);
    free(normal), free(depth), free(albedo), free(ind), free(motion), free(hist);
  }
  pb_gpu_destroy(g);
  return rc;
}
