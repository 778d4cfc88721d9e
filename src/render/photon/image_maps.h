/* The environment maps of the image-space photon tracer (seed 003, Yao et
 * al. 2010, sections 3-5; shaders/shared/pb_image_maps.h has the layout):
 *
 *   centres   k environment-map centres (EMCs) chosen greedily from a set U
 *             of random candidates in the scene's box by new coverage
 *             A(v|C) (section 4.1, eq. 1), visibility tested with
 *             low-resolution cube maps of every candidate (32 x 32 x 6, 4.2),
 *             then swap steps until C is invariant (at most 5; "2 to 5");
 *   maps      a cube map per centre, per texel the first surface's position,
 *             normal, triangle and material, rendered with the GPU ray
 *             casting of the scene BVH (shaders/photon/image_maps.comp);
 *   motion    pb_image_maps_update after the scene moved: the maps are
 *             rendered again, and every `update_every`-th update (5: "the
 *             update is carried out once every 5 frames") the candidates'
 *             maps too and one swap step runs; only the maps a moved
 *             triangle touches are rendered again (image_maps_touch.comp),
 *             none when no vertex moved (a swap renders its own);
 *   queries   rays against the maps (shaders/photon/image_maps_query.comp), the
 *             same search the images build of photon_trace.comp runs: tests
 *             and the benchmark compare it with the BVH's exact hits. */
#ifndef PB_RENDER_IMAGE_MAPS_H
#define PB_RENDER_IMAGE_MAPS_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "scene/scene.h"
#include "shared/pb_gpu.h"
#include "shared/pb_image_maps.h"

/* Defaults (zero means default for every field of the desc). */
enum {
  PB_IMAGE_MAPS_DEFAULT_COUNT = 8,        /* k: "all other scenes are sampled using 8 maps" (section 8) */
  PB_IMAGE_MAPS_DEFAULT_RESOLUTION = 128, /* texels per face side (the paper does not say; bench/README.md) */
  PB_IMAGE_MAPS_DEFAULT_CANDIDATES = 40,  /* |U|: "30 to 50 random points" (4.1) */
  PB_IMAGE_MAPS_SELECT_RESOLUTION = 32,   /* "32 x 32 x 6" (4.2) */
  PB_IMAGE_MAPS_DEFAULT_MARCH = 32,       /* samples of a ray's projection per map */
  PB_IMAGE_MAPS_DEFAULT_SECANT = 4,       /* false position: "3 to 5 iterations" (5.1) */
  PB_IMAGE_MAPS_DEFAULT_UPDATE_EVERY = 5, /* updates between swap steps (4.1) */
  PB_IMAGE_MAPS_MAX_INITIAL_SWAPS = 5,    /* "the initial updating needs only 2 to 5" */
  PB_IMAGE_MAPS_MAX_CANDIDATES = 64
};
#define PB_IMAGE_MAPS_EPSILON 0.001f /* eq. 2's threshold: "epsilon = 0.001 in practice" */

typedef struct pb_image_maps_desc {
  uint32_t count;        /* k, 1..PB_IMAGE_MAPS_MAX; 0: 8 */
  uint32_t resolution;   /* 8..1024; 0: 128 */
  uint32_t candidates;   /* |U|, >= count, <= 64; 0: 40 (at least k) */
  uint32_t march_steps;  /* 0: PB_IMAGE_MAPS_DEFAULT_MARCH */
  uint32_t secant_steps; /* 0: PB_IMAGE_MAPS_DEFAULT_SECANT */
  float epsilon;         /* 0: PB_IMAGE_MAPS_EPSILON */
  uint32_t update_every; /* 0: 5 */
  uint64_t seed;         /* candidates' positions */
} pb_image_maps_desc;

typedef struct pb_image_maps_stats {
  uint32_t count, resolution, candidates;
  uint32_t map_renders;   /* times all k maps were rendered */
  uint32_t maps_rendered; /* single maps rendered (k per full render, 1 per swap on a still pose) */
  uint32_t renders_skipped; /* updates that rendered no map (no vertex moved) */
  uint32_t selections;    /* times the candidates' maps were rendered */
  uint32_t swaps;         /* centres replaced (initial and progressive) */
  uint32_t initial_swaps; /* swap steps of the initial selection */
  double coverage_m2;     /* eq. 1 area the k centres see together, m^2 */
  double uncovered_m2;    /* area some candidate sees and no centre does */
  double render_ms;       /* wall time of the last map render */
  double select_ms;       /* wall time of the last selection (candidates'
                             maps, readback, greedy steps) */
} pb_image_maps_stats;

typedef struct pb_image_maps pb_image_maps;

/* Selects the centres and renders the maps of the scene in its current
 * pose (gs must be up to date). Bad desc values: PB_ERR_USAGE. */
pb_result pb_image_maps_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_image_maps_desc *desc,
                               pb_image_maps **out);
/* The scene was posed again (gs updated): renders again the maps in which
 * moved triangles (old or new positions) can be seen, and on every
 * update_every-th call runs one progressive swap step first (the swapped-in
 * map rendered too). */
pb_result pb_image_maps_update(pb_gpu *g, pb_image_maps *m, const pb_scene *s);
void pb_image_maps_destroy(pb_gpu *g, pb_image_maps *m);

/* The device buffers the images tracer binds: info + maps, texels. */
const pb_gpu_buffer *pb_image_maps_buffer(const pb_image_maps *m);
const pb_gpu_buffer *pb_image_maps_texels(const pb_image_maps *m);
void pb_image_maps_get_stats(const pb_image_maps *m, pb_image_maps_stats *out);
/* centres: count entries. */
void pb_image_maps_centers(const pb_image_maps *m, float (*out)[3]);

/* Tests, benchmark: n rays against the maps (hits as image_maps_query.comp
 * writes them; counts may be NULL). */
pb_result pb_image_maps_query(pb_gpu *g, pb_image_maps *m, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits,
                              pb_gpu_image_counts *counts, double *gpu_ms);

/* Host ports of common/image_maps.glsl (same names, same arithmetic): the
 * cube layout and eq. 2's classification, PB_IMAGE_TYPE_A/B/D. */
enum { PB_IMAGE_TYPE_A = 0, PB_IMAGE_TYPE_B = 1, PB_IMAGE_TYPE_D = 3 };
uint32_t pb_cube_texel(const float w[3], uint32_t res);
void pb_cube_dir(uint32_t idx, uint32_t res, float out[3]);
uint32_t pb_image_classify(const float x[3], const float r[3], const float p[3], float epsilon);
/* Eq. 1's area of one texel: A(p) = 4 / N ((x - v).r_f)^3 / |(v - x).n|,
 * N = res^2 texels per face, r_f the face's forward axis; |cos alpha| is
 * clamped at 0.1 (see image_maps.c). */
double pb_image_texel_area(const float v[3], const pb_gpu_image_texel *t, uint32_t idx, uint32_t res);

#endif
