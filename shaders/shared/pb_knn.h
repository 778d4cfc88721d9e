/* kNN photon mapping (seed 000 section 3.1; src/render/estimate/estimator_knn.c,
 * shaders/estimate/knn.comp): the push constants of the query pass. Included after
 * pb_gpu.h, pb_photon.h and pb_lbvh.h (it reads the photon LBVH). */
#ifndef PB_KNN_SHARED_H
#define PB_KNN_SHARED_H

/* Neighbours per query: the default and the largest (the heap lives in each
 * invocation's private memory, sized by the specialization constant
 * PB_SPEC_KNN_K). */
PB_CONST(PB_KNN_K_DEFAULT, 64)
PB_CONST(PB_KNN_K_MAX, 512)

PB_STRUCT(pb_gpu_knn_push) {
  uint sample_index;
  uint flags;            /* PB_GATHER_NO_BEAUTY */
  float r_max;           /* search radius bound, m (seed 000 3.1's r_max) */
  float edge_reach;      /* kernel renormalisation at face edges looks this
                            far, m (common/kernel_edges.glsl); 0: off */
} PB_END(pb_gpu_knn_push)

#ifndef PB_GLSL
_Static_assert(sizeof(pb_gpu_knn_push) == 16, "pb_gpu_knn_push size");
#endif

#endif
