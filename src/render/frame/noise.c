/* The frame's noise estimate from two groups of independent photon maps
 * (noise.h). */
#include "render/frame/noise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metrics/metrics.h"

void pb_noise_tracker_init(pb_noise_tracker *t, uint32_t width, uint32_t height) {
  memset(t, 0, sizeof *t);
  t->width = width, t->height = height;
  t->estimate = -1.0;
  t->psnr = 0.0;
}

void pb_noise_tracker_free(pb_noise_tracker *t) {
  free(t->prev);
  free(t->group_a);
  free(t->a);
  free(t->b);
  t->prev = t->group_a = t->a = t->b = NULL;
}

pb_result pb_noise_tracker_check(pb_noise_tracker *t, const float *mean, uint32_t samples) {
  size_t n = (size_t)t->width * t->height * 4;
  if (samples <= t->prev_samples) return PB_OK; /* no new block */
  if (!t->prev) {
    t->prev = calloc(n, sizeof(float));
    t->group_a = calloc(n, sizeof(float));
    t->a = malloc(n * sizeof(float));
    t->b = malloc(n * sizeof(float));
    if (!t->prev || !t->group_a || !t->a || !t->b) {
      pb_noise_tracker_free(t);
      return pb_fail(PB_ERR_NOMEM, "render: out of memory for the noise estimate of a %ux%u image", t->width,
                     t->height);
    }
  }
  uint32_t block = samples - t->prev_samples;
  int to_a = t->samples_a <= t->samples_b;
  for (size_t i = 0; i < n; ++i) {
    float sum = mean[i] * (float)samples;
    if (to_a) t->group_a[i] += sum - t->prev[i];
    t->prev[i] = sum;
  }
  if (to_a) t->samples_a += block;
  else t->samples_b += block;
  t->prev_samples = samples;
  t->blocks++;
  t->checks++;
  if (!t->samples_a || !t->samples_b) return PB_OK;
  float ia = 1.0f / (float)t->samples_a, ib = 1.0f / (float)t->samples_b;
  for (size_t i = 0; i < n; ++i) {
    t->a[i] = t->group_a[i] * ia;
    t->b[i] = (t->prev[i] - t->group_a[i]) * ib;
  }
  pb_noise_estimate ne;
  pb_result r = pb_metrics_noise_from_parts(t->a, t->samples_a, t->b, t->samples_b, t->width, t->height, 4, NULL,
                                            &ne);
  if (r != PB_OK) return r;
  t->estimate = ne.rmse_display;
  t->psnr = ne.psnr;
  return PB_OK;
}

uint32_t pb_noise_tracker_next(const pb_noise_tracker *t, double threshold, uint32_t done, uint32_t planned) {
  uint64_t next = (uint64_t)done + 1;
  if (t->estimate > 0 && threshold > 0) {
    double want = (double)done * (t->estimate / threshold) * (t->estimate / threshold);
    if (want > 2.0 * done) want = 2.0 * done;
    if (want > (double)next) next = (uint64_t)ceil(want);
  }
  return next < planned ? (uint32_t)next : planned;
}
