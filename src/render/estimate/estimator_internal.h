/* Shared by lbvh.c (the build) and gather.c (the gather pass). */
#ifndef PB_RENDER_ESTIMATOR_INTERNAL_H
#define PB_RENDER_ESTIMATOR_INTERNAL_H

#include "render/photon/lbvh_sort.h"
#include "render/scene/passes.h"
#include "render/photon/photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"

enum { PB_LBVH_PASS_SETUP = 0, PB_LBVH_PASS_BOUNDS, PB_LBVH_PASS_MORTON, PB_LBVH_PASS_CLIMB, PB_LBVH_PASS_N };
/* Bindings (PB_LBVH_BIND_*, PB_GATHER_BIND_*) and specialization constants
 * (the scene's PB_SPEC_* with the gather's PB_SPEC_NORMAL_MAPS): the shader
 * contract, shaders/shared/pb_contract.h. */

struct pb_photon_estimator {
  pb_photon_estimate_desc desc;
  float footprint_scale; /* of the next build; 0: 1 */
  float edge_reach;      /* the gather's edge renormalisation reach, m; 0: off */
  float scene_area;
  pb_gpu_pipeline pass[PB_LBVH_PASS_N];
  pb_gpu_pipeline gather;
  uint32_t gather_spec[PB_SPEC_COUNT]; /* scene.glsl's, then SC_NORMAL_MAPS */
  uint32_t gather_build;                       /* the module: pb_kernel_select's build */
  int gather_ready;
  /* gather_upsample (gather.comp -DPB_UPSAMPLE=1; upsample.h): its pipeline,
   * constants and module, bound by pb_photon_estimator_bind_upsample. */
  pb_gpu_pipeline gather_ups;
  uint32_t gather_ups_spec[PB_SPEC_COUNT];
  uint32_t gather_ups_build;
  int gather_ups_ready;
  uint32_t capacity;             /* photons the buffers hold */
  pb_radix_sort *sort;           /* Morton codes -> photon indices */
  pb_gpu_buffer info, sorted, nodes, visit, partial;
  pb_gpu_buffer dummy;           /* bound where a map has no photons or counts buffer */
  pb_photon_estimate_stats stats;
  pb_gpu_lbvh_push push;         /* of the build prepared last */
};

#endif
