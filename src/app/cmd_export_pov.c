/* photonbridge export-pov SCENE -o scene.pov: the scene model as POV-Ray 3.7
 * SDL (units, camera and handedness per src/pov/pov.h). What POV-Ray cannot
 * show the same way is reported on stdout (and as comments in the file);
 * --strict makes it an error. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "app/cli.h"
#include "app/commands.h"
#include "pov/pov.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_export_pov) return &pb_commands[i];
  return NULL;
}

int pb_cmd_export_pov(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  int quality = 1; /* index into pb_pov_quality_names: medium */
  double fade = 0;
  int strict = 0;
  pb_pose_opts pose = {NAN, 0};
  const pb_opt opts[] = {
      PB_RENDER_OPTS_OUT(&c, "output file (.pov)"),
      PB_POSE_OPTS(&pose),
      {"quality", 0, PB_OPT_CHOICE, &quality, "PRESET",
       "radiosity and photon settings: draft, medium (default), high, or direct (no radiosity, no photons)",
       pb_pov_quality_names, 0, 0, "Output", 0},
      {"fade-distance", 0, PB_OPT_FLOAT, &fade, "M",
       "POV-Ray fade_distance for point/spot lights (default 1e-3 x scene diagonal; error (f/d)^2)", NULL, 0, 1e6, "Output", PB_OPT_ADVANCED},
      {"strict", 0, PB_OPT_FLAG, &strict, NULL,
       "fail (exit 6) when the scene uses a feature POV-Ray would show differently", NULL, 0, 0, "Output", 0},
  };
  const size_t n = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, n, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, n,
                      "--width/--height fix the camera's aspect; run POV-Ray with the same +W/+H "
                      "(validation/run_povray.sh reads them from the file). Textures are written "
                      "next to OUT as OUTSTEM_mN.png. Notes about approximated features go to stdout.");
    return 0;
  }
  if (npos != 1 || !c.out)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "export-pov: expected SCENE and -o OUT.pov (see "
                                                  "'photonbridge export-pov --help')"));
  /* The file is POV-Ray scene text: a name such as cb.exr or cb.png would
   * hold text under an image's extension. */
  size_t ol = strlen(c.out);
  if (ol < 4 || strcasecmp(c.out + ol - 4, ".pov") != 0)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "export-pov: -o %s: the output is POV-Ray scene text and must end "
                                    "in .pov (render it with 'povray +I%s', or use 'photonbridge render -o OUT.exr' "
                                    "for an image)", c.out, "OUT.pov"));
  pb_scene s;
  r = pb_cli_load_scene(pos[0], &c, &s);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  int camera;
  uint32_t w, h;
  double t;
  r = pb_cli_pose(&s, &pose, &t);
  if (r == PB_OK) r = pb_cli_pick_camera(&s, &c, &camera, &w, &h);
  if (r == PB_OK) {
    pb_pov_desc d = {w, h, camera, (pb_pov_quality)(quality + 1), (float)fade, t};
    pb_pov_report rep;
    r = pb_pov_export(&s, &d, c.out, &rep);
    if (r == PB_OK) {
      if (!c.quiet) {
        printf("wrote %s (%ux%u, quality %s%s, fade_distance %.4g m, %u texture file(s))\n", c.out, rep.width,
               rep.height, pb_pov_quality_names[quality], rep.photons ? ", photons" : "", rep.fade_distance,
               rep.texture_files);
        for (uint32_t i = 0; i < rep.note_count; ++i) printf("note: %s\n", rep.notes[i]);
      }
      if (strict && rep.unsupported_count)
        r = pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: %u feature(s) POV-Ray shows differently (see the notes; "
                                              "the file was written)", pos[0], rep.unsupported_count);
      pb_pov_report_destroy(&rep);
    }
  }
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
}
