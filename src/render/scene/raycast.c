/* The ray-query pass (shaders/scene/raycast.comp): closest hit or occlusion for a
 * batch of rays; used by the tests against Embree and by the benchmark. */
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "render/render.h"
#include "shaders/raycast.spv.h"

void pb_raycast_destroy(pb_gpu *g, pb_raycast_pass *p) {
  if (!p) return;
  pb_gpu_pipeline_destroy(g, &p->pipe);
  pb_gpu_buffer_destroy(g, &p->rays);
  pb_gpu_buffer_destroy(g, &p->hits);
  memset(p, 0, sizeof *p);
}

pb_result pb_raycast_buffers_create(pb_gpu *g, const char *name, uint32_t capacity, pb_raycast_pass *p) {
  char rn[64], hn[64];
  snprintf(rn, sizeof rn, "%s.rays", name);
  snprintf(hn, sizeof hn, "%s.hits", name);
  pb_gpu_buffer_desc rd = {.name = rn, .size = (uint64_t)capacity * sizeof(pb_gpu_ray)};
  pb_result r = pb_gpu_buffer_create(g, &rd, &p->rays);
  if (r != PB_OK) return r;
  pb_gpu_buffer_desc hd = {.name = hn, .size = (uint64_t)capacity * sizeof(pb_gpu_hit), .host_visible = 1};
  r = pb_gpu_buffer_create(g, &hd, &p->hits);
  if (r == PB_OK) p->capacity = capacity;
  return r;
}

pb_result pb_raycast_create(pb_gpu *g, const pb_gpu_scene *gs, uint32_t capacity, pb_raycast_pass *p) {
  memset(p, 0, sizeof *p);
  if (capacity == 0) return pb_fail(PB_ERR_USAGE, "raycast: capacity 0");
  pb_gpu_pipeline_desc pd = {
      .name = "raycast",
      .spirv = pb_spv_raycast,
      .spirv_bytes = sizeof pb_spv_raycast,
      .binding_count = PB_RAYCAST_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_raycast_push),
  };
  pb_result r = pb_gpu_pipeline_create(g, &pd, &p->pipe);
  if (r != PB_OK) goto fail;
  r = pb_raycast_buffers_create(g, "raycast", capacity, p);
  if (r != PB_OK) goto fail;
  const pb_gpu_buffer *b[PB_RAYCAST_BIND_COUNT] = {[PB_RAYCAST_BIND_NODES] = &gs->nodes, [PB_RAYCAST_BIND_TRIS] = &gs->tris,
                                                [PB_RAYCAST_BIND_RAYS] = &p->rays, [PB_RAYCAST_BIND_HITS] = &p->hits};
  r = pb_gpu_pipeline_bind(g, &p->pipe, b, PB_RAYCAST_BIND_COUNT);
  if (r != PB_OK) goto fail;
  return PB_OK;
fail:
  pb_raycast_destroy(g, p);
  return r;
}

pb_result pb_raycast_run(pb_gpu *g, pb_raycast_pass *p, const pb_gpu_ray *rays, uint32_t n, int any_hit,
                         pb_gpu_hit *hits, double *gpu_ms) {
  if (n > p->capacity)
    return pb_fail(PB_ERR_LIMIT, "raycast: %u rays exceed the pass's capacity of %u", n, p->capacity);
  if (gpu_ms) *gpu_ms = -1.0;
  if (n == 0) return PB_OK;
  pb_result r = pb_gpu_buffer_upload(g, &p->rays, 0, rays, (uint64_t)n * sizeof *rays);
  if (r != PB_OK) return r;
  pb_gpu_raycast_push push = {.ray_count = n, .any_hit = any_hit ? 1u : 0u};
  r = pb_gpu_begin(g);
  if (r != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_gpu_dispatch(g, &p->pipe, &push, n);
  pb_gpu_timestamp(g, 1);
  if (r != PB_OK) {
    pb_gpu_submit(g);
    return r;
  }
  double t0 = pb_time_now();
  r = pb_gpu_submit(g);
  double wall = (pb_time_now() - t0) * 1e3;
  if (r != PB_OK) return r;
  if (gpu_ms) {
    double ms = pb_gpu_elapsed_ms(g, 0, 1);
    *gpu_ms = ms >= 0 ? ms : wall;
  }
  return pb_gpu_buffer_download(g, &p->hits, 0, hits, (uint64_t)n * sizeof *hits);
}
