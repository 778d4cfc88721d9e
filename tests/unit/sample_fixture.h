/* The start of every device test that compares a render of a sample scene
 * with the reference renderer: load samples/NAME/NAME.gltf, make its GPU
 * scene, size the image from a width (the camera's aspect gives the height),
 * render the reference. Include after pbtest.h (failures are CHECKed). */
#ifndef PB_TEST_SAMPLE_FIXTURE_H
#define PB_TEST_SAMPLE_FIXTURE_H

#include <stdio.h>
#include <string.h>

#include "gpu/gpu.h"
#include "ref/ref.h"
#include "render/render.h"
#include "scene/scene.h"

typedef struct pbt_sample {
  pb_scene s;
  pb_gpu_scene gs;
  pb_ref_result ref; /* zeroed when ref_desc was NULL */
  uint32_t w, h;
  int loaded, gpu, ok; /* ok: everything asked for is there */
} pbt_sample;

/* ref_desc NULL: no reference. Returns f->ok. */
static inline int pbt_sample_open(pb_gpu *g, const char *name, uint32_t width, const pb_ref_desc *ref_desc,
                                  pbt_sample *f) {
  memset(f, 0, sizeof *f);
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load(path, &ld, &f->s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return 0;
  f->loaded = 1;
  pb_camera_image_size(&f->s.cameras[0], width, 0, &f->w, &f->h);
  r = pb_gpu_scene_create(g, &f->s, &f->gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return 0;
  f->gpu = 1;
  if (ref_desc) {
    r = pb_ref_render(&f->s, 0, f->w, f->h, ref_desc, &f->ref);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) return 0;
  }
  return f->ok = 1;
}

static inline void pbt_sample_close(pb_gpu *g, pbt_sample *f) {
  pb_ref_result_destroy(&f->ref);
  if (f->gpu) pb_gpu_scene_destroy(g, &f->gs);
  if (f->loaded) pb_scene_destroy(&f->s);
  pb_error_clear();
  memset(f, 0, sizeof *f);
}

#endif
