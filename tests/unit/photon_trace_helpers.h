/* Tracing helpers for the photon tracer's GPU unit tests: one trace of a
 * scene into a downloaded photon list with its statistics, its release,
 * and the record checks every tracer test makes (finite, inside the bounds,
 * unit normal and direction on one side, footprint radius over both axes).
 * Shared by test_gpu_photon_trace and test_gpu_photon_rsm. */
#ifndef PB_TEST_PHOTON_TRACE_HELPERS_H
#define PB_TEST_PHOTON_TRACE_HELPERS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_test.h"
#include "pbtest.h"
#include "render/photon/photon.h"
#include "shared/pb_photon.h"

typedef struct traced {
  pb_gpu_photon *ph;
  uint32_t n;
  pb_photon_map map;
  pb_photon_trace_stats st;
} traced;

static int trace(pb_gpu *g, const pb_scene *s, const pb_photon_trace_desc *d, uint64_t seed, uint32_t iter,
                 float h, uint32_t depth, uint32_t flags, traced *out) {
  memset(out, 0, sizeof *out);
  pb_gpu_scene gs;
  pb_result r = pb_gpu_scene_create(g, s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return 0;
  pb_photon_tracer *t = NULL;
  r = pb_photon_tracer_create(g, s, &gs, d, &t);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    pb_photon_tracer_debug(t, h, depth, flags);
    double ms = 0;
    r = pb_photon_tracer_run(g, t, seed, iter, &out->map, &ms);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
    pb_photon_tracer_stats(t, &out->st);
    if (r == PB_OK) {
      out->n = out->map.stored;
      out->ph = calloc(out->n ? out->n : 1, sizeof *out->ph);
      if (out->n)
        CHECK_EQ_INT(pb_gpu_buffer_download(g, &out->map.photons, 0, out->ph, (uint64_t)out->n * sizeof *out->ph),
                     PB_OK);
    }
  }
  pb_photon_tracer_destroy(g, t);
  pb_gpu_scene_destroy(g, &gs);
  return r == PB_OK;
}

static void release(pb_gpu *g, traced *t) {
  free(t->ph);
  pb_photon_map_destroy(g, &t->map);
}

static uint32_t bounce_of(const pb_gpu_photon *p) { return (p->flags >> PB_PHOTON_BOUNCE_SHIFT) & 255u; }

static int finite3(const float v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }
static double len3(const float v[3]) { return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]); }

/* (d) every record finite, inside the bounds, unit normal/wi on one side,
 * footprint radius >= both axes. */
static void check_records(const pb_scene *s, const traced *t, const char *what) {
  uint32_t bad = 0, outside = 0;
  for (uint32_t i = 0; i < t->n; ++i) {
    const pb_gpu_photon *p = &t->ph[i];
    int ok = finite3(p->position) && finite3(p->power) && finite3(p->wi) && finite3(p->normal) &&
             finite3(p->axis_u) && finite3(p->axis_v) && isfinite(p->radius) && isfinite(p->normal_extent);
    ok = ok && fabs(len3(p->normal) - 1) < 1e-3 && fabs(len3(p->wi) - 1) < 1e-3 &&
         p->normal[0] * p->wi[0] + p->normal[1] * p->wi[1] + p->normal[2] * p->wi[2] >= -1e-4f;
    ok = ok && p->radius > 0 && p->radius >= len3(p->axis_u) * 0.999 && p->radius >= len3(p->axis_v) * 0.999 &&
         p->normal_extent >= 0 && p->normal_extent <= p->radius * 1.001f;
    ok = ok && p->power[0] >= 0 && p->power[1] >= 0 && p->power[2] >= 0;
    if (!ok) bad++;
    for (int c = 0; c < 3; ++c) {
      float e = 1e-4f * (1 + fabsf(s->bounds_max[c] - s->bounds_min[c]));
      if (!(p->position[c] >= s->bounds_min[c] - e && p->position[c] <= s->bounds_max[c] + e)) {
        outside++;
        break;
      }
    }
  }
  printf("%s: %u records, %u invalid, %u outside the bounds, %u guarded\n", what, t->n, bad, outside,
         t->st.guarded);
  CHECK_EQ_INT(bad, 0);
  CHECK_EQ_INT(outside, 0);
}

#endif
