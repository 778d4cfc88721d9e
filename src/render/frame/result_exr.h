/* A frame's AOVs as a multilayer EXR: what `render` writes (app/render_out.c),
 * what `serve` and `view` save. */
#ifndef PB_RENDER_RESULT_EXR_H
#define PB_RENDER_RESULT_EXR_H

#include <stdint.h>

#include "core/result.h"
#include "render/render.h"

/* The EXR of a frame. blender_layer NULL: photonbridge's names (RGBA
 * beauty, direct.R, ..., depth.Z; see `render --help`). Otherwise Blender's
 * multilayer EXR names, LAYER.PASS.CHANNEL, so that RenderLayer.
 * load_from_file and Blender's compositor find them: Combined.RGBA (the
 * beauty, scene-linear), Depth.Z (camera depth, 1e10 where nothing is hit,
 * as Cycles writes it), Normal.XYZ, Emit.RGB, and photonbridge's own AOVs as
 * the passes Direct, Indirect, Caustic, Albedo (RGB; Indirect and Caustic 0
 * when the photon stages were off, so the set of channels is always the
 * same; blender_passes, when not NULL, restricts them to that list). `res`
 * may have only the beauty (a preview): the other passes are
 * then written as 0. attr_*: extra header attributes. */
pb_result pb_render_write_exr(const char *path, const pb_render_result *res, const char *blender_layer,
                              const char *blender_passes, const char *const *attr_names,
                              const char *const *attr_values, uint32_t attr_count);

/* Checks a --blender-passes list: comma-separated names of the passes
 * above (Combined, Depth, Normal, Emit, Direct, Indirect, Caustic,
 * Albedo). NULL passes (all of them). PB_ERR_USAGE naming the first
 * unknown one. The writer then writes exactly those, so that every
 * channel of the file has a pass in Blender's render result (Blender warns
 * about the others). */
pb_result pb_render_check_blender_passes(const char *list);

#endif
