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
  /* Thin lens (Cycles 3.4 scene/camera.cpp device_update: blades < 3 is a
   * disc; inv_aperture_ratio = 1 / aperture_ratio). */
  v->aperture = c->aperture_radius > 0.0f ? c->aperture_radius : 0.0f;
  v->focus = c->focus_distance > 1e-5f ? c->focus_distance : 1e-5f;
  v->blades = c->aperture_blades >= 3 ? (float)c->aperture_blades : 0.0f;
  v->blade_rotation = c->aperture_rotation;
  v->inv_ratio = c->aperture_ratio > 0.0f ? 1.0f / c->aperture_ratio : 1.0f;
  if (c->panorama == PB_CAMERA_PANO_NONE) return;
  /* Panoramic: Cycles' viewplane is [0, 1]^2 offset by the shift
   * (blender/camera.cpp blender_camera_viewplane, pano_viewplane of a final
   * render), raster y up; ours runs down from the top row. */
  v->orthographic = 0u;
  v->projection = (uint32_t)c->panorama;
  v->x0 = c->shift[0];
  v->dx = (float)(1.0 / w);
  v->y0 = 1.0f + c->shift[1];
  v->dy = (float)(-1.0 / h);
  switch (c->panorama) {
  case PB_CAMERA_PANO_EQUIRECTANGULAR: /* kcam->equirectangular_range */
    v->pano0 = c->longitude[0] - c->longitude[1];
    v->pano1 = -c->longitude[0];
    v->pano2 = c->latitude[0] - c->latitude[1];
    v->pano3 = (float)(-c->latitude[0] + 0.5 * M_PI);
    break;
  case PB_CAMERA_PANO_FISHEYE_EQUIDISTANT:
    v->pano0 = c->fisheye_fov;
    break;
  case PB_CAMERA_PANO_FISHEYE_EQUISOLID: {
    /* blender_camera_sync's panorama sensor: the fitted side gets the
     * sensor size, the other follows the image (AUTO: width when wider). */
    int horizontal = c->fit == PB_CAMERA_FIT_HORIZONTAL || (c->fit == PB_CAMERA_FIT_AUTO && w > h);
    double size = c->fit == PB_CAMERA_FIT_VERTICAL ? c->sensor[1] : c->sensor[0];
    v->pano0 = c->fisheye_lens;
    v->pano1 = c->fisheye_fov;
    v->pano2 = (float)(horizontal ? size : size * w / h);
    v->pano3 = (float)(horizontal ? size * h / w : size);
    break;
  }
  default:
    break;
  }
}

/* ---- thin lens and panoramas (Cycles 3.4 kernel/camera) ---------------------- */

/* A point of the unit aperture for a sample in [0, 1)^2: Shirley and Chiu's
 * concentric disc (Cycles' concentric_sample_disk), or Cycles'
 * regular_polygon_sample for `blades` corners; x times inv_ratio
 * (camera_sample_aperture). */
static void aperture_point(const pb_gpu_camera *v, float u1, float u2, float *x, float *y) {
  if (v->blades == 0.0f) {
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f, r, phi;
    if (a == 0.0f && b == 0.0f) r = 0.0f, phi = 0.0f;
    else if (a * a > b * b) r = a, phi = (float)(M_PI / 4) * (b / a);
    else r = b, phi = (float)(M_PI / 2) - (float)(M_PI / 4) * (a / b);
    *x = r * cosf(phi);
    *y = r * sinf(phi);
  } else {
    float corners = v->blades, corner = floorf(u1 * corners);
    float u = u1 * corners - corner, w = u2;
    u = sqrtf(u);
    w *= u;
    u = 1.0f - u;
    float angle = (float)M_PI / corners;
    float px = (u + w) * cosf(angle), py = (u - w) * sinf(angle);
    float rot = v->blade_rotation + corner * 2.0f * angle, cr = cosf(rot), sr = sinf(rot);
    *x = cr * px - sr * py;
    *y = sr * px + cr * py;
  }
  *x *= v->inv_ratio;
}

/* Cycles' panorama_to_direction (kernel/camera/projection.h) for panorama
 * coordinates (u, v): a direction in Cycles' panorama frame (x along the
 * view for the equirectangular and fisheye cameras, -y for the mirror ball;
 * see to_world), or 0 where (u, v) has none (outside a fisheye's circle,
 * off the mirror ball). */
static int pano_direction(const pb_gpu_camera *c, float u, float v, float d[3]) {
  switch (c->projection) {
  case PB_GPU_CAMERA_EQUIRECTANGULAR: {
    float phi = c->pano0 * u + c->pano1, theta = c->pano2 * v + c->pano3;
    d[0] = sinf(theta) * cosf(phi), d[1] = sinf(theta) * sinf(phi), d[2] = cosf(theta);
    return 1;
  }
  case PB_GPU_CAMERA_FISHEYE_EQUIDISTANT:
  case PB_GPU_CAMERA_FISHEYE_EQUISOLID: {
    float theta;
    if (c->projection == PB_GPU_CAMERA_FISHEYE_EQUIDISTANT) {
      u = (u - 0.5f) * 2.0f, v = (v - 0.5f) * 2.0f;
      float r = sqrtf(u * u + v * v);
      if (r > 1.0f) return 0;
      theta = r * c->pano0 * 0.5f;
    } else {
      u = (u - 0.5f) * c->pano2, v = (v - 0.5f) * c->pano3;
      float r = sqrtf(u * u + v * v), rmax = 2.0f * c->pano0 * sinf(c->pano1 * 0.25f);
      if (r > rmax) return 0;
      float x = fminf(r / (2.0f * c->pano0), 1.0f); /* 2 asin(x), as the shader computes it */
      theta = 2.0f * atan2f(x, sqrtf(fmaxf(1.0f - x * x, 0.0f)));
    }
    float r = sqrtf(u * u + v * v), cp = r != 0.0f ? u / r : 0.0f, sp = r != 0.0f ? v / r : 0.0f;
    /* phi = acos(u / r), negated below the centre: cos phi = u / r,
     * sin phi = v / r. */
    d[0] = cosf(theta), d[1] = -cp * sinf(theta), d[2] = sp * sinf(theta);
    return 1;
  }
  case PB_GPU_CAMERA_MIRRORBALL: {
    float x = 2.0f * u - 1.0f, z = 2.0f * v - 1.0f;
    if (x * x + z * z > 1.0f) return 0;
    float y = -sqrtf(fmaxf(1.0f - x * x - z * z, 0.0f));
    /* reflection of I = (0, -1, 0) about the ball's normal */
    float k = 2.0f * -y;
    d[0] = k * x, d[1] = k * y + 1.0f, d[2] = k * z;
    return 1;
  }
  default:
    return 0;
  }
}

/* Cycles' panorama frame to world: blender_camera_matrix turns it so that
 * the equirectangular and fisheye cameras look along +x (+y left, +z up)
 * and the mirror ball along -y (+x right, +z up). */
static void pano_to_world(const pb_gpu_camera *c, const float l[3], float w[3]) {
  for (int k = 0; k < 3; ++k)
    w[k] = c->projection == PB_GPU_CAMERA_MIRRORBALL ? l[0] * c->right[k] - l[1] * c->forward[k] + l[2] * c->up[k]
                                                     : l[0] * c->forward[k] - l[1] * c->right[k] + l[2] * c->up[k];
}

static void world_to_pano(const pb_gpu_camera *c, const float w[3], float l[3]) {
  float f = 0, r = 0, u = 0;
  for (int k = 0; k < 3; ++k) f += w[k] * c->forward[k], r += w[k] * c->right[k], u += w[k] * c->up[k];
  if (c->projection == PB_GPU_CAMERA_MIRRORBALL) l[0] = r, l[1] = -f, l[2] = u;
  else l[0] = f, l[1] = -r, l[2] = u;
}

/* The inverse of pano_direction for a unit direction: panorama (u, v);
 * 0 where the direction is outside the camera's field. */
static int pano_coords(const pb_gpu_camera *c, const float d[3], float *u, float *v) {
  switch (c->projection) {
  case PB_GPU_CAMERA_EQUIRECTANGULAR:
    /* direction_to_equirectangular_range */
    *u = (atan2f(d[1], d[0]) - c->pano1) / c->pano0;
    *v = (acosf(fmaxf(-1.0f, fminf(1.0f, d[2]))) - c->pano3) / c->pano2;
    return 1;
  case PB_GPU_CAMERA_FISHEYE_EQUIDISTANT:
  case PB_GPU_CAMERA_FISHEYE_EQUISOLID: {
    /* pano_direction's exact inverse (Cycles' direction_to_fisheye mirrors
     * u; its camera never calls it) */
    float theta = acosf(fmaxf(-1.0f, fminf(1.0f, d[0]))), rho = sqrtf(d[1] * d[1] + d[2] * d[2]);
    float cp = rho > 0.0f ? -d[1] / rho : 1.0f, sp = rho > 0.0f ? d[2] / rho : 0.0f;
    if (c->projection == PB_GPU_CAMERA_FISHEYE_EQUIDISTANT) {
      float r = 2.0f * theta / c->pano0;
      if (r > 1.0f) return 0;
      *u = 0.5f + 0.5f * r * cp, *v = 0.5f + 0.5f * r * sp;
    } else {
      float r = 2.0f * c->pano0 * sinf(0.5f * theta);
      if (theta > 0.5f * c->pano1) return 0;
      *u = 0.5f + r * cp / c->pano2, *v = 0.5f + r * sp / c->pano3;
    }
    return 1;
  }
  case PB_GPU_CAMERA_MIRRORBALL: { /* direction_to_mirrorball */
    float x = d[0], y = d[1] - 1.0f, z = d[2], div = 2.0f * sqrtf(fmaxf(-0.5f * y, 0.0f));
    if (div > 0.0f) x /= div, z /= div;
    *u = 0.5f * (x + 1.0f), *v = 0.5f * (z + 1.0f);
    return 1;
  }
  default:
    return 0;
  }
}

int pb_camera_ray_lens(const pb_gpu_camera *v, float px, float py, const float lens[2], float org[3], float dir[3],
                       float *t0, float *tmax) {
  float sx = v->x0 + px * v->dx, sy = v->y0 + py * v->dy;
  float ax = 0.0f, ay = 0.0f;
  int thin = lens && v->aperture > 0.0f;
  if (thin) {
    aperture_point(v, lens[0], lens[1], &ax, &ay);
    ax *= v->aperture, ay *= v->aperture;
  }
  if (v->projection != PB_GPU_CAMERA_PLANAR) {
    /* camera_sample_panorama: the lens is the plane through the camera
     * normal to the pinhole ray (U from the frame's x, V = D x U), focused
     * at `focus` along that ray; the ray starts clip_near along itself and
     * runs clip_far - clip_near. */
    float l[3], p[3] = {0, 0, 0};
    if (!pano_direction(v, sx, sy, l)) {
      for (int k = 0; k < 3; ++k) org[k] = v->position[k], dir[k] = v->forward[k];
      *t0 = 0.0f, *tmax = 0.0f;
      return 0;
    }
    float n = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int k = 0; k < 3; ++k) l[k] /= n;
    if (thin) {
      float U[3] = {1.0f - l[0] * l[0], -l[0] * l[1], -l[0] * l[2]};
      float un = sqrtf(U[0] * U[0] + U[1] * U[1] + U[2] * U[2]);
      /* along the frame's x itself Cycles' U is 0 / 0: any normal will do */
      if (!(un > 1e-6f)) U[0] = 0.0f, U[1] = 1.0f, U[2] = 0.0f, un = 1.0f;
      for (int k = 0; k < 3; ++k) U[k] /= un;
      float V[3] = {l[1] * U[2] - l[2] * U[1], l[2] * U[0] - l[0] * U[2], l[0] * U[1] - l[1] * U[0]};
      float dn = 0.0f;
      for (int k = 0; k < 3; ++k) {
        p[k] = U[k] * ax + V[k] * ay;
        l[k] = l[k] * v->focus - p[k];
        dn += l[k] * l[k];
      }
      dn = sqrtf(dn);
      for (int k = 0; k < 3; ++k) l[k] /= dn;
    }
    float pw[3];
    pano_to_world(v, p, pw);
    pano_to_world(v, l, dir);
    *t0 = v->clip_near;
    for (int k = 0; k < 3; ++k) org[k] = v->position[k] + pw[k] + dir[k] * *t0;
    *tmax = v->clip_far > 0.0f ? v->clip_far - v->clip_near : INFINITY;
    return 1;
  }
  float cz;
  if (v->orthographic) {
    /* camera_sample_orthographic (3.4): from the window point plus the
     * lens offset on the near plane, toward the point focus further along
     * forward from the lens centre's (so 3.4 focuses at clip_near + focus). */
    float d[3], len = 0.0f;
    for (int k = 0; k < 3; ++k) {
      org[k] = v->position[k] + v->right[k] * (sx + ax) + v->up[k] * (sy + ay) + v->forward[k] * v->clip_near;
      d[k] = v->forward[k] * (thin ? v->focus : 1.0f) - v->right[k] * ax - v->up[k] * ay;
      len += d[k] * d[k];
    }
    len = sqrtf(len);
    for (int k = 0; k < 3; ++k) dir[k] = d[k] / len;
    cz = dir[0] * v->forward[0] + dir[1] * v->forward[1] + dir[2] * v->forward[2];
    *t0 = v->clip_near / cz;
    *tmax = v->clip_far > 0.0f ? (v->clip_far - v->clip_near) / cz : INFINITY;
    return 1;
  }
  float len = 0.0f, pin[3];
  for (int k = 0; k < 3; ++k) {
    pin[k] = v->forward[k] + v->right[k] * sx + v->up[k] * sy;
    len += pin[k] * pin[k];
  }
  len = sqrtf(len);
  if (thin) {
    /* camera_sample_perspective: toward the pinhole ray's point at depth
     * focus from the lens point; clipped by the pinhole ray's cosine. */
    float dl = 0.0f;
    for (int k = 0; k < 3; ++k) {
      float a = v->right[k] * ax + v->up[k] * ay;
      org[k] = v->position[k] + a;
      dir[k] = pin[k] * v->focus - a;
      dl += dir[k] * dir[k];
    }
    dl = sqrtf(dl);
    for (int k = 0; k < 3; ++k) dir[k] /= dl;
    cz = 1.0f / len;
  } else {
    for (int k = 0; k < 3; ++k) {
      dir[k] = pin[k] / len;
      org[k] = v->position[k];
    }
    cz = dir[0] * v->forward[0] + dir[1] * v->forward[1] + dir[2] * v->forward[2];
  }
  /* Cycles' clipping: the ray starts on the near plane and ends on the far
   * one, distances along forward divided by the (pinhole) ray's cosine. */
  *t0 = v->clip_near / cz;
  for (int k = 0; k < 3; ++k) org[k] += dir[k] * *t0;
  *tmax = v->clip_far > 0.0f ? (v->clip_far - v->clip_near) / cz : INFINITY;
  return 1;
}

void pb_camera_ray(const pb_gpu_camera *v, float px, float py, float org[3], float dir[3], float *t0,
                   float *tmax) {
  (void)pb_camera_ray_lens(v, px, py, NULL, org, dir, t0, tmax);
}

int pb_camera_view_project(const pb_gpu_camera *v, const float p[3], float *x, float *y, float *depth) {
  float d[3] = {p[0] - v->position[0], p[1] - v->position[1], p[2] - v->position[2]};
  if (v->projection != PB_GPU_CAMERA_PLANAR) {
    float dist = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), l[3], u, w;
    if (!(dist > 0.0f)) return 0;
    for (int k = 0; k < 3; ++k) d[k] /= dist;
    world_to_pano(v, d, l);
    if (!pano_coords(v, l, &u, &w)) return 0;
    *x = (u - v->x0) / v->dx;
    *y = (w - v->y0) / v->dy;
    *depth = dist;
    return isfinite(*x) && isfinite(*y);
  }
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
  /* Panoramas: the angle one pixel spans at the image's centre, times z. */
  switch (v->projection) {
  case PB_GPU_CAMERA_EQUIRECTANGULAR: return fabsf(v->pano2 * v->dy) * z;
  case PB_GPU_CAMERA_FISHEYE_EQUIDISTANT: return fabsf(v->pano0 * v->dy) * z;
  case PB_GPU_CAMERA_FISHEYE_EQUISOLID: return fabsf(v->pano3 * v->dy / v->pano0) * z;
  case PB_GPU_CAMERA_MIRRORBALL: return fabsf(4.0f * v->dy) * z;
  default: return v->orthographic ? fabsf(v->dy) : fabsf(v->dy) * z;
  }
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
  if (b->type && strcmp(b->type, "PERSP") != 0 && strcmp(b->type, "ORTHO") != 0 && strcmp(b->type, "PANO") != 0)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: " EXT ".type: '%s' is not PERSP, ORTHO or PANO", path, ci,
                   b->type);
  out->orthographic = b->type && strcmp(b->type, "ORTHO") == 0;
  if (b->type && strcmp(b->type, "PANO") == 0) {
    /* Blender's default panorama type is FISHEYE_EQUISOLID (DNA_camera_defaults.h) */
    static const struct { const char *name; pb_camera_panorama p; } pano[] = {
        {"EQUIRECTANGULAR", PB_CAMERA_PANO_EQUIRECTANGULAR},
        {"FISHEYE_EQUIDISTANT", PB_CAMERA_PANO_FISHEYE_EQUIDISTANT},
        {"FISHEYE_EQUISOLID", PB_CAMERA_PANO_FISHEYE_EQUISOLID},
        {"MIRRORBALL", PB_CAMERA_PANO_MIRRORBALL}};
    const char *t = b->panorama_type ? b->panorama_type : "FISHEYE_EQUISOLID";
    for (size_t i = 0; i < sizeof pano / sizeof *pano; ++i)
      if (strcmp(t, pano[i].name) == 0) out->panorama = pano[i].p;
    if (!out->panorama)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: " EXT ".panoramaType: '%s' is not EQUIRECTANGULAR, "
                     "FISHEYE_EQUIDISTANT, FISHEYE_EQUISOLID or MIRRORBALL", path, ci, t);
  }
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
  out->sensor[0] = sw, out->sensor[1] = sh;
  /* Panoramas: Blender 3.4's defaults (DNA_camera_defaults.h) and RNA
   * ranges (latitude within +-pi/2, longitude within +-pi; a little slack
   * for the file's decimal digits). */
  const double half_pi = 0.5 * M_PI + 1e-6, pi = M_PI + 1e-6;
  if ((r = ext_number(path, ci, "fisheyeFov", b->fisheye_fov, M_PI, 0.0, 0, &out->fisheye_fov)) != PB_OK ||
      (r = ext_number(path, ci, "fisheyeLens", b->fisheye_lens, 10.5, 0.0, 0, &out->fisheye_lens)) != PB_OK ||
      (r = ext_number(path, ci, "latitudeMin", b->latitude_min, -0.5 * M_PI, -half_pi, 1, &out->latitude[0])) != PB_OK ||
      (r = ext_number(path, ci, "latitudeMax", b->latitude_max, 0.5 * M_PI, -half_pi, 1, &out->latitude[1])) != PB_OK ||
      (r = ext_number(path, ci, "longitudeMin", b->longitude_min, -M_PI, -pi, 1, &out->longitude[0])) != PB_OK ||
      (r = ext_number(path, ci, "longitudeMax", b->longitude_max, M_PI, -pi, 1, &out->longitude[1])) != PB_OK)
    return r;
  if (out->latitude[0] > half_pi || out->latitude[1] > half_pi)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT ".%s: %g is above pi/2", path, ci,
                   out->latitude[0] > half_pi ? "latitudeMin" : "latitudeMax",
                   (double)(out->latitude[0] > half_pi ? out->latitude[0] : out->latitude[1]));
  if (out->longitude[0] > pi || out->longitude[1] > pi)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT ".%s: %g is above pi", path, ci,
                   out->longitude[0] > pi ? "longitudeMin" : "longitudeMax",
                   (double)(out->longitude[0] > pi ? out->longitude[0] : out->longitude[1]));
  /* Depth of field: present when apertureFstop is (the writer writes the
   * members only for use_dof). Cycles 3.4 blender/camera.cpp: radius =
   * lens[mm] 1e-3 / (2 f-stop), 1 / (2 f-stop) for an orthographic camera;
   * f-stop clamped to 1e-5 there, required positive here. */
  if (!isnan(b->aperture_fstop)) {
    float fstop = 0, blades = 0;
    if ((r = ext_number(path, ci, "apertureFstop", b->aperture_fstop, 0.0, 0.0, 0, &fstop)) != PB_OK ||
        (r = ext_number(path, ci, "focusDistance", b->focus_distance, 10.0, 0.0, 1, &out->focus_distance)) != PB_OK ||
        (r = ext_number(path, ci, "apertureBlades", b->aperture_blades, 0.0, 0.0, 1, &blades)) != PB_OK ||
        (r = ext_number(path, ci, "apertureRotation", b->aperture_rotation, 0.0, -FLT_MAX, 1,
                        &out->aperture_rotation)) != PB_OK ||
        (r = ext_number(path, ci, "apertureRatio", b->aperture_ratio, 1.0, 0.0, 0, &out->aperture_ratio)) != PB_OK)
      return r;
    if (blades != floorf(blades) || blades > 1000.0f)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: " EXT ".apertureBlades: %g is not a whole number up to 1000", path,
                     ci, (double)blades);
    out->aperture_blades = (uint32_t)blades;
    out->aperture_radius = (float)((out->orthographic ? 1.0 : lens * 1e-3) / (2.0 * fstop));
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
