/* The colour-management options of every subcommand that writes a display
 * image (render, reference, compare, display). A subcommand adds
 *     pb_color_opts co = {0};
 *     const pb_opt opts[] = {..., PB_COLOR_OPTS(&co)};
 * and, once parsed, opens the view with pb_color_opts_open(&co, &color) and
 * writes its PNG with pb_png_write_display(path, color, ...). */
#ifndef PB_COLOR_CLI_H
#define PB_COLOR_CLI_H

#include "app/cli.h"
#include "color/color.h"

typedef struct pb_color_opts {
  const char *ocio_config; /* --ocio-config; NULL: $OCIO, else built-in */
  const char *display;     /* --display */
  const char *view;        /* --view */
  const char *look;        /* --look */
} pb_color_opts;

#define PB_COLOR_OPTS(c)                                                       \
  {"ocio-config", 0, PB_OPT_STRING, &(c)->ocio_config, "FILE",                 \
   "OpenColorIO config for display images (default: $OCIO, else the built-in " \
   "one; Blender's: /usr/share/blender/datafiles/colormanagement/config.ocio)",\
   NULL, 0, 0},                                                                \
  {"display", 0, PB_OPT_STRING, &(c)->display, "NAME",                         \
   "OCIO display for PNG images (default: the config's default, sRGB)", NULL,  \
   0, 0},                                                                      \
  {"view", 0, PB_OPT_STRING, &(c)->view, "NAME",                               \
   "OCIO view (built-in config: Standard, 'ACES 1.0 - SDR Video', Raw; "       \
   "Blender's: Standard, Filmic, ...)", NULL, 0, 0},                           \
  {"look", 0, PB_OPT_STRING, &(c)->look, "NAME",                               \
   "OCIO look applied with the view (e.g. Blender's 'Medium High Contrast')",  \
   NULL, 0, 0}

/* Opens the colour pipeline the options name. */
static inline pb_result pb_color_opts_open(const pb_color_opts *o, pb_color **out) {
  pb_color_desc d = {o->ocio_config, o->display, o->view, o->look};
  return pb_color_open(&d, out);
}

#endif
