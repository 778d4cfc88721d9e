#version 450
// Not a pass: compiled only so that the layout test can read the std430
// offsets glslc assigns to every struct of shared/pb_gpu.h (and shared/pb_vsch.h) from the SPIR-V
// (OpMemberDecorate ... Offset) and compare them with the C offsets.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_vsch.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, binding = 0) buffer B0 { pb_gpu_bvh_node d[]; } b0;
layout(std430, binding = 1) buffer B1 { pb_gpu_tri d[]; } b1;
layout(std430, binding = 2) buffer B2 { pb_gpu_ray d[]; } b2;
layout(std430, binding = 3) buffer B3 { pb_gpu_hit d[]; } b3;
layout(std430, binding = 4) buffer B4 { pb_gpu_material d[]; } b4;
layout(std430, binding = 5) buffer B5 { pb_gpu_texture d[]; } b5;
layout(std430, binding = 6) buffer B6 { pb_gpu_light d[]; } b6;
layout(std430, binding = 7) buffer B7 { pb_gpu_frame d[]; } b7;
layout(std430, binding = 8) buffer B8 { pb_gpu_gbuffer d[]; } b8;
layout(std430, binding = 9) buffer B9 { pb_gpu_accum d[]; } b9;
layout(std430, binding = 10) buffer B10 { pb_gpu_raycast_push d[]; } b10;
layout(std430, binding = 11) buffer B11 { pb_gpu_pass_push d[]; } b11;
layout(std430, binding = 12) buffer B12 { pb_gpu_emitter d[]; } b12;
layout(std430, binding = 13) buffer B13 { pb_gpu_world d[]; } b13;
layout(std430, binding = 14) buffer B14 { pb_gpu_camera d[]; } b14;
layout(std430, binding = 15) buffer B15 { pb_gpu_vsch_push d[]; } b15;

void main() {
  uint gid = gl_GlobalInvocationID.x;
  if (gid >= 1u) return;
  b0.d[1] = b0.d[0]; b1.d[1] = b1.d[0]; b2.d[1] = b2.d[0]; b3.d[1] = b3.d[0];
  b4.d[1] = b4.d[0]; b5.d[1] = b5.d[0]; b6.d[1] = b6.d[0]; b7.d[1] = b7.d[0];
  b8.d[1] = b8.d[0]; b9.d[1] = b9.d[0]; b10.d[1] = b10.d[0]; b11.d[1] = b11.d[0];
  b12.d[1] = b12.d[0]; b13.d[1] = b13.d[0]; b14.d[1] = b14.d[0]; b15.d[1] = b15.d[0];
}
