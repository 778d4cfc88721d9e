/* Colour management: scene-linear Rec.709 pixels to a display through an
 * OpenColorIO view (display / view / look), so that every renderer's preview
 * and every display-referred metric passes through the same pipeline.
 *
 * The OCIO config is, in order: pb_color_desc.config, else $OCIO, else (for
 * pictures) Blender's own config where Blender is installed (Debian:
 * /usr/share/blender/datafiles/colormanagement/config.ocio; see
 * pb_color_blender_config), else the built-in config (config/ocio/
 * photonbridge.ocio, embedded in the binary): scene-linear Rec.709, ACEScg,
 * ACES2065-1; display "sRGB" with views "Filmic" (Blender 3.4's Filmic, built
 * from src/color/filmic_builtin.c: the default, as in Blender 3.4), "AgX"
 * (Blender 4.x's default, AgX Base, from src/color/agx_builtin.c), "Khronos
 * PBR Neutral" (Blender 4.2+'s), "Standard" (no tone mapping, clips at 1),
 * "ACES 1.0 - SDR Video" and "Raw", and Blender's looks: Filmic's ("Very
 * High Contrast" ... "Very Low Contrast", in "Filmic Log") and 4.x's AgX
 * looks ("AgX - Punchy", "AgX - Greyscale", "AgX - Very High Contrast" ...
 * "AgX - Very Low Contrast", in "AgX Log"), with Blender's names and
 * transforms.
 *
 * Pictures people look at (PNG previews, `display`, reports) default to the
 * config's default view: Filmic, as Blender 3.4 shows every render. Metrics
 * (PSNR and SSIM of `compare`) default to the built-in config's "Standard"
 * view instead, so that a number means the same on every machine whether or
 * not Blender is installed, and stays comparable with earlier measurements.
 *
 * Input pixels are in the config's `scene_linear` role (Rec.709 primaries in
 * ours and in Blender's). The C++ shim (ocio_shim.cpp) is the only code that
 * sees OCIO's API. EXR output never passes through here: it stays
 * scene-linear, tagged with its chromaticities. */
#ifndef PB_COLOR_H
#define PB_COLOR_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pb_color_purpose {
  PB_COLOR_PICTURE = 0, /* config default: $OCIO, Blender's, built-in; view default: the config's */
  PB_COLOR_METRICS = 1, /* config default: $OCIO, built-in; view default: "Standard" */
} pb_color_purpose;

typedef struct pb_color_desc {
  const char *config;  /* OCIO config file; NULL or "": see above; "built-in": the built-in one */
  const char *display; /* NULL or "": the config's default display */
  const char *view;    /* NULL or "": the display's default view (METRICS: "Standard") */
  const char *look;    /* NULL, "" or "None": the view's own looks */
  /* As Blender's Colour Management panel: pixels are scaled by 2^exposure in
   * scene-linear before the view, and display values raised to 1/gamma after
   * it (Blender's OCIOImpl::createDisplayProcessor). 0 gamma means 1. */
  double exposure, gamma;
  pb_color_purpose purpose;
} pb_color_desc;

typedef struct pb_color pb_color;

/* Loads the config and builds the CPU processor scene_linear -> display/view
 * (+ look). Errors (one line, naming the config): PB_ERR_IO (config file
 * missing or unreadable), PB_ERR_USAGE (unknown display, view or look; the
 * message lists the ones the config has), PB_ERR_NOT_AVAILABLE (OCIO refused
 * the config or the transform), PB_ERR_NOMEM. */
pb_result pb_color_open(const pb_color_desc *desc, pb_color **out);
void pb_color_destroy(pb_color *c); /* accepts NULL */

/* In place: scene-linear RGB(A) -> display-referred values clamped to [0,1]
 * (NaN -> 0). Alpha (channels 4) is left untouched. channels is 3 or 4;
 * pixels are row-major, interleaved. */
pb_result pb_color_apply_display(const pb_color *c, float *pixels, uint32_t width,
                                 uint32_t height, uint32_t channels);

/* In place, between two colour spaces of the same config (no clamping), e.g.
 * "Linear Rec.709 (sRGB)" -> "ACEScg". Errors as pb_color_open. */
pb_result pb_color_convert(const pb_color *c, const char *src, const char *dst,
                           float *pixels, uint32_t width, uint32_t height,
                           uint32_t channels);

/* What the processor uses: the config ("built-in" or its path), the display,
 * the view and the look ("" when none); pb_color_describe writes all of it,
 * exposure and gamma included, as one line ("Blender config /usr/...: sRGB /
 * Filmic, look None, exposure 0, gamma 1") into buf. */
const char *pb_color_config_name(const pb_color *c);
const char *pb_color_display(const pb_color *c);
const char *pb_color_view(const pb_color *c);
const char *pb_color_look(const pb_color *c);
double pb_color_exposure(const pb_color *c);
double pb_color_gamma(const pb_color *c);
void pb_color_describe(const pb_color *c, char *buf, size_t size);

/* Blender's OCIO config on this machine: $PB_BLENDER_OCIO when set (empty:
 * none), else the first that exists of Debian's
 * /usr/share/blender/datafiles/colormanagement/config.ocio, the versioned
 * /usr/share/blender/X.Y/datafiles/..., and X.Y/datafiles/... beside the
 * `blender` found on PATH (Blender's own tarballs). NULL when none. The
 * string is static. */
const char *pb_color_blender_config(void);

/* The config's displays, each with its views, and its looks, one per line
 * ("display sRGB: Standard, Filmic, ..."), for --list. */
void pb_color_list(const pb_color *c, FILE *f);

/* The view baked for the GPU: a 3D LUT of size^3 nodes on
 * a shaper, so that shaders/frame/present.comp (src/view/present_pass.c) shows
 * what pb_color_apply_display gives, to one 8-bit step, HDR values included.
 *
 * The shaper (per channel, after the exposure scale): node 0 is x = 0; node
 * 1 .. size-1 are log2-spaced from 2^lo to 2^hi; between 0 and 2^lo the
 * coordinate is linear in x (the toe). lo and hi are chosen by probing the
 * view (pb_color_bake_lut): hi is where the display values of grey and of
 * the three primaries stop changing (Standard: 1, where it clips; Filmic:
 * 2^8.56, where its curve reaches 1), so every value above 1 up to there
 * has its own nodes and values beyond map as the view maps them (constant);
 * lo is the largest 1/16 stop below which the view is linear in x (sRGB's
 * linear segment, 2^-8.3; Filmic's allocation floor, 2^-12.47) within
 * 2e-5, so the linear toe is exact there (a flat floor is found to float
 * precision by bisection). Interpolation: tetrahedral, as
 * OCIO's own 3D LUTs in Blender's config. The nodes hold the processor's
 * output at exposure 0 (gamma and look included), clamped to [0, 1] as
 * pb_color_apply_display clamps. No dither: the host path rounds to
 * nearest, and so does the pass. */
typedef struct pb_color_lut {
  uint32_t size;   /* nodes per axis: 66 (the node at 0 and 65 log2-spaced), or
                      129 where 66 misses by more than half an 8-bit step
                      (Filmic: 0.93 steps at 129, 2.3 at 66) */
  float lo, hi;    /* log2 of nodes 1 and size-1 */
  float *rgba;     /* size^3 nodes, 4 floats each (alpha 1), red fastest,
                      then green, then blue */
  double max_error; /* |LUT - processor| over the probe set (display units):
                       a grey ramp of 2^-24 .. 2^16 and random colours up to
                       2^8, at exposure 0 */
} pb_color_lut;

/* Bakes c's view (exposure ignored: the pass scales by 2^exposure, so an
 * exposure key needs no new bake). size 0: 66, or 129 when 66 misses by
 * more than half an 8-bit step. Errors: PB_ERR_USAGE (size
 * not in 2..129), PB_ERR_NOMEM, PB_ERR_NOT_AVAILABLE (OCIO). */
pb_result pb_color_bake_lut(const pb_color *c, uint32_t size, pb_color_lut *out);
void pb_color_lut_destroy(pb_color_lut *lut); /* accepts a zeroed one */
/* The pass's arithmetic on the host (display_lut.c; shaders/frame/present.comp
 * does the same): scene-linear RGB scaled by `scale` (2^exposure) to
 * display values in [0, 1] (NaN and negative channels: the node at 0). */
void pb_color_lut_eval(const pb_color_lut *lut, float scale, const float rgb[3], float out[3]);
/* The 8-bit encode both paths use: 0 for NaN and x <= 0, 255 for x >= 1,
 * else round(x * 255) (pb_png_write_display's). */
uint8_t pb_color_to_u8(float x);

/* The embedded config text (config/ocio/photonbridge.ocio). */
extern const char pb_color_builtin_config_text[];

/* Writes an 8-bit PNG through the view: pixels (linear RGB(A), 3 or 4
 * channels) are passed through pb_color_apply_display (the view's exposure
 * and gamma included) and rounded to nearest; alpha is written linearly.
 * With c == NULL it falls back to pb_png_write_srgb (plain sRGB encode).
 * Atomic like every writer. Errors: those of pb_png_write_srgb and
 * pb_color_apply_display. */
pb_result pb_png_write_display(const char *path, const pb_color *c, uint32_t width,
                               uint32_t height, uint32_t channels, const float *pixels);

#ifdef __cplusplus
}
#endif

#endif
