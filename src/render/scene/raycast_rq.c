/* The ray-query twin of raycast.c (shaders/scene/raycast_rq.comp):
 * closest hit or occlusion for a batch of rays through VK_KHR_ray_query on
 * the scene's acceleration structures (gpu/accel.c), on a device that has
 * them (pb_gpu_limits.ray_query); the tests compare it with the GLSL BVH. */
#include <string.h>

#include "core/log.h"
#include "render/render.h"
#include "shaders/raycast_rq.spv.h"

void pb_raycast_rq_destroy(pb_gpu *g, pb_raycast_rq_pass *p) {
  if (!p) return;
  pb_raycast_destroy(g, &p->pass);
  pb_gpu_accel_destroy(g, &p->accel);
  memset(p, 0, sizeof *p);
}

pb_result pb_raycast_rq_create(pb_gpu *g, const pb_scene *s, uint32_t capacity, pb_raycast_rq_pass *p) {
  memset(p, 0, sizeof *p);
  if (capacity == 0) return pb_fail(PB_ERR_USAGE, "raycast_rq: capacity 0");
  if (!pb_gpu_get_limits(g)->ray_query)
    return pb_fail(PB_ERR_NOT_AVAILABLE, "raycast_rq: %s has no ray queries (VK_KHR_ray_query); "
                   "see 'photonbridge info --devices'", pb_gpu_device_name(g));
  pb_gpu_accel_desc ad = {
      .name = "raycast_rq.scene",
      .positions = &s->positions[0][0],
      .vertex_count = s->vertex_count,
      .indices = &s->triangles[0][0],
      .triangle_count = s->triangle_count,
      .updatable = 1, /* the tests refit it (pb_gpu_accel_update) */
  };
  pb_result r = pb_gpu_accel_create(g, &ad, &p->accel);
  if (r != PB_OK) goto fail;
  pb_gpu_pipeline_desc pd = {
      .name = "raycast_rq",
      .spirv = pb_spv_raycast_rq,
      .spirv_bytes = sizeof pb_spv_raycast_rq,
      .binding_count = PB_RAYCAST_RQ_BIND_COUNT,
      .accel_bindings = 1u << PB_RAYCAST_RQ_BIND_TLAS,
      .push_bytes = sizeof(pb_gpu_raycast_push),
  };
  r = pb_gpu_pipeline_create(g, &pd, &p->pass.pipe);
  if (r != PB_OK) goto fail;
  r = pb_raycast_buffers_create(g, "raycast_rq", capacity, &p->pass);
  if (r != PB_OK) goto fail;
  const pb_gpu_buffer *b[PB_RAYCAST_RQ_BIND_COUNT] = {[PB_RAYCAST_RQ_BIND_RAYS] = &p->pass.rays,
                                                      [PB_RAYCAST_RQ_BIND_HITS] = &p->pass.hits};
  r = pb_gpu_pipeline_bind(g, &p->pass.pipe, b, PB_RAYCAST_RQ_BIND_COUNT);
  if (r == PB_OK) r = pb_gpu_pipeline_bind_accel(g, &p->pass.pipe, PB_RAYCAST_RQ_BIND_TLAS, &p->accel);
  if (r != PB_OK) goto fail;
  return PB_OK;
fail:
  pb_raycast_rq_destroy(g, p);
  return r;
}

pb_result pb_raycast_rq_run(pb_gpu *g, pb_raycast_rq_pass *p, const pb_gpu_ray *rays, uint32_t n, int any_hit,
                            pb_gpu_hit *hits, double *gpu_ms) {
  return pb_raycast_run(g, &p->pass, rays, n, any_hit, hits, gpu_ms);
}
