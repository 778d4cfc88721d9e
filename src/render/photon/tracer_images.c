/* The image-space photon tracer (tracer.h; seed 003): the photon tracer's
 * kernel built with the environment-map search (photon_trace_images), over
 * maps that follow the scene (image_maps.h). */
#include <string.h>

#include "render/photon/tracer_internal.h"

static pb_result images_update(pb_gpu *g, pb_tracer *t, const pb_scene *s) {
  pb_result r = pb_photon_tracer_update(g, t->photon, s);
  return r != PB_OK ? r : pb_image_maps_update(g, t->maps, s);
}

static uint32_t images_stats(const pb_tracer *t, pb_tracer_stat *out, uint32_t max) {
  pb_gpu_image_counts c;
  pb_photon_tracer_image_counts(t->photon, &c);
  pb_image_maps_stats ms;
  pb_image_maps_get_stats(t->maps, &ms);
  pb_photon_trace_stats ps;
  pb_photon_tracer_stats(t->photon, &ps);
  double cov = ms.coverage_m2 + ms.uncovered_m2;
  /* summed: counts of one trace, added over a frame's photon maps */
  pb_tracer_stat all[] = {
      {"image_segments", c.segments, 1},
      {"image_hits", c.hits, 1},
      {"image_misses", c.misses, 1},
      {"image_escapes", c.escapes, 1},
      {"image_type_b", c.type_b, 1},
      {"image_type_c", c.type_c, 1},
      {"escaped", ps.escaped, 1},
      {"absorbed", ps.absorbed, 1},
      {"maps", ms.count, 0},
      {"map_resolution", ms.resolution, 0},
      {"candidates", ms.candidates, 0},
      {"map_renders", ms.map_renders, 0},
      {"maps_rendered", ms.maps_rendered, 0},
      {"map_renders_skipped", ms.renders_skipped, 0},
      {"selections", ms.selections, 0},
      {"swaps", ms.swaps, 0},
      {"map_render_ms", ms.render_ms, 0},
      {"select_ms", ms.select_ms, 0},
      {"uncovered_share", cov > 0.0 ? ms.uncovered_m2 / cov : 0.0, 0},
  };
  uint32_t n = sizeof all / sizeof all[0];
  if (n > max) n = max;
  memcpy(out, all, n * sizeof *out);
  return n;
}

static void images_destroy(pb_gpu *g, pb_tracer *t) { (void)g, (void)t; }

static const pb_tracer_ops images_ops = {"images", images_update, images_stats, images_destroy};

pb_result pb_tracer_images_init(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_image_maps_desc *d,
                                pb_tracer *t) {
  pb_result r = pb_image_maps_create(g, s, gs, d, &t->maps);
  if (r != PB_OK) return r;
  if ((r = pb_photon_tracer_use_image_maps(g, t->photon, t->maps)) != PB_OK) return r;
  t->ops = &images_ops;
  return PB_OK;
}
