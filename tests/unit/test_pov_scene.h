/* Code-built scenes for the POV-Ray exporter's tests (pb_scene with malloc'd
 * arrays, freed by pb_scene_destroy), and a POV-Ray runner. Allocation
 * failures abort: a test has no better answer. */
#ifndef PB_TEST_POV_SCENE_H
#define PB_TEST_POV_SCENE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

static void *tps_grow(void *p, size_t count, size_t size) {
  void *n = realloc(p, count * size);
  if (!n) {
    fprintf(stderr, "out of memory\n");
    abort();
  }
  return n;
}

static void tps_init(pb_scene *s) {
  memset(s, 0, sizeof *s);
  s->path = strdup("test-scene");
}

static uint32_t tps_material(pb_scene *s, const char *name, float r, float g, float b) {
  s->materials = tps_grow(s->materials, s->material_count + 1, sizeof *s->materials);
  pb_material *m = &s->materials[s->material_count];
  memset(m, 0, sizeof *m);
  snprintf(m->name, sizeof m->name, "%s", name);
  m->base_color[0] = r;
  m->base_color[1] = g;
  m->base_color[2] = b;
  m->base_color[3] = 1;
  m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = -1;
  m->roughness = 1;
  m->ior = 1.5f;
  m->normal_scale = 1;
  m->double_sided = 1;
  return s->material_count++;
}

/* A horizontal rectangle at height y, x in [x0,x1], z in [z0,z1], facing +Y. */
static void tps_quad_y(pb_scene *s, float x0, float x1, float z0, float z1, float y, uint32_t mat) {
  uint32_t v = s->vertex_count;
  s->positions = tps_grow(s->positions, v + 4, sizeof *s->positions);
  s->normals = tps_grow(s->normals, v + 4, sizeof *s->normals);
  s->uvs = tps_grow(s->uvs, v + 4, sizeof *s->uvs);
  const float p[4][3] = {{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}};
  for (int i = 0; i < 4; ++i) {
    memcpy(s->positions[v + i], p[i], sizeof p[i]);
    s->normals[v + i][0] = 0;
    s->normals[v + i][1] = 1;
    s->normals[v + i][2] = 0;
    s->uvs[v + i][0] = (p[i][0] - x0) / (x1 - x0);
    s->uvs[v + i][1] = (p[i][2] - z0) / (z1 - z0);
  }
  s->vertex_count += 4;
  uint32_t t = s->triangle_count;
  s->triangles = tps_grow(s->triangles, t + 2, sizeof *s->triangles);
  s->triangle_material = tps_grow(s->triangle_material, t + 2, sizeof *s->triangle_material);
  /* Counter-clockwise seen from +Y. */
  s->triangles[t][0] = v;
  s->triangles[t][1] = v + 1;
  s->triangles[t][2] = v + 2;
  s->triangles[t + 1][0] = v;
  s->triangles[t + 1][1] = v + 2;
  s->triangles[t + 1][2] = v + 3;
  s->triangle_material[t] = s->triangle_material[t + 1] = mat;
  s->triangle_count += 2;
}

static pb_light *tps_light(pb_scene *s, pb_light_type type, const char *name) {
  s->lights = tps_grow(s->lights, s->light_count + 1, sizeof *s->lights);
  pb_light *l = &s->lights[s->light_count++];
  memset(l, 0, sizeof *l);
  snprintf(l->name, sizeof l->name, "%s", name);
  l->type = type;
  l->color[0] = l->color[1] = l->color[2] = 1;
  l->direction[1] = -1;
  return l;
}

/* A camera at `pos` looking straight down (-Y), image top towards -Z, image
 * right towards +X (right = forward x up). */
static void tps_camera_down(pb_scene *s, const char *name, float x, float y, float z, float yfov_deg) {
  s->cameras = tps_grow(s->cameras, s->camera_count + 1, sizeof *s->cameras);
  pb_camera *c = &s->cameras[s->camera_count++];
  memset(c, 0, sizeof *c);
  snprintf(c->name, sizeof c->name, "%s", name);
  c->position[0] = x;
  c->position[1] = y;
  c->position[2] = z;
  c->forward[1] = -1;
  c->up[2] = -1;
  c->right[0] = 1;
  c->yfov = yfov_deg * (float)M_PI / 180.0f;
  c->aspect = 1;
  c->znear = 0.01f;
}

#endif
