/* The frame settings `view` and `serve` share (one pb_sequence_desc, as
 * `render --frames` builds it): the option rows, their checks and the
 * descriptor. */
#ifndef PB_APP_LIVE_OPTS_H
#define PB_APP_LIVE_OPTS_H

#include <stdint.h>

#include "app/cli.h"
#include "render/photon.h"
#include "render/sequence.h"
#include "render/tracer.h"

typedef struct pb_live_opts {
  uint32_t spp, max_spec, photons, iterations, bounces, atrous, device, max_bounces;
  int direct_only, progressive, no_temporal, validation, first_bounce;
  int tracer;                              /* index into pb_tracer_names (render/tracer.h) */
  uint32_t image_maps, image_map_resolution; /* --tracer images; 0: the tracer's defaults */
  double smoothing, smoothing_caustic, r_max, alpha, atrous_gamma;
} pb_live_opts;

extern const char *const pb_live_first_bounce_names[];

/* Defaults: 4 A-Trous passes (as render --frames), no device chosen. */
#define PB_LIVE_OPTS_INIT {.atrous = 4, .device = UINT32_MAX, .atrous_gamma = -1, .first_bounce = 0 /* traced */}

#define PB_LIVE_OPTS(o)                                                                                            \
  {"spp", 0, PB_OPT_U32, &(o)->spp, "N", "samples per pixel per frame (default 1)", NULL, 1, 1 << 20, "Sampling", 0},             \
  {"max-specular-depth", 0, PB_OPT_U32, &(o)->max_spec, "N", "mirror/glass interactions along an eye path "       \
   "(default: Russian roulette from the 9th, cap 64)", NULL, 1, PB_RENDER_MAX_SPECULAR_DEPTH, "Sampling", PB_OPT_ADVANCED},                                                           \
  {"direct-only", 0, PB_OPT_FLAG, &(o)->direct_only, NULL, "only paths with at most one scattering event", NULL,   \
   0, 0, "Sampling", 0},                                                                                                          \
  {"photons", 0, PB_OPT_U32, &(o)->photons, "N", "photon paths per map (default 2^18)", NULL, 1, 1u << 26, "Photons", 0},        \
  {"iterations", 0, PB_OPT_U32, &(o)->iterations, "K", "photon maps per frame (default 1)", NULL, 1, 1 << 16, "Photons", 0},     \
  {"photon-bounces", 0, PB_OPT_U32, &(o)->bounces, "N", "bounces stored per photon path (default: unbounded, " \
   "Russian roulette, cap 255)", NULL, 1, 255, "Photons", 0},                                                                                                   \
  {"max-bounces", 0, PB_OPT_U32, &(o)->max_bounces, "N", "scattering events per path, as render --max-bounces "  \
   "(Blender's Max Bounces B is B + 1; default: unbounded, Russian roulette)", NULL, 1, 1024, "Sampling", 0},                     \
  {"smoothing", 0, PB_OPT_FLOAT, &(o)->smoothing, "S", "footprint smoothing factor (default "                      \
   PB_PHOTON_SMOOTHING_DEFAULT_STR ")", NULL, 0, 1e6, "Photons", 0},                                                             \
  {"smoothing-caustic", 0, PB_OPT_FLOAT, &(o)->smoothing_caustic, "S", "caustic photons' footprint factor, as "   \
   "render's (default " PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT_STR ")", NULL, 0, 1e6, "Photons", PB_OPT_ADVANCED},                                \
  {"r-max", 0, PB_OPT_FLOAT, &(o)->r_max, "M", "footprint radius clamp in metres (default 18 photon "  \
   "spacings on the scene's bounding sphere: it shrinks as the photons grow)", NULL, 0, 1e9, "Photons", PB_OPT_ADVANCED},                                                                                       \
  {"progressive", 0, PB_OPT_FLAG, &(o)->progressive, NULL, "footprints shrink from still frame to still frame "   \
   "(probabilistic SPPM), so a still view converges to the unbiased answer", NULL, 0, 0, "Photons", 0},                          \
  {"alpha", 0, PB_OPT_FLOAT, &(o)->alpha, "A", "--progressive: radius^2 fraction kept per map, in (0, 1) "        \
   "(default 2/3)", NULL, 0, 0, "Photons", PB_OPT_ADVANCED},                                                                                   \
  {"first-bounce", 0, PB_OPT_CHOICE, &(o)->first_bounce, "MODE",                                                 \
   "traced, rsm or auto (rsm for lights whose map covers under half of their flux; default traced)",                       \
   pb_live_first_bounce_names, 0, 0, "Photons", PB_OPT_ADVANCED},                                                                              \
  {"tracer", 0, PB_OPT_CHOICE, &(o)->tracer, "KIND", "photon tracer, as render --tracer: bvh (default) or images " \
   "(cube environment maps; approximate, misses counted)", pb_tracer_names, 0, 0, "Photons", PB_OPT_ADVANCED},                                       \
  {"image-maps", 0, PB_OPT_U32, &(o)->image_maps, "K", "--tracer images: environment maps (default 8)", NULL, 1,  \
   PB_IMAGE_MAPS_MAX, "Photons", PB_OPT_ADVANCED},                                                                                             \
  {"image-map-resolution", 0, PB_OPT_U32, &(o)->image_map_resolution, "N", "--tracer images: texels per "         \
   "cube-face side (default 128)", NULL, 8, 1024, "Photons", PB_OPT_ADVANCED},                                                                 \
  {"atrous-iterations", 0, PB_OPT_U32, &(o)->atrous, "N", "A-Trous passes on the indirect light (default 4, as "   \
   "render --frames)", NULL, 0, 12, "Filtering", 0},                                                                               \
  {"atrous-clip", 0, PB_OPT_FLOAT, &(o)->atrous_gamma, "G", "A-Trous detail kept within G standard deviations "    \
   "(default 0.25)", NULL, 0, 100, "Filtering", PB_OPT_ADVANCED},                                                                                \
  {"no-temporal", 0, PB_OPT_FLAG, &(o)->no_temporal, NULL, "no temporal filter while moving (on by default)",      \
   NULL, 0, 0, "Filtering", 0},                                                                                                    \
  {"device", 0, PB_OPT_U32, &(o)->device, "N", "Vulkan device for rendering (see 'photonbridge info --devices')",  \
   NULL, 0, 0, "Device", 0},                                                                                                    \
  {"validation", 0, PB_OPT_FLAG, &(o)->validation, NULL, "Vulkan validation layers; any message is an error "      \
   "(also PB_VK_VALIDATION=1)", NULL, 0, 0, "Device", PB_OPT_ADVANCED}

/* PB_ERR_USAGE naming the command (--alpha out of range). */
pb_result pb_live_opts_check(const char *command, const pb_live_opts *o);

/* Every frame's settings from the options and --seed. */
pb_sequence_desc pb_live_sequence_desc(const pb_live_opts *o, uint64_t seed);

#endif
