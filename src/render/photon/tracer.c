/* The photon tracer interface (tracer.h): a table of operations per
 * implementation, the BVH tracer here and the images tracer in
 * tracer_images.c. */
#include "render/photon/tracer.h"

#include <stdlib.h>
#include <string.h>

#include "render/photon/tracer_internal.h"

const char *const pb_tracer_names[] = {"bvh", "images", NULL};

/* ---- bvh: photon_trace.c unchanged ---------------------------------------- */

static pb_result bvh_update(pb_gpu *g, pb_tracer *t, const pb_scene *s) {
  return pb_photon_tracer_update(g, t->photon, s);
}

static uint32_t bvh_stats(const pb_tracer *t, pb_tracer_stat *out, uint32_t max) {
  pb_photon_trace_stats ps;
  pb_photon_tracer_stats(t->photon, &ps);
  pb_tracer_stat all[] = {{"escaped", ps.escaped, 1}, {"absorbed", ps.absorbed, 1}};
  uint32_t n = sizeof all / sizeof all[0];
  if (n > max) n = max;
  memcpy(out, all, n * sizeof *out);
  return n;
}

static void bvh_destroy(pb_gpu *g, pb_tracer *t) { (void)g, (void)t; }

static const pb_tracer_ops bvh_ops = {"bvh", bvh_update, bvh_stats, bvh_destroy};

/* ---- the interface --------------------------------------------------------- */

pb_result pb_tracer_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_tracer_desc *desc,
                           pb_tracer **out) {
  *out = NULL;
  pb_tracer_desc d = desc ? *desc : (pb_tracer_desc){0};
  if (d.kind > PB_TRACER_IMAGES) return pb_fail(PB_ERR_USAGE, "photons: tracer %u (bvh or images)", d.kind);
  pb_tracer *t = calloc(1, sizeof *t);
  if (!t) return pb_fail(PB_ERR_NOMEM, "photons: out of memory");
  t->ops = &bvh_ops;
  pb_result r = pb_photon_tracer_create(g, s, gs, &d.photon, &t->photon);
  if (r == PB_OK && d.kind == PB_TRACER_IMAGES) r = pb_tracer_images_init(g, s, gs, &d.images, t);
  if (r != PB_OK) {
    pb_tracer_destroy(g, t);
    return r;
  }
  *out = t;
  return PB_OK;
}

pb_result pb_tracer_update(pb_gpu *g, pb_tracer *t, const pb_scene *s) { return t->ops->update(g, t, s); }

pb_result pb_tracer_trace(pb_gpu *g, pb_tracer *t, uint64_t seed, uint32_t iteration, pb_photon_map *map,
                          double *gpu_ms) {
  return pb_photon_tracer_run(g, t->photon, seed, iteration, map, gpu_ms);
}

pb_result pb_tracer_prepare(pb_gpu *g, pb_tracer *t, uint64_t seed, uint32_t iteration, pb_photon_map *map) {
  return pb_photon_tracer_prepare(g, t->photon, seed, iteration, map);
}
pb_result pb_tracer_record(pb_gpu *g, pb_tracer *t, uint32_t ts_slot) {
  return pb_photon_tracer_record(g, t->photon, ts_slot);
}
pb_result pb_tracer_finish(pb_gpu *g, pb_tracer *t, pb_photon_map *map, uint32_t ts_slot, double *gpu_ms) {
  return pb_photon_tracer_finish(g, t->photon, map, ts_slot, gpu_ms);
}

const char *pb_tracer_name(const pb_tracer *t) { return t ? t->ops->name : "none"; }

uint32_t pb_tracer_stats(const pb_tracer *t, pb_tracer_stat *out, uint32_t max) {
  return t ? t->ops->stats(t, out, max) : 0;
}

void pb_tracer_stats_merge(pb_tracer_stat *list, uint32_t *count, const pb_tracer_stat *now, uint32_t n,
                           int last_only) {
  for (uint32_t i = 0; i < n; ++i) {
    if (last_only && now[i].summed) continue;
    uint32_t j = 0;
    while (j < *count && strcmp(list[j].name, now[i].name)) ++j;
    if (j < *count) list[j].value = now[i].summed ? list[j].value + now[i].value : now[i].value;
    else if (*count < PB_TRACER_MAX_STATS) list[(*count)++] = now[i];
  }
}

float pb_tracer_r_max(const pb_tracer *t) {
  pb_photon_trace_stats ps;
  pb_photon_tracer_stats(t->photon, &ps);
  return ps.r_max;
}

void pb_tracer_stats_add(const pb_tracer *t, pb_render_stats *st) {
  pb_photon_trace_stats ps;
  pb_photon_tracer_stats(t->photon, &ps);
  st->photon_guarded += ps.guarded;
  pb_tracer_stat now[PB_TRACER_MAX_STATS];
  uint32_t n = pb_tracer_stats(t, now, PB_TRACER_MAX_STATS);
  st->tracer = pb_tracer_name(t);
  pb_tracer_stats_merge(st->tracer_stats, &st->tracer_stat_count, now, n, 0);
}

/* Seed 000 Table 3: PB_RENDER_RADIUS_BINS - 1 bins below the clamp, the
 * last one at it. */
pb_result pb_tracer_radius_histogram(pb_gpu *g, pb_tracer *t, const pb_photon_map *m, pb_render_stats *st) {
  pb_photon_trace_stats ts;
  pb_photon_tracer_stats(t->photon, &ts);
  uint32_t n = m->stored < m->capacity ? m->stored : m->capacity;
  st->radius_histogram = 1;
  st->radius_r_max = ts.r_max;
  st->scene_radius = ts.scene_radius;
  if (n == 0 || !(ts.r_max > 0.0f)) return PB_OK;
  if (n > t->hist_cap) {
    pb_gpu_photon *p = realloc(t->hist, (size_t)n * sizeof *p);
    if (!p) return pb_fail(PB_ERR_NOMEM, "render: out of memory for the radius histogram (%u photons)", n);
    t->hist = p, t->hist_cap = n;
  }
  pb_gpu_photon *p = t->hist;
  pb_result r = pb_gpu_buffer_download(g, &m->photons, 0, p, (uint64_t)n * sizeof *p);
  if (r != PB_OK) return r;
  const int below = PB_RENDER_RADIUS_BINS - 1;
  for (uint32_t i = 0; i < n; ++i) {
    double x = p[i].radius / ts.r_max;
    int b = below; /* at the clamp */
    if (x < 1.0 - 1e-5) {
      b = x > 0 ? (int)(x * below) : 0;
      if (b > below - 1) b = below - 1;
    }
    st->radius_hist[b]++;
  }
  return PB_OK;
}
pb_image_maps *pb_tracer_image_maps(const pb_tracer *t) { return t ? t->maps : NULL; }

void pb_tracer_destroy(pb_gpu *g, pb_tracer *t) {
  if (!t) return;
  t->ops->destroy(g, t);
  pb_photon_tracer_destroy(g, t->photon);
  pb_image_maps_destroy(g, t->maps);
  free(t->hist);
  free(t);
}
