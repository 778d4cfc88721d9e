#version 450
// Radix sort, one workgroup: the key count from the count buffer (clamped to the capacity), the tile and spine grids for the indirect dispatches, the digit totals cleared.
// The kernels are in common/lbvh_sort.glsl.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh_sort.glsl"

void main() { pb_sort_setup(); }
