/* The frame settings `view` and `serve` share (live_opts.h). */
#include "app/live_opts.h"

const char *const pb_live_first_bounce_names[] = {"traced", "rsm", "auto", NULL};

pb_result pb_live_opts_check(const char *command, const pb_live_opts *o) {
  if (o->alpha < 0 || !(o->alpha < 1))
    return pb_fail(PB_ERR_USAGE, "%s: --alpha %g must lie in (0, 1)", command, o->alpha);
  if ((o->image_maps || o->image_map_resolution) && o->tracer != PB_TRACER_IMAGES)
    return pb_fail(PB_ERR_USAGE, "%s: --image-maps and --image-map-resolution need --tracer images", command);
  return PB_OK;
}

pb_sequence_desc pb_live_sequence_desc(const pb_live_opts *o, uint64_t seed) {
  /* --max-bounces N as cmd_render.c maps it: photon paths store N - 1
   * bounces, eye chains follow N - 1 mirror/glass interactions, 1 is direct
   * light only; explicit --photon-bounces / --max-specular-depth win. */
  uint32_t bounces = o->bounces, max_spec = o->max_spec;
  int direct_only = o->direct_only || o->max_bounces == 1;
  if (o->max_bounces >= 2) {
    uint32_t n = o->max_bounces - 1;
    if (!bounces) bounces = n < PB_PHOTON_BOUNCE_CAP ? n : PB_PHOTON_BOUNCE_CAP;
    if (!max_spec) max_spec = n < PB_RENDER_MAX_SPECULAR_DEPTH ? n : PB_RENDER_MAX_SPECULAR_DEPTH;
  }
  pb_sequence_desc d = {
      .render = {.spp = o->spp, .max_specular_depth = max_spec, .direct_only = direct_only, .seed = seed,
                 .photons = o->photons, .iterations = o->iterations, .photon_bounces = bounces,
                 .smoothing = (float)o->smoothing, .smoothing_caustic = (float)o->smoothing_caustic, .r_max = (float)o->r_max, .progressive = o->progressive,
                 .alpha = (float)o->alpha, .first_bounce = (uint32_t)(PB_FIRST_BOUNCE_TRACE + o->first_bounce),
                 .tracer = (uint32_t)o->tracer, .image_maps = o->image_maps,
                 .image_map_resolution = o->image_map_resolution, .atrous_iterations = o->atrous,
                 /* as cmd_render.c maps --atrous-clip */
                 .atrous_gamma = o->atrous_gamma < 0 ? 0.0f : (o->atrous_gamma > 0 ? (float)o->atrous_gamma : -1.0f),
                 .preview_interval_s = -1.0},
      .temporal = !o->no_temporal,
      .bvh_update = PB_BVH_UPDATE_AUTO};
  return d;
}
