#version 450
// Radix sort, stable ranking within each tile and the scatter.
// Subgroup ballots or shuffles (the host picks this variant where the device has them).
// The kernels are in common/lbvh_sort.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#define PB_SORT_SUBGROUPS 1
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh_sort.glsl"

void main() { pb_sort_downsweep(); }
