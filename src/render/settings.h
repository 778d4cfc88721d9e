/* The render settings, declared once: every setting of a frame that a user
 * can set (the value-only part of pb_render_desc and the sequence's
 * temporal filter), one row each in PB_SETTINGS, as core/result.h declares
 * the results. From the table come:
 *   - the options of `render`, `view` and `serve` (app/settings_opts.h: name,
 *     metavar, range, help, heading), so the three take the same names with
 *     the same ranges;
 *   - serve's "settings" request (serve/protocol.c: the JSON key, type and
 *     range of each row);
 *   - the defaults and the checks across settings (pb_settings_init,
 *     pb_settings_check), and the one translation into a frame's
 *     pb_render_desc (pb_settings_render_desc);
 *   - the Blender add-on's table (`photonbridge settings --python`, written
 *     to exporters/blender/photonbridge/settings_table.py; a test keeps the
 *     two the same), from which its properties take their ranges and
 *     defaults and its command line and viewport requests their names.
 * (The variable bandwidth and the multi-level up-sampling rows are seed 003
 * sec. 6's, the A-Trous rows seed 001 24.4.2's, the footprint rows seed
 * 000 4.3's.)
 * What shapes the GPU resources needs no column: the frame's plan derives
 * its context key from the resolved pb_render_desc (render/frame/plan.h
 * pb_frame_shape).
 *
 * Columns:
 *   id       the C field of pb_settings and the JSON key of serve
 *   kind     U32 (uint32_t), F64 (double), BOOL (int 0/1), CHOICE (int,
 *            an index into `choices`)
 *   cli      the long option; a BOOL's option sets the value that is not
 *            its default (--no-temporal clears `temporal`)
 *   lo, hi   the inclusive range a value must lie in (both 0: unchecked
 *            here; pb_settings_check then says what holds)
 *   def      the value when not given; for most "automatic" settings 0,
 *            which the frame resolves (the help says to what)
 *   surfaces PB_SURFACE_* where the setting is offered
 *   flags    PB_SETTING_ADVANCED: listed by --help-all only, and in the
 *            add-on's advanced panel (algorithm choices, benchmarks,
 *            ablations); PB_SETTING_LIVE_OFF: 0 by default in view and
 *            serve (pb_settings_init_live)
 *   group    the --help heading and the add-on's panel
 *   metavar  the option's value in --help
 *   choices  CHOICE: the NULL-terminated names (their order is the value)
 *   needs    NULL, or "SETTING=NAME,NAME": the setting does something only
 *            with that choice of another (--image-maps with --tracer
 *            images); the command line refuses it otherwise, a live
 *            session keeps it for when it applies
 *   help     one sentence or two, the option's help. */
#ifndef PB_RENDER_SETTINGS_H
#define PB_RENDER_SETTINGS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/result.h"

struct pb_render_desc;

enum {
  PB_SURFACE_RENDER = 1u << 0,  /* photonbridge render (one frame and --frames) */
  PB_SURFACE_LIVE = 1u << 1,    /* photonbridge view and serve (their options) */
  PB_SURFACE_REQUEST = 1u << 2, /* serve's "settings" request (changed while it runs) */
  PB_SURFACE_BLENDER = 1u << 3, /* the Blender add-on (Scene.photonbridge) */
  PB_SURFACE_ALL = 0xf,
  PB_SURFACE_ONE_FRAME = PB_SURFACE_RENDER | PB_SURFACE_BLENDER, /* a frame that ends */
};
enum {
  PB_SETTING_ADVANCED = 1,
  PB_SETTING_LIVE_OFF = 2, /* view and serve start at 0 (off), not at def:
                            * a live view refines until told otherwise */
};

extern const char *const pb_settings_first_bounce_names[]; /* traced, rsm, auto */
/* The other choices are render/estimate/estimator.h's pb_estimator_names and
 * render/photon/tracer.h's pb_tracer_names (the table is expanded in settings.c). */

/* X(id, kind, cli, lo, hi, def, surfaces, flags, group, metavar, choices, needs, help) */
#define PB_SETTINGS(X)                                                                                                 \
  /* ---- Sampling ---- */                                                                                             \
  X(spp, U32, "spp", 1, 1 << 20, 0, PB_SURFACE_ALL, 0, "Sampling", "N", NULL, NULL,                                    \
    "samples per pixel (default 1: pixel centres; more: stratified jitter; a still view or serve's stream adds "       \
    "these every frame)")                                                                                              \
  X(max_bounces, U32, "max-bounces", 1, 1024, 0, PB_SURFACE_ALL, 0, "Sampling", "N",                                   \
    NULL, NULL,                                                                                                        \
    "scattering events per path, direct light = 1, as the reference's --max-bounces (Blender's Max Bounces B is "      \
    "B + 1): photon paths store N - 1 bounces, eye paths follow N - 1 mirror/glass interactions, 1 is "                \
    "--direct-only (default: unbounded)")                                                                              \
  X(max_specular_depth, U32, "max-specular-depth", 1, 64, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Sampling",          \
    "N", NULL, NULL,                                                                                                   \
    "mirror/glass interactions followed along an eye path (default: Russian roulette from the 9th, cap 64)")           \
  X(glossy_path_roughness, F64, "glossy-path-roughness", 0, 1, 0.15, PB_SURFACE_ALL, PB_SETTING_ADVANCED,              \
    "Sampling", "R", NULL, NULL,                                                                                       \
    "Blender materials: specular and clearcoat layers of Roughness above R are shaded where the eye path stops "       \
    "(direct light and the photon map), smoother ones are followed by the eye path; 0: every layer shaded at the "     \
    "first hit, 1: every one followed (default 0.15)")                                                                 \
  X(direct_only, BOOL, "direct-only", 0, 0, 0, PB_SURFACE_ALL, 0, "Sampling", NULL, NULL, NULL,                        \
    "render only paths with at most one scattering event (the reference's direct AOV)")                                \
  X(time_limit, F64, "time-limit", 0, 1e9, 0, PB_SURFACE_ONE_FRAME, 0, "Sampling", "S",                                \
    NULL, NULL,                                                                                                        \
    "start no photon map after S seconds; the image averages the maps done (of --iterations; without "                 \
    "--iterations: as many as S seconds allow, at most 65536)")                                                        \
  X(noise_threshold, F64, "noise-threshold", 0, 0.5, 0.03, PB_SURFACE_ONE_FRAME | PB_SURFACE_LIVE, PB_SETTING_LIVE_OFF, \
    "Sampling", "T", NULL, NULL,                                                                                       \
    "refine photon maps until the render's own estimate of its noise, the RMS error of the displayed image (0 to "     \
    "1, white 1; PSNR = -20 log10 T: 0.01 is 40 dB), is at most T: render stops (or --time-limit or --iterations "     \
    "ends it first), a still view rests, serve's streams stop there unless a stream request says otherwise; 0: off "   \
    "(render: default 0.03 unless --iterations, --spp or --time-limit set the work; view, serve: default 0)")           \
  /* ---- Photons ---- */                                                                                              \
  X(photons, U32, "photons", 1, 1u << 26, 0, PB_SURFACE_ALL, 0, "Photons", "N", NULL, NULL,                            \
    "photon paths per map (default 2^18)")                                                                             \
  X(iterations, U32, "iterations", 1, 1 << 16, 0, PB_SURFACE_ALL, 0, "Photons", "K", NULL, NULL,                       \
    "independent photon maps averaged per frame (sample s gathers map s*K/spp; spp is raised to K); with "             \
    "--noise-threshold or --time-limit the most rendered (default: as many as the noise threshold needs, at most "     \
    "65536; 1 with --spp, --frames, view and serve)")                                                                  \
  X(photon_bounces, U32, "photon-bounces", 1, 255, 0, PB_SURFACE_ALL, 0, "Photons", "N", NULL, NULL,                   \
    "bounces stored per photon path (default: unbounded, paths end by Russian roulette, cap 255)")                     \
  X(smoothing, F64, "smoothing", 0, 1e6, 0, PB_SURFACE_ALL, 0, "Photons", "S", NULL, NULL,                             \
    "footprint smoothing factor s, dimensionless (default 2.5)")                                                       \
  X(smoothing_caustic, F64, "smoothing-caustic", 0, 1e6, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "S",       \
    NULL, NULL, "caustic photons keep their differential footprint, uncompressed, times S (default 1)")                \
  X(r_max, F64, "r-max", 0, 1e9, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "M", NULL, NULL,                   \
    "footprint radius clamp in metres (default 30 photon spacings on the scene's bounding sphere, 30 Delta R: it "     \
    "shrinks as the photons grow)")                                                                                    \
  X(progressive, BOOL, "progressive", 0, 0, 0, PB_SURFACE_ALL, 0, "Photons", NULL, NULL, NULL,                         \
    "shrink the footprints from map to map (probabilistic SPPM: radius^2 *= (i + alpha) / (i + 1)), so more "          \
    "maps (--iterations, a --time-limit, a still view) converge to the unbiased answer")                               \
  X(alpha, F64, "alpha", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "A", NULL, NULL,                     \
    "--progressive: radius^2 fraction kept per map, in (0, 1) (default 2/3)")                                          \
  X(first_bounce, CHOICE, "first-bounce", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "MODE",             \
    pb_settings_first_bounce_names, NULL,                                                                              \
    "how photons find their first hit: traced from the light, rsm: sampled from reflective shadow maps by "            \
    "reflected power, or auto: rsm for the lights whose map covers under half of their flux (open scenes, where "      \
    "most traced photons miss), traced for the others (default traced: unbiased; the shadow maps miss geometry "       \
    "thinner than a texel)")                                                                                           \
  X(caustic_share, F64, "caustic-share", 0, 0.99, 0.5, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",                 \
    "F", NULL, NULL,                                                                                                   \
    "--first-bounce rsm/auto: the share of each shadow map's photons aimed at the texels that see a mirror or "        \
    "glass (caustic paths) at least, their weights raised to it (unbiased: each photon carries its texel's flux "      \
    "over its own probability); 0: by reflected power alone (default 0.5)")                                            \
  X(tracer, CHOICE, "tracer", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "KIND",                         \
    pb_tracer_names, NULL,                                                                                             \
    "photon tracer: bvh (exact hits in the scene BVH) or images (k cube environment maps of the scene, no "            \
    "hierarchy; approximate, misses counted in --json photons.image_misses; default bvh)")                             \
  X(image_maps, U32, "image-maps", 1, 15, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",                           \
    "K", NULL, "tracer=images",                                                                                        \
    "--tracer images: environment maps, their centres chosen by coverage from 40 candidates (default 8)")              \
  X(image_map_resolution, U32, "image-map-resolution", 8, 1024, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",     \
    "N", NULL, "tracer=images", "--tracer images: texels per cube-face side (default 128)")                            \
  X(estimator, CHOICE, "estimator", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "NAME",                   \
    pb_estimator_names, NULL,                                                                                          \
    "photon density estimator: lbvh (footprints in a per-map LBVH, gathered by traversal), knn (the k nearest "        \
    "photons), splat (screen-space splats), vsch (a cluster hierarchy over the view samples) or auto (see "            \
    "'photonbridge info'; default lbvh)")                                                                              \
  X(knn_k, U32, "knn-k", 1, 512, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "K", NULL, "estimator=knn,auto",   \
    "--estimator knn: photons per density estimate, the bandwidth the distance of the K-th nearest (default 64, "      \
    "about as many as the default gather averages: k_PD, docs/reading-the-numbers.md)")                                \
  X(vsch_radius, F64, "vsch-radius", 0, 1e9, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "M", NULL, NULL,       \
    "--estimator vsch: one photon radius in metres for every photon (default 0: each photon's own footprint "          \
    "radius)")                                                                                                         \
  X(vsch_directional, BOOL, "vsch-directional", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", NULL,         \
    NULL, NULL,                                                                                                        \
    "--estimator vsch: the directional variant (flux per node in 8 octant buckets, weighted by 2 cos at shading, "     \
    "blurred; approximate, faster)")                                                                                   \
  X(splat_ntile, F64, "splat-ntile", 0, 1e6, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "N", NULL, NULL,       \
    "--estimator splat: photons expected per point, the splat kernel's density scale (default 128)")                   \
  X(splat_lmax, F64, "splat-lmax", 0, 1e6, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "F", NULL, NULL,         \
    "--estimator splat: the photon path length at which splats reach full size, as F times the scene's bounding "      \
    "radius (default 1)")                                                                                              \
  X(splat_smax, F64, "splat-smax", 0, 1e6, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "S", NULL, NULL,         \
    "--estimator splat: the largest stretch of a splat along the incident direction, >= 1 (default 4)")                \
  X(splat_tile, U32, "splat-tile", 1, 4096, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "N", NULL, NULL,        \
    "--estimator splat: screen tile edge in pixels for the photon density (default 16)")                               \
  X(leaf_size, U32, "leaf-size", 1, 4096, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "N", NULL, NULL,          \
    "benchmark: fixed LBVH leaf-size threshold instead of the automatic one")                                          \
  X(bandwidth_c0, F64, "bandwidth-c0", 0, 1e6, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", "C0", NULL, NULL,    \
    "a variable bandwidth instead of the differential footprints: every photon a disc of radius h = C0 / sqrt(p) "     \
    "sqrt(A / N), p = cos(theta) R^2 / d^2 clamped to [1/4, 4], A the scene's area, N the paths (default: off)")       \
  X(upsample_levels, U32, "upsample-levels", 0, 4, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",                  \
    "L", NULL, "estimator=lbvh,auto",                                                                                  \
    "multi-level up-sampling: the photon estimate's diffuse irradiance at every 2^L-th pixel, up-sampled level by "    \
    "level by a normal- and depth-aware interpolation, recomputed where the surface changes (corners, edges); "        \
    "glossy lobes and caustics at full resolution; --estimator lbvh only, off with normal maps (default 0: off)")      \
  X(constant_kernel, BOOL, "constant-kernel", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",                 \
    NULL, NULL, NULL,                                                                                                  \
    "ablation: gather with a constant kernel instead of Epanechnikov")                                                 \
  X(no_edge_correction, BOOL, "no-edge-correction", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons", NULL,     \
    NULL, NULL, "ablation: no kernel renormalisation at the edges of faces (corners)")                                 \
  X(no_shading_correction, BOOL, "no-shading-correction", 0, 0, 0, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Photons",     \
    NULL, NULL, NULL,                                                                                                  \
    "ablation: in scenes with normal maps, no shading correction of the indirect light for the bumped normal")         \
  /* ---- Filtering ---- */                                                                                            \
  X(atrous_iterations, U32, "atrous-iterations", 0, 12, 0, PB_SURFACE_ALL, 0, "Filtering", "N", NULL, NULL,            \
    "filter the indirect light: N edge-avoiding A-Trous passes with variance clipping (default 0: off for one "        \
    "frame, 4 for --frames, view and serve)")                                                                          \
  X(atrous_clip, F64, "atrous-clip", 0, 100, 0.25, PB_SURFACE_ALL, PB_SETTING_ADVANCED, "Filtering", "G", NULL, NULL,  \
    "A-Trous detail kept within G local standard deviations (variance clipping; default 0.25; 0: none, the plain "     \
    "A-Trous blur)")                                                                                                   \
  X(temporal, BOOL, "no-temporal", 0, 0, 1, PB_SURFACE_ALL & ~PB_SURFACE_BLENDER, 0, "Filtering", NULL, NULL, NULL,    \
    "--frames, view, serve: no temporal filter of the indirect light (reprojected history; on by default)")

/* The settings' values, and which were given. */
typedef struct pb_settings {
  uint64_t given; /* bit PB_SETTING_BIT(id): given by the user (an option,
                     a request), not the table's default */
#define PB_SETTING_CTYPE_U32 uint32_t
#define PB_SETTING_CTYPE_F64 double
#define PB_SETTING_CTYPE_BOOL int
#define PB_SETTING_CTYPE_CHOICE int
#define X(id, kind, ...) PB_SETTING_CTYPE_##kind id;
  PB_SETTINGS(X)
#undef X
} pb_settings;

enum {
#define X(id, ...) PB_SETTING_##id,
  PB_SETTINGS(X)
#undef X
  PB_SETTING_COUNT
};
#define PB_SETTING_BIT(id) (1ull << PB_SETTING_##id)

typedef enum pb_setting_kind { PB_SETTING_U32, PB_SETTING_F64, PB_SETTING_BOOL, PB_SETTING_CHOICE } pb_setting_kind;

/* One row of the table. */
typedef struct pb_setting_info {
  const char *id, *cli;
  pb_setting_kind kind;
  double lo, hi, def;
  unsigned surfaces, flags;
  const char *group, *metavar;
  const char *const *choices;
  const char *needs;
  const char *help;
  size_t offset; /* of the value in pb_settings */
} pb_setting_info;

extern const pb_setting_info pb_setting_table[PB_SETTING_COUNT];

/* Every setting at its default, none given. */
void pb_settings_init(pb_settings *s);
/* The same for view and serve: PB_SETTING_LIVE_OFF settings at 0. */
void pb_settings_init_live(pb_settings *s);

/* The value of row i as a double (a CHOICE's index, a BOOL's 0/1). */
double pb_settings_get(const pb_settings *s, int i);
/* Sets row i to v (converted to its kind) and marks it given. */
void pb_settings_set(pb_settings *s, int i, double v);

/* The rows given in `from` copied into `to` (serve's requests). */
void pb_settings_merge(pb_settings *to, const pb_settings *from);

/* What must hold across settings: --alpha in (0, 1), a splat stretch of at
 * least 1, the estimator built in; and with `given_needs` (the command
 * line), each setting given away from its default with what it needs
 * (its `needs` column). PB_OK, or PB_ERR_USAGE naming `command` and the
 * options. */
pb_result pb_settings_check(const char *command, const pb_settings *s, int given_needs);

/* Whether row i's `needs` holds in s (1 without one). */
int pb_settings_needs_met(const pb_settings *s, int i);

/* The frame's settings in rd (the rest of rd, seed and I/O, untouched):
 * --max-bounces' photon bounces and eye chains, the A-Trous default (4 for
 * a sequence, 0 for one frame), the noise threshold's default (on unless
 * the work is set: --iterations, --spp, --time-limit, --direct-only, a
 * sequence) and the photon maps it and --time-limit plan. */
void pb_settings_render_desc(const pb_settings *s, int sequence, struct pb_render_desc *rd);

/* The photon maps a noise threshold or a time limit plans without
 * --iterations: the option's bound; the threshold or the time ends the
 * frame long before. */
enum { PB_SETTINGS_OPEN_ITERATIONS = 1u << 16 };

/* Writes the table as a Python module (the add-on's settings_table.py). */
void pb_settings_write_python(FILE *f);

#endif
