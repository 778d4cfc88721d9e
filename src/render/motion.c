/* Motion vectors (motion.h). */
#include "render/motion.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CHUNK = 1u << 20 }; /* rays per raycast submission */

int pb_camera_project(const pb_camera *c, uint32_t width, uint32_t height, const float p[3], float *x, float *y,
                      float *depth) {
  float d[3] = {p[0] - c->position[0], p[1] - c->position[1], p[2] - c->position[2]};
  float z = d[0] * c->forward[0] + d[1] * c->forward[1] + d[2] * c->forward[2];
  if (!(z > 0.0f)) return 0;
  /* The inverse of gbuffer.comp's camera ray: sx = (2 x / W - 1) tan_x,
   * sy = (1 - 2 y / H) tan_y, tan_x = tan_y W / H. */
  float tan_y = tanf(0.5f * c->yfov), tan_x = tan_y * (float)width / (float)height;
  float sx = (d[0] * c->right[0] + d[1] * c->right[1] + d[2] * c->right[2]) / z;
  float sy = (d[0] * c->up[0] + d[1] * c->up[1] + d[2] * c->up[2]) / z;
  *x = 0.5f * (sx / tan_x + 1.0f) * (float)width;
  *y = 0.5f * (1.0f - sy / tan_y) * (float)height;
  *depth = z;
  return isfinite(*x) && isfinite(*y);
}

void pb_camera_primary_rays(const pb_camera *c, uint32_t width, uint32_t height, size_t first, uint32_t count,
                            pb_gpu_ray *rays) {
  float tan_y = tanf(0.5f * c->yfov), tan_x = tan_y * (float)width / (float)height;
  for (uint32_t i = 0; i < count; ++i) {
    size_t pix = first + i;
    float fx = (float)(pix % width) + 0.5f, fy = (float)(pix / width) + 0.5f;
    float sx = (2.0f * fx / (float)width - 1.0f) * tan_x, sy = (1.0f - 2.0f * fy / (float)height) * tan_y;
    float d[3], len = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = c->forward[k] + c->right[k] * sx + c->up[k] * sy;
      len += d[k] * d[k];
    }
    len = sqrtf(len);
    for (int k = 0; k < 3; ++k) {
      rays[i].org[k] = c->position[k];
      rays[i].dir[k] = d[k] / len;
    }
    rays[i].tmin = 0.0f;
    rays[i].tmax = INFINITY;
  }
}

pb_result pb_motion_vectors(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const float (*prev_positions)[3],
                            const pb_camera *cam, const pb_camera *prev_cam, uint32_t width, uint32_t height,
                            float *motion, double *gpu_ms) {
  size_t n = (size_t)width * height;
  if (gpu_ms) *gpu_ms = 0;
  uint32_t cap = n < CHUNK ? (uint32_t)n : CHUNK;
  pb_raycast_pass rc;
  pb_result r = pb_raycast_create(g, gs, cap, &rc);
  if (r != PB_OK) return r;
  pb_gpu_ray *rays = malloc((size_t)cap * sizeof *rays);
  pb_gpu_hit *hits = malloc((size_t)cap * sizeof *hits);
  if (!rays || !hits) {
    r = pb_fail(PB_ERR_NOMEM, "motion vectors: out of memory for %ux%u pixels", width, height);
    goto done;
  }
  const float (*pp)[3] = prev_positions ? prev_positions : (const float (*)[3])s->positions;
  for (size_t base = 0; base < n; base += cap) {
    uint32_t m = n - base < cap ? (uint32_t)(n - base) : cap;
    pb_camera_primary_rays(cam, width, height, base, m, rays);
    double ms = 0;
    if ((r = pb_raycast_run(g, &rc, rays, m, 0, hits, &ms)) != PB_OK) goto done;
    if (gpu_ms) *gpu_ms += ms > 0 ? ms : 0;
    for (uint32_t i = 0; i < m; ++i) {
      float *mv = motion + 4 * (base + i);
      memset(mv, 0, 4 * sizeof *mv);
      const pb_gpu_hit *h = &hits[i];
      if (h->prim == PB_GPU_MISS || h->prim >= s->triangle_count) continue;
      const uint32_t *tri = s->triangles[h->prim];
      float b0 = 1.0f - h->u - h->v, p[3];
      for (int k = 0; k < 3; ++k) p[k] = b0 * pp[tri[0]][k] + h->u * pp[tri[1]][k] + h->v * pp[tri[2]][k];
      float x, y, z;
      if (!pb_camera_project(prev_cam, width, height, p, &x, &y, &z)) continue;
      size_t pix = base + i;
      mv[0] = x - ((float)(pix % width) + 0.5f);
      mv[1] = y - ((float)(pix / width) + 0.5f);
      mv[2] = z;
      mv[3] = 1.0f;
    }
  }
done:
  free(rays);
  free(hits);
  pb_raycast_destroy(g, &rc);
  return r;
}
