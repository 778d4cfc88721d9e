/* The photon stages of a frame, as two replaceable parts behind small
 * interfaces (ARCHITECTURE.md: later work adds kNN, screen-space splatting,
 * the view-sample hierarchy and an image-space tracer):
 *
 *   tracer:    scene -> photon map (pb_gpu_photon records on the device)
 *              (RSM first bounce, power-proportional budget, differentials,
 *               Russian roulette; seeds 000 section 4, 001 section 24.2)
 *   estimator: photon map + shading points -> indirect and caustic radiance
 *              (LBVH over footprints + gather, seed 000 sections 5-6)
 *
 * frame.c orders them after `direct`. Both allocate from the photon budget
 * and the scene, never from fixed maxima. */
#ifndef PB_RENDER_PHOTON_H
#define PB_RENDER_PHOTON_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "scene/scene.h"

/* The photon map one tracer iteration produced, resident on the device. */
typedef struct pb_photon_map {
  pb_gpu_buffer photons;      /* pb_gpu_photon[capacity] */
  pb_gpu_buffer counts;       /* pb_gpu_photon_counts */
  uint32_t capacity;
  /* Host copies of the counters, read back after the trace. */
  uint32_t stored, caustic, emitted, overflow, clamped;
} pb_photon_map;

/* Default s of a frame (render.h: smoothing 0). Footprint radius
 * r' = s (Delta R)^(3/4) (Delta |dP|)^(1/4) (seed 000 section 4.3 made
 * scale-free, R the scene's bounding radius; photon_trace.comp pb_store).
 * s = 2.5, chosen from the sweep in bench/README.md ("Smoothing factor s",
 * lavapipe, 128 px, 8 maps of 2^16 and 2^17 paths): cornell_box and
 * spot_room both have their least error vs the reference at s = 2.5-3
 * (k_PD 50-85); s = 1 (k_PD ~10) loses 3 dB, s >= 4 blurs (k_PD > 130,
 * where r_max = 5 % of the scene radius does not clamp first). */
#define PB_PHOTON_SMOOTHING_DEFAULT 2.5f
#define PB_PHOTON_SMOOTHING_DEFAULT_STR "2.5"
/* Default s_caustic: caustic photons keep their
 * differential footprint, uncompressed, times s_caustic (seed 000 4.3
 * compresses only the diffusely reflected ones; photon_trace.comp pb_store,
 * PB_PHOTON_PARAM_CAUSTIC_RAW). The old footprint (compressed like the
 * diffuse ones with s = 5, twice the diffuse s where the paper's caustic
 * factor is 1/12 to 1/2 of it) was only sharp while the old r_max clamped
 * it. Measured (bench/README.md, "Caustic footprints"; r_max 18 Delta R):
 * ring 64 px, 8 maps of 2^16 paths: 23.4 dB at 0.5, 22.3 at 1, 19.5 at 2,
 * 19.1 at 5, 21.6 compressed; 2^18: 25.9 dB at 0.5, 25.5 at 1, 24.8
 * compressed; cornell_caustics 48 px: 33.8-33.9 dB for all (its caustic is
 * not footprint-bound). 0.5 was the best on ring at those budgets, where a
 * map held some 200-800 caustic records. Raised to 1 with the RSM's caustic
 * share (PB_PHOTON_CAUSTIC_SHARE_DEFAULT, 2026-12-04): a footprint of
 * S Delta |dP| holds k ~ pi S^2 photons whatever the budget (0.72 at 0.5,
 * 2.9 at 1: --json photons.k_pd on ring), so the noise of one gather is set
 * by S, not by the photons, and more caustic records only sharpen it; with
 * enough of them S = 1 wins. ring, 128 px, 1 map of 2^18 paths, 16 spp,
 * --first-bounce rsm, caustic share 0.5 (96,480 caustic records), against
 * the bench's 2048-spp reference: 31.6 dB at S 0.5, 34.6 at 0.75, 35.5 at 1;
 * 64 px against tests/data/ring: 31.4 at 0.5, 35.8 at 1 (and with the
 * share off, 31.4 and 33.2). bench/README.md, "The caustic share". */
#define PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT 1.0f
#define PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT_STR "1"
/* Default r_max: PB_PHOTON_R_MAX_FACTOR r_ref, with
 * r_ref = Delta R the photon spacing on the scene's bounding sphere (R its
 * radius, Delta = 2 sqrt(pi / N)). Every footprint is a multiple of Delta
 * (diffuse: r' = s Delta R^(3/4) |dP|^(1/4); caustic, uncompressed:
 * s_c Delta |dP|), so with r_max ~ Delta the clamped share does not depend
 * on the budget N and r_max shrinks as N^(-1/2) with the photons. The old
 * default, 5 % of R, is 0.05 / Delta r_ref: 2.6 r_ref at 2^15 paths, where it
 * clamped 96-100 % of the footprints of every sample (the kernel was a fixed
 * disc), 7.2 r_ref at 2^18. Measured (test_gpu_photon_clamp, one map of 2^15
 * paths, r_max 10 R, the default s and s_caustic): the 99th percentile of
 * r' / r_ref is 10.4 (cornell_box), 14.7 (cornell_caustics), 12.8 (ring),
 * 13.9 (spot_room), 11.2 (sun_atrium); 99.5th 11.9-18.5. 18 clamped at most
 * 1 % on every sample (0.07-0.55 % at 2^15 and 2^17 paths), with a margin
 * for the scene-dependent tail. Raised to 30 with S_c 1 (2026-12-04): a
 * caustic footprint is S_c Delta |dP|, linear in S_c, so ring's (all
 * caustic) doubled: 99th percentile 25.6, 99.5th and max 28.6 at 2^15
 * traced paths, where 18 clamped 1.89 % (0.77 % at 2^17); the others'
 * 99.5th stayed 11.9-19.1 (cornell_caustics 99.9th 32.1). 30 is above
 * ring's largest footprint and keeps the diffuse ones' shares under the old
 * ones. */
#define PB_PHOTON_R_MAX_FACTOR 30.0f

/* Default caustic share of an RSM's photons (render --caustic-share;
 * photon_rsm.comp PB_RSM_MODE_BOOST): the specular texels get at least this
 * share of a map's photons. 0.5: half of a map's paths for caustics where a
 * light sees mirrors or glass, half for the rest (Jensen's practice of a
 * caustic map about as large as the global one), a default that does not
 * starve the diffuse light of scenes whose indirect light is not a caustic.
 * ring (where every stored record is caustic) gains from more: 128 px, 1 map
 * of 2^18, 16 spp, S_c 1: 35.5 dB at 0.5 (96,480 caustic records), 36.0 at
 * 0.9 (173,572), 35.7 at 0.95; without the share 17,359 records and
 * 31.7 dB (bench/README.md, "The caustic share"). */
#define PB_PHOTON_CAUSTIC_SHARE_DEFAULT 0.5f
#define PB_PHOTON_CAUSTIC_SHARE_DEFAULT_STR "0.5"

/* How a path's first hit is found (seed 001 24.2.1). */
typedef enum pb_photon_first_bounce {
  PB_FIRST_BOUNCE_DEFAULT = 0, /* PB_FIRST_BOUNCE_TRACE */
  PB_FIRST_BOUNCE_TRACE,       /* emission traced from the light */
  PB_FIRST_BOUNCE_RSM,         /* texels of a reflective shadow map, sampled
                                  by reflected power (photon_rsm.c) */
  PB_FIRST_BOUNCE_AUTO         /* per light: the map where it covers less
                                  than PB_RSM_AUTO_COVERAGE of the light's
                                  flux (open scenes: most traced photons
                                  would miss), else traced */
} pb_photon_first_bounce;

/* Zero means default for every field. */
typedef struct pb_photon_trace_desc {
  uint32_t photons;           /* paths emitted per iteration; 0: 2^18 */
  uint32_t max_bounces;       /* stored bounces per path; 0: unbounded, paths
                                 end by Russian roulette
                                 (PB_PHOTON_BOUNCE_CAP only a safety net) */
  float smoothing;            /* s for diffuse photons (dimensionless, see
                                 pb_store in photon_trace.comp); 0:
                                 PB_PHOTON_SMOOTHING_DEFAULT */
  float smoothing_caustic;    /* caustic footprints: this times Delta dP,
                                 uncompressed; 0:
                                 PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT */
  float r_max;                /* footprint radius clamp, metres; 0:
                                 PB_PHOTON_R_MAX_FACTOR Delta R */
  uint32_t first_bounce;      /* pb_photon_first_bounce; 0: TRACE */
  uint32_t rsm_resolution;    /* RSM texels per face side; 0: 64 */
  float caustic_share;        /* RSM first bounce: the share of each map's
                                 photons its specular texels get at least
                                 (photon_rsm.comp PB_RSM_MODE_BOOST); 0:
                                 PB_PHOTON_CAUSTIC_SHARE_DEFAULT, < 0: by
                                 reflected power alone */
  float bandwidth_c0;         /* > 0: seed 003's variable bandwidth instead of
                                 seed 000's footprints: every photon a disc
                                 of radius h = C0 / sqrt(p) sqrt(A / N)
                                 (section 6; pb_store in photon_trace.comp),
                                 C0 this; 0: off */
} pb_photon_trace_desc;

/* Seed 003's PDF clamp [P_min, P_max] for the bandwidth (section 6: "p ...
 * is clamped to a certain range"; the paper gives no values). p = cos(theta)
 * / d^2 is made dimensionless with the scene's bounding radius R, p R^2 (a
 * photon that met a surface head-on after travelling R has 1), and clamped
 * to [1/4, 4]: h varies at most 2x either way around C0 sqrt(A / N). */
#define PB_PHOTON_BANDWIDTH_P_MIN 0.25f
#define PB_PHOTON_BANDWIDTH_P_MAX 4.0f

/* Path length. The default stores every bounce until
 * Russian roulette ends the path: survival p = min(1, max_c(Phi_c w_c) /
 * max_c(Phi_c)) (seed 001 eq. 1), capped at 0.95 from the 8th interaction
 * on (where the old default of 7 stored bounces truncated), so a path
 * reaches the cap of 255 stored bounces (the 8 bits of
 * PB_PHOTON_BOUNCE_SHIFT) with probability below 0.95^248 ~ 3e-6 even on
 * white walls, and the light beyond it, rho^255 of a closed room of albedo
 * rho, is nil. Memory: a path stores about rho / (1 - rho) records, so the
 * buffer holds PB_PHOTON_RECORDS_PER_PATH per path (enough up to rho 0.92
 * everywhere), or the device's limit; an overflow is PB_ERR_LIMIT. */
enum { PB_PHOTON_BOUNCE_CAP = 255, PB_PHOTON_RECORDS_PER_PATH = 12 };

typedef struct pb_photon_tracer pb_photon_tracer;

pb_result pb_photon_tracer_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs,
                                  const pb_photon_trace_desc *desc, pb_photon_tracer **out);
/* A new pose of the same scene (sequences: pb_scene_set_time, the GPU scene
 * updated in place): the budget split, light powers, scene centre and radius
 * (and r_max when it was defaulted) follow s, and reflective shadow maps are
 * made again. The scene's counts must be those the tracer was made with. */
pb_result pb_photon_tracer_update(pb_gpu *g, pb_photon_tracer *t, const pb_scene *s);
/* Traces one iteration with seed (seed, iteration) into `map` (created on the
 * first call, reused after). gpu_ms gets per-pass times (may be NULL). */
pb_result pb_photon_tracer_run(pb_gpu *g, pb_photon_tracer *t, uint64_t seed, uint32_t iteration,
                               pb_photon_map *map, double *gpu_ms);
/* pb_photon_tracer_run in three steps, so that the trace and the LBVH build
 * go in one submission with no host round trip between them (the build reads
 * the stored count from map->counts on the GPU): prepare (creates the map on
 * the first call, uploads this iteration's parameters; no command buffer
 * open), record (into the open command buffer; timestamp slots ts_slot and
 * ts_slot + 1), and after the submission finish (reads the counts back into
 * map->stored etc., the per-pass time from the same slots, and fails with
 * PB_ERR_LIMIT where the map overflowed). */
pb_result pb_photon_tracer_prepare(pb_gpu *g, pb_photon_tracer *t, uint64_t seed, uint32_t iteration,
                                   pb_photon_map *map);
pb_result pb_photon_tracer_record(pb_gpu *g, pb_photon_tracer *t, uint32_t ts_slot);
pb_result pb_photon_tracer_finish(pb_gpu *g, pb_photon_tracer *t, pb_photon_map *map, uint32_t ts_slot,
                                  double *gpu_ms);
void pb_photon_tracer_destroy(pb_gpu *g, pb_photon_tracer *t);
/* The image-space tracer (render/photon/tracer.h, seed 003): from now on the
 * tracer's segments are searched in `maps` (image_maps.h; kept alive and
 * up to date by the caller) instead of the scene BVH, with the same
 * emission, scattering and records. image_counts: the search's counters of
 * the last run (zero without maps). */
struct pb_image_maps;
struct pb_gpu_image_counts;
pb_result pb_photon_tracer_use_image_maps(pb_gpu *g, pb_photon_tracer *t, const struct pb_image_maps *maps);
void pb_photon_tracer_image_counts(const pb_photon_tracer *t, struct pb_gpu_image_counts *out);

/* Statistics of the last pb_photon_tracer_run (photon_trace.c). */
typedef struct pb_photon_trace_stats {
  uint32_t guarded;    /* divisions guarded (grazing hits, cos_t -> 0,
                          degenerate footprints) + records dropped as
                          non-finite: nothing non-finite is ever stored */
  uint32_t absorbed;   /* paths ended by Russian roulette */
  uint32_t escaped;    /* paths that left the scene */
  uint32_t photons;    /* paths per iteration (the budget) */
  float delta;         /* global spacing Delta = 2 sqrt(pi / photons) */
  float r_max;         /* footprint radius clamp in use, metres */
  float scene_radius;  /* the scene's bounding radius R, metres */
  uint32_t rsm_lights; /* lights whose photons started from their RSM */
  float rsm_coverage;  /* smallest coverage of a light's RSM (share of its
                          flux on the scene; 1 without maps) */
  float rsm_boost;     /* largest factor a light's specular texels were
                          weighted up by (the caustic share; 1: none) */
} pb_photon_trace_stats;
void pb_photon_tracer_stats(const pb_photon_tracer *t, pb_photon_trace_stats *out);

/* The budget split (seed 001 24.2.1): photons[i] paths for light i, in
 * proportion to the luminance of pb_light_power (directional lights over the
 * disc of the scene's bounding radius), largest remainders, summing to
 * `total` when any light has power. first[i] is the light's first path. A
 * scene with a world has one slot more, the last (index light_count), of
 * power pi R^2 x its radiance integrated over the sphere (the flux through
 * the scene's bounding disc): the arrays hold pb_photon_slots(s) entries. */
uint32_t pb_photon_slots(const pb_scene *s);
void pb_photon_split_budget(const pb_scene *s, uint32_t total, uint32_t *photons, uint32_t *first);

/* Tests only: trace paths in triples whose members 1 and 2 step the
 * (eq.-8-scaled) parameters of decision `depth` (0: emission, k: the k-th
 * interaction) by h (records' `path` is the invocation, 3 j + member); flags:
 * PB_PHOTON_PARAM_RAW_FOOTPRINT stores Delta dP (no -3/4 compression, s or
 * r_max), PB_PHOTON_PARAM_STORE_FIRST stores the first hit too. h = 0 and
 * flags = 0 turn it off. */
void pb_photon_tracer_debug(pb_photon_tracer *t, float h, uint32_t depth, uint32_t flags);
void pb_photon_map_destroy(pb_gpu *g, pb_photon_map *m);

/* ---- estimator: photon LBVH + gather (lbvh.c, lbvh_sort.c, gather.c) -----
 * Per photon map (every iteration of every frame), on the GPU from the map's
 * own photon count: bounds and footprint areas -> T_auto -> Morton codes ->
 * radix sort -> photons in Morton order, hierarchy, boxes and leaf merge by
 * T_auto in one bottom-up pass (seed 000 sections 5-6). Then, per sample,
 * the gather pass reads the frame's G-buffer and adds eq. 1 into per-pixel
 * pb_gpu_photon_accum sums (and into the beauty accumulator). */

struct pb_pass_setup;

/* pb_photon_estimate_desc: render/estimate/estimator_desc.h (via render.h). */

typedef struct pb_photon_estimator pb_photon_estimator;

typedef struct pb_photon_estimate_stats {
  uint32_t photons;           /* photons in the last build */
  uint32_t t_auto;            /* T_auto of the last build (as computed, also
                                 when desc.leaf_size overrides it) */
  uint32_t leaf_size;         /* threshold the last build used */
  uint32_t leaves;            /* leaves after the merge */
  float area_sum;             /* summed footprint ellipse areas, m^2 */
  float scene_area;           /* summed triangle areas, m^2 */
  double build_ms;            /* last build: GPU timestamps (wall without) */
  double bounds_ms;           /* of which setup + bounds + T_auto, */
  double morton_ms;           /* the Morton codes, */
  double sort_ms;             /* the radix sort (all passes), */
  double climb_ms;            /* the reorder + hierarchy + boxes + leaf merge;
                                 each -1 without timestamps */
  uint32_t stack_overflow;    /* gather traversals cut short (expected 0) */
} pb_photon_estimate_stats;

pb_result pb_photon_estimator_create(pb_gpu *g, const pb_scene *s, const pb_photon_estimate_desc *desc,
                                     pb_photon_estimator **out);
/* A new pose of the same scene: the surface area T_auto divides by. */
void pb_photon_estimator_update(pb_photon_estimator *e, const pb_scene *s);
/* Builds the LBVH over the map's photons (own submission, waits): their
 * number is read by the GPU from map->counts (pb_gpu_photon_counts.stored,
 * at most map->capacity) where the map has that buffer (the tracer's maps),
 * else it is map->stored (maps made by the host). Buffers follow
 * map->capacity. */
pb_result pb_photon_estimator_build(pb_gpu *g, pb_photon_estimator *e, const pb_photon_map *map,
                                    double *gpu_ms);
/* pb_photon_estimator_build in three steps (behind pb_photon_tracer_record
 * in the same submission, after a barrier): prepare (buffers for
 * map->capacity, descriptors; no command buffer open), record (timestamp
 * slots ts_slot .. ts_slot + 4), and after the submission done (the build's
 * GPU times from those slots). */
pb_result pb_photon_estimator_prepare(pb_gpu *g, pb_photon_estimator *e, const pb_photon_map *map);
pb_result pb_photon_estimator_record_build(pb_gpu *g, pb_photon_estimator *e, uint32_t ts_slot);
void pb_photon_estimator_build_done(pb_gpu *g, pb_photon_estimator *e, uint32_t ts_slot, double *gpu_ms);
/* Points the gather at the frame's pass buffers (scene.glsl's bindings and
 * specialization constants), at `photon_accum` (pb_gpu_photon_accum per
 * pixel of the band) and, in scenes with normal maps, `photon_nmap`
 * (pb_gpu_photon_nmap per pixel; NULL otherwise). Call after every build
 * (buffers may be reallocated). */
pb_result pb_photon_estimator_bind(pb_gpu *g, pb_photon_estimator *e, const struct pb_pass_setup *ps,
                                   const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *photon_nmap);
/* Records the gather of sample `sample_index` over `pixels` pixels into the
 * open command buffer; flags: PB_GATHER_* (shaders/shared/pb_lbvh.h). */
pb_result pb_photon_estimator_record(pb_gpu *g, pb_photon_estimator *e, uint32_t sample_index,
                                     uint32_t pixels, uint32_t flags);
/* The multi-level up-sampling's gather (gather.comp built with
 * -DPB_UPSAMPLE=1; render/estimate/upsample.h, seed 003 sec. 6): bound as
 * pb_photon_estimator_bind plus the irradiance plane and the pixel list
 * (shared/pb_upsample.h); recorded over `invocations` work items with
 * PB_GATHER_UPS_LIST (the list of level `level`) or PB_GATHER_UPS_REST
 * (every pixel of the band). Call bind after pb_photon_estimator_bind. */
pb_result pb_photon_estimator_bind_upsample(pb_gpu *g, pb_photon_estimator *e, const struct pb_pass_setup *ps,
                                            const pb_gpu_buffer *photon_accum, const pb_gpu_buffer *irradiance,
                                            const pb_gpu_buffer *list);
pb_result pb_photon_estimator_record_upsample(pb_gpu *g, pb_photon_estimator *e, uint32_t sample_index,
                                              uint32_t invocations, uint32_t flags, uint32_t level);
/* The largest footprint radius of the maps gathered next (the tracer's
 * r_max, m): how far the gather looks for the edges of a face to
 * renormalise its kernel (gather.comp); 0 (the default): no renormalisation,
 * as for maps made by the host, whose radii the estimator does not know. */
void pb_photon_estimator_set_edge_reach(pb_photon_estimator *e, float r_max);
/* Bandwidth of the next builds: every footprint's axes, radius and normal
 * extent are multiplied by `scale` (0 or non-finite: 1) when the LBVH is
 * built (lbvh_reorder, lbvh_bounds), so the boxes, T_auto and the gather's
 * kernel and its 1/A normalisation all use the scaled ellipsoid. The
 * progressive frame (render.h) shrinks it between iterations. */
void pb_photon_estimator_set_footprint_scale(pb_photon_estimator *e, float scale);
/* Reads the last build's statistics (t_auto, leaves, areas) back. */
pb_result pb_photon_estimator_stats(pb_gpu *g, pb_photon_estimator *e, pb_photon_estimate_stats *out);
void pb_photon_estimator_destroy(pb_gpu *g, pb_photon_estimator *e);

/* Tests: the device buffers of the last build. nodes: pb_gpu_lbvh_node[count]
 * (inner node p at the split after sorted photon p, the one-leaf root at
 * count - 1); photons: pb_gpu_photon_packed[count] in Morton order
 * (render/photon/photon_pack.h decodes them); keys, order:
 * the sorted 30-bit codes and the photons' indices in the map, uints from
 * sorted_offset; info: pb_gpu_lbvh_info. count: photons of the last
 * build, as of the last pb_photon_estimator_stats. */
typedef struct pb_photon_lbvh_view {
  const pb_gpu_buffer *nodes, *photons, *keys, *order, *info;
  uint32_t sorted_offset;
  uint32_t count;
} pb_photon_lbvh_view;
void pb_photon_estimator_lbvh(const pb_photon_estimator *e, pb_photon_lbvh_view *out);

#endif
