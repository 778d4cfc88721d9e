/* The lit plane of the gather and splat tests: a 2 x 2 m Lambert plane
 * (albedo 0.8) at y = 0 seen from 3 m straight above (vertical angle 0.6,
 * square), as a finalised code-built scene. The arrays live in the fixture,
 * so the scene is valid while it is. Shared by test_gpu_gather and
 * test_gpu_splat. */
#ifndef PB_TEST_PLANE_FIXTURE_H
#define PB_TEST_PLANE_FIXTURE_H

#include <stdint.h>
#include <string.h>

#include "scene/scene.h"

typedef struct plane_fixture {
  float pos[4][3], nrm[4][3], uv[4][2];
  uint32_t tri[2][3], tm[2];
  pb_material mat;
  pb_camera cam;
  pb_scene s;
} plane_fixture;

static void plane_fixture_build(plane_fixture *f) {
  static const float pos[4][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  static const uint32_t tri[2][3] = {{0, 2, 1}, {0, 3, 2}};
  memset(f, 0, sizeof *f);
  memcpy(f->pos, pos, sizeof pos);
  memcpy(f->tri, tri, sizeof tri);
  for (int v = 0; v < 4; ++v) f->nrm[v][1] = 1;
  pb_material *m = &f->mat;
  m->base_color[0] = m->base_color[1] = m->base_color[2] = 0.8f;
  m->base_color[3] = 1;
  m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
  m->roughness = 1;
  m->specular = 0;
  m->ior = 1.5f;
  pb_camera *c = &f->cam;
  c->position[1] = 3;
  c->forward[1] = -1;
  c->up[2] = -1;
  c->right[0] = 1;
  c->yfov = 0.6f;
  c->aspect = 1;
  pb_scene *s = &f->s;
  s->positions = f->pos;
  s->normals = f->nrm;
  s->uvs = f->uv;
  s->vertex_count = 4;
  s->triangles = f->tri;
  s->triangle_material = f->tm;
  s->triangle_count = 2;
  s->materials = &f->mat;
  s->material_count = 1;
  s->cameras = &f->cam;
  s->camera_count = 1;
  pb_scene_finalize(s);
}

#endif
