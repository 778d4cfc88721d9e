/* The caustic photon map of the reference renderer's SPPM mode
 * (photons.c). */
#ifndef PB_REF_PHOTONS_H
#define PB_REF_PHOTONS_H

#include "ref/bsdf.h"
#include "ref/ctx.h"
#include "ref/vec.h"

/* One caustic photon: flux arriving at a surface with a smooth lobe after a
 * chain of `chain` >= 1 delta interactions that started at a delta light. */
typedef struct pb_ref_photon {
  float p[3];
  float wi[3];     /* toward where the photon came from */
  float n[3];      /* geometric normal facing wi */
  float power[3];  /* flux [W], already divided by the pass's path count */
  uint32_t chain;
} pb_ref_photon;

typedef struct pb_ref_photon_map {
  pb_ref_photon *photons; /* sorted by grid cell */
  uint32_t count;
  uint32_t *cell_start; /* bucket -> first photon, bucket_count + 1 entries */
  uint32_t bucket_count; /* power of two */
  float radius, cell;
  uint64_t rays;
} pb_ref_photon_map;

/* Traces `paths` photon paths of pass `pass` (deterministic for a seed) in
 * parallel and builds the map for gathering at `radius`. */
pb_result pb_photon_pass(pb_ref_ctx *ctx, uint32_t pass, uint32_t paths,
                         float radius, pb_ref_photon_map *map);
void pb_ref_photon_map_destroy(pb_ref_photon_map *m);
/* Caustic radiance toward wo at a surface point with bsdf b (the eye vertex
 * at bounce `depth`), from photons whose chain keeps the path within
 * max_bounces. */
v3 pb_photon_gather(const pb_ref_photon_map *m, const pb_bsdf *b, v3 p, v3 wo,
                    uint32_t depth, uint32_t max_bounces);

#endif
