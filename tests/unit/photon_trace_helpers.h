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

#include "gpu_scene_helpers.h"
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

/* (a) energy: a closed Lambert box of albedo rho = 0.6 with a point light
 * of 2 cd inside, 60,000 paths of 4 bounces from `first_bounce`
 * (pb_photon_first_bounce): the stored flux at bounce k is Phi rho^k
 * (within 4 %), nothing at bounce 0 (direct light), nothing escapes, no
 * caustic record, every record valid. `what` prefixes the lines printed. */
static void check_box_energy(pb_gpu *g, uint32_t first_bounce, const char *what) {
  static tscene t;
  const float rho = 0.6f, I = 2.0f;
  box(&t, rho);
  float w[3] = {1, 1, 1};
  add_point(&t, 0.13f, -0.21f, 0.07f, I, w);
  finish(&t);
  pb_photon_trace_desc d = {.photons = 60000, .max_bounces = 4, .first_bounce = first_bounce};
  traced tr;
  if (!trace(g, &t.s, &d, 7, 0, 0, 0, 0, &tr)) return;
  double sum[8] = {0};
  uint32_t cnt[8] = {0};
  for (uint32_t i = 0; i < tr.n; ++i) {
    uint32_t b = bounce_of(&tr.ph[i]);
    if (b < 8) sum[b] += tr.ph[i].power[0], cnt[b]++;
  }
  double phi = 4 * M_PI * I;
  CHECK_EQ_INT(cnt[0], 0); /* the first hit is direct light */
  CHECK_EQ_INT(tr.map.emitted, 60000);
  CHECK_EQ_INT(tr.map.overflow, 0);
  CHECK_EQ_INT(tr.st.escaped, 0); /* closed box */
  CHECK_EQ_INT(tr.map.caustic, 0);
  for (int k = 1; k <= 4; ++k) {
    double want = phi * pow(rho, k);
    printf("%s: bounce %d: %u photons, flux %.5f W, expected Phi rho^k = %.5f W (%+.2f %%)\n", what, k, cnt[k],
           sum[k], want, 100 * (sum[k] / want - 1));
    CHECK_NEAR(sum[k], want, 0.04 * want);
  }
  char label[64];
  snprintf(label, sizeof label, "%s box", what);
  check_records(&t.s, &tr, label);
  release(g, &tr);
}

#endif
