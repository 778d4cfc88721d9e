/* Motion vectors (motion.h). */
#include "render/scene/motion.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/camera.h"
#include "render/scene/passes.h"
#include "shaders/motion.spv.h"
#include "shaders/motion_rq.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_filter.h"

int pb_camera_project(const pb_camera *c, uint32_t width, uint32_t height, const float p[3], float *x, float *y,
                      float *depth) {
  pb_gpu_camera v;
  pb_camera_view(c, width, height, &v);
  return pb_camera_view_project(&v, p, x, y, depth);
}

void pb_camera_primary_rays(const pb_camera *c, uint32_t width, uint32_t height, size_t first, uint32_t count,
                            pb_gpu_ray *rays) {
  pb_gpu_camera v;
  pb_camera_view(c, width, height, &v);
  for (uint32_t i = 0; i < count; ++i) {
    size_t pix = first + i;
    float t0;
    pb_camera_ray(&v, (float)(pix % width) + 0.5f, (float)(pix / width) + 0.5f, rays[i].org, rays[i].dir, &t0,
                  &rays[i].tmax);
    rays[i].tmin = 0.0f;
  }
}

struct pb_motion_pass {
  uint32_t width, height, vertex_count;
  pb_gpu_pipeline pipe;
  pb_gpu_buffer params, prev, motion;
};

void pb_motion_pass_destroy(pb_gpu *g, pb_motion_pass *m) {
  if (!m) return;
  pb_gpu_pipeline_destroy(g, &m->pipe);
  pb_gpu_buffer_destroy(g, &m->params);
  pb_gpu_buffer_destroy(g, &m->prev);
  pb_gpu_buffer_destroy(g, &m->motion);
  free(m);
}

pb_result pb_motion_pass_create(pb_gpu *g, uint32_t width, uint32_t height, uint32_t vertex_count,
                                pb_motion_pass **out) {
  *out = NULL;
  pb_motion_pass *m = calloc(1, sizeof *m);
  if (!m) return pb_fail(PB_ERR_NOMEM, "motion vectors: out of memory");
  m->width = width, m->height = height, m->vertex_count = vertex_count;
  pb_gpu_buffer_desc pd = {.name = "motion.params", .size = sizeof(pb_gpu_motion_params), .host_visible = 1};
  pb_gpu_buffer_desc vd = {.name = "motion.prev_positions", .size = (uint64_t)(vertex_count ? vertex_count : 1) * 12};
  pb_gpu_buffer_desc md = {.name = "motion.vectors", .size = (uint64_t)width * height * 4 * sizeof(float),
                           .host_visible = 1, .readback = 1};
  /* The ray-query build on a device with ray queries, where every GPU
   * scene has its acceleration structure (render.h pb_gpu_scene_accel). */
  static const pb_kernel_builds k = PB_KERNEL_BUILDS_GLTF(motion);
  pb_gpu_pipeline_desc pl = {.name = "pass.motion", .binding_count = PB_MOTION_BIND_COUNT};
  pb_kernel_select(&pl, &k, 0, pb_gpu_get_limits(g)->ray_query, PB_MOTION_BIND_NODES);
  pb_result r;
  if ((r = pb_gpu_buffer_create(g, &pd, &m->params)) != PB_OK || (r = pb_gpu_buffer_create(g, &vd, &m->prev)) != PB_OK ||
      (r = pb_gpu_buffer_create(g, &md, &m->motion)) != PB_OK || (r = pb_gpu_pipeline_create(g, &pl, &m->pipe)) != PB_OK) {
    pb_motion_pass_destroy(g, m);
    return r;
  }
  *out = m;
  return PB_OK;
}

pb_result pb_motion_pass_prepare(pb_gpu *g, pb_motion_pass *m, const pb_scene *s, const pb_gpu_scene *gs,
                                 const float (*prev_positions)[3], const pb_camera *cam, const pb_camera *prev_cam) {
  if (s->vertex_count != m->vertex_count)
    return pb_fail(PB_ERR_USAGE, "motion vectors: scene of %u vertices, pass made for %u", s->vertex_count,
                   m->vertex_count);
  pb_gpu_motion_params p;
  memset(&p, 0, sizeof p);
  pb_camera_view(cam, m->width, m->height, &p.cam);
  pb_camera_view(prev_cam, m->width, m->height, &p.prev);
  p.width = m->width, p.height = m->height, p.triangle_count = s->triangle_count;
  pb_result r = pb_gpu_buffer_upload(g, &m->params, 0, &p, sizeof p);
  /* Geometry that did not move: the scene's own positions are the previous ones. */
  const pb_gpu_buffer *prev = &gs->positions;
  if (r == PB_OK && prev_positions && s->vertex_count) {
    r = pb_gpu_buffer_upload(g, &m->prev, 0, prev_positions, (uint64_t)s->vertex_count * 12);
    prev = &m->prev;
  }
  if (r != PB_OK) return r;
  const pb_gpu_buffer *b[PB_MOTION_BIND_COUNT] = {
      [PB_MOTION_BIND_NODES] = &gs->nodes,   [PB_MOTION_BIND_TRIS] = &gs->tris,
      [PB_MOTION_BIND_INDICES] = &gs->indices, [PB_MOTION_BIND_PREV_POSITIONS] = prev,
      [PB_MOTION_BIND_PARAMS] = &m->params,  [PB_MOTION_BIND_MOTION] = &m->motion};
  return pb_kernel_bind(g, &m->pipe, b, PB_MOTION_BIND_COUNT, pb_gpu_scene_accel(gs));
}

pb_result pb_motion_pass_record(pb_gpu *g, pb_motion_pass *m) {
  return pb_gpu_dispatch(g, &m->pipe, NULL, (uint64_t)m->width * m->height);
}

const pb_gpu_buffer *pb_motion_pass_output(const pb_motion_pass *m) { return &m->motion; }

pb_result pb_motion_pass_run(pb_gpu *g, pb_motion_pass *m, const pb_scene *s, const pb_gpu_scene *gs,
                             const float (*prev_positions)[3], const pb_camera *cam, const pb_camera *prev_cam,
                             float *motion, double *gpu_ms) {
  if (gpu_ms) *gpu_ms = 0;
  pb_result r = pb_motion_pass_prepare(g, m, s, gs, prev_positions, cam, prev_cam);
  if (r != PB_OK) return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_motion_pass_record(g, m);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, 1);
  pb_result rs = pb_gpu_submit(g);
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  if (gpu_ms) {
    double ms = pb_gpu_elapsed_ms(g, 0, 1);
    *gpu_ms = ms > 0 ? ms : 0;
  }
  return pb_gpu_buffer_download(g, &m->motion, 0, motion, (uint64_t)m->width * m->height * 4 * sizeof(float));
}

pb_result pb_motion_vectors(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const float (*prev_positions)[3],
                            const pb_camera *cam, const pb_camera *prev_cam, uint32_t width, uint32_t height,
                            float *motion, double *gpu_ms) {
  pb_motion_pass *m;
  pb_result r = pb_motion_pass_create(g, width, height, s->vertex_count, &m);
  if (r != PB_OK) return r;
  r = pb_motion_pass_run(g, m, s, gs, prev_positions, cam, prev_cam, motion, gpu_ms);
  pb_motion_pass_destroy(g, m);
  return r;
}
