/* The frame settings `view` and `serve` share (live_opts.h). */
#include "app/live_opts.h"

const char *const pb_live_first_bounce_names[] = {"traced", "rsm", NULL};

pb_result pb_live_opts_check(const char *command, const pb_live_opts *o) {
  if (o->alpha < 0 || !(o->alpha < 1))
    return pb_fail(PB_ERR_USAGE, "%s: --alpha %g must lie in (0, 1)", command, o->alpha);
  return PB_OK;
}

pb_sequence_desc pb_live_sequence_desc(const pb_live_opts *o, uint64_t seed) {
  pb_sequence_desc d = {
      .render = {.spp = o->spp, .max_specular_depth = o->max_spec, .direct_only = o->direct_only, .seed = seed,
                 .photons = o->photons, .iterations = o->iterations, .photon_bounces = o->bounces,
                 .smoothing = (float)o->smoothing, .r_max = (float)o->r_max, .progressive = o->progressive,
                 .alpha = (float)o->alpha, .first_bounce = (uint32_t)(PB_FIRST_BOUNCE_TRACE + o->first_bounce),
                 .atrous_iterations = o->atrous,
                 /* as cmd_render.c maps --atrous-clip */
                 .atrous_gamma = o->atrous_gamma < 0 ? 0.0f : (o->atrous_gamma > 0 ? (float)o->atrous_gamma : -1.0f),
                 .preview_interval_s = -1.0},
      .temporal = !o->no_temporal,
      .bvh_update = PB_BVH_UPDATE_AUTO};
  return d;
}
