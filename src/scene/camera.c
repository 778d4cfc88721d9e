/* Camera windows and rays (camera.h). */
#include "scene/camera.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "core/result.h"

void pb_camera_window(const pb_camera *c, uint32_t full_w, uint32_t full_h, double *width, double *height,
                      double *cx, double *cy) {
  double w = full_w ? full_w : 1, h = full_h ? full_h : 1;
  /* Extent of the fitted side: at distance 1 (perspective) or in metres. */
  double ext = c->orthographic ? (double)c->ortho_size : 2.0 * tan(0.5 * (double)c->yfov);
  int horizontal = c->fit == PB_CAMERA_FIT_HORIZONTAL || (c->fit == PB_CAMERA_FIT_AUTO && w >= h);
  *width = horizontal ? ext : ext * w / h;
  *height = horizontal ? ext * h / w : ext;
  *cx = (double)c->shift[0] * ext;
  *cy = (double)c->shift[1] * ext;
}

void pb_camera_view(const pb_camera *c, uint32_t full_w, uint32_t full_h, pb_gpu_camera *v) {
  memset(v, 0, sizeof *v);
  memcpy(v->position, c->position, sizeof v->position);
  memcpy(v->forward, c->forward, sizeof v->forward);
  memcpy(v->right, c->right, sizeof v->right);
  memcpy(v->up, c->up, sizeof v->up);
  double w = full_w ? full_w : 1, h = full_h ? full_h : 1, ww, wh, cx, cy;
  pb_camera_window(c, full_w, full_h, &ww, &wh, &cx, &cy);
  double dx = ww / w, dy = -wh / h;
  v->x0 = (float)(cx - 0.5 * ww);
  v->y0 = (float)(cy + 0.5 * wh);
  v->dx = (float)dx;
  v->dy = (float)dy;
  v->clip_near = c->znear > 0.0f ? c->znear : 0.0f;
  v->clip_far = c->zfar > v->clip_near ? c->zfar : 0.0f;
  v->orthographic = c->orthographic ? 1u : 0u;
}

void pb_camera_ray(const pb_gpu_camera *v, float px, float py, float org[3], float dir[3], float *t0,
                   float *tmax) {
  float sx = v->x0 + px * v->dx, sy = v->y0 + py * v->dy;
  if (v->orthographic) {
    for (int k = 0; k < 3; ++k) {
      org[k] = v->position[k] + v->right[k] * sx + v->up[k] * sy;
      dir[k] = v->forward[k];
    }
  } else {
    float len = 0.0f;
    for (int k = 0; k < 3; ++k) {
      dir[k] = v->forward[k] + v->right[k] * sx + v->up[k] * sy;
      len += dir[k] * dir[k];
    }
    len = sqrtf(len);
    for (int k = 0; k < 3; ++k) {
      dir[k] /= len;
      org[k] = v->position[k];
    }
  }
  /* Cycles' clipping: the ray starts on the near plane and ends on the far
   * one, distances along forward divided by the ray's cosine to it. */
  float cz = dir[0] * v->forward[0] + dir[1] * v->forward[1] + dir[2] * v->forward[2];
  *t0 = v->clip_near / cz;
  for (int k = 0; k < 3; ++k) org[k] += dir[k] * *t0;
  *tmax = v->clip_far > 0.0f ? (v->clip_far - v->clip_near) / cz : INFINITY;
}

int pb_camera_view_project(const pb_gpu_camera *v, const float p[3], float *x, float *y, float *depth) {
  float d[3] = {p[0] - v->position[0], p[1] - v->position[1], p[2] - v->position[2]};
  float z = d[0] * v->forward[0] + d[1] * v->forward[1] + d[2] * v->forward[2];
  if (!(z > 0.0f)) return 0;
  float sx = d[0] * v->right[0] + d[1] * v->right[1] + d[2] * v->right[2];
  float sy = d[0] * v->up[0] + d[1] * v->up[1] + d[2] * v->up[2];
  if (!v->orthographic) sx /= z, sy /= z;
  *x = (sx - v->x0) / v->dx;
  *y = (sy - v->y0) / v->dy;
  *depth = z;
  return isfinite(*x) && isfinite(*y);
}

float pb_camera_pixel_size(const pb_gpu_camera *v, float z) {
  return v->orthographic ? fabsf(v->dy) : fabsf(v->dy) * z;
}

/* ---- from glTF -------------------------------------------------------------- */

static int finite_float(double x) { return isfinite(x) && fabs(x) <= FLT_MAX; }

/* The plain glTF camera (perspective or orthographic; types checked as
 * before the extension existed, with the same messages). */
static pb_result from_plain(const char *path, int ci, const pb_gltf_camera *c, pb_camera *out) {
  if (c->perspective) {
    if (!(c->yfov > 0 && c->yfov < M_PI))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.yfov: %g is not in (0, pi)", path, ci, c->yfov);
    if (!(c->znear > 0) || !finite_float(c->znear))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.znear: %g is not positive", path, ci, c->znear);
    if (c->zfar != 0 && !(c->zfar > c->znear && finite_float(c->zfar)))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.zfar: %g is not above znear (%g)", path, ci,
                     c->zfar, c->znear);
    if (c->aspect_ratio < 0 || !finite_float(c->aspect_ratio))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.aspectRatio: %g is not positive", path, ci,
                     c->aspect_ratio);
    out->yfov = (float)c->yfov;
    out->aspect = (float)c->aspect_ratio;
  } else {
    /* glTF 2.0 5.14: xmag and ymag must not be zero (half the view's width
     * and height); zfar is required and above znear >= 0. */
    if (!(c->xmag != 0) || !finite_float(c->xmag))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].orthographic.xmag: %g is not a non-zero size", path, ci,
                     c->xmag);
    if (!(c->ymag != 0) || !finite_float(c->ymag))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].orthographic.ymag: %g is not a non-zero size", path, ci,
                     c->ymag);
    if (!(c->znear >= 0) || !finite_float(c->znear))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].orthographic.znear: %g is negative", path, ci, c->znear);
    if (!(c->zfar > c->znear) || !finite_float(c->zfar))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].orthographic.zfar: %g is not above znear (%g)", path, ci,
                     c->zfar, c->znear);
    out->orthographic = 1;
    out->ortho_size = (float)(2.0 * fabs(c->ymag));
    out->aspect = (float)(fabs(c->xmag) / fabs(c->ymag));
  }
  out->fit = PB_CAMERA_FIT_VERTICAL;
  out->znear = (float)c->znear;
  out->zfar = (float)c->zfar;
  return PB_OK;
}

#define EXT "cameras[%d].extensions.PHOTONBRIDGE_blender"

/* A number of the extension: Blender's default when absent, else finite
 * and above `min` (or at least it when min_ok). */
static pb_result ext_number(const char *path, int ci, const char *key, double v, double dflt, double min,
                            int min_ok, float *out) {
  if (isnan(v)) v = dflt;
  else if (!finite_float(v) || (min_ok ? v < min : !(v > min)))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT ".%s: %g is %s %g", path, ci, key, v,
                   min_ok ? "below" : "not above", min);
  *out = (float)v;
  return PB_OK;
}

/* The extension's camera (the file records Blender's own values; Blender
 * 3.4's defaults for absent members: DNA_camera_defaults.h). Sensor size
 * per BKE_camera_sensor_size: the height for a VERTICAL fit, the width
 * otherwise (AUTO included); field of view = 2 atan(sensor / (2 lens)). */
static pb_result from_blender(const char *path, int ci, const pb_gltf_camera_blender *b, pb_camera *out) {
  if (b->bad_member)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT "%s%s: not %s", path, ci, b->bad_member[0] ? "." : "",
                   b->bad_member, b->bad_expect);
  double plain_aspect = out->aspect; /* the render's, from the plain camera */
  memset(out, 0, sizeof *out);
  if (b->type && strcmp(b->type, "PERSP") != 0 && strcmp(b->type, "ORTHO") != 0)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: " EXT ".type: '%s' is not PERSP or ORTHO (panoramic cameras are "
                   "not supported)", path, ci, b->type);
  out->orthographic = b->type && strcmp(b->type, "ORTHO") == 0;
  out->fit = PB_CAMERA_FIT_AUTO;
  if (b->sensor_fit) {
    if (strcmp(b->sensor_fit, "HORIZONTAL") == 0) out->fit = PB_CAMERA_FIT_HORIZONTAL;
    else if (strcmp(b->sensor_fit, "VERTICAL") == 0) out->fit = PB_CAMERA_FIT_VERTICAL;
    else if (strcmp(b->sensor_fit, "AUTO") != 0)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT ".sensorFit: '%s' is not AUTO, HORIZONTAL or VERTICAL", path,
                     ci, b->sensor_fit);
  }
  float lens = 0, sw = 0, sh = 0, shift_lo = -FLT_MAX;
  pb_result r;
  if ((r = ext_number(path, ci, "lens", b->lens, 50.0, 0.0, 0, &lens)) != PB_OK ||
      (r = ext_number(path, ci, "sensorWidth", b->sensor_width, 36.0, 0.0, 0, &sw)) != PB_OK ||
      (r = ext_number(path, ci, "sensorHeight", b->sensor_height, 24.0, 0.0, 0, &sh)) != PB_OK ||
      (r = ext_number(path, ci, "orthoScale", b->ortho_scale, 6.0, 0.0, 0, &out->ortho_size)) != PB_OK ||
      (r = ext_number(path, ci, "shiftX", b->shift_x, 0.0, shift_lo, 1, &out->shift[0])) != PB_OK ||
      (r = ext_number(path, ci, "shiftY", b->shift_y, 0.0, shift_lo, 1, &out->shift[1])) != PB_OK ||
      (r = ext_number(path, ci, "clipStart", b->clip_start, 0.1, 0.0, 0, &out->znear)) != PB_OK ||
      (r = ext_number(path, ci, "clipEnd", b->clip_end, 1000.0, out->znear, 0, &out->zfar)) != PB_OK ||
      (r = ext_number(path, ci, "aspect", b->aspect, plain_aspect, 0.0, 1, &out->aspect)) != PB_OK)
    return r;
  if (!out->orthographic) {
    double sensor = out->fit == PB_CAMERA_FIT_VERTICAL ? sh : sw;
    out->yfov = (float)(2.0 * atan(0.5 * sensor / lens));
    out->ortho_size = 0;
  }
  return PB_OK;
}

pb_result pb_camera_projection_from_gltf(const char *path, int index, const pb_gltf_camera *c, pb_camera *out) {
  memset(out, 0, sizeof *out);
  /* The plain camera is checked even where the extension replaces it: the
   * file must load elsewhere too. */
  if (c->perspective || c->orthographic) {
    pb_result r = from_plain(path, index, c, out);
    if (r != PB_OK) return r;
  }
  return c->blender.present ? from_blender(path, index, &c->blender, out) : PB_OK;
}
