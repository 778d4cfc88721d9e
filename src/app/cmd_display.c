/* photonbridge display IMAGE.exr -o IMAGE.png: a scene-linear EXR to a PNG
 * through an OCIO display/view/look (the same pipeline render, reference and
 * compare use for their previews). --list shows what the config offers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/color_opts.h"
#include "image/image.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_display) return &pb_commands[i];
  return NULL;
}

/* R, G, B (and A when present) of the main image, or of layer `layer`. */
static pb_result gather(const pb_image *img, const char *path, const char *layer, float **out,
                        uint32_t *channels) {
  static const char *const names[4] = {"R", "G", "B", "A"};
  int idx[4];
  uint32_t nc = 0;
  for (int k = 0; k < 4; ++k) {
    char full[160];
    snprintf(full, sizeof full, "%s%s%s", layer ? layer : "", layer ? "." : "", names[k]);
    idx[k] = pb_image_find_channel(img, full);
    if (idx[k] < 0 && k < 3)
      return pb_fail(PB_ERR_IMAGE, "%s: no channel '%s' (need %sR, G and B)", path, full,
                     layer ? "LAYER." : "");
    if (idx[k] >= 0) nc = (uint32_t)k + 1;
  }
  const size_t n = (size_t)img->width * img->height;
  float *p = malloc(n * nc * sizeof *p);
  if (!p) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t k = 0; k < nc; ++k) p[i * nc + k] = img->pixels[i * img->channel_count + (uint32_t)idx[k]];
  *out = p;
  *channels = nc;
  return PB_OK;
}

int pb_cmd_display(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_color_opts co = PB_COLOR_OPTS_INIT;
  const char *out = NULL, *layer = NULL;
  int list = 0;
  const pb_opt opts[] = {
      {"output", 'o', PB_OPT_STRING, &out, "OUT", "output PNG", NULL, 0, 0, "Output", 0},
      {"layer", 0, PB_OPT_STRING, &layer, "NAME", "EXR layer to show (default: the main R, G, B)",
       NULL, 0, 0, "Output", 0},
      {"list", 0, PB_OPT_FLAG, &list, NULL, "list the config's displays, views and looks, then exit",
       NULL, 0, 0, "Colour", 0},
      PB_COLOR_OPTS(&co),
  };
  const size_t n = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, n, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, n,
                      "Input is scene-linear Rec.709 (the config's scene_linear role); output is "
                      "8-bit display-referred, clamped to [0,1].");
    return 0;
  }
  pb_color *color = NULL;
  if (list) {
    r = pb_color_opts_open(&co, &color);
    if (r == PB_OK) pb_color_list(color, stdout);
    pb_color_destroy(color);
    return pb_cli_exit(cmd, r);
  }
  if (npos != 1 || !out)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "display: expected IMAGE.exr and -o OUT.png (see "
                                                  "'photonbridge display --help')"));
  r = pb_color_opts_open(&co, &color);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  pb_image img;
  r = pb_exr_read(pos[0], NULL, &img);
  if (r == PB_OK) {
    float *rgba = NULL;
    uint32_t nc = 0;
    r = gather(&img, pos[0], layer, &rgba, &nc);
    if (r == PB_OK)
      r = pb_png_write_display(out, color, img.width, img.height, nc, rgba);
    if (r == PB_OK) {
      char view[768];
      pb_color_describe(color, view, sizeof view);
      printf("display: wrote %s through %s\n", out, view);
    }
    free(rgba);
    pb_image_destroy(&img);
  }
  pb_color_destroy(color);
  return pb_cli_exit(cmd, r);
}
