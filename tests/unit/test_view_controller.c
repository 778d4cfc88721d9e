/* The viewer's camera controller (view/controller.h), window-free: an orbit
 * keeps the distance to the pivot and the pivot on the camera's axis, turns
 * by pi per window height of drag and stops short of the poles; pan moves
 * camera and pivot together, the pivot's point following the cursor; dolly
 * scales the distance by 0.85 a notch; fly moves at half the scene radius a
 * second; the frame stays orthonormal and right-handed throughout. */
#include <math.h>
#include <string.h>

#include "pbtest.h"
#include "view/controller.h"

static double dot3(const float *a, const float *b) { return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]; }

static double dist(const pb_view_controller *v) {
  double d = 0;
  for (int i = 0; i < 3; ++i) d += ((double)v->cam.position[i] - v->pivot[i]) * ((double)v->cam.position[i] - v->pivot[i]);
  return sqrt(d);
}

static void check_frame(const pb_camera *c) {
  CHECK_NEAR(dot3(c->forward, c->forward), 1.0, 1e-5);
  CHECK_NEAR(dot3(c->up, c->up), 1.0, 1e-5);
  CHECK_NEAR(dot3(c->forward, c->up), 0.0, 1e-5);
  CHECK_NEAR(dot3(c->right, c->forward), 0.0, 1e-5);
  /* right = forward x up */
  CHECK_NEAR(c->right[0], c->forward[1] * c->up[2] - c->forward[2] * c->up[1], 1e-5);
  CHECK_NEAR(c->right[1], c->forward[2] * c->up[0] - c->forward[0] * c->up[2], 1e-5);
}

/* The pivot lies on the camera's axis, in front. */
static void check_axis(const pb_view_controller *v) {
  float to[3] = {v->pivot[0] - v->cam.position[0], v->pivot[1] - v->cam.position[1], v->pivot[2] - v->cam.position[2]};
  CHECK_NEAR(dot3(to, v->cam.forward), dist(v), 1e-4 * dist(v));
}

static void drag(pb_view_controller *v, double dx, double dy, int button) {
  pb_view_controller_cursor(v, 100, 100, 200);
  pb_view_controller_button(v, button, 1);
  pb_view_controller_cursor(v, 100 + dx, 100 + dy, 200);
  pb_view_controller_button(v, button, 0);
}

int main(void) {
  pb_camera c;
  memset(&c, 0, sizeof c);
  c.position[2] = 4;  /* at +Z, looking down -Z at the origin */
  c.forward[2] = -1, c.up[1] = 1, c.right[0] = 1;
  c.yfov = 0.8f;
  float bmin[3] = {-1, -1, -1}, bmax[3] = {1, 1, 1};
  pb_view_controller v;
  memset(&v, 0, sizeof v);
  pb_view_controller_reset(&v, &c, bmin, bmax);
  CHECK_NEAR(v.pivot[2], 0.0, 1e-6);
  CHECK_NEAR(v.scene_radius, sqrt(3.0), 1e-5);

  /* Orbit: 100 px of a 200 px window is a quarter turn about +Y. Dragging
   * right moves the camera to the left around the pivot (the scene turns
   * with the cursor, as in Blender). */
  drag(&v, 100, 0, PB_VIEW_BUTTON_LEFT);
  CHECK_NEAR(dist(&v), 4.0, 1e-4);
  CHECK_NEAR(v.cam.position[0], -4.0, 1e-4);
  CHECK_NEAR(v.cam.position[2], 0.0, 1e-4);
  CHECK_NEAR(v.cam.up[1], 1.0, 1e-5);
  check_frame(&v.cam);
  check_axis(&v);
  CHECK_EQ_INT((int)v.moves, 1);
  /* Pitch: 50 px up is pi/4 of elevation; 1000 px more stops below the pole. */
  drag(&v, 0, 50, PB_VIEW_BUTTON_LEFT);
  CHECK_NEAR(asin(v.cam.forward[1]), -M_PI / 4, 1e-4);
  CHECK_NEAR(dist(&v), 4.0, 1e-4);
  drag(&v, 0, 1000, PB_VIEW_BUTTON_LEFT);
  CHECK_NEAR(asin(v.cam.forward[1]), -(M_PI / 2 - 0.01), 1e-3);
  check_frame(&v.cam);
  check_axis(&v);

  /* Pan (middle, and shift + left): camera and pivot move together by the
   * pivot depth's metres per pixel, 2 d tan(yfov/2) / height. */
  pb_view_controller_reset(&v, &c, bmin, bmax);
  drag(&v, 20, 0, PB_VIEW_BUTTON_MIDDLE);
  double m = 2.0 * 4.0 * tan(0.4) / 200.0;
  CHECK_NEAR(v.cam.position[0], -20 * m, 1e-5);
  CHECK_NEAR(v.pivot[0], -20 * m, 1e-5);
  CHECK_NEAR(dist(&v), 4.0, 1e-5);
  pb_view_controller_shift(&v, 1);
  drag(&v, 0, 10, PB_VIEW_BUTTON_LEFT);
  pb_view_controller_shift(&v, 0);
  CHECK_NEAR(v.cam.position[1], 10 * m, 1e-5);
  CHECK_NEAR(v.cam.forward[2], -1.0, 1e-6); /* no rotation */

  /* Dolly: two notches closer. */
  pb_view_controller_reset(&v, &c, bmin, bmax);
  pb_view_controller_scroll(&v, 2);
  CHECK_NEAR(dist(&v), 4.0 * 0.85 * 0.85, 1e-4);
  check_axis(&v);

  /* Fly: W for 2 s at half the radius a second; W+D together; the pivot
   * comes along; no key, no move. */
  pb_view_controller_reset(&v, &c, bmin, bmax);
  unsigned before = v.moves;
  pb_view_controller_tick(&v, 1.0);
  CHECK_EQ_INT((int)v.moves, (int)before);
  pb_view_controller_fly_key(&v, PB_VIEW_FLY_FORWARD, 1);
  pb_view_controller_tick(&v, 2.0);
  CHECK_NEAR(v.cam.position[2], 4.0 - sqrt(3.0), 1e-4);
  CHECK_NEAR(dist(&v), 4.0, 1e-4);
  pb_view_controller_fly_key(&v, PB_VIEW_FLY_RIGHT, 1);
  pb_view_controller_fly_key(&v, PB_VIEW_FLY_FORWARD, 0);
  pb_view_controller_fly_key(&v, PB_VIEW_FLY_UP, 1);
  pb_view_controller_tick(&v, 1.0);
  CHECK_NEAR(v.cam.position[0], 0.5 * sqrt(3.0), 1e-4);
  CHECK_NEAR(v.cam.position[1], 0.5 * sqrt(3.0), 1e-4);
  CHECK(v.moves > before);
  return pbt_done();
}
