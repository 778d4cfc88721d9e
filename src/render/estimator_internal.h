/* Shared by lbvh.c (the build) and gather.c (the gather pass). */
#ifndef PB_RENDER_ESTIMATOR_INTERNAL_H
#define PB_RENDER_ESTIMATOR_INTERNAL_H

#include "render/lbvh_sort.h"
#include "render/passes.h"
#include "render/photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"

enum { PB_LBVH_PASS_SETUP = 0, PB_LBVH_PASS_BOUNDS, PB_LBVH_PASS_MORTON, PB_LBVH_PASS_CLIMB, PB_LBVH_PASS_N };
enum { PB_LBVH_BIND_COUNT = 12 }; /* common/lbvh.glsl */
/* Gather bindings: scene.glsl's 15, then these. */
enum { PB_GATHER_BIND_PHOTONS = 15, PB_GATHER_BIND_NODES, PB_GATHER_BIND_INFO, PB_GATHER_BIND_ACCUM,
       PB_GATHER_BIND_NMAP, PB_GATHER_BIND_COUNT };

/* The gather's specialization constants: scene.glsl's (passes.h), with its
 * own SC_NORMAL_MAPS in id 5 (4 is photon_trace's SC_TRANSMISSION, unused). */
enum { PB_GATHER_SPEC_NORMAL_MAPS = PB_SPEC_PASS_5, PB_GATHER_SPEC_COUNT = PB_SPEC_COUNT };

struct pb_photon_estimator {
  pb_photon_estimate_desc desc;
  float footprint_scale; /* of the next build; 0: 1 */
  float scene_area;
  pb_gpu_pipeline pass[PB_LBVH_PASS_N];
  pb_gpu_pipeline gather;
  uint32_t gather_spec[PB_GATHER_SPEC_COUNT]; /* scene.glsl's, then SC_NORMAL_MAPS */
  uint32_t gather_blender;                     /* the module: 1 the PB_BLENDER build */
  int gather_ready;
  uint32_t capacity;             /* photons the buffers hold */
  pb_radix_sort *sort;           /* Morton codes -> photon indices */
  pb_gpu_buffer info, sorted, nodes, visit, partial;
  pb_gpu_buffer dummy;           /* bound where a map has no photons or counts buffer */
  pb_photon_estimate_stats stats;
};

#endif
