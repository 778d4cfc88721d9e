/* The display-only readback (the live viewer reads back only what
 * it shows). The same pb_sequence (cornell_box, photons, temporal filter and
 * A-Trous, the still run's means on the GPU; frames 0-1 still, 2-3 with the
 * camera moving) rendered four times with the same seed:
 *   full         desc.readback ALL (render --frames, the reference)
 *   stats        _STATS, as `view` with the GPU display sets it
 *   beauty       _BEAUTY, as `serve` (rgba32f frames) sets it
 *   stats_fif2   _STATS with two frames in flight (the ring slots),
 *                every plane kept in the ring (keep_planes, as the viewer
 *                does for the depth AOV and while P / F12 waits)
 *   beauty_fif2  _BEAUTY with two frames in flight, nothing kept (the ring
 *                slot holds the beauty plane alone)
 *   view_fif2    _STATS with two frames in flight keeping the beauty plane,
 *                as `view --frames-in-flight 2` does showing the beauty
 *                (the shown AOV's planes; viewer.c set_keep)
 * and checked per frame:
 *   - readback_bytes of stats at most STATS_BYTES (no plane: the guard's
 *     count, k_PD's sums reduced on the GPU, the temporal filter's counts;
 *     before the reduction it read the k_PD plane, 8 bytes a pixel), of
 *     beauty at most 16 bytes a pixel + STATS_BYTES (before: 24 a pixel);
 *   - ring_bytes (frames in flight: what the ring copy moved): every plane
 *     (104 bytes a pixel) with keep_planes all, the beauty plane alone (16)
 *     for beauty_fif2 and view_fif2 (before: every plane in every mode, and
 *     the viewer kept every plane), 0 without;
 *   - the picture: the beauty where each mode leaves it (the host array for
 *     full and beauty, the GPU planes of out->gpu for the lean modes) equal
 *     to full's within FLOAT_TOL (relative above 1; the run-to-run rounding
 *     of the photon store's order, measured below as full_again against
 *     full), and the display pass's
 *     RGBA8 (view/present_pass.h; the built-in sRGB / Standard view baked)
 *     from the GPU planes equal to full's made from the uploaded beauty, as
 *     the viewer did before, within one 8-bit step on at most 0.1 % of the
 *     channels (identical in every run so far);
 *   - the statistics the lean modes keep: non-finite count, photons
 *     stored, k_PD equal to full's (the GPU's sums against the host's sums
 *     of the plane: counts, so equal to 1e-9);
 *   - pb_render_result_read_gpu after a lean frame: every AOV equal to
 *     full's (what the viewer's depth AOV, P / F12 and --reference use);
 *     after beauty_fif2's last frame it fails (the planes were not kept).
 * PB_VIEW_READBACK_WIDTH=N (default 64) renders N pixels wide and prints the
 * per-frame bytes and wall ms of each mode (the brief's measurement). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "sample_fixture.h"
#include "color/color.h"
#include "render/frame/sequence.h"
#include "shared/pb_resolve.h"
#include "view/present_pass.h"

enum { FRAMES = 4, MODES = 7 };
/* A lean frame's readback without pixels: the guard's count (4 bytes), k_PD's
 * sums (16), the temporal filters' counts (16 each); a small constant with
 * room to spare, far below a plane's 4 bytes a pixel at 64 px (16 KiB). */
#define STATS_BYTES 256u
/* Two runs of the same sequence differ within float rounding where the
 * photon store's slot order varies (atomics; sequence.h frames_in_flight):
 * measured full against full again, cornell_box 2^14 photons, up to 1.7e-6
 * relative at 256 px and 5.6e-6 at 512 px, 1e-7 at 64 px. A wrong plane, slot
 * or frame differs by O(1) (the ring-slot race this test found: 1.5). */
#define FLOAT_TOL 1e-5f

typedef struct run {
  const char *name;
  int mode;
  uint32_t fif;
  uint64_t keep; /* keep_planes */
  uint64_t bytes[FRAMES], ring[FRAMES], kept[FRAMES];
  double wall[FRAMES], gpu[FRAMES]; /* frame_wall_ms, frame_gpu_ms (printed only) */
  int got_mode[FRAMES], got[FRAMES];
  uint64_t nonfinite[FRAMES], stored[FRAMES];
  double k_pd[FRAMES];
  float *beauty[FRAMES];  /* the beauty where the mode leaves it */
  uint8_t *shown[FRAMES]; /* the display pass's bytes */
  pb_render_result last;  /* the last frame, every AOV (read_gpu for the lean ones) */
} run;

static float max_rel_diff(const float *a, const float *b, size_t n) {
  float m = 0;
  for (size_t i = 0; i < n; ++i) {
    float d = fabsf(a[i] - b[i]) / fmaxf(1.0f, fabsf(b[i]));
    if (!(d <= m)) m = d; /* NaN counts as the worst */
  }
  return m;
}

static void record(pb_gpu *g, pb_present_pass *pass, run *u, pb_render_result *res, const pb_sequence_frame_info *fi,
                   int last) {
  uint32_t k = fi->index;
  if (k >= FRAMES) return;
  size_t n = (size_t)res->width * res->height;
  u->got[k] = 1;
  u->bytes[k] = res->stats.readback_bytes;
  u->ring[k] = res->stats.ring_bytes;
  u->kept[k] = res->gpu.kept;
  u->wall[k] = res->stats.frame_wall_ms;
  u->gpu[k] = res->stats.frame_gpu_ms;
  u->got_mode[k] = res->stats.readback_mode;
  u->nonfinite[k] = res->stats.nonfinite_values;
  u->stored[k] = res->stats.photons_stored;
  u->k_pd[k] = res->stats.k_pd;
  u->beauty[k] = malloc(4 * n * sizeof(float));
  u->shown[k] = malloc(4 * n);
  pb_present_job job = {.channels = 4, .pixels = (uint32_t)n, .scale = 1.0f};
  if (res->beauty) {
    memcpy(u->beauty[k], res->beauty, 4 * n * sizeof(float));
  } else {
    /* Nothing on the host: the test looks at the planes on the GPU. */
    CHECK(res->gpu.planes != NULL);
    if (!res->gpu.planes) return;
    CHECK_EQ_INT(pb_gpu_buffer_download(g, res->gpu.planes, (uint64_t)PB_RESOLVE_BEAUTY * n * sizeof(float),
                                        u->beauty[k], 4 * n * sizeof(float)),
                 PB_OK);
  }
  if (u->mode == PB_RENDER_READBACK_ALL) { /* the viewer before: the host's beauty uploaded */
    CHECK_EQ_INT(pb_present_pass_upload(g, pass, res->beauty, (uint32_t)n, 4), PB_OK);
  } else { /* the viewer now: the planes where they lie */
    job.src = res->gpu.planes;
    job.offset = PB_RESOLVE_BEAUTY * (uint32_t)n;
    pass->bound_src = NULL; /* as the viewer: a later sequence's buffers can sit at the same address */
  }
  CHECK_EQ_INT(pb_present_pass_run(g, pass, &job), PB_OK);
  CHECK_EQ_INT(pb_present_pass_download(g, pass, u->shown[k], (uint32_t)n), PB_OK);
  if (last && u->fif == 2 && u->mode != PB_RENDER_READBACK_ALL && u->keep != PB_RENDER_KEEP_ALL) {
    /* The ring slot holds the beauty alone: the other AOVs cannot come. */
    CHECK(pb_render_result_read_gpu(g, res) != PB_OK);
  } else if (last) {
    uint64_t before = res->stats.readback_bytes;
    CHECK_EQ_INT(pb_render_result_read_gpu(g, res), PB_OK);
    if (u->mode != PB_RENDER_READBACK_ALL) {
      CHECK(res->stats.readback_bytes > before); /* the rest came now, and is counted */
      CHECK(res->direct && res->albedo && res->normal && res->depth && res->indirect && res->caustic);
    }
    u->last = *res;
    memset(res, 0, sizeof *res);
  }
}

static void run_sequence(pb_gpu *g, pbt_sample *fx, pb_present_pass *pass, run *u) {
  pb_sequence_desc sd = {.render = {.spp = 1, .photons = 1u << 14, .iterations = 1, .seed = 7, .atrous_iterations = 2},
                         .temporal = 1,
                         .frames_in_flight = u->fif,
                         .readback = u->mode,
                         .keep_planes = u->keep};
  pb_camera base = fx->s.cameras[0];
  pb_sequence *q = NULL;
  CHECK_EQ_INT(pb_sequence_create(g, &fx->s, &fx->gs, 0, fx->w, fx->h, &sd, &q), PB_OK);
  if (!q) return;
  pb_render_result res;
  pb_sequence_frame_info fi;
  for (uint32_t i = 0; i < FRAMES; ++i) {
    fx->s.cameras[0] = base;
    if (i >= 2) fx->s.cameras[0].position[0] += 0.02f * (float)(i - 1); /* frames 2, 3: moving */
    pb_result r = pb_sequence_frame(g, q, i, 0.0, &res, &fi);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) break;
    if (fi.ready) record(g, pass, u, &res, &fi, fi.index == FRAMES - 1);
    pb_render_result_destroy(&res);
  }
  CHECK_EQ_INT(pb_sequence_flush(g, q, &res, &fi), PB_OK);
  if (fi.ready) record(g, pass, u, &res, &fi, fi.index == FRAMES - 1);
  pb_render_result_destroy(&res);
  pb_sequence_destroy(g, q);
  fx->s.cameras[0] = base;
}

int main(void) {
  PBT_GPU_OPEN(g);
  const char *we = getenv("PB_VIEW_READBACK_WIDTH");
  uint32_t width = we && atoi(we) > 0 ? (uint32_t)atoi(we) : 64;
  pbt_sample fx;
  if (!pbt_sample_open(g, "cornell_box", width, NULL, &fx)) {
    pbt_sample_close(g, &fx);
    pb_gpu_destroy(g);
    return pbt_done();
  }
  size_t n = (size_t)fx.w * fx.h;
  pb_color *c = NULL;
  pb_color_desc cd = {.config = "built-in", .display = "sRGB", .view = "Standard"};
  CHECK_EQ_INT(pb_color_open(&cd, &c), PB_OK);
  pb_color_lut lut;
  memset(&lut, 0, sizeof lut);
  CHECK_EQ_INT(pb_color_bake_lut(c, 0, &lut), PB_OK);
  pb_present_pass pass;
  CHECK_EQ_INT(pb_present_pass_create(g, &lut, (uint32_t)n, &pass), PB_OK);

  run runs[MODES] = {{.name = "full", .mode = PB_RENDER_READBACK_ALL, .fif = 1},
                     {.name = "stats", .mode = PB_RENDER_READBACK_STATS, .fif = 1},
                     {.name = "beauty", .mode = PB_RENDER_READBACK_BEAUTY, .fif = 1},
                     {.name = "stats_fif2", .mode = PB_RENDER_READBACK_STATS, .fif = 2, .keep = PB_RENDER_KEEP_ALL},
                     {.name = "beauty_fif2", .mode = PB_RENDER_READBACK_BEAUTY, .fif = 2},
                     {.name = "full_again", .mode = PB_RENDER_READBACK_ALL, .fif = 1},
                     /* `view --frames-in-flight 2` showing the beauty: its ring
                        slot keeps that AOV's plane alone (viewer.c set_keep) */
                     {.name = "view_fif2", .mode = PB_RENDER_READBACK_STATS, .fif = 2,
                      .keep = PB_RENDER_KEEP(PB_RESOLVE_BEAUTY)}};
  for (int m = 0; m < MODES; ++m) run_sequence(g, &fx, &pass, &runs[m]);

  const run *full = &runs[0];
  printf("cornell_box %ux%u, 2^14 photons, 1 spp, temporal + 2 A-Trous, frames 0-1 still, 2-3 moving\n", fx.w, fx.h);
  for (int m = 0; m < MODES; ++m) {
    const run *u = &runs[m];
    double bytes = 0, wall = 0, gpu = 0;
    uint32_t got = 0;
    for (int k = 0; k < FRAMES; ++k) {
      CHECK(u->got[k]);
      if (!u->got[k]) continue;
      printf("  %-11s frame %d: readback %9llu bytes (%.1f B/px), ring %9llu bytes (%.1f B/px), wall %8.2f ms, "
             "gpu %8.2f ms, mode %d\n",
             u->name, k, (unsigned long long)u->bytes[k], (double)u->bytes[k] / (double)n,
             (unsigned long long)u->ring[k], (double)u->ring[k] / (double)n, u->wall[k], u->gpu[k], u->got_mode[k]);
      if (k > 0) bytes += (double)u->bytes[k], wall += u->wall[k], gpu += u->gpu[k], got++;
    }
    if (got)
      printf("  %-11s mean of frames 1-%d: %.0f bytes a frame, wall %.2f ms, gpu %.2f ms a frame\n", u->name,
             FRAMES - 1, bytes / got, wall / got, gpu / got);
  }
  for (int m = 1; m < MODES; ++m) {
    const run *u = &runs[m];
    double bound = u->mode == PB_RENDER_READBACK_STATS ? 0.25 : u->mode == PB_RENDER_READBACK_BEAUTY ? 0.30 : 1.0001;
    for (int k = 0; k < FRAMES; ++k) {
      if (!u->got[k] || !full->got[k]) continue;
      CHECK_EQ_INT(u->got_mode[k], u->mode); /* the lean mode was honoured, not fallen back from */
      double ratio = (double)u->bytes[k] / (double)full->bytes[k];
      printf("  %-11s frame %d: %.4f of full's bytes (bound %.2f)", u->name, k, ratio, bound);
      CHECK(full->bytes[k] > 0);
      CHECK(ratio < bound);
      /* The lean modes' bytes: no k_PD plane (k_PD's sums reduced
       * on the GPU), the beauty plane alone for BEAUTY. */
      if (u->mode == PB_RENDER_READBACK_STATS) CHECK(u->bytes[k] <= STATS_BYTES);
      if (u->mode == PB_RENDER_READBACK_BEAUTY) CHECK(u->bytes[k] <= 16u * n + STATS_BYTES);
      /* The ring copy: what the readback reads and keep_planes, no more. */
      if (u->fif == 2) {
        uint64_t all = (uint64_t)n * PB_RESOLVE_PHOTON_CHANNELS * sizeof(float);
        CHECK_EQ_INT(u->ring[k], u->keep == PB_RENDER_KEEP_ALL || u->mode == PB_RENDER_READBACK_ALL ? all : 16u * n);
        if (u->keep != PB_RENDER_KEEP_ALL) CHECK_EQ_INT(u->kept[k], PB_RENDER_KEEP(PB_RESOLVE_BEAUTY));
      } else {
        CHECK_EQ_INT(u->ring[k], 0);
      }
      if (u->mode == PB_RENDER_READBACK_ALL) CHECK(ratio > 0.9999); /* full again: the same bytes */
      float d = max_rel_diff(u->beauty[k], full->beauty[k], 4 * n);
      uint32_t differ = 0;
      int step = 0;
      for (size_t i = 0; i < 4 * n; ++i) {
        int e = abs((int)u->shown[k][i] - (int)full->shown[k][i]);
        differ += e != 0;
        step = e > step ? e : step;
      }
      printf(", beauty max rel diff %.3g, display bytes differing %u (max %d)\n", (double)d, differ, step);
      CHECK(d <= FLOAT_TOL);
      /* The same picture: floats that differ by rounding may round to the
       * next 8-bit step (none did in the runs above). */
      CHECK(step <= 1);
      CHECK(differ <= 4 * n / 1000);
      CHECK_EQ_INT(u->nonfinite[k], full->nonfinite[k]);
      CHECK_EQ_INT(u->stored[k], full->stored[k]);
      CHECK(full->k_pd[k] > 1.0); /* photons were gathered: the sums compare something */
      CHECK_NEAR(u->k_pd[k], full->k_pd[k], 1e-9 * fmax(1.0, full->k_pd[k]));
    }
    /* The rest of the last frame, fetched after the fact. */
    const pb_render_result *a = &u->last, *b = &full->last;
    if (u->fif == 2 && u->mode != PB_RENDER_READBACK_ALL && u->keep != PB_RENDER_KEEP_ALL) {
      /* not kept (checked in record) */
    } else if (a->beauty && b->beauty) {
      CHECK(max_rel_diff(a->direct, b->direct, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->albedo, b->albedo, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->normal, b->normal, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->depth, b->depth, n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->emission, b->emission, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->indirect, b->indirect, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->caustic, b->caustic, 3 * n) <= FLOAT_TOL);
      CHECK(max_rel_diff(a->beauty, b->beauty, 4 * n) <= FLOAT_TOL);
    } else {
      CHECK(!"the last frame's AOVs are missing");
    }
  }
  /* The picture is not black: the comparison above compares something. */
  double sum = 0;
  for (size_t i = 0; full->beauty[FRAMES - 1] && i < n; ++i) sum += full->beauty[FRAMES - 1][4 * i];
  printf("mean red of the last full frame %.4g\n", sum / (double)n);
  CHECK(sum / (double)n > 1e-3);

  for (int m = 0; m < MODES; ++m) {
    for (int k = 0; k < FRAMES; ++k) free(runs[m].beauty[k]), free(runs[m].shown[k]);
    pb_render_result_destroy(&runs[m].last);
  }
  pb_present_pass_destroy(g, &pass);
  pb_color_lut_destroy(&lut);
  pb_color_destroy(c);
  pbt_sample_close(g, &fx);
  pb_gpu_destroy(g);
  return pbt_done();
}
