#version 450
// LBVH pass 4: photons copied into Morton order (leaves are intervals of
// this sequence), the leaf-end flag cleared (set again by lbvh_finalize);
// a single photon is its own leaf. The footprint is scaled by
// info.footprint_scale (the estimator's per-build bandwidth factor, e.g.
// SPPM's shrinking radius): the boxes (lbvh_boxes*) and the gather's kernel
// and normalisation all read these sorted copies.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= info.count) return;
  pb_gpu_photon p = photons_in[vals[gid]];
  p.flags &= ~PB_PHOTON_LEAF_END;
  float k = info.footprint_scale;
  p.axis_u *= k;
  p.axis_v *= k;
  p.normal_extent *= k;
  p.radius *= k;
  if (info.count == 1u) p.flags |= PB_PHOTON_LEAF_END;
  photons[gid] = p;
}
