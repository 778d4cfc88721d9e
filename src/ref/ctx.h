/* The state one reference render shares between its files (ref.c). */
#ifndef PB_REF_CTX_H
#define PB_REF_CTX_H

#include "ref/accel.h"
#include "ref/lights.h"
#include "ref/ref.h"
#include "scene/camera.h"
#include "scene/scene.h"

typedef struct pb_ref_ctx {
  const pb_scene *scene;
  const pb_camera *cam;
  uint32_t width, height;
  uint32_t max_bounces;
  uint32_t threads;
  uint64_t seed;
  pb_ref_mode mode;
  pb_ref_accel accel;
  pb_ref_lights lights;
  /* The camera's window for this image (scene/camera.h). */
  pb_gpu_camera view;
} pb_ref_ctx;

#endif
