/* glTF cameras -> pb_camera (the projection in camera.c), and the camera
 * framing the scene for files without one. Part of the loader
 * (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/camera.h"
#include "scene/load_internal.h"

pb_result load_camera(loader *L, int32_t node, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  int32_t ci = d->nodes[node].camera;
  if (ci < 0 || (size_t)ci >= d->camera_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].camera: %d does not exist (%zu cameras)", L->path, node, ci,
                   d->camera_count);
  const pb_gltf_camera *c = &d->cameras[ci];
  if (!c->perspective && !c->orthographic && !c->blender.present)
    return load_warn(L, "cameras[%d]: type '%s' skipped: only perspective and orthographic cameras are supported", ci,
                c->type);
  pb_camera proj;
  pb_result r = pb_camera_projection_from_gltf(L->path, ci, c, &proj);
  if (r != PB_OK) return r;
  double o[3] = {0, 0, 0}, pos[3], f[3], u[3];
  double fz[3] = {0, 0, -1}, uy[3] = {0, 1, 0};
  xform_point(M, o, pos);
  xform_dir(M, fz, f);
  xform_dir(M, uy, u);
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera position is out of float range", L->path, node);
  if (!normalize3(f))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera transform is degenerate", L->path, node);
  /* Orthonormalise (Gram-Schmidt) so a sheared or scaled node still gives a
   * proper camera frame. */
  double dp = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
  for (int k = 0; k < 3; ++k) u[k] -= dp * f[k];
  if (!normalize3(u))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera transform is degenerate", L->path, node);
  pb_scene *s = L->s;
  r = load_grow(L, (void **)&s->cameras, &L->camera_cap, (uint64_t)s->camera_count + 1, sizeof *s->cameras, "cameras");
  if (r != PB_OK) return r;
  pb_camera *cam = &s->cameras[s->camera_count++];
  *cam = proj;
  load_copy_name(cam->name, d->nodes[node].name, c->name);
  if (!cam->name[0]) snprintf(cam->name, PB_NAME_MAX, "cameras[%d]", ci);
  for (int k = 0; k < 3; ++k) cam->position[k] = (float)pos[k], cam->forward[k] = (float)f[k], cam->up[k] = (float)u[k];
  cam->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
  cam->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
  cam->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  return PB_OK;
}

/* A camera framing the whole scene, for files without one: 50 degrees
 * vertical field of view, looking at the bounds' centre from the front (+Z)
 * and a little above, far enough for the bounding sphere to fit. */
pb_result load_default_camera(loader *L) {
  pb_scene *s = L->s;
  /* In double: the bounds of a scene that fits in float may not (a 1e20 m
   * box's squared radius overflows float, found by fuzz_gltf). */
  const float yfov = 50.0f * (float)M_PI / 180.0f;
  double ctr[3], rad = 0;
  for (int k = 0; k < 3; ++k) {
    ctr[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
    double e = 0.5 * ((double)s->bounds_max[k] - s->bounds_min[k]);
    rad += e * e;
  }
  rad = sqrt(rad);
  if (!(rad > 0)) rad = 1;
  double dist = 1.1 * rad / sin(0.5 * yfov);
  double f[3] = {0, -0.25, -1}, pos[3];
  normalize3(f);
  for (int k = 0; k < 3; ++k) pos[k] = ctr[k] - dist * f[k];
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_LIMIT, "%s: cameras: none, and the scene (%g across) is too large to frame with a default camera",
                   L->path, 2 * rad);
  pb_result r = load_grow(L, (void **)&s->cameras, &L->camera_cap, 1, sizeof *s->cameras, "cameras");
  if (r != PB_OK) return r;
  pb_camera *c = &s->cameras[0];
  memset(c, 0, sizeof *c);
  snprintf(c->name, PB_NAME_MAX, "default");
  c->synthesized = 1;
  c->yfov = yfov; /* no clip planes: it frames the bounds whatever their size */
  for (int k = 0; k < 3; ++k) {
    c->forward[k] = (float)f[k];
    c->position[k] = (float)pos[k];
  }
  /* up = orthonormalised +Y, right = forward x up */
  double u[3] = {0, 1, 0}, dp = f[1];
  for (int k = 0; k < 3; ++k) u[k] -= dp * f[k];
  normalize3(u);
  for (int k = 0; k < 3; ++k) c->up[k] = (float)u[k];
  c->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
  c->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
  c->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  s->camera_count = 1;
  return PB_OK;
}
