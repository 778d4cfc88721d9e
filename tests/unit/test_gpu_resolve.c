/* The resolve pass (shaders/frame/resolve.comp) and the readback (readback.h) on
 * accumulators written by hand: the means, the normalised normal, depth over
 * coverage, the opaque alpha, eq. 20's unit vectors and clamped fraction, and
 * the guard: every non-finite value of a guarded AOV becomes 0 and is counted
 * once by the atomic (a NaN normal sum gives a 0 normal, not a count, as the
 * host resolve did); the planes equal the host reference (PB_RESOLVE_ON_HOST);
 * the planes add nothing to the band's per-pixel limit.
 * Validation layers on. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/frame/readback.h"
#include "render/frame/resolve.h"
#include "render/frame/targets.h"
#include "shared/pb_lbvh.h"

enum { N = 6 };

static void alloc(pb_render_result *o) {
  memset(o, 0, sizeof *o);
  o->beauty = calloc(4 * N, sizeof(float));
  o->direct = calloc(3 * N, sizeof(float));
  o->albedo = calloc(3 * N, sizeof(float));
  o->normal = calloc(3 * N, sizeof(float));
  o->depth = calloc(N, sizeof(float));
  o->material = calloc(N, sizeof(float));
  o->emission = calloc(3 * N, sizeof(float));
  o->indirect = calloc(3 * N, sizeof(float));
  o->caustic = calloc(3 * N, sizeof(float));
}

/* Resolves the targets over 2 samples (opaque: alpha 1) and reads them back. */
static void resolve(pb_gpu *g, const pb_frame_targets *t, const pb_gpu_pipeline *p, int opaque, pb_render_result *o,
                    uint64_t *bad, double *k, double *hit) {
  CHECK_EQ_INT(pb_gpu_buffer_fill_zero(g, (pb_gpu_buffer *)&t->guard), PB_OK);
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  CHECK_EQ_INT(pb_resolve_record(g, p, t, N, 0.5f, opaque), PB_OK);
  CHECK_EQ_INT(pb_gpu_submit(g), PB_OK);
  alloc(o);
  *k = *hit = 0;
  CHECK_EQ_INT(pb_readback_band(g, t, PB_RENDER_READBACK_ALL, N, 0, N, 0.5f, opaque, 1, o, k, hit), PB_OK);
  CHECK_EQ_INT(pb_readback_guard(g, t, bad), PB_OK);
}

int main(void) {
  /* The resolved planes never narrow the band: the accumulators stay the
   * widest per-pixel target (frame.c sizes bands by it). */
  CHECK_EQ_INT(pb_frame_targets_max_pixel_bytes(), sizeof(pb_gpu_accum));
  PBT_GPU_OPEN(g);
  pb_frame_targets t;
  pb_gpu_pipeline p = {0};
  CHECK_EQ_INT(pb_frame_targets_create(g, N, 1, 1, &t), PB_OK);
  CHECK_EQ_INT(pb_resolve_create(g, &t, &p), PB_OK);
  pb_gpu_accum a[N];
  pb_gpu_photon_accum pa[N];
  pb_gpu_photon_nmap pn[N];
  memset(a, 0, sizeof a);
  memset(pa, 0, sizeof pa);
  memset(pn, 0, sizeof pn);
  for (int i = 0; i < N; ++i) {
    for (int k = 0; k < 4; ++k) a[i].beauty[k] = 2.0f * (float)(i + 1) + (float)k;
    for (int k = 0; k < 3; ++k) {
      a[i].direct[k] = 1.0f + (float)k;
      a[i].albedo[k] = 0.5f;
      a[i].emission[k] = 0.25f * (float)k;
      pa[i].indirect[k] = 4.0f;
      pa[i].caustic[k] = 6.0f;
    }
    a[i].normal[2] = 3.0f; /* the sum of two samples' normals: resolves to +z */
    a[i].depth = 2.0f * a[i].beauty[3];
    a[i].material = 3.0f;
    pa[i].indirect[3] = 10.0f;
    pn[i].geo[1] = 2.0f;
    pn[i].dir[0] = 0.5f;
    pn[i].ns[0] = 1.0f, pn[i].ns[1] = 1.0f, pn[i].ns[3] = 1.0f;
  }
  a[1].beauty[0] = NAN;      /* counted */
  a[2].direct[1] = INFINITY; /* counted */
  a[3].normal[0] = NAN;      /* normal 0, not counted (nl > 0 is false) */
  a[4].depth = NAN;          /* counted */
  pa[5].caustic[2] = -INFINITY; /* counted */
  pn[5].ns[3] = 8.0f;        /* fraction 4 clamped to 1 */
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &t.accum, 0, a, sizeof a), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &t.paccum, 0, pa, sizeof pa), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &t.pnmap, 0, pn, sizeof pn), PB_OK);

  pb_render_result o, h;
  uint64_t bad = 0, bad_h = 0;
  double k, hit, k_h, hit_h;
  resolve(g, &t, &p, 0, &o, &bad, &k, &hit);
  CHECK_EQ_INT(bad, 4);
  CHECK_NEAR(o.beauty[0], 1.0f, 0);          /* 2 x 0.5 */
  CHECK_NEAR(o.beauty[3], 2.5f, 0);          /* coverage sum 5, not opaque */
  CHECK_NEAR(o.beauty[4 * 1 + 0], 0.0f, 0);  /* NaN -> 0 */
  CHECK_NEAR(o.beauty[4 * 1 + 1], 2.5f, 0);
  CHECK_NEAR(o.direct[3 * 2 + 1], 0.0f, 0);  /* Inf -> 0 */
  CHECK_NEAR(o.direct[3 * 2 + 2], 1.5f, 0);
  CHECK_NEAR(o.normal[2], 1.0f, 1e-6);
  CHECK_NEAR(o.normal[3 * 3 + 2], 0.0f, 0);  /* NaN sum -> 0 normal */
  CHECK_NEAR(o.depth[0], 2.0f, 1e-6);        /* depth sum / coverage sum */
  CHECK_NEAR(o.depth[4], 0.0f, 0);
  CHECK_NEAR(o.material[0], 3.0f, 0);
  CHECK_NEAR(o.emission[2], 0.25f, 0);
  CHECK_NEAR(o.indirect[0], 2.0f, 0);
  CHECK_NEAR(o.caustic[3 * 5 + 2], 0.0f, 0); /* -Inf -> 0 */
  CHECK_NEAR(o.caustic[3 * 5 + 1], 3.0f, 0);
  CHECK(o.geo_normal && o.photon_dir && o.shading_normal);
  if (o.geo_normal) {
    CHECK_NEAR(o.geo_normal[1], 1.0f, 1e-6);
    CHECK_NEAR(o.photon_dir[0], 1.0f, 1e-6);
    CHECK_NEAR(o.shading_normal[0], 0.70710678f, 1e-6);
    CHECK_NEAR(o.shading_normal[3], 0.5f, 0);
    CHECK_NEAR(o.shading_normal[4 * 5 + 3], 1.0f, 0);
  }
  double hit_want = 0;
  for (int i = 0; i < N; ++i) hit_want += a[i].beauty[3];
  CHECK_NEAR(k, 10.0 * N, 0);
  CHECK_NEAR(hit, hit_want, 0);

  /* The host reference gives the same planes, bit for bit here. */
  setenv("PB_RESOLVE_ON_HOST", "1", 1);
  resolve(g, &t, &p, 0, &h, &bad_h, &k_h, &hit_h);
  unsetenv("PB_RESOLVE_ON_HOST");
  CHECK_EQ_INT(bad_h, 4); /* the GPU pass still ran and counted */
  CHECK(!memcmp(o.beauty, h.beauty, 4 * N * sizeof(float)));
  CHECK(!memcmp(o.direct, h.direct, 3 * N * sizeof(float)));
  CHECK(!memcmp(o.normal, h.normal, 3 * N * sizeof(float)));
  CHECK(!memcmp(o.depth, h.depth, N * sizeof(float)));
  CHECK(!memcmp(o.caustic, h.caustic, 3 * N * sizeof(float)));
  CHECK(h.shading_normal && !memcmp(o.shading_normal, h.shading_normal, 4 * N * sizeof(float)));
  CHECK(k_h == k && hit_h == hit);
  pb_render_result_destroy(&h);

  /* Opaque film: alpha 1 whatever the coverage. */
  pb_render_result_destroy(&o);
  resolve(g, &t, &p, 1, &o, &bad, &k, &hit);
  CHECK_NEAR(o.beauty[3], 1.0f, 0);
  CHECK_NEAR(o.beauty[4 * 5 + 3], 1.0f, 0);
  pb_render_result_destroy(&o);

  pb_gpu_pipeline_destroy(g, &p);
  pb_frame_targets_destroy(g, &t);
  pb_gpu_destroy(g);
  return pbt_done();
}
