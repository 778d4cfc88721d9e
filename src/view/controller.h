/* The viewer's camera controller: mouse and key input to a pb_camera, the
 * one code path that both the window's GLFW callbacks and a --script of
 * synthetic events drive (viewer.c). No window-system dependency.
 *
 *   orbit  left drag: yaw about world +Y (glTF's up) and pitch about the
 *          camera's right axis, both through the pivot; pi radians per
 *          window height of drag (a half turn across the window, as
 *          Blender's turntable orbit at its default sensitivity feels)
 *   pan    middle drag, or shift + left drag: camera and pivot move in the
 *          image plane so that the point at the pivot's depth follows the
 *          cursor
 *   dolly  wheel: the distance to the pivot times 0.85 per notch (ortho:
 *          the orthographic size)
 *   fly    W/S forward/back, A/D left/right, E/Q up/down along world Y, at
 *          half the scene's bounding radius per second (crossing a room in
 *          about 4 s); the pivot moves with the camera
 *
 * Units: positions in metres (scene units), cursor positions in window
 * pixels, dt in seconds. */
#ifndef PB_VIEW_CONTROLLER_H
#define PB_VIEW_CONTROLLER_H

#include "scene/scene.h"

enum {
  PB_VIEW_BUTTON_LEFT = 0,
  PB_VIEW_BUTTON_MIDDLE = 1,
  PB_VIEW_BUTTON_RIGHT = 2,
};

/* Fly keys, bits of pb_view_controller.fly. */
enum {
  PB_VIEW_FLY_FORWARD = 1 << 0, PB_VIEW_FLY_BACK = 1 << 1, PB_VIEW_FLY_LEFT = 1 << 2,
  PB_VIEW_FLY_RIGHT = 1 << 3, PB_VIEW_FLY_UP = 1 << 4, PB_VIEW_FLY_DOWN = 1 << 5,
};

typedef struct pb_view_controller {
  pb_camera cam;        /* the view camera */
  float pivot[3];       /* orbit and dolly centre, metres */
  float scene_radius;   /* half the bounds' diagonal, metres (speeds) */
  unsigned buttons;     /* 1 << PB_VIEW_BUTTON_* held */
  int shift;            /* shift held (left drag pans) */
  double last_x, last_y;
  int has_last;         /* last_x/last_y hold a cursor position */
  unsigned fly;         /* PB_VIEW_FLY_* held */
  unsigned moves;       /* counts every input that moved the camera */
} pb_view_controller;

/* Starts from camera c of a scene with bounds [bmin, bmax]: the pivot is the
 * point on c's axis at the depth of the bounds' centre (the centre's
 * distance when it lies behind c). Keeps held buttons and keys. */
void pb_view_controller_reset(pb_view_controller *v, const pb_camera *c, const float bmin[3], const float bmax[3]);

void pb_view_controller_button(pb_view_controller *v, int button, int down);
void pb_view_controller_shift(pb_view_controller *v, int down);
/* Cursor moved to (x, y) in a window of `height` pixels: orbits or pans
 * while a button is held. */
void pb_view_controller_cursor(pb_view_controller *v, double x, double y, double height);
/* Wheel: dy notches, positive away from the user (closer). */
void pb_view_controller_scroll(pb_view_controller *v, double dy);
void pb_view_controller_fly_key(pb_view_controller *v, unsigned bit, int down);
/* Advances the fly movement by dt seconds (nothing when no fly key is held). */
void pb_view_controller_tick(pb_view_controller *v, double dt);

#endif
