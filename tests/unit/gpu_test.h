/* The start of every test that opens a Vulkan device: validation layers on
 * (any message fails the next submission), exit 77 (ctest's skip code, see
 * tests/gpu.cmake) when there is no device. Include after pbtest.h. */
#ifndef PB_TEST_GPU_TEST_H
#define PB_TEST_GPU_TEST_H

#include <stdio.h>

#include "gpu/gpu.h"

static inline pb_result pbt_gpu_open(pb_gpu **g) {
  pb_gpu_desc gd = {.validation = 1};
  pb_result r = pb_gpu_create(&gd, g);
  if (r == PB_ERR_NO_DEVICE || r == PB_ERR_NOT_AVAILABLE) {
    printf("SKIP: %s\n", pb_error_message());
    return r;
  }
  CHECK_EQ_INT(r, PB_OK);
  return r;
}

/* Declares pb_gpu *G and pb_result r in main(); returns 77 without a device
 * and the failure count when the device cannot be opened. */
#define PBT_GPU_OPEN(G)                                              \
  pb_gpu *G = NULL;                                                  \
  pb_result r = pbt_gpu_open(&G);                                    \
  if (r == PB_ERR_NO_DEVICE || r == PB_ERR_NOT_AVAILABLE) return 77; \
  if (r != PB_OK) return pbt_done()

#endif
