/* photonbridge view SCENE: the interactive window (src/view/viewer.h). This
 * file only parses the options, loads the scene and the GPU, and hands them
 * to the viewer; without GLFW at build time the command exists and says so. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/settings_opts.h"
#include "app/color_opts.h"
#include "core/log.h"
#include "gpu/gpu.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "render/frame/sequence.h"
#ifdef PB_HAVE_GLFW
#include "view/viewer.h"
#endif

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_view) return &pb_commands[i];
  return NULL;
}

int pb_cmd_view(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  pb_color_opts co = {0};
  pb_live_opts lo;
  pb_live_opts_init(&lo);
  uint32_t exit_after = 0, in_flight = 1;
  const char *screenshot = NULL, *script = NULL, *reference = NULL, *save = "photonbridge_view";
  const pb_opt rows[] = {
      {"width", 0, PB_OPT_U32, &c.width, "W", "image width (default 640, or from --height and the camera's aspect)",
       NULL, 1, 16384, "Output", 0},
      {"height", 0, PB_OPT_U32, &c.height, "H", "image height (default from the camera's aspect ratio)", NULL, 1, 16384, "Output", 0},
      {"camera", 0, PB_OPT_STRING, &c.camera, "NAME|N", "the scene camera to start from (default: 0)", NULL, 0, 0, "Output", 0},
      {"seed", 0, PB_OPT_U64, &c.seed, "N", "random seed (default 0; frame i of the run uses it mixed with i, as "
       "render --frames)", NULL, 0, 0, "Sampling", 0},
      PB_SCENE_OPTS(&c),
      PB_COLOR_OPTS(&co),
      PB_DEVICE_OPTS(&lo),
      {"reference", 0, PB_OPT_STRING, &reference, "FILE.exr", "show the PSNR of every frame against this image "
       "(compare's metric) in the heads-up line", NULL, 0, 0, "Window", 0},
      {"save", 0, PB_OPT_STRING, &save, "PREFIX", "P / F12 write PREFIX_NNNN.exr (every AOV) and PREFIX_NNNN.png "
       "(what is shown; default photonbridge_view)", NULL, 0, 0, "Window", 0},
      {"frames-in-flight", 0, PB_OPT_U32, &in_flight, "N", "1 (default): each frame is shown once rendered; 2: the "
       "window shows the frame before the one rendering, whose last GPU pass runs while the host makes the "
       "picture and presents (one frame more latency; --exit-after and --script count shown frames)", NULL, 1, 2, "Window", PB_OPT_ADVANCED},
      {"exit-after", 0, PB_OPT_U32, &exit_after, "N", "close after N frames (scripts, tests)", NULL, 1, 10000000, "Window", PB_OPT_ADVANCED},
      {"screenshot", 0, PB_OPT_STRING, &screenshot, "FILE.png", "at exit, write the shown image (the frame's pixels, "
       "8-bit, before scaling to the window)", NULL, 0, 0, "Window", PB_OPT_ADVANCED},
      {"script", 0, PB_OPT_STRING, &script, "FILE", "synthetic input: lines 'FRAME ACTION ARGS' (cursor X Y, press|"
       "release left|middle|right, scroll DY, key|keydown|keyup NAME, resize W H, screenshot FILE), through the "
       "handlers the mouse and keyboard use", NULL, 0, 0, "Window", PB_OPT_ADVANCED},
  };
  /* The settings' rows (the table, render/settings.h), then the rest. */
  pb_opt opts[128];
  size_t nopts = 0;
  pb_settings_opts(&lo.set, PB_SURFACE_LIVE, opts, &nopts, 128);
  pb_opts_append(opts, &nopts, 128, rows, sizeof rows / sizeof *rows);
  const char *pos[1];
  size_t npos;
  int help;
  unsigned char given[128];
  pb_result r = pb_cli_parse_given(cmd, argc, argv, opts, nopts, pos, 1, &npos, &help, given);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  pb_settings_mark_given(&lo.set, opts, given, nopts);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, nopts,
                      "Mouse: left drag orbit, middle or shift+left drag pan, wheel dolly. Keys: W A S D + Q E fly,\n"
                      "1-9 and [ ] the scene's cameras, Home back to the scene camera, space play/pause the\n"
                      "animation, Tab or F1-F8 the AOV (beauty, direct, indirect, caustic, emission, albedo,\n"
                      "normal, depth), + / - exposure by 1/2 stop, 0 exposure back, P or F12 save EXR + PNG,\n"
                      "Esc close. A still view refines frame after frame as 'render --frames' does on a still\n"
                      "camera; any move restarts it (temporal + A-Trous filtering of the indirect light).\n"
                      "The window title is the heads-up line.");
    return 0;
  }
  if (npos != 1)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "view: expected SCENE (see 'photonbridge view --help')"));
  pb_sequence_desc seq;
  if ((r = pb_live_sequence_desc("view", &lo, c.seed, &seq)) != PB_OK) return pb_cli_exit(cmd, r);
#ifndef PB_HAVE_GLFW
  return pb_cli_exit(cmd, pb_fail(PB_ERR_NOT_AVAILABLE, "view: this photonbridge was built without GLFW (install "
                                  "libglfw3-dev and rebuild); render to a file with 'photonbridge render'"));
#else
  if ((r = pb_view_check_display()) != PB_OK) return pb_cli_exit(cmd, r);
  pb_scene s;
  if ((r = pb_cli_load_scene(pos[0], &c, &s)) != PB_OK) return pb_cli_exit(cmd, r);
  pb_gpu *g = NULL;
  pb_gpu_scene gs;
  memset(&gs, 0, sizeof gs);
  int camera;
  uint32_t w, h;
  if ((r = pb_cli_pick_camera(&s, &c, &camera, &w, &h)) != PB_OK) goto done;
  if (r == PB_OK) pb_cli_warn_clip("view", &s, camera);
  pb_gpu_desc gd = {.device_set = lo.device != UINT32_MAX, .device = lo.device, .validation = lo.validation,
                    .traversal = lo.traversal};
  pb_view_gpu_desc(&gd); /* the window presents through the render device (view/present.h) */
  if ((r = pb_gpu_create(&gd, &g)) != PB_OK) goto done;
  pb_cli_warn_cpu_device("view", g);
  if ((r = pb_gpu_scene_create(g, &s, &gs)) != PB_OK) goto done;
  pb_sequence_desc sd = seq;
  sd.frames_in_flight = in_flight;
  pb_view_desc vd = {
      .seq = sd,
      .camera = camera, .width = w, .height = h,
      .color = {co.ocio_config, co.display, co.view, co.look, co.exposure, co.gamma, PB_COLOR_PICTURE},
      .exit_after = exit_after, .screenshot = screenshot, .script = script, .reference = reference,
      .noise_threshold = lo.set.noise_threshold, .save_prefix = save, .json = c.json, .validation = lo.validation || pb_gpu_validation_enabled(g), .quiet = c.quiet};
  r = pb_view_run(g, &s, &gs, &vd);
  if (r == PB_OK && pb_view_validation_total())
    r = pb_fail(PB_ERR_VULKAN, "view: Vulkan validation reported %u message%s on the window's device (printed above)",
                pb_view_validation_total(), pb_view_validation_total() == 1 ? "" : "s");
done:
  pb_gpu_scene_destroy(g, &gs);
  pb_gpu_destroy(g);
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
#endif
}
