/* photonbridge serve SCENE: the persistent session (src/serve/serve.h; the
 * protocol in src/serve/protocol.h). This file parses the options, opens
 * the GPU and hands over. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/settings_opts.h"
#include "core/log.h"
#include "gpu/gpu.h"
#include "serve/serve.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_serve) return &pb_commands[i];
  return NULL;
}

/* Every scene the session loads, as the command line says. */
static pb_result load_scene(void *user, const char *path, pb_scene *s, int *camera, uint32_t *w,
                            uint32_t *h) {
  const pb_core_opts *c = user;
  pb_result r = pb_cli_load_scene(path, c, s);
  if (r == PB_OK && (r = pb_cli_pick_camera(s, c, camera, w, h)) != PB_OK) pb_scene_destroy(s);
  return r;
}

static const char *const format_names[] = {"rgba32f", "exr", NULL};

int pb_cmd_serve(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  pb_live_opts lo;
  pb_live_opts_init(&lo);
  const char *socket_path = NULL, *frame_dir = NULL;
  int format = 0;
  const pb_opt rows[] = {
      {"width", 0, PB_OPT_U32, &c.width, "W", "image width until a resolution request (default 640, or from "
       "--height and the camera's aspect)", NULL, 1, 16384, "Output", 0},
      {"height", 0, PB_OPT_U32, &c.height, "H", "image height (default from the camera's aspect ratio)", NULL, 1,
       16384, "Output", 0},
      {"camera", 0, PB_OPT_STRING, &c.camera, "NAME|N", "the scene camera until a camera request (default: 0)", NULL,
       0, 0, "Output", 0},
      {"seed", 0, PB_OPT_U64, &c.seed, "N", "random seed (default 0; frame i after a (re)start uses it mixed with "
       "i, as render --frames)", NULL, 0, 0, "Sampling", 0},
      PB_SCENE_OPTS(&c),
      PB_DEVICE_OPTS(&lo),
      {"socket", 0, PB_OPT_STRING, &socket_path, "PATH", "requests and replies on a UNIX socket at PATH (one "
       "client; the session ends when it disconnects) instead of stdin/stdout", NULL, 0, 0, "Session", 0},
      {"frame-dir", 0, PB_OPT_STRING, &frame_dir, "DIR", "where the session's private folder (0700; "
       "frames 0600) is made (default /dev/shm, else $TMPDIR or /tmp)", NULL, 0, 0, "Session", 0},
      {"format", 0, PB_OPT_CHOICE, &format, "FMT", "frame files: rgba32f (default: a 32-byte header and float RGBA, "
       "top row first) or exr (every AOV, as render writes them)", format_names, 0, 0, "Session", 0},
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
                      "One JSON object a line each way (docs/serve.md; src/serve/protocol.h):\n"
                      "  {\"cmd\":\"camera\",\"view\":[16],\"projection\":[16],\"axes\":\"blender\"}  "
                      "{\"cmd\":\"resolution\",\"width\":W,\"height\":H}\n"
                      "  {\"cmd\":\"time\",\"t\":S}  {\"cmd\":\"settings\",\"photons\":N,...}  {\"cmd\":\"frame\"}\n"
                      "  {\"cmd\":\"stream\",\"on\":true,\"max_passes\":N}  {\"cmd\":\"reload\",\"scene\":PATH}  "
                      "{\"cmd\":\"quit\"}\n"
                      "Each request gets one reply line; a frame names its file, number, size and passes.\n"
                      "EOF on stdin (or the socket) ends the session.");
    return 0;
  }
  if (npos != 1)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "serve: expected SCENE (see 'photonbridge serve --help')"));
  pb_sequence_desc seq;
  if ((r = pb_live_sequence_desc("serve", &lo, c.seed, &seq)) != PB_OK) return pb_cli_exit(cmd, r);
  if (c.json)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "serve: --json is not taken here (stdout carries the protocol; "
                                    "each frame's reply has its statistics)"));
  if (socket_path && (r = pb_serve_socket_check(socket_path)) != PB_OK) return pb_cli_exit(cmd, r);
  pb_gpu *g = NULL;
  pb_gpu_desc gd = {.device_set = lo.device != UINT32_MAX, .device = lo.device, .validation = lo.validation,
                    .traversal = lo.traversal};
  if (c.quiet) pb_log_set_level(PB_LOG_QUIET); /* before the device's warning (the scene loads later) */
  if ((r = pb_gpu_create(&gd, &g)) == PB_OK) {
    pb_cli_warn_cpu_device("serve", g);
    pb_serve_desc d = {.scene = pos[0], .load = load_scene, .load_user = &c, .seq = seq, .settings = lo.set,
                       .socket_path = socket_path, .frame_dir = frame_dir, .format = format};
    r = pb_serve_run(g, &d);
    if (r == PB_OK && pb_gpu_validation_total())
      r = pb_fail(PB_ERR_VULKAN, "serve: Vulkan validation reported %u message(s) (printed above)",
                  pb_gpu_validation_total());
  }
  pb_gpu_destroy(g);
  return pb_cli_exit(cmd, r);
}
