/* The render settings (render/settings.h) on the command line: the options
 * of `render`, `view` and `serve` come from the one table, so the three
 * take the same names with the same ranges; and the device options of the
 * live commands. */
#ifndef PB_APP_SETTINGS_OPTS_H
#define PB_APP_SETTINGS_OPTS_H

#include <stddef.h>
#include <stdint.h>

#include "app/cli.h"
#include "render/frame/sequence.h"
#include "render/settings.h"

/* The options of the settings offered on `surface` (PB_SURFACE_*),
 * targets in s, appended at out[*n ..], at most cap in all. */
void pb_settings_opts(pb_settings *s, unsigned surface, pb_opt *out, size_t *n, size_t cap);

/* After pb_cli_parse_given: the bit of each setting of s the command line
 * gave set in s->given. */
void pb_settings_mark_given(pb_settings *s, const pb_opt *opts, const unsigned char *given, size_t n);

/* Appends the count options of `rows` at out[*n ..] (at most cap in all). */
void pb_opts_append(pb_opt *out, size_t *n, size_t cap, const pb_opt *rows, size_t count);

/* `view` and `serve`: the settings, the device and validation. */
typedef struct pb_live_opts {
  pb_settings set;
  uint32_t device; /* UINT32_MAX: the default choice */
  int validation;
  int traversal;   /* PB_GPU_TRAVERSAL_* */
} pb_live_opts;

void pb_live_opts_init(pb_live_opts *o);

/* --traversal's names, indexed by PB_GPU_TRAVERSAL_* (gpu/gpu.h). */
extern const char *const pb_traversal_names[];

/* The rows of --device, --validation and --traversal. */
#define PB_DEVICE_OPTS(o)                                                                                          \
  {"device", 0, PB_OPT_U32, &(o)->device, "N", "Vulkan device for rendering (see 'photonbridge info --devices'; "  \
   "default: a discrete GPU first, lavapipe last)", NULL, 0, 0, "Device", 0},                                        \
  {"validation", 0, PB_OPT_FLAG, &(o)->validation, NULL, "Vulkan validation layers; any message is an error "      \
   "(also PB_VK_VALIDATION=1)", NULL, 0, 0, "Device", PB_OPT_ADVANCED},                                              \
  {"traversal", 0, PB_OPT_CHOICE, &(o)->traversal, "MODE", "how rays find surfaces: auto (ray queries on a GPU "   \
   "with VK_KHR_ray_query, its ray-tracing units; else the BVH), bvh (the shaders' own BVH) or ray-query (also "   \
   "on a CPU device; fails without); default auto", pb_traversal_names, 0, 0, "Device", PB_OPT_ADVANCED}

/* Every frame's settings of a live session from its options and --seed:
 * the settings checked (PB_ERR_USAGE naming `command`) and turned into a
 * sequence's desc, as `render --frames` builds it. */
pb_result pb_live_sequence_desc(const char *command, const pb_live_opts *o, uint64_t seed, pb_sequence_desc *d);

#endif
