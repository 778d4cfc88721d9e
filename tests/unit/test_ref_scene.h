/* Code-built scenes for the reference renderer's tests: fills a pb_scene with
 * malloc'd arrays (pb_scene_destroy frees them) so the tests need no glTF
 * loader. All helpers abort on allocation failure: a test has no better
 * answer. */
#ifndef PB_TEST_REF_SCENE_H
#define PB_TEST_REF_SCENE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ref/ref.h"
#include "scene/scene.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static inline void *tsc_grow(void *p, size_t count, size_t size) {
  void *n = realloc(p, count * size);
  if (!n) {
    fprintf(stderr, "out of memory\n");
    abort();
  }
  return n;
}

static inline void tsc_init(pb_scene *s) {
  memset(s, 0, sizeof *s);
  s->path = strdup("test-scene");
}

/* A purely diffuse glTF material (KHR_materials_specular with colour 0, as
 * Blender writes for Specular 0). */
static inline pb_material tsc_lambert(float r, float g, float b) {
  pb_material m;
  memset(&m, 0, sizeof m);
  snprintf(m.name, sizeof m.name, "lambert");
  m.base_color[0] = r;
  m.base_color[1] = g;
  m.base_color[2] = b;
  m.base_color[3] = 1;
  m.base_color_tex = m.metallic_roughness_tex = m.emissive_tex = m.normal_tex = -1;
  m.metallic = 0;
  m.roughness = 1;
  m.specular = 0;
  m.ior = 1.5f;
  m.normal_scale = 1;
  return m;
}

static inline pb_material tsc_mirror(void) {
  pb_material m = tsc_lambert(1, 1, 1);
  snprintf(m.name, sizeof m.name, "mirror");
  m.metallic = 1;
  m.roughness = 0;
  return m;
}

static inline pb_material tsc_glass(float ior) {
  pb_material m = tsc_lambert(1, 1, 1);
  snprintf(m.name, sizeof m.name, "glass");
  m.transmission = 1;
  m.roughness = 0;
  m.ior = ior;
  m.specular = 1;
  m.specular_color[0] = m.specular_color[1] = m.specular_color[2] = 1;
  return m;
}

static inline uint32_t tsc_material(pb_scene *s, pb_material m) {
  s->materials = tsc_grow(s->materials, s->material_count + 1, sizeof *s->materials);
  s->materials[s->material_count] = m;
  return s->material_count++;
}

static inline uint32_t tsc_vertex(pb_scene *s, const float p[3], const float n[3]) {
  uint32_t i = s->vertex_count++;
  s->positions = tsc_grow(s->positions, s->vertex_count, sizeof *s->positions);
  s->normals = tsc_grow(s->normals, s->vertex_count, sizeof *s->normals);
  s->uvs = tsc_grow(s->uvs, s->vertex_count, sizeof *s->uvs);
  memcpy(s->positions[i], p, sizeof s->positions[i]);
  memcpy(s->normals[i], n, sizeof s->normals[i]);
  s->uvs[i][0] = s->uvs[i][1] = 0;
  return i;
}

static inline void tsc_triangle_idx(pb_scene *s, uint32_t a, uint32_t b, uint32_t c,
                             uint32_t mat) {
  uint32_t t = s->triangle_count++;
  s->triangles = tsc_grow(s->triangles, s->triangle_count, sizeof *s->triangles);
  s->triangle_material =
      tsc_grow(s->triangle_material, s->triangle_count, sizeof *s->triangle_material);
  s->triangles[t][0] = a;
  s->triangles[t][1] = b;
  s->triangles[t][2] = c;
  s->triangle_material[t] = mat;
}

static inline void tsc_flat_normal(const float a[3], const float b[3], const float c[3],
                            float n[3]) {
  float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) n[k] = l > 0 ? n[k] / l : 0;
}

/* A flat-shaded triangle, counter-clockwise seen from its front. */
static inline void tsc_triangle(pb_scene *s, const float a[3], const float b[3],
                         const float c[3], uint32_t mat) {
  float n[3];
  tsc_flat_normal(a, b, c, n);
  uint32_t i = tsc_vertex(s, a, n), j = tsc_vertex(s, b, n), k = tsc_vertex(s, c, n);
  tsc_triangle_idx(s, i, j, k, mat);
}

/* Quad a b c d, counter-clockwise seen from its front. */
static inline void tsc_quad(pb_scene *s, const float a[3], const float b[3], const float c[3],
                     const float d[3], uint32_t mat) {
  tsc_triangle(s, a, b, c, mat);
  tsc_triangle(s, a, c, d, mat);
}

/* Axis-aligned square in the plane z = z0, facing +z (up), half-size h. */
static inline void tsc_floor(pb_scene *s, float h, float z0, uint32_t mat) {
  float a[3] = {-h, -h, z0}, b[3] = {h, -h, z0}, c[3] = {h, h, z0}, d[3] = {-h, h, z0};
  tsc_quad(s, a, b, c, d, mat);
}

static inline pb_light *tsc_light(pb_scene *s, pb_light_type type) {
  s->lights = tsc_grow(s->lights, s->light_count + 1, sizeof *s->lights);
  pb_light *l = &s->lights[s->light_count++];
  memset(l, 0, sizeof *l);
  snprintf(l->name, sizeof l->name, "light%u", s->light_count - 1);
  l->type = type;
  l->color[0] = l->color[1] = l->color[2] = 1;
  l->direction[2] = -1;
  return l;
}

static inline void tsc_norm3(float v[3]) {
  float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] /= l;
}

/* Camera at pos looking along fwd, with up (orthogonalised). */
static inline void tsc_camera(pb_scene *s, const float pos[3], const float fwd_in[3],
                       const float up_in[3], float yfov_deg) {
  s->cameras = tsc_grow(s->cameras, s->camera_count + 1, sizeof *s->cameras);
  pb_camera *c = &s->cameras[s->camera_count++];
  memset(c, 0, sizeof *c);
  snprintf(c->name, sizeof c->name, "cam%u", s->camera_count - 1);
  float f[3] = {fwd_in[0], fwd_in[1], fwd_in[2]};
  tsc_norm3(f);
  /* right = forward x up; up = right x forward */
  float r[3] = {f[1] * up_in[2] - f[2] * up_in[1], f[2] * up_in[0] - f[0] * up_in[2],
                f[0] * up_in[1] - f[1] * up_in[0]};
  tsc_norm3(r);
  float u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2],
                r[0] * f[1] - r[1] * f[0]};
  memcpy(c->position, pos, sizeof c->position);
  memcpy(c->forward, f, sizeof f);
  memcpy(c->up, u, sizeof u);
  memcpy(c->right, r, sizeof r);
  c->yfov = yfov_deg * (float)M_PI / 180.0f;
  c->aspect = 1;
}

/* The renderer's camera model: the unit ray direction through image point
 * (px, py) in pixels (not necessarily a pixel centre). */
static inline void tsc_camera_ray(const pb_camera *c, uint32_t w, uint32_t h, double px,
                           double py, double d[3]) {
  double ty = tan(0.5 * c->yfov), tx = ty * w / h;
  double sx = (2.0 * px / w - 1.0) * tx, sy = (1.0 - 2.0 * py / h) * ty;
  double l = 0;
  for (int k = 0; k < 3; ++k) {
    d[k] = c->forward[k] + sx * c->right[k] + sy * c->up[k];
    l += d[k] * d[k];
  }
  l = sqrt(l);
  for (int k = 0; k < 3; ++k) d[k] /= l;
}

/* Mean over pixel (x, y) of f(point on the plane z = z0 seen through it), by
 * an n x n midpoint rule: what a box-filtered render of f converges to. */
static inline double tsc_pixel_mean_on_plane(const pb_camera *c, uint32_t w, uint32_t h,
                                      uint32_t x, uint32_t y, double z0, int n,
                                      double (*f)(const double p[3], void *), void *user) {
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double d[3], p[3];
      tsc_camera_ray(c, w, h, x + (i + 0.5) / n, y + (j + 0.5) / n, d);
      double t = (z0 - c->position[2]) / d[2];
      for (int k = 0; k < 3; ++k) p[k] = c->position[k] + t * d[k];
      sum += f(p, user);
    }
  return sum / ((double)n * n);
}

/* Mean of channel c of an RGB(A) buffer over all pixels. */
static inline double tsc_mean(const float *px, uint32_t w, uint32_t h, uint32_t ch, int c) {
  double s = 0;
  for (size_t i = 0; i < (size_t)w * h; ++i) s += px[i * ch + (size_t)c];
  return s / ((double)w * h);
}

/* Relative difference |a - b| / |b|. */
static inline double tsc_rel(double a, double b) { return fabs(a - b) / fabs(b); }

#endif
