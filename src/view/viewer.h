/* `photonbridge view`: the interactive window (cmd_view.c parses the
 * options). The loop, one frame at a time:
 *
 *   input (GLFW callbacks, or the --script events due at this frame; both
 *   call the same handlers) -> the camera controller (controller.h) ->
 *   pb_sequence_frame (render/frame/sequence.h, as `render --frames` drives it):
 *   a frame where nothing moved refines the previous ones (progressive:
 *   the temporal filter's cumulative mean of the indirect light, the
 *   running mean of the rest, jittered samples, and with --progressive the
 *   shrinking footprints), a frame where the camera, the time or a light
 *   moved restarts the run and reprojects the indirect light's history
 *   (temporal filter + A-Trous) -> the chosen AOV through the OCIO view
 *   (pb_color_apply_display, the function `display` uses, so the window
 *   shows display's PNG) -> the swapchain (present.h) -> the window title
 *   as the heads-up line.
 *
 * Keys: 1-9 and [ ] the glTF cameras, Home back to the scene camera, left
 * drag orbit, middle or shift+left drag pan, wheel dolly, WASD + QE fly,
 * space play/pause, Tab / F1-F8 the AOV (beauty, direct, indirect,
 * caustic, emission, albedo, normal, depth), + / - exposure by 1/2 stop,
 * 0 exposure back, P or F12 save EXR + PNG, Esc close. */
#ifndef PB_VIEW_VIEWER_H
#define PB_VIEW_VIEWER_H

#include <stdint.h>

#include "color/color.h"
#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "render/frame/sequence.h"
#include "scene/scene.h"

typedef struct pb_view_desc {
  pb_sequence_desc seq;      /* every frame's settings (render --frames') */
  int camera;                /* the scene camera (index into s->cameras) */
  uint32_t width, height;    /* rendered image; the window starts this size */
  pb_color_desc color;       /* the view (exposure is the start value) */
  uint32_t exit_after;       /* close after this many frames; 0: never */
  const char *screenshot;    /* PNG of the shown image at exit, or NULL */
  const char *script;        /* timed synthetic input events, or NULL */
  const char *reference;     /* EXR for the heads-up PSNR, or NULL */
  double noise_threshold;    /* a still view rests once its own noise estimate is at most this; 0: never */
  const char *save_prefix;   /* P / F12 write PREFIX_NNNN.exr and .png */
  const char *json;          /* per-frame statistics at exit, or NULL */
  int validation;            /* validation layer on the presenter too */
  int quiet;
} pb_view_desc;

/* Runs the window until it is closed, Esc, or exit_after frames. Errors:
 * PB_ERR_NOT_AVAILABLE without a display (one line suggesting `render`),
 * PB_ERR_USAGE (a bad --script line, named by file and line; a reference of
 * another size), the renderer's and the presenter's (PB_ERR_DEVICE_LOST
 * included) and the writers'. */
pb_result pb_view_run(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, const pb_view_desc *d);

/* PB_ERR_NOT_AVAILABLE (one line suggesting `render`) when the environment
 * names no display (DISPLAY, WAYLAND_DISPLAY): checked before the scene
 * loads; pb_view_run checks it again, and that GLFW can open it. */
pb_result pb_view_check_display(void);
/* Fills gd's presentation fields (gpu.h) so that the render device can also
 * present to the viewer's window (the presenter then shares it,
 * present.h): GLFW's instance extensions and its presentation test. Leaves
 * gd alone when GLFW cannot start here (pb_view_run then says why). */
struct pb_gpu_desc;
void pb_view_gpu_desc(struct pb_gpu_desc *gd);

/* Validation messages the presenter's Vulkan instance reported in this
 * process (the renderer's are pb_gpu_validation_total's). */
uint32_t pb_view_validation_total(void);

#endif
