/* The colour-management options of every subcommand that writes a display
 * image (render, reference, compare, display). A subcommand adds
 *     pb_color_opts co = PB_COLOR_OPTS_INIT;
 *     const pb_opt opts[] = {..., PB_COLOR_OPTS(&co)};
 * and, once parsed, opens the view with pb_color_opts_open(&co, &color) and
 * writes its PNG with pb_png_write_display(path, color, ...). */
#ifndef PB_APP_COLOR_OPTS_H
#define PB_APP_COLOR_OPTS_H

#include <math.h>

#include "app/cli.h"
#include "color/color.h"

typedef struct pb_color_opts {
  const char *ocio_config; /* --ocio-config; NULL: $OCIO, else Blender's, else built-in */
  const char *display;     /* --display */
  const char *view;        /* --view */
  const char *look;        /* --look */
  double exposure;         /* --exposure, stops; NAN: not given (0) */
  double gamma;            /* --gamma; 0: 1 */
} pb_color_opts;

#define PB_COLOR_OPTS_INIT {.exposure = NAN}

#define PB_COLOR_OPTS(c)                                                       \
  {"ocio-config", 0, PB_OPT_STRING, &(c)->ocio_config, "FILE",                 \
   "OpenColorIO config for display images (default: $OCIO, else Blender's "    \
   "own where installed, else the built-in one, which has Blender's Filmic; "  \
   "'built-in' names it)",                                                     \
   NULL, 0, 0, "Colour", 0},                                                                \
  {"display", 0, PB_OPT_STRING, &(c)->display, "NAME",                         \
   "OCIO display for PNG images (default: the config's default, sRGB)", NULL,  \
   0, 0, "Colour", 0},                                                                      \
  {"view", 0, PB_OPT_STRING, &(c)->view, "NAME",                               \
   "OCIO view (default: the config's, Filmic as in Blender 3.4; also AgX, "    \
   "Standard, Raw, ...; --list of `display` shows them)", NULL, 0, 0, "Colour", 0},         \
  {"look", 0, PB_OPT_STRING, &(c)->look, "NAME",                               \
   "OCIO look applied with the view (e.g. Blender's 'Medium High Contrast')",  \
   NULL, 0, 0, "Colour", 0},                                                                \
  {"exposure", 0, PB_OPT_FLOAT, &(c)->exposure, "STOPS",                       \
   "scale by 2^STOPS before the view, as Blender's Exposure (default 0)",      \
   NULL, -64, 64, "Colour", 0},                                                             \
  {"gamma", 0, PB_OPT_FLOAT, &(c)->gamma, "G",                                 \
   "display values to the power 1/G after the view, as Blender's Gamma "       \
   "(default 1)", NULL, 0.001, 1000, "Colour", 0}

/* Opens the colour pipeline the options name, for pictures (defaults:
 * Blender's config and view) or metrics (defaults: built-in, Standard). */
static inline pb_result pb_color_opts_open_for(const pb_color_opts *o, pb_color_purpose purpose,
                                               pb_color **out) {
  pb_color_desc d = {o->ocio_config, o->display, o->view,    o->look,
                     isnan(o->exposure) ? 0 : o->exposure, o->gamma, purpose};
  return pb_color_open(&d, out);
}

static inline pb_result pb_color_opts_open(const pb_color_opts *o, pb_color **out) {
  return pb_color_opts_open_for(o, PB_COLOR_PICTURE, out);
}

/* The pictures of a scene (render and reference PNGs, info's display
 * line): what the command line gives, else the scene's own colour
 * management (scene.h pb_scene_view: a scene from the Blender render engine
 * keeps its display, view, look, exposure and gamma), else the config's
 * defaults. The config: --ocio-config; else the one the scene names
 * (colorManagement.ocioConfig, Blender's own) where it exists here; else,
 * when the scene names one that is not here, $OCIO or the built-in config
 * (a one-line warning); else the usual defaults. A scene's look is not
 * applied under a --view or --display of the command line (Blender's looks
 * belong to their view). A name of the scene's that the config lacks
 * (Blender's config has views the built-in one has not; a custom config, looks) is a
 * one-line warning naming it and what is used instead, not an error: a
 * look the config lacks is left out (the view kept), a display or view
 * gives the config's default display, view and look (the scene's exposure
 * and gamma kept). Errors as pb_color_open for the command line's. */
pb_result pb_color_opts_open_scene(const pb_color_opts *o, const pb_scene *s, pb_color **out);

#endif
