#version 450
// Radix sort, the digit counts of each tile.
// Workgroup barriers and shared atomics only, on every device.
// The kernels are in common/lbvh_sort.glsl.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
layout(local_size_x = PB_GPU_WORKGROUP) in;
#include "common/lbvh_sort.glsl"

void main() { pb_sort_upsweep(); }
