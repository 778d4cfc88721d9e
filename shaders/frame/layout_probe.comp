#version 450
// Not a pass: compiled only so that the layout test (tests/unit/test_gpu_layout.c)
// can read the std430 offsets glslc assigns to every struct of shaders/shared/*.h
// from the SPIR-V (OpMemberDecorate ... Offset, and each struct's ArrayStride)
// and compare them with the C offsets and sizes. One buffer block per header
// (the device allows only so many bindings), each struct an array of two in
// it; main() copies element 0 to element 1 so that every struct, and so every
// member, is used and kept by the optimizer. A struct added to a shared header
// gets a line here and its members in the test (the test names any it misses).
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_accumulate.h"
#include "shared/pb_filter.h"
#include "shared/pb_image_maps.h"
#include "shared/pb_knn.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"
#include "shared/pb_present.h"
#include "shared/pb_resolve.h"
#include "shared/pb_rsm.h"
#include "shared/pb_splat.h"
#include "shared/pb_upsample.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, binding = 0) buffer B_accumulate {  // shared/pb_accumulate.h
  pb_gpu_accumulate_push accumulate_push[2];
} b_accumulate;
layout(std430, binding = 1) buffer B_filter {  // shared/pb_filter.h
  pb_gpu_atrous_push atrous_push[2];
  pb_gpu_temporal_push temporal_push[2];
  pb_gpu_temporal_stats temporal_stats[2];
  pb_gpu_filter_io_push filter_io_push[2];
  pb_gpu_shading_push shading_push[2];
  pb_gpu_motion_params motion_params[2];
} b_filter;
layout(std430, binding = 2) buffer B_gpu {  // shared/pb_gpu.h
  pb_gpu_bvh_node bvh_node[2];
  pb_gpu_tri tri[2];
  pb_gpu_ray ray[2];
  pb_gpu_hit hit[2];
  pb_gpu_material material[2];
  pb_gpu_texture texture[2];
  pb_gpu_light light[2];
  pb_gpu_world world[2];
  pb_gpu_emitter emitter[2];
  pb_gpu_camera camera[2];
  pb_gpu_frame frame[2];
  pb_gpu_gbuffer gbuffer[2];
  pb_gpu_accum accum[2];
  pb_gpu_pass_push pass_push[2];
  pb_gpu_raycast_push raycast_push[2];
  pb_gpu_photon_params photon_params[2];
  pb_gpu_photon_light photon_light[2];
} b_gpu;
layout(std430, binding = 3) buffer B_image_maps {  // shared/pb_image_maps.h
  pb_gpu_image_texel image_texel[2];
  pb_gpu_image_map image_map[2];
  pb_gpu_image_maps_info image_maps_info[2];
  pb_gpu_image_counts image_counts[2];
  pb_gpu_image_maps_push image_maps_push[2];
  pb_gpu_image_touch image_touch[2];
} b_image_maps;
layout(std430, binding = 4) buffer B_knn {  // shared/pb_knn.h
  pb_gpu_knn_push knn_push[2];
} b_knn;
layout(std430, binding = 5) buffer B_lbvh {  // shared/pb_lbvh.h
  pb_gpu_lbvh_child lbvh_child[2];
  pb_gpu_lbvh_node lbvh_node[2];
  pb_gpu_lbvh_info lbvh_info[2];
  pb_gpu_lbvh_push lbvh_push[2];
  pb_gpu_sort_state sort_state[2];
  pb_gpu_sort_push sort_push[2];
  pb_gpu_photon_accum photon_accum[2];
  pb_gpu_photon_nmap photon_nmap[2];
  pb_gpu_gather_push gather_push[2];
} b_lbvh;
layout(std430, binding = 6) buffer B_photon {  // shared/pb_photon.h
  pb_gpu_photon photon[2];
  pb_gpu_photon_packed photon_packed[2];
  pb_gpu_photon_counts photon_counts[2];
} b_photon;
layout(std430, binding = 7) buffer B_present {  // shared/pb_present.h
  pb_gpu_present_push present_push[2];
} b_present;
layout(std430, binding = 8) buffer B_resolve {  // shared/pb_resolve.h
  pb_gpu_resolve_kpd resolve_kpd[2];
  pb_gpu_resolve_push resolve_push[2];
} b_resolve;
layout(std430, binding = 9) buffer B_rsm {  // shared/pb_rsm.h
  pb_gpu_rsm_light rsm_light[2];
  pb_gpu_rsm_texel rsm_texel[2];
  pb_gpu_rsm_push rsm_push[2];
} b_rsm;
layout(std430, binding = 10) buffer B_splat {  // shared/pb_splat.h
  pb_gpu_splat_push splat_push[2];
  pb_gpu_splat_stats splat_stats[2];
} b_splat;
layout(std430, binding = 11) buffer B_upsample {  // shared/pb_upsample.h
  pb_gpu_upsample_push upsample_push[2];
} b_upsample;
layout(std430, binding = 12) buffer B_vsch {  // shared/pb_vsch.h
  pb_gpu_vsch_push vsch_push[2];
} b_vsch;

void main() {
  if (gl_GlobalInvocationID.x >= 1u) return;
  b_accumulate.accumulate_push[1] = b_accumulate.accumulate_push[0];
  b_filter.atrous_push[1] = b_filter.atrous_push[0];
  b_filter.temporal_push[1] = b_filter.temporal_push[0];
  b_filter.temporal_stats[1] = b_filter.temporal_stats[0];
  b_filter.filter_io_push[1] = b_filter.filter_io_push[0];
  b_filter.shading_push[1] = b_filter.shading_push[0];
  b_filter.motion_params[1] = b_filter.motion_params[0];
  b_gpu.bvh_node[1] = b_gpu.bvh_node[0];
  b_gpu.tri[1] = b_gpu.tri[0];
  b_gpu.ray[1] = b_gpu.ray[0];
  b_gpu.hit[1] = b_gpu.hit[0];
  b_gpu.material[1] = b_gpu.material[0];
  b_gpu.texture[1] = b_gpu.texture[0];
  b_gpu.light[1] = b_gpu.light[0];
  b_gpu.world[1] = b_gpu.world[0];
  b_gpu.emitter[1] = b_gpu.emitter[0];
  b_gpu.camera[1] = b_gpu.camera[0];
  b_gpu.frame[1] = b_gpu.frame[0];
  b_gpu.gbuffer[1] = b_gpu.gbuffer[0];
  b_gpu.accum[1] = b_gpu.accum[0];
  b_gpu.pass_push[1] = b_gpu.pass_push[0];
  b_gpu.raycast_push[1] = b_gpu.raycast_push[0];
  b_gpu.photon_params[1] = b_gpu.photon_params[0];
  b_gpu.photon_light[1] = b_gpu.photon_light[0];
  b_image_maps.image_texel[1] = b_image_maps.image_texel[0];
  b_image_maps.image_map[1] = b_image_maps.image_map[0];
  b_image_maps.image_maps_info[1] = b_image_maps.image_maps_info[0];
  b_image_maps.image_counts[1] = b_image_maps.image_counts[0];
  b_image_maps.image_maps_push[1] = b_image_maps.image_maps_push[0];
  b_image_maps.image_touch[1] = b_image_maps.image_touch[0];
  b_knn.knn_push[1] = b_knn.knn_push[0];
  b_lbvh.lbvh_child[1] = b_lbvh.lbvh_child[0];
  b_lbvh.lbvh_node[1] = b_lbvh.lbvh_node[0];
  b_lbvh.lbvh_info[1] = b_lbvh.lbvh_info[0];
  b_lbvh.lbvh_push[1] = b_lbvh.lbvh_push[0];
  b_lbvh.sort_state[1] = b_lbvh.sort_state[0];
  b_lbvh.sort_push[1] = b_lbvh.sort_push[0];
  b_lbvh.photon_accum[1] = b_lbvh.photon_accum[0];
  b_lbvh.photon_nmap[1] = b_lbvh.photon_nmap[0];
  b_lbvh.gather_push[1] = b_lbvh.gather_push[0];
  b_photon.photon[1] = b_photon.photon[0];
  b_photon.photon_packed[1] = b_photon.photon_packed[0];
  b_photon.photon_counts[1] = b_photon.photon_counts[0];
  b_present.present_push[1] = b_present.present_push[0];
  b_resolve.resolve_kpd[1] = b_resolve.resolve_kpd[0];
  b_resolve.resolve_push[1] = b_resolve.resolve_push[0];
  b_rsm.rsm_light[1] = b_rsm.rsm_light[0];
  b_rsm.rsm_texel[1] = b_rsm.rsm_texel[0];
  b_rsm.rsm_push[1] = b_rsm.rsm_push[0];
  b_splat.splat_push[1] = b_splat.splat_push[0];
  b_splat.splat_stats[1] = b_splat.splat_stats[0];
  b_upsample.upsample_push[1] = b_upsample.upsample_push[0];
  b_vsch.vsch_push[1] = b_vsch.vsch_push[0];
}
