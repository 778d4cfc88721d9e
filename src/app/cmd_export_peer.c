/* photonbridge export-peer SCENE --format luxcore|mitsuba -o DIR: the scene
 * model as a neutral dump for LuxCoreRender or Mitsuba 3 (src/peer/peer.h):
 * world-space PLY meshes per material, the camera, the lights in the peer's
 * units. What the peer shows differently is reported on stdout (and as
 * comments in the scene file); what it cannot hold is an error. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "peer/peer.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_export_peer) return &pb_commands[i];
  return NULL;
}

int pb_cmd_export_peer(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  int format = -1;
  uint64_t spp = 64, threads = 2;
  pb_pose_opts pose = {NAN, 0};
  const pb_opt opts[] = {
      PB_RENDER_OPTS_OUT_W(&c, "output folder (created if missing)",
                           "image width (default 128, or from --height and the camera's aspect)"),
      PB_POSE_OPTS(&pose),
      {"format", 0, PB_OPT_CHOICE, &format, "PEER", "luxcore (scene.scn + render.cfg) or mitsuba (scene.xml)",
       pb_peer_format_names, 0, 0, "Output", 0},
      {"spp", 0, PB_OPT_U64, &spp, "N", "samples per pixel written into the settings (default 64)", NULL, 1, 1u << 30, "Sampling", 0},
      {"threads", 0, PB_OPT_U64, &threads, "N", "render threads written into the LuxCore settings (default 2)", NULL, 1,
       4096, "Sampling", 0},
  };
  const size_t n = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, n, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, n,
                      "Writes DIR/mN.ply (one per material), DIR/mN_base.exr (linear base colour textures) and "
                      "DIR/scene.scn + DIR/render.cfg (LuxCore) or DIR/scene.xml (Mitsuba 3); file names inside "
                      "are relative to DIR. Notes about approximated features go to stdout.");
    return 0;
  }
  if (npos != 1 || !c.out || format < 0)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "export-peer: expected SCENE, --format luxcore|mitsuba and -o DIR "
                                                  "(see 'photonbridge export-peer --help')"));
  if (!c.width && !c.height) c.width = 128;
  pb_scene s;
  r = pb_cli_load_scene(pos[0], &c, &s);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  int camera;
  uint32_t w, h;
  double t;
  r = pb_cli_pose(&s, &pose, &t);
  if (r == PB_OK) r = pb_cli_pick_camera(&s, &c, &camera, &w, &h);
  if (r == PB_OK) {
    pb_peer_desc d = {(pb_peer_format)format, w, h, camera, (uint32_t)spp, (uint32_t)threads};
    pb_peer_report rep;
    r = pb_peer_export(&s, &d, c.out, &rep);
    if (r == PB_OK) {
      if (!c.quiet) {
        printf("wrote %s/%s (%s, %ux%u, %u mesh(es), %u vertices, %u triangles, %u texture file(s))\n", c.out,
               format == PB_PEER_LUXCORE ? "scene.scn" : "scene.xml", pb_peer_format_names[format], w, h,
               rep.ply_files, rep.vertex_count, rep.triangle_count, rep.texture_files);
        for (uint32_t i = 0; i < rep.note_count; ++i) printf("note: %s\n", rep.notes[i]);
      }
      pb_peer_report_destroy(&rep);
    }
  }
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
}
