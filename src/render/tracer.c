/* The photon tracer interface (tracer.h): a table of operations per
 * implementation, the BVH tracer here and the images tracer in
 * tracer_images.c. */
#include "render/tracer.h"

#include <stdlib.h>
#include <string.h>

#include "render/tracer_internal.h"

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

pb_photon_tracer *pb_tracer_photon(const pb_tracer *t) { return t ? t->photon : NULL; }
pb_image_maps *pb_tracer_image_maps(const pb_tracer *t) { return t ? t->maps : NULL; }

void pb_tracer_destroy(pb_gpu *g, pb_tracer *t) {
  if (!t) return;
  t->ops->destroy(g, t);
  pb_photon_tracer_destroy(g, t->photon);
  pb_image_maps_destroy(g, t->maps);
  free(t);
}
