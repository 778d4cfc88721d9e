/* The frame context (render.h): the frames of a sequence reuse one frame's
 * pipelines, buffers, photon tracer and estimator, updated to each new pose.
 * A frame rendered through a context must equal the same frame rendered
 * from scratch: for a moving point light (cornell_box_moving_light), moving
 * geometry with caustics (cornell_caustics_moving_sphere), with the RSM
 * first bounce (its maps made again per pose), and a context whose settings
 * change (rebuilt, not reused wrongly). */
#include <math.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/photon/photon.h"
#include "render/render.h"

static double max_diff(const pb_render_result *a, const pb_render_result *b) {
  double m = 0;
  size_t n = (size_t)a->width * a->height * 4;
  for (size_t i = 0; i < n; ++i) {
    double d = fabs((double)a->beauty[i] - b->beauty[i]) / (fabs((double)b->beauty[i]) + 1e-3);
    if (d > m) m = d;
  }
  return m;
}

static void sequence(pb_gpu *g, const char *path, uint32_t first_bounce) {
  pb_scene s;
  pb_load_desc ld = {0};
  CHECK_EQ_INT(pb_scene_load(path, &ld, &s), PB_OK);
  CHECK(s.anim != NULL);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_frame_context *ctx = NULL;
  CHECK_EQ_INT(pb_frame_context_create(&ctx), PB_OK);
  double worst = 0;
  for (int f = 0; f < 3; ++f) {
    CHECK_EQ_INT(pb_scene_set_time(&s, 0.5 * f), PB_OK);
    CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_AUTO, NULL), PB_OK);
    pb_render_desc d = {.spp = 2, .photons = 8192, .iterations = 2, .seed = 11u + (uint64_t)f,
                        .first_bounce = first_bounce};
    pb_render_result fresh, reused;
    CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, 40, 40, &d, &fresh), PB_OK);
    pb_render_io io = {.context = ctx};
    CHECK_EQ_INT(pb_render_frame_io(g, &s, &gs, 0, 40, 40, &d, &io, &reused), PB_OK);
    double m = max_diff(&reused, &fresh);
    if (m > worst) worst = m;
    CHECK(reused.stats.photons_stored == fresh.stats.photons_stored);
    pb_render_result_destroy(&fresh);
    pb_render_result_destroy(&reused);
  }
  printf("%s (%s first bounce): 3 poses through one context, largest relative difference from fresh frames %.2e\n",
         path, first_bounce == PB_FIRST_BOUNCE_RSM ? "RSM" : "traced", worst);
  CHECK(worst < 1e-4);
  /* Other settings: the context is rebuilt, and the frame still matches. */
  pb_render_desc d = {.spp = 1, .photons = 4096, .seed = 5};
  pb_render_io io = {.context = ctx};
  pb_render_result a, b;
  CHECK_EQ_INT(pb_render_frame_io(g, &s, &gs, 0, 24, 32, &d, &io, &a), PB_OK);
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, 24, 32, &d, &b), PB_OK);
  CHECK(a.width == 24 && a.height == 32 && max_diff(&a, &b) < 1e-4);
  pb_render_result_destroy(&a);
  pb_render_result_destroy(&b);
  pb_frame_context_destroy(g, ctx);
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
}

int main(void) {
  PBT_GPU_OPEN(g);
  sequence(g, "samples/cornell_box_moving_light/cornell_box_moving_light.gltf", PB_FIRST_BOUNCE_TRACE);
  sequence(g, "samples/cornell_caustics_moving_sphere/cornell_caustics_moving_sphere.gltf", PB_FIRST_BOUNCE_TRACE);
  sequence(g, "samples/cornell_box_moving_light/cornell_box_moving_light.gltf", PB_FIRST_BOUNCE_RSM);
  pb_gpu_destroy(g);
  return pbt_done();
}
