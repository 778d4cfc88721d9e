/* Temporal then spatial filtering of the indirect AOV (filters.h). */
#include "render/filters.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/atrous.h"

/* Caustics: their own temporal filter (filters.h), the beauty updated. */
static pb_result filter_caustic(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d, const float *normal) {
  size_t n = (size_t)res->width * res->height;
  float *raw = malloc(3 * n * sizeof *raw);
  if (!raw) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the filters");
  memcpy(raw, res->caustic, 3 * n * sizeof *raw);
  pb_temporal_stats ts;
  pb_result r = pb_temporal_apply(g, d->temporal_caustic, normal, res->depth, res->albedo, d->motion, d->still,
                                  res->caustic, NULL, &ts);
  if (r == PB_OK) {
    res->stats.temporal_ms += ts.gpu_ms;
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        float *c = &res->caustic[3 * i + k];
        if (!isfinite(*c)) *c = 0.0f, res->stats.nonfinite_values++;
        res->beauty[4 * i + k] += *c - raw[3 * i + k];
      }
  }
  free(raw);
  return r;
}

pb_result pb_filter_indirect(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d) {
  if (d->temporal_caustic && res->caustic) {
    pb_result r = filter_caustic(g, res, d, res->geo_normal ? res->geo_normal : res->normal);
    if (r != PB_OK) return r;
  }
  if (!res->indirect || (!d->temporal && !d->atrous_iterations)) return PB_OK;
  size_t n = (size_t)res->width * res->height;
  float *raw = malloc(3 * n * sizeof *raw);
  float *hist = d->temporal ? malloc(n * sizeof *hist) : NULL;
  if (!raw || (d->temporal && !hist)) {
    free(raw);
    free(hist);
    return pb_fail(PB_ERR_NOMEM, "render: out of memory for the filters");
  }
  memcpy(raw, res->indirect, 3 * n * sizeof *raw);
  pb_result r = PB_OK;
  pb_render_stats *st = &res->stats;
  /* Edge-stopping on the geometric normal where normal maps bend the
   * shading one (seed 001 24.4.3: the photon irradiance has no normal-map
   * detail to keep; eq. 20 puts it back after the filters). */
  const float *fn = res->geo_normal ? res->geo_normal : res->normal;
  if (d->temporal) {
    pb_temporal_stats ts;
    r = pb_temporal_apply(g, d->temporal, fn, res->depth, res->albedo, d->motion, d->still,
                          res->indirect, hist, &ts);
    if (r == PB_OK) {
      st->temporal_ms += ts.gpu_ms;
      st->temporal_reset_pixels = ts.reset_pixels;
      st->temporal_surface_pixels = ts.surface_pixels;
      st->temporal_mean_history = ts.mean_history;
    }
  }
  if (r == PB_OK && d->atrous_iterations) {
    pb_atrous_desc fd = {.iterations = d->atrous_iterations, .gamma = d->atrous_gamma, .history = hist};
    double ms = 0;
    r = d->atrous ? pb_atrous_pass_run(g, d->atrous, fn, res->depth, res->albedo, res->indirect, &fd, &ms)
                  : pb_atrous_filter(g, res->width, res->height, fn, res->depth, res->albedo, res->indirect, &fd, &ms);
    st->filter_ms += ms;
  }
  if (r == PB_OK) {
    for (size_t i = 0; i < 3 * n; ++i)
      if (!isfinite(res->indirect[i])) res->indirect[i] = 0.0f, st->nonfinite_values++;
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) res->beauty[4 * i + k] += res->indirect[3 * i + k] - raw[3 * i + k];
  }
  free(raw);
  free(hist);
  return r;
}
