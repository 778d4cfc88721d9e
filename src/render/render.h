/* The GPU renderer: scene upload, the passes of a frame (one file each) and
 * the frame that orders them (frame.c).
 *
 * Frame (the photon stages slot in after `direct`):
 *   per sample s < spp:  gbuffer (primary visibility, specular eye chains,
 *                        emission seen along them) -> direct (shadow rays to
 *                        point, spot and directional lights, and to one
 *                        emissive triangle picked by power)
 *   photon stages (unless direct_only; render/photon/photon.h): per iteration k < K
 *     trace (seed, k) -> LBVH build (lbvh.c) -> gather of that iteration's
 *     samples s in [k spp / K, (k+1) spp / K) (gather.c), after `direct`,
 *     into the indirect/caustic accumulators and the beauty
 *   [future: temporal -> a-trous -> compose]
 *   resolve on the host: divide by spp, split into AOVs. */
#ifndef PB_RENDER_H
#define PB_RENDER_H

#include <stdint.h>

#include "core/result.h"
#include "render/scene/bvh.h"
#include "gpu/gpu.h"
#include "render/estimate/estimator_desc.h"
#include "scene/scene.h"

/* The scene resident on the GPU. */
typedef struct pb_gpu_scene {
  pb_bvh bvh;                 /* host copy (stats, tests) */
  pb_gpu_buffer nodes, tris;  /* BVH */
  pb_gpu_buffer indices;      /* uint[3 * triangle_count] */
  pb_gpu_buffer positions;    /* float[3 * vertex_count] */
  pb_gpu_buffer normals;      /* float[3 * vertex_count] (or 1 dummy) */
  pb_gpu_buffer uvs;          /* float[2 * vertex_count] */
  pb_gpu_buffer tri_material; /* uint[triangle_count] */
  pb_gpu_buffer materials, textures, texels, lights;
  pb_gpu_buffer emitters;     /* pb_gpu_emitter[emitter_count] (or 1 dummy) */
  pb_gpu_buffer world;        /* pb_gpu_world + its map and sampling table
                                 (shared/pb_gpu.h); a header with flags 0
                                 when the scene has no world */
  uint32_t light_count, material_count, texture_count;
  uint32_t emitter_count;     /* emissive triangles with power > 0 */
  uint32_t features;          /* PB_FEATURE_* of the scene */
  int has_normals;
  uint32_t tangent_base;      /* normal maps: float index of the tangents in
                                 `normals` (pb_gpu_frame.tangent_base); 0:
                                 none */
  uint32_t uv1_base, color_base; /* float indices of TEXCOORD_1 and COLOR_0
                                 in `uvs` (pb_gpu_frame); 0: none */
  uint32_t principled2_base;  /* Principled v2 tables in `texels`
                                 (pb_gpu_frame.principled2_base); 0: none */
  double upload_s;
  /* For pb_gpu_scene_update: the shape of the scene it was made from, and
   * room for a rebuilt BVH (PB_BVH_WIDTH x triangles + 1 nodes, the most a
   * build can make, when the scene has anim; the first build's otherwise)
   * and for every emissive triangle, so that updates never replace a buffer
   * that passes have bound. */
  uint32_t vertex_count, triangle_count, node_capacity, emitter_capacity;
  double sah_built;           /* pb_bvh_sah_cost after the last (re)build */
  double sah;                 /* ... now (after refits) */
  uint32_t refits;            /* refits since the last (re)build */
  /* Ray queries (a device with pb_gpu_limits.ray_query): the scene's
   * triangles as acceleration structures (gpu/accel.c), which every pass
   * that casts rays traces instead of the BVH (pb_kernel_select, the
   * shaders' _rq builds); brought up to date with the BVH by
   * pb_gpu_scene_update. The BVH is still built (statistics, tests). */
  int ray_query;
  pb_gpu_accel accel;
} pb_gpu_scene;

/* The acceleration structure the scene's passes trace, or NULL: the BVH. */
static inline const pb_gpu_accel *pb_gpu_scene_accel(const pb_gpu_scene *gs) {
  return gs && gs->ray_query ? &gs->accel : NULL;
}

pb_result pb_gpu_scene_create(pb_gpu *g, const pb_scene *s, pb_gpu_scene *out);
void pb_gpu_scene_destroy(pb_gpu *g, pb_gpu_scene *gs);

/* How pb_gpu_scene_update brings the BVH up to date. */
enum {
  PB_BVH_UPDATE_AUTO = 0,    /* refit, or rebuild once the refitted tree's SAH
                                cost exceeds PB_BVH_REFIT_MAX_SAH x that of the
                                last build (scene_gpu.c, bench/anim.c) */
  PB_BVH_UPDATE_REFIT = 1,   /* same topology, boxes recomputed bottom-up */
  PB_BVH_UPDATE_REBUILD = 2, /* a new SAH build (pb_bvh_build) */
};

/* Brings `gs` (made by pb_gpu_scene_create from `s`) up to date after `s`
 * was posed again (pb_scene_set_time): uploads positions, normals, lights and
 * the emitter table (emissive triangles move too), and refits or rebuilds the
 * BVH per `mode`. Buffers are kept (passes created on `gs` stay valid); the
 * scene must have the same vertices, triangles, lights and materials as at
 * creation (PB_ERR_USAGE otherwise). `ms` (may be NULL): wall time of the
 * whole update. A refit that meets a non-finite triangle rebuilds instead;
 * a rebuild that needs more nodes than gs holds (a scene without anim at
 * creation) refits in AUTO mode and fails with PB_ERR_LIMIT in REBUILD. */
pb_result pb_gpu_scene_update(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs, int mode, double *ms);

/* Ray queries (tests, benchmark): closest hit or occlusion for each ray. */
typedef struct pb_raycast_pass {
  pb_gpu_pipeline pipe;
  pb_gpu_buffer rays, hits;
  uint32_t capacity;
} pb_raycast_pass;

pb_result pb_raycast_create(pb_gpu *g, const pb_gpu_scene *gs, uint32_t capacity,
                            pb_raycast_pass *out);
void pb_raycast_destroy(pb_gpu *g, pb_raycast_pass *p);
/* Traces n <= capacity rays; gpu_ms (may be NULL) gets the kernel's time from
 * timestamps (or wall time of the submission when the device has none). */
pb_result pb_raycast_run(pb_gpu *g, pb_raycast_pass *p, const pb_gpu_ray *rays, uint32_t n,
                         int any_hit, pb_gpu_hit *hits, double *gpu_ms);
/* The rays and hits buffers of a pass of `capacity` rays (both passes). */
pb_result pb_raycast_buffers_create(pb_gpu *g, const char *name, uint32_t capacity, pb_raycast_pass *p);

/* The same through VK_KHR_ray_query (raycast_rq.c), on a device with
 * pb_gpu_limits.ray_query (PB_ERR_NOT_AVAILABLE otherwise): its own
 * acceleration structures over s's triangles (hit prim = s's triangle index,
 * as the BVH's pb_gpu_tri.prim), the same rays, hits and timing. */
typedef struct pb_raycast_rq_pass {
  pb_gpu_accel accel;
  pb_raycast_pass pass; /* its pipeline, buffers and run: pb_raycast_run's */
} pb_raycast_rq_pass;

pb_result pb_raycast_rq_create(pb_gpu *g, const pb_scene *s, uint32_t capacity, pb_raycast_rq_pass *out);
void pb_raycast_rq_destroy(pb_gpu *g, pb_raycast_rq_pass *p);
pb_result pb_raycast_rq_run(pb_gpu *g, pb_raycast_rq_pass *p, const pb_gpu_ray *rays, uint32_t n,
                            int any_hit, pb_gpu_hit *hits, double *gpu_ms);

/* ---- the frame ----------------------------------------------------------- */

/* A named statistic of the photon tracer (tracer.h). summed: a count of one
 * photon map, added over the frame's maps; otherwise the last value. */
typedef struct pb_tracer_stat {
  const char *name;
  double value;
  int summed;
} pb_tracer_stat;
enum { PB_TRACER_MAX_STATS = 24 };
/* Merges one photon map's named statistics `now` (n of them) into a frame's
 * list of *count (at most PB_TRACER_MAX_STATS): summed ones added, the
 * others replaced, new names appended while there is room. last_only: only
 * the statistics that are not summed (read again after the frame's last
 * sample). tracer.c; the tracer's, the estimator's and the up-sampling's. */
void pb_tracer_stats_merge(pb_tracer_stat *list, uint32_t *count, const pb_tracer_stat *now, uint32_t n,
                           int last_only);

/* What pb_render_io.progress hears after each finished photon iteration
 * (band 0 of the image, the first rows when it needs several bands). */
typedef struct pb_render_progress {
  uint32_t iteration, iterations;  /* finished, planned (fewer once the
                                      time limit stopped the refinement) */
  uint32_t samples, spp;           /* samples per pixel done, planned */
  double noise;                    /* the frame's noise estimate (RMS on the
                                      display image, noise.h), < 0: none yet */
  double elapsed_s;                /* since pb_render_frame began */
  uint32_t width, height;
  const float *beauty;             /* NULL, or the mean beauty (RGBA,
                                      width x height, top row first) of the
                                      samples done: see preview_interval_s */
} pb_render_progress;
/* A non-PB_OK return stops the render with that result. */
typedef pb_result (*pb_render_progress_fn)(void *user, const pb_render_progress *p);

/* A frame's settings: values only, zero meaning default for every field
 * (what the frame reads, calls or keeps besides: pb_render_io). */
typedef struct pb_render_desc {
  uint32_t spp;                /* 0: 1 (pixel centres); >1 jittered/stratified */
  uint32_t max_specular_depth; /* delta interactions along an eye path; 0:
                                  PB_RENDER_MAX_SPECULAR_DEPTH, a safety cap:
                                  Russian roulette ends longer chains
                                  (gbuffer.comp) */
  float glossy_path_roughness; /* Blender materials: a specular or clearcoat
                                  layer of Roughness above this is shaded
                                  where the eye path stops (direct light and
                                  the photon map), a smoother one followed by
                                  the eye path; 1: every one followed; < 0:
                                  none; 0: PB_RENDER_GLOSSY_PATH_ROUGHNESS */
  int direct_only;             /* 1: only paths with at most one scattering
                                  event (the reference's direct AOV) */
  uint64_t seed;
  /* Photon mapping (indirect light; off with direct_only or without point,
   * spot or directional lights, which the tracer emits from). */
  uint32_t photons;            /* paths per iteration; 0: the tracer's 2^18 */
  uint32_t iterations;         /* independent photon maps (seeds) averaged;
                                  sample s gathers from map s * K / spp, spp
                                  is raised to K; 0: 1 */
  uint32_t photon_bounces;     /* stored bounces per path; 0: unbounded
                                  (Russian roulette, photon.h) */
  float smoothing;             /* footprint factor s (dimensionless); 0:
                                  PB_PHOTON_SMOOTHING_DEFAULT (photon.h) */
  float r_max;                 /* footprint clamp, m; 0: the tracer's */
  float smoothing_caustic;     /* caustic photons keep their differential
                                  footprint, times this (uncompressed);
                                  0:
                                  PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT */
  pb_estimator_desc estimator; /* the density estimator (estimator.h:
                                  lbvh, knn, splat, vsch, auto) and its own
                                  settings (the LBVH gather's leaf size,
                                  constant kernel, edge correction: .lbvh);
                                  zero: the LBVH gather, T_auto,
                                  Epanechnikov */
  uint32_t first_bounce;       /* pb_photon_first_bounce (photon.h); 0:
                                  traced from the light */
  float caustic_share;         /* RSM first bounce: share of a map's photons
                                  its specular texels get at least; 0:
                                  PB_PHOTON_CAUSTIC_SHARE_DEFAULT, < 0: by
                                  reflected power alone */
  uint32_t tracer;             /* pb_tracer_kind (tracer.h); 0: the BVH */
  uint32_t image_maps;         /* tracer images: k maps; 0: 8 */
  uint32_t image_map_resolution; /* tracer images: texels per face side; 0: 128 */
  float bandwidth_c0;          /* > 0: seed 003's variable bandwidth footprints,
                                  h = C0 / sqrt(p) sqrt(A / N) (photon.h); 0:
                                  seed 000's differential footprints */
  uint32_t upsample_levels;    /* seed 003's multi-level up-sampling of the
                                  diffuse photon irradiance (upsample.h):
                                  estimated at every 2^L-th pixel, up-sampled
                                  L times; 0: off, 1 .. 4; the LBVH gather
                                  only; off in scenes with normal maps */
  uint32_t atrous_iterations;  /* spatial filter of the indirect AOV
                                  (atrous.h, seed 001 24.4.2); 0: off */
  float atrous_gamma;          /* its detail clipping in standard
                                  deviations; 0: the filter's default, < 0:
                                  no detail kept (plain A-Trous) */
  int no_shading_correction;   /* 1: skip seed 001's eq. 20 on the indirect
                                  AOV in scenes with normal maps
                                  (shading_correction.h; tests, ablation) */
  int progressive;             /* 1: footprints shrink between iterations
                                  (probabilistic SPPM, frame.c) */
  float alpha;                 /* progressive: radius^2 kept per iteration,
                                  in (0, 1); 0: 2/3 */
  int jitter;                  /* 1: jittered sample positions also at 1
                                  spp (still frames of a sequence) */
  uint32_t iteration_base;     /* progressive: iterations already averaged
                                  by earlier frames of a still view
                                  (sequence.h); the radius schedule goes on
                                  from there */
  /* Progressive refinement (render --time-limit, --preview, --progress):
   * pb_render_io.progress is called after each iteration; with
   * preview_interval_s >= 0 it also gets the mean beauty so far, at most
   * once per that many seconds (never for the last iteration; the image in
   * one band only: the accumulators are read back for it). time_limit_s >
   * 0: no iteration starts after that many seconds; the frame averages
   * those run (stats.spp and stats.iterations say how many). */
  double preview_interval_s;   /* < 0: no preview (progress only) */
  double time_limit_s;
  /* The noise threshold: > 0: the frame checks its own estimate of its
   * noise (render/frame/noise.h: the RMS noise of the display image, from two
   * groups of independent photon maps) as the maps finish, and no map
   * starts once the estimate is at or below this (the iterations are then
   * the most it runs). Checked on band 0 (the whole image in one band).
   * stats.noise_* report it; 0: off. */
  double noise_threshold;
  /* A crop of a larger frame (render --crop, Blender's border): the image
   * is the width x height pixels at column crop_x, row crop_y (top row
   * first) of a full_width x full_height frame, with that frame's camera
   * window and random numbers, so it equals that part of the full render
   * (up to the photon maps' own sampling, which does not depend on the
   * image). full_width 0: the image is the whole frame. */
  uint32_t full_width, full_height, crop_x, crop_y;
  /* Frames in flight (sequences, with pb_render_io.context): 1: the frame's
   * last submission (resolve, filters, eq. 20, and a copy of the resolved
   * planes into the readback's staging ring, targets.h) is not waited for;
   * pb_render_frame returns with out->pending set, out's arrays allocated
   * but not filled and its statistics partial, and the host goes on (the
   * next frame's pose, the caller's output of the previous frame) while the
   * GPU runs it. pb_render_frame_settle then waits and completes the
   * statistics (before the context's next pb_render_frame, or by it:
   * pb_render_io.settle_first; the frame's timestamps stay in its own submission
   * context), pb_render_frame_read brings the pixels from
   * the ring (before the context's second pb_render_frame after this one:
   * the ring has two slots). Frames with several bands or the host path
   * (PB_RESOLVE_ON_HOST=1) are rendered synchronously as without (pending
   * 0). The same commands as the synchronous path (and the ring's copy after
   * the last pass), only the wait moves: the same pixels, up to the photon
   * store's slot order that any two runs may differ in (bit-identical on
   * lavapipe in tests/frame_same_pixels.py in_flight). */
  int in_flight;
  /* What the readback brings to the host (PB_RENDER_READBACK_*):
   * ALL (0) every AOV, as `render` needs them; BEAUTY the beauty alone
   * (`serve`, which sends it on); STATS none of the pixels, only what the
   * statistics need (the guard's count, the k_PD plane's sums): the
   * viewer's GPU display, which shows the planes where they lie
   * (pb_render_result.gpu). Honoured for a frame in one band on the GPU
   * path with a context (the planes must outlive the call), and with a
   * still sum (pb_render_io) only when it ran on the GPU; otherwise everything is read
   * (stats.readback_mode says what was). The arrays not read are NULL;
   * pb_render_result_read_gpu fetches them later, while the planes last. */
  int readback;
  /* Frames in flight with a lean readback: the ring slot (targets.h) holds
   * only what the readback reads (BEAUTY: the beauty plane; STATS: none)
   * and the planes named here (PB_RENDER_KEEP(PB_RESOLVE_P) bits,
   * shared/pb_resolve.h; PB_RENDER_KEEP_ALL: every one), those the caller
   * reads from out->gpu after the frame (the viewer's display pass,
   * pb_render_result_read_gpu); out->gpu.kept says which are there.
   * Without frames in flight, or with READBACK_ALL, every plane is kept. */
  uint64_t keep_planes;
  /* Benchmark (bench/run_bench.py): */
  int radius_histogram;        /* 1: read every traced map back and bin its
                                  footprint radii (stats.radius_hist; costs a
                                  download per map, so off for timing) */
} pb_render_desc;

/* A frame's I/O objects, apart from its settings: what it reads besides
 * them, calls, or keeps for the caller (pb_render_frame_io; all NULL for
 * pb_render_frame). */
typedef struct pb_render_io {
  pb_render_progress_fn progress; /* see pb_render_desc.preview_interval_s */
  void *progress_user;
  const struct pb_photon_map *photon_map; /* tests: gather this map (every
                                  iteration) instead of tracing */
  struct pb_frame_context *context; /* sequences: keeps pipelines, per-pixel
                                  buffers, the photon tracer and estimator
                                  for the next frame (pb_frame_context_*) */
  struct pb_filter_chain *filters; /* sequences: the temporal and spatial
                                  filters of the indirect light (filters.h),
                                  recorded after the resolve on the GPU;
                                  NULL: atrous_iterations alone (a chain made
                                  for the call) */
  /* Frames in flight: the previous frame of the same context, still pending
   * (out->pending 1) or NULL. This frame is then recorded and its first
   * submissions queued while that one's last submission still runs (the
   * GPU runs them after it: gpu.h PB_GPU_FRAMES); pb_render_frame settles
   * it (pb_render_frame_settle) before its own last submission, the one
   * that overwrites what that settle reads (the guard, the k_PD sums, the
   * temporal filter's counts). Its pixels stay in its ring slot. */
  struct pb_render_result *settle_first;
  /* Sequences: a still run's running means on the GPU
   * (targets.h pb_still_sum), updated after eq. 20 in the frame's last
   * submission when the frame is one band on the GPU path; out->stats.
   * still_on_gpu says whether it was (else the caller averages on the
   * host). NULL: none. */
  struct pb_still_sum *still_sum;
} pb_render_io;

/* pb_render_stats.stop: the planned maps all ran, the time limit or the
 * noise threshold ended the frame. */
enum { PB_RENDER_STOP_PLANNED = 0, PB_RENDER_STOP_TIME_LIMIT = 1, PB_RENDER_STOP_NOISE = 2 };

enum { PB_RENDER_READBACK_ALL = 0, PB_RENDER_READBACK_BEAUTY = 1, PB_RENDER_READBACK_STATS = 2 };
/* pb_render_desc.keep_planes, pb_render_gpu_planes.kept: bit P for the
 * resolved plane at float offset P (PB_RESOLVE_BEAUTY ..). */
#define PB_RENDER_KEEP(plane) (1ull << (plane))
#define PB_RENDER_KEEP_ALL (~0ull)

enum { PB_RENDER_MAX_SPECULAR_DEPTH = 64 };
/* Where following a glossy layer with the eye path and shading it from the
 * photon map cross over in error at equal cost (bench/README.md, "Blender
 * materials": the studio at Roughness 0.1 to 0.5). */
#define PB_RENDER_GLOSSY_PATH_ROUGHNESS 0.15f
#define PB_RENDER_GLOSSY_PATH_ROUGHNESS_STR "0.15"
/* Footprint radius histogram: PB_RENDER_RADIUS_BINS - 1 bins of width
 * r_max / (PB_RENDER_RADIUS_BINS - 1) below the clamp, then the footprints
 * at the clamp r_max (seed 000 Table 3). */
enum { PB_RENDER_RADIUS_BINS = 21 };

typedef struct pb_render_stats {
  double upload_ms, bvh_build_ms;
  double gbuffer_ms, direct_ms, total_gpu_ms; /* timestamps, summed over samples */
  double wall_ms;
  uint64_t primary_rays, shadow_rays_max;     /* shadow_rays_max: upper bound */
  uint32_t spp, bvh_nodes, bvh_depth;
  int timestamps;                             /* 0: *_ms are wall-clock */
  /* Photon stages (0 when off): sums over iterations. estimator_build_ms:
   * the density estimator's per-map build (the LBVH's), gather_ms its
   * per-sample pass (the gather, kNN query, splat...). k_pd: photons
   * contributing per estimate at a surface. */
  double photon_trace_ms, estimator_build_ms, gather_ms;
  double filter_ms;                           /* A-Trous passes (0 when off) */
  double temporal_ms;                         /* temporal filter (0 when off) */
  double motion_ms;                           /* motion vectors (0 when none) */
  uint64_t temporal_surface_pixels;           /* temporal filter: pixels with a */
  uint64_t temporal_reset_pixels;             /* surface; of those, without */
  double temporal_mean_history;               /* history; mean history length */
  uint64_t photons_emitted, photons_stored, photons_caustic;
  uint64_t photons_clamped;                   /* of the stored, footprints
                                                 at r_max */
  uint32_t iterations;
  double k_pd;
  /* What ended the refinement (PB_RENDER_STOP_*) and, with a noise
   * threshold, the frame's last noise estimate (render/frame/noise.h: RMS on the
   * display image; < 0: fewer than two maps checked), its PSNR and the
   * number of checks. */
  int stop;
  double noise_estimate, noise_psnr;
  uint32_t noise_checks;
  /* Guards: NaN/Inf values met in the resolved AOVs and replaced
   * by 0 (a correct render has none), and divisions the photon tracer
   * guarded, summed over iterations (grazing hits, degenerate footprints;
   * never stored non-finite). */
  uint64_t nonfinite_values, photon_guarded;
  /* With desc.radius_histogram: counts over all maps; bin width r_max /
   * (PB_RENDER_RADIUS_BINS - 1) metres; the last bin: at the clamp. */
  uint64_t radius_hist[PB_RENDER_RADIUS_BINS];
  float radius_r_max, scene_radius;
  int radius_histogram;
  /* The frame as a whole (--json "timing"): frame_wall_ms from
   * the call's start to its return (a sequence frame: pb_sequence_frame's,
   * pose, scene update, motion vectors and filters included); frame_gpu_ms
   * the GPU time of every pass recorded for it (G-buffer, direct, photon
   * tracing, LBVH builds, gathers, motion vectors, temporal filter, A-Trous),
   * summed from timestamp queries; -1 without timestamps. Their difference
   * is the host's share: what the GPU-resident frame removes. */
  double frame_wall_ms, frame_gpu_ms;
  /* Sequences: the time from the previous frame's coming out of
   * pb_sequence_frame to this one's (the caller's work between the calls
   * included: one frame's period at steady state); 0 for the first. With
   * frames in flight frame_wall_ms is the host's time on the frame and this
   * the throughput: (interval - gpu) / interval is the share of a frame's
   * period in which the host kept the GPU idle. */
  double frame_interval_ms;
  int still_on_gpu;                           /* 1: pb_render_io.still_sum's pass ran on this frame */
  int in_flight;                              /* 1: the frame's last submission ran
                                                 while the host went on (pb_render_desc.in_flight) */
  /* Frames in flight: 1 when the frame's first command buffer was recorded
   * while the host had not waited for the previous frame's last submission
   * (structural: every frame after the first with 2 in flight; 0 with 1);
   * record_running: and that submission was still running on the GPU then
   * (its fence unsignalled: how long the host took, not a property of the
   * code). */
  int record_overlapped, record_running;
  /* The photon tracer that ran (tracer.h: "bvh", "images"; NULL when the
   * photon stages are off) and its named statistics over the frame. */
  const char *tracer;
  uint32_t tracer_stat_count;
  pb_tracer_stat tracer_stats[PB_TRACER_MAX_STATS];
  /* The density estimator that ran (estimator.h: "lbvh", "knn", ...; auto
   * resolved; NULL when the photon stages are off) and its named
   * statistics over the frame (summed ones added over the maps, the others
   * the last map's; the LBVH's: pb_estimator_lbvh_named_stats). */
  const char *estimator;
  uint32_t estimator_stat_count;
  pb_tracer_stat estimator_stats[PB_TRACER_MAX_STATS];
  /* Host <-> device traffic of the frame (--json "transfers"):
   * pb_gpu_buffer_upload and _download bytes outside the readback, and
   * what the readback (readback.h) brought to the host. The GPU-resident
   * frame moves no pixels but the readback's: uploads are constants and
   * scene data, other downloads the photon counts (tests/sequence.cmake
   * sequence_transfers). */
  uint64_t upload_bytes, download_bytes, readback_bytes;
  /* Frames in flight: the bytes the frame's last submission copied into
   * its readback ring slot (host-cached memory; on a discrete GPU the
   * download itself, made by the GPU): every plane with READBACK_ALL, else
   * what the lean readback reads and keep_planes. 0 without. */
  uint64_t ring_bytes;
  int readback_mode; /* PB_RENDER_READBACK_*: what this frame's readback brought (pb_render_desc.readback) */
} pb_render_stats;

/* Where a frame's resolved planes (shared/pb_resolve.h: plane P of `pixels`
 * pixels at float P * pixels of planes, from PB_RESOLVE_BASE_CHANNELS on in
 * pplanes) stay on the GPU after the frame: the context's planes, or with
 * frames in flight its readback ring slot. Valid until the context's next
 * pb_render_frame (frames in flight: the second after this frame's), the
 * caller's to read without copying (the viewer's display pass). */
typedef struct pb_render_gpu_planes {
  const pb_gpu_buffer *planes, *pplanes; /* NULL: none kept (no context, several bands) */
  uint64_t kept; /* the planes there (PB_RENDER_KEEP bits; a frame in flight
                    with a lean readback keeps only some: keep_planes) */
  uint32_t pixels, channels;
  int photons, nmap, nmap_aovs;
} pb_render_gpu_planes;

/* Per-pixel float buffers, width*height*channels, top row first. */
typedef struct pb_render_result {
  uint32_t width, height;
  float *beauty;    /* RGBA: A = fraction of samples that hit geometry */
  float *direct;    /* RGB: at most one scattering event */
  float *albedo;    /* RGB at the first hit */
  float *normal;    /* XYZ shading normal at the first hit, facing the camera */
  float *depth;     /* camera-space z of the first hit, 0 on a miss */
  float *material;  /* material index of the first hit + 1, 0 on a miss */
  float *emission;  /* RGB emitted by the first hit toward the camera
                       (Blender's Emit pass; part of direct and beauty) */
  float *indirect;  /* RGB: photon gather, non-caustic photons (NULL when the
                       photon stages are off) */
  float *caustic;   /* RGB: photon gather, caustic photons (NULL when off);
                       beauty = emission + direct + indirect + caustic */
  /* Seed 001's shading-normal correction (24.4.3, eq. 20;
   * shading_correction.h), only in scenes with normal maps and the photon
   * stages on (NULL otherwise), all at the gather surface (the first smooth
   * vertex after the eye's specular chain), unit length or 0: */
  float *geo_normal;    /* XYZ geometric normal, facing the eye */
  float *photon_dir;    /* XYZ power-weighted mean incoming direction wi of
                           the indirect (non-caustic) photons; 0: none */
  float *shading_normal;/* XYZW: XYZ the normal-mapped n_s, W the fraction
                           of samples on a normal-mapped material */
  pb_render_stats stats;
  pb_render_gpu_planes gpu; /* the frame's planes on the GPU (with a context, one band) */
  /* Frames in flight (pb_render_desc.in_flight): 1 the GPU may still run
   * the frame (pb_render_frame_settle next), 2 settled, pixels not yet read
   * (pb_render_frame_read next), 0 complete; pending_slot: its ring slot. */
  int pending;
  uint32_t pending_slot;
} pb_render_result;

/* What one frame builds before it renders (pipelines, per-pixel buffers,
 * the photon tracer and density estimator, the photon map's storage), kept
 * between the frames of a sequence: a frame with the same GPU scene, size
 * and photon settings reuses it, updating the tracer and estimator to the
 * scene's new pose; anything else builds afresh. Saves the pipeline
 * compilation and allocations of every frame. */
typedef struct pb_frame_context pb_frame_context;
pb_result pb_frame_context_create(pb_frame_context **out);
void pb_frame_context_destroy(pb_gpu *g, pb_frame_context *c);

pb_result pb_render_frame(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera,
                          uint32_t width, uint32_t height, const pb_render_desc *desc,
                          pb_render_result *out);
/* The same with I/O objects (io may be NULL: none). */
pb_result pb_render_frame_io(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width,
                             uint32_t height, const pb_render_desc *desc, const pb_render_io *io,
                             pb_render_result *out);
void pb_render_result_destroy(pb_render_result *r);
/* The AOVs a lean readback (pb_render_desc.readback) left out, from
 * r->gpu while it is valid (render.h pb_render_gpu_planes): every array
 * still NULL is allocated and read; r->stats.readback_bytes counts the
 * bytes. A complete frame only (r->pending 0). */
pb_result pb_render_result_read_gpu(pb_gpu *g, pb_render_result *r);
/* The estimator statistic `name` of st (pb_render_stats.estimator_stats),
 * or `missing` where the estimator has none of that name. */
double pb_render_estimator_stat(const pb_render_stats *st, const char *name, double missing);
/* The environment-map tracer's miss rate (tracer "images": photon segments
 * no map confirmed, over all), or -1 where the frame has none. */
double pb_render_image_miss_rate(const pb_render_stats *st);

/* A frame in flight (pb_render_desc.in_flight, out->pending): settle waits
 * for the GPU and completes the statistics (out->pending 1 -> 2); read
 * brings the pixels from the readback ring (2 -> 0); complete does what is
 * left of both. frame_wall_ms of such a frame is the host's time on it:
 * pb_render_frame up to its last submission, the wait in settle and the
 * copy in read, not the time the host spent elsewhere while it ran. */
pb_result pb_render_frame_settle(pb_gpu *g, pb_frame_context *c, pb_render_result *out);
pb_result pb_render_frame_read(pb_gpu *g, pb_frame_context *c, pb_render_result *out);
pb_result pb_render_frame_complete(pb_gpu *g, pb_frame_context *c, pb_render_result *out);

#endif
