/* Code-built scenes for the GPU unit tests: a fixed-capacity scene of quads,
 * Lambert/metal materials and point lights, finalised into a pb_scene
 * (finish: no camera; finish_with_camera: one). Shared by
 * test_gpu_photon_trace, test_gpu_photon_rsm, test_gpu_image_tracer and
 * test_gpu_knn. */
#ifndef PB_TEST_GPU_SCENE_HELPERS_H
#define PB_TEST_GPU_SCENE_HELPERS_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "scene/scene.h"

enum { MAXV = 64, MAXT = 32, MAXM = 4, MAXL = 4 };
typedef struct tscene {
  float pos[MAXV][3], nrm[MAXV][3], uv[MAXV][2];
  uint32_t tri[MAXT][3], tm[MAXT];
  uint32_t nv, nt;
  pb_material mat[MAXM];
  uint32_t nm;
  pb_light light[MAXL];
  uint32_t nl;
  pb_camera cam; /* finish_with_camera's */
  pb_scene s;
} tscene;

static inline uint32_t add_mat(tscene *t, float rho, float metallic) {
  pb_material *m = &t->mat[t->nm];
  memset(m, 0, sizeof *m);
  m->base_color[0] = m->base_color[1] = m->base_color[2] = rho;
  m->base_color[3] = 1;
  m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
  m->metallic = metallic;
  m->roughness = metallic > 0 ? 0.0f : 1.0f;
  m->specular = 0; /* pure Lambert for the non-metals */
  m->ior = 1.5f;
  return t->nm++;
}

/* Quad a, b, c, d (counter-clockwise seen from the side n points to). */
static inline void add_quad(tscene *t, const float q[4][3], const float n[3], uint32_t mat) {
  uint32_t b = t->nv;
  for (int i = 0; i < 4; ++i) {
    memcpy(t->pos[b + i], q[i], sizeof t->pos[0]);
    memcpy(t->nrm[b + i], n, sizeof t->nrm[0]);
  }
  t->nv += 4;
  uint32_t a[2][3] = {{b, b + 1, b + 2}, {b, b + 2, b + 3}};
  for (int i = 0; i < 2; ++i) {
    memcpy(t->tri[t->nt], a[i], sizeof a[i]);
    t->tm[t->nt++] = mat;
  }
}

/* Horizontal quad of half-size r at height y. */
static inline void add_hplane(tscene *t, float y, float r, int up, uint32_t mat) {
  float q[4][3] = {{-r, y, -r}, {-r, y, r}, {r, y, r}, {r, y, -r}};
  float n[3] = {0, up ? 1.0f : -1.0f, 0};
  add_quad(t, q, n, mat);
}

static inline void add_point(tscene *t, float x, float y, float z, float intensity, const float col[3]) {
  pb_light *l = &t->light[t->nl++];
  memset(l, 0, sizeof *l);
  l->type = PB_LIGHT_POINT;
  l->position[0] = x, l->position[1] = y, l->position[2] = z;
  memcpy(l->color, col, sizeof l->color);
  l->intensity = intensity;
}

static inline void finish(tscene *t) {
  pb_scene *s = &t->s;
  memset(s, 0, sizeof *s);
  s->positions = t->pos;
  s->normals = t->nrm;
  s->uvs = t->uv;
  s->vertex_count = t->nv;
  s->triangles = t->tri;
  s->triangle_material = t->tm;
  s->triangle_count = t->nt;
  s->materials = t->mat;
  s->material_count = t->nm;
  s->lights = t->light;
  s->light_count = t->nl;
  pb_scene_finalize(s);
}

/* finish() with one camera at `at` looking along -y, tilted by `pitch`
 * towards -z (vertical field of view 1.2 rad, square). */
static inline void finish_with_camera(tscene *t, const float at[3], float pitch) {
  pb_camera *c = &t->cam;
  memset(c, 0, sizeof *c);
  memcpy(c->position, at, sizeof c->position);
  c->forward[1] = -cosf(pitch), c->forward[2] = -sinf(pitch);
  c->up[1] = -sinf(pitch), c->up[2] = cosf(pitch);
  c->right[0] = 1;
  c->yfov = 1.2f;
  c->aspect = 1;
  finish(t);
  t->s.cameras = c;
  t->s.camera_count = 1;
}

/* Closed cube [-1, 1]^3 of albedo rho (faces towards the inside). */
static inline void box(tscene *t, float rho) {
  memset(t, 0, sizeof *t);
  uint32_t m = add_mat(t, rho, 0);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      float q[4][3], n[3] = {0, 0, 0};
      float c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int i = 0; i < 4; ++i) {
        q[i][axis] = (float)side;
        q[i][u] = c[i][0];
        q[i][v] = c[i][1];
      }
      n[axis] = (float)-side;
      add_quad(t, q, n, m);
    }
}

#endif
