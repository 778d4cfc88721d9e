/* Camera controller (controller.h). Rotations by Rodrigues' formula on the
 * camera's position about the pivot and on its frame; the frame is
 * re-orthonormalised after every step so that float drift never skews it. */
#include "view/controller.h"

#include <math.h>
#include <string.h>

static void cross(const float a[3], const float b[3], float o[3]) {
  float t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  memcpy(o, t, sizeof t);
}
static float dot(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static int normalize(float v[3]) {
  float l = sqrtf(dot(v, v));
  if (!(l > 1e-20f)) return 0;
  v[0] /= l, v[1] /= l, v[2] /= l;
  return 1;
}

/* v rotated by angle a (radians) about unit axis k. */
static void rotate(float v[3], const float k[3], float a) {
  float c = cosf(a), s = sinf(a), kv[3], d = dot(k, v);
  cross(k, v, kv);
  for (int i = 0; i < 3; ++i) v[i] = v[i] * c + kv[i] * s + k[i] * d * (1.0f - c);
}

/* forward and up orthonormal again, right = forward x up (right-handed,
 * as pb_camera's frame). */
static void orthonormalize(pb_camera *c) {
  if (!normalize(c->forward)) return;
  float d = dot(c->up, c->forward);
  for (int i = 0; i < 3; ++i) c->up[i] -= d * c->forward[i];
  if (!normalize(c->up)) return;
  cross(c->forward, c->up, c->right);
  normalize(c->right);
}

static float pivot_distance(const pb_view_controller *v) {
  float d[3] = {v->pivot[0] - v->cam.position[0], v->pivot[1] - v->cam.position[1], v->pivot[2] - v->cam.position[2]};
  return sqrtf(dot(d, d));
}

void pb_view_controller_reset(pb_view_controller *v, const pb_camera *c, const float bmin[3], const float bmax[3]) {
  v->cam = *c;
  float centre[3], diag2 = 0;
  for (int i = 0; i < 3; ++i) {
    centre[i] = 0.5f * (bmin[i] + bmax[i]);
    diag2 += (bmax[i] - bmin[i]) * (bmax[i] - bmin[i]);
  }
  v->scene_radius = 0.5f * sqrtf(diag2) > 1e-6f ? 0.5f * sqrtf(diag2) : 1.0f;
  float to[3] = {centre[0] - c->position[0], centre[1] - c->position[1], centre[2] - c->position[2]};
  float depth = dot(to, c->forward);
  if (!(depth > 1e-3f * v->scene_radius)) depth = sqrtf(dot(to, to)) > 1e-6f ? sqrtf(dot(to, to)) : v->scene_radius;
  for (int i = 0; i < 3; ++i) v->pivot[i] = c->position[i] + depth * c->forward[i];
}

void pb_view_controller_button(pb_view_controller *v, int button, int down) {
  if (button < 0 || button > 2) return;
  if (down) v->buttons |= 1u << button;
  else v->buttons &= ~(1u << button);
}

void pb_view_controller_shift(pb_view_controller *v, int down) { v->shift = down; }

static void orbit(pb_view_controller *v, float dx, float dy, float height) {
  const float world_up[3] = {0, 1, 0};
  float per_px = (float)M_PI / (height > 1 ? height : 1);
  float off[3] = {v->cam.position[0] - v->pivot[0], v->cam.position[1] - v->pivot[1], v->cam.position[2] - v->pivot[2]};
  /* Yaw about world up through the pivot. */
  float yaw = -dx * per_px;
  rotate(off, world_up, yaw);
  rotate(v->cam.forward, world_up, yaw);
  rotate(v->cam.up, world_up, yaw);
  orthonormalize(&v->cam);
  /* Pitch about the camera's right axis, stopped short of the poles (the
   * forward axis within 0.01 rad of world up), where yaw would spin it. */
  float pitch = -dy * per_px;
  float elev = asinf(fmaxf(-1.0f, fminf(1.0f, v->cam.forward[1])));
  const float lim = (float)M_PI / 2 - 0.01f;
  if (elev + pitch > lim) pitch = lim - elev;
  if (elev + pitch < -lim) pitch = -lim - elev;
  float axis[3] = {v->cam.right[0], v->cam.right[1], v->cam.right[2]};
  rotate(off, axis, pitch);
  rotate(v->cam.forward, axis, pitch);
  rotate(v->cam.up, axis, pitch);
  orthonormalize(&v->cam);
  for (int i = 0; i < 3; ++i) v->cam.position[i] = v->pivot[i] + off[i];
}

static void pan(pb_view_controller *v, float dx, float dy, float height) {
  /* Metres per pixel at the pivot's depth: the window spans 2 d tan(fov/2)
   * (yfov spans the fitted side; the vertical one for glTF cameras, a close
   * enough pan rate for the others) or the orthographic size. */
  float h = height > 1 ? height : 1;
  float m = v->cam.orthographic ? v->cam.ortho_size / h : 2.0f * pivot_distance(v) * tanf(0.5f * v->cam.yfov) / h;
  for (int i = 0; i < 3; ++i) {
    float d = (-dx * v->cam.right[i] + dy * v->cam.up[i]) * m;
    v->cam.position[i] += d;
    v->pivot[i] += d;
  }
}

void pb_view_controller_cursor(pb_view_controller *v, double x, double y, double height) {
  if (v->has_last && v->buttons) {
    float dx = (float)(x - v->last_x), dy = (float)(y - v->last_y);
    if (dx != 0 || dy != 0) {
      int panning = (v->buttons & (1u << PB_VIEW_BUTTON_MIDDLE)) || v->shift;
      if (panning) pan(v, dx, dy, (float)height);
      else if (v->buttons & (1u << PB_VIEW_BUTTON_LEFT)) orbit(v, dx, dy, (float)height);
      v->moves++;
    }
  }
  v->last_x = x, v->last_y = y, v->has_last = 1;
}

void pb_view_controller_scroll(pb_view_controller *v, double dy) {
  if (dy == 0) return;
  float k = powf(0.85f, (float)dy);
  if (v->cam.orthographic) {
    v->cam.ortho_size *= k;
  } else {
    float d = pivot_distance(v), nd = d * k;
    if (nd < 1e-4f * v->scene_radius) nd = 1e-4f * v->scene_radius;
    for (int i = 0; i < 3; ++i) v->cam.position[i] = v->pivot[i] - v->cam.forward[i] * nd;
  }
  v->moves++;
}

void pb_view_controller_fly_key(pb_view_controller *v, unsigned bit, int down) {
  if (down) v->fly |= bit;
  else v->fly &= ~bit;
}

void pb_view_controller_tick(pb_view_controller *v, double dt) {
  if (!v->fly || !(dt > 0)) return;
  float step = 0.5f * v->scene_radius * (float)dt, d[3] = {0, 0, 0};
  const float up[3] = {0, 1, 0};
  struct { unsigned bit; const float *axis; float sign; } keys[] = {
      {PB_VIEW_FLY_FORWARD, v->cam.forward, 1}, {PB_VIEW_FLY_BACK, v->cam.forward, -1},
      {PB_VIEW_FLY_RIGHT, v->cam.right, 1},     {PB_VIEW_FLY_LEFT, v->cam.right, -1},
      {PB_VIEW_FLY_UP, up, 1},                  {PB_VIEW_FLY_DOWN, up, -1}};
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
    if (v->fly & keys[k].bit)
      for (int i = 0; i < 3; ++i) d[i] += keys[k].sign * keys[k].axis[i] * step;
  if (d[0] == 0 && d[1] == 0 && d[2] == 0) return;
  for (int i = 0; i < 3; ++i) v->cam.position[i] += d[i], v->pivot[i] += d[i];
  v->moves++;
}
