/* The density estimator's description (estimator.h), apart so that
 * pb_render_desc (render.h) holds one by value: the kinds and each
 * estimator's own settings. Zero means default for every field. */
#ifndef PB_RENDER_ESTIMATOR_DESC_H
#define PB_RENDER_ESTIMATOR_DESC_H

#include <stdint.h>

typedef enum pb_estimator_kind {
  PB_ESTIMATOR_LBVH = 0,
  PB_ESTIMATOR_KNN = 1,
  PB_ESTIMATOR_SPLAT = 2,
  PB_ESTIMATOR_VSCH = 3,
  PB_ESTIMATOR_AUTO = 4,
  PB_ESTIMATOR_KIND_COUNT
} pb_estimator_kind;

/* The LBVH gather's settings (lbvh.c, gather.c); kNN builds the same LBVH
 * and reads leaf_size too. */
typedef struct pb_photon_estimate_desc {
  int constant_kernel;        /* 1: constant kernel; 0: Epanechnikov */
  int no_edge_correction;     /* 1: no kernel renormalisation at the edges of
                                 faces (gather.comp; tests, ablation) */
  uint32_t leaf_size;         /* fixed leaf-size threshold instead of T_auto
                                 (1..PB_LBVH_MAX_FIXED_LEAF; benchmark sweeps
                                 as in seed 000 Table 1); 0: T_auto */
} pb_photon_estimate_desc;

/* Each implementation reads its own part; the frame's key (frame.c
 * ctx_key) compares the whole struct (all 4-byte fields: no padding). */
typedef struct pb_estimator_desc {
  uint32_t kind;                /* pb_estimator_kind; 0: lbvh */
  pb_photon_estimate_desc lbvh; /* leaf_size, constant_kernel, edges */
  struct {
    uint32_t k;                 /* neighbours per shading point; 0: default */
    float r_max;                /* search radius bound, m; 0: the tracer's */
  } knn;
  struct {
    float s_l, s_d, s_u;        /* seed 001 eq. 2-9 kernel scales; 0: default */
    uint32_t tile;              /* tile edge, pixels; 0: default */
  } splat;
  struct {
    float radius;               /* photon radius, m; 0: the tracer's */
    uint32_t directional;       /* 1: 8 octant flux buckets per node */
  } vsch;
} pb_estimator_desc;

#endif
