/* The viewer's display pass (shaders/frame/present.comp, src/view/present_pass.c):
 * scene-linear pixels through the baked OCIO view
 * (color.h pb_color_lut: shaper + tetrahedral 3D LUT) into 8-bit RGBA on
 * the render device. Shared by C and GLSL. */
#ifndef PB_PRESENT_SHARED_H
#define PB_PRESENT_SHARED_H

#include "shared/pb_gpu.h"

PB_CONST(PB_PRESENT_DATA, 1u) /* flags: no view: data_scale * x + data_bias, clamped (normals) */

PB_STRUCT(pb_gpu_present_push) {
  uint pixels;     /* to write */
  uint size;       /* LUT nodes per axis */
  uint offset;     /* float offset of the AOV in the input buffer */
  uint channels;   /* floats per pixel of the AOV (3 or 4) */
  float lo, hi;    /* the shaper: log2 of nodes 1 and size-1 */
  float scale;     /* 2^exposure */
  uint flags;      /* PB_PRESENT_* */
  float data_scale, data_bias;
  uint pad0, pad1;
} PB_END(pb_gpu_present_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_present_push) == 48, "pb_gpu_present_push size");
#endif
#endif
