/* Emissive triangles as lights: the one table of them that both renderers
 * sample from (the reference, src/ref/lights.c, and the GPU's direct pass
 * through src/render/scene/scene_gpu.c), so they pick emitters with the same
 * probabilities. */
#ifndef PB_SCENE_EMITTERS_H
#define PB_SCENE_EMITTERS_H

#include "scene/scene.h"

/* Every triangle with an emissive material and a positive weight, in scene
 * order. Weight (power up to a constant): area x max(luminance, 1e-3 x the
 * largest channel) of the emissive factor clamped at 0 (a saturated emitter
 * never gets weight 0) times its emission texture's mean (pb_texture_mean;
 * 1 without one), x 2 when double-sided. cdf[i] is the normalised sum
 * of the weights before entry i (summed in double): cdf[0] = 0, cdf[count] =
 * 1; entry i is picked for u in [cdf[i], cdf[i + 1]). */
typedef struct pb_emitter_table {
  uint32_t *prim;  /* triangle indices */
  float *area;     /* their areas [m^2] */
  double *cdf;     /* count + 1 entries */
  uint32_t count;  /* 0: no emitter (arrays NULL) */
} pb_emitter_table;

/* Errors: PB_ERR_NOMEM. */
pb_result pb_emitter_table_build(const pb_scene *s, pb_emitter_table *t);
void pb_emitter_table_destroy(pb_emitter_table *t);

/* The emitters' flux [W], RGB: sum over the table's triangles of
 * pi A L x sides, L the emissive factor times its texture's mean (the
 * photon budget's share of the emitter slot, render/photon/photon_trace.c). */
void pb_emitter_flux(const pb_scene *s, double out[3]);

/* Area of triangle t [m^2]. */
float pb_triangle_area(const pb_scene *s, uint32_t t);

#endif
