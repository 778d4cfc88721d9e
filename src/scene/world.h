/* The world light's sampling distribution (pb_world in scene.h), shared by
 * the reference renderer (src/ref) and the GPU pipeline (src/render uploads
 * the same tables; shaders/common/lights.glsl mirrors the functions), so both
 * pick world directions with the same probabilities.
 *
 * Map: piecewise constant over the map's texel cells (cell (i, j) covers
 * u in [i, i+1) / width, v in [j, j+1) / height, rows from the top), cell
 * weight = mean over the cell of the bilinear radiance's channel average
 * (exactly the [1 6 1]/8 x [1 6 1]/8 filter of the texels: the mean of a
 * linear interpolant over a cell reaching half-way to each neighbour),
 * times sin(theta) at the cell's centre (the solid angle of a cell is
 * dphi dtheta sin(theta); pbrt-v3 14.2.4, Cycles 3.4 scene/light.cpp
 * background_cdf). A cell whose bilinear radiance is non-zero anywhere has
 * weight > 0, so light sampling alone is unbiased (the GPU's direct pass
 * relies on it). A direction's solid-angle pdf is
 *     p(u, v) W H / (2 pi^2 sin theta).
 * A constant world has no table: directions are uniform on the sphere
 * (pdf 1 / (4 pi)). */
#ifndef PB_SCENE_WORLD_H
#define PB_SCENE_WORLD_H

#include "scene/scene.h"

typedef struct pb_world_dist {
  uint32_t width, height;  /* 0: constant world (uniform sphere) */
  /* height rows of width + 1 entries: row j's CDF over its cells, cond[j][0]
   * = 0, cond[j][width] = 1 (a row of weight 0 is uniform). */
  float *cond;
  float *marg;             /* height + 1 entries over the rows, marg[height] = 1 */
} pb_world_dist;

/* Builds the table of w (nothing for a constant world or no world). Errors:
 * PB_ERR_NOMEM. */
pb_result pb_world_dist_build(const pb_world *w, pb_world_dist *d);
void pb_world_dist_destroy(pb_world_dist *d);

/* Samples a direction (unit, toward the sky, scene axes) from (u1, u2) in
 * [0, 1)^2; *pdf: its solid-angle density. Returns 0 when the sample has no
 * density (a world of zero weight). */
int pb_world_sample(const pb_world *w, const pb_world_dist *d, float u1, float u2, float dir[3], float *pdf);
/* Solid-angle density of pb_world_sample returning `dir`. */
float pb_world_pdf(const pb_world *w, const pb_world_dist *d, const float dir[3]);

/* Map coordinates of a direction: u in [0, 1) across, v in [0, 1] from the
 * top row (see pb_world in scene.h), and sin(theta). */
void pb_world_dir_to_uv(const pb_world *w, const float dir[3], float *u, float *v, float *sin_theta);
void pb_world_uv_to_dir(const pb_world *w, float u, float v, float dir[3]);

/* Blender's Z-up axes from glTF's +Y up (the glTF exporter writes
 * (x, y, z)_Blender as (x, z, -y)), then the Mapping node's rotation: Euler
 * XYZ in radians, R = Rz Ry Rx (Blender's convention; measured against
 * Cycles 3.4 with a coordinate-coded map). Fills pb_world.env_to_map. */
void pb_world_set_rotation(pb_world *w, const double euler_xyz[3]);

/* Sets w->integral from the map (or the colour): sum over the cells of the
 * cell mean (the filter above) times the cell's exact solid angle. */
void pb_world_update_integral(pb_world *w);

#endif
