/* The CPU reference renderer: Embree 3 path tracing with next-event
 * estimation and MIS, plus a progressive caustic photon map for the paths a
 * path tracer cannot sample (delta light -> specular chain -> diffuse -> eye).
 *
 * A replaceable stage with a small interface: it reads a pb_scene and returns
 * per-pixel float buffers; the GPU pipeline renders the same scene model and
 * its pictures are compared against these (src/metrics).
 *
 * Contract of the image:
 *  - Pixel (x, y), row-major, top row first; a box filter over each pixel
 *    (jittered sample positions).
 *  - Values are radiance in W/(m^2 sr) per linear Rec.709 channel, in the
 *    radiometric light units of scene.h.
 *  - Deterministic: for a fixed seed, scene, size and sample count the output
 *    is bit-identical whatever the thread count (per-pixel random streams,
 *    photon chunks merged in a fixed order).
 *  - Never NaN or Inf: a sample whose estimate is not finite is dropped (its
 *    contribution is zero) and counted in stats.guarded_samples.
 *
 * Scene semantics (scene.h): lights as documented there (spot: smoothstep
 * between the cone cosines, or Cycles 3.4's falloff; soft lights and the
 * world as pb_light and pb_world say); emissive triangles are area lights emitting
 * from their front (counter-clockwise) side only, both sides when the
 * material is double-sided; every surface shades on both sides, a back face
 * with its normals flipped; transmission is a solid refracting dielectric
 * (as in Cycles), not glTF's thin-walled default. The material model is
 * described at pb_bsdf in ref/bsdf.h.
 * Not modelled (yet): alpha mask/blend (surfaces are opaque), normal maps,
 * rough transmission (rendered smooth), light `range` (no cut-off), the
 * camera's znear/zfar, animation (the scene as loaded). */
#ifndef PB_REF_H
#define PB_REF_H

#include <stdint.h>

#include "core/result.h"
#include "scene/scene.h"

typedef enum pb_ref_mode {
  /* SPPM when the scene has specular (delta) surfaces and a light other
   * than emissive triangles, or a world (delta lights are where path tracing
   * misses paths; small soft lights seen through glass are where it
   * struggles), otherwise PT. */
  PB_REF_MODE_AUTO = 0,
  PB_REF_MODE_PT = 1,   /* path tracing only; caustics of delta lights are absent */
  PB_REF_MODE_SPPM = 2, /* path tracing + progressive caustic photon map */
} pb_ref_mode;

/* Zero means default for every field. */
typedef struct pb_ref_desc {
  uint32_t spp;          /* samples per pixel; 0: 64, or 2^24 (unbounded) when
                            time_limit_s > 0 */
  uint32_t max_bounces;  /* scattering events on a path between light and eye
                            (direct lighting is 1); 0: unbounded, paths end
                            by Russian roulette alone (PB_REF_BOUNCE_CAP is
                            only a safety net, see pathtrace.c). Use
                            PB_REF_BOUNCES_ZERO to render only emitters seen
                            directly. */
  uint64_t seed;
  uint32_t threads;      /* 0: every core this process may run on */
  double time_limit_s;   /* 0: none; otherwise stop after the first whole pass
                            ending past it (spp stays an upper bound) */
  pb_ref_mode mode;
  /* SPPM only: photon paths emitted per pass (0: width*height, at least
   * 16384) and the first pass's gather radius in scene units (0: twice the
   * pixel footprint at the distance of the scene's centre). */
  uint32_t photons_per_pass;
  float photon_radius;
  float photon_alpha;    /* radius reduction, (0,1); 0: 2/3 */
  /* Accumulate even and odd samples separately and estimate the image's own
   * noise from their difference (stats.noise_*). Rounds spp up to even. */
  int estimate_noise;
  /* Called from the calling thread, about ten times a second and after every
   * pass, with samples done so far out of the planned total; may be NULL. */
  void (*progress)(void *user, uint64_t done, uint64_t total);
  void *progress_user;
} pb_ref_desc;

enum { PB_REF_BOUNCES_ZERO = UINT32_MAX };
/* The default path length: a safety cap that Russian roulette makes
 * unreachable in practice (pathtrace.c: survival at most 0.95 per event from
 * the third, so a path reaches 1024 events with probability below
 * 0.95^1021 ~ 2e-23; the light of longer paths in a closed room of albedo
 * rho is rho^1024 of the total). Explicit --max-bounces values (Blender's
 * bounce limits) still truncate. */
enum { PB_REF_BOUNCE_CAP = 1024 };

typedef struct pb_ref_stats {
  uint32_t spp;               /* samples per pixel actually rendered */
  uint32_t passes;
  uint32_t threads;
  pb_ref_mode mode;           /* the mode used (AUTO resolved) */
  double time_s;              /* wall time of rendering (BVH build excluded) */
  double cpu_s;               /* CPU time the process used meanwhile (all
                                 threads): rays / cpu_s is the per-core rate
                                 even on a machine shared with other work */
  double build_s;             /* Embree BVH build */
  uint64_t rays;              /* closest-hit + shadow rays traced */
  uint64_t camera_samples;    /* width*height*spp */
  uint64_t guarded_samples;   /* samples dropped as non-finite */
  uint64_t photon_paths;      /* SPPM: photon paths traced, all passes */
  uint64_t photons_stored;    /* SPPM: caustic photons deposited, all passes */
  float photon_radius_first, photon_radius_last;
  /* With estimate_noise (else negative): the estimated RMSE and relMSE of the
   * beauty image against its own expectation, from the two halves' difference
   * (Var(mean) = E[(A-B)^2] / 4 for independent halves A and B of equal
   * size; pb_metrics_noise_from_halves). Measures variance only: SPPM's
   * radius bias is not included. */
  double noise_rmse, noise_relmse;
  double noise_psnr;          /* display-image PSNR of the estimate (plain
                                 sRGB display; callers with an OCIO view
                                 recompute it from half_a/half_b), dB */
} pb_ref_stats;

/* Per-pixel buffers, width*height*channels floats, top row first. */
typedef struct pb_ref_result {
  uint32_t width, height;
  float *beauty;     /* RGBA: A = fraction of camera samples that hit geometry,
                        or 1 with an opaque film (pb_scene.film_opaque) */
  float *direct;     /* RGB: paths with at most one scattering event (emitters
                        seen directly, and light scattered once to the eye) */
  float *indirect;   /* RGB: beauty - direct (two or more scattering events,
                        caustics included) */
  float *albedo;     /* RGB: reflectance at the first hit (base colour, glass
                        as white; 0 on a miss) */
  float *normal;     /* XYZ: world-space shading normal at the first hit,
                        facing the camera, averaged over the pixel's samples */
  float *depth;      /* 1 channel: camera-space z of the first hit (metres
                        along the camera's forward axis), averaged over the
                        samples that hit; 0 where none did */
  /* With estimate_noise (else NULL): RGB beauty of the even and of the odd
   * samples, two independent renders whose mean is `beauty`. */
  float *half_a, *half_b;
  pb_ref_stats stats;
} pb_ref_result;

/* Renders camera `camera` of `scene` (which pb_scene_finalize has seen) at
 * width x height. On success `out` owns the buffers (pb_ref_result_destroy);
 * on failure it holds nothing to free. Errors: PB_ERR_USAGE (bad desc,
 * camera, size), PB_ERR_SCENE_EMPTY (no triangles), PB_ERR_SCENE_INVALID
 * (index out of range), PB_ERR_NOMEM, PB_ERR_INTERNAL (Embree). */
pb_result pb_ref_render(const pb_scene *scene, int camera, uint32_t width,
                        uint32_t height, const pb_ref_desc *desc,
                        pb_ref_result *out);
void pb_ref_result_destroy(pb_ref_result *r);

/* The mode AUTO picks for this scene. */
pb_ref_mode pb_ref_auto_mode(const pb_scene *scene);
const char *pb_ref_mode_name(pb_ref_mode m);

/* Logical CPUs this process may run on (sched affinity), at least 1. */
uint32_t pb_ref_default_threads(void);

#endif
