/* photonbridge view SCENE: the interactive window (src/view/viewer.h). This
 * file only parses the options, loads the scene and the GPU, and hands them
 * to the viewer; without GLFW at build time the command exists and says so. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "color/color_cli.h"
#include "core/log.h"
#include "gpu/gpu.h"
#include "render/photon.h"
#include "render/render.h"
#include "render/sequence.h"
#ifdef PB_HAVE_GLFW
#include "view/viewer.h"
#endif

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_view) return &pb_commands[i];
  return NULL;
}

static const char *const first_bounce_names[] = {"traced", "rsm", NULL};

int pb_cmd_view(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  pb_color_opts co = {0};
  uint32_t spp = 0, max_spec = 0, photons = 0, iterations = 0, bounces = 0, atrous = 4, device = UINT32_MAX;
  uint32_t exit_after = 0;
  int direct_only = 0, progressive = 0, no_temporal = 0, validation = 0, first_bounce = 0;
  double smoothing = 0, r_max = 0, alpha = 0, atrous_gamma = -1;
  const char *screenshot = NULL, *script = NULL, *reference = NULL, *save = "photonbridge_view";
  const pb_opt opts[] = {
      {"width", 0, PB_OPT_U32, &c.width, "W", "image width (default 640, or from --height and the camera's aspect)",
       NULL, 1, 16384},
      {"height", 0, PB_OPT_U32, &c.height, "H", "image height (default from the camera's aspect ratio)", NULL, 1, 16384},
      {"camera", 0, PB_OPT_STRING, &c.camera, "NAME|N", "the scene camera to start from (default: 0)", NULL, 0, 0},
      {"seed", 0, PB_OPT_U64, &c.seed, "N", "random seed (default 0; frame i of the run uses it mixed with i, as "
       "render --frames)", NULL, 0, 0},
      PB_SCENE_OPTS(&c),
      PB_COLOR_OPTS(&co),
      {"spp", 0, PB_OPT_U32, &spp, "N", "samples per pixel per frame (default 1)", NULL, 1, 1 << 20},
      {"max-specular-depth", 0, PB_OPT_U32, &max_spec, "N", "mirror/glass interactions along an eye path (default: Russian roulette from the 9th, cap 64)",
       NULL, 1, PB_RENDER_MAX_SPECULAR_DEPTH},
      {"direct-only", 0, PB_OPT_FLAG, &direct_only, NULL, "only paths with at most one scattering event", NULL, 0, 0},
      {"photons", 0, PB_OPT_U32, &photons, "N", "photon paths per map (default 2^18)", NULL, 1, 1u << 26},
      {"iterations", 0, PB_OPT_U32, &iterations, "K", "photon maps per frame (default 1)", NULL, 1, 1 << 16},
      {"photon-bounces", 0, PB_OPT_U32, &bounces, "N", "bounces stored per photon path (default: unbounded, Russian roulette, cap 255)", NULL, 1, 255},
      {"smoothing", 0, PB_OPT_FLOAT, &smoothing, "S", "footprint smoothing factor (default " PB_PHOTON_SMOOTHING_DEFAULT_STR ")",
       NULL, 0, 1e6},
      {"r-max", 0, PB_OPT_FLOAT, &r_max, "M", "footprint radius clamp in metres (default 5% of the scene radius)", NULL,
       0, 1e9},
      {"progressive", 0, PB_OPT_FLAG, &progressive, NULL, "footprints shrink from still frame to still frame "
       "(probabilistic SPPM), so a still view converges to the unbiased answer", NULL, 0, 0},
      {"alpha", 0, PB_OPT_FLOAT, &alpha, "A", "--progressive: radius^2 fraction kept per map, in (0, 1) (default 2/3)",
       NULL, 0, 0},
      {"first-bounce", 0, PB_OPT_CHOICE, &first_bounce, "MODE", "traced (default) or rsm", first_bounce_names, 0, 0},
      {"atrous-iterations", 0, PB_OPT_U32, &atrous, "N", "A-Trous passes on the indirect light (default 4, as "
       "render --frames)", NULL, 0, 12},
      {"atrous-clip", 0, PB_OPT_FLOAT, &atrous_gamma, "G", "A-Trous detail kept within G standard deviations "
       "(default 0.25)", NULL, 0, 100},
      {"no-temporal", 0, PB_OPT_FLAG, &no_temporal, NULL, "no temporal filter while moving (on by default)", NULL, 0, 0},
      {"device", 0, PB_OPT_U32, &device, "N", "Vulkan device for rendering (see 'photonbridge info --devices')", NULL,
       0, 0},
      {"validation", 0, PB_OPT_FLAG, &validation, NULL, "Vulkan validation layers on the renderer and the window; "
       "any message is an error (also PB_VK_VALIDATION=1)", NULL, 0, 0},
      {"reference", 0, PB_OPT_STRING, &reference, "FILE.exr", "show the PSNR of every frame against this image "
       "(compare's metric) in the heads-up line", NULL, 0, 0},
      {"save", 0, PB_OPT_STRING, &save, "PREFIX", "P / F12 write PREFIX_NNNN.exr (every AOV) and PREFIX_NNNN.png "
       "(what is shown; default photonbridge_view)", NULL, 0, 0},
      {"exit-after", 0, PB_OPT_U32, &exit_after, "N", "close after N frames (scripts, tests)", NULL, 1, 10000000},
      {"screenshot", 0, PB_OPT_STRING, &screenshot, "FILE.png", "at exit, write the shown image (the frame's pixels, "
       "8-bit, before scaling to the window)", NULL, 0, 0},
      {"script", 0, PB_OPT_STRING, &script, "FILE", "synthetic input: lines 'FRAME ACTION ARGS' (cursor X Y, press|"
       "release left|middle|right, scroll DY, key|keydown|keyup NAME, resize W H, screenshot FILE), through the "
       "handlers the mouse and keyboard use", NULL, 0, 0},
  };
  const size_t nopts = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, nopts, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, cmd, opts, nopts,
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
  if (alpha < 0 || !(alpha < 1))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "view: --alpha %g must lie in (0, 1)", alpha));
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
  pb_gpu_desc gd = {.device_set = device != UINT32_MAX, .device = device, .validation = validation};
  if ((r = pb_gpu_create(&gd, &g)) != PB_OK) goto done;
  if ((r = pb_gpu_scene_create(g, &s, &gs)) != PB_OK) goto done;
  pb_view_desc vd = {
      .seq = {.render = {.spp = spp, .max_specular_depth = max_spec, .direct_only = direct_only, .seed = c.seed,
                         .photons = photons, .iterations = iterations, .photon_bounces = bounces,
                         .smoothing = (float)smoothing, .r_max = (float)r_max, .progressive = progressive,
                         .alpha = (float)alpha, .first_bounce = (uint32_t)(PB_FIRST_BOUNCE_TRACE + first_bounce),
                         .atrous_iterations = atrous,
                         /* as cmd_render.c maps --atrous-clip */
                         .atrous_gamma = atrous_gamma < 0 ? 0.0f : (atrous_gamma > 0 ? (float)atrous_gamma : -1.0f),
                         .preview_interval_s = -1.0},
              .temporal = !no_temporal,
              .bvh_update = PB_BVH_UPDATE_AUTO},
      .camera = camera, .width = w, .height = h,
      .color = {co.ocio_config, co.display, co.view, co.look, co.exposure, co.gamma, PB_COLOR_PICTURE},
      .exit_after = exit_after, .screenshot = screenshot, .script = script, .reference = reference,
      .save_prefix = save, .json = c.json, .validation = validation || pb_gpu_validation_enabled(g), .quiet = c.quiet};
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
